//! The engine cycle as one transient (docs/model.md §12): the drive the engine imposes, the
//! crank steps, the oil on the liner and the run that steps them.

mod drive;
mod oil;
mod run;

pub use drive::{crank_steps, Drive, DrivePoint, StepRule};
pub use oil::{Ahead, OilMap, Taken};
pub use run::{CycleNumerics, CycleOutcome, CycleRow, CycleRun, CycleSummary, OilBalance};
