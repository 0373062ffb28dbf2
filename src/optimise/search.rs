//! The search layer every optimisation runs on: its settings, the evaluation service
//! (designs → study jobs → cache), what a search minimises (an [`Objective`], over which the
//! argmin cost function is written once), a particle swarm, and a compass search polishing
//! its best point. The simulator knows nothing of this: every evaluation is a study job.

use argmin::core::{
    CostFunction, Error as ArgminError, Executor, IterState, Problem, Solver, State,
    TerminationReason, TerminationStatus, KV,
};
use argmin::solver::particleswarm::ParticleSwarm;
use rand::SeedableRng;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use super::error::OptimiseError;
use super::goal::{Goal, FAILED_COST};
use super::space::Space;
use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::{Scales, Validity};
use crate::study::cache::Cache;
use crate::study::sweep::{self, CaseFailure};
use crate::study::Job;
use crate::time::Overrides;
use crate::time::{simulate_with, Fidelity, Limits, Outcome, RunOptions, SeriesRow, Watch};

/// One evaluated design.
#[derive(Clone, Debug, Serialize)]
pub struct Evaluation {
    pub texture: Texture,
    pub fidelity: Fidelity,
    pub outcome: sweep::CaseEvaluation,
}

/// Study jobs through the cache, in parallel: the sweep's summary and each job's evaluation
/// (not run where the sweep stopped first: the summary says it stopped). The one path from
/// jobs to evaluations of every search, one operating point ([`Evaluator`]) or many (the
/// angles of a cycle).
pub fn run_jobs(
    jobs: &[Job],
    cache: &Mutex<Cache>,
    options: &sweep::Options,
    stop: &AtomicBool,
) -> Result<(sweep::Summary, Vec<sweep::CaseEvaluation>), OptimiseError> {
    let (sum, results) = sweep::run(jobs, cache, options, stop).map_err(OptimiseError::Cache)?;
    let out = results
        .into_iter()
        .map(|r| r.unwrap_or(Err(CaseFailure::NotRun)))
        .collect();
    Ok((sum, out))
}

/// The evaluation service shared by every search: designs → jobs → cache/simulation.
pub struct Evaluator<'a> {
    pub base: CaseSpec,
    /// The scales of the base's operating point (for the reports in physical units).
    pub scales: Scales,
    pub fidelity: Fidelity,
    pub overrides: Overrides,
    pub cache: &'a Mutex<Cache>,
    pub options: sweep::Options,
    pub stop: &'a AtomicBool,
    /// Every design evaluated, in order.
    pub log: Mutex<Vec<Evaluation>>,
    /// Simulations run (not answered by the cache).
    pub simulations: Mutex<usize>,
    /// Print a line per batch on stderr, headed by `name` (the search's, when several run
    /// at once; empty: none).
    pub progress: bool,
    pub name: String,
}

