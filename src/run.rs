//! A run: the coupled transient from an initial state to the periodic regime (model.md §6),
//! or, for an untextured liner, the steady 1D force balance (model.md §6, last paragraph).

use serde::{Deserialize, Serialize};
use std::time::Instant;

use crate::case::{CaseSpec, Coupling, Numerics, Start};
use crate::dynamics::{Ring, RingState};
use crate::film::{FilmError, FilmSolver, FilmState, Grid, KeptFactors, Method, SolveStats, Step};
use crate::friction::{friction_thresholds, Friction, FrictionModel};
use crate::scene::Scene;
use crate::steady::{solve_untextured, SteadyError};

/// Pseudo-period used to average and test an untextured transient run (no texture period).
pub const UNTEXTURED_PERIOD: f64 = 0.06;

/// Largest relative mass defect of a step ([`Transient::mass_defect`]) taken for a converged
/// solve: the Elrod–Adams scheme conserves mass to round-off (≤ 1.5e-12 over the stability
/// map, results/stability.md), inexact multigrid solves to ≈ their tolerance.
pub const MASS_TOL: f64 = 1e-6;

/// Contact: the ring is on the liner once Z (its apex's clearance above the plateau, µm) is at
/// or below this, 1 nm, a few oil molecules: no continuum film (model.md §3's thin-film
/// Reynolds model) is left to lubricate. Why not Z ≤ 0: the film iteration closes the gap by
/// at most half per iteration and each step's Z guesses are at least half the last Z, so a
/// ring pushed into the liner approaches Z = 0 geometrically and never reaches it (a load 10⁴
/// times the paper's: Z = 4e-250 µm and f̄ = 7e241 after 30 ms); only unguarded guesses that
/// happened to cross zero had reported contact before.
pub const CONTACT_Z: f64 = 1e-3;

/// Outcomes of one evaluation (model.md §6). Friction coefficients per eq. (11); Z and
/// clearances in µm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// Period-mean friction coefficient f̄ and its Couette, Poiseuille and pressure terms.
    pub f_mean: f64,
    pub f_couette: f64,
    pub f_poiseuille: f64,
    pub f_pressure: f64,
    /// Mean, minimum and maximum of Z over the last period (µm).
    pub z_mean: f64,
    pub z_min: f64,
    pub z_max: f64,
    /// Minimum clearance over the period: min over t and over the ring of h_U + Z (µm).
    pub c_min: f64,
    /// Texture periods simulated (0 for a steady solve).
    pub periods: usize,
    /// Time steps taken (0 for a steady solve).
    pub steps: usize,
    /// Whether the periodic regime (or the steady force balance) was reached.
    pub converged: bool,
    /// Estimated relative distance of f̄ and Z̄ from their periodic limits at the end.
    pub periodic_error: f64,
    /// "steady-1d" or "transient-2d".
    pub method: String,
    /// Time step used (divides the texture period exactly); 0 for steady.
    pub dt: f64,
    /// Simulated time at the end.
    pub t_end: f64,
    /// Mean complementarity/Newton iterations per step (per film solve when steady).
    pub iterations_per_step: f64,
    /// Largest relative nodal residual of the film equation over the run.
    pub max_residual: f64,
    pub wall_time_s: f64,
    /// Of `steps` (and `periods`), those taken on the coarse approach mesh
    /// (`Numerics::approach_n2`); 0 without one. Absent in records made before it existed.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub approach_steps: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// One row of the time series: values at the end of each step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeriesRow {
    pub t: f64,
    pub z: f64,
    pub w_h: f64,
    pub f: f64,
    pub f_couette: f64,
    pub f_poiseuille: f64,
    pub f_pressure: f64,
}

/// A run's outcomes and, on request, its time series.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub outcome: Outcome,
    pub series: Option<Vec<SeriesRow>>,
    /// The outcomes for further shear thresholds θ_s asked for (same film and ring).
    pub extra: Vec<(f64, Outcome)>,
}

impl Outcome {
    /// This outcome with other friction terms (another θ_s of the same run).
    pub fn with_friction(&self, f: &Friction) -> Outcome {
        Outcome {
            f_mean: f.total(),
            f_couette: f.couette,
            f_poiseuille: f.poiseuille,
            f_pressure: f.pressure,
            ..self.clone()
        }
    }
}

/// Why a run failed: always names the case and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error("case {case}: film solve failed at t = {t:.5}: {source}")]
    Film {
        case: String,
        t: f64,
        source: FilmError,
    },
    #[error("case {case}: the ring reached the liner (Z = {z:.2e} µm, under the {floor} µm a lubricating film needs) at t = {t:.5}; contact is outside the lubrication model", floor = CONTACT_Z)]
    Contact { case: String, t: f64, z: f64 },
    #[error("case {case}: {quantity} = {value} at t = {t:.5}: the run is numerically unstable (try the implicit coupling or a smaller dt)")]
    Unstable {
        case: String,
        t: f64,
        quantity: String,
        value: f64,
    },
    #[error("case {case}: mass not conserved at t = {t:.5}: the step's film content changed by {defect:.2e} of its throughflow more than the boundary flows carried (tolerance {tol:.0e}); {hint}")]
    MassNotConserved {
        case: String,
        t: f64,
        defect: f64,
        tol: f64,
        hint: String,
    },
    #[error("case {case}: steady force balance failed: {source}")]
    Steady { case: String, source: SteadyError },
}

/// The coupled transient: film under the moving texture, ring dynamics, friction.
/// Advance it with `step`; `run_to_periodic` drives it to the periodic regime.
#[derive(Clone)]
pub struct Transient {
    pub case: CaseSpec,
    pub scene: Scene,
    pub state: FilmState,
    /// φ at the previous time level.
    pub phi_old: Vec<f64>,
    pub ring: Ring,
    pub ring_state: RingState,
    pub t: f64,
    pub dt: f64,
    /// Steps per texture period (the period is per/u, or UNTEXTURED_PERIOD).
    pub steps_per_period: usize,
    pub steps: usize,
    pub solver: FilmSolver,
    pub last: SolveStats,
    pub friction: Friction,
    /// Further shear thresholds θ_s whose friction is reported alongside (model.md §5: θ_s
    /// enters only the Couette term, so one run serves them all) and their current friction.
    pub extra_theta_s: Vec<f64>,
    pub extra_friction: Vec<Friction>,
    /// Ring coupling (implicit unless a stability study asks otherwise).
    pub coupling: Coupling,
    /// Guard: a step whose relative mass defect exceeds this is an error
    /// (`SolveError::MassNotConserved`). [`MASS_TOL`] unless a study of a non-conserving
    /// model sets it to infinity to measure how far it drifts.
    pub mass_tolerance: f64,
    /// Largest relative mass defect of a step so far.
    pub max_mass_defect: f64,
    total_iterations: usize,
    max_residual: f64,
    /// Solved states of the last texture period, slot = step index mod steps per period:
    /// the initial guess of the film iteration one period later ([`PeriodGuess`]).
    period_ago: PeriodGuess,
    /// The texture as placed at each phase of the period ([`PlacedTexture`]).
    placed: PlacedTexture,
    /// Node columns the texture moves in one step (u·dt/dx rounded; 0 untextured): how
    /// far a step's initial guess carries the film inside the pockets ([`TextureShift`]).
    shift: TextureShift,
    /// What a coarse approach ([`Transient::refined`]) took before this run's mesh.
    pub approach: ApproachDone,
}

/// The part of a run taken on a coarse approach mesh (zero without one).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ApproachDone {
    pub steps: usize,
    pub periods: usize,
    pub wall_time_s: f64,
}

impl Transient {
    /// Memory the factors kept for the next period's solves take (bytes).
    pub fn kept_factor_bytes(&self) -> usize {
        self.period_ago.factor_bytes
    }

