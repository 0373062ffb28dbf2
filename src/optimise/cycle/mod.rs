//! Liners designed over an engine's cycle (docs/model.md §10, §12, §13). Three designs share
//! the engine and search settings ([`CycleSettings`]):
//!
//! - the zones' textures searched over the whole cycle as one transient
//!   (`transient_search`: each candidate from the plain liner's cyclic state, through the
//!   cache and the map search's runner), then the plain, uniform and zoned liners run to their cyclic state
//!   (`transient_liners`) and reported (`transient_report`);
//! - bands next to the dead centres searched over the engine's operating map (`bands`: the
//!   liner and its space; `map_search`: the search and its judge; `map_runs`: its runs
//!   through the cache, handed to a runner here or on a cluster; `map_report`);
//! - the angle-by-angle (quasi-steady) evaluation, each angle a periodic regime
//!   (`angles`, `angles_report`).
//!
//! Every report weighs the plain liner, the best uniform texture and the design, by name
//! (`liner`: `Liner`, `Trio`).

pub mod angles;
pub mod angles_report;
pub mod bands;
mod cells;
pub mod liner;
pub mod map_report;
pub mod map_runs;
pub mod map_search;
pub mod transient_liners;
pub mod transient_report;
pub mod transient_search;

pub use angles::CycleSettings;
