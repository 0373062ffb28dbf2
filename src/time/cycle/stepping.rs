//! The engine cycle as one transient (docs/model.md §12): the film of §3 under the ring as the
//! liner slides back and forth beneath it, the ring's radial dynamics of §4 under the engine's
//! load, the liner's texture and oil where the stroke has put them, stepped through the crank
//! angle and repeated cycle after cycle until the cycle repeats itself.
//!
//! The film is always solved in a frame where the liner moves towards +x1 (the stencil's
//! upwinding, docs/model.md §3): when the liner's direction turns, at a dead centre, the film
//! and the boundary data are mirrored, x1 → length − x1. The ring's face is symmetric about
//! the domain's centre, so the mirrored scene is the same contact seen from the other side.

use super::drive::{crank_steps, Drive, DrivePoint};
use super::oil::OilMap;
use super::record::{CycleRow, CycleSummary, OilBalance};
use super::tiers::{CycleEnd, CycleNumerics};
use crate::mesh::integrals::{boundary_flows, friction};
use crate::mesh::{FilmState, Grid, Scene};
use crate::model::case::CaseSpec;
use crate::model::film::Boundary;
use crate::model::friction::{Friction, FrictionModel};
use crate::model::liner_layout::LinerLayout;
use crate::model::ring::{Ring, RingState};
use crate::solve::{FilmMethod, FilmSolver, Step};
use crate::time::characteristic::{courant, shift, MAX_COURANT};
use crate::time::common::{Observers, SolveError, MASS_TOL};
use crate::time::coupled::{guard_mass, RingStep};
use crate::time::start::equilibrium_start;
use crate::time::steady::solve_untextured;
use crate::time::TimeScheme;

/// Who watches a cycle run: a closure after every cycle (its summary), one after every
/// crank step (its row).
pub type CycleWatch<'a> = Observers<'a, CycleRow, CycleSummary>;

/// What a cycle run found: its last cycle step by step, every cycle's summary, the oil map
/// at the end, and where the run stands then (for another liner's run to start from).
#[derive(Clone, Debug)]
pub struct CycleOutcome {
    pub rows: Vec<CycleRow>,
    pub cycles: Vec<CycleSummary>,
    /// Why the run stopped.
    pub stopped: CycleEnd,
    /// Liner coordinates (cm) and layers (µm) of the oil map after the last cycle.
    pub oil_y_cm: Vec<f64>,
    pub oil_um: Vec<f64>,
    pub end: CycleState,
}

impl CycleOutcome {
    /// Whether the last cycle repeated the one before within the tolerance.
    pub fn cyclic(&self) -> bool {
        self.stopped == CycleEnd::Repeated
    }
}

/// Cycles after which a run resumed from another liner's cyclic state on the same engine
/// ([`CycleRun::resume`]) is settled: the oil map's memory is one cycle (each stretch of liner
/// the ring passes is laid anew on each pass), so the first cycle still meets the other
/// liner's oil and the second its own. Measured on the example engine's uniform Case I
/// texture at draft: first cycle 0.55 % off the converged work, second 1.6e-5
/// (docs/model.md §12).
pub const SETTLE_CYCLES: usize = 2;

/// Where a cycle run stands at the end of a cycle: film, ring, oil map. A run of another
/// liner of the same engine, ring and mesh may start from it ([`CycleRun::resume`]): its
/// first cycle then starts near its own cyclic state instead of the untextured force
/// balance, and is settled after [`SETTLE_CYCLES`].
#[derive(Clone, Debug)]
pub struct CycleState {
    film: Standing,
    oil: OilMap,
    /// The oil map's cell length the run was asked for (its numerics').
    oil_cell_cm: f64,
}

/// Film and ring where a run stands: what a step changes but the oil map (which it changes
/// only once its film is solved), so what a step taken again in halves starts from.
#[derive(Debug)]
struct Standing {
    scene: Scene,
    state: FilmState,
    phi_old: Vec<f64>,
    ring: RingState,
    /// Whether the film is solved mirrored (the liner moving towards the combustion chamber).
    mirrored: bool,
    /// The lattice width the film is simulated across (half of it), None: one cell across.
    width: Option<f64>,
    /// The inlet film of the last step (µm): the layer the liner brings.
    phi_inlet: f64,
    /// The asperities' share of the load at the end of the last step.
    last_share: f64,
}

