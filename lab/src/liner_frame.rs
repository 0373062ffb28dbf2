//! The textured film in the liner's frame, in two dimensions with the ring's dynamics
//! (results/liner_frame/, docs/solver.md "Deep pockets"). In the liner's frame the pockets
//! stand still and the ring's smooth face moves over them, so no rim crosses a control volume
//! during a step; the nodes follow the ring by k whole cells a step (dt = k·dx1/u), a
//! relabelling of the liner's film, no interpolation.
//!
//! The film equation of docs/model.md §3 read along the liner (ξ = x1 − u·t):
//! ∂(hθ)/∂t|ξ − ∂((u/2)·hθ)/∂ξ = ∇·(h³∇p), the Couette content carried at the ring's half
//! speed against the liner. Backward Euler along the liner: node i's storage term is
//! (φⁿ⁺¹_i − φⁿ_{i−k})/dt, the liner's film that was k cells upstream; BDF2 along the liner
//! relabels its older level by 2k cells, and falls back on backward Euler where its combined
//! old term would go negative.
//!
//! Solved by the product's film solver on the mirrored film (x1 → L − x1): there the Couette
//! content runs towards +x1 at u/2, as the product's stencil upwinds it, the old level moves
//! one cell against x1 per cell the liner moves, and the ring's implicit Newmark link is the
//! product's. The ring's face is symmetric about the domain's centre, so the mirrored scene is
//! the same contact with the texture placed at L − x1. The trailing end (x1 = L, the mirrored
//! inlet) brings in the liner's own film there, the mean across x2 of the node's old content;
//! the leading end's film (x1 = 0) is the flooded supply the liner brings. Friction is the
//! product's, on the film mirrored back.
//!
//! The ring's leading edge: ahead of the face the gap is e (1000 µm), under it a few µm, so
//! the film the liner carries under the face in one step is mostly more than the gap there
//! holds. The ring frame's stencil returns that excess through the wide gap by the small
//! pressure it takes (it lifts the ring by about 1 % at e = 1000 µm); here the excess of the
//! k columns that passed under the face is handed to the column just ahead of it, which
//! returns it the same way. Left under the face, more than one cell in, it would raise a
//! spurious pressure spike; dropped, the run would lose the lift and its mass balance.
//!
//! The gap: the product's (nodal along x1, the tier's strips across x2), or, with
//! `x1_samples` > 1, each node's texture depth the mean over that many points along its cell
//! (the cut cell's storage: in the liner's frame a cell's film volume does not change as the
//! texture passes, only the ring face's smooth part does). With `fitted`, the x1 faces where
//! a pocket lies between the nodes are fitted to the gap along x1 as well
//! ([`texopt::mesh::FittedFaces`]: each strip's exact one-dimensional conductance and Couette
//! content), and the friction is integrated along the faces with the same profile
//! ([`crate::liner_friction`]). The texture moves whole cells a step, so its depths are
//! computed once over a period (`PhaseTable`) and each step reads a column's phase.

use texopt::mesh::integrals::{boundary_flows, friction_thresholds};
use texopt::mesh::{sample_across, FilmState, FittedFaces, Grid, Scene};
use texopt::model::case::CaseSpec;
use texopt::model::film::Boundary;
use texopt::model::friction::{Friction, FrictionModel};
use texopt::model::ring::{Ring, RingState};
use texopt::solve::{FilmMethod, FilmSolver, Method, Step};
use texopt::time::{paper_start, texture_period};

use crate::liner_friction::fitted_friction;

