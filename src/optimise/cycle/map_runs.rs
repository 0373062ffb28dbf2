//! The map search's cycle runs, and its report's, through the evaluation cache (docs/model.md
//! §13, "Scale"): each liner at each operating point is one run, keyed by everything that
//! determines it.
//! A batch of liners is looked up first; the runs missing are handed to a [`Runner`], which
//! stores their answers (or why each failed) in the cache: here, on this machine's threads,
//! or elsewhere (a cluster's tasks, each into a cache of its own merged back). The search
//! then reads every answer from the cache, so a rerun, or another machine's share, gives the
//! same numbers.

use std::sync::Mutex;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::bands::Banded;
use super::transient_search::CycleJudge;
use crate::model::case::Texture;
use crate::model::liner_layout::{LayoutError, LinerLayout};
use crate::optimise::error::{OptimiseError, RunsError};
use crate::study::cache::{Cache, Key};
use crate::study::cycle_cache::{CycleAnswer, CycleFailure};

/// A liner a batch runs: banded, one texture over the whole stroke, or a texture per zone
/// (the zone search's; `bounds_cm` from top dead centre, one more than `textures`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MapLiner {
    Banded(Banded),
    Uniform(Texture),
    Zoned {
        bounds_cm: Vec<f64>,
        textures: Vec<Option<Texture>>,
    },
}

impl MapLiner {
    pub fn layout(&self, stroke_mm: f64) -> Result<LinerLayout, LayoutError> {
        Ok(match self {
            MapLiner::Banded(b) => b.layout(stroke_mm),
            MapLiner::Uniform(t) => LinerLayout::uniform(0.1 * stroke_mm, Some(t.clone())),
            MapLiner::Zoned {
                bounds_cm,
                textures,
            } => LinerLayout::zoned(bounds_cm.clone(), textures.clone())?,
        })
    }
}

/// One run of a batch: a liner (its index) at a point of the map (its index), and the key
/// its answer is stored under.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapRun {
    pub liner: usize,
    pub point: usize,
    pub key: String,
}

/// The runs a search step (or the report) needs that the cache does not hold, point by
/// point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapBatch {
    pub liners: Vec<MapLiner>,
    pub runs: Vec<MapRun>,
    /// The report's runs: at the report's fidelity, each until it repeats itself, its rows
    /// kept.
    #[serde(default)]
    pub report: bool,
}

impl MapBatch {
    /// Share `i` of `n` (1-based): a contiguous run of about len/n runs. The runs are in
    /// point order, so a share meets few points and runs few plain liners.
    pub fn share(&self, i: usize, n: usize) -> &[MapRun] {
        let len = self.runs.len();
        let (lo, hi) = ((i - 1) * len / n, i * len / n);
        &self.runs[lo..hi]
    }
}

/// What a runner needs of the judge whose batch it runs (the map search's judge).
pub trait BatchJudge: Sync {
    /// The judge of point `k`.
    fn point(&self, k: usize) -> Option<&CycleJudge<'_>>;
    fn stroke_mm(&self) -> f64;
    /// The cache the batch's answers go to.
    fn cache(&self) -> Result<&Mutex<Cache>, OptimiseError>;
    /// Whether to say what the runner is doing.
    fn progress(&self) -> bool;
}

/// Who runs a batch: every run's answer (or why it failed) stored in the judge's cache.
pub trait Runner: Sync {
    fn run(&self, judge: &dyn BatchJudge, batch: &MapBatch) -> Result<(), OptimiseError>;
}

/// Runs a batch on this machine's threads.
pub struct Here;

impl Runner for Here {
    fn run(&self, judge: &dyn BatchJudge, batch: &MapBatch) -> Result<(), OptimiseError> {
        run_here(judge, batch, &batch.runs, judge.cache()?).map(|_| ())
    }
}

/// `runs` of `batch` run here, each answer stored in `cache` as it comes; those `cache`
/// already holds (a task run again) are skipped. Refused before anything runs: a run whose
/// key differs from the one this judge gives it (the batch was made with other settings).
/// Returns how many were run.
pub fn run_here(
    judge: &dyn BatchJudge,
    batch: &MapBatch,
    runs: &[MapRun],
    cache: &Mutex<Cache>,
) -> Result<usize, OptimiseError> {
    let stroke_mm = judge.stroke_mm();
    let mut todo = Vec::new();
    for r in runs {
        let (Some(liner), Some(point)) = (batch.liners.get(r.liner), judge.point(r.point)) else {
            return Err(RunsError::NotInBatch {
                liner: r.liner,
                point: r.point,
            }
            .into());
        };
        let layout = liner.layout(stroke_mm)?;
        let key = point.key(&layout);
        if key.hash != r.key {
            return Err(RunsError::OtherKey {
                key: r.key.chars().take(12).collect(),
                liner: r.liner,
                point: r.point,
            }
            .into());
        }
        if lock(cache).get_cycle(&key)?.is_none() {
            todo.push((layout, point, key));
        }
    }
    todo.par_iter()
        .map(|(layout, point, key)| {
            let t0 = std::time::Instant::now();
            let (judged, _) = point.judge_layout(layout.clone(), None)?;
            let wall_time_s = t0.elapsed().as_secs_f64();
            let answer = judged
                .map(|j| CycleAnswer {
                    metrics: j.metrics,
                    rows: point.reports().then_some(j.rows),
                    wall_time_s,
                })
                .map_err(|e| (e.to_string(), wall_time_s));
            lock(cache)
                .put_cycle(key, &answer)
                .map_err(OptimiseError::Cache)
        })
        .collect::<Result<Vec<()>, _>>()?;
    Ok(todo.len())
}

pub use crate::study::cache::lock;

/// The answer the cache holds for `key`, or the error that says it has none.
pub(super) fn stored(
    cache: &Mutex<Cache>,
    key: &Key,
) -> Result<Result<CycleAnswer, CycleFailure>, OptimiseError> {
    lock(cache).get_cycle(key)?.ok_or_else(|| {
        RunsError::NoAnswer {
            key: key.hash[..12].to_string(),
        }
        .into()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shares_of_a_batch_are_disjoint_and_cover_it() {
        for len in [0, 1, 5, 17] {
            let batch = MapBatch {
                report: false,
                liners: Vec::new(),
                runs: (0..len)
                    .map(|k| MapRun {
                        liner: k,
                        point: 0,
                        key: k.to_string(),
                    })
                    .collect(),
            };
            for n in [1, 2, 4, 7] {
                let all: Vec<usize> = (1..=n)
                    .flat_map(|i| batch.share(i, n).iter().map(|r| r.liner))
                    .collect();
                assert_eq!(all, (0..len).collect::<Vec<_>>(), "len {len}, n {n}");
                let sizes: Vec<usize> = (1..=n).map(|i| batch.share(i, n).len()).collect();
                let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(hi - lo <= 1, "len {len}, n {n}: {sizes:?}");
            }
        }
    }
}
