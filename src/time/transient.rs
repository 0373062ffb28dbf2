//! The coupled transient (docs/model.md §3–5): the film under the moving texture, the ring's
//! dynamics and the friction, advanced one time step at a time (docs/solver.md, "Time scheme").
//! Its parts: the film's time levels (time/levels.rs), the operating point each step reads
//! (time/schedule.rs), what the film iteration keeps from a period ago (time/memory.rs) and
//! the run's tallies (time/stats.rs).

use super::common::{Observers, SolveError, MASS_TOL};
use super::coupled::{guard_mass, RingStep};
use super::interpolate::interpolate;
use super::levels::TimeLevels;
use super::memory::{PeriodGuess, PlacedTexture, TextureShift};
use super::numerics::{Numerics, Start, TimeScheme};
use super::outcome::SeriesRow;
use super::schedule::{OperatingPoint, Schedule};
use super::start::{equilibrium_start, paper_start};
use super::stats::{ApproachDone, RunStats};
use super::steady::solve_untextured;
use crate::mesh::integrals::{boundary_flows, friction_thresholds};
use crate::mesh::{FilmState, Scene};
use crate::model::asperity::ContactLaw;
use crate::model::case::CaseSpec;
use crate::model::film::Boundary;
use crate::model::friction::{Friction, FrictionModel};
use crate::model::ring::{Ring, RingState};
use crate::solve::{FilmMethod, SolveStats, Step};

/// Pseudo-period used to average and test an untextured transient run (no texture period).
pub const UNTEXTURED_PERIOD: f64 = 0.06;

/// The time the texture takes to repeat under the ring, per/u (units of L/U), or
/// [`UNTEXTURED_PERIOD`] for a plain liner: the period a run steps, averages and tests.
pub fn texture_period(case: &CaseSpec) -> f64 {
    case.texture
        .as_ref()
        .map_or(UNTEXTURED_PERIOD, |t| t.per / case.u)
}

/// Who watches a transient run (see [`Observers`]).
pub type Watch<'a> = Observers<'a, Transient>;

/// The run's time step and where it is: steps taken, of `steps_per_period` a texture period.
#[derive(Clone, Copy, Debug)]
struct Clock {
    dt: f64,
    steps_per_period: usize,
    steps: usize,
}

/// What the step last taken found: its film solve's tallies and the friction, for the case's
/// θ_s and the further thresholds asked for (docs/model.md §5: θ_s enters only the Couette
/// term, so one run serves them all).
#[derive(Default)]
struct LastStep {
    solve: SolveStats,
    friction: Friction,
    extra_theta_s: Vec<f64>,
    extra_friction: Vec<Friction>,
}

/// What the film iteration keeps from a period ago, and how far the texture moves a step
/// (time/memory.rs): accelerators of the step, outside its physics.
pub(super) struct PeriodMemory {
    /// Solved states and factors of the last texture period, the initial guesses of the
    /// film iteration one period later.
    pub(super) period_ago: PeriodGuess,
    /// The texture as placed at each phase of the period.
    pub(super) placed: PlacedTexture,
    /// Node columns the texture moves in one step: how far a step's initial guess carries
    /// the film inside the pockets.
    pub(super) shift: TextureShift,
}

/// The coupled transient. Advance it with [`Transient::step`];
/// [`Transient::run_to_periodic`] drives it to the periodic regime.
pub struct Transient {
    case: CaseSpec,
    /// The case's asperity contact in scaled units (docs/model.md §11).
    contact: Option<ContactLaw>,
    scene: Scene,
    state: FilmState,
    ring_state: RingState,
    levels: TimeLevels,
    clock: Clock,
    /// The operating point each step reads at its time.
    schedule: Schedule,
    /// The film solver of every step.
    solver: Box<dyn FilmMethod>,
    pub(super) memory: PeriodMemory,
    last: LastStep,
    stats: RunStats,
    /// Guard: a step whose relative mass defect exceeds this is an error
    /// ([`SolveError::MassNotConserved`]); [`MASS_TOL`] by default.
    mass_tolerance: f64,
}

impl Transient {
    /// The transient of `case` on the numerics' mesh and time step, from the numerics'
    /// start, with the numerics' film solver.
    pub fn new(case: &CaseSpec, num: &Numerics) -> Self {
        Self::with_solver(case, num, num.solver.solver())
    }

