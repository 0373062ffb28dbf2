//! Where to texture the liner (docs/model.md §13): banded liners searched over the engine's
//! operating map. A liner is judged at every point of the map by the transient cycle (the
//! zones' judge of `transient_search`, one per point), and costs the time-weighted mean friction
//! power over the map relative to the plain liner's; a liner that thins the film below both
//! the least clearance and the plain liner's least film at any point is infeasible. The
//! swarm searches the band space; the uniform candidates are the best liner's band textures
//! laid over the whole stroke; plain, uniform and banded are then run at the report's
//! fidelity until each repeats itself.

use std::sync::{Arc, Mutex};

use rayon::prelude::*;
use serde::Serialize;

use super::angles::CycleSettings;
use super::bands::{BandSpace, Banded};
use super::map_runs::{lock, stored, BatchJudge, Here, MapBatch, MapLiner, MapRun, Runner};
use super::transient_search::{
    keeps_film, metrics_over, zoned_cost, CycleJudge, Judged, PlainAt, ZonedCosts,
};
use crate::model::case::Texture;
use crate::model::engine::MapPoint;
use crate::model::liner_layout::LinerLayout;
use crate::optimise::error::{OptimiseError, RunsError};
use crate::optimise::goal::FAILED_COST;
use crate::optimise::search::{swarm, CubeObjective};
use crate::study::cache::{Cache, Key};
use crate::study::cycle_cache::{CycleAnswer, CycleFailure};
use crate::time::cycle::CycleMetrics;
use crate::time::Fidelity;

/// What a liner's run at a point gives the search: its figures (the report's runs keep their
/// cycle's rows too).
pub trait Figures {
    fn figures(&self) -> &CycleMetrics;
}

impl Figures for Judged {
    fn figures(&self) -> &CycleMetrics {
        &self.metrics
    }
}

impl Figures for CycleMetrics {
    fn figures(&self) -> &CycleMetrics {
        self
    }
}

/// One liner over the map: per point its run (or why it failed) and the plain liner's on the
/// same mesh.
pub struct OverMap<R = Judged> {
    pub points: Vec<Result<R, CycleFailure>>,
    pub plain: Vec<Arc<PlainAt>>,
}

/// The time-weighted mean of `f` over the map's points (shares sum to 1).
fn weighted(points: &[MapPoint], f: impl Fn(usize) -> f64) -> f64 {
    points.iter().enumerate().map(|(k, p)| p.share * f(k)).sum()
}

impl<R: Figures> OverMap<R> {
    /// Per point its figures, where its run succeeded.
    pub fn metrics(&self, k: usize) -> Option<&CycleMetrics> {
        self.points[k].as_ref().ok().map(Figures::figures)
    }

    /// The time-weighted mean friction power (W/m): the friction energy over the drive
    /// cycle over its duration (docs/model.md §13). None where a point failed.
    pub fn mean_power(&self, map: &[MapPoint]) -> Option<f64> {
        let ok = (0..map.len()).all(|k| self.metrics(k).is_some());
        ok.then(|| {
            weighted(map, |k| {
                self.metrics(k).map_or(0.0, |m| m.mean_power_w_per_m)
            })
        })
    }

    pub fn plain_mean_power(&self, map: &[MapPoint]) -> f64 {
        weighted(map, |k| self.plain[k].metrics.mean_power_w_per_m)
    }

    /// The least film over every point (µm), None where a point failed.
    pub fn worst_film(&self) -> Option<f64> {
        (0..self.points.len())
            .map(|k| self.metrics(k).map(|m| m.h_min_um))
            .try_fold(f64::INFINITY, |a, h| h.map(|h| a.min(h)))
    }

