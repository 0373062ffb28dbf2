//! The physics (docs/model.md): scales, geometry of ring and liner, the case's inputs and their
//! validity, the film equation and its stencil, the ring's dynamics and the friction terms.
//! Nothing here knows a mesh beyond the stencil's column of nodes, nor how anything is solved.

pub mod asperity;
pub mod case;
pub mod engine;
pub mod film;
pub mod flow_factors;
pub mod friction;
pub mod geometry;
pub mod input;
pub mod liner_layout;
pub mod operating;
pub mod ring;
pub mod scales;
pub mod units;
