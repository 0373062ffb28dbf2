//! The film equation and its one discrete stencil (docs/model.md §3; paper eqs. 4, 5, 14).
//!
//! Nondimensional Elrod–Adams film (docs/model.md §3, with the factor 2 the scales imply):
//!
//! ```text
//!     ∇·(h³ ∇p) = u ∂(hθ)/∂x1 + 2 ∂(hθ)/∂t,   p ≥ p_c, 0 ≤ θ ≤ 1, (p − p_c)·(1 − θ) = 0
//! ```
//!
//! i.e. ∂φ/∂t + ∇·q = 0 with φ = hθ and mass flux q = (u/2)·φ·e1 − (h³/2)·∇p; p_c is the
//! cavity pressure, 0 in the paper, each side's gas pressure in general ([`Boundary`]).
//!
//! Finite volumes: vertex-centred in x1 (node columns i = 0..=n1), cell-centred in x2 (rows
//! j = 0..n2, zero-flux walls). Couette flux upwinded ((u/2)·φ_i at face i+½ for u > 0),
//! Poiseuille flux centred with the face gap the mean of the two nodal gaps, backward Euler on
//! φ with h at the new time level. Node (i, j) is stored at i·n2 + j. Every solver path
//! (Newton residual and Jacobian, Z-derivative, upwind sweeps, mass checks, and the lab's
//! solvers) evaluates the film through [`Column::balance`]: there is one stencil. The
//! characteristic time scheme (time/characteristic.rs) uses it with u = 0 and the old level
//! moved along the Couette characteristics, which then carry the Couette flux.

use super::flow_factors::FlowFactors;

/// Boundary data along x1 (docs/model.md §3).
#[derive(Clone, Copy, Debug)]
pub struct Boundary {
    /// Liner speed u (≥ 0; u = 1 in the paper) of the Couette flux (u/2)·φ the stencil
    /// carries: 0 where the old level carries it (the characteristic scheme).
    pub u: f64,
    /// Liner speed of a rough film's share of the Couette flux, (u/2)·(κ − 1)·φ
    /// (docs/model.md §11, "Flow factors"): the liner's speed in every time scheme, as no old
    /// level carries it. Unused on a smooth film.
    pub u_rough: f64,
    /// Pressure at x1 = 0 and at x1 = length (0 in the paper).
    pub p_left: f64,
    pub p_right: f64,
    /// Film φ = hθ carried in at x1 = 0 (µm); capped at the local gap (θ ≤ 1) per node.
    pub phi_inlet: f64,
    /// Cavity pressure of the gas at x1 = 0 and of the gas at x1 = length (0 in the paper):
    /// a cavity open to one end holds its gas's pressure (docs/model.md §3, "Gas pressures";
    /// `mesh::cavity_pressures`).
    pub cavity_left: f64,
    pub cavity_right: f64,
}

impl Boundary {
    /// The film between end pressures `p_left` and `p_right`, its cavities at 0 (the paper's),
    /// the liner at speed `u` (the stencil carrying the Couette flux), the inlet bringing
    /// `phi_inlet`.
    pub fn with_ends(u: f64, (p_left, p_right): (f64, f64), phi_inlet: f64) -> Self {
        Boundary {
            u,
            u_rough: u,
            p_left,
            p_right,
            phi_inlet,
            cavity_left: 0.0,
            cavity_right: 0.0,
        }
    }

    /// The cavity pressure p_c of node column i of n1 cells for a cavity open to both ends
    /// (docs/model.md §3): the left end's where 2i < n1, the right end's where 2i > n1, their
    /// mean at the centre column. The split is symmetric under the mirror i → n1 − i.
    #[inline(always)]
    pub fn cavity_pressure(&self, i: usize, n1: usize) -> f64 {
        match (2 * i).cmp(&n1) {
            std::cmp::Ordering::Less => self.cavity_left,
            std::cmp::Ordering::Greater => self.cavity_right,
            std::cmp::Ordering::Equal => 0.5 * (self.cavity_left + self.cavity_right),
        }
    }

