//! The engine cycle as one transient (docs/model.md §12): the drive the engine imposes, the
//! crank steps, the oil on the liner and the run that steps them.

mod drive;
mod metrics;
mod numerics;
mod oil;
mod run;

pub use drive::{crank_steps, Drive, DrivePoint, StepRule};
pub use metrics::{metrics, CycleMetrics, Regime};
pub use numerics::{cycle_numerics, CONTACT_SHARE, TEXTURE_CELLS};
pub use oil::{Ahead, OilMap, Taken};
pub use run::{
    CycleNumerics, CycleOutcome, CycleRow, CycleRun, CycleState, CycleSummary, OilBalance,
    MAX_HALVINGS, SETTLE_CYCLES,
};
