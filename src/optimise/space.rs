//! Texture optimisation for one ring: the design space (pocket semiaxes, period, depth) mapped
//! feasibly from the unit cube, so no design that breaks a manufacturing or validity
//! constraint is ever simulated; the cost functions argmin minimises; the Pareto front of
//! friction against clearance. The simulator knows nothing of this module: every evaluation
//! is a study job run through the cache (sweep.rs).

use argmin::core::{
    CostFunction, Error as ArgminError, Executor, IterState, Problem, Solver, State,
    TerminationReason, TerminationStatus, KV,
};
use argmin::solver::particleswarm::ParticleSwarm;
use rand::SeedableRng;
use serde::Serialize;
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;

use crate::model::case::{bad, CaseSpec, InputError, Texture};
use crate::study::cache::Cache;
use crate::study::sweep;
use crate::study::{numerics_for, Job, NumericsOverride};
use crate::time::{Fidelity, Outcome};

/// Bounds of the design variables. Lengths in cm, depth in µm. Defaults: the paper's ranges
/// (model.md §7).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bounds {
    pub l1: (f64, f64),
    pub l2: (f64, f64),
    pub per: (f64, f64),
    /// None: width = per (square lattice); Some: width is a free variable.
    pub width: Option<(f64, f64)>,
    pub depth: (f64, f64),
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds {
            l1: (0.0025, 0.03),
            l2: (0.0025, 0.03),
            per: (0.005, 0.06),
            width: None,
            depth: (2.0, 30.0),
        }
    }
}

/// Manufacturability and validity constraints (model.md §2).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Constraints {
    /// Least wall between neighbouring pockets, per − 2·l1 and width − 2·l2 (cm).
    pub w_min: f64,
    /// Largest textured area fraction π·l1·l2/(per·width), if any.
    pub max_area: Option<f64>,
    /// Largest depth-to-diameter ratio depth/(2·l) over both axes (µm/µm), if any.
    pub max_depth_ratio: Option<f64>,
    /// Lift the thin-film rule 10⁴·l ≥ 5·depth.
    pub allow_thick: bool,
}

/// Default least wall thickness: 10 µm.
pub const DEFAULT_W_MIN_CM: f64 = 0.001;

impl Default for Constraints {
    fn default() -> Self {
        Constraints {
            w_min: DEFAULT_W_MIN_CM,
            max_area: None,
            max_depth_ratio: None,
            allow_thick: false,
        }
    }
}

/// The design space: the unit cube mapped onto designs that satisfy every constraint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Space {
    pub bounds: Bounds,
    pub cons: Constraints,
}

fn lerp((lo, hi): (f64, f64), u: f64) -> f64 {
    lo + u.clamp(0.0, 1.0) * (hi - lo)
}

/// Relative slack under which a constraint counts as active.
const ACTIVE: f64 = 1e-3;

impl Space {
    /// Dimensions: u = (per, l1, l2, depth[, width]).
    pub fn dim(&self) -> usize {
        if self.bounds.width.is_some() {
            5
        } else {
            4
        }
    }

    /// Least semiaxis any depth in range allows (thin film, depth ratio).
    fn l_floor(&self) -> f64 {
        let d = self.bounds.depth.0;
        let mut l = 0.0f64;
        if !self.cons.allow_thick {
            l = l.max(5.0 * d * 1e-4);
        }
        if let Some(r) = self.cons.max_depth_ratio {
            l = l.max(d / (2.0 * r * 1e4));
        }
        l
    }

