//! texopt's lab: solvers and studies beside the product. The solvers run through the
//! product's [`texopt::solve::FilmMethod`] trait on its one stencil; the studies (speed
//! against accuracy, mesh convergence, stability) are run by the `texopt-lab` binary and
//! write under results/.

pub mod line_multigrid;
pub mod liner_frame;
pub mod liner_friction;
pub mod pt_multigrid;
pub mod solvers;
pub mod stencil;
pub mod studies;
