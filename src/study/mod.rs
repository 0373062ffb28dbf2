//! Many evaluations: study files expanded into cases, the persistent evaluation cache, the
//! parallel runner through it, the study report, and the benchmark.

pub mod bench;
pub mod cache;
pub mod cache_merge;
mod entry;
pub mod file;
mod operating_figures;
pub mod report;
pub mod shard;
pub mod sweep;
mod wal;

pub use file::{load, parse, Job, NumericsOverride, Study, StudyError};
