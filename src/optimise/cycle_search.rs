//! The zones' textures searched over the engine cycle as one transient (docs/model.md §12,
//! "Designing over the cycle"): each candidate is judged by the friction work of the whole
//! cycle, dead centres included, with its zone textured and the rest of the liner plain.
//!
//! A candidate's run starts from the plain liner's cyclic state (film, ring and oil map at the
//! cycle's start) and runs [`SETTLE_CYCLES`] cycles, after which it is settled; its cost is the
//! last cycle's work over the plain liner's.

use std::sync::Mutex;

use rayon::prelude::*;

use super::cycle::{CycleSettings, Designs};
use super::cycle_transient::ring_case;
use super::error::OptimiseError;
use super::goal::FAILED_COST;
use super::search::{swarm, Objective};
use super::space::Space;
use crate::model::case::Texture;
use crate::model::liner_layout::LinerLayout;
use crate::time::cycle::{
    cycle_numerics, metrics, CycleNumerics, CycleRun, CycleState, Drive, SETTLE_CYCLES,
};
use crate::time::Fidelity;

/// The plain liner's cyclic run: its friction work (J/m), least film (µm) and end state.
struct PlainAt {
    work: f64,
    h_min_um: f64,
    end: CycleState,
}

/// What a candidate's run gave: the friction work of its last cycle (J/m) and its least
/// film (µm).
struct Judged {
    work: f64,
    h_min_um: f64,
}

/// Runs liners through the cycle at the search's fidelity, each from the plain liner's
/// cyclic state (computed once: the cells along x1, which a resumed run shares, do not depend
/// on the texture, and a plain liner is one cell across).
pub struct CycleJudge<'a> {
    s: &'a CycleSettings,
    drive: Drive,
    fidelity: Fidelity,
    plain: Mutex<Option<std::sync::Arc<PlainAt>>>,
}

impl<'a> CycleJudge<'a> {
    pub fn new(s: &'a CycleSettings) -> Self {
        CycleJudge {
            s,
            drive: Drive::new(&s.engine),
            fidelity: s.search.search_fidelity,
            plain: Mutex::new(None),
        }
    }

    fn numerics(&self, textures: &[Option<Texture>]) -> CycleNumerics {
        let finest = textures
            .iter()
            .flatten()
            .min_by(|a, b| a.per.total_cmp(&b.per));
        let ring = ring_case(self.s, &self.drive);
        cycle_numerics(self.fidelity, &self.s.search.overrides, &ring, finest)
    }

    fn layout(&self, textures: Vec<Option<Texture>>) -> Result<LinerLayout, OptimiseError> {
        let bounds_cm: Vec<f64> = self.s.engine.bounds_mm.iter().map(|b| 0.1 * b).collect();
        LinerLayout::zoned(bounds_cm, textures).map_err(|e| OptimiseError::Series(e.to_string()))
    }

    /// The plain liner with `numerics`, run until it repeats itself (once).
    fn plain(&self, numerics: &CycleNumerics) -> Result<std::sync::Arc<PlainAt>, OptimiseError> {
        let mut plain = self.plain.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = plain.as_ref() {
            return Ok(p.clone());
        }
        let zones = self.s.engine.bounds_mm.len() - 1;
        let layout = self.layout(vec![None; zones])?;
        let ring = ring_case(self.s, &self.drive);
        let o = CycleRun::new(&self.drive, ring, layout, numerics.clone())
            .and_then(|r| r.run(&mut |_| {}, &mut |_| {}))
            .map_err(|e| OptimiseError::Series(format!("plain liner: {e}")))?;
        let m = metrics(&o.rows, &self.s.engine);
        let p = std::sync::Arc::new(PlainAt {
            work: m.work_j_per_m,
            h_min_um: m.h_min_um,
            end: o.end,
        });
        *plain = Some(p.clone());
        Ok(p)
    }