    /// The paper's initial state (model.md §4): Z = z0, Z' = v0. The paper leaves the initial
    /// film open; texopt floods the gap upstream of the ring (θ = 1 for x1 < a) and lays a
    /// film of d_oil elsewhere (θ = min(1, d_oil/h)), nothing pressurised. Why: with a flooded
    /// inlet the ring passes less oil than arrives, and the surplus banks up in front of the
    /// ring, filling the wide gap e upstream; its front creeps to the inlet at surplus/(e −
    /// d_oil) ≈ 0.005 cm/ms, so from a thin film the periodic regime is reached only after
    /// ≈ 12 ms, and the bank's back-pressure lifts Z by up to 0.3 % on the way. Starting from the
    /// flooded inlet reaches the same periodic regime without that creep. The initial
    /// acceleration is consistent with the unpressurised film: Z''(0) = −W_ps/m.
    ///
    /// With `Start::Equilibrium` (numerics) the run starts instead from the untextured force
    /// balance; the periodic regime it reaches is the same (tests/solvers.rs).
    pub fn new(case: &CaseSpec, num: &Numerics) -> Self {
        let scene = Scene::new(case, num);
        let period = case
            .texture
            .as_ref()
            .map_or(UNTEXTURED_PERIOD, |t| t.per / case.u);
        let steps_per_period = ((period / num.dt) - 1e-9).ceil().max(1.0) as usize;
        let dt = period / steps_per_period as f64;
        let g = &scene.grid;
        let equilibrium = match num.start {
            Start::Paper => None,
            // A contact that has no untextured balance falls back to the paper's start.
            Start::Equilibrium => solve_untextured(case, num.n1).ok(),
        };
        let (state, ring_state) = match equilibrium {
            // The untextured force balance (model.md §6) laid on the textured gap: its
            // saturation and pressure per column, Z at the balance, at rest, W_h = W_ps so
            // Z''(0) = 0. The texture then only perturbs a balanced ring.
            Some(eq) => {
                let mut st = FilmState::cavitated(g, &scene.gap, eq.z, 0.0);
                for i in 0..=g.n1 {
                    for j in 0..g.n2 {
                        let k = g.idx(i, j);
                        let h = scene.gap.h(g, k, eq.z);
                        st.phi[k] = eq.theta[i].min(1.0) * h;
                        if eq.p[i] > 0.0 && i > 0 && i < g.n1 {
                            st.p[k] = eq.p[i];
                            st.pressurised[k] = true;
                        }
                    }
                }
                let rs = RingState {
                    z: eq.z,
                    v: 0.0,
                    a: 0.0,
                };
                (st, rs)
            }
            None => {
                let mut st = FilmState::cavitated(g, &scene.gap, case.z0, case.d_oil);
                let (a, _) = scene.contact.ring_edges();
                for i in (0..=g.n1).filter(|&i| g.x(i) < a) {
                    for j in 0..g.n2 {
                        let k = g.idx(i, j);
                        st.phi[k] = scene.gap.h(g, k, case.z0);
                    }
                }
                let rs = RingState {
                    z: case.z0,
                    v: case.v0,
                    a: -case.w_ps / case.mass,
                };
                (st, rs)
            }
        };
        let mut state = state;
        if !num.cavitation.is_elrod_adams() {
            // Reynolds cut-off: a full film (θ ≡ 1) by construction.
            for k in 0..g.nodes() {
                state.phi[k] = scene.gap.h(g, k, ring_state.z);
            }
        }
        let period_ago = PeriodGuess::new(case.texture.is_some(), steps_per_period, g.nodes());
        // The inexact multigrid path keeps the previous state as it is: from the carried
        // guess its solves, stopped on the nodal residual, left a step's mass defect of 7e-6
        // (> MASS_TOL) in the speed study's 256×16 runs of Case I and Case III.
        let shift = match num.solver {
            Method::Multigrid | Method::PtMultigrid => TextureShift::NONE,
            _ => TextureShift::of(case, dt, g),
        };
        let placed = PlacedTexture::new(case.texture.is_some(), steps_per_period, g.nodes());
        let mut solver = FilmSolver::with_method(num.film_tolerance(), num.solver);
        solver.cavitation = num.cavitation;
        let ring = Ring {
            mass: case.mass,
            w_ps: case.w_ps,
        };
        Transient {
            case: case.clone(),
            phi_old: state.phi.clone(),
            state,
            ring,
            ring_state,
            t: 0.0,
            dt,
            steps_per_period,
            steps: 0,
            solver,
            last: SolveStats::default(),
            friction: Friction::default(),
            extra_theta_s: Vec::new(),
            extra_friction: Vec::new(),
            coupling: num.coupling,
            scene,
            mass_tolerance: MASS_TOL,
            max_mass_defect: 0.0,
            total_iterations: 0,
            max_residual: 0.0,
            period_ago,
            placed,
            shift,
            approach: ApproachDone::default(),
        }
    }

    /// Turns the period-old initial guess of the film iteration on (the default for
    /// textured runs) or off (every step starts from the previous time level), e.g. to
    /// show that it changes outcomes at round-off only.
    pub fn set_period_guess(&mut self, on: bool) {
        let textured = on && self.case.texture.is_some();
        self.period_ago =
            PeriodGuess::new(textured, self.steps_per_period, self.scene.grid.nodes());
    }

    pub fn friction_model(&self) -> FrictionModel {
        FrictionModel {
            u: self.case.u,
            theta_s: self.case.theta_s,
            w_ps: self.case.w_ps,
        }
    }

