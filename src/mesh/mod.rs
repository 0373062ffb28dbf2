//! The discretised contact (docs/model.md §2–3): the grid, the gap over it, the texture placed
//! at a time, the film fields, and integrals over the film (load, friction, flows).

mod faces;
mod fields;
mod fitted;
mod gap;
mod grid;
pub mod integrals;
mod rows;
mod scene;

pub use faces::face_conductances;
pub use fields::{cavity_pressures, FilmState};
pub use fitted::{FaceFit, FittedFaces};
pub use gap::Gap;
pub use grid::Grid;
pub use rows::{sample_across, RimModel, Rows};
pub use scene::Scene;
