//! Factors kept for later solves: exchanged whole, or copied in single precision.

use super::factor::shared_rows;
use super::solve::{solve2_in, solve_in};
use super::{BandLu, KeptBand, KeptLu};
use crate::solve::stencil5::Stencil5;

impl KeptLu {
    /// Keeps a single-precision copy of `lu`'s factors (complete ones; otherwise none),
    /// reusing this copy's memory.
    pub fn keep_single(&mut self, lu: &BandLu) {
        let len = lu.n * (2 * lu.w + 1);
        let valid = lu.valid && lu.a.len() >= len;
        (self.n, self.w) = if valid { (lu.n, lu.w) } else { (0, 0) };
        let a = lu.a[..if valid { len } else { 0 }]
            .iter()
            .map(|&v| v as f32);
        match &mut self.band {
            KeptBand::Single(b) => {
                b.clear();
                b.extend(a);
            }
            band => *band = KeptBand::Single(a.collect()),
        }
        self.rounded_rows = false;
        self.orig.reshape(lu.orig.m1, lu.orig.n2);
        for (o, v) in self
            .orig
            .coefficients_mut()
            .into_iter()
            .zip(lu.orig.coefficients())
        {
            o.copy_from_slice(v);
        }
    }

    /// Exchanges the factors held here with `lu`'s, in double precision and without a copy:
    /// these keep `lu`'s (if complete), and `lu` takes the double ones held here, the same
    /// bits and valid for their operator (single or no factors leave `lu` with none).
    pub fn exchange(&mut self, lu: &mut BandLu) {
        let held = match &mut self.band {
            KeptBand::Double(b) if self.n > 0 => Some(std::mem::take(b)),
            _ => None,
        };
        let (held_n, held_w, held_rounded) = (self.n, self.w, self.rounded_rows);
        (self.n, self.w) = if lu.valid { (lu.n, lu.w) } else { (0, 0) };
        self.rounded_rows = lu.rounded;
        std::mem::swap(&mut self.orig, &mut lu.orig);
        let valid = held.is_some();
        self.band = KeptBand::Double(std::mem::replace(&mut lu.a, held.unwrap_or_default()));
        (lu.n, lu.w) = if valid { (held_n, held_w) } else { (0, 0) };
        lu.valid = valid;
        lu.rounded = valid && held_rounded;
    }

    /// Whether these factors are single precision (they solve their matrix to ≈ 1e-7).
    pub fn is_single(&self) -> bool {
        matches!(self.band, KeptBand::Single(_))
    }

    /// Whether these factors solve their matrix only to ≈ 1e-7 (single precision, whole or
    /// in part).
    pub fn rounded(&self) -> bool {
        self.is_single() || self.rounded_rows
    }

    /// Memory held by the factors and the operator they are of (bytes).
    pub fn bytes(&self) -> usize {
        let band = match &self.band {
            KeptBand::Double(b) => 8 * b.capacity(),
            KeptBand::Single(b) => 4 * b.capacity(),
        };
        band + 8 * 5 * self.orig.c.capacity()
    }

    /// Solves A x = b in place with the kept factors.
    pub fn solve(&self, b: &mut [f64]) {
        match &self.band {
            KeptBand::Double(a) => solve_in(a, self.n, self.w, b),
            KeptBand::Single(a) => solve_in(a, self.n, self.w, b),
        }
    }

    /// [`BandLu::solve2`] with the kept factors.
    pub fn solve2(&self, b1: &mut [f64], b2: &mut [f64], work: &mut Vec<[f64; 2]>) {
        match &self.band {
            KeptBand::Double(a) => solve2_in(a, self.n, self.w, b1, b2, work),
            KeptBand::Single(a) => solve2_in(a, self.n, self.w, b1, b2, work),
        }
    }

    pub(super) fn shared_rows(&self, s: &Stencil5) -> usize {
        shared_rows(&self.orig, self.n, self.w, s)
    }
}
