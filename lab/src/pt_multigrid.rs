//! A p–θ multigrid for the Elrod–Adams problem of one time step, the class of solver the
//! paper used (a Gauss–Seidel-type p–θ iteration accelerated by multigrid, paper §2.6 and its
//! refs. \[29\], \[30\]), as a film solver ([`PtSolver`]). Its cost grows with the node count
//! only, so it runs the finest reference meshes (2048×128), where the band LU costs ≈ 1.5 s a
//! step.
//!
//! - Smoother: lexicographic Gauss–Seidel in the upwind direction; each node solves its own
//!   balance (the one stencil, [`crate::stencil::balance`]) for its one unknown, exactly: the
//!   balance is affine in p_ij on the pressurised branch and in φ_ij on the cavitated one,
//!   and increasing in both, so the node is pressurised iff the balance at p = 0, φ = h is
//!   negative (the Ausas–Jai–Buscaglia update without relaxation).
//! - Coarse correction (truncated, as in monotone multigrid for obstacle problems): the
//!   smooth error of a step lives in the pressure of the pressurised set, where the balance
//!   is the Poiseuille operator alone (φ = h is fixed there). The coarse levels solve for a
//!   pressure correction on the coarse nodes whose every fine node is pressurised, zero
//!   elsewhere (the smoother moves the fronts). A first version as a full approximation
//!   scheme on p and φ did not converge: a restricted state is not complementary at the
//!   coarse nodes that straddle a front, so the coarse smoother moved even an exact solution.
//! - Coarse meshes: x1 is halved alone while the cells are long in x2 (semi-coarsening
//!   for the anisotropy; 512×32 at per = 0.06 has dy ≈ 2.4·dx), then both. A coarse face
//!   conductance is the fine faces it spans in series along the flow and in parallel across
//!   it, so the jump of h³ by ≈ 10⁶ at the ring's edges (gap e against the film) stays
//!   where it is instead of smearing a coarse cell into the ring. Residuals are restricted
//!   by their sums (the stencil is the integrated balance of a cell), corrections prolonged
//!   linearly. No coarse node straddles a ring edge (`restrict`). Or (`galerkin`,
//!   `PtMultigrid::galerkin`): Galerkin coarse operators Pᵀ·A·P with a truncated,
//!   operator-dependent prolongation.
//! - The ring: with a ring link in the step, Z moves after every V-cycle by a chord step on
//!   the Newmark equation (docs/model.md §4).
//!

use texopt::mesh::integrals::{contact_load, load};
use texopt::mesh::{face_conductances, FilmState, Gap, Grid};
use texopt::model::film::{Column, Faces};
use texopt::model::ring::RingLink;
use texopt::solve::{
    finish, impose_boundary, max_relative_residual, FilmError, FilmMethod, GapCache, SolveStats,
    Step,
};

use crate::stencil::{balance, conductance_sum};

mod galerkin;

/// The fine level: the film problem and its state.
struct Fine {
    g: Grid,
    /// Nodal gap at the fixed Z (µm).
    h: Vec<f64>,
    /// Face conductances, laid out as the product's ([`Faces`]).
    cx: Vec<f64>,
    cy: Vec<f64>,
    /// φ at the old time level.
    old: Vec<f64>,
    /// Sum of the four face conductances of each node (∂balance/∂p_ij) and its inverse, set
    /// with the gap: the smoother's nodal solve multiplies instead of dividing.
    sc: Vec<f64>,
    inv_sc: Vec<f64>,
    p: Vec<f64>,
    phi: Vec<f64>,
    /// Couette and time coefficients of the stencil (u·dy, 2·dx·dy/dt).
    adv: f64,
    at: f64,
}

/// A coarse level: the Poiseuille operator of the pressure correction on its mesh.
struct Coarse {
    n1: usize,
    n2: usize,
    cx: Vec<f64>,
    cy: Vec<f64>,
    /// Per node column: under the ring (Some(true)), outside it (Some(false)), or made of
    /// fine columns of both (None: never corrected, see [`restrict`]).
    side: Vec<Option<bool>>,
    /// Nodes that carry a correction (every fine node beneath them pressurised).
    active: Vec<bool>,
    /// Right-hand side and correction.
    b: Vec<f64>,
    e: Vec<f64>,
}

/// How a mesh is halved for the next level: along x1, along x2.
#[derive(Clone, Copy)]
struct Halving {
    x1: bool,
    x2: bool,
}

/// Which directions a mesh of n1 × n2 cells of dx × dy is halved in for the next level:
/// x1 while its cells are at most ⅔ as long as they are wide, x2 while they are at most
/// 1.5 times as wide as long.
fn halving(n1: usize, n2: usize, dx: f64, dy: f64) -> Halving {
    Halving {
        x1: n1.is_multiple_of(2) && n1 >= 16 && dx <= 1.5 * dy,
        x2: n2.is_multiple_of(2) && n2 >= 2 && dy <= 1.5 * dx,
    }
}