    /// The film problem of the step last taken, with the ring held where that step put it
    /// (solve at Z = `ring_state.z`; its solution is `state`): for probes of other solvers
    /// on a run's own problems (`examples/pt_multigrid_probe.rs`).
    pub fn fixed_z_problem(&self) -> Step<'_> {
        Step {
            grid: &self.scene.grid,
            gap: &self.scene.gap,
            phi_old: &self.phi_old,
            inv_dt: 1.0 / self.dt,
            boundary: self.case.film_boundary(),
            ring: None,
        }
    }

    /// One backward-Euler step of the film with the implicit Newmark ring update.
    pub fn step(&mut self) -> Result<(), SolveError> {
        let t_new = (self.steps + 1) as f64 * self.dt;
        // The texture placed by its phase within the period, so that the gap is the same to
        // the bit at the same phase of every period (u·t_new is that plus whole periods):
        // the matrix rows the texture alone sets (the flooded gap upstream) then match
        // the factors kept from a period ago and are not eliminated again.
        let slot = (self.steps + 1) % self.steps_per_period;
        self.placed
            .place(&mut self.scene, slot, slot as f64 * self.dt);
        std::mem::swap(&mut self.phi_old, &mut self.state.phi);
        let s = self.ring_state;
        let link = self.ring.link(&s, self.dt);
        let explicit = self.coupling == Coupling::Explicit;
        // Initial guess: the velocity extrapolation, or with the period-old state the ring's
        // step of a period ago repeated; either never closer to the liner than half the
        // current clearance (a guess must not put the ring on the liner by itself; the
        // iteration then moves Z as far as the film demands).
        // Explicit coupling: Z⁺ = Z + dt·V + dt²/2·A, held fixed in the film solve.
        let mut z = if explicit {
            s.z + self.dt * s.v + 0.5 * self.dt * self.dt * s.a
        } else {
            s.z + self.dt * s.v
        };
        // Initial guess of the film iteration: the previous time level, or the state one
        // texture period ago when its active set is the nearer (`PeriodGuess::guess`).
        match self.period_ago.guess(self.steps + 1, s.z) {
            Some((snap, z_shifted)) => {
                if !explicit {
                    z = z_shifted;
                }
                self.state.assign(snap);
            }
            None => {
                self.state.phi.copy_from_slice(&self.phi_old);
                self.shift
                    .carry(&self.scene.grid, &self.scene.hl, &mut self.state);
            }
        }
        if !explicit {
            z = z.max(0.5 * s.z);
        }
        if !z.is_finite() {
            return Err(SolveError::Unstable {
                case: self.case.label(),
                t: t_new,
                quantity: "predicted ring position Z".into(),
                value: z,
            });
        }
        if z <= 0.0 {
            return Err(SolveError::Contact {
                case: self.case.label(),
                t: t_new,
                z,
            });
        }
        let step = Step {
            grid: &self.scene.grid,
            gap: &self.scene.gap,
            phi_old: &self.phi_old,
            inv_dt: 1.0 / self.dt,
            boundary: self.case.film_boundary(),
            ring: (!explicit).then_some(link),
        };
        let level = self.steps + 1;
        self.period_ago.lend_factors(level, &mut self.solver);
        let stats = self
            .solver
            .solve(&step, &mut self.state, &mut z)
            .map_err(|source| SolveError::Film {
                case: self.case.label(),
                t: t_new,
                source,
            })?;
        self.period_ago.keep_factors(level, &mut self.solver);
        if z <= CONTACT_Z {
            return Err(SolveError::Contact {
                case: self.case.label(),
                t: t_new,
                z,
            });
        }
        self.ring_state = self.ring.advance(&s, self.dt, z, stats.w_h);
        // Guard: the step must conserve mass (a wrong number that looks right is worse
        // than an error).
        let defect = self.mass_defect();
        self.max_mass_defect = self.max_mass_defect.max(defect);
        if defect.is_nan() || defect > self.mass_tolerance {
            return Err(SolveError::MassNotConserved {
                case: self.case.label(),
                t: t_new,
                defect,
                tol: self.mass_tolerance,
                hint: if self.solver.cavitation.is_elrod_adams() {
                    "the film solve is not converged (tighten --solve-tol or use --solver direct)"
                        .into()
                } else {
                    "the Reynolds cut-off does not conserve mass in cavitated regions (paper ref. [7]); use the Elrod–Adams model".into()
                },
            });
        }
        self.t = t_new;
        self.steps += 1;
        self.period_ago.store(
            self.steps,
            &self.state,
            z,
            (self.shift, &self.scene.grid, &self.scene.hl),
        );
        self.last = stats;
        self.total_iterations += stats.iterations;
        self.max_residual = self.max_residual.max(stats.residual);
        (self.friction, self.extra_friction) = friction_thresholds(
            &self.scene.grid,
            &self.scene.gap,
            z,
            &self.scene.hl,
            &self.state,
            &self.friction_model(),
            &self.extra_theta_s,
        );
        Ok(())
    }

    /// This run, after `done` (its periods, wall time) on a coarse mesh, carried over to the
    /// mesh of `num`: same N1 and time step, another N2 (model.md §3's grid, x2 cells only).
    /// The ring state, time, step count and iteration tally go on as they are; the film's
    /// saturation θ and pressure are interpolated in x2 ([`interpolate_x2`]) at the current
    /// texture phase, and that film is also the new mesh's previous time level. The new
    /// run's first step then solves the new mesh's film for it; the mismatch decays like any
    /// start's (the periodic regime does not depend on the start).
    pub fn refined(&self, num: &Numerics, done: ApproachDone) -> Transient {
        // Its own start is replaced below: the paper's costs nothing to set up.
        let fresh = Numerics {
            start: Start::Paper,
            ..num.clone()
        };
        let mut fine = Transient::new(&self.case, &fresh);
        debug_assert_eq!(
            (fine.scene.grid.n1, fine.steps_per_period),
            (self.scene.grid.n1, self.steps_per_period)
        );
        let phase = (self.steps % self.steps_per_period) as f64 * self.dt;
        fine.scene.place(phase);
        let mut coarse = self.scene.clone();
        coarse.place(phase);
        fine.state = interpolate_x2(&coarse, &self.state, self.ring_state.z, &fine.scene);
        fine.phi_old.copy_from_slice(&fine.state.phi);
        fine.ring_state = self.ring_state;
        fine.t = self.t;
        fine.steps = self.steps;
        fine.total_iterations = self.total_iterations;
        fine.max_residual = self.max_residual;
        fine.max_mass_defect = self.max_mass_defect;
        fine.extra_theta_s.clone_from(&self.extra_theta_s);
        fine.approach = done;
        fine
    }

    /// The oil the film holds (∫ h·θ over the domain but the inlet row, whose film is set)
    /// and the larger of the boundary inflow and outflow rates. (A total: compared window to
    /// window against a window's throughput, its summation round-off, ≈ 1e-12 of that, is far
    /// below any periodic tolerance; per step it would not be, see `mass_defect`.)
    fn oil_held(&self) -> (f64, f64) {
        let g = &self.scene.grid;
        let content = (g.n2..g.n1 * g.n2).map(|k| self.state.phi[k]).sum::<f64>() * g.dx * g.dy;
        let (inflow, outflow) = crate::film::boundary_flows(
            g,
            &self.scene.gap,
            self.ring_state.z,
            self.case.u,
            &self.state,
        );
        (content, inflow.abs().max(outflow.abs()))
    }

    /// Relative discrete mass defect of the last step: |Σ(φⁿ⁺¹ − φⁿ)·area − dt·(in − out)|
    /// over dt·(|in| + |out|), the x1-end flows. Round-off for the conservative scheme when
    /// the film solve converged. (Σ of differences: the totals hold the flooded upstream gap,
    /// φ ≈ 1000 µm, and would lose the per-step change to summation round-off.)
    pub fn mass_defect(&self) -> f64 {
        let g = &self.scene.grid;
        let change: f64 = (g.n2..g.n1 * g.n2)
            .map(|k| self.state.phi[k] - self.phi_old[k])
            .sum::<f64>()
            * g.dx
            * g.dy;
        let (inflow, outflow) = crate::film::boundary_flows(
            g,
            &self.scene.gap,
            self.ring_state.z,
            self.case.u,
            &self.state,
        );
        let defect = change - self.dt * (inflow - outflow);
        defect.abs() / (self.dt * (inflow.abs() + outflow.abs())).max(f64::MIN_POSITIVE)
    }

    /// The time-series row of the current state.
    pub fn row(&self) -> SeriesRow {
        SeriesRow {
            t: self.t,
            z: self.ring_state.z,
            w_h: self.last.w_h,
            f: self.friction.total(),
            f_couette: self.friction.couette,
            f_poiseuille: self.friction.poiseuille,
            f_pressure: self.friction.pressure,
        }
    }

    /// Runs period by period until the periodic regime is detected or t_max is reached.
    pub fn run_to_periodic(
        &mut self,
        num: &Numerics,
        record_series: bool,
    ) -> Result<RunResult, SolveError> {
        self.run_observed(num, record_series, &mut |_| {})
    }

    /// As `run_to_periodic`, calling `observe` after every texture period.
    pub fn run_observed(
        &mut self,
        num: &Numerics,
        record_series: bool,
        observe: &mut dyn FnMut(&Progress),
    ) -> Result<RunResult, SolveError> {
        self.run_with(num, record_series, observe, &mut |_| {})
    }

    /// As `run_observed`, also calling `on_step` with the state after every time step.
    pub fn run_with(
        &mut self,
        num: &Numerics,
        record_series: bool,
        observe: &mut dyn FnMut(&Progress),
        on_step: &mut dyn FnMut(&Transient),
    ) -> Result<RunResult, SolveError> {
        let start = Instant::now();
        let mut series = record_series.then(Vec::new);
        let mut history: Vec<PeriodMeans> = Vec::new();
        let wp = self.window_periods();
        let n = self.steps_per_period * wp;
        let mut snaps: Vec<PeriodEnd> = Vec::new();
        let (mut jumps, mut since_jump) = (0, 0);
        let (converged, periodic_error) = loop {
            let mut acc = PeriodMeans::empty();
            for _ in 0..n {
                self.step()?;
                on_step(self);
                let row = self.row();
                acc.add(&row, &self.friction, &self.extra_friction);
                if let Some(s) = series.as_mut() {
                    s.push(row);
                }
            }
            let (content, flow) = self.oil_held();
            history.push(PeriodMeans {
                content,
                throughput: flow * n as f64 * self.dt,
                ..acc.finish(n)
            });
            if num.extrapolate && jumps < MAX_JUMPS {
                snaps.push(PeriodEnd::of(self));
                if snaps.len() > 3 {
                    snaps.remove(0);
                }
                // A slow mode read from the window means: jump the state to its limit. Only
                // the start of the remaining run changes; the periodic test then runs on
                // fresh windows, so the reported regime is still a simulated one.
                let fresh = &history[since_jump..];
                // A pair jumps only when both of its modes are slow (a damped oscillation,
                // or two slow real modes); one slow real mode beside a fast one is the
                // geometric jump's, a window or two later, once the fast one has gone (the
                // pair fitted over it lands less close: R = 51.2 at 512×32 after the
                // coarse approach needed a second jump and four more windows).
                let mode = slow_mode_ratio(fresh).or_else(|| {
                    slow_pair(fresh)
                        .filter(|m| m.second_radius() >= PAIR_SECOND && m.worth_a_jump(fresh, num))
                });
                if let (Some(mode), [a, b, c]) = (mode, &snaps[..]) {
                    if self.jump_to_limit([a, b, c], mode) {
                        jumps += 1;
                        since_jump = history.len();
                        snaps.clear();
                    }
                }
            }
            // The estimate must hold at two consecutive period ends, so that one lucky
            // cancellation between a decaying oscillation and a drift does not stop the run.
            let fresh = &history[since_jump..];
            let err = periodic_error(fresh).max(if fresh.len() > 3 {
                periodic_error(&fresh[..fresh.len() - 1])
            } else {
                f64::INFINITY
            });
            observe(&Progress {
                period: self.approach.periods + history.len() * wp,
                t: self.t,
                f_mean: history[history.len() - 1].friction.total(),
                z_mean: history[history.len() - 1].z_mean,
                periodic_error: err,
            });
            if history.len() - since_jump >= num.min_periods.max(4) && err <= num.periodic_tol {
                break (true, err);
            }
            if self.t + 1e-12 >= num.t_max {
                break (false, err);
            }
        };
        let last = history.last().expect("at least one period").clone();
        let c_min = self.scene.contact.clearance_um(last.z_min);
        let outcome = Outcome {
            f_mean: last.friction.total(),
            f_couette: last.friction.couette,
            f_poiseuille: last.friction.poiseuille,
            f_pressure: last.friction.pressure,
            z_mean: last.z_mean,
            z_min: last.z_min,
            z_max: last.z_max,
            c_min,
            periods: self.approach.periods + history.len() * wp,
            steps: self.steps,
            converged,
            periodic_error,
            method: "transient-2d".into(),
            dt: self.dt,
            t_end: self.t,
            iterations_per_step: self.total_iterations as f64 / self.steps.max(1) as f64,
            max_residual: self.max_residual,
            wall_time_s: self.approach.wall_time_s + start.elapsed().as_secs_f64(),
            approach_steps: self.approach.steps,
        };
        let extra = self
            .extra_theta_s
            .iter()
            .zip(&last.extra)
            .map(|(&theta_s, f)| (theta_s, outcome.with_friction(f)))
            .collect();
        Ok(RunResult {
            outcome,
            series,
            extra,
        })
    }
}

/// The texture depth and the gap without Z at each phase of the texture period, as
/// [`Scene::place`] set them at that phase the first time (the same bits every period, since
/// the texture is placed by its phase). Why: placing evaluates the pocket shape at every
/// node, ≈ 3.5 % of a `fast` run, for fields that repeat every period.
#[derive(Clone, Default)]
struct PlacedTexture {
    /// Slot k: h_L and the gap base at phase k·dt; empty when disabled. The slot lent to
    /// the scene holds the scene's spare arrays meanwhile.
    slots: Vec<Option<(Vec<f64>, Vec<f64>)>>,
    /// The slot whose arrays the scene holds (exchanged, not copied: at 512×32 a copy is
    /// 260 kB a step).
    lent: Option<usize>,
}

/// Most memory the placed texture of a period may take (bytes): 512×32 with 150 steps a
/// period needs ≈ 40 MB; longer periods or finer meshes place the texture every step.
const PLACED_TEXTURE_MEMORY: usize = 128 << 20;

impl PlacedTexture {
    fn new(textured: bool, steps_per_period: usize, nodes: usize) -> Self {
        let bytes = steps_per_period * nodes * 2 * std::mem::size_of::<f64>();
        let on = textured && steps_per_period > 1 && bytes <= PLACED_TEXTURE_MEMORY;
        PlacedTexture {
            slots: if on {
                vec![None; steps_per_period]
            } else {
                Vec::new()
            },
            lent: None,
        }
    }

    /// Places the texture of `scene` at phase `phase` (slot `slot` of the period).
    fn place(&mut self, scene: &mut Scene, slot: usize, phase: f64) {
        let exchange = |(hl, base): &mut (Vec<f64>, Vec<f64>), scene: &mut Scene| {
            std::mem::swap(hl, &mut scene.hl);
            std::mem::swap(base, &mut scene.gap.base);
        };
        // The arrays the scene holds go back to their slot, the scene's own come back.
        if let Some(Some(pair)) = self.lent.take().and_then(|j| self.slots.get_mut(j)) {
            exchange(pair, scene);
        }
        match self.slots.get_mut(slot) {
            Some(Some(pair)) => {
                exchange(pair, scene);
                self.lent = Some(slot);
            }
            Some(empty) => {
                scene.place(phase);
                *empty = Some((scene.hl.clone(), scene.gap.base.clone()));
            }
            None => scene.place(phase),
        }
    }
}

