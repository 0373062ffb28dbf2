//! Transient cycle runs in the evaluation cache: a liner's run at one operating point, from
//! the plain liner's cyclic state, keyed by everything that determines it (the point's engine,
//! the ring, the liner, the numerics and the cycles run) and holding its figures. The entries
//! sit beside the film evaluations in the same table, so merging, clearing, export and stats
//! treat them alike; their keys cannot meet a film evaluation's.

use serde::{Deserialize, Serialize};

use super::cache::{Cache, CacheError, Key, Stored, MODEL_VERSION};
use super::entry;
use crate::model::case::CaseSpec;
use crate::model::engine::EngineFile;
use crate::model::liner_layout::LinerLayout;
use crate::time::cycle::{CycleMetrics, CycleNumerics, CycleRow};

/// A cycle run as its key holds it: everything that determines its answer.
#[derive(Serialize)]
pub struct CycleRunInputs<'a> {
    /// The engine as it runs at the point (its map's changes applied).
    pub engine: &'a EngineFile,
    /// The ring's case (roughness and contact).
    pub ring: &'a CaseSpec,
    pub layout: &'a LinerLayout,
    pub numerics: &'a CycleNumerics,
    /// Cycles run from the plain liner's cyclic state (None: until it repeats itself).
    pub settle: Option<usize>,
}

#[derive(Serialize)]
struct CycleKey<'a> {
    model: &'a str,
    cycle: &'a CycleRunInputs<'a>,
}

/// What the cache keeps of a finished cycle run: its figures, and the last cycle step by step
/// where a report draws it (None for a search's run).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CycleAnswer {
    pub metrics: CycleMetrics,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rows: Option<Vec<CycleRow>>,
    pub wall_time_s: f64,
}

/// Why a cycle run has no answer to give.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CycleFailure {
    /// The run failed: the cache keeps its error in the run's own words (the typed error
    /// does not outlive the process that ran it, a cluster's task among them).
    #[error("{0}")]
    Failed(String),
    /// The cache holds the run without its cycle's rows (a search's run), which a report
    /// reads.
    #[error("the cache holds this run without its cycle (a search's run)")]
    WithoutRows,
    /// The liner was not run (a report's row for a liner the search did not make).
    #[error("not run")]
    NotRun,
}

/// A report writes a failure as its words.
impl Serialize for CycleFailure {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl Key {
    /// The key of a cycle run.
    pub fn of_cycle(run: &CycleRunInputs) -> Key {
        let json = serde_json::to_string(&CycleKey {
            model: MODEL_VERSION,
            cycle: run,
        })
        .expect("plain data serialises");
        Key {
            hash: entry::hash_of(&json),
            json,
        }
    }
}

impl Cache {
    /// The cycle run stored for `key`: its answer, or why it failed. None where nothing is
    /// stored, or what is stored is damaged or of an older layout (the run is done again and
    /// replaces it).
    pub fn get_cycle(
        &self,
        key: &Key,
    ) -> Result<Option<Result<CycleAnswer, CycleFailure>>, CacheError> {
        Ok(match self.get_as::<CycleAnswer>(key)? {
            Some(Stored::Done(a)) => Some(Ok(a)),
            Some(Stored::Failed(why)) => Some(Err(CycleFailure::Failed(why))),
            Some(Stored::Unreadable | Stored::Damaged(_)) | None => None,
        })
    }

    /// Stores a cycle run's answer, or why it failed (after `wall_time_s`).
    pub fn put_cycle(
        &self,
        key: &Key,
        answer: &Result<CycleAnswer, (String, f64)>,
    ) -> Result<(), CacheError> {
        match answer {
            Ok(a) => {
                let json = serde_json::to_string(a).expect("plain data");
                self.put(key, Ok(&json), a.wall_time_s, 0)
            }
            Err((why, wall)) => self.put(key, Err(why), *wall, 0),
        }
    }
}