/// The chain of halvings from mesh `g` down to the first that cannot be halved, each with
/// the mesh it makes (n1, n2).
fn halving_chain(g: &Grid) -> Vec<(Halving, usize, usize)> {
    let (mut n1, mut n2, mut dx, mut dy) = (g.n1, g.n2, g.dx, g.dy);
    let mut chain = Vec::new();
    loop {
        let hv = halving(n1, n2, dx, dy);
        if !(hv.x1 || hv.x2) {
            return chain;
        }
        if hv.x1 {
            (n1, dx) = (n1 / 2, 2.0 * dx);
        }
        if hv.x2 {
            (n2, dy) = (n2 / 2, 2.0 * dy);
        }
        chain.push((hv, n1, n2));
    }
}

/// x1 weights of the fine node columns around coarse column `ic` (vertex-centred).
fn x1_stencil(halve: bool, ic: usize, n1f: usize) -> impl Iterator<Item = (usize, f64)> {
    let c = if halve { 2 * ic } else { ic };
    let side = |i: Option<usize>| i.filter(|&i| halve && i <= n1f).map(|i| (i, 0.5));
    std::iter::once((c, 1.0))
        .chain(side(c.checked_sub(1)))
        .chain(side(Some(c + 1)))
}

/// x2 rows of the fine cells inside coarse cell `jc` (cell-centred).
fn x2_rows(halve: bool, jc: usize) -> std::ops::Range<usize> {
    if halve {
        2 * jc..2 * jc + 2
    } else {
        jc..jc + 1
    }
}

/// The coarse faces of fine faces (cx, cy) on n1f × n2f: in series along the flow, in
/// parallel across it. Returns (n1, n2, cx, cy) of the coarse mesh.
fn coarse_faces(
    cx: &[f64],
    cy: &[f64],
    n1f: usize,
    n2f: usize,
    hv: Halving,
) -> (usize, usize, Vec<f64>, Vec<f64>) {
    let n1 = if hv.x1 { n1f / 2 } else { n1f };
    let n2 = if hv.x2 { n2f / 2 } else { n2f };
    let mut ccx = vec![0.0; n1 * n2];
    for ic in 0..n1 {
        for jc in 0..n2 {
            let mut c = 0.0;
            for j in x2_rows(hv.x2, jc) {
                c += if hv.x1 {
                    let (a, b) = (cx[2 * ic * n2f + j], cx[(2 * ic + 1) * n2f + j]);
                    1.0 / (1.0 / a + 1.0 / b)
                } else {
                    cx[ic * n2f + j]
                };
            }
            ccx[ic * n2 + jc] = c;
        }
    }
    let (nyf, ny) = (n2f.saturating_sub(1), n2.saturating_sub(1));
    let mut ccy = vec![0.0; (n1 + 1) * ny];
    for ic in 0..=n1 {
        for jc in 0..ny {
            let mut c = 0.0;
            for (i, wi) in x1_stencil(hv.x1, ic, n1f) {
                let f = &cy[i * nyf..(i + 1) * nyf];
                c += wi
                    * if hv.x2 {
                        let j = 2 * jc;
                        1.0 / (0.5 / f[j] + 1.0 / f[j + 1] + 0.5 / f[j + 2])
                    } else {
                        f[jc]
                    };
            }
            ccy[ic * ny + jc] = c;
        }
    }
    (n1, n2, ccx, ccy)
}

