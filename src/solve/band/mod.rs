//! Banded LU without pivoting, for the M-matrices of the film solver.
//!
//! The film Jacobian for a fixed active set is a nonsingular M-matrix (positive diagonal,
//! non-positive off-diagonals, column diagonal dominance), so Gaussian elimination without
//! pivoting is stable and keeps the band. The matrix comes as a 5-point operator
//! ([`Stencil5`], node (i, j) at i·n2 + j), so its half bandwidth is n2. The factors are
//! stored row-major: row r holds columns r−w..=r+w.
//!
//! `factor.rs` eliminates (reusing the leading rows an operator shares with factors at
//! hand), `solve.rs` substitutes, `kept.rs` keeps factors for later solves (in single
//! precision where memory counts).

use super::stencil5::Stencil5;

mod factor;
mod kept;
mod solve;

use solve::{solve2_in, solve_in};

#[derive(Debug, Default, Clone)]
pub struct BandLu {
    n: usize,
    w: usize,
    /// The factors (L below the diagonal, U on and above), row-major band.
    a: Vec<f64>,
    /// The operator `a` was factored from, to find the rows a new one shares with it.
    orig: Stencil5,
    /// Whether `a` holds complete factors of `orig`.
    valid: bool,
    /// Whether some rows of `a` were taken from single-precision kept factors
    /// ([`BandLu::factor_taking_reusing`]): the factors are then those of `orig` to ≈ 1e-7
    /// relative, not to round-off.
    rounded: bool,
}

/// Band LU factors kept for later solves (the film keeps one set per step of a texture
/// period, time/memory.rs): a [`BandLu`]'s own, exchanged without a copy ([`KeptLu::exchange`]), or,
/// to halve the memory, a single-precision copy ([`KeptLu::keep_single`]). Solves with single
/// factors read them widened and sum in double, so they solve the factored matrix to ≈ 1e-7
/// relative: as a chord step through factors of a nearby matrix does, which is all the film
/// asks of kept factors. Invariant: n > 0 exactly when complete factors of `orig` are held.
#[derive(Debug, Default, Clone)]
pub struct KeptLu {
    n: usize,
    w: usize,
    band: KeptBand,
    /// The operator the factors are of, to find the rows a new one shares with it.
    orig: Stencil5,
    /// Double factors holding rows taken from single ones ([`BandLu::rounded`]).
    rounded_rows: bool,
}

#[derive(Debug, Clone)]
enum KeptBand {
    Double(Vec<f64>),
    Single(Vec<f32>),
}

impl Default for KeptBand {
    fn default() -> Self {
        KeptBand::Double(Vec::new())
    }
}

/// A zero or non-finite pivot: the matrix is singular (should not happen for an M-matrix).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularPivot {
    pub row: usize,
    pub value: f64,
}

impl BandLu {
    /// Solves A x = b in place (after `factor`).
    pub fn solve(&self, b: &mut [f64]) {
        solve_in(&self.a, self.n, self.w, b);
    }

    /// Solves A x = b1 and A x = b2 in place together (each row of the factors is read
    /// once for both): the same arithmetic as two `solve` calls, so the same bits. `work`
    /// holds the two right-hand sides interleaved while they are solved (see `solve.rs`).
    pub fn solve2(&self, b1: &mut [f64], b2: &mut [f64], work: &mut Vec<[f64; 2]>) {
        solve2_in(&self.a, self.n, self.w, b1, b2, work);
    }
}

#[cfg(test)]
mod tests;