impl Evaluator<'_> {
    pub fn job(&self, t: Option<&Texture>) -> Job {
        let case = CaseSpec {
            texture: t.cloned(),
            ..self.base.clone()
        };
        let numerics = crate::time::resolve(self.fidelity, &self.overrides, &case);
        Job {
            case,
            numerics,
            scales: self.scales,
        }
    }

    /// Evaluates the designs (None: the plain liner) in parallel through the cache.
    pub fn evaluate(
        &self,
        designs: &[Option<Texture>],
    ) -> Result<Vec<sweep::CaseEvaluation>, OptimiseError> {
        let jobs: Vec<Job> = designs.iter().map(|t| self.job(t.as_ref())).collect();
        for j in &jobs {
            j.numerics
                .validate(&j.case)
                .map_err(|error| OptimiseError::Numerics {
                    case: j.case.label(),
                    error,
                })?;
        }
        let (sum, out) = run_jobs(&jobs, self.cache, &self.options, self.stop)?;
        let total_sims = {
            let mut n = self.simulations.lock().expect("lock");
            *n += sum.simulations;
            *n
        };
        if self.progress {
            eprintln!(
                "  {}{} designs at {}: {} from the cache, {} simulated ({:.1} s); {total_sims} simulations so far",
                self.name,
                designs.len(),
                self.fidelity.name(),
                sum.cached,
                sum.simulations,
                sum.wall_time_s
            );
        }
        if sum.stopped {
            return Err(OptimiseError::Stopped);
        }
        let mut log = self.log.lock().expect("lock");
        for (t, o) in designs.iter().zip(&out) {
            if let Some(t) = t {
                log.push(Evaluation {
                    texture: t.clone(),
                    fidelity: self.fidelity,
                    outcome: o.clone(),
                });
            }
        }
        Ok(out)
    }

    /// The plain liner's outcome.
    pub fn plain(&self) -> Result<Outcome, OptimiseError> {
        self.evaluate(&[None])?
            .remove(0)
            .map_err(OptimiseError::PlainFailed)
    }

    /// The time series of the last `period` of a design's run, under the same limits and
    /// stop flag as its evaluation. The cache keeps outcomes, not series: the series is kept
    /// in `path` with the case's cache key, so that a warm rerun does not simulate it again.
    pub fn last_period(
        &self,
        t: &Texture,
        period: f64,
        path: &Path,
    ) -> Result<Vec<SeriesRow>, OptimiseError> {
        #[derive(Serialize, serde::Deserialize)]
        struct Kept {
            key: String,
            rows: Vec<SeriesRow>,
        }
        let Job { case, numerics, .. } = self.job(Some(t));
        let key = crate::study::cache::Key::of(&case, &numerics).hash;
        if let Some(text) = crate::output::read_regular(path) {
            if let Ok(k) = serde_json::from_str::<Kept>(&text) {
                if k.key == key {
                    return Ok(k.rows);
                }
            }
        }
        crate::time::limits::check(&case, &numerics, &self.options.limits).map_err(|error| {
            OptimiseError::Numerics {
                case: case.label(),
                error,
            }
        })?;
        if self.stop.load(Ordering::SeqCst) {
            return Err(OptimiseError::Stopped);
        }
        let opts = RunOptions {
            series: true,
            ..RunOptions::default()
        };
        let res = simulate_with(&case, &numerics, &opts, &mut Watch::default())
            .map_err(OptimiseError::Run)?;
        let rows: Vec<SeriesRow> = res.series.unwrap_or_default();
        let t_end = rows.last().map_or(0.0, |x| x.t);
        let rows: Vec<SeriesRow> = rows
            .into_iter()
            .filter(|x| x.t > t_end - period - 1e-12)
            .collect();
        let kept = Kept { key, rows };
        let json = serde_json::to_string(&kept).map_err(|source| OptimiseError::JsonAt {
            path: path.to_path_buf(),
            source,
        })?;
        crate::output::write(path, json)?;
        Ok(kept.rows)
    }
}

/// The swarm settings, fidelities, numerics, threads, limits and files every search shares:
/// `optimise` for one ring or a range of them, and `cycle`.
#[derive(Clone, Debug)]
pub struct SearchSettings {
    pub space: Space,
    /// Where the film model stops.
    pub validity: Validity,
    /// Fidelity of the searches, and of the reported (confirmed) designs.
    pub search_fidelity: Fidelity,
    pub report_fidelity: Fidelity,
    /// Mesh/time-step overrides for both (coarse meshes for quick looks).
    pub overrides: Overrides,
    pub swarm: SwarmSettings,
    /// Worker threads.
    pub jobs: usize,
    /// What one evaluation may cost (a design over them fails unrun).
    pub limits: Limits,
    pub progress: bool,
    /// Output directory; None: write nothing.
    pub out_dir: Option<PathBuf>,
}

impl SearchSettings {
    /// The defaults: searches at draft (within 2 % of the converged answer on the benchmark
    /// cases), designs reported at fast.
    pub const SEARCH_FIDELITY: Fidelity = Fidelity::Draft;
    pub const REPORT_FIDELITY: Fidelity = Fidelity::Fast;

    /// A progress line on stderr, stamped with the seconds since `t0`, where progress is
    /// asked for.
    pub fn say_since(&self, t0: std::time::Instant) -> impl Fn(String) + '_ {
        move |m| {
            if self.progress {
                eprintln!("[{:6.1} s] {m}", t0.elapsed().as_secs_f64());
            }
        }
    }

    /// Threads by default: every core.
    pub fn default_jobs() -> usize {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    }

    /// The sweep options of one evaluation batch.
    pub fn sweep_options(&self) -> sweep::Options {
        sweep::Options {
            jobs: self.jobs,
            retry_failed: false,
            progress: false,
            limits: self.limits,
        }
    }
}