impl Fine {
    fn faces(&self) -> Faces<'_> {
        Faces::new(&self.cx, &self.cy)
    }

    /// The one stencil at interior node (i, j) ([`crate::stencil::balance`]).
    fn balance(&self, i: usize, j: usize) -> f64 {
        let f = self.faces();
        balance(
            &self.g,
            &f,
            self.adv,
            self.at,
            &self.p,
            &self.phi,
            Some(&self.old),
            i,
            j,
        )
    }

    /// `sweeps` Gauss–Seidel sweeps over the interior node columns.
    fn smooth(&mut self, sweeps: usize) {
        let (n1, n2) = (self.g.n1, self.g.n2);
        let d = self.adv + self.at;
        let inv_d = 1.0 / d;
        let (mut p_col, mut phi_col) = (vec![0.0; n2], vec![0.0; n2]);
        for _ in 0..sweeps {
            for i in 1..n1 {
                let c = i * n2;
                {
                    // The stencil read column by column (no index checked per term): with
                    // the column's values before this sweep and the node south of each
                    // one corrected for its update (the only neighbour in the column a
                    // node's balance reads).
                    let faces = self.faces();
                    let col =
                        Column::new(self.g.n2, &faces, &self.p, &self.phi, Some(&self.old), i);
                    let mut south = 0.0;
                    for j in 0..n2 {
                        let k = c + j;
                        let mut r = col.balance(self.adv, self.at, j);
                        if j > 0 {
                            r -= col.cy[j - 1] * south;
                        }
                        // The balance at p_ij = 0, φ_ij = h_ij.
                        let f0 = r - self.sc[k] * self.p[k] + d * (self.h[k] - self.phi[k]);
                        (p_col[j], phi_col[j]) = if f0 < 0.0 {
                            (-f0 * self.inv_sc[k], self.h[k])
                        } else {
                            (0.0, self.h[k] - f0 * inv_d)
                        };
                        south = p_col[j] - self.p[k];
                    }
                }
                self.p[c..c + n2].copy_from_slice(&p_col);
                self.phi[c..c + n2].copy_from_slice(&phi_col);
            }
        }
    }

    /// −balance at every interior node into `out` (0 on the boundary columns).
    fn residual(&self, out: &mut Vec<f64>) {
        let (n1, n2) = (self.g.n1, self.g.n2);
        out.clear();
        out.resize(self.p.len(), 0.0);
        for i in 1..n1 {
            for j in 0..n2 {
                out[i * n2 + j] = -self.balance(i, j);
            }
        }
    }
}

impl Coarse {
    /// Gauss–Seidel sweeps on A·e = b over the active nodes (e = 0 elsewhere).
    fn smooth(&mut self, sweeps: usize) {
        let (n1, n2) = (self.n1, self.n2);
        let ny = n2.saturating_sub(1);
        for _ in 0..sweeps {
            for i in 1..n1 {
                for j in 0..n2 {
                    let k = i * n2 + j;
                    if !self.active[k] {
                        continue;
                    }
                    let (cw, ce) = (self.cx[k - n2], self.cx[k]);
                    let mut diag = cw + ce;
                    let mut s = self.b[k] + cw * self.e[k - n2] + ce * self.e[k + n2];
                    if j > 0 {
                        let c = self.cy[i * ny + j - 1];
                        diag += c;
                        s += c * self.e[k - 1];
                    }
                    if j + 1 < n2 {
                        let c = self.cy[i * ny + j];
                        diag += c;
                        s += c * self.e[k + 1];
                    }
                    self.e[k] = s / diag;
                }
            }
        }
    }

    /// b − A·e at the active nodes (0 elsewhere) into `out`.
    fn residual(&self, out: &mut Vec<f64>) {
        let (n1, n2) = (self.n1, self.n2);
        let ny = n2.saturating_sub(1);
        out.clear();
        out.resize(self.e.len(), 0.0);
        for i in 1..n1 {
            for j in 0..n2 {
                let k = i * n2 + j;
                if !self.active[k] {
                    continue;
                }
                let e = self.e[k];
                let mut a =
                    self.cx[k - n2] * (e - self.e[k - n2]) + self.cx[k] * (e - self.e[k + n2]);
                if j > 0 {
                    a += self.cy[i * ny + j - 1] * (e - self.e[k - 1]);
                }
                if j + 1 < n2 {
                    a += self.cy[i * ny + j] * (e - self.e[k + 1]);
                }
                out[k] = self.b[k] - a;
            }
        }
    }
}

/// Restriction of nodal residuals `r` (fine n1f × n2f) by their sums, and of the active
/// mask, into `c`. A coarse node is active iff every fine node it sums is, all of them on
/// one side of a ring edge: there h³ jumps by ≈ 10⁶ (the gap e against the film), which
/// linear interpolation of a correction ignores (corrections across it diverged).
fn restrict(r: &[f64], active: &[bool], n1f: usize, n2f: usize, hv: Halving, c: &mut Coarse) {
    let (n1, n2) = (c.n1, c.n2);
    for ic in 0..=n1 {
        for jc in 0..n2 {
            let (mut s, mut all) = (0.0, ic > 0 && ic < n1 && c.side[ic].is_some());
            for (i, wi) in x1_stencil(hv.x1, ic, n1f) {
                for j in x2_rows(hv.x2, jc) {
                    s += wi * r[i * n2f + j];
                    all &= active[i * n2f + j];
                }
            }
            let k = ic * n2 + jc;
            c.b[k] = if all { s } else { 0.0 };
            c.active[k] = all;
            c.e[k] = 0.0;
        }
    }
}

/// The coarse correction `e` (n1 × n2) prolonged to fine node (i, j): linear in x1 between
/// coinciding columns, linear in x2 between cell centres.
fn prolonged(e: &[f64], n2: usize, hv: Halving, i: usize, j: usize) -> f64 {
    let at_row = |ic: usize| -> f64 {
        if !hv.x2 {
            return e[ic * n2 + j];
        }
        let jc = j / 2;
        let nb = if j.is_multiple_of(2) {
            jc.saturating_sub(1)
        } else {
            (jc + 1).min(n2 - 1)
        };
        0.75 * e[ic * n2 + jc] + 0.25 * e[ic * n2 + nb]
    };
    if !hv.x1 {
        at_row(i)
    } else if i.is_multiple_of(2) {
        at_row(i / 2)
    } else {
        0.5 * (at_row(i / 2) + at_row(i / 2 + 1))
    }
}

