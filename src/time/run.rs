//! A run: a case brought to its periodic regime (docs/model.md §6), or, for an untextured
//! liner, the steady 1D force balance. The loop steps window by window and asks its named
//! parts after each: the stopping rule ([`super::stop`], the periodic regime of
//! [`super::periodic`]), the accelerator ([`super::anderson`]), the BDF2 fall-back
//! ([`super::fallback`]) and the observers ([`super::common::Observers`]).

use std::time::Instant;

use super::anderson::Anderson;
use super::approach::start_transient;
use super::common::{Progress, SolveError};
use super::fallback::Bdf2Fallback;
use super::fidelity::unresolved_depth;
use super::numerics::Numerics;
use super::outcome::{Outcome, RunResult, SeriesRow};
use super::periodic::{oil_imbalance, PeriodicRegime};
use super::stats::ApproachDone;
use super::steady::steady_outcome;
use super::stop::StopRule;
use super::transient::{Transient, Watch};
use super::uncertainty::{needs_uncertainty, Coarse, MeshUncertainty};
use super::window::{window_periods, PeriodMeans};
use crate::model::case::CaseSpec;
use crate::solve::FilmMethod;

/// What a run records beside its outcome, and with which film solver.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Record the time series (every step, a coarse approach's included).
    pub series: bool,
    /// Further shear thresholds θ_s to report outcomes for (θ_s enters only the Couette
    /// term, docs/model.md §5: the film and the ring are simulated once).
    pub extra_theta_s: Vec<f64>,
    /// Run an untextured liner as a 2D transient too (by default it is the steady 1D
    /// balance).
    pub transient: bool,
    /// The film solver of the run's own mesh (a coarse approach runs the direct one), when
    /// not the numerics' method: how the lab crate runs its solvers.
    pub solver: Option<fn() -> Box<dyn FilmMethod>>,
}

/// One evaluation: an untextured liner is solved as the steady 1D force balance on n1
/// cells; a textured one by the 2D transient to the periodic regime.
pub fn simulate(case: &CaseSpec, num: &Numerics) -> Result<RunResult, SolveError> {
    simulate_with(case, num, &RunOptions::default(), &mut Watch::default())
}

/// As [`simulate`], with the options and observers given.
pub fn simulate_with(
    case: &CaseSpec,
    num: &Numerics,
    opts: &RunOptions,
    watch: &mut Watch,
) -> Result<RunResult, SolveError> {
    if case.texture.is_none() && !opts.transient {
        let mut r = steady_outcome(case, num.n1)?;
        for &theta_s in &opts.extra_theta_s {
            let other = CaseSpec {
                theta_s,
                ..case.clone()
            };
            r.extra
                .push((theta_s, steady_outcome(&other, num.n1)?.outcome));
        }
        return Ok(r);
    }
    let mut series = opts.series.then(Vec::new);
    let mut t = start_transient(case, num, opts.solver, series.as_mut(), watch)?;
    t.set_extra_theta_s(&opts.extra_theta_s);
    let mut r = t.run_to_periodic(num, opts.series, watch)?;
    if let Some(deep) = deep_continuation(case, num, &r) {
        if let (Some(all), Some(rows)) = (series.as_mut(), r.series.take()) {
            all.extend(rows);
        }
        go_on_deep(&t, deep, num, opts, watch, &mut r);
    }
    if let (Some(mut all), Some(rows)) = (series, r.series.take()) {
        all.extend(rows);
        r.series = Some(all);
    }
    if r.outcome.mesh_uncertainty.is_none() {
        measure_uncertainty(&t, num, num, opts, &mut r);
    }
    Ok(r)
}

/// The numerics a run goes on with, on a mesh with more cells across, when it reached its
/// periodic regime with pockets deeper than its mesh resolves ([`Numerics::deep`]).
fn deep_continuation(case: &CaseSpec, num: &Numerics, r: &RunResult) -> Option<Numerics> {
    let depth = case.texture.as_ref()?.depth;
    let deep = num.deep_numerics(case)?;
    (r.outcome.converged && unresolved_depth(depth, r.outcome.c_min)).then_some(deep)
}

