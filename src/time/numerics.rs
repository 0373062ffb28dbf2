//! The numerics of a run: mesh, time step, periodic tolerance, start and accelerators, with
//! their validity against the case checked up front.

use serde::{Deserialize, Serialize};

use super::characteristic::MAX_COURANT;
use crate::mesh::RimModel;
use crate::model::case::{bad, positive, CaseSpec, InputError, Texture, PAPER_RING_WIDTH};
use crate::solve::Method;

/// Numerical fidelity and run control.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Numerics {
    /// Cells along x1 over the domain (0.2 cm for the paper's ring; 2.5 ring widths).
    pub n1: usize,
    /// Cells along x2 over the simulated half texture cell.
    pub n2: usize,
    /// Largest time step (L/U units); the step used divides the texture period exactly.
    pub dt: f64,
    /// Periodic regime reached when the estimated relative distance of the window means of
    /// f and Z from their periodic limits is below this (docs/solver.md, "Periodic regime").
    pub periodic_tol: f64,
    /// Guard: give up (converged = false) after this much simulated time.
    pub t_max: f64,
    /// At least this many averaging windows are simulated.
    pub min_periods: usize,
    /// Film solver.
    #[serde(default)]
    pub solver: Method,
    /// Initial state of the transient.
    #[serde(default)]
    pub start: Start,
    /// Accelerate the approach to the periodic regime: Anderson acceleration of the period
    /// map (docs/solver.md, "Periodic regime"), stopped on the map's residual. Off: every
    /// window is marched plainly and the stopping rule reads the slow modes of the window
    /// means.
    #[serde(default = "yes")]
    pub accelerate: bool,
    /// Coarse approach: reach the periodic regime first on a cheaper mesh and time step
    /// (N2 raised where a pocket would span fewer than 2 cells), then carry the state over to
    /// this mesh and run on to its own periodic regime. The answer is this mesh's (the
    /// periodic regime does not depend on the start); the coarse mesh only takes the ring's
    /// transient. None: off (the plain method, which the tests compare against). Not
    /// serialised when off, so cache keys of runs without it do not carry it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach: Option<Approach>,
    /// Time discretisation of the film (docs/model.md §3). Not serialised when backward
    /// Euler, so cache keys of runs with it do not carry it.
    #[serde(default, skip_serializing_if = "TimeScheme::is_backward_euler")]
    pub scheme: TimeScheme,
    /// Deep pockets (docs/solver.md, "Deep pockets"): a run that reaches its periodic regime
    /// with pockets deeper than [`super::DEEP_POCKET_RATIO`]·C_min goes on from there on this
    /// mesh (more cells across than the run's own) and its step, to that mesh's periodic
    /// regime, and reports its answer. None: off. Not serialised when off, so cache keys of
    /// runs without it do not carry it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deep: Option<Approach>,
    /// How the film sees the gap across a cell (docs/solver.md, "Deep pockets"). Not
    /// serialised when nodal, so cache keys of runs with it do not carry it.
    #[serde(default, skip_serializing_if = "RimModel::is_nodal")]
    pub rim: RimModel,
}

/// The mesh and time step of a coarse approach (see [`Numerics::approach`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Approach {
    pub n1: usize,
    pub n2: usize,
    pub dt: f64,
}

/// How the film's storage term ∂(hθ)/∂t is discretised in time (docs/solver.md, "Time
/// scheme").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimeScheme {
    /// First order ([`TimeScheme::summary`] gives each scheme's storage term).
    #[default]
    BackwardEuler,
    /// Second order, falling back on a backward-Euler step where it cannot take its own.
    Bdf2,
    /// Backward Euler along the Couette characteristics.
    Characteristic,
}