/// Field by field; `clone_from` keeps the arrays' allocations (a step saves where the run
/// stands into the buffer the last step's save left).
impl Clone for Standing {
    fn clone(&self) -> Self {
        Standing {
            scene: self.scene.clone(),
            state: self.state.clone(),
            phi_old: self.phi_old.clone(),
            ..*self
        }
    }

    fn clone_from(&mut self, s: &Self) {
        self.scene.clone_from(&s.scene);
        self.state.clone_from(&s.state);
        self.phi_old.clone_from(&s.phi_old);
        (self.ring, self.mirrored, self.width) = (s.ring, s.mirrored, s.width);
        (self.phi_inlet, self.last_share) = (s.phi_inlet, s.last_share);
    }
}

/// The film, ring and oil of a cycle run, stepped one crank step at a time.
pub struct CycleRun<'a> {
    drive: &'a Drive,
    layout: LinerLayout,
    case: CaseSpec,
    /// Film, ring and oil map: where the run stands.
    st: CycleState,
    solver: FilmSolver,
    numerics: CycleNumerics,
    tally: OilBalance,
    /// Where the run stood before its last step, kept to save the next one into (a step is
    /// saved before it is tried, and restored where it is taken again in halves).
    spare: Option<Standing>,
}

impl<'a> CycleRun<'a> {
    /// The run of `layout` under `drive`'s engine, at its first cycle's start: the
    /// untextured force balance at the start's operating point laid on the liner.
    /// `ring`: the engine's ring as a case ([`Drive::ring_case`], its contact as the run
    /// wants it).
    pub fn new(
        drive: &'a Drive,
        ring: CaseSpec,
        layout: LinerLayout,
        numerics: CycleNumerics,
    ) -> Result<Self, SolveError> {
        let case = ring;
        let p0 = drive.at(numerics.start_deg);
        let (length, x_c) = {
            let c = case.contact();
            (c.length_cm, c.x_center_cm)
        };
        let (a, b) = case.contact().ring_edges();
        let width = layout.width_over(p0.position_cm + a - x_c, p0.position_cm + b - x_c);
        let scene = film_scene(&case, &numerics, width);
        let supply = |y: f64| 0.5 * drive.engine().d_oil_um(10.0 * y.max(0.0));
        let stroke_cm = 0.1 * drive.engine().file.engine.stroke_mm;
        let oil = OilMap::new(-x_c, stroke_cm + length - x_c, numerics.oil_cell_cm, supply);
        let start_case = CaseSpec {
            u: p0.u.abs(),
            w_ps: p0.w,
            d_oil: 2.0 * supply(p0.position_cm),
            ..case.clone()
        };
        let eq =
            solve_untextured(&start_case, numerics.n1).map_err(|source| SolveError::Steady {
                case: cycle_label(drive),
                source,
            })?;
        let (state, ring) = equilibrium_start(&scene, &eq);
        let st = CycleState {
            film: Standing {
                scene,
                phi_old: state.phi.clone(),
                state,
                ring,
                mirrored: p0.u < 0.0,
                width,
                phi_inlet: start_case.d_oil,
                last_share: 0.0,
            },
            oil,
            oil_cell_cm: numerics.oil_cell_cm,
        };
        let mut run = CycleRun {
            drive,
            layout,
            case,
            st,
            solver: numerics.solver(),
            numerics,
            tally: OilBalance::default(),
            spare: None,
        };
        run.place(&p0);
        Ok(run)
    }

    /// The run of `layout` started from `from`, the end of a cycle of another liner on the
    /// same engine, ring (`ring`) and numerics (the start angle, the film's cells along x1,
    /// the oil map's cells); the film is carried onto the lattice under the ring at the start
    /// as at any change of lattice. Where `from` was run on other cells the run starts as
    /// [`CycleRun::new`] does.
    pub fn resume(
        drive: &'a Drive,
        ring: CaseSpec,
        layout: LinerLayout,
        numerics: CycleNumerics,
        from: &CycleState,
    ) -> Result<Self, SolveError> {
        let g = &from.film.scene.grid;
        let same_cells = g.n1 == numerics.n1
            && (from.film.width.is_none() || g.n2 == numerics.n2)
            && from.oil_cell_cm == numerics.oil_cell_cm;
        if !same_cells {
            return Self::new(drive, ring, layout, numerics);
        }
        let p0 = drive.at(numerics.start_deg);
        let mut run = CycleRun {
            drive,
            layout,
            case: ring,
            st: from.clone(),
            solver: numerics.solver(),
            numerics,
            tally: OilBalance::default(),
            spare: None,
        };
        run.regrid(&p0);
        run.place(&p0);
        Ok(run)
    }