/// The multigrid of one film problem at fixed Z.
pub struct PtMultigrid {
    fine: Fine,
    /// Halving from the fine level to coarse[0], and from coarse[l] to coarse[l + 1].
    halvings: Vec<Halving>,
    coarse: Vec<Coarse>,
    /// Smoothing sweeps before and after the coarse correction, and on the coarsest level.
    pub pre: usize,
    pub post: usize,
    pub coarsest_sweeps: usize,
    /// Coarse levels by Galerkin products with a truncated, operator-dependent prolongation
    /// (`galerkin`) instead of rediscretised faces.
    pub galerkin: bool,
    r: Vec<f64>,
    /// The gap as a function of Z, the ring link (None: Z fixed) and the current Z.
    gap: Gap,
    link: Option<RingLink>,
    z: f64,
    /// The Galerkin levels of the last V-cycle and the active set they are of.
    galerkin_levels: Option<(Vec<bool>, Vec<galerkin::Level>)>,
    /// ∂W_h/∂Z the ring's chord step assumes (the caller's estimate, e.g. from the last
    /// step; 0 treats W_h as independent of Z).
    pub dw_dz: f64,
}

impl PtMultigrid {
    /// The hierarchy of `step` (a time step: its φ_old is read) with the ring at `z`, down
    /// to the first mesh that cannot be halved further. With a ring link in `step`, every
    /// V-cycle also moves Z by a chord step on the ring equation ([`PtMultigrid::dw_dz`]).
    pub fn new(step: &Step, z: f64) -> PtMultigrid {
        let g = step.grid.clone();
        let nodes = g.nodes();
        let mut mg = PtMultigrid {
            fine: Fine {
                adv: step.boundary.u * g.dy,
                at: 2.0 * g.dx * g.dy * step.inv_dt,
                h: Vec::new(),
                cx: Vec::new(),
                cy: Vec::new(),
                old: step.phi_old.to_vec(),
                sc: vec![0.0; nodes],
                inv_sc: vec![0.0; nodes],
                p: vec![0.0; nodes],
                phi: vec![0.0; nodes],
                g,
            },
            halvings: Vec::new(),
            coarse: Vec::new(),
            pre: 2,
            post: 2,
            coarsest_sweeps: 50,
            galerkin: false,
            r: Vec::new(),
            gap: step.gap.clone(),
            link: step.ring,
            z,
            dw_dz: 0.0,
            galerkin_levels: None,
        };
        mg.set_z(z);
        mg
    }

    /// The gap and its conductances at ring position `z`, φ = h on the pressurised nodes;
    /// the rediscretised coarse levels are rebuilt by the next V-cycle that uses them.
    fn set_z(&mut self, z: f64) {
        self.z = z;
        let f = &mut self.fine;
        self.gap.fill(&f.g, z, &mut f.h);
        face_conductances(&f.g, &f.h, None, &self.gap, &mut f.cx, &mut f.cy);
        let (n1, n2) = (f.g.n1, f.g.n2);
        for i in 1..n1 {
            for j in 0..n2 {
                let k = i * n2 + j;
                f.sc[k] = conductance_sum(&f.g, &f.faces(), i, j);
                f.inv_sc[k] = 1.0 / f.sc[k];
            }
        }
        for ((phi, &h), &p) in f.phi.iter_mut().zip(&f.h).zip(&f.p) {
            if p > 0.0 {
                *phi = h;
            }
        }
        // The rediscretised levels are of this gap: built when a V-cycle needs them.
        self.coarse.clear();
    }

    /// The rediscretised ("faces") coarse levels of the current gap.
    fn faces_hierarchy(&mut self) {
        let f = &self.fine;
        self.halvings.clear();
        self.coarse.clear();
        let (mut n1, mut n2) = (f.g.n1, f.g.n2);
        for (hv, _, _) in halving_chain(&f.g) {
            let (fcx, fcy) = match self.coarse.last() {
                Some(c) => (&c.cx, &c.cy),
                None => (&f.cx, &f.cy),
            };
            let (m1, m2, ccx, ccy) = coarse_faces(fcx, fcy, n1, n2, hv);
            let fine_side = match self.coarse.last() {
                Some(c) => c.side.clone(),
                None => self.gap.ring.iter().map(|&r| Some(r)).collect(),
            };
            let side = (0..=m1)
                .map(|ic| {
                    let mut cols = x1_stencil(hv.x1, ic, n1).map(|(i, _)| fine_side[i]);
                    let first = cols.next().flatten();
                    if cols.all(|s| s == first) {
                        first
                    } else {
                        None
                    }
                })
                .collect();
            let m = (m1 + 1) * m2;
            self.halvings.push(hv);
            self.coarse.push(Coarse {
                n1: m1,
                n2: m2,
                cx: ccx,
                cy: ccy,
                side,
                active: vec![false; m],
                b: vec![0.0; m],
                e: vec![0.0; m],
            });
            (n1, n2) = (m1, m2);
        }
    }