    pub fn plain_worst_film(&self) -> f64 {
        self.plain
            .iter()
            .map(|p| p.metrics.h_min_um)
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether every point ran and [`keeps_film`] there.
    pub fn feasible(&self, least_um: f64) -> bool {
        (0..self.points.len()).all(|k| {
            self.metrics(k)
                .is_some_and(|m| keeps_film(m.h_min_um, self.plain[k].metrics.h_min_um, least_um))
        })
    }

    /// Why it is infeasible: the first point whose run failed, or whose least film falls too
    /// far (docs/model.md §13); None where it is feasible.
    pub fn why_infeasible(&self, map: &[MapPoint], least_um: f64) -> Option<Infeasible> {
        map.iter().enumerate().find_map(|(k, p)| {
            let plain_um = self.plain[k].metrics.h_min_um;
            match &self.points[k] {
                Err(why) => Some(Infeasible::Failed {
                    point: p.name.clone(),
                    why: why.clone(),
                }),
                Ok(j) if !keeps_film(j.figures().h_min_um, plain_um, least_um) => {
                    Some(Infeasible::ThinFilm {
                        point: p.name.clone(),
                        film_um: j.figures().h_min_um,
                        plain_um,
                    })
                }
                Ok(_) => None,
            }
        })
    }

    /// Its cost: mean power over the plain liner's, the search's failed cost where infeasible.
    pub fn cost(&self, map: &[MapPoint], least_um: f64) -> f64 {
        match self.mean_power(map) {
            Some(p) if self.feasible(least_um) => p / self.plain_mean_power(map),
            _ => FAILED_COST,
        }
    }
}

/// Why a liner is infeasible over the map (docs/model.md §13).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Infeasible {
    /// Its run at a point failed.
    #[error("{point}: {why}")]
    Failed { point: String, why: CycleFailure },
    /// At a point it thins the film below both the least clearance and the plain liner's
    /// least film.
    #[error("{point}: least film {film_um:.4} µm against the plain liner's {plain_um:.4} µm")]
    ThinFilm {
        point: String,
        film_um: f64,
        plain_um: f64,
    },
}

/// A report writes the reason as its words.
impl Serialize for Infeasible {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// One liner the search judged: its cost (mean power over the plain liner's) and its least
/// film over the plain liner's, both at the search's fidelity.
#[derive(Clone, Debug, Serialize)]
pub struct MapEval {
    pub banded: Banded,
    pub power_ratio: f64,
    /// NaN where a run failed (written as null).
    #[serde(serialize_with = "crate::finite::absent")]
    pub film_ratio: f64,
    pub feasible: bool,
    /// Why it is infeasible: the first point whose run failed, and why, or that thinned the
    /// film too far (None: feasible).
    pub why: Option<Infeasible>,
}

/// Judges liners over the map, a cycle judge per point; the search's runs through the cache
/// and a runner ([`MapJudge::through`]).
pub struct MapJudge<'a> {
    pub s: &'a CycleSettings,
    pub map: Vec<MapPoint>,
    judges: Vec<CycleJudge<'a>>,
    through: Option<(&'a Mutex<Cache>, &'a dyn Runner)>,
    /// Runs answered by the cache and runs handed to the runner, so far.
    counts: Mutex<(usize, usize)>,
    /// Every banded liner judged, in order.
    pub log: Mutex<Vec<MapEval>>,
}

impl<'a> MapJudge<'a> {
    /// At the search's fidelity.
    pub fn new(s: &'a CycleSettings) -> Self {
        let map = s.engine.operating_points();
        let judges = map
            .iter()
            .map(|p| CycleJudge::at(s, p.engine.clone()))
            .collect();
        MapJudge {
            s,
            map,
            judges,
            through: None,
            counts: Mutex::new((0, 0)),
            log: Mutex::new(Vec::new()),
        }
    }

    /// The same, its runs looked up in `cache` and the missing ones run by `runner`.
    pub fn through(self, cache: &'a Mutex<Cache>, runner: &'a dyn Runner) -> Self {
        MapJudge {
            through: Some((cache, runner)),
            ..self
        }
    }

    /// The same at the report's fidelity, each liner run until it repeats itself.
    pub fn reporting(self) -> Self {
        MapJudge {
            judges: self.judges.into_iter().map(CycleJudge::reporting).collect(),
            log: Mutex::new(Vec::new()),
            ..self
        }
    }

