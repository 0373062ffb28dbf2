//! Texture optimisation: the design space mapped feasibly from the unit cube (`space`), what
//! a search minimises (`goal`), and one search layer (`search`: the settings every search
//! shares, the evaluation service through the cache, the `Objective` trait over which the
//! argmin cost is written once, the swarm and its compass refinement). On it run `optimise`
//! for one ring (`driver`; what it reports of its designs `design`, written by
//! `design_report`; designs the reported fidelity cannot tell apart merged by `front_merge`,
//! and its pictures `figures`), over a range of radii (`robust`), and over an engine cycle
//! (`cycle`: the liner's zones through the transient cycle, bands over the engine's operating
//! map, and the angle-by-angle evaluation); what stops them is an `error::OptimiseError`. The
//! simulator knows nothing of this module: every evaluation is a study job or a cycle run
//! through the cache.

pub mod cycle;
pub mod design;
pub mod design_report;
pub mod driver;
pub mod error;
pub mod figures;
pub mod front_merge;
pub mod goal;
pub mod robust;
pub mod search;
pub mod space;