    /// The liner of zone `textures` judged from the plain liner's cyclic state: its last
    /// cycle's work and least film (an error where its run fails), and the plain liner's on
    /// the same mesh (the outer error: the plain liner itself failed, which no design mends).
    #[allow(clippy::type_complexity)]
    fn judge(
        &self,
        textures: Vec<Option<Texture>>,
    ) -> Result<(Result<Judged, OptimiseError>, Judged), OptimiseError> {
        let mut numerics = self.numerics(&textures);
        let plain = self.plain(&numerics)?;
        numerics.max_cycles = SETTLE_CYCLES;
        let layout = self.layout(textures)?;
        let ring = ring_case(self.s, &self.drive);
        let judged = CycleRun::resume(&self.drive, ring, layout, numerics, &plain.end)
            .and_then(|r| r.run(&mut |_| {}, &mut |_| {}))
            .map(|o| {
                let m = metrics(&o.rows, &self.s.engine);
                Judged {
                    work: m.work_j_per_m,
                    h_min_um: m.h_min_um,
                }
            })
            .map_err(|e| OptimiseError::Series(e.to_string()));
        let plain = Judged {
            work: plain.work,
            h_min_um: plain.h_min_um,
        };
        Ok((judged, plain))
    }

    /// A liner's cost: its work over the plain liner's, or [`FAILED_COST`] where its run
    /// fails or its least film falls below both the least clearance and the plain liner's.
    fn cost(&self, textures: Vec<Option<Texture>>) -> Result<f64, OptimiseError> {
        let (judged, p) = self.judge(textures)?;
        Ok(match judged {
            Ok(t) if t.h_min_um >= self.s.min_clearance_um.min(p.h_min_um) => t.work / p.work,
            _ => FAILED_COST,
        })
    }
}

/// One zone's search: the liner with that zone textured, the others plain.
struct ZoneOverCycle<'a, 'b> {
    judge: &'b CycleJudge<'a>,
    zone: usize,
}

impl Objective for ZoneOverCycle<'_, '_> {
    fn space(&self) -> &Space {
        &self.judge.s.search.space
    }

    fn costs(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        let zones = self.judge.s.engine.bounds_mm.len() - 1;
        designs
            .par_iter()
            .map(|t| {
                let mut textures = vec![None; zones];
                textures[self.zone] = Some(t.clone());
                self.judge.cost(textures)
            })
            .collect()
    }
}

/// Every zone's texture searched over the cycle as one transient; the uniform candidate is
/// the zones' best textures laid over the whole stroke, the one of least work.
pub fn design_over_cycle(s: &CycleSettings) -> Result<Designs, OptimiseError> {
    let t0 = std::time::Instant::now();
    let say = |m: String| {
        if s.search.progress {
            eprintln!("[{:6.1} s] {m}", t0.elapsed().as_secs_f64());
        }
    };
    let judge = CycleJudge::new(s);
    let zones = s.engine.bounds_mm.len() - 1;
    let (mut found, mut candidates) = (Vec::new(), Vec::new());
    for zone in 0..zones {
        say(format!(
            "zone {} of {zones}: searching over the cycle at {} …",
            zone + 1,
            judge.fidelity.name()
        ));
        let problem = ZoneOverCycle {
            judge: &judge,
            zone,
        };
        // The swarm alone: each candidate costs two cycles of the transient, and the compass
        // polish that follows `optimise`'s swarms would take twice the swarm's evaluations
        // again.
        let (u, ratio) = swarm(&problem, s.search.swarm)?;
        if ratio >= FAILED_COST {
            say(format!(
                "zone {}: every candidate failed or thinned the film below {} µm and the plain liner's least film: plain",
                zone + 1,
                s.min_clearance_um
            ));
            found.push(None);
            candidates.push(None);
            continue;
        }
        let t = s.search.space.decode(&u);
        say(format!(
            "zone {}: {}, work ratio {ratio:.5}{}",
            zone + 1,
            t.rounded_label(),
            if ratio < 1.0 {
                ""
            } else {
                " (no better than plain)"
            }
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
    let costs: Vec<f64> = distinct
        .par_iter()
        .map(|t| judge.cost(vec![Some(t.clone()); zones]))
        .collect::<Result<_, _>>()?;
    let best = (0..distinct.len())
        .filter(|&k| costs[k] < FAILED_COST)
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]));
    let uniform_candidate = best.map(|k| distinct[k].clone());
    if let Some(k) = best {
        say(format!(
            "uniform: {}, work ratio {:.5}",
            distinct[k].rounded_label(),
            costs[k]
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