/// How the liner-frame film is discretised: nodes followed per step, time scheme, samples of
/// the gap along each cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinerScheme {
    /// Whole cells the ring moves over the liner in one step (dt = k·dx1/u).
    pub k: usize,
    /// BDF2 along the liner (else backward Euler).
    pub bdf2: bool,
    /// Points along x1 each node's texture depth is the mean of (1: the node's own).
    pub x1_samples: usize,
    /// The x1 faces fitted to the gap along x1 wherever a pocket lies between their nodes,
    /// at `x1_samples` points a strip ([`texopt::mesh::FittedFaces`]): each strip's exact
    /// one-dimensional conductance and Couette content, the cell's mean gap as its storage.
    pub fitted: bool,
    /// The x2 faces fitted as well wherever a pocket lies between their rows: on each of
    /// `x1_samples` strips along x1 across the cell, 8 points between the rows in series.
    pub fitted_x2: bool,
}

/// One period's means: f̄ (the friction terms' total), mean and least Z (µm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PeriodMean {
    pub f_mean: f64,
    pub z_mean: f64,
    pub z_min: f64,
}

/// The liner-frame transient of one case on one mesh.
pub struct LinerFrame {
    case: CaseSpec,
    scheme: LinerScheme,
    /// The scene as the product orients it (x1 from the leading end), for the friction.
    scene: Scene,
    /// The mirrored scene the film solver sees (its column i is the scene's column n1 − i).
    mirrored: Scene,
    /// The film, mirrored.
    state: FilmState,
    /// The film one step earlier (mirrored), BDF2's older level.
    older: Option<Vec<f64>>,
    ring_state: RingState,
    dt: f64,
    steps_per_period: usize,
    steps: usize,
    solver: FilmSolver,
    /// Film-solve iterations, over all steps.
    pub iterations: usize,
    /// BDF2 steps taken as backward Euler (a combined old term negative somewhere).
    pub fallbacks: std::cell::Cell<usize>,
    /// The last step's old level (mirrored) and storage factor, for its mass balance.
    last_old: (Vec<f64>, f64),
    /// The texture's depths over a period.
    table: PhaseTable,
}

/// Why a liner-frame run cannot be set up or failed.
#[derive(Debug, thiserror::Error)]
pub enum LinerError {
    #[error("the texture period is not a whole number of {k}-cell steps on {n1} cells ({cells} cells a period): choose N1 so that per·N1/L is a multiple of k")]
    Period { k: usize, n1: usize, cells: f64 },
    #[error("the liner frame needs a textured case")]
    Untextured,
    #[error("the film solve failed at step {step}: {source}")]
    Film {
        step: usize,
        source: texopt::solve::FilmError,
    },
    #[error("the ring touched the liner at step {step} (Z = {z:e} µm)")]
    Contact { step: usize, z: f64 },
}

/// Column-reversed copy of a node field (columns of `n2` nodes).
fn mirror<T: Copy>(v: &[T], n2: usize) -> Vec<T> {
    v.chunks_exact(n2).rev().flatten().copied().collect()
}

/// The texture's depths over one period of whole cells, computed once: the texture moves
/// whole cells a step, so a column's depths at any step are those of its phase, the liner
/// position it holds modulo the period (a uniform lattice along x1).
struct PhaseTable {
    /// Cells a texture period.
    cells: usize,
    n2: usize,
    /// Samples across a cell, points along it.
    ns: usize,
    m: usize,
    /// Per phase c and row j: at each sample across the cell, the mean depth over `m` points
    /// along the cell centred at c·dx (the depth at c·dx when m = 1).
    cell: Vec<f64>,
    /// Per phase c and row j, strip after strip: the depth at `m` points along the face from
    /// c·dx back to (c − 1)·dx (empty when no face is fitted).
    face: Vec<f64>,
    /// Per phase c and row j < n2 − 1, strip after strip: on each of `m` strips along the
    /// cell centred at c·dx, the depth at [`X2_POINTS`] points from row j to row j + 1
    /// (empty when no x2 face is fitted).
    face_x2: Vec<f64>,
}

/// Points between two rows on each strip of a fitted x2 face.
const X2_POINTS: usize = 8;

