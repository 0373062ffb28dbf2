//! The searches through argmin: the evaluation service (designs → study jobs → cache), the
//! cost function a search minimises, a particle swarm, and a compass search polishing its
//! best point. The simulator knows nothing of this: every evaluation is a study job.

use argmin::core::{
    CostFunction, Error as ArgminError, Executor, IterState, Problem, Solver, State,
    TerminationReason, TerminationStatus, KV,
};
use argmin::solver::particleswarm::ParticleSwarm;
use rand::SeedableRng;
use serde::Serialize;
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;

use super::goal::{Goal, FAILED_COST};
use super::space::Space;
use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::Scales;
use crate::study::cache::Cache;
use crate::study::{sweep, Job, NumericsOverride};
use crate::time::{Fidelity, Outcome};

/// One evaluated design.
#[derive(Clone, Debug, Serialize)]
pub struct Evaluation {
    pub texture: Texture,
    pub fidelity: Fidelity,
    pub outcome: Result<Outcome, String>,
}

/// The evaluation service shared by every search: designs → jobs → cache/simulation.
pub struct Evaluator<'a> {
    pub base: CaseSpec,
    /// The scales of the base's operating point (for the reports in physical units).
    pub scales: Scales,
    pub fidelity: Fidelity,
    pub overrides: NumericsOverride,
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
        let numerics = crate::time::resolve(self.fidelity, &(&self.overrides).into(), &case);
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
    ) -> Result<Vec<Result<Outcome, String>>, String> {
        let jobs: Vec<Job> = designs.iter().map(|t| self.job(t.as_ref())).collect();
        for j in &jobs {
            j.numerics
                .validate(&j.case)
                .map_err(|e| format!("{}: {e}", j.case.label()))?;
        }
        let (sum, results) =
            sweep::run(&jobs, self.cache, &self.options, self.stop).map_err(|e| e.to_string())?;
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
            return Err("stopped (Ctrl-C); finished evaluations are in the cache".into());
        }
        let out: Vec<Result<Outcome, String>> = results
            .into_iter()
            .map(|r| r.unwrap_or_else(|| Err("not run".into())))
            .collect();
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
}

/// The argmin problem of one search: minimise `goal` over the unit cube of `space`.
pub struct Search<'a> {
    pub space: &'a Space,
    pub eval: &'a Evaluator<'a>,
    pub goal: Goal,
    pub plain: Outcome,
}

impl CostFunction for Search<'_> {
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
        let designs: Vec<Option<Texture>> = params
            .iter()
            .map(|u| Some(self.space.decode(u.borrow())))
            .collect();
        let out = self.eval.evaluate(&designs).map_err(ArgminError::msg)?;
        Ok(out
            .iter()
            .map(|o| match o {
                Ok(o) => self.goal.cost(o, &self.plain),
                Err(_) => FAILED_COST,
            })
            .collect())
    }
}

/// Particle-swarm settings of one search.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SwarmSettings {
    pub particles: usize,
    pub iterations: u64,
    pub seed: u64,
}

/// Runs one particle-swarm search; returns the best unit-cube point and its cost.
pub fn search(s: &Search, settings: SwarmSettings) -> Result<(Vec<f64>, f64), String> {
    swarm(s, s.space.dim(), settings)
}

/// A particle swarm over the unit cube of dimension `n` minimising `problem`.
pub fn swarm<C>(problem: C, n: usize, settings: SwarmSettings) -> Result<(Vec<f64>, f64), String>
where
    C: CostFunction<Param = Vec<f64>, Output = f64> + argmin::core::SyncAlias,
{
    let solver = ParticleSwarm::new((vec![0.0; n], vec![1.0; n]), settings.particles)
        .with_rng_generator(rand::rngs::StdRng::seed_from_u64(settings.seed));
    let res = Executor::new(problem, solver)
        .configure(|st| st.max_iters(settings.iterations))
        .run()
        .map_err(|e| e.to_string())?;
    let best = res
        .state()
        .get_best_param()
        .map(|p| p.position.clone())
        .ok_or("the search ended without a best design")?;
    Ok((best, res.state().get_best_cost()))
}

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

/// Refines a point by compass search; returns the best point and its cost.
pub fn refine<C>(
    problem: C,
    start: Vec<f64>,
    step: f64,
    min_step: f64,
    max_iters: u64,
) -> Result<(Vec<f64>, f64), String>
where
    C: CostFunction<Param = Vec<f64>, Output = f64> + argmin::core::SyncAlias,
{
    let res = Executor::new(problem, CompassSearch { step, min_step })
        .configure(|st| st.param(start).max_iters(max_iters))
        .run()
        .map_err(|e| e.to_string())?;
    let best = res
        .state()
        .get_best_param()
        .cloned()
        .ok_or("the refinement ended without a best design")?;
    Ok((best, res.state().get_best_cost()))
}

impl CostFunction for &Search<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Vec<f64>) -> Result<f64, ArgminError> {
        (*self).cost(u)
    }
    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<f64>, ArgminError>
    where
        P: std::borrow::Borrow<Vec<f64>> + argmin::core::SyncAlias,
    {
        (*self).bulk_cost(params)
    }
}