    /// Where the run stands (see [`CycleState`]).
    fn snapshot(&self) -> CycleState {
        self.st.clone()
    }

    /// The oil the film holds, Σφ·dx·dy/B over the interior nodes (µm·cm per unit
    /// circumferential length; the inlet column's film is the boundary's).
    pub fn film_oil(&self) -> f64 {
        self.oil_of(&self.st.film.state.phi)
    }

    /// The oil of film content `phi` on the run's grid (see [`CycleRun::film_oil`]).
    fn oil_of(&self, phi: &[f64]) -> f64 {
        let g = &self.st.film.scene.grid;
        let s: f64 = phi[g.n2..g.n1 * g.n2].iter().sum();
        s * g.dx * g.dy / g.width
    }

    pub fn oil(&self) -> &OilMap {
        &self.st.oil
    }

    /// The liner coordinate (cm) under solve-frame position `x` with the ring at
    /// `position_cm` from its top-dead-centre position.
    fn liner_y(&self, position_cm: f64, x: f64) -> f64 {
        let c = &self.st.film.scene.contact;
        let x_phys = if self.st.film.mirrored {
            c.length_cm - x
        } else {
            x
        };
        position_cm + x_phys - c.x_center_cm
    }

    /// The texture under the ring with the ring at `p`'s position (docs/model.md §12: the
    /// liner's depth at the liner coordinate under each node). Pockets are placed under the
    /// ring and one node column either side (the friction's ∂h_L/∂x1 reads them); beyond, the
    /// gap is e, against which a pocket's depth is nothing, and the film there does not vary
    /// across: so the film is one cell across whenever no pocket is under the ring.
    fn place(&mut self, p: &DrivePoint) {
        let g = self.st.film.scene.grid.clone();
        let cols = self.st.film.scene.gap.ring_columns();
        let textured = cols.start.saturating_sub(1)..(cols.end + 1).min(g.n1 + 1);
        for i in 0..=g.n1 {
            let y = self.liner_y(p.position_cm, g.x(i));
            let ring_part = self.st.film.scene.contact.ring_part_um(g.x(i));
            for j in 0..g.n2 {
                let k = g.idx(i, j);
                let hl = if textured.contains(&i) && self.st.film.width.is_some() {
                    self.layout.depth_um(y, g.y(j))
                } else {
                    0.0
                };
                self.st.film.scene.hl[k] = hl;
                self.st.film.scene.gap.base[k] = hl + ring_part;
            }
        }
    }

    /// The film across the lattice width the ring is over at `p` (one cell across where it is
    /// over a plain liner), its content carried over column by column so that each column
    /// keeps its oil: spread in proportion to the new gap (its θ uniform across). The old
    /// level may then hold more than a shallower lattice's gap, as after a squeeze: the step's
    /// storage term presses it out. While the ring straddles two lattices of different widths
    /// the film is simulated across the width of the one under its centre, the other's
    /// pockets sampled on that grid (docs/model.md §12).
    fn regrid(&mut self, p: &DrivePoint) {
        let (a, b) = self.st.film.scene.contact.ring_edges();
        let x_c = self.st.film.scene.contact.x_center_cm;
        let width = self
            .layout
            .width_over(p.position_cm + a - x_c, p.position_cm + b - x_c);
        if width == self.st.film.width {
            return;
        }
        self.st.film.width = width;
        let old = std::mem::replace(
            &mut self.st.film.scene,
            film_scene(&self.case, &self.numerics, width),
        );
        self.place(p);
        let z = self.st.film.ring.z;
        let phi = carry(&old, &self.st.film.state.phi, &self.st.film.scene, z);
        self.st.film.phi_old = carry(&old, &self.st.film.phi_old, &self.st.film.scene, z);
        let g = &self.st.film.scene.grid;
        self.st.film.state = FilmState::cavitated(g, &self.st.film.scene.gap, z, 0.0);
        for (k, f) in phi.into_iter().enumerate() {
            self.st.film.state.phi[k] = f.min(self.st.film.scene.gap.h(g, k, z));
        }
        self.solver = self.numerics.solver();
    }