impl PhaseTable {
    fn new(scene: &Scene, cells: usize, m: usize, (fitted, fitted_x2): (bool, bool)) -> Self {
        let (g, liner) = (&scene.grid, &scene.contact.liner);
        let ns = scene.rim.samples();
        let step = g.dx / m as f64;
        let (mut cell, mut face, mut face_x2, mut depths) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for c in 0..cells {
            let x = c as f64 * g.dx;
            for j in 0..g.n2 {
                let along = |y: f64| {
                    (0..m)
                        .map(|q| liner.depth_um(x - 0.5 * g.dx + (q as f64 + 0.5) * step, y))
                        .sum::<f64>()
                        / m as f64
                };
                let node = |y: f64| liner.depth_um(x, y);
                match m {
                    1 => sample_across(g.y(j), g.dy, ns, node, &mut depths),
                    _ => sample_across(g.y(j), g.dy, ns, along, &mut depths),
                }
                cell.extend_from_slice(&depths);
                if fitted_x2 {
                    let dy = g.dy / X2_POINTS as f64;
                    for q in 0..m {
                        let xq = x - 0.5 * g.dx + (q as f64 + 0.5) * step;
                        face_x2.extend(
                            (0..X2_POINTS)
                                .map(|r| liner.depth_um(xq, g.y(j) + (r as f64 + 0.5) * dy)),
                        );
                    }
                }
                if fitted {
                    for s in 0..ns {
                        let y = g.y(j) - 0.5 * g.dy + (s as f64 + 0.5) * g.dy / ns as f64;
                        face.extend((0..m).map(|q| liner.depth_um(x - (q as f64 + 0.5) * step, y)));
                    }
                }
            }
        }
        PhaseTable {
            cells,
            n2: g.n2,
            ns,
            m,
            cell,
            face,
            face_x2,
        }
    }

    fn face_x2(&self, c: usize, j: usize) -> &[f64] {
        let n = self.m * X2_POINTS;
        &self.face_x2[(c * self.n2 + j) * n..][..n]
    }

    /// The phase of column `col` once the texture has moved `shift` cells.
    fn phase(&self, col: usize, shift: usize) -> usize {
        (col + self.cells - shift % self.cells) % self.cells
    }

    fn cell(&self, c: usize, j: usize) -> &[f64] {
        &self.cell[(c * self.n2 + j) * self.ns..][..self.ns]
    }

    fn face(&self, c: usize, j: usize) -> &[f64] {
        let n = self.ns * self.m;
        &self.face[(c * self.n2 + j) * n..][..n]
    }
}

/// Places the texture moved `shift` cells in `scene`, mirrored or not: each node's depth from
/// the table (its cell's mean along x1, across x2 as the scene's rim model samples it); the
/// gap without Z is that depth plus the ring's part (eq. 15).
fn place(scene: &mut Scene, table: &PhaseTable, shift: usize, mirrored: bool) {
    let g = scene.grid.clone();
    let contact = scene.contact.clone();
    let ns = scene.rim.samples();
    scene.gap.rows.reset(g.nodes(), scene.rim);
    for i in 0..=g.n1 {
        let col = if mirrored { g.n1 - i } else { i };
        let x = g.x(col);
        scene.gap.ring[i] = contact.under_ring(x);
        let ring_part = contact.ring_part_um(x);
        let c = table.phase(col, shift);
        for j in 0..g.n2 {
            let k = g.idx(i, j);
            let depths = table.cell(c, j);
            let hl = if ns > 1 {
                scene.gap.rows.set(k, depths)
            } else {
                depths[0]
            };
            scene.hl[k] = hl;
            scene.gap.base[k] = hl + ring_part;
        }
    }
}

