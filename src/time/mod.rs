//! Time and workflow (docs/model.md §4–6): the coupled transient stepped to its periodic
//! regime, the steady untextured balance, the numerics and fidelity tiers, what a run
//! reports. The accelerators (period-old guesses, slow-mode jumps, the coarse approach) sit
//! beside the step, outside the physics.

mod anderson;
mod approach;
pub mod characteristic;
mod fidelity;
pub mod limits;
mod memory;
mod numerics;
mod outcome;
mod periodic;
mod resolve;
mod run;
mod steady;
mod transient;

#[cfg(test)]
mod tests;

pub use fidelity::{
    unresolved_depth, Fidelity, APPROACH, CHARACTERISTIC_APPROACH, DEEP_MESH, DEEP_POCKET_RATIO,
    POCKET_CELLS, RESOLVED_DEEP_RATIO,
};
pub use limits::Limits;
pub use numerics::{
    short, steps_per_period, Approach, Numerics, Start, TimeScheme, APPROACH_TOL,
    MIN_STEPS_PER_PERIOD,
};
pub use outcome::{Outcome, Progress, RunResult, SeriesRow, SolveError};
pub use periodic::{window_periods, MIN_WINDOW};
pub use resolve::{resolve, Overrides};
pub use run::{simulate, simulate_with, RunOptions, Watch};
pub use steady::{solve_untextured, steady_outcome, Steady, SteadyError};
pub use transient::{
    equilibrium_start, paper_start, texture_period, ApproachDone, Transient, BDF2_PATIENCE,
    CONTACT_Z, MASS_TOL, UNTEXTURED_PERIOD,
};
