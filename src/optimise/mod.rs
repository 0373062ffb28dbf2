//! Texture optimisation for one ring: the design space mapped feasibly from the unit cube
//! (`space`), what a search minimises (`goal`), the searches through argmin (`search`), the
//! driver (`driver`), its report (`design_report`, with designs the reported fidelity cannot tell
//! apart merged by `front_merge`) and its pictures (`figures`). The simulator knows nothing of this module:
//! every evaluation is a study job run through the cache.

pub mod cycle;
pub mod cycle_report;
pub mod design_report;
pub mod driver;
pub mod error;
pub mod figures;
pub mod front_merge;
pub mod goal;
pub mod robust;
pub mod search;
pub mod space;