/// Fits the interior x1 faces of the mirrored `scene`, the texture moved `shift` cells
/// ([`LinerScheme::fitted`]): the gap without Z at the table's points between each face's
/// nodes on each strip across its cell, wherever a pocket lies there; the end faces stay
/// nodal (the film's boundary flows are theirs).
fn fit_faces(scene: &mut Scene, table: &PhaseTable, shift: usize) {
    let g = scene.grid.clone();
    let contact = &scene.contact;
    let (ns, m) = (table.ns, table.m);
    let mut fitted = FittedFaces::new(g.n1 * g.n2, ns, m);
    let mut base = Vec::with_capacity(ns * m);
    let step = g.dx / m as f64;
    for i in 1..g.n1.saturating_sub(1) {
        // Mirrored column i is the scene's column n1 − i: the face runs back from there.
        let col = g.n1 - i;
        let c = table.phase(col, shift);
        let ring: Vec<(f64, bool)> = (0..m)
            .map(|q| g.x(col) - (q as f64 + 0.5) * step)
            .map(|x| (contact.ring_part_um(x), contact.under_ring(x)))
            .collect();
        let under: Vec<bool> = (0..ns).flat_map(|_| ring.iter().map(|r| r.1)).collect();
        for j in 0..g.n2 {
            let depths = table.face(c, j);
            if depths.iter().all(|&d| d <= 0.0) {
                continue;
            }
            base.clear();
            base.extend(depths.iter().enumerate().map(|(n, d)| d + ring[n % m].0));
            fitted.set(g.idx(i, j), &base, &under);
        }
    }
    scene.gap.fitted = Some(fitted);
}

/// Fits the x2 faces of the interior columns of the mirrored `scene`, the texture moved
/// `shift` cells ([`LinerScheme::fitted_x2`]): on each strip along x1 across the cell, the
/// gap without Z at the table's points between the two rows, wherever a pocket lies there.
fn fit_x2_faces(scene: &mut Scene, table: &PhaseTable, shift: usize) {
    let g = scene.grid.clone();
    let contact = &scene.contact;
    let (m, ny) = (table.m, g.n2.saturating_sub(1));
    let mut fitted = FittedFaces::new((g.n1 + 1) * ny, m, X2_POINTS);
    let mut base = Vec::with_capacity(m * X2_POINTS);
    let step = g.dx / m as f64;
    for i in 1..g.n1 {
        let col = g.n1 - i;
        let c = table.phase(col, shift);
        let ring: Vec<(f64, bool)> = (0..m)
            .map(|q| g.x(col) - 0.5 * g.dx + (q as f64 + 0.5) * step)
            .map(|x| (contact.ring_part_um(x), contact.under_ring(x)))
            .collect();
        let under: Vec<bool> = (0..m)
            .flat_map(|q| std::iter::repeat_n(ring[q].1, X2_POINTS))
            .collect();
        for j in 0..ny {
            let depths = table.face_x2(c, j);
            if depths.iter().all(|&d| d <= 0.0) {
                continue;
            }
            base.clear();
            base.extend(
                depths
                    .iter()
                    .enumerate()
                    .map(|(n, d)| d + ring[n / X2_POINTS].0),
            );
            fitted.set(i * ny + j, &base, &under);
        }
    }
    scene.gap.fitted_x2 = Some(fitted);
}

/// The storage term's old level and its factor times dt along the liner, from the last level
/// and, for BDF2, the one before it, each already moved with the liner: BDF2's combined
/// (4φⁿ − φⁿ⁻¹)/3 with 3/2, or backward Euler's φⁿ with 1 where there is no older level or the
/// combined one would go negative somewhere.
pub fn bdf2_old_level(last: Vec<f64>, older: Option<Vec<f64>>) -> (Vec<f64>, f64) {
    let Some(o) = older else {
        return (last, 1.0);
    };
    let combined: Vec<f64> = last
        .iter()
        .zip(&o)
        .map(|(a, b)| (4.0 * a - b) / 3.0)
        .collect();
    if combined.iter().all(|&c| c >= 0.0) {
        (combined, 1.5)
    } else {
        (last, 1.0)
    }
}

