//! One film problem: a time step (or a steady state) of the Elrod–Adams film with the ring
//! position Z as one more unknown (docs/model.md §3–4; how and why: docs/solver.md).
//!
//! Every node carries one unknown: p on the pressurised set (θ = 1, φ = h) or φ on the
//! cavitated set (p = 0). The complementarity problem is solved by a primal–dual active-set
//! (semi-smooth Newton) iteration ([`newton`]): for a fixed active set the equations are
//! linear, their matrix ([`Stencil5`]) is an M-matrix, solved exactly by a band LU ([`band`])
//! over the x1-range that holds the pressurised nodes; cavitated nodes outside it are exact
//! upwind sweeps. Z is bordered onto the system (Schur complement), so the Newmark coupling is
//! implicit and converged inside the same iteration. Factors are reused where the matrix has
//! hardly changed (`solve/reuse.rs`).
//!
//! [`FilmMethod`] is what a time step asks of a film solver; the product has one,
//! [`FilmSolver`], and the lab crate plugs its experimental solvers in through the same trait.

pub mod band;
mod direct;
#[cfg(test)]
mod gas_tests;
pub mod newton;
mod problem;
mod reuse;
mod stencil5;

pub use direct::FilmSolver;
pub use problem::{
    check_finite, finish, impose_boundary, limit_closing, max_relative_residual, GapCache,
};
pub use reuse::KeptFactors;
pub use stencil5::Stencil5;

use crate::mesh::{FilmState, Gap, Grid};
use crate::model::film::Boundary;
use crate::model::ring::RingLink;

/// One film problem: a time step (inv_dt > 0) or a steady state (inv_dt = 0).
#[derive(Clone, Copy, Debug)]
pub struct Step<'a> {
    pub grid: &'a Grid,
    pub gap: &'a Gap,
    /// φ = hθ at the old time level (ignored when steady).
    pub phi_old: &'a [f64],
    /// 1/dt; 0 for a steady problem.
    pub inv_dt: f64,
    pub boundary: Boundary,
    /// None: Z is held fixed.
    pub ring: Option<RingLink>,
}

impl<'a> Step<'a> {
    /// A steady problem (no storage term, `phi_old` unread) with Z held fixed.
    pub fn steady(grid: &'a Grid, gap: &'a Gap, phi_old: &'a [f64], boundary: Boundary) -> Self {
        Step {
            grid,
            gap,
            phi_old,
            inv_dt: 0.0,
            boundary,
            ring: None,
        }
    }

    /// φ at the old time level, or None for a steady problem.
    pub fn phi_old(&self) -> Option<&[f64]> {
        (self.inv_dt > 0.0).then_some(self.phi_old)
    }

    /// The stencil's advection and storage coefficients adv = u·dy and at = 2·dx·dy/dt
    /// ([`crate::model::film::Column::balance`]).
    pub fn coefficients(&self) -> (f64, f64) {
        let g = self.grid;
        (self.boundary.u * g.dy, 2.0 * g.dx * g.dy * self.inv_dt)
    }
}

/// What a time step asks of a film solver.
pub trait FilmMethod: Send {
    /// Solves one film problem in place: `state` holds the initial guess and receives the
    /// solution; `z` the ring position, updated when the problem carries a ring link.
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError>;

    /// Whether this solver keeps factors for the film problem of the same texture phase one
    /// period later ([`FilmMethod::keep_factors`], [`FilmMethod::inherit_factors`]).
    fn keeps_factors(&self) -> bool {
        false
    }

    /// Takes factors kept from the same texture phase one period earlier, for the next solve.
    fn inherit_factors(&mut self, _kept: &mut KeptFactors) {}

    /// Puts the last solve's factors into `slot` to keep them for one period.
    fn keep_factors(&mut self, _slot: &mut KeptFactors) {}

    /// Whether a step may start from the previous state carried along with the texture
    /// (only a starting point: a solver whose result depends on its start, an inexact one,
    /// starts from the previous state as it is).
    fn carries_guess(&self) -> bool {
        true
    }
}

/// Which product film solver a run uses. Both solve the same discrete problem.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Band LU over the pressurised range, reusing factors where the matrix has hardly
    /// changed (the default).
    #[default]
    Direct,
    /// The plain reference: a band LU of the whole domain in every iteration, nothing reused
    /// (tests compare the direct solver with it).
    Reference,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::Reference => "reference",
        }
    }

    /// A solver of this kind.
    pub fn solver(self) -> Box<dyn FilmMethod> {
        Box::new(FilmSolver::new(self))
    }
}

/// Tolerances of the complementarity/ring iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Converged when the active set no longer changes and the last ring update |δZ| is
    /// below this (µm). The relative error left in p and φ is then at most
    /// `CHORD_CONFIRM` (solve/reuse.rs).
    pub z_abs: f64,
    /// Iteration cap beyond n1 (a cold start moves a cavitation front by about one node per
    /// iteration, and the iteration is monotone for M-matrices, so n1 + this bounds a sound
    /// solve): more means a failed solve (an error, never a number).
    pub extra_iterations: usize,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            z_abs: 1e-10,
            extra_iterations: 60,
        }
    }
}

/// Why a film solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilmError {
    #[error("complementarity iteration did not converge in {iterations} iterations ({changes} active-set changes in the last one, last |δZ| = {dz:.3e} µm, Z = {z:.4e} µm)")]
    NotConverged {
        iterations: usize,
        changes: usize,
        dz: f64,
        z: f64,
    },
    #[error("non-finite {quantity} at x1 = {x1:.5} cm, x2 = {x2:.5} cm")]
    NonFinite {
        quantity: &'static str,
        x1: f64,
        x2: f64,
    },
    #[error("the gap closed (h = {h:.3e} µm at x1 = {x1:.5} cm, x2 = {x2:.5} cm): solid contact is outside the lubrication model")]
    GapClosed { h: f64, x1: f64, x2: f64 },
    #[error("saturation θ = {theta:.6e} outside [0, 1] beyond round-off at x1 = {x1:.5} cm, x2 = {x2:.5} cm")]
    SaturationOutOfRange { theta: f64, x1: f64, x2: f64 },
    #[error("singular film matrix at unknown {row} (pivot {pivot:e})")]
    Singular { row: usize, pivot: f64 },
    /// A solver of the lab crate failed in its own way (its message).
    #[error("{0}")]
    Other(String),
}

/// What one film solve did.
#[derive(Clone, Copy, Debug, Default)]
pub struct SolveStats {
    /// Active-set/Newton iterations (sweeps or cycles for the lab's solvers).
    pub iterations: usize,
    /// Multigrid V-cycles (0 for the band LU).
    pub cycles: usize,
    /// Band LU factorisations: iterations without one were chord steps on factors at hand.
    pub factorisations: usize,
    /// Matrix rows those factorisations eliminated (rows they shared with the factors at
    /// hand were kept).
    pub eliminated_rows: usize,
    /// Largest nodal mass-balance residual after the solve, relative to the largest flux
    /// term at that node (round-off level when converged).
    pub residual: f64,
    /// Hydrodynamic load W_h = (1/B)∫∫_ring p (eq. 16).
    pub w_h: f64,
    /// Asperity load W_a = (1/B)∫∫_ring p_a(h) (docs/model.md §11) of the problem's ring
    /// link's contact; 0 without one.
    pub w_a: f64,
}