    /// The ring after a V-cycle: a chord step on G(Z) = Z − z_pred − κ·(W_h(Z) + W_a(Z) − W_ps)
    /// (the Newmark update, docs/model.md §4) with slope 1 − κ·`dw_dz`, W_h from the current
    /// pressure; at most halving the smallest gap under the ring.
    fn move_ring(&mut self) {
        let Some(link) = self.link else {
            return;
        };
        let w = load(&self.fine.g, &self.gap.ring, &self.fine.p);
        // The asperity load (docs/model.md §11) with its exact slope, added only where it acts.
        let (w_a, dw_a) = link.contact.map_or((0.0, 0.0), |law| {
            contact_load(&self.fine.g, &self.gap, self.z, &law)
        });
        let g = if w_a == 0.0 {
            self.z - link.z_pred - link.kappa * (w - link.w_ps)
        } else {
            self.z - link.z_pred - link.kappa * (w + w_a - link.w_ps)
        };
        let dz = -g / (1.0 - link.kappa * self.dw_dz - link.kappa * dw_a);
        let floor = 0.5 * (self.z + self.gap.ring_min_base(&self.fine.g));
        let z = self.z + dz.max(-floor);
        self.set_z(z);
    }

    /// ∂W_h/∂Z of `step`'s film at fixed ring position `z` near `state`, by two fixed-Z
    /// solves (40 Galerkin V-cycles each) at z and z·(1 + 1e-4): a slope for
    /// [`PtMultigrid::dw_dz`] where no earlier step gives one.
    pub fn load_slope(step: &Step, state: &FilmState, z: f64) -> f64 {
        let fixed = Step {
            ring: None,
            ..*step
        };
        let w_at = |z: f64| {
            let mut mg = PtMultigrid::new(&fixed, z);
            mg.galerkin = true;
            mg.load(state);
            for _ in 0..40 {
                mg.vcycle();
            }
            mg.w_h()
        };
        let dz = 1e-4 * z;
        (w_at(z + dz) - w_at(z)) / dz
    }

    /// The ring position Z (µm) the state belongs to.
    pub fn z(&self) -> f64 {
        self.z
    }

    /// W_h of the current pressure (eq. 16).
    pub fn w_h(&self) -> f64 {
        load(&self.fine.g, &self.gap.ring, &self.fine.p)
    }

    /// The meshes of the hierarchy, finest first.
    pub fn meshes(&self) -> Vec<(usize, usize)> {
        let g = &self.fine.g;
        std::iter::once((g.n1, g.n2))
            .chain(halving_chain(g).into_iter().map(|(_, n1, n2)| (n1, n2)))
            .collect()
    }

    /// Starts from `state` (p and φ).
    pub fn load(&mut self, state: &FilmState) {
        self.fine.p.copy_from_slice(&state.p);
        self.fine.phi.copy_from_slice(&state.phi);
    }

    /// The current state into `state` (pressurised where p > 0).
    pub fn store(&self, state: &mut FilmState) {
        state.p.copy_from_slice(&self.fine.p);
        state.phi.copy_from_slice(&self.fine.phi);
        for (s, &p) in state.pressurised.iter_mut().zip(&self.fine.p) {
            *s = p > 0.0;
        }
    }

    /// Gauss–Seidel sweeps on the fine level only (the smoother alone, for comparison).
    pub fn smooth(&mut self, sweeps: usize) {
        self.fine.smooth(sweeps);
    }

    /// One V-cycle: smooth, coarse pressure correction on the active set, smooth.
    pub fn vcycle(&mut self) {
        if self.galerkin {
            self.galerkin_vcycle();
            self.move_ring();
            return;
        }
        self.fine.smooth(self.pre);
        if self.coarse.is_empty() {
            self.faces_hierarchy();
        }
        if !self.coarse.is_empty() {
            let f = &self.fine;
            let mut r = std::mem::take(&mut self.r);
            f.residual(&mut r);
            let active: Vec<bool> = f.p.iter().map(|&p| p > 0.0).collect();
            restrict(
                &r,
                &active,
                f.g.n1,
                f.g.n2,
                self.halvings[0],
                &mut self.coarse[0],
            );
            self.r = r;
            self.coarse_cycle(0);
            let (c, hv) = (&self.coarse[0], self.halvings[0]);
            let f = &mut self.fine;
            let n2f = f.g.n2;
            for i in 1..f.g.n1 {
                for j in 0..n2f {
                    let k = i * n2f + j;
                    if f.p[k] > 0.0 {
                        f.p[k] += prolonged(&c.e, c.n2, hv, i, j);
                    }
                }
            }
        }
        self.fine.smooth(self.post);
        self.move_ring();
    }