/// Particle-swarm settings of one search.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SwarmSettings {
    pub particles: usize,
    pub iterations: u64,
    pub seed: u64,
}

impl SwarmSettings {
    pub const DEFAULT: SwarmSettings = SwarmSettings {
        particles: 8,
        iterations: 3,
        seed: 1,
    };
}

/// What a texture search minimises over the unit cube of its design space: the costs of a
/// batch of textures (a batch, so that the evaluations run in parallel). Every texture search
/// is one of these, and through it a [`CubeObjective`].
pub trait Objective: Sync {
    fn space(&self) -> &Space;
    fn costs(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError>;
}

/// What any search minimises over a unit cube: its dimension, the design at a point, and the
/// costs of a batch of designs. The argmin cost function over them is [`Cost`]; a texture
/// search is one through its [`Space`], a banded liner's through its band space.
pub trait CubeObjective: Sync {
    type Design: Clone + Send + Sync;
    fn dim(&self) -> usize;
    fn decode(&self, u: &[f64]) -> Self::Design;
    fn costs_of(&self, designs: &[Self::Design]) -> Result<Vec<f64>, OptimiseError>;
}

impl<O: Objective + ?Sized> CubeObjective for O {
    type Design = Texture;

    fn dim(&self) -> usize {
        self.space().dim()
    }

    fn decode(&self, u: &[f64]) -> Texture {
        self.space().decode(u)
    }

    fn costs_of(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        self.costs(designs)
    }
}

/// The argmin cost function of a [`CubeObjective`]: unit-cube points decoded into designs.
pub struct Cost<'a, O: ?Sized>(pub &'a O);

impl<O: CubeObjective + ?Sized> CostFunction for Cost<'_, O> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.bulk_cost(std::slice::from_ref(u))?[0])
    }

    /// The swarm's whole population at once, so the sweep runs it in parallel.
    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<f64>, ArgminError>
    where
        P: std::borrow::Borrow<Vec<f64>> + argmin::core::SyncAlias,
    {
        let designs: Vec<O::Design> = params.iter().map(|u| self.0.decode(u.borrow())).collect();
        Ok(self.0.costs_of(&designs)?)
    }
}

/// An argmin run's error as ours: an objective's own error comes back as it was.
fn solver_error(e: ArgminError) -> OptimiseError {
    e.downcast::<OptimiseError>()
        .unwrap_or_else(OptimiseError::Solver)
}

/// One ring's search: minimise `goal` relative to the plain liner's outcome.
pub struct GoalSearch<'a> {
    pub space: &'a Space,
    pub eval: &'a Evaluator<'a>,
    pub goal: Goal,
    pub plain: Outcome,
}

impl Objective for GoalSearch<'_> {
    fn space(&self) -> &Space {
        self.space
    }

    fn costs(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        let designs: Vec<Option<Texture>> = designs.iter().cloned().map(Some).collect();
        Ok(self
            .eval
            .evaluate(&designs)?
            .iter()
            .map(|o| match o {
                Ok(o) => self.goal.cost(o, &self.plain),
                Err(_) => FAILED_COST,
            })
            .collect())
    }
}

/// A particle swarm over the unit cube of `problem`'s space; returns the best point and its
/// cost.
pub fn swarm<O: CubeObjective + ?Sized>(
    problem: &O,
    settings: SwarmSettings,
) -> Result<(Vec<f64>, f64), OptimiseError> {
    let n = problem.dim();
    let solver = ParticleSwarm::new((vec![0.0; n], vec![1.0; n]), settings.particles)
        .with_rng_generator(rand::rngs::StdRng::seed_from_u64(settings.seed));
    let res = Executor::new(Cost(problem), solver)
        .configure(|st| st.max_iters(settings.iterations))
        .run()
        .map_err(solver_error)?;
    let best = res
        .state()
        .get_best_param()
        .map(|p| p.position.clone())
        .ok_or(OptimiseError::NoBest("search"))?;
    Ok((best, res.state().get_best_cost()))
}