impl TimeScheme {
    /// The scheme's storage term and where it applies (the command line's help shows it).
    pub fn summary(self) -> &'static str {
        match self {
            TimeScheme::BackwardEuler => "First order: (φⁿ⁺¹ − φⁿ)/dt",
            TimeScheme::Bdf2 => {
                "Second order: (3φⁿ⁺¹ − 4φⁿ + φⁿ⁻¹)/(2dt), with a backward-Euler step where the \
                two previous levels are not at hand (a start, a jump, a new mesh) or where the \
                old-level term (4φⁿ − φⁿ⁻¹)/3 would be negative somewhere (a film emptying \
                within a step)"
            }
            TimeScheme::Characteristic => {
                "Backward Euler along the Couette characteristics: (φⁿ⁺¹ − φⁿ(x1 − u·dt/2))/dt, \
                the Couette flux carried by that shift instead of the stencil; exact transport \
                of the cavitated film at dt = 2·dx1/u (the step the tiers take where the \
                texture period is a multiple of 2·dx1), interpolated below it, and rejected \
                above it (docs/solver.md)"
            }
        }
    }

    pub fn is_backward_euler(&self) -> bool {
        *self == TimeScheme::BackwardEuler
    }
}

fn yes() -> bool {
    true
}

/// Where a transient run starts (the periodic regime it reaches does not depend on it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Start {
    /// The paper's initial state ([`Start::summary`] says what each start is).
    Paper,
    /// The untextured force balance.
    #[default]
    Equilibrium,
}

impl Start {
    /// What the start is and why (the command line's help shows it).
    pub fn summary(self) -> &'static str {
        match self {
            Start::Paper => {
                "The paper's initial state (docs/model.md §4): Z = z0, Z' = v0, flooded \
                upstream gap"
            }
            Start::Equilibrium => {
                "The untextured force balance (steady 1D film at its Z, at rest): the texture \
                only perturbs an already balanced ring, so the periodic regime comes sooner"
            }
        }
    }
}

impl Default for Numerics {
    /// The paper's fidelity: 512×32, dt = 4e-4 (docs/model.md §3).
    fn default() -> Self {
        Numerics {
            n1: 512,
            n2: 32,
            dt: 4e-4,
            periodic_tol: 1e-5,
            t_max: 30.0,
            min_periods: 3,
            solver: Method::default(),
            start: Start::default(),
            accelerate: true,
            approach: None,
            scheme: TimeScheme::BackwardEuler,
            deep: None,
            rim: RimModel::Nodal,
        }
    }
}

/// Fewest time steps a texture period may take. Why: a step moves the texture by u·dt, and
/// with a step of a period or more the texture stands still under the ring (the same phase
/// every step) while the run reports a periodic regime several % off. Measured on Case I on
/// 512×8 with BDF2 against dt = 4e-4 (150 steps): 8 steps a period put f̄ 1.5 % and C_min
/// 1.2 % off, 16 steps 0.2 %, 32 steps 0.03 % — at 8 the error is that of a 512×8 mesh, below
/// it the step dominates. The paper study's shortest period (0.005 cm) takes 9 steps at
/// `fast` and 8 at `draft`.
pub const MIN_STEPS_PER_PERIOD: usize = 8;

/// The steps a run takes per texture period of `period` ms at step `dt` (the step is then
/// shortened to divide the period).
pub fn steps_per_period(period: f64, dt: f64) -> f64 {
    ((period / dt) - 1e-9).ceil().max(1.0)
}

/// A number in a message: short (`1e-308`, not 308 digits).
pub fn short(x: f64) -> String {
    crate::model::case::short(x)
}

/// Largest periodic tolerance a run may be given ([`Numerics::check`]).
pub const MAX_PERIODIC_TOL: f64 = 0.1;

/// Most cells across [`Numerics::resolve_pockets`] raises N2 to.
const MAX_RAISED_N2: f64 = 1e5;