    /// The V-cycle with Galerkin coarse levels, built anew from the active set the
    /// pre-smoothing leaves (down to ≤ 64 unknowns, solved exactly).
    fn galerkin_vcycle(&mut self) {
        self.fine.smooth(self.pre);
        let f = &self.fine;
        let active: Vec<bool> = f.p.iter().map(|&p| p > 0.0).collect();
        // The levels of the last cycle serve while the active set is the same: they are then
        // of a gap at most a few ring updates old, which only blunts the coarse correction.
        let mut levels = match self.galerkin_levels.take() {
            Some((set, levels)) if set == active => levels,
            _ => self.galerkin_hierarchy(&active),
        };
        if levels.len() >= 2 {
            let mut r = std::mem::take(&mut self.r);
            self.fine.residual(&mut r);
            let r0: Vec<f64> = levels[0].nodes.iter().map(|&k| r[k]).collect();
            self.r = r;
            {
                let (a, b) = levels.split_at_mut(1);
                b[0].b.iter_mut().for_each(|x| *x = 0.0);
                a[0].pt.add_mul(&r0, &mut b[0].b);
            }
            galerkin::cycle(&mut levels, 1, self.pre, self.post);
            let mut e0 = vec![0.0; levels[0].nodes.len()];
            levels[0].p.add_mul(&levels[1].e, &mut e0);
            for (&k, e) in levels[0].nodes.iter().zip(e0) {
                self.fine.p[k] += e;
            }
        }
        self.galerkin_levels = Some((active, levels));
        self.fine.smooth(self.post);
    }

    /// The Galerkin levels of the pressurised set `active`, down to ≤ 64 unknowns.
    fn galerkin_hierarchy(&self, active: &[bool]) -> Vec<galerkin::Level> {
        let f = &self.fine;
        let mut levels = vec![galerkin::fine_level(f.g.n1, f.g.n2, &f.cx, &f.cy, active)];
        for (hv, _, _) in halving_chain(&f.g) {
            let last = levels.last_mut().expect("the fine level");
            if last.nodes.len() <= 64 {
                break;
            }
            let Some(next) = galerkin::coarsen(last, hv) else {
                break;
            };
            levels.push(next);
        }
        levels
    }

    fn coarse_cycle(&mut self, l: usize) {
        if l + 1 == self.coarse.len() {
            let n = self.coarsest_sweeps;
            self.coarse[l].smooth(n);
            return;
        }
        let (pre, post) = (self.pre, self.post);
        self.coarse[l].smooth(pre);
        let mut r = std::mem::take(&mut self.r);
        self.coarse[l].residual(&mut r);
        let hv = self.halvings[l + 1];
        {
            let (a, b) = self.coarse.split_at_mut(l + 1);
            let c = &a[l];
            restrict(&r, &c.active, c.n1, c.n2, hv, &mut b[0]);
        }
        self.r = r;
        // A level with (almost) nothing active below it is the coarsest of this cycle: the
        // smooth error must be solved somewhere.
        if self.coarse[l + 1].active.iter().filter(|&&a| a).count() < 4 {
            let n = self.coarsest_sweeps;
            self.coarse[l].smooth(n);
            return;
        }
        self.coarse_cycle(l + 1);
        {
            let (a, b) = self.coarse.split_at_mut(l + 1);
            let (c, cc) = (&mut a[l], &b[0]);
            let n2 = c.n2;
            for i in 1..c.n1 {
                for j in 0..n2 {
                    let k = i * n2 + j;
                    if c.active[k] {
                        c.e[k] += prolonged(&cc.e, cc.n2, hv, i, j);
                    }
                }
            }
        }
        self.coarse[l].smooth(post);
    }

    /// Largest nodal residual of the fine level relative to that node's largest flux term
    /// (the measure the film solver stops on).
    pub fn relative_residual(&self) -> f64 {
        let f = &self.fine;
        max_relative_residual(&f.g, &f.faces(), f.adv, f.at, &f.p, &f.phi, Some(&f.old))
    }
}

/// Most V-cycles of one solve, and the count past which its ring slope is measured again
/// (every step of Case III at `paper` converges in ≤ 25 to 1e-8 of the direct solution).
const PT_MAX_CYCLES: usize = 80;
const PT_SLOW: usize = 40;

