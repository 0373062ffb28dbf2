//! What can stop a search, a cycle design or their reports. A design whose run fails is not
//! an error here: it is data (its reason is reported, its cost is `FAILED_COST`).

use crate::time::MissingUncertainty;
use std::path::PathBuf;

use crate::finite::NonFinite;
use crate::model::case::InputError;
use crate::model::liner_layout::LayoutError;
use crate::optimise::cycle::angles::NoAngleInside;
use crate::output::OutputError;
use crate::study::cache::CacheError;
use crate::study::sweep::CaseFailure;
use crate::time::SolveError;

#[derive(Debug, thiserror::Error)]
pub enum OptimiseError {
    /// A design's numerics are invalid for its case.
    #[error("{case}: {error}")]
    Numerics { case: String, error: InputError },
    /// The design space's bounds or constraints are inconsistent.
    #[error("{0}")]
    Space(InputError),
    /// The evaluation cache could not be read or written.
    #[error("{0}")]
    Cache(#[from] CacheError),
    #[error("stopped (Ctrl-C); finished evaluations are in the cache")]
    Stopped,
    #[error(transparent)]
    Uncertainty(#[from] MissingUncertainty),
    #[error("the plain liner failed: {0}")]
    PlainFailed(CaseFailure),
    /// argmin's own failure.
    #[error("{0}")]
    Solver(argmin::core::Error),
    /// A search (or its refinement) that ended without a best point.
    #[error("the {0} ended without a best design")]
    NoBest(&'static str),
    #[error("cannot start {jobs} worker threads: {source}")]
    Threads {
        jobs: usize,
        source: rayon::ThreadPoolBuildError,
    },
    /// Nothing to report: no design (it names the list that was empty).
    #[error("no {0}")]
    Nothing(&'static str),
    /// No crank angle of the cycle lies inside the model (it names the first ones).
    #[error("{0}")]
    NoAngleInside(NoAngleInside),
    /// A run the search or its report needs failed (a report's time series, a liner's cycle).
    #[error("{0}")]
    Run(SolveError),
    /// The same, of the run `label` names.
    #[error("{label}: {source}")]
    RunOf { label: String, source: SolveError },
    /// A liner's zones do not fit its textures.
    #[error("{0}")]
    Layout(#[from] LayoutError),
    /// A batch of cycle runs handed to a runner that failed, did not answer, or was asked of
    /// a process with other settings.
    #[error("{0}")]
    Runs(#[from] RunsError),
    /// A report's directory could not be made.
    #[error("cannot create {}: {source}", .dir.display())]
    CreateDir {
        dir: PathBuf,
        source: std::io::Error,
    },
    /// A report could not be serialised (`path`: the file it was for, where named).
    #[error("{0}")]
    Json(serde_json::Error),
    #[error("{}: {source}", .path.display())]
    JsonAt {
        path: PathBuf,
        source: serde_json::Error,
    },
    /// A report's CSV could not be written.
    #[error("{0}")]
    Csv(std::io::Error),
    #[error("{}: {source}", .path.display())]
    CsvAt {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A report holds a number that is not finite (nothing of it is written).
    #[error("the report's {0} is not a finite number; nothing printed or written")]
    NonFinite(#[from] NonFinite),
    /// A report file could not be written (the output layer's error).
    #[error("{0}")]
    Output(#[from] OutputError),
}

/// Why a batch of cycle runs handed to a runner gave no answers.
#[derive(Debug, thiserror::Error)]
pub enum RunsError {
    #[error("the batch names liner {liner} at point {point}, which it does not hold")]
    NotInBatch { liner: usize, point: usize },
    /// `key`: the run's key as the batch gives it (its first 12 characters).
    #[error("run {key} (liner {liner} at point {point}): this process's settings give it another key than the batch's; run it with the engine file and flags of the search that wrote the batch")]
    OtherKey {
        key: String,
        liner: usize,
        point: usize,
    },
    #[error("no answer in the cache for run {key} after its batch ran (a task that stopped early? its log says why)")]
    NoAnswer { key: String },
    #[error("this judge has no cache to run through")]
    NoCache,
    /// A runner elsewhere (a cluster's array) failed at batch `batch`, in its own words.
    #[error("batch {batch}: {why}")]
    Elsewhere { batch: usize, why: String },
}
