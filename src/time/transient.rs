//! The coupled transient (docs/model.md §3–5): the film under the moving texture, the ring's
//! dynamics and the friction, advanced one time step at a time (docs/solver.md, "Time scheme").

use super::characteristic;
use super::memory::{PeriodGuess, PlacedTexture, TextureShift};
use super::numerics::{Numerics, Start, TimeScheme};
use super::outcome::{Outcome, SeriesRow, SolveError};
use super::steady::{solve_untextured, Steady};
use crate::mesh::integrals::{boundary_flows, friction_thresholds};
use crate::mesh::{FilmState, Scene};
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

/// Largest relative mass defect of a step ([`Transient::mass_defect`]) taken for a converged
/// solve: the Elrod–Adams scheme conserves mass to round-off (≤ 1.5e-12 over the stability
/// map, results/stability/).
pub const MASS_TOL: f64 = 1e-6;

/// Averaging windows a BDF2 run may take on its mesh, without its distance from the periodic
/// regime halving over the last half of them, before it goes on with backward Euler.
/// Why: at a Courant number u·dt/Δx1 near 1, BDF2 can settle into a slow spurious oscillation
/// where backward Euler's damping finds the periodic regime (R = 1.6, pockets 0.005 / 0.01 /
/// 10 µm on 384×8 at dt = 5.4e-4: f̄ swinging between 0.181 and 0.209 with a period of 2.4 ms,
/// where backward Euler settles at 0.151 in 102 periods and both schemes at dt = 1e-4 agree on
/// 0.158; tests/time_scheme.rs). Every benchmark case settles within 12 windows, a
/// conformal ring's creep within 20; a run whose distance stalls after 30 (a spurious
/// oscillation, or a draining oil bank, which takes ≈ 220) finishes with backward Euler, at
/// its first-order accuracy, and says so (`Outcome::scheme`). A run still settling goes on:
/// the plain march to 1e-8 takes ≈ 40 windows.
pub const BDF2_PATIENCE: usize = 30;

/// Contact: the ring is on the liner once Z (its apex's clearance above the plateau, µm) is at
/// or below this, 1 nm, a few oil molecules: no continuum film (docs/model.md §3's thin-film
/// model) is left to lubricate. Why not Z ≤ 0: the film iteration closes the gap by at most
/// half per iteration and each step's Z guess is at least half the last Z, so a ring pushed
/// into the liner approaches Z = 0 geometrically and never reaches it (a load 10⁴ times the
/// paper's: Z = 4e-250 µm and f̄ = 7e241 after 30 ms).
pub const CONTACT_Z: f64 = 1e-3;