/// Periodic tolerance at which a coarse approach hands over to the full mesh: about the
/// coarse mesh's own offset from the full one (512×8 against 512×32: 0.1–0.4 % in f̄ and Z̄),
/// which only the full mesh's periods remove; converging the coarse run much further buys
/// nothing, stopping it much earlier leaves the full mesh part of the transient. Measured
/// (`paper` tier, Case I / Case III / R = 51.2, wall s): from the paper's start 19.6 / 19.7 /
/// 23.0 at 1e-1, 15.9 / 23.2 / 25.6 at 1e-2, 14.7 / 19.1 / 25.2 at 1e-3.
pub const APPROACH_TOL: f64 = 1e-3;

impl Numerics {
    /// The step in which the liner moves one cell, dx1/u, on this mesh for this case
    /// (infinite for a liner at rest).
    pub fn cell_crossing_dt(&self, case: &CaseSpec) -> f64 {
        case.contact().length_cm / self.n1 as f64 / case.u
    }

    /// With the characteristic scheme and a moving liner, the step at which the film content
    /// moves exactly one cell, 2·dx1/u: the scheme's step and its largest.
    pub fn characteristic_dt(&self, case: &CaseSpec) -> Option<f64> {
        (self.scheme == TimeScheme::Characteristic && case.u > 0.0)
            .then(|| 2.0 * self.cell_crossing_dt(case))
    }

    /// With the characteristic scheme, the step is the mesh's: 2·dx1/u (then fitted to
    /// divide the texture period, which only lowers it). A step given explicitly is
    /// checked by [`Self::validate`] instead.
    pub fn fit_characteristic_step(&mut self, case: &CaseSpec) {
        if let Some(dt) = self.characteristic_dt(case) {
            self.dt = dt;
        }
    }

    /// Raises N2 where the pocket would span fewer than `cells` cells across.
    pub fn resolve_pockets(&mut self, case: &CaseSpec, cells: f64) {
        if let Some(t) = &case.texture {
            let half = 0.5 * t.width;
            let need = (cells * half / (2.0 * t.l2) - 1e-9).ceil();
            // Beyond any mesh a run could hold, N2 is left as it is and the check says what
            // the pockets would need (no overflowing count).
            if need.is_finite() && need > self.n2 as f64 && need <= MAX_RAISED_N2 {
                self.n2 = need as usize;
            }
        }
    }

    /// Lowers the time step where it would give fewer than [`MIN_STEPS_PER_PERIOD`] steps a
    /// texture period (a tier's step on a very short period), as [`Self::resolve_pockets`]
    /// raises N2; a step given explicitly is checked by [`Self::validate`] instead.
    pub fn fit_step_to_period(&mut self, case: &CaseSpec) {
        if let Some(t) = &case.texture {
            let period = t.per / case.u;
            if steps_per_period(period, self.dt) < MIN_STEPS_PER_PERIOD as f64 {
                self.dt = period / MIN_STEPS_PER_PERIOD as f64;
            }
        }
    }

    /// Scales N1 (and the coarse approach's) with the domain, which is 2.5 ring widths long,
    /// so that a wider ring keeps the tier's cell size: the tiers' N1 are stated for the
    /// paper's 0.08 cm ring (docs/model.md §2). The paper's width leaves them as they are.
    pub fn fit_mesh_to_ring(&mut self, case: &CaseSpec) {
        let scale = case.ring_width / PAPER_RING_WIDTH;
        if scale == 1.0 {
            return;
        }
        let fit = |n: usize| ((n as f64 * scale - 1e-9).ceil() as usize).max(16);
        self.n1 = fit(self.n1);
        if let Some(a) = self.approach.as_mut() {
            a.n1 = fit(a.n1);
        }
    }