    /// The cache the search's runs go through.
    pub fn cache(&self) -> Result<&'a Mutex<Cache>, OptimiseError> {
        self.through
            .map(|(c, _)| c)
            .ok_or(OptimiseError::Runs(RunsError::NoCache))
    }

    /// The judge of point `k`.
    pub fn point(&self, k: usize) -> Option<&CycleJudge<'a>> {
        self.judges.get(k)
    }

    pub fn stroke_mm(&self) -> f64 {
        self.s.engine.file.engine.stroke_mm
    }

    /// `liners` over the map through the cache: the runs it does not hold handed to the
    /// runner as one batch (point by point), then every answer read from it; and the plain
    /// liner at every point.
    #[allow(clippy::type_complexity)]
    fn answers(
        &self,
        liners: &[MapLiner],
    ) -> Result<
        (
            Vec<Vec<Result<CycleAnswer, CycleFailure>>>,
            Vec<Arc<PlainAt>>,
        ),
        OptimiseError,
    > {
        let cache = self.cache()?;
        let layouts: Vec<LinerLayout> = liners
            .iter()
            .map(|l| l.layout(self.stroke_mm()))
            .collect::<Result<_, _>>()?;
        let Some(first) = layouts.first() else {
            return Ok((Vec::new(), Vec::new()));
        };
        let plain: Vec<Arc<PlainAt>> = self
            .judges
            .par_iter()
            .map(|j| j.plain_of(first))
            .collect::<Result<_, _>>()?;
        let keys: Vec<Vec<Key>> = layouts
            .iter()
            .map(|l| self.judges.iter().map(|j| j.key(l)).collect())
            .collect();
        let mut runs: Vec<MapRun> = Vec::new();
        for point in 0..self.judges.len() {
            for (liner, k) in keys.iter().enumerate() {
                let key = &k[point].hash;
                let held = lock(cache).get_cycle(&k[point])?;
                if held.is_none() && !runs.iter().any(|r| &r.key == key) {
                    runs.push(MapRun {
                        liner,
                        point,
                        key: key.clone(),
                    });
                }
            }
        }
        {
            let mut c = self.counts.lock().unwrap_or_else(|e| e.into_inner());
            c.0 += keys.len() * self.judges.len() - runs.len();
            c.1 += runs.len();
        }
        if !runs.is_empty() {
            let runner = self.through.map(|(_, r)| r).unwrap_or(&Here);
            let report = self.judges.first().is_some_and(|j| j.reports());
            runner.run(
                self,
                &MapBatch {
                    liners: liners.to_vec(),
                    runs,
                    report,
                },
            )?;
        }
        let answers = keys
            .iter()
            .map(|k| k.iter().map(|key| stored(cache, key)).collect())
            .collect::<Result<_, _>>()?;
        Ok((answers, plain))
    }

    /// `liners` over the map through the cache, each point's figures only.
    fn figures(&self, liners: &[MapLiner]) -> Result<Vec<OverMap<CycleMetrics>>, OptimiseError> {
        let (answers, plain) = self.answers(liners)?;
        Ok(answers
            .into_iter()
            .map(|points| OverMap {
                points: points.into_iter().map(|a| a.map(|a| a.metrics)).collect(),
                plain: plain.clone(),
            })
            .collect())
    }

    /// `liners` over the map through the cache with their cycles' rows (a reporting judge's),
    /// work per zone of `zones_cm`.
    pub fn judge_all(
        &self,
        liners: &[MapLiner],
        zones_cm: &[f64],
    ) -> Result<Vec<OverMap>, OptimiseError> {
        let (answers, plain) = self.answers(liners)?;
        let judged = |k: usize, a: CycleAnswer| -> Result<Judged, CycleFailure> {
            let rows = a.rows.ok_or(CycleFailure::WithoutRows)?;
            let metrics = metrics_over(&rows, self.judges[k].engine(), zones_cm);
            Ok(Judged { metrics, rows })
        };
        Ok(answers
            .into_iter()
            .map(|points| OverMap {
                points: points
                    .into_iter()
                    .enumerate()
                    .map(|(k, a)| a.and_then(|a| judged(k, a)))
                    .collect(),
                plain: plain.clone(),
            })
            .collect())
    }

    /// Runs answered by the cache and runs handed to the runner, so far.
    pub fn counts(&self) -> (usize, usize) {
        *self.counts.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Banded liners' costs over the map, each logged.
    fn banded_costs(&self, designs: &[Banded]) -> Result<Vec<f64>, OptimiseError> {
        let liners: Vec<MapLiner> = designs.iter().cloned().map(MapLiner::Banded).collect();
        let least = self.s.min_clearance_um;
        let overs = self.figures(&liners)?;
        let mut log = self.log.lock().unwrap_or_else(|e| e.into_inner());
        Ok(designs
            .iter()
            .zip(&overs)
            .map(|(b, over)| {
                let cost = over.cost(&self.map, least);
                let film_ratio = over
                    .worst_film()
                    .map_or(f64::NAN, |h| h / over.plain_worst_film());
                log.push(MapEval {
                    banded: b.clone(),
                    power_ratio: cost,
                    film_ratio,
                    feasible: cost < FAILED_COST,
                    why: (cost >= FAILED_COST)
                        .then(|| over.why_infeasible(&self.map, least))
                        .flatten(),
                });
                cost
            })
            .collect())
    }

    /// Textures over the whole stroke: their costs.
    fn uniform_costs(&self, textures: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        let liners: Vec<MapLiner> = textures.iter().cloned().map(MapLiner::Uniform).collect();
        Ok(self
            .figures(&liners)?
            .iter()
            .map(|o| o.cost(&self.map, self.s.min_clearance_um))
            .collect())
    }
}