    /// At a dead centre, the oil the ring has pushed ahead of itself into the free gap before
    /// its leading edge, beyond the layer the liner brought there, leaves the liner: thrown
    /// into the ring's land, above it at top dead centre and below at bottom dead centre
    /// (docs/model.md §12). The liner's own layer stays, for the ring to meet on its way back.
    fn throw_off_bank(&mut self) {
        let g = &self.st.film.scene.grid;
        let (a, _) = self.st.film.scene.contact.ring_edges();
        let mut thrown = 0.0;
        for i in (1..g.n1).take_while(|&i| g.x(i) < a) {
            for j in 0..g.n2 {
                let k = g.idx(i, j);
                let keep = self.st.film.state.phi[k].min(self.st.film.phi_inlet);
                thrown += self.st.film.state.phi[k] - keep;
                self.st.film.state.phi[k] = keep;
                self.st.film.state.p[k] = 0.0;
                self.st.film.state.pressurised[k] = false;
            }
        }
        self.tally.thrown += thrown * g.dx * g.dy / g.width;
        self.st
            .film
            .phi_old
            .copy_from_slice(&self.st.film.state.phi);
    }

    /// Mirrors the film and its old level, x1 → length − x1 (the liner's direction turned).
    fn mirror(&mut self) {
        let g = &self.st.film.scene.grid;
        let n2 = g.n2;
        for i in 0..g.n1.div_ceil(2) {
            let m = g.n1 - i;
            for j in 0..n2 {
                let (a, b) = (i * n2 + j, m * n2 + j);
                self.st.film.state.p.swap(a, b);
                self.st.film.state.phi.swap(a, b);
                self.st.film.state.pressurised.swap(a, b);
                self.st.film.phi_old.swap(a, b);
            }
        }
        self.st.film.mirrored = !self.st.film.mirrored;
    }
}

/// The film's scene: one cell across a plain liner's film, `numerics.n2` across half a
/// lattice of `width`.
fn film_scene(case: &CaseSpec, numerics: &CycleNumerics, width: Option<f64>) -> Scene {
    let contact = case.contact();
    let length = contact.length_cm;
    let (n2, half) = width.map_or((1, 1.0), |w| (numerics.n2, 0.5 * w));
    let grid = Grid::new(numerics.n1, n2, length, half);
    Scene::with_grid(contact, grid, 1.0, case.flow)
}

/// Film content `phi` on scene `from` carried onto scene `to` (the same node columns) with
/// the ring at `z`: each column's mean content kept, spread in proportion to `to`'s gap.
fn carry(from: &Scene, phi: &[f64], to: &Scene, z: f64) -> Vec<f64> {
    let (gf, gt) = (&from.grid, &to.grid);
    let mut out = vec![0.0; gt.nodes()];
    for i in 0..=gt.n1 {
        let mean = phi[i * gf.n2..(i + 1) * gf.n2].iter().sum::<f64>() / gf.n2 as f64;
        let h: Vec<f64> = (0..gt.n2).map(|j| to.gap.h(gt, gt.idx(i, j), z)).collect();
        let h_mean = h.iter().sum::<f64>() / gt.n2 as f64;
        for (j, hj) in h.iter().enumerate() {
            out[gt.idx(i, j)] = mean * hj / h_mean;
        }
    }
    out
}

/// The run's name in messages.
fn cycle_label(drive: &Drive) -> String {
    format!("engine {} cycle", drive.engine().file.engine.name)
}

/// Most halvings of a crank step whose film solve does not converge.
pub const MAX_HALVINGS: usize = 4;

/// What a crank step came to: its row, or a call to take it again in halves (the
/// asperities' share changed too much over it).
enum Stepped {
    Row(CycleRow),
    Refine,
}

/// A run's state before a step, to take the step again in halves.
struct Saved {
    film: Standing,
    tally: OilBalance,
}