    /// The numerics of the coarse approach to the periodic regime ([`Numerics::approach`]),
    /// if it applies to this case (textured, and a cheaper mesh or step than this one): its
    /// mesh and step, N2 raised where a pocket would span fewer than 2 cells (as for
    /// `draft`); periodic tolerance [`APPROACH_TOL`]; no approach of its own; the direct
    /// solver.
    pub fn approach_numerics(&self, case: &CaseSpec) -> Option<Numerics> {
        case.texture.as_ref()?;
        let a = self.approach?;
        let mut coarse = Numerics {
            n1: a.n1.min(self.n1),
            n2: a.n2.min(self.n2),
            dt: a.dt.max(self.dt),
            periodic_tol: APPROACH_TOL.max(self.periodic_tol),
            approach: None,
            deep: None,
            solver: Method::Direct,
            ..self.clone()
        };
        coarse.resolve_pockets(case, 2.0);
        if let Some(dt) = coarse.characteristic_dt(case) {
            coarse.dt = coarse.dt.min(dt);
        }
        let cheaper = coarse.n1 < self.n1 || coarse.n2 < self.n2 || coarse.dt > self.dt;
        // The approach is exempt from the steps a period: it only carries the ring's transient
        // to the run's mesh, and its answer is not read (the paper study's 0.005 cm periods
        // take 4 of its steps).
        let valid = coarse.check(case, false).is_ok();
        (cheaper && coarse.n2 <= self.n2 && valid).then_some(coarse)
    }

    /// The numerics a run on these goes on with where its pockets end deeper than the mesh
    /// resolves ([`Numerics::deep`]): that mesh (N1 scaled with the ring as the run's own)
    /// and step (the characteristic one where the scheme is), the rest the run's. None
    /// without a texture, or where that mesh has no more cells across than the run's.
    pub fn deep_numerics(&self, case: &CaseSpec) -> Option<Numerics> {
        case.texture.as_ref()?;
        let d = self.deep?;
        let mut deep = Numerics {
            n1: d.n1,
            n2: d.n2,
            dt: d.dt,
            approach: None,
            deep: None,
            ..self.clone()
        };
        deep.fit_mesh_to_ring(case);
        deep.fit_characteristic_step(case);
        deep.fit_step_to_period(case);
        let valid = deep.validate(case).is_ok();
        (deep.n2 > self.n2 && valid).then_some(deep)
    }

    /// Checks the numerics against the case (cells across pockets, time step, guards).
    /// Errors name the field (`mesh` for n1 and n2).
    pub fn validate(&self, case: &CaseSpec) -> Result<(), InputError> {
        self.check(case, true)
    }