/// Initial guesses for the film iteration from one texture period earlier.
///
/// Why: the texture moves about one cell per step, so the previous time level's active set
/// is wrong along every pocket edge (≈ 20–90 nodes switch in the first Newton iteration of
/// a step), while the state one period earlier has the texture in the same place and
/// differs only by the ring's drift over the period. Near the periodic regime the iteration
/// then needs one solve and one confirming solve per step instead of about four (Case III:
/// 4.9 → 2.0 iterations per step). It is only a starting point: the iteration converges
/// to the same solution (the film problem of a step has one solution), so outcomes change
/// at round-off only.
#[derive(Clone, Default)]
struct PeriodGuess {
    /// Slot n mod len: the solved state of time level n and its Z; empty when disabled.
    slots: Vec<Option<(FilmState, f64)>>,
    /// Slot n mod len: the film-matrix factors of time level n's last iteration (direct
    /// method), lent to the solve one period later; empty when disabled.
    factors: Vec<Option<KeptFactors>>,
    /// Memory the kept factors take (bytes, as measured when each slot was filled).
    factor_bytes: usize,
    /// Slot n mod (len + 1): Z of time level n, one level further back than the states, for
    /// the ring's step of one period ago.
    z: Vec<Option<f64>>,
    /// For the last stored level n: how many nodes' active-set flags differ from level
    /// n − period's and from level n − 1's carried with the texture ([`TextureShift`], the
    /// other guess; see [`PeriodGuess::guess`]).
    switched: Option<(usize, usize)>,
}

/// Most memory the kept factors of a period may take (bytes): 512×32 needs ≈ 0.55 GB for
/// per = 0.06 (150 steps of ≈ 3.7 MB: the band in single precision and the stencil it is of;
/// 1.0 GB in double until stop 27), 512×8 ≈ 50 MB (double); beyond it the later steps of a
/// period go without. Why 1.5 GiB: at 1 GiB (until stop 21, double) Case III at `paper` kept
/// factors for only ≈ 90 % of its steps, and the others factored every step of the settled
/// windows (0.11 factorisations a step, 1160 rows eliminated); at 1.5 GiB 0.00–0.02 (0–10
/// rows), and the whole 512×32 stage eliminated 11 % fewer rows. Finer meshes (1024×64:
/// ≈ 37 MB a step) keep what fits.
const PERIOD_FACTORS_MEMORY: usize = 3 << 29;

/// Most memory the period's states may take (bytes); longer periods go without.
const PERIOD_GUESS_MEMORY: usize = 256 << 20;

impl PeriodGuess {
    fn new(textured: bool, steps_per_period: usize, nodes: usize) -> Self {
        let bytes = steps_per_period * nodes * (2 * std::mem::size_of::<f64>() + 1);
        let on = textured && steps_per_period > 1 && bytes <= PERIOD_GUESS_MEMORY;
        PeriodGuess {
            slots: if on {
                vec![None; steps_per_period]
            } else {
                Vec::new()
            },
            factors: if on {
                vec![None; steps_per_period]
            } else {
                Vec::new()
            },
            factor_bytes: 0,
            switched: None,
            z: if on {
                vec![None; steps_per_period + 1]
            } else {
                Vec::new()
            },
        }
    }

    /// Lends the solver the factors kept from time level `level − period` (same texture
    /// phase), if any: near the periodic regime they serve the step's first iteration as a
    /// chord step, and their rows the texture alone sets are reused bit for bit.
    fn lend_factors(&mut self, level: usize, solver: &mut FilmSolver) {
        let n = self.factors.len();
        if let Some(Some(f)) = level.checked_rem(n).map(|k| &mut self.factors[k]) {
            solver.inherit_factors(f);
        }
    }

    /// Keeps the solver's factors of time level `level` for one period (within
    /// [`PERIOD_FACTORS_MEMORY`]), leaving the solver the slot's old ones.
    fn keep_factors(&mut self, level: usize, solver: &mut FilmSolver) {
        if solver.method != Method::Direct {
            return;
        }
        let n = self.factors.len();
        let Some(slot) = level.checked_rem(n).map(|k| &mut self.factors[k]) else {
            return;
        };
        match slot {
            Some(f) => solver.keep_factors(f),
            None if self.factor_bytes <= PERIOD_FACTORS_MEMORY => {
                let mut f = KeptFactors::default();
                solver.keep_factors(&mut f);
                self.factor_bytes += f.bytes();
                *slot = Some(f);
            }
            None => {}
        }
    }

    /// The state of time level `level − period`, if stored and the better guess: when the
    /// active set of the last solved level (`level − 1`) differs from the one a period
    /// before it in no more nodes than from the one a step before it (carried with the
    /// texture, as that guess is: [`TextureShift`]). With it a guess of Z:
    /// the ring's step of one period ago repeated from `z_now`, i.e. the drift over the last
    /// period carried forward by one step (near the periodic regime far closer than the
    /// velocity extrapolation, which lets the direct method settle the step by one chord
    /// solve).
    ///
    /// Why the active sets decide: how many nodes the first Newton iteration must switch is
    /// what a guess costs (about one iteration and one factorisation per sweep of switches),
    /// and the last level's switches over a period and over a step are known for free. The
    /// ring's drift alone (the rule before, |Z_guess − Z_then| ≤ 10·|Z_guess − Z_now|) is
    /// no measure of it: while a creeping ring drifts by 0.5–1 % a period the period-old
    /// set is still far the better guess (R = 51.2, `fast`: 3.0 against 4–11 iterations a
    /// step), and in the first periods after a start, with the ring nearly still, the
    /// film's own transient makes it the worse (14–50 against 4–11). Measured (`fast`,
    /// tolerance 1e-4, iterations a step and wall time): R = 51.2, 0.01/0.02/2 µm 4.93 →
    /// 3.38, 9.95 → 7.18 s; R = 6.4, 0.0025/0.005/5 µm 4.37 → 2.44, 8.4 → 5.0 s; Case III
    /// 3.48 → 3.21; outcomes equal to round-off (the guess only starts the iteration).
    fn guess(&self, level: usize, z_now: f64) -> Option<(&FilmState, f64)> {
        let n = self.slots.len();
        let (state, z_then) = self.slots.get(level.checked_rem(n)?)?.as_ref()?;
        let better = matches!(self.switched, Some((period, step)) if period <= step);
        // Z of level − period − 1 (the slot of level − 1 holds level − 1 itself).
        let z_before = self.z[level.checked_sub(n + 1)? % (n + 1)]?;
        better.then_some((state, z_now + (z_then - z_before)))
    }

    /// Keeps the solved state of time level `level` (reusing the slot's buffers). The last
    /// argument says how the next step's other guess carries the previous state with the
    /// texture, so that the switches counted against the previous level are those that
    /// guess would need.
    fn store(
        &mut self,
        level: usize,
        state: &FilmState,
        z: f64,
        (shift, grid, hl): (TextureShift, &Grid, &[f64]),
    ) {
        let n = self.slots.len();
        if let Some(slot) = level.checked_rem(n + 1).and_then(|k| self.z.get_mut(k)) {
            *slot = Some(z);
        }
        let Some(k) = level.checked_rem(n) else {
            return;
        };
        let differ = |s: &Option<(FilmState, f64)>, shift: TextureShift| {
            s.as_ref()
                .map(|(s, _)| shift.switches(grid, hl, &s.pressurised, &state.pressurised))
        };
        self.switched = differ(&self.slots[k], TextureShift::NONE)
            .zip(differ(&self.slots[(k + n - 1) % n], shift));
        let slot = &mut self.slots[k];
        match slot {
            Some((s, zs)) => {
                s.assign(state);
                *zs = z;
            }
            None => *slot = Some((state.clone(), z)),
        }
    }
}

/// How a step's initial guess from the previous time level follows the texture: the liner,
/// and the pockets with it, move u·dt per step, about one node column at every tier (dt is
/// matched to dx). Inside a pocket the film moves with it (the oil it carries, the cavity
/// it opens), so there the previous state `columns` upstream is the nearer guess; outside,
/// the film is held by the ring, which stays. Only a starting point: the step's film
/// problem has one solution, so outcomes change at round-off only. Measured (stop 22):
/// iterations a step at `paper` from the paper's start (`bench`), Case I 1.69 → 1.65, Case
/// III 2.59 → 2.26, R = 51.2 2.47 → 1.89; instructions (valgrind) at `fast` Case III 17.16 G
/// → 16.05 G, R = 51.2 17.00 G → 13.51 G, at `paper` Case III 83.4 G → 81.4 G (its 512×32
/// windows eliminate as many band rows as before: fewer, longer refactorisations). Carrying
/// every node instead (the ring's own cavity too) cost Case I at `fast` 1.92 → 2.50.
#[derive(Clone, Copy, Debug, PartialEq)]
struct TextureShift {
    columns: usize,
}

impl TextureShift {
    const NONE: TextureShift = TextureShift { columns: 0 };

    fn of(case: &CaseSpec, dt: f64, g: &Grid) -> Self {
        let columns = if case.texture.is_some() {
            (case.u * dt / g.dx).round().clamp(0.0, g.n1 as f64) as usize
        } else {
            0
        };
        TextureShift { columns }
    }