/// How a crank step reads its old level ([`CycleRun::old_level`]).
struct OldLevel {
    /// The liner's speed in the stencil: 0 where the old level carries the Couette flux.
    stencil_u: f64,
    /// The oil the move carries in at the inlet and out past the last interior column over
    /// the step (µm·cm per unit circumferential length; 0 without the move).
    carried: (f64, f64),
}

/// What a step's film exchanged with the liner.
struct Exchange {
    /// Oil taken off the liner ahead, its layer (µm), and the inlet film φ = 2·layer.
    taken: f64,
    layer_met: f64,
    phi_inlet: f64,
    /// Liner swept by the leading and the trailing edge over the step (cm, their two ends).
    lead: (f64, f64),
    trail: (f64, f64),
}

impl CycleRun<'_> {
    /// The crank from `from` to `to` degrees (no dead centre strictly between) in one step,
    /// or in halves (at most [`MAX_HALVINGS`] deep) where its film solve does not converge or
    /// the asperities' share of the load changes by more than the step rule's
    /// `contact_share` over it: the step follows the dynamics where they outrun the crank's
    /// steps. Returns the rows of the steps taken.
    pub fn advance(&mut self, from: f64, to: f64) -> Result<Vec<CycleRow>, SolveError> {
        self.advance_halving(from, to, 0)
    }

    fn advance_halving(
        &mut self,
        from: f64,
        to: f64,
        depth: usize,
    ) -> Result<Vec<CycleRow>, SolveError> {
        let saved = self.save();
        match self.try_step(from, to, depth < MAX_HALVINGS) {
            Ok(Stepped::Row(row)) => {
                self.spare = Some(saved.film);
                Ok(vec![row])
            }
            Ok(Stepped::Refine) | Err(SolveError::Film { .. }) if depth < MAX_HALVINGS => {
                self.restore(saved);
                let mid = 0.5 * (from + to);
                let mut rows = self.advance_halving(from, mid, depth + 1)?;
                rows.extend(self.advance_halving(mid, to, depth + 1)?);
                Ok(rows)
            }
            Ok(Stepped::Refine) => unreachable!("a step is refined only above the least halving"),
            Err(e) => Err(e),
        }
    }

    /// What a step changes but the oil map (which it changes only once its film is solved),
    /// into the spare buffer where there is one.
    fn save(&mut self) -> Saved {
        let film = match self.spare.take() {
            Some(mut f) => {
                f.clone_from(&self.st.film);
                f
            }
            None => self.st.film.clone(),
        };
        Saved {
            film,
            tally: self.tally,
        }
    }

    /// Back to `s`; where the step had got to becomes the spare buffer.
    fn restore(&mut self, s: Saved) {
        self.spare = Some(std::mem::replace(&mut self.st.film, s.film));
        self.tally = s.tally;
        // A failed solve may leave its factors in any state.
        self.solver = self.numerics.solver();
    }

    /// One crank step from `from` to `to` degrees (no dead centre strictly between): the
    /// film of the step's end with the ring's implicit Newmark update, the liner's speed the
    /// step's mean (its displacement over the step's time, so the texture moves and the oil
    /// is carried exactly as far as the crank moves the ring).
    pub fn step(&mut self, from: f64, to: f64) -> Result<CycleRow, SolveError> {
        self.try_step(from, to, false).map(|s| match s {
            Stepped::Row(row) => row,
            Stepped::Refine => unreachable!("a step not allowed to refine gives its row"),
        })
    }

    /// [`CycleRun::step`], or [`Stepped::Refine`] where `may_refine` and the asperities' share of the load
    /// changes by more than the step rule's `contact_share` over the step (the run is then
    /// left mid-step: the caller restores it).
    fn try_step(&mut self, from: f64, to: f64, may_refine: bool) -> Result<Stepped, SolveError> {
        let (a, b) = (self.drive.at(from), self.drive.at(to));
        let dt = self.drive.time_of(to - from);
        // The liner's displacement under the ring along x1 is −(the ring's along the stroke).
        let u = -(b.position_cm - a.position_cm) / dt;
        if (u < 0.0) != self.st.film.mirrored && u != 0.0 {
            self.throw_off_bank();
            self.mirror();
        }
        self.regrid(&b);
        self.place(&b);
        let ex = self.exchange_ahead(&a, &b);
        self.st.film.phi_inlet = ex.phi_inlet;
        let boundary = self.boundary(&b, u.abs(), ex.phi_inlet);
        let contact = self.case.contact_law();
        let rs = RingStep {
            ring: Ring {
                mass: self.case.mass,
                w_ps: b.w,
                contact,
            },
            from: self.st.film.ring,
            dt,
        };
        let drive = self.drive;
        let label = || cycle_label(drive);
        let mut z = rs.guess(rs.predicted(), label, to)?;
        // The old level: the film as the last step left it, carried onto this step's grid,
        // and moved along the Couette characteristics where the scheme and the step allow.
        let old = self.old_level(u.abs(), dt, ex.phi_inlet);
        let phi_old = &self.st.film.phi_old;
        let film_before = self.oil_of(phi_old);
        let step = Step {
            grid: &self.st.film.scene.grid,
            gap: &self.st.film.scene.gap,
            phi_old,
            inv_dt: 1.0 / dt,
            boundary: Boundary {
                u: old.stencil_u,
                ..boundary
            },
            ring: Some(rs.link()),
        };
        let stats = self
            .solver
            .solve(&step, &mut self.st.film.state, &mut z)
            .map_err(|source| SolveError::Film {
                case: label(),
                t: to,
                source,
            })?;
        let ring = rs.close(z, &stats, label, to)?;
        let share = stats.w_a / b.w;
        if may_refine && (share - self.st.film.last_share).abs() > self.numerics.steps.contact_share
        {
            return Ok(Stepped::Refine);
        }
        self.st.film.last_share = share;
        self.st.film.ring = ring;
        let outflow = self.exchange_oil(&old, &ex, (u.abs(), dt, to), z, film_before)?;
        let f = friction(
            &self.st.film.scene.grid,
            &self.st.film.scene.gap,
            z,
            &self.st.film.scene.hl,
            &self.st.film.state,
            &FrictionModel {
                u: u.abs(),
                theta_s: self.case.theta_s,
                w_ps: b.w,
                contact,
            },
        );
        let mut row = self.row(&b, u, z, &f, ex.layer_met, outflow / dt);
        row.step_deg = to - from;
        row.asperity_share = share;
        row.lambda = contact.map_or(f64::INFINITY, |c| row.h_min_um / c.sigma_um());
        Ok(Stepped::Row(row))
    }

    /// The oil a solved step exchanged: in and out through the film's ends (the stencil's
    /// flows at liner speed `u` over `dt`, and the shifted Couette content), the film's
    /// balance checked, the liner's oil map and the cycle's tally updated, and the film
    /// kept as the next step's old level. Returns the oil out past the trailing edge.
    fn exchange_oil(
        &mut self,
        old: &OldLevel,
        ex: &Exchange,
        (u, dt, to): (f64, f64, f64),
        z: f64,
        film_before: f64,
    ) -> Result<f64, SolveError> {
        let (inflow, outflow) = self.flows((old.stencil_u, u), z);
        let (inflow, outflow) = (dt * inflow + old.carried.0, dt * outflow + old.carried.1);
        self.check_mass(
            film_before,
            inflow - outflow - (old.carried.0 - old.carried.1),
            inflow.abs() + outflow.abs(),
            to,
        )?;
        let t = self.st.oil.take(
            ex.lead.0,
            ex.lead.1,
            self.drive.ahead(self.st.film.mirrored),
        );
        self.tally.supplied += t.supplied;
        self.tally.scraped += t.scraped;
        self.tally.thrown += ex.taken - inflow;
        self.tally.thrown += if self.drive.keeps_trail() {
            self.st.oil.put(ex.trail.0, ex.trail.1, outflow)
        } else {
            outflow
        };
        self.st
            .film
            .phi_old
            .copy_from_slice(&self.st.film.state.phi);
        Ok(outflow)
    }

    /// The old level a step of `dt` at liner speed `u` reads, with inlet film `phi_inlet`.
    /// Along the characteristics (docs/solver.md, "Time scheme"), where the scheme asks for
    /// it and u·dt/(2·dx1) ≤ 1, φⁿ is moved in place by that many cells downstream, the
    /// inlet's film entering behind it: the Couette flux is that move, so the stencil's liner
    /// speed is 0. Otherwise φⁿ stays as it is, at the liner's speed. (A step that is taken
    /// again restores φⁿ; one that goes through replaces it.)
    fn old_level(&mut self, u: f64, dt: f64, phi_inlet: f64) -> OldLevel {
        let g = &self.st.film.scene.grid;
        let c = courant(u, dt, g.dx);
        if self.numerics.scheme != TimeScheme::Characteristic || c > MAX_COURANT {
            return OldLevel {
                stencil_u: u,
                carried: (0.0, 0.0),
            };
        }
        let phi = &mut self.st.film.phi_old;
        phi[..g.n2].fill(phi_inlet);
        // What the move brings in at the inlet and takes past the last interior column
        // (characteristic.rs: Σφ changes by c·(column 0) − c·(column n1 − 1)).
        let column = |i: usize| phi[i * g.n2..(i + 1) * g.n2].iter().sum::<f64>();
        let area = c.min(1.0) * g.dx * g.dy / g.width;
        let carried = (area * column(0), area * column(g.n1 - 1));
        shift(phi, g.n1, g.n2, c.min(1.0));
        OldLevel {
            stencil_u: 0.0,
            carried,
        }
    }

    /// The oil the leading edge meets over the step from `a` to `b`: taken off the liner
    /// ahead (the supply's towards the crankcase, the ring's own oil on the way back).
    fn exchange_ahead(&self, a: &DrivePoint, b: &DrivePoint) -> Exchange {
        let length = self.st.film.scene.contact.length_cm;
        let (lead_a, lead_b) = (
            self.liner_y(a.position_cm, 0.0),
            self.liner_y(b.position_cm, 0.0),
        );
        let trail = (
            self.liner_y(a.position_cm, length),
            self.liner_y(b.position_cm, length),
        );
        // Mirrored: the liner moves towards the combustion chamber, the ring towards the
        // crankcase.
        let t = self
            .st
            .oil
            .meet(lead_a, lead_b, self.drive.ahead(self.st.film.mirrored));
        Exchange {
            taken: t.layer * (lead_b - lead_a).abs(),
            layer_met: t.layer,
            phi_inlet: 2.0 * t.layer,
            lead: (lead_a, lead_b),
            trail,
        }
    }

    /// The film's boundary data in the solve frame: the liner's speed, the gas pressures on
    /// the two sides (above the ring at x1 = 0 unless mirrored) and the inlet film.
    fn boundary(&self, b: &DrivePoint, u: f64, phi_inlet: f64) -> Boundary {
        let (p_left, p_right) = if self.st.film.mirrored {
            (b.p_below, b.p_above)
        } else {
            (b.p_above, b.p_below)
        };
        Boundary {
            u,
            u_rough: u,
            p_left,
            p_right,
            phi_inlet,
            cavity_left: p_left,
            cavity_right: p_right,
        }
    }

    /// Oil flow rates into and out of the film (per unit circumferential length, through the
    /// faces next to the domain's ends): the stencil's, at liner speeds `u`
    /// ([`boundary_flows`]).
    fn flows(&self, u: (f64, f64), z: f64) -> (f64, f64) {
        let g = &self.st.film.scene.grid;
        let (i, o) = boundary_flows(g, &self.st.film.scene.gap, z, u, &self.st.film.state);
        (i / g.width, o / g.width)
    }

    /// Guard ([`guard_mass`]): the film's oil changed by what flowed in and out, to
    /// round-off.
    fn check_mass(&self, before: f64, net: f64, through: f64, to: f64) -> Result<(), SolveError> {
        let defect = (self.film_oil() - before - net).abs() / through.max(f64::MIN_POSITIVE);
        // The totals hold the wide gap's oil; their difference carries its round-off.
        let tol = MASS_TOL.max(1e-12 * self.film_oil() / through.max(f64::MIN_POSITIVE));
        guard_mass(defect, tol, || cycle_label(self.drive), to)
    }

    /// The step's row in the engine's units.
    fn row(
        &self,
        b: &DrivePoint,
        u: f64,
        z: f64,
        f: &Friction,
        met: f64,
        outflow: f64,
    ) -> CycleRow {
        let s = self.drive.scales();
        let bar = s.pressure_pa() / 1e5;
        // f = (H/6L)·F/W (eq. 11): the force is f·W in load units (docs/model.md §1).
        let force = f.total() * b.w * s.load_n_per_m();
        let asperity = f.boundary * b.w * s.load_n_per_m();
        let sign = if self.st.film.mirrored { -1.0 } else { 1.0 };
        CycleRow {
            crank_deg: b.crank_deg.rem_euclid(720.0),
            step_deg: 0.0,
            position_mm: 10.0 * b.position_cm,
            u_ms: u * s.speed_ms,
            load_n_per_m: b.w * s.load_n_per_m(),
            p_above_bar: b.p_above * bar,
            p_below_bar: b.p_below * bar,
            z_um: z,
            h_min_um: self.st.film.scene.contact.clearance_um(z),
            friction_n_per_m: sign * force,
            asperity_friction_n_per_m: sign * asperity,
            asperity_share: 0.0,
            lambda: f64::INFINITY,
            power_w_per_m: (force * u * s.speed_ms).abs(),
            oil_met_um: met,
            oil_left_um: if u != 0.0 { outflow / u.abs() } else { 0.0 },
        }
    }
}