/// The p–θ multigrid as a film solver: Galerkin V(2,2) cycles, Z moved after each, until the
/// largest relative nodal residual is at most 1e-12 (the flooded gap's large φ needs it for
/// the mass guard) and the last ring update at most 1e-10 µm.
#[derive(Default)]
pub struct PtSolver {
    gap: GapCache,
    /// The ∂W_h/∂Z its ring updates assume, measured at the first coupled solve and again
    /// whenever a solve needs more than [`PT_SLOW`] V-cycles.
    slope: Option<f64>,
}

impl PtSolver {
    fn cycles(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<usize, FilmError> {
        let tol = 1e-12;
        let mut cycles = 0;
        // A ring slope that has gone stale (the ring moved far since it was measured) shows as
        // a slow solve: measured again, the solve starts over once.
        for attempt in 0..2 {
            let mut mg = PtMultigrid::new(step, *z);
            mg.galerkin = true;
            if step.ring.is_some() {
                let slope = match self.slope {
                    Some(s) if attempt == 0 => s,
                    _ => PtMultigrid::load_slope(step, state, *z),
                };
                self.slope = Some(slope);
                mg.dw_dz = slope;
            }
            mg.load(state);
            for c in 1..=PT_MAX_CYCLES {
                let z_before = mg.z();
                mg.vcycle();
                cycles += 1;
                let moved = (mg.z() - z_before).abs();
                if !mg.z().is_finite() {
                    break;
                }
                if moved <= 1e-10f64.max(1e-12 * mg.z()) && mg.relative_residual() <= tol {
                    mg.store(state);
                    *z = mg.z();
                    return Ok(cycles);
                }
                if c == PT_SLOW && attempt == 0 && step.ring.is_some() {
                    break;
                }
            }
            if step.ring.is_none() {
                break;
            }
        }
        Err(FilmError::NotConverged {
            iterations: cycles,
            changes: 0,
            dz: f64::NAN,
            z: *z,
        })
    }
}

impl FilmMethod for PtSolver {
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        crate::solvers::refuse_cavity_pressure(step, "pt-multigrid")?;
        self.gap.begin(step);
        impose_boundary(step, state, *z);
        let cycles = self.cycles(step, state, z)?;
        finish(&mut self.gap, step, state, *z, cycles, cycles)
    }

    /// Stopped on its residual, its answer depends on its start by the tolerance: the
    /// previous state is taken as it is.
    fn carries_guess(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use texopt::model::case::{CaseSpec, Texture};
    use texopt::time::{Numerics, Transient};

    /// Largest |p − p*| relative to max p*, and the nodes whose active set differs.
    fn error(a: &FilmState, exact: &FilmState) -> (f64, usize) {
        let pmax = exact.p.iter().fold(0.0f64, |m, &p| m.max(p));
        let e =
            a.p.iter()
                .zip(&exact.p)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        let differ =
            a.p.iter()
                .zip(&exact.p)
                .filter(|(x, y)| (**x > 0.0) != (**y > 0.0))
                .count();
        (e / pmax, differ)
    }

    /// On a textured step with cavitation inside the pockets (Case III at 128×8, twelve and
    /// a half periods from the paper's start), from the solution a period before, 25
    /// V-cycles reach the direct solver's solution to 1e-6 of the largest pressure (seen:
    /// 1.3e-7; the rest sits at the ring's leading edge, see the module's notes), the same
    /// active set included, while as many Gauss–Seidel sweeps alone leave ≥ 30 times more (seen: 115):
    /// the coarse correction is what converges it. With Galerkin coarse levels the same
    /// cycles reach 1e-8.
    #[test]
    fn v_cycles_reach_the_direct_solution_where_the_smoother_alone_stalls() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        let num = Numerics {
            n1: 128,
            n2: 8,
            ..Numerics::default()
        };
        let mut t = Transient::new(&case, &num);
        let n = t.steps_per_period();
        let mut history = Vec::new();
        let mut before = t.ring_state();
        for _ in 0..12 * n + n / 2 {
            before = t.ring_state();
            t.step().expect("the direct solver's step");
            history.push(t.state().clone());
        }
        let exact = &t.state();
        let guess = &history[history.len() - 1 - n];
        let cavitated = exact.pressurised.iter().filter(|&&p| !p).count();
        assert!(cavitated > 0);
        let step = t.fixed_z_problem();
        let z = t.ring_state().z;
        let mg = PtMultigrid::new(&step, z);
        assert!(mg.meshes().len() >= 3, "{:?}", mg.meshes());
        let (e0, _) = error(guess, exact);
        let cycles = 25;
        let run = |galerkin: bool| {
            let mut mg = PtMultigrid::new(&step, z);
            mg.galerkin = galerkin;
            mg.load(guess);
            for _ in 0..cycles {
                mg.vcycle();
            }
            let mut st = guess.clone();
            mg.store(&mut st);
            error(&st, exact)
        };
        let (e, differ) = run(false);
        let (e_galerkin, differ_galerkin) = run(true);
        let mut gs = PtMultigrid::new(&step, z);
        gs.load(guess);
        gs.smooth(cycles * (gs.pre + gs.post));
        let mut st_gs = guess.clone();
        gs.store(&mut st_gs);
        let (e_gs, _) = error(&st_gs, exact);
        eprintln!(
            "p error: start {e0:.2e}, {cycles} V-cycles {e:.2e} (Galerkin {e_galerkin:.2e}), Gauss–Seidel alone {e_gs:.2e}"
        );
        assert!(e0 > 1e-6, "the start is already the solution ({e0:.2e})");
        assert!(e < 1e-6, "V-cycles left {e:.2e}");
        assert_eq!(differ, 0);
        assert!(e_gs > 30.0 * e, "the smoother alone reached {e_gs:.2e}");
        assert!(e_galerkin < 1e-8, "Galerkin V-cycles left {e_galerkin:.2e}");
        assert_eq!(differ_galerkin, 0);

        // With the ring: Z from the ring's velocity, moved after every V-cycle, lands on
        // the direct solver's Z and pressure.
        let coupled = Step {
            ring: Some(t.ring().link(&before, t.dt())),
            ..step
        };
        let z0 = before.z + t.dt() * before.v;
        let mut mg = PtMultigrid::new(&coupled, z0);
        mg.galerkin = true;
        mg.dw_dz = PtMultigrid::load_slope(&coupled, exact, z);
        mg.load(guess);
        for _ in 0..cycles {
            mg.vcycle();
        }
        let mut st = guess.clone();
        mg.store(&mut st);
        let (e_ring, _) = error(&st, exact);
        let ez = (mg.z() - z).abs() / z;
        eprintln!(
            "with the ring: Z from {:.2e} to {ez:.2e}, p error {e_ring:.2e}",
            (z0 - z).abs() / z
        );
        assert!(
            ez < 1e-9 && e_ring < 1e-8,
            "Z error {ez:.2e}, p error {e_ring:.2e}"
        );
    }