/// A search over a band space: its liners' costs, a batch at a time, by `costs`.
pub struct OverBands<'s, F> {
    pub space: &'s BandSpace,
    pub costs: F,
}

impl<F> CubeObjective for OverBands<'_, F>
where
    F: Fn(&[Banded]) -> Result<Vec<f64>, OptimiseError> + Sync,
{
    type Design = Banded;

    fn dim(&self) -> usize {
        self.space.dim()
    }

    fn decode(&self, u: &[f64]) -> Banded {
        self.space.decode(u)
    }

    fn costs_of(&self, designs: &[Banded]) -> Result<Vec<f64>, OptimiseError> {
        (self.costs)(designs)
    }
}

impl BatchJudge for MapJudge<'_> {
    fn point(&self, k: usize) -> Option<&CycleJudge<'_>> {
        MapJudge::point(self, k)
    }

    fn stroke_mm(&self) -> f64 {
        MapJudge::stroke_mm(self)
    }

    fn cache(&self) -> Result<&Mutex<Cache>, OptimiseError> {
        MapJudge::cache(self)
    }

    fn progress(&self) -> bool {
        self.s.search.progress
    }
}

impl MapJudge<'_> {
    /// A batch of banded liners judged over the map, the best so far said.
    fn costs(&self, designs: &[Banded], t0: std::time::Instant) -> Result<Vec<f64>, OptimiseError> {
        let costs = self.banded_costs(designs)?;
        if self.s.search.progress {
            let log = self.log.lock().unwrap_or_else(|e| e.into_inner());
            let best = log
                .iter()
                .map(|e| e.power_ratio)
                .fold(f64::INFINITY, f64::min);
            let best = if best < FAILED_COST {
                format!("{best:.5}")
            } else {
                "none feasible yet".into()
            };
            let (held, ran) = *self.counts.lock().unwrap_or_else(|e| e.into_inner());
            eprintln!(
                "[{:6.1} s] {} banded liners judged, best power ratio {best} ({held} runs from the cache, {ran} run)",
                t0.elapsed().as_secs_f64(),
                log.len()
            );
        }
        Ok(costs)
    }
}

/// What the search found, at its fidelity: the best banded liner and its cost, the best
/// uniform texture (the banded liner's band textures over the whole stroke) and its cost,
/// and every banded liner judged.
pub struct MapDesigns {
    pub banded: Banded,
    pub banded_cost: f64,
    pub uniform: Option<(Texture, f64)>,
    pub log: Vec<MapEval>,
    pub fidelity: Fidelity,
}