    /// The node whose previous state guesses node m's: `columns` upstream when m (an
    /// interior node) lies in a pocket and that node is interior too; m itself otherwise.
    #[inline]
    fn source(self, g: &Grid, hl: &[f64], m: usize) -> usize {
        let back = self.columns * g.n2;
        let interior = m >= back + g.n2 && m < g.n1 * g.n2;
        if back > 0 && interior && hl[m] > 0.0 {
            m - back
        } else {
            m
        }
    }

    /// How many nodes m are in another set in `now` than their source was in `before`
    /// (`before[source(m)] != now[m]`). Counted over slices, without a branch per node:
    /// counted node by node it was ≈ 3.7 % of a settled 512×32 step.
    fn switches(self, g: &Grid, hl: &[f64], before: &[bool], now: &[bool]) -> usize {
        let differ = |a: &[bool], b: &[bool]| a.iter().zip(b).filter(|(x, y)| x != y).count();
        let back = self.columns * g.n2;
        // Nodes that may take a source upstream (see `source`): [lo, hi).
        let (lo, hi) = (back + g.n2, (g.n1 * g.n2).min(now.len()));
        if back == 0 || lo >= hi {
            return differ(before, now);
        }
        let shifted = now[lo..hi]
            .iter()
            .zip(&hl[lo..hi])
            .zip(before[lo..hi].iter().zip(&before[lo - back..hi - back]))
            .filter(|((&x, &h), (&own, &up))| x != if h > 0.0 { up } else { own })
            .count();
        differ(&before[..lo], &now[..lo]) + shifted + differ(&before[hi..], &now[hi..])
    }

    /// Carries `state` (the previous time level) with the texture placed now (`hl`), in
    /// place: downstream first, so every node reads a source not yet overwritten.
    fn carry(self, g: &Grid, hl: &[f64], state: &mut FilmState) {
        if self.columns == 0 {
            return;
        }
        for m in (0..g.nodes()).rev() {
            let from = self.source(g, hl, m);
            if from != m {
                state.pressurised[m] = state.pressurised[from];
                state.p[m] = state.p[from];
                state.phi[m] = state.phi[from];
            }
        }
    }
}

/// Reported after each texture period of a transient run.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub period: usize,
    pub t: f64,
    pub f_mean: f64,
    pub z_mean: f64,
    /// Estimated relative distance from the periodic regime (infinite until it can be told).
    pub periodic_error: f64,
}

/// Means over one texture period.
#[derive(Clone, Debug)]
struct PeriodMeans {
    friction: Friction,
    extra: Vec<Friction>,
    z_mean: f64,
    z_min: f64,
    z_max: f64,
    /// Oil the film holds at the window's end (∫ h·θ dx1 dx2 over the domain, nondimensional).
    content: f64,
    /// Oil through the domain over the window at the end's boundary flow rates (the larger
    /// of inflow and outflow, times the window's length): the scale of a content change.
    throughput: f64,
}

impl PeriodMeans {
    fn empty() -> Self {
        PeriodMeans {
            friction: Friction::default(),
            extra: Vec::new(),
            z_mean: 0.0,
            z_min: f64::INFINITY,
            z_max: f64::NEG_INFINITY,
            content: 0.0,
            throughput: 0.0,
        }
    }
    fn add(&mut self, row: &SeriesRow, f: &Friction, extra: &[Friction]) {
        self.friction.add(f);
        self.extra.resize(extra.len(), Friction::default());
        for (a, e) in self.extra.iter_mut().zip(extra) {
            a.add(e);
        }
        self.z_mean += row.z;
        self.z_min = self.z_min.min(row.z);
        self.z_max = self.z_max.max(row.z);
    }
    /// The samples at the n step ends of a period: their plain mean is the trapezoidal mean
    /// of the periodic signal over the period.
    fn finish(mut self, n: usize) -> Self {
        self.friction = self.friction.scaled(1.0 / n as f64);
        for e in &mut self.extra {
            *e = e.scaled(1.0 / n as f64);
        }
        self.z_mean /= n as f64;
        self
    }
}

/// Shortest averaging window (ms = L/U): as long as the pseudo-period of an untextured run.
const MIN_WINDOW: f64 = UNTEXTURED_PERIOD;

/// Most state extrapolations per run.
const MAX_JUMPS: usize = 3;

/// The state at the end of a texture period (same texture phase at every period end).
struct PeriodEnd {
    phi: Vec<f64>,
    ring: RingState,
}

impl PeriodEnd {
    fn of(t: &Transient) -> Self {
        PeriodEnd {
            phi: t.state.phi.clone(),
            ring: t.ring_state,
        }
    }
}

impl Transient {
    /// Texture periods per averaging window: the fewest whole periods spanning at least
    /// `MIN_WINDOW`. Why: for short periods (per = 0.005 is 13 steps) the cycle-to-cycle
    /// change of a slow creep is tiny against its tail (ratio ≈ 0.993 a period at R = 102.4),
    /// so neither the periodicity estimate nor the slow-mode jump could read it period by
    /// period. Means over whole periods are the same in the periodic regime.
    pub fn window_periods(&self) -> usize {
        let period = self.dt * self.steps_per_period as f64;
        ((MIN_WINDOW / period) - 1e-9).ceil().max(1.0) as usize
    }

    /// Moves the state to the limit of `mode` read from three consecutive window ends
    /// (oldest first), keeping θ in [0, 1]. The film content and the ring move together, as
    /// the slow mode couples them (the oil held in the contact and the clearance it
    /// carries). Refused (false, state unchanged) when the jump would take the ring to less
    /// than half or more than twice its clearance: then the mode is not the clean decay the
    /// extrapolation assumes.
    fn jump_to_limit(&mut self, ends: [&PeriodEnd; 3], mode: SlowMode) -> bool {
        let g = &self.scene.grid;
        let [a, b, c] = ends;
        let z = mode.limit(a.ring.z, b.ring.z, c.ring.z);
        if !(z.is_finite() && z >= 0.5 * c.ring.z && z <= 2.0 * c.ring.z) {
            return false;
        }
        for k in 0..g.nodes() {
            let h = self.scene.gap.h(g, k, z);
            let phi = mode.limit(a.phi[k], b.phi[k], c.phi[k]);
            self.state.phi[k] = phi.max(0.0).min(h);
            if self.state.pressurised[k] {
                self.state.phi[k] = h;
            }
        }
        // The states kept from the last period stay the guesses of the next one: the jump
        // moves the film and Z by the mode's remainder only, so their active sets are still
        // far nearer than the previous step's, and a guess changes no solution. Measured
        // (iterations a step): R = 51.2 at `paper`, the window after the fine mesh's jump
        // 6.18 → 2.41 (23 → 9 ms a step); at `fast` Case I / III / R = 51.2 1.97 / 2.74 /
        // 2.88 → 1.92 / 2.68 / 2.66, outcomes within 7e-12. (Until stop 21 they were
        // dropped, and the period after a jump started from the previous step's state.)
        self.ring_state = RingState {
            z,
            v: mode.limit(a.ring.v, b.ring.v, c.ring.v),
            a: mode.limit(a.ring.a, b.ring.a, c.ring.a),
        };
        true
    }
}

/// A slow mode of the approach to the periodic regime, as the recurrence its window-to-window
/// changes obey: d_{i+1} = α·d_i + β·d_{i−1} (β = 0: one geometric mode of ratio α; β ≠ 0:
/// a damped oscillation or two modes). Any sequence y_i that obeys it tends to
/// y* = (y_k − α·y_{k−1} − β·y_{k−2}) / (1 − α − β).
#[derive(Clone, Copy, Debug)]
struct SlowMode {
    alpha: f64,
    beta: f64,
}

impl SlowMode {
    /// The limit y* from three consecutive values, oldest first.
    fn limit(&self, y0: f64, y1: f64, y2: f64) -> f64 {
        (y2 - self.alpha * y1 - self.beta * y0) / (1.0 - self.alpha - self.beta)
    }

    /// |λ| of the two roots of λ² = αλ + β, larger first (equal for a complex pair): the
    /// decay per window of the slower and the faster mode.
    fn radii(&self) -> (f64, f64) {
        let (a, b) = (self.alpha, self.beta);
        let disc = a * a + 4.0 * b;
        if disc < 0.0 {
            ((-b).sqrt(), (-b).sqrt())
        } else {
            (
                0.5 * (a.abs() + disc.sqrt()),
                0.5 * (a.abs() - disc.sqrt()).abs(),
            )
        }
    }

    /// Largest |λ|: the decay per window.
    fn radius(&self) -> f64 {
        self.radii().0
    }

    /// Smaller |λ| (equal to the larger for a complex pair).
    fn second_radius(&self) -> f64 {
        self.radii().1
    }

    /// Whether jumping along this mode saves windows: only when, decaying at its own rate,
    /// the mode would still need more than [`JUMP_WINDOWS`] windows to fall to the periodic
    /// tolerance, or to [`JUMP_TOL`] if that is tighter (the run after a jump needs at least
    /// four fresh windows, and a mode decaying fast, Case III's 0.49 a period, gains little:
    /// the jump only resets the history).
    fn worth_a_jump(&self, h: &[PeriodMeans], num: &Numerics) -> bool {
        let k = h.len() - 1;
        let z = |i: usize| h[i].z_mean;
        let distance = ((z(k) - self.limit(z(k - 2), z(k - 1), z(k))) / z(k)).abs();
        let tol = num.periodic_tol.min(JUMP_TOL);
        distance > tol * self.radius().powi(-(JUMP_WINDOWS as i32))
    }
}

