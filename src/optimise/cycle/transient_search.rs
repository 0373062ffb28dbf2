//! The zones' textures searched over the engine cycle as one transient (docs/model.md §12,
//! "Designing over the cycle"): each candidate is judged by the friction work of the whole
//! cycle, dead centres included, with its zone textured and the rest of the liner plain.
//!
//! A candidate's run starts from the plain liner's cyclic state (film, ring and oil map at the
//! cycle's start) and runs [`SETTLE_CYCLES`] cycles, after which it is settled; its cost is the
//! last cycle's work over the plain liner's.

use std::sync::Mutex;

use super::angles::{CycleSettings, Designs};
use super::transient_liners::ring_case;
use crate::model::case::Texture;
use crate::model::engine::Engine;
use crate::model::liner_layout::LinerLayout;
use crate::optimise::error::OptimiseError;
use crate::optimise::goal::FAILED_COST;
use crate::optimise::search::{swarm, Objective};
use crate::optimise::space::Space;
use crate::study::cache::Key;
use crate::study::cycle_cache::CycleRunInputs;
use crate::time::cycle::CycleWatch;
use crate::time::cycle::{
    cycle_numerics, metrics, CycleMetrics, CycleNumerics, CycleRow, CycleRun, CycleState, Drive,
    SETTLE_CYCLES,
};
use crate::time::Fidelity;

/// Share by which a liner's least film may fall below the plain liner's where that is already
/// below the least clearance: the tiers' error on the least film is about 1 % (§12), within
/// which the two cannot be told apart (docs/model.md §12, "Designing over the cycle").
pub const FILM_TOLERANCE: f64 = 0.01;

/// Whether a liner's least film `h_um` keeps the least clearance `least_um`, or where the plain
/// liner's `plain_um` is below it, the plain liner's within [`FILM_TOLERANCE`].
pub fn keeps_film(h_um: f64, plain_um: f64, least_um: f64) -> bool {
    if plain_um >= least_um {
        h_um >= least_um
    } else {
        h_um >= plain_um * (1.0 - FILM_TOLERANCE)
    }
}

/// The figures of a cycle's `rows` on `engine`, with work per zone of a liner layout's
/// `bounds_cm` (cm).
pub fn metrics_over(rows: &[CycleRow], engine: &Engine, bounds_cm: &[f64]) -> CycleMetrics {
    let bounds_mm: Vec<f64> = bounds_cm.iter().map(|x| 10.0 * x).collect();
    metrics(rows, engine, &bounds_mm)
}

/// The plain liner's cyclic run: its figures, its last cycle and its end state.
pub struct PlainAt {
    pub metrics: CycleMetrics,
    pub rows: Vec<CycleRow>,
    end: CycleState,
}

/// A liner's run from the plain liner's cyclic state: its last cycle's figures and rows.
pub struct Judged {
    pub metrics: CycleMetrics,
    pub rows: Vec<CycleRow>,
}

/// Runs liners of one engine through the cycle at the search's fidelity, each from the plain
/// liner's cyclic state (computed once: the cells along x1, which a resumed run shares, do
/// not depend on the texture, and a plain liner is one cell across).
pub struct CycleJudge<'a> {
    s: &'a CycleSettings,
    engine: Engine,
    drive: Drive,
    fidelity: Fidelity,
    /// Cycles a judged liner runs from the plain liner's state (None: until it repeats
    /// itself, as the plain liner does).
    settle: Option<usize>,
    plain: Mutex<Option<std::sync::Arc<PlainAt>>>,
}

impl<'a> CycleJudge<'a> {
    /// The judge of the settings' engine.
    pub fn new(s: &'a CycleSettings) -> Self {
        Self::at(s, s.engine.clone())
    }

    /// The judge of `engine` (a point of the settings' engine's map) with the settings'
    /// search.
    pub fn at(s: &'a CycleSettings, engine: Engine) -> Self {
        CycleJudge {
            s,
            drive: Drive::new(&engine),
            engine,
            fidelity: s.search.search_fidelity,
            settle: Some(SETTLE_CYCLES),
            plain: Mutex::new(None),
        }
    }

    /// The same judge at the report's fidelity, each liner run until it repeats itself.
    pub fn reporting(self) -> Self {
        CycleJudge {
            fidelity: self.s.search.report_fidelity,
            settle: None,
            ..self
        }
    }