    /// The lower of the two cavity pressures: the pressure below which a full film away from
    /// any cavity ruptures (docs/model.md §3).
    #[inline(always)]
    pub fn rupture_pressure(&self) -> f64 {
        self.cavity_left.min(self.cavity_right)
    }

    /// Whether the two ends' cavity pressures differ (a cavity's pressure then depends on
    /// which end it is open to, docs/model.md §3).
    #[inline(always)]
    pub fn split_cavity(&self) -> bool {
        self.cavity_left != self.cavity_right
    }
}

/// Poiseuille conductance of a face between nodal gaps `a` and `b`: h_f³·s with
/// h_f = (a + b)/2, the mean of the two nodal gaps (docs/model.md §3), and s the face's
/// geometry factor (dy/dx across an x1 face, dx/dy across an x2 face).
#[inline(always)]
pub fn face_conductance(a: f64, b: f64, s: f64) -> f64 {
    let hf = 0.5 * (a + b);
    hf * hf * hf * s
}

/// A strip's Poiseuille conductance before its geometry factor: h³, times the pressure flow
/// factor φx(h) on a rough film (docs/model.md §3, §11), for the faces whose rows vary
/// across their cells (the mesh's rows sampled across each cell).
#[inline(always)]
pub fn strip_conductance(h: f64, flow: Option<&FlowFactors>) -> f64 {
    match flow {
        None => h * h * h,
        Some(f) => h * h * h * f.pressure_flow(h).0,
    }
}

/// Mass flux of φ through an x1 face per unit width (docs/model.md §3): the upwind Couette
/// part (u/2)·φ_upstream and the centred Poiseuille part −(h_f³/2)·∂p/∂x1 (a rough film's
/// pressure flow factor φx is in `dp`, its shear flow in the caller's content: §11).
#[inline]
pub fn x1_flux(u: f64, phi_upstream: f64, h_face: f64, dp: f64, dx: f64) -> f64 {
    0.5 * u * phi_upstream - 0.5 * h_face * h_face * h_face * dp / dx
}

/// Face conductances of a mesh: `cx[i·n2 + j]` of the x1 face east of node (i, j),
/// `cy[i·(n2 − 1) + j]` of the x2 face north of node (i, j); and `rough`, per node, the
/// coefficient u·dy·(κ − 1) of the rough film's share of the Couette flux (u/2)·κ·φ, which
/// the stencil carries in every time scheme (docs/model.md §11, "Flow factors"); empty for a
/// smooth film (κ = 1).
#[derive(Clone, Copy)]
pub struct Faces<'a> {
    pub cx: &'a [f64],
    pub cy: &'a [f64],
    pub rough: &'a [f64],
}

impl<'a> Faces<'a> {
    /// Conductances of a smooth film.
    pub fn new(cx: &'a [f64], cy: &'a [f64]) -> Self {
        Faces { cx, cy, rough: &[] }
    }
}

/// What the stencil reads around node column i, sliced once for the column: a pass over a
/// column then indexes slices of length n2 (no bounds check per term), with the same
/// arithmetic in the same order as node by node.
pub struct Column<'a> {
    /// Pressures of columns i − 1, i, i + 1.
    pub p_w: &'a [f64],
    pub p: &'a [f64],
    pub p_e: &'a [f64],
    /// Film content φ = hθ of columns i − 1 (upstream) and i, and φ at the old time level.
    pub phi_w: &'a [f64],
    pub phi: &'a [f64],
    pub old: Option<&'a [f64]>,
    /// Conductances of the x1 faces west and east of the column, and of its n2 − 1 x2 faces.
    pub cx_w: &'a [f64],
    pub cx_e: &'a [f64],
    pub cy: &'a [f64],
    /// The rough film's Couette coefficients of columns i − 1 and i ([`Faces::rough`]);
    /// empty for a smooth film.
    pub rough_w: &'a [f64],
    pub rough: &'a [f64],
}

