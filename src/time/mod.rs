//! Time and workflow (docs/model.md §4–6, §12): the coupled transient stepped to its periodic
//! regime, the steady untextured balance, the numerics and fidelity tiers, what a run
//! reports; and the engine cycle as one transient through the crank angle (`cycle`). The
//! accelerators (period-old guesses, slow-mode jumps, the coarse approach) sit beside the
//! step, outside the physics.

mod anderson;
mod approach;
pub mod characteristic;
mod common;
mod coupled;
pub mod cycle;
mod fallback;
mod fidelity;
mod interpolate;
mod levels;
pub mod limits;
mod memory;
mod numerics;
mod outcome;
mod periodic;
mod resolve;
mod run;
mod schedule;
mod start;
mod stats;
mod steady;
mod stop;
mod transient;
mod uncertainty;
mod window;

#[cfg(test)]
mod tests;

pub use common::{Observers, Progress, SolveError, SteadyError, CONTACT_Z, MASS_TOL};
pub use fallback::BDF2_PATIENCE;
pub use fidelity::{
    unresolved_depth, Fidelity, APPROACH, CHARACTERISTIC_APPROACH, DEEP_MESH, DEEP_POCKET_RATIO,
    POCKET_CELLS, RESOLVED_DEEP_RATIO,
};
pub use limits::Limits;
pub use numerics::{
    short, steps_per_period, Approach, Numerics, Start, TimeScheme, APPROACH_TOL,
    MIN_STEPS_PER_PERIOD,
};
pub use outcome::{Outcome, RunResult, SeriesRow};
pub use resolve::{resolve, Overrides};
pub use run::{simulate, simulate_with, RunOptions};
pub use schedule::{OperatingPoint, Schedule};
pub use start::{equilibrium_start, paper_start};
pub use stats::{ApproachDone, RunStats};
pub use steady::{solve_untextured, steady_outcome, Steady};
pub use transient::{texture_period, Transient, Watch, UNTEXTURED_PERIOD};
pub use uncertainty::{
    needs_uncertainty, AnswerError, Coarse, ErrorSource, MeshUncertainty, MissingUncertainty,
    UNCERTAINTY_FLOOR,
};
pub use window::{window_periods, MIN_WINDOW};