/// Goes on from the end of `r`'s run `t` on the deep-pocket mesh `deep` to that mesh's
/// periodic regime, whose answer then replaces `r`'s. Where that mesh does not reach its
/// periodic regime within its allowance (half the run's), or fails, `r` keeps the run's own
/// answer and says so (`deep_unsettled`): a starved film on R = 5 (d_oil = 1 µm, S = 5.6e-3)
/// settles on 700×8 and wanders on 600×24 for as long again.
fn go_on_deep(
    t: &Transient,
    deep: Numerics,
    num: &Numerics,
    opts: &RunOptions,
    watch: &mut Watch,
    r: &mut RunResult,
) {
    let began = Instant::now();
    let solver = opts.solver.map_or_else(|| deep.solver.solver(), |f| f());
    let mut d = t.refined(&deep, ApproachDone::of(&r.outcome), solver);
    let deep = Numerics {
        t_max: d.t() + 0.5 * num.t_max,
        ..deep
    };
    d.set_extra_theta_s(&opts.extra_theta_s);
    match d.run_to_periodic(&deep, opts.series, watch) {
        Ok(mut rd) if rd.outcome.converged => {
            let mesh = Some((deep.n1, deep.n2));
            rd.outcome.deep_mesh = mesh;
            for (_, o) in rd.extra.iter_mut() {
                o.deep_mesh = mesh;
            }
            *r = rd;
            measure_uncertainty(&d, &deep, num, opts, r);
        }
        _ => {
            // The attempt's time counts.
            r.outcome.wall_time_s += began.elapsed().as_secs_f64();
            r.outcome.deep_unsettled = true;
            for (_, o) in r.extra.iter_mut() {
                o.deep_unsettled = true;
            }
        }
    }
}

/// Gives the answer `r` of the run `t` on `answer` (its own numerics, or the deep-pocket
/// mesh's) its mesh uncertainty where its pockets end deeper than the tiers resolve
/// ([`MeshUncertainty`]): the answer's mesh coarsened uniformly, run on from the answer's
/// periodic regime. An answer that did not reach its periodic regime gets none measured.
fn measure_uncertainty(
    t: &Transient,
    answer: &Numerics,
    num: &Numerics,
    opts: &RunOptions,
    r: &mut RunResult,
) {
    if !needs_uncertainty(t.case(), r.outcome.c_min) {
        return;
    }
    let began = Instant::now();
    let coarse = if r.outcome.converged {
        coarsened(t, answer, ApproachDone::of(&r.outcome), num, opts)
    } else {
        None
    };
    let answer_of = |o: Option<&Outcome>, mesh: (usize, usize)| {
        o.map(|o| Coarse {
            n1: mesh.0,
            n2: mesh.1,
            f_mean: o.f_mean,
            c_min: o.c_min,
        })
    };
    let mesh = coarse.as_ref().map(|(_, m)| *m).unwrap_or_default();
    let main = answer_of(coarse.as_ref().map(|(c, _)| &c.outcome), mesh);
    r.outcome.mesh_uncertainty = Some(Box::new(MeshUncertainty::of(
        (r.outcome.f_mean, r.outcome.c_min),
        main,
    )));
    for (k, (_, o)) in r.extra.iter_mut().enumerate() {
        let theirs = coarse
            .as_ref()
            .and_then(|(c, _)| c.extra.get(k))
            .map(|(_, o)| o);
        o.mesh_uncertainty = Some(Box::new(MeshUncertainty::of(
            (o.f_mean, o.c_min),
            answer_of(theirs, mesh),
        )));
    }
    r.outcome.wall_time_s += began.elapsed().as_secs_f64();
}

/// Periodic tolerance of the coarsened run: it measures changes of a per cent and more
/// (below [`super::UNCERTAINTY_FLOOR`] they are not read), which a tenth of a per cent
/// resolves.
const COARSE_TOL: f64 = 1e-3;

/// The run `t`, settled on `answer`'s mesh, carried on to that mesh coarsened uniformly (N1
/// and N2 halved, the step doubled, or the characteristic step of the coarser cells) and run
/// to its periodic regime there (within half the run's allowance): its result and mesh. None
/// where that mesh is not valid for the case, or the run fails or does not settle. Its steps
/// are watched by no one and keep no series: they measure, the answer stays `answer`'s.
fn coarsened(
    t: &Transient,
    answer: &Numerics,
    done: ApproachDone,
    num: &Numerics,
    opts: &RunOptions,
) -> Option<(RunResult, (usize, usize))> {
    let case = t.case();
    let mut n = Numerics {
        n1: answer.n1 / 2,
        n2: answer.n2 / 2,
        dt: 2.0 * answer.dt,
        approach: None,
        deep: None,
        ..answer.clone()
    };
    n.fit_characteristic_step(case);
    n.fit_step_to_period(case);
    n.validate(case).ok()?;
    let solver = opts.solver.map_or_else(|| n.solver.solver(), |f| f());
    let mut c = t.refined(&n, done, solver);
    c.set_extra_theta_s(&opts.extra_theta_s);
    let n = Numerics {
        t_max: c.t() + 0.5 * num.t_max,
        periodic_tol: COARSE_TOL.max(n.periodic_tol),
        ..n
    };
    let r = c
        .run_to_periodic(&n, false, &mut Watch::default())
        .ok()
        .filter(|r| r.outcome.converged)?;
    Some((r, (n.n1, n.n2)))
}

impl Transient {
    /// Runs window by window until the periodic regime is detected or t_max is reached.
    pub fn run_to_periodic(
        &mut self,
        num: &Numerics,
        record_series: bool,
        watch: &mut Watch,
    ) -> Result<RunResult, SolveError> {
        let mut rule = PeriodicRegime::new(num, self.operating_point().w_ps);
        self.run_until(&mut rule, num, record_series, watch)
    }