impl CycleRun<'_> {
    /// One cycle over the crank angles `steps` (from one start to the same angle 720° on):
    /// its rows and summary. `watch` sees every row.
    pub fn cycle(
        &mut self,
        steps: &[f64],
        watch: &mut CycleWatch,
    ) -> Result<(Vec<CycleRow>, CycleSummary), SolveError> {
        self.tally = OilBalance {
            film_start: self.film_oil(),
            liner_start: self.st.oil.total(),
            ..OilBalance::default()
        };
        let mut rows = Vec::with_capacity(steps.len());
        let mut work = 0.0;
        for w in steps.windows(2) {
            for row in self.advance(w[0], w[1])? {
                work += row.power_w_per_m * self.drive.time_of(row.step_deg);
                watch.step(&row);
                rows.push(row);
            }
        }
        self.tally.film_end = self.film_oil();
        self.tally.liner_end = self.st.oil.total();
        // Power (W/m) × time (units of L/U, in ms: time_ms) gives mJ/m.
        let summary = CycleSummary {
            index: 0,
            friction_work_j_per_m: work * self.drive.scales().time_ms() * 1e-3,
            work_change: f64::INFINITY,
            oil_change: f64::INFINITY,
            oil: self.tally,
            steps: rows.len(),
        };
        Ok((rows, summary))
    }

    /// Cycles from the run's start until the numerics' stop rule ends it
    /// ([`CycleNumerics::stop`]: repeated, settled, or out of cycles); `watch` sees every
    /// cycle's summary and every step's row.
    pub fn run(mut self, mut watch: CycleWatch) -> Result<CycleOutcome, SolveError> {
        // Pockets under the ring, or within a ring's width of it, call for the texture's step.
        let (a, b) = self.st.film.scene.contact.ring_edges();
        let (x_c, w) = (self.st.film.scene.contact.x_center_cm, b - a);
        let layout = &self.layout;
        let textured = |pos: f64| {
            layout
                .width_over(pos + a - x_c - w, pos + b - x_c + w)
                .is_some()
        };
        let steps = crank_steps(
            self.drive,
            self.numerics.start_deg,
            &self.numerics.steps,
            &textured,
        );
        let mut cycles: Vec<CycleSummary> = Vec::new();
        let mut last_rows = Vec::new();
        let stopped = loop {
            if let Some(end) = self.numerics.stop(&cycles) {
                break end;
            }
            let before = self.st.oil.clone();
            let (rows, mut summary) = self.cycle(&steps, &mut watch)?;
            summary.index = cycles.len();
            if let Some(prev) = cycles.last() {
                summary.work_change = (summary.friction_work_j_per_m - prev.friction_work_j_per_m)
                    .abs()
                    / prev.friction_work_j_per_m.abs().max(f64::MIN_POSITIVE);
                summary.oil_change = self.st.oil.change_from(&before);
            }
            watch.window(&summary);
            cycles.push(summary);
            last_rows = rows;
        };
        last_rows.sort_by(|a, b| a.crank_deg.total_cmp(&b.crank_deg));
        Ok(CycleOutcome {
            rows: last_rows,
            cycles,
            stopped,
            oil_y_cm: (0..self.st.oil.layer().len())
                .map(|k| self.st.oil.y(k))
                .collect(),
            oil_um: self.st.oil.layer().to_vec(),
            end: self.snapshot(),
        })
    }
}