    /// The design at u ∈ [0, 1]^dim. Each variable's interval depends on those before it, so
    /// that every u gives a feasible design (when `validate` passed).
    pub fn decode(&self, u: &[f64]) -> Texture {
        let b = &self.bounds;
        let c = &self.cons;
        let floor = self.l_floor();
        let l1_min = b.l1.0.max(floor);
        let l2_min = b.l2.0.max(floor);
        let per_lo = b.per.0.max(2.0 * l1_min + c.w_min);
        // Least cell area the smallest pockets need under an area-fraction limit.
        let min_cell = c
            .max_area
            .map_or(0.0, |a| std::f64::consts::PI * l1_min * l2_min / a);
        let (per, width) = match b.width {
            None => {
                let lo = per_lo.max(2.0 * l2_min + c.w_min).max(min_cell.sqrt());
                let p = lerp((lo, b.per.1), u[0]);
                (p, p)
            }
            Some(w) => {
                let p = lerp((per_lo.max(min_cell / w.1), b.per.1), u[0]);
                let wlo = w.0.max(2.0 * l2_min + c.w_min).max(min_cell / p);
                (p, lerp((wlo, w.1), u[4]))
            }
        };
        let area_cap = |other: f64| {
            c.max_area.map_or(f64::INFINITY, |a| {
                a * per * width / (std::f64::consts::PI * other)
            })
        };
        let l1_hi = b.l1.1.min(0.5 * (per - c.w_min)).min(area_cap(l2_min));
        let l1 = lerp((l1_min, l1_hi.max(l1_min)), u[1]);
        let l2_hi = b.l2.1.min(0.5 * (width - c.w_min)).min(area_cap(l1));
        let l2 = lerp((l2_min, l2_hi.max(l2_min)), u[2]);
        let lmin = l1.min(l2);
        let mut d_hi = b.depth.1;
        if !c.allow_thick {
            d_hi = d_hi.min(lmin * 1e4 / 5.0);
        }
        if let Some(r) = c.max_depth_ratio {
            d_hi = d_hi.min(r * 2.0 * lmin * 1e4);
        }
        let depth = lerp((b.depth.0, d_hi.max(b.depth.0)), u[3]);
        Texture {
            l1,
            l2,
            per,
            width,
            depth,
            phase: 0.0,
        }
    }

    /// Every constraint and bound the design breaks (empty: feasible).
    pub fn violations(&self, t: &Texture) -> Vec<String> {
        let b = &self.bounds;
        let c = &self.cons;
        let tol = 1e-9;
        let mut v = Vec::new();
        let mut within = |name: &str, x: f64, (lo, hi): (f64, f64)| {
            if x < lo * (1.0 - tol) || x > hi * (1.0 + tol) {
                v.push(format!("{name} = {x} outside [{lo}, {hi}]"));
            }
        };
        within("l1", t.l1, b.l1);
        within("l2", t.l2, b.l2);
        within("per", t.per, b.per);
        within("width", t.width, b.width.unwrap_or(b.per));
        within("depth", t.depth, b.depth);
        if b.width.is_none() && t.width != t.per {
            v.push("width ≠ per on a square lattice".into());
        }
        let (w1, w2) = wall(t);
        if w1 < c.w_min - tol || w2 < c.w_min - tol {
            v.push(format!(
                "wall thickness ({w1:.6}, {w2:.6}) cm below w_min = {}",
                c.w_min
            ));
        }
        if !c.allow_thick && 1e4 * t.l1.min(t.l2) < 5.0 * t.depth * (1.0 - tol) {
            v.push("thin-film validity 10⁴·l ≥ 5·depth broken".into());
        }
        if let Some(a) = c.max_area {
            if t.area_fraction() > a * (1.0 + tol) {
                v.push(format!("area fraction {:.4} above {a}", t.area_fraction()));
            }
        }
        if let Some(r) = c.max_depth_ratio {
            if depth_ratio(t) > r * (1.0 + tol) {
                v.push(format!("depth/diameter {:.4} above {r}", depth_ratio(t)));
            }
        }
        v
    }