/// The jump rule weighs a mode against this tolerance when the run's is looser. Why: the
/// periodic test passes only once its estimate of the distance, read from the changes of
/// the window means, is below the tolerance at two window ends in a row, which for a damped
/// oscillation comes well after the mode itself has decayed to the tolerance; weighed
/// against 1e-4 the jump was refused where it would have paid (Case I at `fast`: 18 windows
/// without it, 14 with it), and a run could stop short of its tolerance (R = 0.8, 0.01 /
/// 0.02 / 20 µm at `fast`: 1.2e-4 from its limit, 6.1e-6 with this rule). Measured on 30
/// sampled study cases at `fast` (1e-4): periods 1037 → 982, the worst outcome 1.2e-4 →
/// 4.5e-5 from runs to 1e-6; the 730-case paper + θs study: periods −1.7 %, wall time 22.1
/// → 21.0 min, every status the same.
const JUMP_TOL: f64 = 1e-5;

/// Smallest |λ| the second mode of a pair must have for the pair to jump.
const PAIR_SECOND: f64 = 0.2;

/// Windows a slow mode must still need before a jump along it pays (see
/// [`SlowMode::worth_a_jump`]).
const JUMP_WINDOWS: usize = 6;

/// The per-period decay ratio r of the period-mean Z when the last four periods show one
/// monotone geometric mode (three successive ratios within 2 % of each other, 0.5 < r < 0.99,
/// and the changes still well above round-off); None otherwise (oscillating or noisy).
fn slow_mode_ratio(h: &[PeriodMeans]) -> Option<SlowMode> {
    if h.len() < 5 {
        return None;
    }
    let k = h.len() - 1;
    let d: Vec<f64> = (k - 3..=k).map(|i| h[i].z_mean - h[i - 1].z_mean).collect();
    if d.iter().any(|x| x.abs() < 1e-9 * h[k].z_mean.abs()) {
        return None;
    }
    let r: Vec<f64> = d.windows(2).map(|w| w[1] / w[0]).collect();
    let steady = r.iter().all(|&x| x > 0.5 && x < 0.99)
        && r.windows(2).all(|w| (w[1] - w[0]).abs() <= 0.02 * w[1]);
    steady.then_some(SlowMode {
        alpha: r[2],
        beta: 0.0,
    })
}