    /// Runs window by window until `rule` says the run is there or t_max is reached. After
    /// each window the accelerator (when `num.accelerate`) may move the state, the rule reads
    /// the distance, the observers see it, and the BDF2 fall-back may change the scheme.
    pub(crate) fn run_until(
        &mut self,
        rule: &mut impl StopRule,
        num: &Numerics,
        record_series: bool,
        watch: &mut Watch,
    ) -> Result<RunResult, SolveError> {
        let start = Instant::now();
        let mut series = record_series.then(Vec::new);
        let wp = self.window_periods();
        let window = self.dt() * (self.steps_per_period() * wp) as f64;
        let mut anderson = num.accelerate.then(|| Anderson::new(window));
        let mut fallback = Bdf2Fallback::default();
        let (converged, distance) = loop {
            if let Some(a) = anderson.as_mut() {
                a.before_window(self);
            }
            rule.push(self.advance_window(wp, series.as_mut(), watch)?);
            let imbalance = oil_imbalance(rule.last());
            let residual = anderson.as_mut().map(|a| a.after_window(self, imbalance));
            let d = rule.distance(residual);
            watch.window(&self.progress(rule, wp, d.total));
            if rule.reached(d.total) {
                break (true, d.total);
            }
            if fallback.after_window(d.motion, self.scheme()) {
                // A new map: its windows and the acceleration's pairs start afresh.
                self.fall_back_to_backward_euler();
                rule.restart();
                anderson = num.accelerate.then(|| Anderson::new(window));
            }
            if self.t() + 1e-12 >= num.t_max {
                break (false, d.total);
            }
        };
        let periods = self.stats().approach.periods + rule.windows() * wp;
        let last = rule.last();
        let outcome = self.outcome(last, periods, converged, distance, start);
        let extra = self
            .extra_theta_s()
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

    /// The progress after a window of `wp` texture periods at distance `distance`.
    fn progress(&self, rule: &impl StopRule, wp: usize, distance: f64) -> Progress {
        let last = rule.last();
        Progress {
            period: self.stats().approach.periods + rule.windows() * wp,
            t: self.t(),
            f_mean: last.friction.total(),
            z_mean: last.z_mean,
            periodic_error: distance,
        }
    }

    /// Texture periods per averaging window (see [`window_periods`]).
    pub fn window_periods(&self) -> usize {
        window_periods(self.dt() * self.steps_per_period() as f64)
    }

    /// Steps through one averaging window of `wp` texture periods: the window's means, the
    /// oil held at its end and the oil through the domain in it.
    fn advance_window(
        &mut self,
        wp: usize,
        mut series: Option<&mut Vec<SeriesRow>>,
        watch: &mut Watch,
    ) -> Result<PeriodMeans, SolveError> {
        let n = self.steps_per_period() * wp;
        let mut acc = PeriodMeans::empty();
        let start_content = self.oil_held().0;
        for _ in 0..n {
            self.step()?;
            watch.step(self);
            let row = self.row();
            acc.add(&row, self.friction(), self.extra_friction());
            if let Some(s) = series.as_mut() {
                s.push(row);
            }
        }
        let (content, flow) = self.oil_held();
        Ok(PeriodMeans {
            start_content,
            content,
            throughput: flow * n as f64 * self.dt(),
            ..acc.finish(n)
        })
    }

    /// The outcome of the last window `last`.
    fn outcome(
        &self,
        last: &PeriodMeans,
        periods: usize,
        converged: bool,
        periodic_error: f64,
        start: Instant,
    ) -> Outcome {
        let stats = self.stats();
        let approach = stats.approach;
        Outcome {
            f_mean: last.friction.total(),
            f_couette: last.friction.couette,
            f_poiseuille: last.friction.poiseuille,
            f_pressure: last.friction.pressure,
            f_boundary: last.friction.boundary,
            asperity_share: last.w_a / self.operating_point().w_ps,
            z_mean: last.z_mean,
            z_min: last.z_min,
            z_max: last.z_max,
            c_min: self.scene().contact.clearance_um(last.z_min),
            periods,
            // The steps on this mesh and those of a coarse approach before it (this run's
            // count starts at the texture period the approach ended on).
            steps: self.steps() + approach.steps - approach.periods * self.steps_per_period(),
            converged,
            periodic_error,
            method: "transient-2d".into(),
            dt: self.dt(),
            t_end: self.t(),
            iterations_per_step: stats.iterations as f64 / self.steps().max(1) as f64,
            max_residual: stats.max_residual,
            wall_time_s: approach.wall_time_s + start.elapsed().as_secs_f64(),
            approach_steps: approach.steps,
            scheme: self.scheme(),
            deep_mesh: None,
            deep_unsettled: false,
            mesh_uncertainty: None,
        }
    }
}