    /// Truncation can make a Galerkin operator singular (two coarse nodes over one lone fine
    /// node): the coarsest solve must still return a finite solution of a consistent system
    /// (it made NaNs before, and a V-cycle then emptied the film).
    #[test]
    fn the_coarsest_solve_survives_a_singular_galerkin_operator() {
        use galerkin::{cycle, Csr, Level};
        let level = Level {
            n1: 2,
            n2: 2,
            nodes: vec![0, 1],
            a: Csr {
                ncols: 2,
                ptr: vec![0, 2, 4],
                col: vec![0, 1, 0, 1],
                val: vec![2.0, 2.0, 2.0, 2.0],
            },
            p: Csr::default(),
            pt: Csr::default(),
            b: vec![3.0, 3.0],
            e: vec![f64::NAN; 2],
        };
        let mut levels = vec![level];
        cycle(&mut levels, 0, 2, 2);
        let e = &levels[0].e;
        assert!(e.iter().all(|x| x.is_finite()), "{e:?}");
        assert_eq!(2.0 * e[0] + 2.0 * e[1], 3.0);
    }

    /// The sparse products the Galerkin levels are built of, against dense arithmetic.
    #[test]
    fn sparse_products_match_dense_ones() {
        use galerkin::Csr;
        let dense = |m: &Csr| -> Vec<Vec<f64>> {
            let mut d = vec![vec![0.0; m.ncols]; m.ptr.len() - 1];
            for (r, row) in d.iter_mut().enumerate() {
                for k in m.ptr[r]..m.ptr[r + 1] {
                    row[m.col[k]] += m.val[k];
                }
            }
            d
        };
        // 3×4 and 4×2, with empty rows and unsorted use of columns.
        let a = Csr {
            ncols: 4,
            ptr: vec![0, 2, 2, 5],
            col: vec![0, 3, 1, 2, 3],
            val: vec![1.0, -2.0, 0.5, 3.0, 4.0],
        };
        let b = Csr {
            ncols: 2,
            ptr: vec![0, 1, 3, 3, 4],
            col: vec![1, 0, 1, 0],
            val: vec![2.0, -1.0, 5.0, 7.0],
        };
        let (da, db) = (dense(&a), dense(&b));
        let ab = dense(&a.mul(&b));
        for r in 0..3 {
            for c in 0..2 {
                let want: f64 = (0..4).map(|k| da[r][k] * db[k][c]).sum();
                assert_eq!(ab[r][c], want, "({r}, {c})");
            }
        }
        let at = dense(&a.transpose());
        for r in 0..3 {
            for c in 0..4 {
                assert_eq!(at[c][r], da[r][c]);
            }
        }
    }
}