    /// The constraints (not plain bounds) the design sits on.
    pub fn active(&self, t: &Texture) -> Vec<&'static str> {
        let c = &self.cons;
        let mut a = Vec::new();
        let (w1, w2) = wall(t);
        if w1 <= c.w_min + ACTIVE * t.per {
            a.push("wall x1");
        }
        if w2 <= c.w_min + ACTIVE * t.width {
            a.push("wall x2");
        }
        if !c.allow_thick && 5.0 * t.depth >= 1e4 * t.l1.min(t.l2) * (1.0 - ACTIVE) {
            a.push("thin film");
        }
        if c.max_area
            .is_some_and(|m| t.area_fraction() >= m * (1.0 - ACTIVE))
        {
            a.push("area");
        }
        if c.max_depth_ratio
            .is_some_and(|m| depth_ratio(t) >= m * (1.0 - ACTIVE))
        {
            a.push("depth ratio");
        }
        a
    }

    /// Refuses empty or inverted ranges and constraint sets no design satisfies (checked at
    /// every corner of the cube, where the intervals are tightest).
    pub fn validate(&self) -> Result<(), InputError> {
        let b = &self.bounds;
        let mut ranges = vec![
            ("l1", b.l1),
            ("l2", b.l2),
            ("per", b.per),
            ("depth", b.depth),
        ];
        if let Some(w) = b.width {
            ranges.push(("width", w));
        }
        for (name, (lo, hi)) in ranges {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
                return Err(bad(
                    name,
                    format!("{lo}..{hi}"),
                    "a range LO..HI needs 0 < LO ≤ HI",
                ));
            }
        }
        let c = &self.cons;
        if !(c.w_min.is_finite() && c.w_min >= 0.0) {
            return Err(bad(
                "w_min",
                c.w_min,
                "the least wall thickness must be ≥ 0 (cm)",
            ));
        }
        if let Some(a) = c.max_area {
            if !(a > 0.0 && a <= std::f64::consts::FRAC_PI_4) {
                return Err(bad(
                    "max_area",
                    a,
                    "an area fraction must lie in (0, π/4] (π/4: touching circular pockets)",
                ));
            }
        }
        if let Some(r) = c.max_depth_ratio {
            if !(r.is_finite() && r > 0.0) {
                return Err(bad("max_depth_ratio", r, "must be a finite number > 0"));
            }
        }
        let n = self.dim();
        for corner in 0..(1usize << n) {
            let u: Vec<f64> = (0..n).map(|k| ((corner >> k) & 1) as f64).collect();
            let t = self.decode(&u);
            if let Some(v) = self.violations(&t).first() {
                return Err(bad(
                    "constraints",
                    format!(
                        "w_min = {} cm, l1 {:?}, l2 {:?}, per {:?}, depth {:?}",
                        c.w_min, b.l1, b.l2, b.per, b.depth
                    ),
                    format!(
                        "no feasible texture in part of the space ({v}); widen the ranges or relax the constraints"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Wall thickness between neighbouring pockets along x1 and x2 (cm).
pub fn wall(t: &Texture) -> (f64, f64) {
    (t.per - 2.0 * t.l1, t.width - 2.0 * t.l2)
}

/// Depth over the smaller pocket diameter (µm/µm).
pub fn depth_ratio(t: &Texture) -> f64 {
    t.depth / (2.0 * t.l1.min(t.l2) * 1e4)
}

/// What a search minimises, in outcomes relative to the plain liner: a = f̄/f̄_plain,
/// b = C_min,plain/C_min (both 1 for the plain liner, lower is better).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Goal {
    Friction,
    Clearance,
    /// Chebyshev scalarisation max(w·(a − a*), (1 − w)·(b − b*)) about the ideal point
    /// (a*, b*) of the single-objective searches.
    Balanced {
        w: f64,
        ideal: (f64, f64),
    },
}

/// Cost of a failed evaluation: worse than any plausible design, finite for the swarm.
const FAILED_COST: f64 = 10.0;

impl Goal {
    pub fn cost(&self, o: &Outcome, plain: &Outcome) -> f64 {
        let a = o.f_mean / plain.f_mean;
        let b = plain.c_min / o.c_min;
        match *self {
            Goal::Friction => a,
            Goal::Clearance => b,
            Goal::Balanced { w, ideal } => (w * (a - ideal.0)).max((1.0 - w) * (b - ideal.1)),
        }
    }
}

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
    pub fidelity: Fidelity,
    pub overrides: NumericsOverride,
    pub cache: &'a Mutex<Cache>,
    pub options: sweep::Options,
    pub stop: &'a AtomicBool,
    /// Every design evaluated, in order.
    pub log: Mutex<Vec<Evaluation>>,
    /// Simulations run (not answered by the cache).
    pub simulations: Mutex<usize>,
    /// Print a line per batch on stderr.
    pub progress: bool,
}

impl Evaluator<'_> {
    pub fn job(&self, t: Option<&Texture>) -> Job {
        let case = CaseSpec {
            texture: t.cloned(),
            ..self.base.clone()
        };
        let numerics = numerics_for(&case, self.fidelity, &self.overrides);
        Job { case, numerics }
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
                "  {} designs at {}: {} from the cache, {} simulated ({:.1} s); {total_sims} simulations so far",
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
    let n = s.space.dim();
    let solver = ParticleSwarm::new((vec![0.0; n], vec![1.0; n]), settings.particles)
        .with_rng_generator(rand::rngs::StdRng::seed_from_u64(settings.seed));
    let res = Executor::new(s, solver)
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
pub fn refine(
    s: &Search,
    start: Vec<f64>,
    step: f64,
    min_step: f64,
    max_iters: u64,
) -> Result<(Vec<f64>, f64), String> {
    let res = Executor::new(s, CompassSearch { step, min_step })
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

/// Indices of the non-dominated points (minimise x, maximise y).
pub fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (xi, yi) = points[i];
            xi.is_finite()
                && yi.is_finite()
                && !points
                    .iter()
                    .enumerate()
                    .any(|(j, &(xj, yj))| j != i && xj <= xi && yj >= yi && (xj < xi || yj > yi))
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_of_the_cube_decodes_to_a_feasible_design() {
        let spaces = [
            Space {
                bounds: Bounds::default(),
                cons: Constraints::default(),
            },
            Space {
                bounds: Bounds {
                    width: Some((0.01, 0.08)),
                    ..Bounds::default()
                },
                cons: Constraints {
                    w_min: 0.003,
                    max_area: Some(0.3),
                    max_depth_ratio: Some(0.02),
                    allow_thick: false,
                },
            },
        ];
        for s in &spaces {
            s.validate().unwrap();
            let n = s.dim();
            // A deterministic low-discrepancy-ish walk over the cube.
            for k in 0..5000u64 {
                let u: Vec<f64> = (0..n)
                    .map(|d| {
                        ((k as f64 + 0.5) * [0.618034, 0.414214, 0.732051, 0.236068, 0.123106][d])
                            .fract()
                    })
                    .collect();
                let t = s.decode(&u);
                assert!(
                    s.violations(&t).is_empty(),
                    "{u:?} → {t:?}: {:?}",
                    s.violations(&t)
                );
            }
        }
    }

    #[test]
    fn impossible_constraint_sets_are_refused() {
        let s = Space {
            bounds: Bounds {
                per: (0.005, 0.006),
                ..Bounds::default()
            },
            cons: Constraints {
                w_min: 0.002,
                ..Constraints::default()
            },
        };
        assert_eq!(s.validate().unwrap_err().param, "constraints");
    }

    #[test]
    fn pareto_keeps_only_non_dominated_points() {
        let p = [
            (1.0, 1.0),
            (0.9, 0.8),
            (0.95, 1.2),
            (1.1, 1.3),
            (0.9, 0.7),
            (1.2, 1.0),
        ];
        assert_eq!(pareto(&p), vec![1, 2, 3]);
    }
}