impl LinerFrame {
    /// The case on `scene`'s mesh (rim model included), from the paper's start with the ring
    /// at `z0` (None: the case's own start).
    pub fn new(
        case: &CaseSpec,
        scene: Scene,
        scheme: LinerScheme,
        z0: Option<f64>,
    ) -> Result<Self, LinerError> {
        let per = case.texture.as_ref().ok_or(LinerError::Untextured)?.per;
        let g = scene.grid.clone();
        let cells = per / g.dx / scheme.k as f64;
        let steps_per_period = cells.round() as usize;
        let cells_per_period = steps_per_period * scheme.k;
        if (cells - steps_per_period as f64).abs() > 1e-6 || steps_per_period == 0 {
            return Err(LinerError::Period {
                k: scheme.k,
                n1: g.n1,
                cells: per / g.dx,
            });
        }
        let dt = texture_period(case) / steps_per_period as f64;
        let mut scene = scene;
        let fits = (scheme.fitted, scheme.fitted_x2);
        let table = PhaseTable::new(&scene, cells_per_period, scheme.x1_samples, fits);
        place(&mut scene, &table, 0, false);
        let (start, mut ring_state) = paper_start(&scene, case);
        if let Some(z) = z0 {
            ring_state.z = z;
        }
        let mut mirrored = scene.clone();
        place(&mut mirrored, &table, 0, true);
        if scheme.fitted {
            fit_faces(&mut mirrored, &table, 0);
        }
        if scheme.fitted_x2 {
            fit_x2_faces(&mut mirrored, &table, 0);
        }
        let n2 = g.n2;
        let state = FilmState {
            p: mirror(&start.p, n2),
            phi: mirror(&start.phi, n2),
            pressurised: mirror(&start.pressurised, n2),
            cavity: mirror(&start.cavity, n2),
        };
        Ok(LinerFrame {
            case: case.clone(),
            scheme,
            scene,
            mirrored,
            state,
            older: None,
            ring_state,
            dt,
            steps_per_period,
            steps: 0,
            solver: FilmSolver::new(Method::Direct),
            iterations: 0,
            fallbacks: std::cell::Cell::new(0),
            last_old: (Vec::new(), 0.0),
            table,
        })
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn steps_per_period(&self) -> usize {
        self.steps_per_period
    }

    pub fn ring_state(&self) -> RingState {
        self.ring_state
    }

    fn grid(&self) -> &Grid {
        &self.scene.grid
    }

    /// The film `level` (mirrored) moved with the liner by `by` cells: node i holds what node
    /// i + by held (mirrored, the liner runs towards −x1), the flooded supply beyond the
    /// leading end. Film carried from ahead of the ring to under its face is capped at the gap
    /// there (at the last step's Z), and what is above the cap is given to the node just
    /// ahead of the ring's face: there the wide gap (e) returns it by the pressure it needs,
    /// which a node under the face, more than a cell in, could only do by a spurious spike.
    fn moved(&self, level: &[f64], by: usize) -> Vec<f64> {
        let (n1, n2) = (self.grid().n1, self.grid().n2);
        let (gap, z) = (&self.mirrored.gap, self.ring_state.z);
        let supply = self.case.d_oil;
        let mut out: Vec<f64> = (0..=n1)
            .flat_map(|i| (0..n2).map(move |j| (i, j)))
            .map(|(i, j)| {
                let k = i * n2 + j;
                if i + by <= n1 {
                    level[k + by * n2]
                } else {
                    supply.min(gap.base[k])
                }
            })
            .collect();
        // The ring's leading edge: its last column under the face (mirrored).
        let Some(edge) = gap.ring.iter().rposition(|&r| r) else {
            return out;
        };
        if edge == n1 {
            return out;
        }
        for i in (edge + 1).saturating_sub(by)..=edge {
            for j in 0..n2 {
                let k = i * n2 + j;
                let excess = out[k] - (gap.base[k] + z);
                if excess > 0.0 {
                    out[k] -= excess;
                    out[(edge + 1) * n2 + j] += excess;
                }
            }
        }
        out
    }

    /// The storage term's old level and 1/dt factor: backward Euler along the liner, or BDF2
    /// (3φⁿ⁺¹ − 4φⁿ + φⁿ⁻¹)/(2dt) with each older level moved with the liner, backward Euler
    /// where its combined old term would go negative.
    fn old_level(&self) -> (Vec<f64>, f64) {
        let k = self.scheme.k;
        let last = self.moved(&self.state.phi, k);
        let older = self.older.as_ref().filter(|_| self.scheme.bdf2);
        let (old, per_dt) = bdf2_old_level(last, older.map(|o| self.moved(o, 2 * k)));
        if older.is_some() && per_dt == 1.0 {
            self.fallbacks.set(self.fallbacks.get() + 1);
        }
        (old, per_dt / self.dt)
    }

    /// One step: the texture moved k cells under the ring, the film solved along the liner
    /// with the ring's Newmark link; returns the friction after it.
    pub fn step(&mut self) -> Result<Friction, LinerError> {
        let shift = (self.steps + 1) * self.scheme.k;
        place(&mut self.scene, &self.table, shift, false);
        place(&mut self.mirrored, &self.table, shift, true);
        if self.scheme.fitted {
            fit_faces(&mut self.mirrored, &self.table, shift);
        }
        if self.scheme.fitted_x2 {
            fit_x2_faces(&mut self.mirrored, &self.table, shift);
        }
        let (old, inv_dt) = self.old_level();
        let n2 = self.grid().n2;
        // The trailing end brings in the liner's film there (one value across x2).
        let trailing = old[..n2].iter().sum::<f64>() / n2 as f64;
        let ring = Ring {
            mass: self.case.mass,
            w_ps: self.case.w_ps,
            contact: self.case.contact_law(),
        };
        let before = self.state.phi.clone();
        let step = Step {
            grid: &self.mirrored.grid,
            gap: &self.mirrored.gap,
            phi_old: &old,
            inv_dt,
            boundary: Boundary {
                phi_inlet: trailing,
                ..self.case.film_boundary()
            },
            ring: Some(ring.link(&self.ring_state, self.dt)),
        };
        let mut z = (self.ring_state.z + self.dt * self.ring_state.v).max(0.5 * self.ring_state.z);
        let stats = self
            .solver
            .solve(&step, &mut self.state, &mut z)
            .map_err(|source| LinerError::Film {
                step: self.steps + 1,
                source,
            })?;
        if z <= texopt::time::CONTACT_Z {
            return Err(LinerError::Contact {
                step: self.steps + 1,
                z,
            });
        }
        self.iterations += stats.iterations;
        self.ring_state = ring.advance(&self.ring_state, self.dt, z, stats.w_h + stats.w_a);
        // The leading end holds the flooded supply the liner brings (not the outflow the
        // solver copies there).
        let n1 = self.grid().n1;
        for j in 0..n2 {
            let k = n1 * n2 + j;
            self.state.phi[k] = self.case.d_oil.min(self.mirrored.gap.base[k]);
        }
        self.older = Some(before);
        self.steps += 1;
        self.last_old = (old, inv_dt);
        Ok(self.friction())
    }

    /// The last step's relative mass defect: |Σ(φⁿ⁺¹ − old)·area/dt − (inflow − outflow)| over
    /// the interior control volumes, relative to |inflow| + |outflow| through the x1 ends
    /// (round-off when the relabelled old level and the stencil's fluxes balance).
    pub fn mass_defect(&self) -> f64 {
        let g = &self.mirrored.grid;
        let (old, inv_dt) = (&self.last_old.0, self.last_old.1);
        let change = (g.n2..g.n1 * g.n2)
            .map(|k| self.state.phi[k] - old[k])
            .sum::<f64>()
            * g.dx
            * g.dy
            * inv_dt;
        let (inflow, outflow) = boundary_flows(
            g,
            &self.mirrored.gap,
            self.ring_state.z,
            (self.case.u, self.case.u),
            &self.state,
        );
        (change - (inflow - outflow)).abs() / (inflow.abs() + outflow.abs())
    }

    /// The friction of the present film: the product's, on the film mirrored back, or with
    /// fitted faces their own integrals along x1 ([`fitted_friction`]).
    fn friction(&self) -> Friction {
        let n2 = self.grid().n2;
        let film = FilmState {
            p: mirror(&self.state.p, n2),
            phi: mirror(&self.state.phi, n2),
            pressurised: mirror(&self.state.pressurised, n2),
            cavity: mirror(&self.state.cavity, n2),
        };
        let model = FrictionModel {
            u: self.case.u,
            theta_s: self.case.theta_s,
            w_ps: self.case.w_ps,
            contact: self.case.contact_law(),
        };
        let g = &self.scene.grid;
        let nodal = friction_thresholds(
            g,
            &self.scene.gap,
            self.ring_state.z,
            &self.scene.hl,
            &film,
            &model,
            &[],
        )
        .0;
        if !self.scheme.fitted {
            return nodal;
        }
        let shift = self.steps * self.scheme.k;
        let table = &self.table;
        let depth = |i: usize, j: usize| table.face(table.phase(g.n1 - i, shift), j).to_vec();
        fitted_friction(
            &self.mirrored,
            &self.state,
            self.ring_state.z,
            &model,
            depth,
            nodal.boundary,
        )
    }

    /// One texture period: its mean friction and its mean and least Z.
    pub fn period(&mut self) -> Result<PeriodMean, LinerError> {
        let n = self.steps_per_period;
        let (mut f, mut z, mut z_min) = (0.0, 0.0, f64::INFINITY);
        for _ in 0..n {
            f += self.step()?.total();
            z += self.ring_state.z;
            z_min = z_min.min(self.ring_state.z);
        }
        Ok(PeriodMean {
            f_mean: f / n as f64,
            z_mean: z / n as f64,
            z_min,
        })
    }

    /// Periods until the periodic regime: the distance of f̄ and of the least Z from their
    /// limits, estimated from the last three periods as a geometric tail, below `tol`
    /// (relative), or `max_periods`. Returns the last period and whether it got there.
    pub fn run_to_periodic(
        &mut self,
        tol: f64,
        max_periods: usize,
    ) -> Result<(PeriodMean, bool, usize), LinerError> {
        let mut last: Vec<PeriodMean> = Vec::new();
        for period in 1..=max_periods {
            last.push(self.period()?);
            if last.len() >= 3 {
                let n = last.len();
                let tail = |q: fn(&PeriodMean) -> f64| {
                    let (a, b, c) = (q(&last[n - 3]), q(&last[n - 2]), q(&last[n - 1]));
                    let (d1, d2) = (b - a, c - b);
                    let r = (d2 / d1).abs().min(0.95);
                    (d2.abs() * r / (1.0 - r)).max(d2.abs()) / c.abs()
                };
                if tail(|p| p.f_mean) < tol && tail(|p| p.z_min) < tol {
                    return Ok((last[n - 1], true, period));
                }
            }
        }
        Ok((
            *last.last().expect("at least one period"),
            false,
            max_periods,
        ))
    }

    /// The least clearance (µm) of a least Z.
    pub fn clearance(&self, z_min: f64) -> f64 {
        self.scene.contact.clearance_um(z_min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirroring_reverses_the_columns() {
        let v: Vec<usize> = (0..6).collect();
        assert_eq!(mirror(&v, 2), vec![4, 5, 2, 3, 0, 1]);
        assert_eq!(mirror(&mirror(&v, 3), 3), v);
    }
}