    /// As [`Transient::new`] with a film solver of the caller's (the lab crate's solvers).
    ///
    /// The initial state is `num.start`'s: the paper's (docs/model.md §4, [`paper_start`]) or
    /// the untextured force balance ([`equilibrium_start`]); the periodic regime reached is
    /// the same (tests/solvers.rs). A contact that has no untextured balance starts from the
    /// paper's state.
    pub fn with_solver(case: &CaseSpec, num: &Numerics, solver: Box<dyn FilmMethod>) -> Self {
        let scene = Scene::new(case, num.n1, num.n2).with_rim(num.rim);
        let period = texture_period(case);
        let steps_per_period = super::numerics::steps_per_period(period, num.dt) as usize;
        let dt = period / steps_per_period as f64;
        let equilibrium = match num.start {
            Start::Paper => None,
            Start::Equilibrium => solve_untextured(case, num.n1).ok(),
        };
        let (state, ring_state) = match equilibrium {
            Some(eq) => equilibrium_start(&scene, &eq),
            None => paper_start(&scene, case),
        };
        let (textured, nodes) = (case.texture.is_some(), scene.grid.nodes());
        let shift = if solver.carries_guess() {
            TextureShift::of(case, dt, &scene.grid)
        } else {
            TextureShift::NONE
        };
        Transient {
            case: case.clone(),
            contact: case.contact_law(),
            levels: TimeLevels::new(num.scheme, &state.phi, dt),
            state,
            ring_state,
            clock: Clock {
                dt,
                steps_per_period,
                steps: 0,
            },
            schedule: Schedule::Constant(OperatingPoint::of(case)),
            solver,
            memory: PeriodMemory {
                period_ago: PeriodGuess::new(textured, steps_per_period, nodes),
                placed: PlacedTexture::new(textured, steps_per_period, nodes, scene.rim.samples()),
                shift,
            },
            scene,
            last: LastStep::default(),
            stats: RunStats::default(),
            mass_tolerance: MASS_TOL,
        }
    }

    pub fn case(&self) -> &CaseSpec {
        &self.case
    }

    /// The mesh and the gap as placed for the step last taken.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The film after the step last taken.
    pub fn state(&self) -> &FilmState {
        &self.state
    }

    pub fn ring_state(&self) -> RingState {
        self.ring_state
    }

    /// The ring's dynamics at the present operating point.
    pub fn ring(&self) -> Ring {
        Ring {
            mass: self.case.mass,
            w_ps: self.operating_point().w_ps,
            contact: self.contact,
        }
    }

    /// The film's time scheme (backward Euler where a BDF2 run fell back on it).
    pub fn scheme(&self) -> TimeScheme {
        self.levels.scheme()
    }

    /// The time step (it divides the texture period exactly).
    pub fn dt(&self) -> f64 {
        self.clock.dt
    }

    /// Steps taken (a coarse approach's, counted in its periods, included).
    pub fn steps(&self) -> usize {
        self.clock.steps
    }

    /// Steps per texture period (the period is per/u, or [`UNTEXTURED_PERIOD`]).
    pub fn steps_per_period(&self) -> usize {
        self.clock.steps_per_period
    }

    /// The simulated time.
    pub fn t(&self) -> f64 {
        self.clock.steps as f64 * self.clock.dt
    }

    /// The operating point at the present time.
    pub fn operating_point(&self) -> OperatingPoint {
        self.schedule.at(self.t())
    }

    /// The film solve of the step last taken.
    pub fn last(&self) -> &SolveStats {
        &self.last.solve
    }

    /// The friction after the step last taken.
    pub fn friction(&self) -> &Friction {
        &self.last.friction
    }

    /// The friction after the step last taken at the further thresholds θ_s asked for.
    pub fn extra_friction(&self) -> &[Friction] {
        &self.last.extra_friction
    }

    pub fn extra_theta_s(&self) -> &[f64] {
        &self.last.extra_theta_s
    }

    /// Further shear thresholds θ_s whose friction is reported alongside the case's own.
    pub fn set_extra_theta_s(&mut self, theta_s: &[f64]) {
        self.last.extra_theta_s = theta_s.to_vec();
    }

    /// The run's tallies so far.
    pub fn stats(&self) -> &RunStats {
        &self.stats
    }

    /// Sets the mass guard (see [`MASS_TOL`]); infinite turns it off, to measure how far a
    /// model that does not conserve mass drifts.
    pub fn set_mass_tolerance(&mut self, tol: f64) {
        self.mass_tolerance = tol;
    }

