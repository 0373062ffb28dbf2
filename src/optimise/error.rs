//! What can stop a search, a cycle design or their reports. A design whose run fails is not
//! an error here: it is data (its reason is reported, its cost is `FAILED_COST`).

use crate::model::case::InputError;
use crate::output::OutputError;
use crate::study::cache::CacheError;
use crate::study::sweep::CaseFailure;

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
    #[error("the plain liner failed: {0}")]
    PlainFailed(CaseFailure),
    /// argmin's own failure.
    #[error("{0}")]
    Solver(String),
    /// A search (or its refinement) that ended without a best point.
    #[error("the {0} ended without a best design")]
    NoBest(&'static str),
    #[error("cannot start {jobs} worker threads: {why}")]
    Threads { jobs: usize, why: String },
    /// Nothing to report: no design (it names the list that was empty).
    #[error("no {0}")]
    Nothing(&'static str),
    /// No crank angle of the cycle lies inside the model (the message names the first ones).
    #[error("{0}")]
    NoAngleInside(String),
    /// The run of a report's time series failed.
    #[error("{0}")]
    Series(String),
    /// A batch of cycle runs handed to other processes (a cluster's tasks) that failed, did
    /// not answer, or was asked of a process with other settings.
    #[error("{0}")]
    Runs(String),
    /// A report file or figure could not be written.
    #[error("{0}")]
    Files(String),
    /// A report file could not be written (the output layer's error).
    #[error("{0}")]
    Output(#[from] OutputError),
}