    /// [`Self::validate`], with the steps-per-period rule or without it.
    fn check(&self, case: &CaseSpec, steps_rule: bool) -> Result<(), InputError> {
        if self.n1 < 16 {
            return Err(bad(
                "mesh",
                format!("{}x{}", self.n1, self.n2),
                "needs at least 16 cells along x1",
            ));
        }
        if self.n2 < 1 {
            return Err(bad(
                "mesh",
                format!("{}x{}", self.n1, self.n2),
                "needs at least 1 cell along x2",
            ));
        }
        if let Some(a) = self.approach {
            if a.n1 < 16 || a.n2 < 1 || !(a.dt > 0.0 && a.dt.is_finite()) {
                return Err(bad(
                    "approach",
                    format!("{}x{}@{}", a.n1, a.n2, a.dt),
                    "needs at least 16 cells along x1, 1 along x2 and a time step > 0 \
                     (or none for no coarse approach)",
                ));
            }
        }
        // An x2 face takes half of each row's samples (docs/model.md §3).
        let samples = self.rim.samples();
        if !self.rim.is_nodal() && (samples % 2 == 1 || !(2..=64).contains(&samples)) {
            return Err(bad(
                "rim samples",
                samples,
                "must be an even number from 2 to 64 (the samples across a cell)",
            ));
        }
        positive("dt", self.dt)?;
        positive("periodic_tol", self.periodic_tol)?;
        // A relative distance from the periodic regime; beyond 10 % a run would stop in its
        // transient and report that as its answer.
        if self.periodic_tol > MAX_PERIODIC_TOL {
            return Err(bad(
                "periodic_tol",
                self.periodic_tol,
                format!(
                    "is a relative distance from the periodic regime and must be at most {MAX_PERIODIC_TOL} (the tiers use 1e-3 to 1e-5)"
                ),
            ));
        }
        positive("t_max", self.t_max)?;
        if let Some(t) = &case.texture {
            self.check_texture(case, t, steps_rule)?;
        }
        if let Some(limit) = self.characteristic_dt(case) {
            if self.dt > limit * MAX_COURANT {
                return Err(bad(
                    "dt",
                    self.dt,
                    format!(
                        "moves the film more than one cell a step along the characteristics (u·dt/2 > dx1 on {} cells): dt ≤ 2·dx1/u = {} with this mesh, or more cells along x1",
                        self.n1,
                        short(limit)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The time steps a texture period needs (with `steps_rule`) and the cells a pocket's
    /// axes need, for the case's texture `t`.
    fn check_texture(
        &self,
        case: &CaseSpec,
        t: &Texture,
        steps_rule: bool,
    ) -> Result<(), InputError> {
        let period = t.per / case.u;
        let steps = steps_per_period(period, self.dt);
        if steps_rule && steps < MIN_STEPS_PER_PERIOD as f64 {
            return Err(bad(
                "dt",
                self.dt,
                format!(
                    "gives only {steps} time steps per texture period (per/u = {} ms), where at least {MIN_STEPS_PER_PERIOD} are needed: dt ≤ {}",
                    short(period),
                    short(period / MIN_STEPS_PER_PERIOD as f64)
                ),
            ));
        }
        let length = case.contact().length_cm;
        // (axis, semiaxis, cell size, extent the cells divide, name of the count)
        let axes = [
            ("l1", t.l1, length / self.n1 as f64, length, "N1"),
            (
                "l2",
                t.l2,
                0.5 * t.width / self.n2 as f64,
                0.5 * t.width,
                "N2",
            ),
        ];
        for (axis, l, d, extent, count) in axes {
            if 2.0 * l < 2.0 * d * (1.0 - 1e-12) {
                return Err(bad(
                    "mesh",
                    format!("{}x{}", self.n1, self.n2),
                    format!(
                        "puts {} cells across the pocket axis 2·{axis} = {} cm (need ≥ 2); raise {count} to at least {}",
                        short(2.0 * l / d),
                        short(2.0 * l),
                        short((extent / l).ceil())
                    ),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::case::Texture;
    use crate::time::Fidelity;

    #[test]
    fn a_rim_model_takes_an_even_number_of_samples() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 20.0));
        let with = |rim| Numerics {
            rim,
            ..Numerics::default()
        };
        assert!(with(RimModel::Nodal).validate(&case).is_ok());
        assert!(with(RimModel::Strips { samples: 8 })
            .validate(&case)
            .is_ok());
        for samples in [0, 1, 3, 66] {
            let e = with(RimModel::Strips { samples })
                .validate(&case)
                .unwrap_err();
            assert!(e.to_string().contains("rim samples"), "{e}");
        }
    }

    #[test]
    fn a_wider_ring_keeps_the_tiers_cell_size() {
        let paper = CaseSpec::paper(5.0).with_texture(Texture::circular(0.03, 0.06, 10.0));
        let wide = CaseSpec {
            ring_width: 0.12,
            ..paper.clone()
        };
        for f in [Fidelity::Draft, Fidelity::Fast, Fidelity::Fine] {
            let (a, b) = (f.numerics_for(&paper), f.numerics_for(&wide));
            let (la, lb) = (paper.contact().length_cm, wide.contact().length_cm);
            assert_eq!(la, 0.2);
            assert!((lb - 0.3).abs() < 1e-12);
            let (dxa, dxb) = (la / a.n1 as f64, lb / b.n1 as f64);
            assert!(
                dxb <= dxa * (1.0 + 1e-12) && dxb > 0.99 * dxa,
                "{f:?}: {dxa} vs {dxb}"
            );
            let (ca, cb) = (a.approach.unwrap(), b.approach.unwrap());
            assert!(lb / cb.n1 as f64 <= la / ca.n1 as f64 * (1.0 + 1e-12));
        }
        let (a, b) = wide.contact().ring_edges();
        assert!(
            (a - 0.09).abs() < 1e-12 && (b - 0.21).abs() < 1e-12,
            "{a} {b}"
        );
    }

    #[test]
    fn the_coarse_approach_runs_on_the_direct_solver_on_its_own_mesh() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        for solver in [Method::Direct, Method::Reference] {
            let num = Numerics {
                solver,
                ..Fidelity::Paper.numerics_for(&case)
            };
            let a = num.approach.expect("the paper tier approaches");
            let coarse = num
                .approach_numerics(&case)
                .expect("the paper tier approaches this case");
            assert_eq!(coarse.solver, Method::Direct);
            assert_eq!((coarse.n1, coarse.n2, coarse.dt), (a.n1, a.n2, a.dt));
            assert_eq!(coarse.approach, None);
        }
    }

    #[test]
    fn a_short_period_keeps_its_coarse_approach() {
        // 0.005 cm periods take 2 steps of the approach's 3.3e-3 (fewer than a run may take):
        // the approach is exempt, the run's own step is not.
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.0025, 0.005, 5.0));
        let num = Fidelity::Fast.numerics_for(&case);
        assert!(num.validate(&case).is_ok());
        let coarse = num.approach_numerics(&case).expect("an approach");
        let coarse_step = Numerics {
            dt: coarse.dt,
            ..num
        };
        let e = coarse_step.validate(&case).unwrap_err().to_string();
        assert!(e.contains("time steps per texture period"), "{e}");
    }

    #[test]
    fn no_coarse_approach_where_it_would_not_be_cheaper() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        let num = Numerics {
            approach: Some(Approach {
                n1: 1024,
                n2: 64,
                dt: 1e-4,
            }),
            ..Numerics::default()
        };
        // Never finer than the run itself: clipped to its mesh and step, which is no approach.
        assert_eq!(num.approach_numerics(&case), None);
        // Nor for an untextured liner (its steady balance needs none).
        let coarse = Numerics {
            approach: Some(Approach {
                n1: 128,
                n2: 4,
                dt: 1.6e-3,
            }),
            ..Numerics::default()
        };
        assert_eq!(coarse.approach_numerics(&CaseSpec::paper(3.2)), None);
    }

    #[test]
    fn deep_pockets_go_on_on_more_rows_at_the_mesh_s_characteristic_step() {
        let deep = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 20.0));
        let num = Fidelity::Fast.numerics_for(&deep);
        let d = num
            .deep_numerics(&deep)
            .expect("fast resolves deep pockets");
        assert_eq!((d.n1, d.n2), (600, 24));
        assert_eq!(d.dt, 2.0 * 0.2 / 600.0);
        assert_eq!((d.approach, d.deep), (None, None));
        assert_eq!(d.periodic_tol, num.periodic_tol);
        // A wider ring scales N1 as the run's own mesh.
        let wide = CaseSpec {
            ring_width: 2.0 * deep.ring_width,
            ..deep.clone()
        };
        let w = Fidelity::Fast.numerics_for(&wide);
        assert_eq!(
            w.deep_numerics(&wide).map(|d| (d.n1, d.n2)),
            Some((1200, 24))
        );
        // None for an untextured liner, for a run already as fine across, or for a tier
        // without it.
        assert_eq!(num.deep_numerics(&CaseSpec::paper(3.2)), None);
        let across = Numerics { n2: 24, ..num };
        assert_eq!(across.deep_numerics(&deep), None);
        assert_eq!(
            Fidelity::Draft.numerics_for(&deep).deep_numerics(&deep),
            None
        );
    }
}
