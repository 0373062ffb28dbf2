//! The engine cycle as one transient (docs/model.md §12): the drive the engine imposes, the
//! crank steps, the oil on the liner and the run that steps them.

mod drive;
mod metrics;
mod oil;
mod record;
mod stepping;
mod tiers;

pub use drive::{crank_steps, Drive, DrivePoint, StepRule};
pub use metrics::{metrics, whole_stroke, CycleMetrics, Regime};
pub use oil::{Ahead, OilMap, Taken};
pub use record::{CycleRow, CycleSummary, OilBalance};
pub use stepping::{CycleOutcome, CycleRun, CycleState, CycleWatch, MAX_HALVINGS, SETTLE_CYCLES};
pub use tiers::{cycle_numerics, CycleEnd, CycleNumerics, CONTACT_SHARE, TEXTURE_CELLS};