/// The ring's slow mode as a damped oscillation: coefficients (α, β) of the recurrence
/// d_{i+1} = α·d_i + β·d_{i−1} fitted by least squares to the last three changes of the
/// period-mean Z̄ (six period means), when it fits them (RMS residual ≤ [`PAIR_FIT`] of the
/// changes) and decays (both roots of λ² = αλ + β inside |λ| < [`PAIR_RADIUS`]); None
/// otherwise, and for one monotone mode (the changes then lie on one line and β is
/// undetermined: [`slow_mode_ratio`] and the geometric tail read it).
///
/// Why: near its periodic regime a textured ring settles by a complex pair of slow modes
/// (Case III: |λ| ≈ 0.49 a period, a pseudo-period of ≈ 5 periods; Case I: 0.65, 7.5). Its
/// cycle-to-cycle changes swing in size with the phase of the oscillation, so a ratio of two
/// changes says nothing about the tail and the geometric estimate stayed infinite for a third
/// of the periods: Case III at `fast` ran 24 periods at any tolerance from 1e-3 to 1e-5,
/// to 3e-8 of its limit.
fn slow_pair(h: &[PeriodMeans]) -> Option<SlowMode> {
    if h.len() < 6 {
        return None;
    }
    let d: Vec<f64> = h.windows(2).map(|w| w[1].z_mean - w[0].z_mean).collect();
    let d = &d[d.len() - 5..];
    // Normal equations of the 3×2 least-squares fit d[i] ≈ α d[i−1] + β d[i−2], i = 2..5.
    let (mut s11, mut s12, mut s22, mut t1, mut t2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 2..5 {
        let (u, v, y) = (d[i - 1], d[i - 2], d[i]);
        s11 += u * u;
        s12 += u * v;
        s22 += v * v;
        t1 += u * y;
        t2 += v * y;
    }
    let det = s11 * s22 - s12 * s12;
    if !det.is_finite() || det <= 1e-6 * s11 * s22 {
        return None;
    }
    let mode = SlowMode {
        alpha: (t1 * s22 - t2 * s12) / det,
        beta: (s11 * t2 - s12 * t1) / det,
    };
    let residual: f64 = (2..5)
        .map(|i| (d[i] - mode.alpha * d[i - 1] - mode.beta * d[i - 2]).powi(2))
        .sum();
    let size: f64 = (2..5).map(|i| d[i].powi(2)).sum();
    (residual <= PAIR_FIT * PAIR_FIT * size && mode.radius() < PAIR_RADIUS).then_some(mode)
}

/// Largest RMS residual of the slow pair's fit, relative to the changes it fits.
const PAIR_FIT: f64 = 0.1;

/// Slowest decay per period the slow pair may have: closer to 1, 1/(1 − α − β) amplifies
/// the fit's error too much for the limit to be read from six periods.
const PAIR_RADIUS: f64 = 0.95;

/// Estimated relative distance of the last window means (f̄ and Z̄) from their periodic
/// limits (model.md §6), and never less than the film's oil imbalance over the last window
/// ([`oil_imbalance`]). For the motion:
/// - when the changes of Z̄ follow a damped oscillation ([`slow_pair`]: α, β), the limit of
///   a sequence y_i obeying that recurrence, y* = (y_k − α y_{k−1} − β y_{k−2})/(1 − α − β),
///   gives the distance |y_k − y*| (for f̄ with Z̄'s α, β: one mode moves both); never less
///   than the last change |y_k − y_{k−1}|;
/// - otherwise the cycle-to-cycle change d_k, extended by its geometric tail d_k/(1 − r)
///   when the changes shrink monotonically at ratio r = d_k/d_{k−1} ∈ (0, 1) (a slow creep);
///   infinite while fewer than three periods exist or while the changes grow.
fn periodic_error(h: &[PeriodMeans]) -> f64 {
    if h.len() < 3 {
        return f64::INFINITY;
    }
    let k = h.len() - 1;
    oil_imbalance(&h[k - 1], &h[k]).max(motion_error(h))
}

/// The change of the oil the film holds over the last window, relative to the oil through
/// the domain in it: zero in the periodic regime (the film holds the same oil at every window
/// end). Why: a ring that passes more oil than arrives (deep pockets carry it) drains the
/// flooded bank in front of it at a steady rate, and with it Z and f̄ creep by less than the
/// tolerance per window for as long as the bank lasts, then settle elsewhere (R = 0.2,
/// pockets 0.02 / 0.04 / 30 µm at `fast`: 43 % more oil out than in, Z̄ creeping by 4e-6 a
/// window for ≈ 190 windows, after which f̄ is 17 % lower; the motion alone had passed for
/// periodic at window 36).
fn oil_imbalance(before: &PeriodMeans, now: &PeriodMeans) -> f64 {
    (now.content - before.content).abs() / now.throughput.max(f64::MIN_POSITIVE)
}

/// The periodic error of the motion: f̄ and Z̄ (see [`periodic_error`]).
fn motion_error(h: &[PeriodMeans]) -> f64 {
    let k = h.len() - 1;
    if let Some(mode) = slow_pair(h) {
        let est = |y: &dyn Fn(&PeriodMeans) -> f64| {
            let (y0, y1, y2) = (y(&h[k - 2]), y(&h[k - 1]), y(&h[k]));
            let limit = mode.limit(y0, y1, y2);
            (y2 - limit).abs().max((y2 - y1).abs()) / y2.abs().max(f64::MIN_POSITIVE)
        };
        return est(&|p| p.friction.total()).max(est(&|p| p.z_mean));
    }
    let est = |y: &dyn Fn(&PeriodMeans) -> f64| {
        let (y0, y1, y2) = (y(&h[k - 2]), y(&h[k - 1]), y(&h[k]));
        let (d1, d2) = (y1 - y0, y2 - y1);
        let scale = y2.abs().max(f64::MIN_POSITIVE);
        if d2.abs() <= 1e-13 * scale {
            return d2.abs() / scale;
        }
        let r = if d1 != 0.0 { d2 / d1 } else { f64::INFINITY };
        let tail = if r > 0.0 && r < 1.0 {
            d2.abs() / (1.0 - r)
        } else if r <= 0.0 {
            d2.abs()
        } else {
            // Growing changes say nothing of the tail, however small they are. (Reading them
            // as 10× to 100× the change instead saved nothing at `fast`: 30 sampled study
            // cases at 1e-4 took 1033–1035 periods against 1037.)
            f64::INFINITY
        };
        tail / scale
    };
    est(&|p| p.friction.total()).max(est(&|p| p.z_mean))
}

/// The transient of a textured case ready to run on `num`'s mesh: from the start of
/// `num.start`, or, with a coarse approach (`num.approach_n2` below N2), from where a run on
/// the coarse mesh reached its periodic regime to [`APPROACH_TOL`] (`observe` sees that
/// run's periods; its time series, when asked for, goes to `series`).
fn start_transient(
    case: &CaseSpec,
    num: &Numerics,
    series: Option<&mut Vec<SeriesRow>>,
    observe: &mut dyn FnMut(&Progress),
    on_step: &mut dyn FnMut(&Transient),
) -> Result<Transient, SolveError> {
    let Some(mut coarse) = num.approach_numerics(case) else {
        return Ok(Transient::new(case, num));
    };
    // The full mesh keeps at least half of the time allowed.
    coarse.t_max = 0.5 * num.t_max;
    let began = Instant::now();
    let mut t = Transient::new(case, &coarse);
    let r = match t.run_with(&coarse, series.is_some(), observe, on_step) {
        Ok(r) => r,
        // A coarse mesh may fail where the full one would not (a pocket it resolves poorly
        // closing the gap): then the full mesh runs from the start alone (the time spent
        // still counts).
        Err(_) => {
            let mut full = Transient::new(case, num);
            full.approach.wall_time_s = began.elapsed().as_secs_f64();
            return Ok(full);
        }
    };
    if let (Some(all), Some(rows)) = (series, r.series) {
        all.extend(rows);
    }
    let done = ApproachDone {
        steps: r.outcome.steps,
        periods: r.outcome.periods,
        wall_time_s: r.outcome.wall_time_s,
    };
    Ok(t.refined(num, done))
}

/// The 2D transient of `case` to its periodic regime (with the coarse approach of `num`, if
/// any), reporting the outcomes for the further shear thresholds `extra_theta_s` too and
/// calling `observe` after every texture period of either mesh. The time series, when
/// asked for, holds every step, the coarse approach's included.
pub fn run_transient(
    case: &CaseSpec,
    num: &Numerics,
    record_series: bool,
    extra_theta_s: &[f64],
    observe: &mut dyn FnMut(&Progress),
) -> Result<RunResult, SolveError> {
    run_transient_with(
        case,
        num,
        record_series,
        extra_theta_s,
        observe,
        &mut |_| {},
    )
}

/// As `run_transient`, also calling `on_step` with the state after every time step of either
/// mesh (e.g. to tally the film solver's work, `examples/where_time_goes.rs`).
pub fn run_transient_with(
    case: &CaseSpec,
    num: &Numerics,
    record_series: bool,
    extra_theta_s: &[f64],
    observe: &mut dyn FnMut(&Progress),
    on_step: &mut dyn FnMut(&Transient),
) -> Result<RunResult, SolveError> {
    let mut series = record_series.then(Vec::new);
    let mut t = start_transient(case, num, series.as_mut(), observe, on_step)?;
    t.extra_theta_s = extra_theta_s.to_vec();
    let mut r = t.run_with(num, record_series, observe, on_step)?;
    if let (Some(mut all), Some(rows)) = (series, r.series.take()) {
        all.extend(rows);
        r.series = Some(all);
    }
    Ok(r)
}

/// Periodic tolerance at which a coarse approach hands over to the full mesh: about the
/// coarse mesh's own offset from the full one (512×8 vs 512×32: 0.1–0.4 % in f̄ and Z̄),
/// which only the full mesh's periods remove; converging the coarse run much further buys
/// nothing, stopping it much earlier leaves the full mesh part of the transient. Measured
/// (paper tier, `bench`, Case I / Case III / R = 51.2, wall s, two runs side by side): from
/// the paper's start 19.6 / 19.7 / 23.0 at 1e-1, 15.9 / 23.2 / 25.6 at 1e-2, 14.7 / 19.1 /
/// 25.2 at 1e-3; from the equilibrium start 25.7 / 22.2 / 36.0, 15.5 / 17.4 / 24.0, 13.1 /
/// 19.9 / 23.6 (without the approach 31.3 / 40.9 / 33.2). Measured with the geometric-tail
/// periodic test alone; with the damped-oscillation reading (`slow_pair`) the coarse run
/// reaches 1e-3 sooner (Case III from the paper's start: 24 → 12 coarse periods).
pub const APPROACH_TOL: f64 = 1e-3;

/// One evaluation with the default dispatch: an untextured liner is solved as the steady
/// 1D force balance on n1 cells; a textured one by the 2D transient to the periodic regime.
pub fn simulate(
    case: &CaseSpec,
    num: &Numerics,
    record_series: bool,
) -> Result<RunResult, SolveError> {
    simulate_theta_s(case, num, record_series, &[])
}

/// As `simulate`, also reporting the outcomes for the shear thresholds `extra_theta_s`
/// (`RunResult::extra`): θ_s changes only the Couette friction term (model.md §5), so the
/// film and the ring are simulated once.
pub fn simulate_theta_s(
    case: &CaseSpec,
    num: &Numerics,
    record_series: bool,
    extra_theta_s: &[f64],
) -> Result<RunResult, SolveError> {
    match case.texture {
        None => {
            let mut r = steady_outcome(case, num.n1)?;
            for &theta_s in extra_theta_s {
                let other = CaseSpec {
                    theta_s,
                    ..case.clone()
                };
                r.extra
                    .push((theta_s, steady_outcome(&other, num.n1)?.outcome));
            }
            Ok(r)
        }
        Some(_) => run_transient(case, num, record_series, extra_theta_s, &mut |_| {}),
    }
}

/// The steady untextured outcome in the common form.
pub fn steady_outcome(case: &CaseSpec, n1: usize) -> Result<RunResult, SolveError> {
    let start = Instant::now();
    let s = solve_untextured(case, n1).map_err(|source| SolveError::Steady {
        case: case.label(),
        source,
    })?;
    let c_min = case.contact().clearance_um(s.z);
    let outcome = Outcome {
        f_mean: s.friction.total(),
        f_couette: s.friction.couette,
        f_poiseuille: s.friction.poiseuille,
        f_pressure: s.friction.pressure,
        z_mean: s.z,
        z_min: s.z,
        z_max: s.z,
        c_min,
        periods: 0,
        steps: 0,
        converged: true,
        periodic_error: 0.0,
        method: "steady-1d".into(),
        dt: 0.0,
        t_end: 0.0,
        iterations_per_step: 0.0,
        max_residual: 0.0,
        wall_time_s: start.elapsed().as_secs_f64(),
        approach_steps: 0,
    };
    Ok(RunResult {
        outcome,
        series: None,
        extra: Vec::new(),
    })
}

/// The film state of scene `from` (ring at z) on the mesh of scene `to`: same N1, other N2,
/// both placed at the same texture phase. Saturation θ and pressure are interpolated
/// linearly in x2 between node centres (held constant beyond the outermost ones, the
/// symmetry lines), φ = θ·h on the new gap (h on the pressurised set, θ = 1), the active set
/// that of the nearer node. Why θ rather than φ: the pockets' depth differs node by node
/// between the meshes, the saturation far less.
fn interpolate_x2(from: &Scene, state: &FilmState, z: f64, to: &Scene) -> FilmState {
    let (gc, gf) = (&from.grid, &to.grid);
    let mut out = FilmState::cavitated(gf, &to.gap, z, 0.0);
    let last = (gc.n2 - 1) as f64;
    for j in 0..gf.n2 {
        // The fine node's x2 in coarse node units, and its two neighbours there.
        let s = (gf.y(j) / gc.dy - 0.5).clamp(0.0, last);
        let j0 = s.floor() as usize;
        let j1 = (j0 + 1).min(gc.n2 - 1);
        let w = s - j0 as f64;
        for i in 0..=gf.n1 {
            let (k0, k1) = (gc.idx(i, j0), gc.idx(i, j1));
            let theta_at = |k: usize| state.theta(gc, &from.gap, z, k).clamp(0.0, 1.0);
            let theta = (1.0 - w) * theta_at(k0) + w * theta_at(k1);
            let p = (1.0 - w) * state.p[k0] + w * state.p[k1];
            let k = gf.idx(i, j);
            let h = to.gap.h(gf, k, z);
            let pressurised = state.pressurised[if w < 0.5 { k0 } else { k1 }];
            out.pressurised[k] = pressurised;
            out.p[k] = if pressurised { p.max(0.0) } else { 0.0 };
            out.phi[k] = if pressurised { h } else { theta * h };
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Window means whose f̄ and Z̄ follow y_k = y* + A·ρ^k·cos(ωk + φ).
    fn oscillation(n: usize, rho: f64, omega: f64) -> Vec<PeriodMeans> {
        (0..n)
            .map(|k| {
                let k = k as f64;
                let mut m = PeriodMeans::empty();
                m.z_mean = 3.0 + 0.05 * rho.powf(k) * (omega * k + 0.3).cos();
                m.friction.couette = 0.08 + 0.002 * rho.powf(k) * (omega * k + 1.1).cos();
                m
            })
            .collect()
    }

    #[test]
    fn a_damped_oscillation_is_read_to_its_limit() {
        let h = oscillation(12, 0.75, 1.5);
        let mode = slow_pair(&h).expect("a clean damped oscillation fits");
        assert!((mode.radius() - 0.75).abs() < 1e-9, "{mode:?}");
        assert!((mode.second_radius() - 0.75).abs() < 1e-9, "{mode:?}");
        // Two real modes, 0.9 and 0.1: λ² = λ − 0.09.
        let real = SlowMode {
            alpha: 1.0,
            beta: -0.09,
        };
        assert!((real.radius() - 0.9).abs() < 1e-12 && (real.second_radius() - 0.1).abs() < 1e-12);
        assert!((real.limit(1.0, 2.0, 2.5) - (2.5 - 2.0 + 0.09) / 0.09).abs() < 1e-9);
        // The estimate is the larger of the distance from the limit and the last change.
        let k = h.len() - 1;
        let rel = |y: &dyn Fn(&PeriodMeans) -> f64, limit: f64| {
            let (now, before) = (y(&h[k]), y(&h[k - 1]));
            ((now - limit).abs().max((now - before).abs())) / now.abs()
        };
        let expected = rel(&|m| m.z_mean, 3.0).max(rel(&|m| m.friction.total(), 0.08));
        let est = periodic_error(&h);
        assert!((est / expected - 1.0).abs() < 1e-6, "{est} vs {expected}");
        // The geometric tail alone cannot read it: the ratio of the last two changes is
        // negative or above 1 for most windows of a rotating mode.
        assert!(slow_mode_ratio(&h).is_none());
    }

    #[test]
    fn a_film_that_still_gains_or_loses_oil_is_not_periodic() {
        // The motion has settled (f̄ and Z̄ constant), but the film loses 1 % of the oil
        // through it every window: not periodic, whatever the motion says.
        let h: Vec<PeriodMeans> = (0..8)
            .map(|k| {
                let mut m = PeriodMeans::empty();
                m.z_mean = 3.0;
                m.friction.couette = 0.08;
                m.throughput = 0.5;
                m.content = 1.0 - 0.005 * k as f64;
                m
            })
            .collect();
        assert!((periodic_error(&h) - 0.01).abs() < 1e-12);
        let held: Vec<PeriodMeans> = h
            .into_iter()
            .map(|m| PeriodMeans { content: 1.0, ..m })
            .collect();
        assert_eq!(periodic_error(&held), 0.0);
    }

    #[test]
    fn the_slow_pair_is_refused_when_it_does_not_describe_the_changes() {
        // Five windows: too few to check a fit of two coefficients.
        assert!(slow_pair(&oscillation(5, 0.75, 1.5)).is_none());
        // A single geometric mode: the changes lie on one line (β undetermined); the
        // geometric tail reads it instead.
        let geometric: Vec<PeriodMeans> = (0..8)
            .map(|k| {
                let mut m = PeriodMeans::empty();
                m.z_mean = 3.0 + 0.05 * 0.9f64.powi(k);
                m
            })
            .collect();
        assert!(slow_pair(&geometric).is_none());
        assert!(slow_mode_ratio(&geometric).is_some());
        // Growing, or changes that follow no recurrence.
        assert!(slow_pair(&oscillation(12, 1.05, 1.5)).is_none());
        let mut noisy = oscillation(12, 0.75, 1.5);
        for (i, m) in noisy.iter_mut().enumerate() {
            m.z_mean += 1e-3
                * [
                    0.3, -1.0, 0.7, 0.2, -0.6, 1.0, -0.4, 0.9, -0.8, 0.1, 0.5, -0.2,
                ][i];
        }
        assert!(slow_pair(&noisy).is_none());
    }

    #[test]
    fn a_jump_is_weighed_against_a_tight_tolerance_whatever_the_runs() {
        // A damped oscillation ≈ 1e-4 from its limit, decaying at 0.75 a window: six
        // windows bring it to ≈ 2e-5, above 1e-5, so the jump pays even for a run at 1e-3,
        // whose periodic test would still have to watch it decay.
        let h = oscillation(12, 0.75, 1.5);
        let mode = slow_pair(&h).expect("a clean damped oscillation fits");
        let loose = Numerics {
            periodic_tol: 1e-3,
            ..Numerics::default()
        };
        assert!(mode.worth_a_jump(&h, &loose));
        // Far into the decay (≈ 1e-7 from the limit) no tolerance makes it worth a jump.
        let late = oscillation(40, 0.75, 1.5);
        let mode = slow_pair(&late).expect("still a clean damped oscillation");
        assert!(!mode.worth_a_jump(&late, &loose));
        let tight = Numerics {
            periodic_tol: 1e-6,
            ..Numerics::default()
        };
        assert!(!mode.worth_a_jump(&late, &tight));
    }

    /// A transient of Case III's texture on a small mesh, `steps` steps in (two periods and
    /// a bit: every phase slot has been placed once and served once).
    fn case_iii_after(steps: usize) -> Transient {
        let case =
            CaseSpec::paper(3.2).with_texture(crate::case::Texture::circular(0.03, 0.06, 10.0));
        let num = Numerics {
            n1: 64,
            n2: 4,
            dt: 4e-3,
            ..Numerics::default()
        };
        let mut t = Transient::new(&case, &num);
        for _ in 0..steps {
            t.step().expect("a coarse Case III steps");
        }
        t
    }

    #[test]
    fn the_texture_kept_from_a_period_ago_is_the_texture_placed_now() {
        let mut t = case_iii_after(0);
        let n = t.steps_per_period;
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for _ in 0..2 * n + 3 {
            t.step().expect("a coarse Case III steps");
            // The scene as placing the texture afresh at this step's phase gives it.
            let mut fresh = t.scene.clone();
            fresh.place((t.steps % n) as f64 * t.dt);
            assert_eq!(bits(&t.scene.hl), bits(&fresh.hl), "step {}", t.steps);
            assert_eq!(
                bits(&t.scene.gap.base),
                bits(&fresh.gap.base),
                "step {}",
                t.steps
            );
        }
        // The kept phases served: every slot is filled.
        assert!(t.placed.slots.iter().all(Option::is_some));
    }

    #[test]
    fn a_jump_keeps_the_states_of_the_last_period_as_guesses() {
        let mut t = case_iii_after(0);
        let n = t.steps_per_period;
        let mut ends = Vec::new();
        for _ in 0..3 {
            for _ in 0..n {
                t.step().expect("a coarse Case III steps");
            }
            ends.push(PeriodEnd::of(&t));
        }
        let mode = SlowMode {
            alpha: 0.5,
            beta: 0.0,
        };
        assert!(t.jump_to_limit([&ends[0], &ends[1], &ends[2]], mode));
        // Every phase of the next period still has its state of a period ago (dropping them
        // cost the period after a jump 2.5× the iterations).
        assert!(t.period_ago.slots.iter().all(Option::is_some));
        assert!(t.period_ago.z.iter().all(Option::is_some));
        // And the run goes on from the jumped state.
        for _ in 0..n {
            t.step().expect("the period after a jump steps");
        }
    }

    #[test]
    fn switches_counted_over_slices_are_those_node_by_node() {
        // Two levels of a coarse Case III a few steps apart: sets that differ in and out of
        // the pockets.
        let mut t = case_iii_after(3);
        let before = t.state.pressurised.clone();
        for _ in 0..4 {
            t.step().expect("a coarse Case III steps");
        }
        let (g, hl, now) = (&t.scene.grid, &t.scene.hl, &t.state.pressurised);
        assert!(hl.iter().any(|&h| h > 0.0) && hl.iter().any(|&h| h <= 0.0));
        for columns in [0, 1, 3, g.n1, g.n1 + 1] {
            let shift = TextureShift { columns };
            let by_node = (0..now.len())
                .filter(|&m| before[shift.source(g, hl, m)] != now[m])
                .count();
            assert!(columns > 1 || by_node > 0, "the sets must differ somewhere");
            assert_eq!(
                shift.switches(g, hl, &before, now),
                by_node,
                "{columns} columns"
            );
        }
    }

    #[test]
    fn the_previous_state_carried_with_the_texture_is_the_nearer_guess() {
        // Each step's guess from the previous level alone (no period-old states), with and
        // without carrying the pockets' film along with them.
        let mut carried = case_iii_after(0);
        carried.set_period_guess(false);
        assert_eq!(
            carried.shift.columns, 1,
            "u·dt/dx = 1.28 at 64×4, dt = 4e-3"
        );
        let mut held = carried.clone();
        held.shift = TextureShift::NONE;
        let n = carried.steps_per_period;
        let (mut switched_carried, mut switched_held) = (0, 0);
        let (mut it_carried, mut it_held) = (0, 0);
        for _ in 0..2 * n {
            let before = carried.state.clone();
            carried.step().expect("a coarse Case III steps");
            held.step().expect("a coarse Case III steps");
            it_carried += carried.last.iterations;
            it_held += held.last.iterations;
            let mut guess = before.clone();
            carried
                .shift
                .carry(&carried.scene.grid, &carried.scene.hl, &mut guess);
            let differ = |g: &FilmState| {
                g.pressurised
                    .iter()
                    .zip(&carried.state.pressurised)
                    .filter(|(a, b)| a != b)
                    .count()
            };
            switched_carried += differ(&guess);
            switched_held += differ(&before);
        }
        // The pockets’ cavities move with them: the carried guess is the nearer active set
        // and needs fewer iterations (carrying the nodes outside the pockets instead, it
        // would not: 410 against 406 switches, 120 against 120 iterations).
        assert!(
            switched_carried < switched_held,
            "{switched_carried} {switched_held}"
        );
        assert!(it_carried < it_held, "{it_carried} {it_held}");
        // A guess only starts the iteration: the same film and ring to the solve tolerance.
        let dz = (carried.ring_state.z - held.ring_state.z).abs() / held.ring_state.z;
        assert!(dz < 1e-9, "{dz}");
        let pmax = held.state.p.iter().fold(0.0f64, |m, &p| m.max(p));
        for (a, b) in carried.state.p.iter().zip(&held.state.p) {
            assert!((a - b).abs() <= 1e-8 * pmax, "{a} {b}");
        }
    }

    #[test]
    fn friction_for_several_thresholds_in_one_pass_is_each_ones_own() {
        let t = case_iii_after(20);
        let z = t.ring_state.z;
        let thresholds = [0.75, 0.5, 0.25, 0.05];
        let model = t.friction_model();
        let (own, extra) = friction_thresholds(
            &t.scene.grid,
            &t.scene.gap,
            z,
            &t.scene.hl,
            &t.state,
            &model,
            &thresholds,
        );
        let alone = |theta_s: f64| {
            crate::friction::friction(
                &t.scene.grid,
                &t.scene.gap,
                z,
                &t.scene.hl,
                &t.state,
                &FrictionModel { theta_s, ..model },
            )
        };
        assert_eq!(own, alone(model.theta_s));
        for (f, &theta_s) in extra.iter().zip(&thresholds) {
            assert_eq!(*f, alone(theta_s), "θs = {theta_s}");
        }
        // The thresholds do differ here (a cavitated film under the ring).
        assert_ne!(extra[0].couette, extra[3].couette);
    }
}
