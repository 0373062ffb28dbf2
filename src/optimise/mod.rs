//! Texture optimisation for one ring: the design space mapped feasibly from the unit cube,
//! the goals, the searches through argmin, the driver and its report. The simulator knows
//! nothing of this module: every evaluation is a study job run through the cache.

pub mod driver;
pub mod space;
