//! Texture optimisation: the design space mapped feasibly from the unit cube (`space`), what
//! a search minimises (`goal`), and one search layer (`search`: the settings every search
//! shares, the evaluation service through the cache, the `Objective` trait over which the
//! argmin cost is written once, the swarm and its compass refinement). On it run `optimise`
//! for one ring (`driver`; what it reports of its designs `design`, written by
//! `design_report`; designs the reported fidelity cannot tell apart merged by `front_merge`,
//! and its pictures `figures`), over a range of radii (`robust`), and over an engine cycle:
//! angle by angle (`cycle`, `cycle_report`), the liner's zones through the transient cycle
//! (`cycle_search`, `cycle_transient`, `cycle_transient_report`) and bands over the engine's
//! operating map (`bands`, `cycle_map`, its runs through the cache `cycle_runs`, its report
//! `cycle_map_report`); what stops them is an `error::OptimiseError`. The simulator knows
//! nothing of this module: every evaluation is a study job or a cycle run through the cache
//! (the zones' transient search runs directly).

pub mod bands;
pub mod cycle;
pub mod cycle_map;
pub mod cycle_map_report;
pub mod cycle_report;
pub mod cycle_runs;
pub mod cycle_search;
pub mod cycle_transient;
pub mod cycle_transient_report;
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
