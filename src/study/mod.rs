//! Many evaluations: study files expanded into cases, engine files read, the persistent
//! evaluation cache, the parallel runner through it, the study report, and the benchmark.

pub mod bench;
pub mod cache;
pub mod cache_merge;
pub mod cycle_cache;
pub mod engine_file;
mod entry;
pub mod file;
mod file_error;
mod file_keys;
mod operating_figures;
pub mod report;
pub mod shard;
pub mod sweep;
mod wal;

pub use file::{load, parse, Job, NumericsOverride, Study, StudyError};