    /// Records what a coarse approach took before this run's mesh.
    pub(super) fn set_approach(&mut self, done: ApproachDone) {
        self.stats.approach = done;
    }

    /// Memory the factors kept for the next period's solves take (bytes).
    pub fn kept_factor_bytes(&self) -> usize {
        self.memory.period_ago.factor_bytes
    }

    /// Turns the period-old initial guess of the film iteration on (the default for
    /// textured runs) or off (every step starts from the previous time level).
    pub fn set_period_guess(&mut self, on: bool) {
        let textured = on && self.case.texture.is_some();
        self.memory.period_ago = PeriodGuess::new(
            textured,
            self.clock.steps_per_period,
            self.scene.grid.nodes(),
        );
    }

    /// Lays the film `phi` (per node) as the present state and the previous time level, the
    /// ring where it is (a start of the caller's, before the first step).
    pub fn lay_film(&mut self, phi: impl Fn(&Scene, usize, f64) -> f64) {
        let z = self.ring_state.z;
        for k in 0..self.scene.grid.nodes() {
            self.state.phi[k] = phi(&self.scene, k, z);
        }
        self.levels.set(&self.state.phi);
    }

    /// Moves the run to another state on the same mesh (an extrapolation along slow modes):
    /// the film `phi` and the ring `ring`, the time levels' history moved with the film.
    pub(super) fn jump(&mut self, phi: Vec<f64>, ring: RingState) {
        let before = std::mem::replace(&mut self.state.phi, phi);
        self.levels.shift(&before, &self.state.phi);
        self.ring_state = ring;
    }

    pub fn friction_model(&self) -> FrictionModel {
        self.friction_model_at(&self.operating_point())
    }

    fn friction_model_at(&self, op: &OperatingPoint) -> FrictionModel {
        FrictionModel {
            u: op.u,
            theta_s: self.case.theta_s,
            w_ps: op.w_ps,
            contact: self.contact,
        }
    }

    /// The film problem of the step last taken, with the ring held where that step put it
    /// (solved at Z = `ring_state.z`, its solution is `state`): for probes of other solvers
    /// on a run's own problems.
    pub fn fixed_z_problem(&self) -> Step<'_> {
        Step {
            grid: &self.scene.grid,
            gap: &self.scene.gap,
            phi_old: self.levels.read(),
            inv_dt: self.levels.inv_dt(),
            boundary: self.film_boundary(&self.operating_point()),
            ring: None,
        }
    }

    /// The film's boundary data as the stencil sees it at operating point `op`: with the
    /// characteristic scheme the old level carries the Couette flux
    /// (time/characteristic.rs), so the stencil's liner speed is 0.
    fn film_boundary(&self, op: &OperatingPoint) -> Boundary {
        let mut b = Boundary {
            u: op.u,
            u_rough: op.u,
            phi_inlet: op.d_oil,
            ..self.case.film_boundary()
        };
        if self.scheme() == TimeScheme::Characteristic {
            b.u = 0.0;
        }
        b
    }

    /// Restarts the time scheme's history: the next step is backward Euler (after the state
    /// was moved: a jump, another mesh).
    fn restart_history(&mut self) {
        self.levels.restart();
    }

    /// Goes on with backward Euler (see [`super::BDF2_PATIENCE`]): the history restarts and
    /// the factors kept a period ago, of BDF2's storage coefficient, are dropped.
    pub(super) fn fall_back_to_backward_euler(&mut self) {
        self.levels.fall_back_to_backward_euler();
        self.restart_history();
        self.set_period_guess(!self.memory.period_ago.slots.is_empty());
    }
}