    fn numerics(&self, layout: &LinerLayout) -> CycleNumerics {
        let finest = layout
            .textures()
            .iter()
            .flatten()
            .min_by(|a, b| a.per.total_cmp(&b.per));
        let ring = ring_case(self.s, &self.drive);
        cycle_numerics(self.fidelity, &self.s.search.overrides, &ring, finest)
    }

    fn layout(&self, textures: Vec<Option<Texture>>) -> Result<LinerLayout, OptimiseError> {
        Ok(LinerLayout::zoned(self.s.zones.bounds_cm(), textures)?)
    }

    /// The figures of a cycle's rows, with work per zone of `bounds_cm` (None: the engine's
    /// zones).
    pub fn metrics(&self, rows: &[CycleRow], bounds_cm: Option<&[f64]>) -> CycleMetrics {
        match bounds_cm {
            None => metrics(rows, &self.engine, self.s.zones.bounds_mm()),
            Some(b) => metrics_over(rows, &self.engine, b),
        }
    }

    /// Whether this judge runs each liner until it repeats itself (the report's), so that its
    /// runs keep their cycles' rows.
    pub fn reports(&self) -> bool {
        self.settle.is_none()
    }

    /// The engine at this judge's point.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The numerics `layout` is judged with: the tier's, with the judge's settle rule.
    fn settled(&self, layout: &LinerLayout) -> CycleNumerics {
        CycleNumerics {
            settle: self.settle,
            ..self.numerics(layout)
        }
    }

    /// The cache key of `layout`'s run by this judge: the point's engine, the ring, the liner,
    /// the numerics and the settle rule.
    pub fn key(&self, layout: &LinerLayout) -> Key {
        Key::of_cycle(&CycleRunInputs {
            engine: &self.engine.file,
            ring: &ring_case(self.s, &self.drive),
            layout,
            numerics: &self.settled(layout).keyed(),
            settle: self.settle,
        })
    }

    /// The plain liner with `numerics`, run until it repeats itself (once).
    fn plain(&self, numerics: &CycleNumerics) -> Result<std::sync::Arc<PlainAt>, OptimiseError> {
        let mut plain = self.plain.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = plain.as_ref() {
            return Ok(p.clone());
        }
        let zones = self.s.zones.count();
        let layout = self.layout(vec![None; zones])?;
        let ring = ring_case(self.s, &self.drive);
        let o = CycleRun::new(&self.drive, ring, layout, numerics.clone())
            .and_then(|r| r.run(CycleWatch::default()))
            .map_err(|source| OptimiseError::RunOf {
                label: "plain liner".into(),
                source,
            })?;
        let p = std::sync::Arc::new(PlainAt {
            metrics: self.metrics(&o.rows, None),
            rows: o.rows,
            end: o.end,
        });
        *plain = Some(p.clone());
        Ok(p)
    }

    /// The plain liner on `layout`'s mesh, run until it repeats itself (once).
    pub fn plain_of(&self, layout: &LinerLayout) -> Result<std::sync::Arc<PlainAt>, OptimiseError> {
        self.plain(&self.numerics(layout))
    }

    /// `layout` judged from the plain liner's cyclic state: its last cycle (work per zone of
    /// `zones_cm` where given, else of the engine's), an error where its run fails, and the plain liner's on the same mesh (the outer error: the plain liner itself
    /// failed, which no design mends).
    #[allow(clippy::type_complexity)]
    pub fn judge_layout(
        &self,
        layout: LinerLayout,
        zones_cm: Option<&[f64]>,
    ) -> Result<(Result<Judged, OptimiseError>, std::sync::Arc<PlainAt>), OptimiseError> {
        let plain = self.plain(&self.numerics(&layout))?;
        let numerics = self.settled(&layout);
        let ring = ring_case(self.s, &self.drive);
        let judged = CycleRun::resume(&self.drive, ring, layout, numerics, &plain.end)
            .and_then(|r| r.run(CycleWatch::default()))
            .map(|o| Judged {
                metrics: self.metrics(&o.rows, zones_cm),
                rows: o.rows,
            })
            .map_err(OptimiseError::Run);
        Ok((judged, plain))
    }
}

/// A zoned liner's cost: its work over the plain liner's, or `FAILED_COST` where its run
/// failed (`judged` None) or its least film does not [`keeps_film`].
pub fn zoned_cost(judged: Option<&CycleMetrics>, plain: &CycleMetrics, least_um: f64) -> f64 {
    match judged {
        Some(t) if keeps_film(t.h_min_um, plain.h_min_um, least_um) => {
            t.work_j_per_m / plain.work_j_per_m
        }
        _ => FAILED_COST,
    }
}