impl<'a> Column<'a> {
    /// Column i (1 ≤ i < n1) of fields with n2 nodes a column. `phi` may end at column i
    /// (exclusive) when the caller holds column i's φ apart ([`Column::balance_with`]).
    #[inline(always)]
    pub fn new(
        n2: usize,
        f: &Faces<'a>,
        p: &'a [f64],
        phi: &'a [f64],
        phi_old: Option<&'a [f64]>,
        i: usize,
    ) -> Self {
        let (w, c, e) = ((i - 1) * n2, i * n2, (i + 1) * n2);
        Column {
            p_w: &p[w..c],
            p: &p[c..e],
            p_e: &p[e..e + n2],
            phi_w: &phi[w..c],
            phi: phi.get(c..e).unwrap_or(&[]),
            old: phi_old.map(|o| &o[c..e]),
            cx_w: &f.cx[w..c],
            cx_e: &f.cx[c..e],
            cy: &f.cy[i * (n2 - 1)..(i + 1) * (n2 - 1)],
            rough_w: f.rough.get(w..c).unwrap_or(&[]),
            rough: f.rough.get(c..e).unwrap_or(&[]),
        }
    }

    /// The stencil at node (i, j): −(discrete film equation), i.e. the mass balance
    /// Σ_faces c·(p_ij − p_nb) + adv·(φ_ij − φ_{i−1,j}) + at·(φ_ij − φ_old,ij) with
    /// adv = u·dy and at = 2·dx·dy/dt (0 when steady), and on a rough film
    /// r_ij·φ_ij − r_{i−1,j}·φ_{i−1,j} with r = u·dy·(κ − 1) ([`Faces::rough`]). It is (−2)× [net outflow + cell area ·
    /// ∂φ/∂t] of the control volume (docs/model.md §3).
    #[inline(always)]
    pub fn balance(&self, adv: f64, at: f64, j: usize) -> f64 {
        self.balance_with(adv, at, j, self.phi[j])
    }

    /// The stencil at node (i, j) with φ_ij given (the column's own φ held apart).
    #[inline(always)]
    pub fn balance_with(&self, adv: f64, at: f64, j: usize, phi_j: f64) -> f64 {
        let n2 = self.p.len();
        let pk = self.p[j];
        let mut r = self.cx_w[j] * (pk - self.p_w[j]) + self.cx_e[j] * (pk - self.p_e[j]);
        if j > 0 {
            r += self.cy[j - 1] * (pk - self.p[j - 1]);
        }
        if j + 1 < n2 {
            r += self.cy[j] * (pk - self.p[j + 1]);
        }
        r += adv * (phi_j - self.phi_w[j]);
        if !self.rough.is_empty() {
            r += self.rough[j] * phi_j - self.rough_w[j] * self.phi_w[j];
        }
        r += at * phi_j;
        if let Some(old) = self.old {
            r -= at * old[j];
        }
        r
    }

    /// ∂(balance)/∂φ through the Couette flux of node (i, j) and (negated) of the node
    /// upstream: adv, plus r on a rough film.
    #[inline(always)]
    pub fn couette_slopes(&self, adv: f64, j: usize) -> (f64, f64) {
        if self.rough.is_empty() {
            (adv, adv)
        } else {
            (adv + self.rough[j], adv + self.rough_w[j])
        }
    }