/// The banded search over the map (the swarm, and the least bands at the dead centres), then
/// the uniform candidates.
pub fn design_over_map(
    s: &CycleSettings,
    space: &BandSpace,
    cache: &Mutex<Cache>,
    runner: &dyn Runner,
) -> Result<MapDesigns, OptimiseError> {
    let t0 = std::time::Instant::now();
    let say = s.search.say_since(t0);
    let judge = MapJudge::new(s).through(cache, runner);
    say(format!(
        "bands over {} operating point(s) at {}: {} particles × {} iterations, each liner a cycle run per point …",
        judge.map.len(),
        s.search.search_fidelity.name(),
        s.search.swarm.particles,
        s.search.swarm.iterations,
    ));
    let problem = OverBands {
        space,
        costs: |d: &[Banded]| judge.costs(d, t0),
    };
    let (mut u, mut banded_cost) = swarm(&problem, s.search.swarm)?;
    // Also the least bands at both dead centres with the design space's middle texture: a
    // band away from where it helps costs alike wherever it lies, a plateau a small swarm
    // may not leave.
    let start = space.at_dead_centres();
    if let Some(&c) = problem.costs_of(&[space.decode(&start)])?.first() {
        if c < banded_cost {
            (u, banded_cost) = (start, c);
        }
    }
    let banded = space.decode(&u);
    say(format!(
        "bands: {}, power ratio {banded_cost:.5}",
        banded.label()
    ));
    let mut textures: Vec<Texture> = Vec::new();
    for b in &banded.bands {
        if !textures.contains(&b.texture) {
            textures.push(b.texture.clone());
        }
    }
    let costs = judge.uniform_costs(&textures)?;
    let uniform = (0..textures.len())
        .filter(|&k| costs[k] < FAILED_COST)
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .map(|k| (textures[k].clone(), costs[k]));
    match &uniform {
        Some((t, c)) => say(format!("uniform: {}, power ratio {c:.5}", t.rounded_label())),
        None => say(format!(
            "uniform: every band texture over the whole stroke failed or thinned the film below {:.3} µm (or 1 % below the plain liner's where that is thinner) at some point",
            s.min_clearance_um
        )),
    }
    let log = std::mem::take(&mut *judge.log.lock().unwrap_or_else(|e| e.into_inner()));
    Ok(MapDesigns {
        banded,
        banded_cost,
        uniform,
        log,
        fidelity: s.search.search_fidelity,
    })
}

/// The three liners at the report's fidelity over the map, each until it repeats itself:
/// plain, the best uniform texture (None: every uniform candidate failed) and the banded
/// liner; work per zone of the banded liner's zones for all three.
pub struct MapLiners {
    pub map: Vec<MapPoint>,
    pub zones_cm: Vec<f64>,
    pub uniform: Option<OverMap>,
    pub banded: OverMap,
}

impl MapLiners {
    /// The plain liner's figures at point k with work per band zone.
    pub fn plain(&self, k: usize) -> &PlainAt {
        &self.banded.plain[k]
    }
}

pub fn evaluate_over_map(
    s: &CycleSettings,
    d: &MapDesigns,
    cache: &Mutex<Cache>,
    runner: &dyn Runner,
) -> Result<MapLiners, OptimiseError> {
    let t0 = std::time::Instant::now();
    let say = s.search.say_since(t0);
    let judge = MapJudge::new(s).reporting().through(cache, runner);
    let zones_cm = d.banded.layout(judge.stroke_mm()).bounds_cm().to_vec();
    let mut liners = vec![MapLiner::Banded(d.banded.clone())];
    liners.extend(d.uniform.iter().map(|(t, _)| MapLiner::Uniform(t.clone())));
    say(format!(
        "the {} over the map at {}, each point until it repeats itself …",
        if liners.len() > 1 {
            "banded and uniform liners"
        } else {
            "banded liner"
        },
        s.search.report_fidelity.name()
    ));
    let mut overs = judge.judge_all(&liners, &zones_cm)?.into_iter();
    let (Some(banded), uniform) = (overs.next(), overs.next()) else {
        return Err(OptimiseError::Nothing("banded liner"));
    };
    for (name, over) in [("banded", Some(&banded)), ("uniform", uniform.as_ref())] {
        let Some(over) = over else { continue };
        for (k, p) in judge.map.iter().enumerate() {
            let plain = &over.plain[k].metrics;
            say(match over.metrics(k) {
                Some(m) => format!(
                    "{name}, {}: {:.4} J/m (plain {:.4}), least film {:.3} µm (plain {:.3})",
                    p.name, m.work_j_per_m, plain.work_j_per_m, m.h_min_um, plain.h_min_um
                ),
                None => format!("{name}, {}: its run failed", p.name),
            });
        }
    }
    Ok(MapLiners {
        map: judge.map,
        zones_cm,
        uniform,
        banded,
    })
}