impl Transient {
    /// One step of the film (its time scheme's storage term on φ, time/levels.rs) with the
    /// implicit Newmark ring update, at the operating point of the step's end.
    pub fn step(&mut self) -> Result<(), SolveError> {
        let (level, dt) = (self.clock.steps + 1, self.clock.dt);
        let t_new = level as f64 * dt;
        let op = self.schedule.at(t_new);
        self.place_texture(level);
        self.levels
            .advance(&mut self.state.phi, dt, op.u, &self.scene.grid);
        let rs = RingStep {
            ring: Ring {
                mass: self.case.mass,
                w_ps: op.w_ps,
                contact: self.contact,
            },
            from: self.ring_state,
            dt,
        };
        let mut z = self.initial_guess(&rs, t_new)?;
        let stats = self.solve_film(level, rs.link(), &op, &mut z, t_new)?;
        self.ring_state = rs.close(z, &stats, || self.case.label(), t_new)?;
        self.check_mass(&op, t_new)?;
        self.clock.steps = level;
        self.levels.solved();
        self.memory.period_ago.store(
            level,
            &self.state,
            z,
            (self.memory.shift, &self.scene.grid, &self.scene.hl),
        );
        self.stats.record(&stats);
        self.last.solve = stats;
        (self.last.friction, self.last.extra_friction) = friction_thresholds(
            &self.scene.grid,
            &self.scene.gap,
            z,
            &self.scene.hl,
            &self.state,
            &self.friction_model_at(&op),
            &self.last.extra_theta_s,
        );
        Ok(())
    }

    /// The texture placed by its phase within the period for the step to `level`, so that
    /// the gap is the same to the bit at the same phase of every period (u·t is that plus
    /// whole periods): the matrix rows the texture alone sets (the flooded gap upstream) then
    /// match the factors kept from a period ago and are not eliminated again.
    fn place_texture(&mut self, level: usize) {
        let slot = level % self.clock.steps_per_period;
        self.memory
            .placed
            .place(&mut self.scene, slot, slot as f64 * self.clock.dt);
    }

    /// The film solve of the step to `level` (Z in `z`, from its guess), lending it the
    /// factors kept a period ago and keeping its own, where the step took its scheme's own
    /// storage term (a restart step of BDF2, backward Euler, neither takes nor keeps them).
    fn solve_film(
        &mut self,
        level: usize,
        link: crate::model::ring::RingLink,
        op: &OperatingPoint,
        z: &mut f64,
        t_new: f64,
    ) -> Result<SolveStats, SolveError> {
        let step = Step {
            grid: &self.scene.grid,
            gap: &self.scene.gap,
            phi_old: self.levels.read(),
            inv_dt: self.levels.inv_dt(),
            boundary: self.film_boundary(op),
            ring: Some(link),
        };
        let regular = self.levels.regular();
        if regular {
            self.memory
                .period_ago
                .lend_factors(level, self.solver.as_mut());
        }
        let stats = self
            .solver
            .solve(&step, &mut self.state, z)
            .map_err(|source| SolveError::Film {
                case: self.case.label(),
                t: t_new,
                source,
            })?;
        if regular {
            self.memory
                .period_ago
                .keep_factors(level, self.solver.as_mut());
        }
        Ok(stats)
    }

    /// The step's initial guess: the film into `state` and Z returned. The state one texture
    /// period ago when its active set is the nearer ([`PeriodGuess::guess`]), with the ring's
    /// step of a period ago repeated; else the previous time level carried with the texture
    /// and the velocity extrapolation of Z; either floored by [`RingStep::guess`].
    fn initial_guess(&mut self, rs: &RingStep, t_new: f64) -> Result<f64, SolveError> {
        let mut z = rs.predicted();
        match self
            .memory
            .period_ago
            .guess(self.clock.steps + 1, rs.from.z)
        {
            Some((snap, z_shifted)) => {
                z = z_shifted;
                self.state.assign(snap);
            }
            None => {
                self.state.phi.copy_from_slice(self.levels.old());
                self.memory
                    .shift
                    .carry(&self.scene.grid, &self.scene.hl, &mut self.state);
            }
        }
        rs.guess(z, || self.case.label(), t_new)
    }

    /// Guard: the step must conserve mass ([`guard_mass`]); the run keeps its largest defect.
    fn check_mass(&mut self, op: &OperatingPoint, t_new: f64) -> Result<(), SolveError> {
        let defect = self.mass_defect_at(op);
        self.stats.max_mass_defect = self.stats.max_mass_defect.max(defect);
        guard_mass(defect, self.mass_tolerance, || self.case.label(), t_new)
    }