/// Who weighs the zone search's liners (a texture per zone, None: plain): each one's
/// [`zoned_cost`], its runs looked up in the evaluation cache and the missing ones run
/// (the map search's judge, through its runner: here or a cluster's tasks).
pub trait ZonedCosts: Sync {
    fn costs(&self, liners: &[Vec<Option<Texture>>]) -> Result<Vec<f64>, OptimiseError>;
    /// What a progress line adds: runs answered by the cache and runs made, so far.
    fn held(&self) -> String;
}

/// One zone's search: the liner with that zone textured, the others plain.
struct ZoneOverCycle<'a> {
    s: &'a CycleSettings,
    judge: &'a dyn ZonedCosts,
    zone: usize,
}

impl Objective for ZoneOverCycle<'_> {
    fn space(&self) -> &Space {
        &self.s.search.space
    }

    fn costs(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        let zones = self.s.zones.count();
        let liners: Vec<Vec<Option<Texture>>> = designs
            .iter()
            .map(|t| {
                let mut textures = vec![None; zones];
                textures[self.zone] = Some(t.clone());
                textures
            })
            .collect();
        self.judge.costs(&liners)
    }
}

/// Every zone's texture searched over the cycle as one transient; the uniform candidate is
/// the zones' best textures laid over the whole stroke, the one of least work. Each liner is
/// weighed by `judge`: through the cache, a search repeated over it runs nothing.
pub fn design_over_cycle(
    s: &CycleSettings,
    judge: &dyn ZonedCosts,
) -> Result<Designs, OptimiseError> {
    let t0 = std::time::Instant::now();
    let say = s.search.say_since(t0);
    let held = |j: &dyn ZonedCosts| j.held();
    let zones = s.zones.count();
    let (mut found, mut candidates) = (Vec::new(), Vec::new());
    for zone in 0..zones {
        say(format!(
            "zone {} of {zones}: searching over the cycle at {} …",
            zone + 1,
            s.search.search_fidelity.name()
        ));
        let problem = ZoneOverCycle { s, judge, zone };
        // The swarm alone: each candidate costs two cycles of the transient, and the compass
        // polish that follows `optimise`'s swarms would take twice the swarm's evaluations
        // again.
        let (u, ratio) = swarm(&problem, s.search.swarm)?;
        if ratio >= FAILED_COST {
            say(format!(
                "zone {}: every candidate failed or thinned the film below {:.3} µm (or 1 % below the plain liner's where that is thinner): plain",
                zone + 1,
                s.min_clearance_um
            ));
            found.push(None);
            candidates.push(None);
            continue;
        }
        let t = s.search.space.decode(&u);
        say(format!(
            "zone {}: {}, work ratio {ratio:.5}{}{}",
            zone + 1,
            t.rounded_label(),
            if ratio < 1.0 {
                ""
            } else {
                " (no better than plain)"
            },
            held(judge)
        ));
        found.push((ratio < 1.0).then(|| t.clone()));
        candidates.push(Some(t));
    }
    // The uniform liner: each distinct zone design over the whole stroke.
    let mut distinct: Vec<Texture> = Vec::new();
    for t in candidates.iter().flatten() {
        if !distinct.contains(t) {
            distinct.push(t.clone());
        }
    }
    say(format!(
        "uniform liner: the {} zone design(s) over the whole stroke …",
        distinct.len()
    ));
    let liners: Vec<Vec<Option<Texture>>> = distinct
        .iter()
        .map(|t| vec![Some(t.clone()); zones])
        .collect();
    let costs = judge.costs(&liners)?;
    let best = (0..distinct.len())
        .filter(|&k| costs[k] < FAILED_COST)
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]));
    let uniform_candidate = best.map(|k| distinct[k].clone());
    if let Some(k) = best {
        say(format!(
            "uniform: {}, work ratio {:.5}{}",
            distinct[k].rounded_label(),
            costs[k],
            held(judge)
        ));
    }
    Ok(Designs {
        zones: found,
        uniform: best
            .filter(|&k| costs[k] < 1.0)
            .map(|k| distinct[k].clone()),
        candidates,
        uniform_candidate,
    })
}