/// The zone search's liners through the cache and the runner, on the engine's own point
/// (an engine without a map: the judge's one point).
impl ZonedCosts for MapJudge<'_> {
    fn costs(&self, liners: &[Vec<Option<Texture>>]) -> Result<Vec<f64>, OptimiseError> {
        let bounds_cm = self.s.zones.bounds_cm();
        let liners: Vec<MapLiner> = liners
            .iter()
            .map(|textures| MapLiner::Zoned {
                bounds_cm: bounds_cm.clone(),
                textures: textures.clone(),
            })
            .collect();
        let least = self.s.min_clearance_um;
        Ok(self
            .figures(&liners)?
            .iter()
            .map(|over| zoned_cost(over.points[0].as_ref().ok(), &over.plain[0].metrics, least))
            .collect())
    }

    fn held(&self) -> String {
        let (held, ran) = self.counts();
        format!(" ({held} runs from the cache, {ran} run)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimise::search::{swarm_and_refine, SwarmSettings};
    use crate::optimise::space::Space;

    /// Reversal zones: within 8 mm of either dead centre of an 81 mm stroke.
    const REVERSALS: [(f64, f64); 2] = [(0.0, 8.0), (73.0, 81.0)];

    /// A liner's cost along the stroke known by construction: a texture saves 1 per mm where
    /// the ring reverses (asperity friction it lowers) and costs 1 per mm elsewhere (film
    /// shear it adds). The best liner has a band over each reversal zone, mid-stroke plain.
    fn cost(b: &Banded) -> f64 {
        b.bands
            .iter()
            .map(|band| {
                let over: f64 = REVERSALS
                    .iter()
                    .map(|&(a, e)| (band.end_mm.min(e) - band.start_mm.max(a)).max(0.0))
                    .sum();
                (band.end_mm - band.start_mm) - 2.0 * over
            })
            .sum()
    }

    #[test]
    fn the_search_puts_the_bands_over_the_reversals_and_leaves_mid_stroke_plain() {
        let texture = Space {
            bounds: Default::default(),
            cons: Default::default(),
        };
        let space = BandSpace::new(texture, 81.0, 4.0).unwrap();
        let problem = OverBands {
            space: &space,
            costs: |d: &[Banded]| Ok(d.iter().map(cost).collect()),
        };
        // A band away from its reversal zone costs the same wherever it lies: a plateau the
        // swarm needs a fuller population to leave (24 particles stay on it for the top band).
        let settings = SwarmSettings {
            particles: 40,
            iterations: 30,
            seed: 1,
        };
        let (u, c) = swarm_and_refine(&problem, settings, &[]).unwrap();
        let b = problem.decode(&u);
        // The optimum is −16: each band exactly over its reversal zone.
        assert!(c <= -14.0, "cost {c}: {}", b.label());
        let (top, bottom) = (&b.bands[0], &b.bands[1]);
        assert!(
            top.start_mm <= 1.0 && (6.0..=10.0).contains(&top.end_mm),
            "{}",
            b.label()
        );
        assert!(
            bottom.end_mm >= 80.0 && (71.0..=75.0).contains(&bottom.start_mm),
            "{}",
            b.label()
        );
    }
}