/// The coupled transient. Advance it with [`Transient::step`];
/// [`Transient::run_to_periodic`] drives it to the periodic regime.
pub struct Transient {
    pub case: CaseSpec,
    pub scene: Scene,
    pub state: FilmState,
    /// φ at the previous time level.
    pub phi_old: Vec<f64>,
    /// φ one level before that (BDF2), and the old-level term the last step's stencil read:
    /// φⁿ (backward Euler) or (4φⁿ − φⁿ⁻¹)/3 (BDF2).
    phi_older: Vec<f64>,
    phi_eff: Vec<f64>,
    /// The film's time scheme, the levels solved since the last restart of its history (a
    /// start, a jump, a new mesh), and 1/dt of the last step's storage term (1/dt, or 1.5/dt
    /// for BDF2).
    pub scheme: TimeScheme,
    levels: usize,
    inv_dt_eff: f64,
    /// Whether the last step's storage term read `phi_eff` (BDF2 or a flux correction).
    eff: bool,
    pub ring: Ring,
    pub ring_state: RingState,
    pub t: f64,
    pub dt: f64,
    /// Steps per texture period (the period is per/u, or UNTEXTURED_PERIOD).
    pub steps_per_period: usize,
    pub steps: usize,
    /// The film solver of every step.
    pub solver: Box<dyn FilmMethod>,
    pub last: SolveStats,
    pub friction: Friction,
    /// Further shear thresholds θ_s whose friction is reported alongside (docs/model.md §5:
    /// θ_s enters only the Couette term, so one run serves them all) and their friction.
    pub extra_theta_s: Vec<f64>,
    pub extra_friction: Vec<Friction>,
    /// Guard: a step whose relative mass defect exceeds this is an error
    /// ([`SolveError::MassNotConserved`]); [`MASS_TOL`] by default.
    pub mass_tolerance: f64,
    /// Largest relative mass defect of a step so far.
    pub max_mass_defect: f64,
    pub(super) total_iterations: usize,
    pub(super) max_residual: f64,
    /// Solved states and factors of the last texture period, the initial guesses of the
    /// film iteration one period later.
    pub(super) period_ago: PeriodGuess,
    /// The texture as placed at each phase of the period.
    pub(super) placed: PlacedTexture,
    /// Node columns the texture moves in one step: how far a step's initial guess carries
    /// the film inside the pockets.
    pub(super) shift: TextureShift,
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

impl ApproachDone {
    /// The whole of a finished run, as the part before a continuation on a finer mesh.
    pub fn of(o: &Outcome) -> Self {
        ApproachDone {
            steps: o.steps,
            periods: o.periods,
            wall_time_s: o.wall_time_s,
        }
    }
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
        let scene = Scene::new(case, num.n1, num.n2);
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
            phi_old: state.phi.clone(),
            phi_older: state.phi.clone(),
            phi_eff: Vec::new(),
            scheme: num.scheme,
            levels: 0,
            inv_dt_eff: 1.0 / dt,
            eff: false,
            state,
            ring: Ring {
                mass: case.mass,
                w_ps: case.w_ps,
            },
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
            scene,
            mass_tolerance: MASS_TOL,
            max_mass_defect: 0.0,
            total_iterations: 0,
            max_residual: 0.0,
            period_ago: PeriodGuess::new(textured, steps_per_period, nodes),
            placed: PlacedTexture::new(textured, steps_per_period, nodes),
            shift,
            approach: ApproachDone::default(),
        }
    }

    /// Memory the factors kept for the next period's solves take (bytes).
    pub fn kept_factor_bytes(&self) -> usize {
        self.period_ago.factor_bytes
    }

    /// Turns the period-old initial guess of the film iteration on (the default for
    /// textured runs) or off (every step starts from the previous time level).
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
    /// (solved at Z = `ring_state.z`, its solution is `state`): for probes of other solvers
    /// on a run's own problems.
    pub fn fixed_z_problem(&self) -> Step<'_> {
        Step {
            grid: &self.scene.grid,
            gap: &self.scene.gap,
            phi_old: self.old_level(),
            inv_dt: self.inv_dt_eff,
            boundary: self.film_boundary(),
            ring: None,
        }
    }

    /// The film's boundary data as the stencil sees it: with the characteristic scheme the
    /// old level carries the Couette flux (time/characteristic.rs), so the stencil's liner
    /// speed is 0.
    fn film_boundary(&self) -> Boundary {
        let mut b = self.case.film_boundary();
        if self.scheme == TimeScheme::Characteristic {
            b.u = 0.0;
        }
        b
    }

    /// The old-level film the last step's storage term read.
    fn old_level(&self) -> &[f64] {
        if !self.eff {
            &self.phi_old
        } else {
            &self.phi_eff
        }
    }

    /// Restarts the time scheme's history: the next step is backward Euler (after the state
    /// was moved: a jump, another mesh).
    pub fn restart_history(&mut self) {
        self.levels = 0;
    }

    /// Goes on with backward Euler (see [`BDF2_PATIENCE`]): the history restarts and the
    /// factors kept a period ago, of BDF2's storage coefficient, are dropped.
    pub fn fall_back_to_backward_euler(&mut self) {
        self.scheme = TimeScheme::BackwardEuler;
        self.restart_history();
        self.set_period_guess(!self.period_ago.slots.is_empty());
    }

    /// Keeps the time scheme's history after the film was moved from `before` to the
    /// present `state.phi` on the same mesh (an extrapolation along slow modes): the previous
    /// level moves by the same change (kept ≥ 0), so BDF2 continues instead of restarting
    /// with a backward-Euler step, whose first-order error a periodic orbit would otherwise
    /// carry at every window.
    pub fn shift_history(&mut self, before: &[f64]) {
        for ((old, &now), &b) in self.phi_old.iter_mut().zip(&self.state.phi).zip(before) {
            *old = (*old + now - b).max(0.0);
        }
    }

    /// The storage term of the next step (docs/solver.md, "Time scheme"): BDF2 when the
    /// scheme asks for it, the two previous levels are at hand and its old-level term
    /// (4φⁿ − φⁿ⁻¹)/3 (into `phi_eff`) is nowhere negative; else backward Euler. Returns
    /// 1/dt of the storage term (1.5/dt for BDF2).
    fn storage_term(&mut self) -> f64 {
        if self.scheme == TimeScheme::Bdf2 && self.levels >= 1 {
            self.phi_eff.clear();
            self.phi_eff.extend(
                self.phi_old
                    .iter()
                    .zip(&self.phi_older)
                    .map(|(&now, &before)| (4.0 * now - before) / 3.0),
            );
            if self.phi_eff.iter().all(|&p| p >= 0.0) {
                return 1.5 / self.dt;
            }
        }
        1.0 / self.dt
    }

    /// One step of the film (backward Euler or BDF2 on φ) with the implicit Newmark ring
    /// update.
    pub fn step(&mut self) -> Result<(), SolveError> {
        let t_new = (self.steps + 1) as f64 * self.dt;
        // The texture placed by its phase within the period, so that the gap is the same to
        // the bit at the same phase of every period (u·t_new is that plus whole periods):
        // the matrix rows the texture alone sets (the flooded gap upstream) then match
        // the factors kept from a period ago and are not eliminated again.
        let slot = (self.steps + 1) % self.steps_per_period;
        self.placed
            .place(&mut self.scene, slot, slot as f64 * self.dt);
        // The last two levels move down (φⁿ⁻¹, φⁿ); the third buffer takes the guess.
        std::mem::swap(&mut self.phi_older, &mut self.phi_old);
        std::mem::swap(&mut self.phi_old, &mut self.state.phi);
        if self.scheme == TimeScheme::Characteristic {
            let g = &self.scene.grid;
            let c = characteristic::courant(self.case.u, self.dt, g.dx);
            characteristic::shift(&mut self.phi_old, g.n1, g.n2, c);
        }
        self.inv_dt_eff = self.storage_term();
        self.eff = self.inv_dt_eff != 1.0 / self.dt;
        // Factors kept a period ago are of the scheme's own storage term: a restart step of
        // BDF2 (backward Euler) neither takes nor keeps them.
        let regular = (self.inv_dt_eff != 1.0 / self.dt) == (self.scheme == TimeScheme::Bdf2);
        let s = self.ring_state;
        let link = self.ring.link(&s, self.dt);
        let mut z = self.initial_guess(&s, t_new)?;
        let step = Step {
            grid: &self.scene.grid,
            gap: &self.scene.gap,
            phi_old: if !self.eff {
                &self.phi_old
            } else {
                &self.phi_eff
            },
            inv_dt: self.inv_dt_eff,
            boundary: self.film_boundary(),
            ring: Some(link),
        };
        let level = self.steps + 1;
        if regular {
            self.period_ago.lend_factors(level, self.solver.as_mut());
        }
        let stats = self
            .solver
            .solve(&step, &mut self.state, &mut z)
            .map_err(|source| SolveError::Film {
                case: self.case.label(),
                t: t_new,
                source,
            })?;
        if regular {
            self.period_ago.keep_factors(level, self.solver.as_mut());
        }
        if z <= CONTACT_Z {
            return Err(SolveError::Contact {
                case: self.case.label(),
                t: t_new,
                z,
            });
        }
        self.ring_state = self.ring.advance(&s, self.dt, z, stats.w_h);
        self.check_mass(t_new)?;
        self.t = t_new;
        self.steps += 1;
        self.levels += 1;
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

    /// The step's initial guess: the film into `state` and Z returned. The state one texture
    /// period ago when its active set is the nearer ([`PeriodGuess::guess`]), with the ring's
    /// step of a period ago repeated; else the previous time level carried with the texture
    /// and the velocity extrapolation of Z. Either never closer to the liner than half the
    /// current clearance (a guess must not put the ring on the liner by itself; the iteration
    /// then moves Z as far as the film demands).
    fn initial_guess(&mut self, s: &RingState, t_new: f64) -> Result<f64, SolveError> {
        let mut z = s.z + self.dt * s.v;
        match self.period_ago.guess(self.steps + 1, s.z) {
            Some((snap, z_shifted)) => {
                z = z_shifted;
                self.state.assign(snap);
            }
            None => {
                self.state.phi.copy_from_slice(&self.phi_old);
                self.shift
                    .carry(&self.scene.grid, &self.scene.hl, &mut self.state);
            }
        }
        z = z.max(0.5 * s.z);
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
        Ok(z)
    }

    /// Guard: the step must conserve mass (a wrong number that looks right is worse than an
    /// error).
    fn check_mass(&mut self, t_new: f64) -> Result<(), SolveError> {
        let defect = self.mass_defect();
        self.max_mass_defect = self.max_mass_defect.max(defect);
        if defect.is_nan() || defect > self.mass_tolerance {
            return Err(SolveError::MassNotConserved {
                case: self.case.label(),
                t: t_new,
                defect,
                tol: self.mass_tolerance,
                hint: "the film solve did not conserve mass to round-off, which the \
                       Elrod–Adams scheme does when solved: the solve is not converged"
                    .into(),
            });
        }
        Ok(())
    }

    /// This run, after `done` (its periods, wall time) on a coarse mesh, carried over to the
    /// mesh and time step of `num` with `solver`, at the end of a texture period. The ring
    /// state, time and tallies go on as they are; the film's saturation θ and pressure are
    /// interpolated (time/approach.rs) at the texture's phase, and that film is also the new
    /// mesh's previous time level. The new mesh's first step then solves its own film; the
    /// mismatch decays like any start's.
    pub fn refined(
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
        debug_assert_eq!(
            self.steps % self.steps_per_period,
            0,
            "hand over at a period end"
        );
        let periods = self.steps / self.steps_per_period;
        fine.scene.place(0.0);
        let mut coarse = self.scene.clone();
        coarse.place(0.0);
        fine.state =
            super::approach::interpolate(&coarse, &self.state, self.ring_state.z, &fine.scene);
        fine.phi_old.copy_from_slice(&fine.state.phi);
        fine.restart_history();
        fine.steps = periods * fine.steps_per_period;
        fine.t = fine.steps as f64 * fine.dt;
        fine.ring_state = self.ring_state;
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
    pub(super) fn oil_held(&self) -> (f64, f64) {
        let g = &self.scene.grid;
        let content = (g.n2..g.n1 * g.n2).map(|k| self.state.phi[k]).sum::<f64>() * g.dx * g.dy;
        let (inflow, outflow) = boundary_flows(
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
        let change: f64 = if !self.eff {
            (g.n2..g.n1 * g.n2)
                .map(|k| self.state.phi[k] - self.phi_old[k])
                .sum::<f64>()
                * g.dx
                * g.dy
        } else {
            // BDF2: 1.5·Σ(φⁿ⁺¹ − (4φⁿ − φⁿ⁻¹)/3)·area is what a step holds to the flows.
            (g.n2..g.n1 * g.n2)
                .map(|k| self.state.phi[k] - self.phi_eff[k])
                .sum::<f64>()
                * g.dx
                * g.dy
                * (self.inv_dt_eff * self.dt)
        };
        let flows = |u: f64| boundary_flows(g, &self.scene.gap, self.ring_state.z, u, &self.state);
        // The stencil's flows (without the Couette flux when the old level carries it)
        // balance the change; the film's own flows give the scale.
        let (inflow, outflow) = flows(self.film_boundary().u);
        let (scale_in, scale_out) = if self.scheme == TimeScheme::Characteristic {
            flows(self.case.u)
        } else {
            (inflow, outflow)
        };
        let defect = change - self.dt * (inflow - outflow);
        defect.abs() / (self.dt * (scale_in.abs() + scale_out.abs())).max(f64::MIN_POSITIVE)
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
}

/// The untextured force balance (docs/model.md §6) laid on the textured gap: its saturation
/// and pressure per column, Z at the balance, at rest, W_h = W_ps so Z''(0) = 0. The texture
/// then only perturbs a balanced ring, so the periodic regime comes sooner.
pub fn equilibrium_start(scene: &Scene, eq: &Steady) -> (FilmState, RingState) {
    let g = &scene.grid;
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

/// The paper's initial state (docs/model.md §4): Z = z0, Z' = v0. The paper leaves the
/// initial film open; texopt floods the gap upstream of the ring (θ = 1 for x1 < a) and lays
/// a film of d_oil elsewhere (θ = min(1, d_oil/h)), nothing pressurised. Why: with a flooded
/// inlet the ring passes less oil than arrives, and the surplus banks up in front of the
/// ring, filling the wide gap e upstream; from a thin film that bank's front creeps to the
/// inlet at surplus/(e − d_oil) ≈ 0.005 cm/ms, so the periodic regime would come only after
/// ≈ 12 ms, with the bank's back-pressure lifting Z by up to 0.3 % on the way. The initial
/// acceleration is consistent with the unpressurised film: Z''(0) = −W_ps/m.
pub fn paper_start(scene: &Scene, case: &CaseSpec) -> (FilmState, RingState) {
    let g = &scene.grid;
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