/// Every search: a particle swarm, the best of its answer and the `starts` (points worth
/// trying, e.g. other searches' optima), polished by a compass search; returns the point and
/// its cost.
pub fn swarm_and_refine<O: CubeObjective + ?Sized>(
    problem: &O,
    settings: SwarmSettings,
    starts: &[Vec<f64>],
) -> Result<(Vec<f64>, f64), OptimiseError> {
    let (mut u, mut c) = swarm(problem, settings)?;
    if !starts.is_empty() {
        let designs: Vec<O::Design> = starts.iter().map(|x| problem.decode(x)).collect();
        for (x, cost) in starts.iter().zip(problem.costs_of(&designs)?) {
            if cost < c {
                (u, c) = (x.clone(), cost);
            }
        }
    }
    refine(problem, u)
}

/// Compass refinement after each swarm: first step, last step and most polls (cube units).
pub const REFINE_STEP: f64 = 0.25;
pub const REFINE_MIN_STEP: f64 = 1.0 / 16.0;
pub const REFINE_ITERS: u64 = 8;

/// Compass (pattern) search on the unit cube, an argmin `Solver`: polls ±step along every
/// axis (clamped to the cube) in one bulk evaluation, moves to the best poll point that
/// improves, else halves the step; converged when the step falls below `min_step`. Why: the
/// optima here sit on bounds and constraints (close-packed pockets, the longest period), where
/// a swarm's particles arrive slowly; polling along the axes reaches a face in a few steps.
pub struct CompassSearch {
    pub step: f64,
    pub min_step: f64,
}

type CubeState = IterState<Vec<f64>, (), (), (), (), f64>;

impl<O> Solver<O, CubeState> for CompassSearch
where
    O: CostFunction<Param = Vec<f64>, Output = f64> + argmin::core::SyncAlias,
{
    fn name(&self) -> &str {
        "compass search"
    }

    fn init(
        &mut self,
        problem: &mut Problem<O>,
        mut state: CubeState,
    ) -> Result<(CubeState, Option<KV>), ArgminError> {
        let x = state
            .take_param()
            .ok_or_else(|| ArgminError::msg("compass search needs a starting point"))?;
        let c = problem.cost(&x)?;
        Ok((state.param(x).cost(c), None))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        mut state: CubeState,
    ) -> Result<(CubeState, Option<KV>), ArgminError> {
        let x = state
            .take_param()
            .ok_or_else(|| ArgminError::msg("compass search lost its point"))?;
        let c = state.get_cost();
        let mut polls: Vec<Vec<f64>> = Vec::new();
        for d in 0..x.len() {
            for sign in [1.0, -1.0] {
                let mut y = x.clone();
                y[d] = (y[d] + sign * self.step).clamp(0.0, 1.0);
                if y != x && !polls.contains(&y) {
                    polls.push(y);
                }
            }
        }
        let costs = problem.bulk_cost(&polls)?;
        let best = costs
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .map(|(i, &v)| (i, v));
        match best {
            Some((i, v)) if v < c - 1e-12 * c.abs() => {
                Ok((state.param(polls[i].clone()).cost(v), None))
            }
            _ => {
                self.step *= 0.5;
                Ok((state.param(x).cost(c), None))
            }
        }
    }

    fn terminate(&mut self, _state: &CubeState) -> TerminationStatus {
        if self.step < self.min_step {
            TerminationStatus::Terminated(TerminationReason::SolverConverged)
        } else {
            TerminationStatus::NotTerminated
        }
    }
}

/// Refines a point by compass search ([`REFINE_STEP`] down to [`REFINE_MIN_STEP`], at most
/// [`REFINE_ITERS`] polls); returns the best point and its cost.
pub fn refine<O: CubeObjective + ?Sized>(
    problem: &O,
    start: Vec<f64>,
) -> Result<(Vec<f64>, f64), OptimiseError> {
    let compass = CompassSearch {
        step: REFINE_STEP,
        min_step: REFINE_MIN_STEP,
    };
    let res = Executor::new(Cost(problem), compass)
        .configure(|st| st.param(start).max_iters(REFINE_ITERS))
        .run()
        .map_err(solver_error)?;
    let best = res
        .state()
        .get_best_param()
        .cloned()
        .ok_or(OptimiseError::NoBest("refinement"))?;
    Ok((best, res.state().get_best_cost()))
}