    /// Sum of the four face conductances of node (i, j): ∂(balance)/∂p_ij.
    #[inline(always)]
    pub fn conductance_sum(&self, j: usize) -> f64 {
        let n2 = self.p.len();
        let mut c = self.cx_w[j] + self.cx_e[j];
        if j > 0 {
            c += self.cy[j - 1];
        }
        if j + 1 < n2 {
            c += self.cy[j];
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × n2 block of fields around column 1.
    fn block(
        n2: usize,
        p: impl Fn(usize, usize) -> f64,
        phi: impl Fn(usize, usize) -> f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let mut pv = vec![0.0; 3 * n2];
        let mut fv = vec![0.0; 3 * n2];
        for i in 0..3 {
            for j in 0..n2 {
                pv[i * n2 + j] = p(i, j);
                fv[i * n2 + j] = phi(i, j);
            }
        }
        (pv, fv)
    }

    #[test]
    fn the_cavity_pressure_split_mirrors_with_the_sides() {
        let bc = Boundary {
            u: 1.0,
            u_rough: 1.0,
            p_left: 3.0,
            p_right: 1.0,
            phi_inlet: 1.0,
            cavity_left: 3.0,
            cavity_right: 1.0,
        };
        let mirrored = Boundary {
            cavity_left: 1.0,
            cavity_right: 3.0,
            ..bc
        };
        for n1 in [8, 9] {
            for i in 0..=n1 {
                assert_eq!(
                    bc.cavity_pressure(i, n1),
                    mirrored.cavity_pressure(n1 - i, n1)
                );
            }
        }
        assert_eq!(bc.cavity_pressure(3, 8), 3.0);
        assert_eq!(bc.cavity_pressure(4, 8), 2.0);
        assert_eq!(bc.cavity_pressure(5, 8), 1.0);
        assert_eq!(bc.rupture_pressure(), 1.0);
    }

    #[test]
    fn a_constant_pressure_full_film_carries_exactly_the_couette_flux() {
        // Uniform gap h, uniform p, θ = 1: no Poiseuille flux, and in a steady state the
        // Couette flux in equals the flux out: the balance is zero at every node.
        let (n2, h) = (4, 3.0);
        let (p, phi) = block(n2, |_, _| 0.7, |_, _| h);
        let c = face_conductance(h, h, 2.0);
        let (cx, cy) = (vec![c; 3 * n2], vec![c; 3 * (n2 - 1)]);
        let faces = Faces::new(&cx, &cy);
        let col = Column::new(n2, &faces, &p, &phi, None, 1);
        for j in 0..n2 {
            assert_eq!(col.balance(0.25, 0.0, j), 0.0);
        }
        // The flux through an x1 face is then (u/2)·h exactly.
        assert_eq!(x1_flux(1.0, h, h, 0.0, 0.1), 0.5 * h);
    }

    #[test]
    fn the_balance_is_minus_two_times_net_outflow_plus_storage() {
        // Node (1, j) of a linear pressure along x1 in a uniform gap: the two x1 faces
        // carry the same Poiseuille flux, so only the Couette imbalance and storage remain.
        let (n2, h, dx, dy, u, dt) = (3, 2.0, 0.1, 0.05, 1.0, 0.01);
        let (p, phi) = block(n2, |i, _| 1.0 - 0.2 * i as f64, |i, _| 1.5 + 0.1 * i as f64);
        let cxv = face_conductance(h, h, dy / dx);
        let cyv = face_conductance(h, h, dx / dy);
        let (cx, cy) = (vec![cxv; 3 * n2], vec![cyv; 3 * (n2 - 1)]);
        let old = vec![1.4; 3 * n2];
        let faces = Faces::new(&cx, &cy);
        let col = Column::new(n2, &faces, &p, &phi, Some(&old), 1);
        let (adv, at) = (u * dy, 2.0 * dx * dy / dt);
        for j in 0..n2 {
            let out = (x1_flux(u, 1.6, h, -0.2, dx) - x1_flux(u, 1.5, h, -0.2, dx)) * dy;
            let storage = dx * dy * (1.6 - 1.4) / dt;
            let expect = 2.0 * (out + storage);
            assert!((col.balance(adv, at, j) - expect).abs() < 1e-12, "{j}");
        }
    }

    #[test]
    fn a_rough_film_carries_kappa_phi_whichever_part_the_old_level_carries() {
        // Column 1 of a rough film, κ per node: the stencil at liner speed u (adv = u·dy,
        // r = u·dy·(κ − 1)) carries (u/2)·κ·φ; with adv = 0 (the old level carrying (u/2)·φ)
        // it keeps the roughness's part (u/2)·(κ − 1)·φ alone.
        let n2 = 3;
        let (p, phi) = block(n2, |_, _| 0.0, |i, j| 1.0 + 0.2 * i as f64 + 0.1 * j as f64);
        let kappa = |i: usize, j: usize| 1.05 + 0.01 * (i + j) as f64;
        let (u, dy) = (1.3, 0.25);
        let rough: Vec<f64> = (0..3 * n2)
            .map(|k| u * dy * (kappa(k / n2, k % n2) - 1.0))
            .collect();
        let (cx, cy) = (vec![0.0; 3 * n2], vec![0.0; 3 * (n2 - 1)]);
        let faces = Faces {
            cx: &cx,
            cy: &cy,
            rough: &rough,
        };
        let col = Column::new(n2, &faces, &p, &phi, None, 1);
        for j in 0..n2 {
            let (kp, kw) = (kappa(1, j), kappa(0, j));
            let (fp, fw) = (phi[n2 + j], phi[j]);
            let full = u * dy * (kp * fp - kw * fw);
            assert!((col.balance(u * dy, 0.0, j) - full).abs() < 1e-14, "{j}");
            let part = u * dy * ((kp - 1.0) * fp - (kw - 1.0) * fw);
            assert!((col.balance(0.0, 0.0, j) - part).abs() < 1e-14, "{j}");
            let (s, sw) = col.couette_slopes(u * dy, j);
            assert!((s - u * dy * kp).abs() < 1e-14 && (sw - u * dy * kw).abs() < 1e-14);
        }
    }

    #[test]
    fn the_stencil_is_symmetric_across_x2() {
        // Fields mirrored about the middle row give mirrored balances.
        let n2 = 5;
        let pf = |i: usize, j: usize| (1.0 + i as f64) * (1.0 + (j as f64 - 2.0).powi(2));
        let ff = |i: usize, j: usize| 2.0 + 0.1 * i as f64 + 0.05 * (j as f64 - 2.0).abs();
        let (p, phi) = block(n2, pf, ff);
        let h = |_i: usize, j: usize| 1.0 + 0.3 * (j as f64 - 2.0).abs();
        let cx: Vec<f64> = (0..3 * n2)
            .map(|k| face_conductance(h(k / n2, k % n2), h(k / n2 + 1, k % n2), 2.0))
            .collect();
        let cy: Vec<f64> = (0..3 * (n2 - 1))
            .map(|k| {
                face_conductance(
                    h(k / (n2 - 1), k % (n2 - 1)),
                    h(k / (n2 - 1), k % (n2 - 1) + 1),
                    0.5,
                )
            })
            .collect();
        let faces = Faces::new(&cx, &cy);
        let col = Column::new(n2, &faces, &p, &phi, None, 1);
        for j in 0..n2 {
            let (a, b) = (col.balance(0.3, 0.0, j), col.balance(0.3, 0.0, n2 - 1 - j));
            assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{j}: {a} {b}");
        }
    }

    #[test]
    fn the_diagonal_is_the_sum_of_the_face_conductances() {
        let n2 = 3;
        let (p, phi) = block(n2, |i, j| (i * n2 + j) as f64, |_, _| 1.0);
        let cx: Vec<f64> = (0..3 * n2).map(|k| 1.0 + k as f64).collect();
        let cy: Vec<f64> = (0..3 * (n2 - 1)).map(|k| 0.5 + k as f64).collect();
        let faces = Faces::new(&cx, &cy);
        let col = Column::new(n2, &faces, &p, &phi, None, 1);
        for j in 0..n2 {
            // ∂balance/∂p_ij by a unit change of p_ij.
            let mut p2 = p.clone();
            p2[n2 + j] += 1.0;
            let col2 = Column::new(n2, &faces, &p2, &phi, None, 1);
            let d = col2.balance(0.0, 0.0, j) - col.balance(0.0, 0.0, j);
            assert!((d - col.conductance_sum(j)).abs() < 1e-12);
        }
    }
}