    /// This run, after `done` (its periods, wall time) on a coarse mesh, carried over to the
    /// mesh and time step of `num` with `solver`, at the end of a texture period. The ring
    /// state, time and tallies go on as they are; the film's saturation θ and pressure are
    /// interpolated (time/interpolate.rs) at the texture's phase, and that film is also the
    /// new mesh's previous time level. The new mesh's first step then solves its own film;
    /// the mismatch decays like any start's.
    pub(super) fn refined(
        &self,
        num: &Numerics,
        done: ApproachDone,
        solver: Box<dyn FilmMethod>,
    ) -> Transient {
        // Its own start is replaced below: the paper's costs nothing to set up.
        let fresh = Numerics {
            start: Start::Paper,
            ..num.clone()
        };
        let mut fine = Transient::with_solver(&self.case, &fresh, solver);
        let spp = self.clock.steps_per_period;
        debug_assert_eq!(self.clock.steps % spp, 0, "hand over at a period end");
        let periods = self.clock.steps / spp;
        fine.scene.place(0.0);
        let mut coarse = self.scene.clone();
        coarse.place(0.0);
        fine.state = interpolate(&coarse, &self.state, self.ring_state.z, &fine.scene);
        fine.levels.set(&fine.state.phi);
        fine.restart_history();
        fine.clock.steps = periods * fine.clock.steps_per_period;
        fine.ring_state = self.ring_state;
        fine.stats = RunStats {
            approach: done,
            ..self.stats
        };
        fine.last.extra_theta_s.clone_from(&self.last.extra_theta_s);
        fine
    }

    /// The oil the film holds (∫ h·θ over the domain but the inlet row, whose film is set)
    /// and the larger of the boundary inflow and outflow rates. (A total: compared window to
    /// window against a window's throughput, its summation round-off, ≈ 1e-12 of that, is far
    /// below any periodic tolerance; per step it would not be, see `mass_defect`.)
    pub(super) fn oil_held(&self) -> (f64, f64) {
        let g = &self.scene.grid;
        let content = (g.n2..g.n1 * g.n2).map(|k| self.state.phi[k]).sum::<f64>() * g.dx * g.dy;
        let (inflow, outflow) = boundary_flows(
            g,
            &self.scene.gap,
            self.ring_state.z,
            (self.operating_point().u, self.operating_point().u),
            &self.state,
        );
        (content, inflow.abs().max(outflow.abs()))
    }

    /// Relative discrete mass defect of the last step: |Σ(φⁿ⁺¹ − φⁿ)·area − dt·(in − out)|
    /// over dt·(|in| + |out|), the x1-end flows. Round-off for the conservative scheme when
    /// the film solve converged. (Σ of differences: the totals hold the flooded upstream gap,
    /// φ ≈ 1000 µm, and would lose the per-step change to summation round-off.)
    pub fn mass_defect(&self) -> f64 {
        self.mass_defect_at(&self.operating_point())
    }

    /// As [`Transient::mass_defect`], of a step at operating point `op`.
    fn mass_defect_at(&self, op: &OperatingPoint) -> f64 {
        let (g, dt) = (&self.scene.grid, self.clock.dt);
        let old = self.levels.read();
        let change = (g.n2..g.n1 * g.n2)
            .map(|k| self.state.phi[k] - old[k])
            .sum::<f64>()
            * g.dx
            * g.dy;
        // BDF2: 1.5·Σ(φⁿ⁺¹ − (4φⁿ − φⁿ⁻¹)/3)·area is what a step holds to the flows.
        let change = self.levels.scale(dt).map_or(change, |s| change * s);
        let flows = |u: f64| {
            boundary_flows(
                g,
                &self.scene.gap,
                self.ring_state.z,
                (u, op.u),
                &self.state,
            )
        };
        // The stencil's flows (without the Couette flux when the old level carries it)
        // balance the change; the film's own flows give the scale.
        let (inflow, outflow) = flows(self.film_boundary(op).u);
        let (scale_in, scale_out) = if self.scheme() == TimeScheme::Characteristic {
            flows(op.u)
        } else {
            (inflow, outflow)
        };
        let defect = change - dt * (inflow - outflow);
        defect.abs() / (dt * (scale_in.abs() + scale_out.abs())).max(f64::MIN_POSITIVE)
    }

    /// The time-series row of the current state.
    pub fn row(&self) -> SeriesRow {
        let f = &self.last.friction;
        SeriesRow {
            t: self.t(),
            z: self.ring_state.z,
            w_h: self.last.solve.w_h,
            w_a: self.last.solve.w_a,
            f: f.total(),
            f_couette: f.couette,
            f_poiseuille: f.poiseuille,
            f_pressure: f.pressure,
            f_boundary: f.boundary,
        }
    }
}
