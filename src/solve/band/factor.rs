//! Band LU elimination without pivoting, reusing the leading rows an operator shares with
//! factors at hand.

use super::{BandLu, KeptBand, KeptLu, SingularPivot};
use crate::solve::stencil5::Stencil5;

impl BandLu {
    /// Memory held by the factors and the operator they are of (bytes).
    pub fn bytes(&self) -> usize {
        8 * (self.a.capacity() + 5 * self.orig.c.capacity())
    }

    /// LU factorisation of the 5-point operator `s` (unit lower L below the diagonal, U on
    /// and above). Elimination never changes a row from the rows after it, so the leading
    /// rows `s` shares bit for bit with the operator factored last keep their factors and
    /// only the rest is eliminated: the film's flooded inlet bank, untouched by Z, is
    /// factored once per time step instead of once per Newton iteration. Same bits as a
    /// full factorisation. Rows are compared on the stencil (5 numbers), not on the band.
    /// Returns the number of rows eliminated (those not kept).
    pub fn factor(&mut self, s: &Stencil5) -> Result<usize, SingularPivot> {
        let r0 = self.shared_rows(s);
        self.rounded &= r0 > 0;
        // The operator factored: its rows before r0 are already those of `s`.
        self.orig.reshape(s.m1, s.n2);
        for (o, v) in self
            .orig
            .coefficients_mut()
            .into_iter()
            .zip(s.coefficients())
        {
            o[r0..].copy_from_slice(&v[r0..]);
        }
        self.factor_orig_from(r0)
    }

    /// `factor`, taking the operator instead of copying it: `s` is left holding the one
    /// factored before (of any shape), for the caller to overwrite. The same factors, bit
    /// for bit; for a caller that assembles a whole new operator every time (the film
    /// solver), it saves copying five arrays per factorisation.
    pub fn factor_taking(&mut self, s: &mut Stencil5) -> Result<usize, SingularPivot> {
        self.factor_taking_reusing(s, None)
    }

    /// `factor_taking`, which may also take the leading rows `s` shares with `kept`'s
    /// operator from those factors (when they share more rows than the factors at hand): the
    /// film's factors of the same texture phase a period ago share the rows the texture alone
    /// sets. Rows from double-precision kept factors are the same bits as eliminating them;
    /// from single ones they are widened, and the factors are then [`BandLu::rounded`].
    pub fn factor_taking_reusing(
        &mut self,
        s: &mut Stencil5,
        kept: Option<&KeptLu>,
    ) -> Result<usize, SingularPivot> {
        let own = self.shared_rows(s);
        let from_kept = kept.map_or(0, |k| k.shared_rows(s));
        std::mem::swap(&mut self.orig, s);
        match kept {
            Some(k) if from_kept > own => {
                let rows = ..from_kept * (2 * k.w + 1);
                self.a.resize(self.orig.len() * (2 * k.w + 1), 0.0);
                match &k.band {
                    KeptBand::Double(b) => self.a[rows].copy_from_slice(&b[rows]),
                    KeptBand::Single(b) => {
                        for (a, &v) in self.a[rows].iter_mut().zip(&b[rows]) {
                            *a = f64::from(v);
                        }
                    }
                }
                self.rounded = k.rounded();
                self.factor_orig_from(from_kept)
            }
            _ => {
                // Rows kept from the factors at hand keep their precision.
                self.rounded &= own > 0;
                self.factor_orig_from(own)
            }
        }
    }

    /// The half band width (cells across) of the factors.
    pub fn half_band(&self) -> usize {
        self.w
    }

    /// Whether the factors are those of their operator only to ≈ 1e-7 (rows taken from
    /// single-precision kept factors), not to round-off.
    pub fn rounded(&self) -> bool {
        self.rounded
    }

    /// Leading rows `s` shares bit for bit with the operator of the factors at hand (none
    /// when they are invalid or of another band).
    pub(super) fn shared_rows(&self, s: &Stencil5) -> usize {
        if self.valid {
            shared_rows(&self.orig, self.n, self.w, s)
        } else {
            0
        }
    }

    /// Factors `orig`, whose rows before r0 are those of the factors at hand.
    fn factor_orig_from(&mut self, r0: usize) -> Result<usize, SingularPivot> {
        let s = &self.orig;
        let (n, w) = (s.len(), s.n2);
        let stride = 2 * w + 1;
        self.n = n;
        self.w = w;
        self.a.resize(n * stride, 0.0);
        // The band rows from r0 on: the stencil's five entries (0.0 + v: the bits an
        // accumulation into a zeroed band gives, −0.0 included), zeros elsewhere.
        // j = r mod w, the row's x2 index, carried along (no division per row).
        let mut j = r0 % w.max(1);
        // One fill for all the rows (per row it was a library call of a few dozen bytes).
        self.a[r0 * stride..n * stride].fill(0.0);
        for (r, row) in self.a[r0 * stride..n * stride]
            .chunks_exact_mut(stride)
            .enumerate()
            .map(|(t, row)| (r0 + t, row))
        {
            row[w] = 0.0 + s.c[r];
            if r >= w {
                row[0] = 0.0 + s.w[r];
            }
            if r + w < n {
                row[2 * w] = 0.0 + s.e[r];
            }
            if j > 0 {
                row[w - 1] += s.s[r];
            }
            if j + 1 < w {
                row[w + 1] += s.n[r];
            }
            j = if j + 1 == w { 0 } else { j + 1 };
        }
        self.valid = false;
        // Band widths of the tiers (8, 32) and of raised meshes get their own instance, in
        // which a row update has a fixed length: unrolled and vectorised, the same bits.
        match w {
            8 => self.eliminate_from::<8>(r0)?,
            16 => self.eliminate_from::<16>(r0)?,
            24 => self.eliminate_from::<24>(r0)?,
            32 => self.eliminate_from::<32>(r0)?,
            _ => self.eliminate_from::<0>(r0)?,
        }
        self.valid = true;
        Ok(n - r0)
    }

    /// Right-looking elimination of rows r0.. (rows before r0 hold their final factors),
    /// two pivots at a time: each row takes the updates of pivots k and k+1 in one pass
    /// over its band (half the loads and stores of one pass per pivot), in the same order
    /// and with the same operations as one pivot at a time, so the factors are the same
    /// bits. Each row sees its updates in the order of a full factorisation.
    /// W: the band width when known at compile time (0: only at run time); pivot pairs
    /// whose rows span the full band then update rows of fixed length.
    fn eliminate_from<const W: usize>(&mut self, r0: usize) -> Result<(), SingularPivot> {
        let (n, w) = (self.n, self.w);
        debug_assert!(W == 0 || W == w);
        let stride = 2 * w + 1;
        let a = &mut self.a;
        let inverse_pivot = |a: &[f64], k: usize| {
            let piv = a[k * stride + w];
            if piv.is_finite() && piv != 0.0 {
                Ok(1.0 / piv)
            } else {
                Err(SingularPivot { row: k, value: piv })
            }
        };
        let mut k = r0.saturating_sub(w);
        while k < n {
            let inv_k = inverse_pivot(a, k)?;
            if k + 1 == n {
                break;
            }
            let last_k = (k + w).min(n - 1);
            // Row k+1 takes pivot k alone: it must be final before it serves as a pivot.
            if k + 1 >= r0 {
                let (head, tail) = a.split_at_mut((k + 1) * stride);
                let uk = &head[k * stride + w + 1..k * stride + w + 1 + (last_k - k)];
                let row = &mut tail[..stride];
                let l = row[w - 1] * inv_k;
                if l != 0.0 {
                    row[w - 1] = l;
                    sub_scaled(&mut row[w..w + (last_k - k)], l, uk);
                }
            }
            let inv_k1 = inverse_pivot(a, k + 1)?;
            let last_k1 = (k + 1 + w).min(n - 1);
            // Both pivots' rows span the full band (then last_k = k + w too).
            let full = W > 0 && last_k1 == k + 1 + W;
            if full {
                update_rows_full::<W>(a, k, r0, inv_k, inv_k1);
                k += 2;
                continue;
            }
            let (head, tail) = a.split_at_mut((k + 2) * stride);
            // U rows k (columns k+1..=last_k) and k+1 (columns k+2..=last_k1).
            let uk = &head[k * stride + w + 1..k * stride + w + 1 + (last_k - k)];
            let uk1 = &head[(k + 1) * stride + w + 1..(k + 1) * stride + w + 1 + (last_k1 - k - 1)];
            for i in (k + 2).max(r0)..=last_k1 {
                let row = &mut tail[(i - k - 2) * stride..(i - k - 1) * stride];
                // Column c of row i sits at c + w − i; column k+1 at c1.
                let c1 = k + 1 + w - i;
                let (l1, l2) = multipliers(row, c1, i <= last_k, inv_k, inv_k1, uk[0]);
                // Columns k+2..=last_k take both pivots, columns up to last_k1 only k+1.
                let both = if i <= last_k { last_k - k - 1 } else { 0 };
                let x = &mut row[c1 + 1..c1 + 1 + (last_k1 - k - 1)];
                match (l1 != 0.0, l2 != 0.0) {
                    (true, true) => {
                        let (xb, xr) = x.split_at_mut(both);
                        for ((x, &u), &v) in xb.iter_mut().zip(&uk[1..]).zip(uk1) {
                            *x = (*x - l1 * u) - l2 * v;
                        }
                        sub_scaled(xr, l2, &uk1[both..]);
                    }
                    (true, false) => sub_scaled(&mut x[..both], l1, &uk[1..]),
                    (false, true) => sub_scaled(x, l2, uk1),
                    (false, false) => {}
                }
            }
            k += 2;
        }
        Ok(())
    }
}

/// Leading rows `s` shares bit for bit with `orig`, the n × (half band w) operator of some
/// complete factors (none when the band differs); a reused row must also have seen the same
/// (untruncated) elimination updates, hence the margin before the end.
pub(super) fn shared_rows(orig: &Stencil5, n_orig: usize, w_orig: usize, s: &Stencil5) -> usize {
    let (n, w) = (s.len(), s.n2);
    let mut r0 = 0;
    if w == w_orig && n_orig > 0 {
        let limit = n.min(n_orig).saturating_sub(w + 1);
        let o = orig;
        let same = |x: f64, y: f64| x.to_bits() == y.to_bits();
        while r0 < limit
            && same(s.c[r0], o.c[r0])
            && same(s.w[r0], o.w[r0])
            && same(s.e[r0], o.e[r0])
            && same(s.s[r0], o.s[r0])
            && same(s.n[r0], o.n[r0])
        {
            r0 += 1;
        }
    }
    r0
}

/// The multipliers of pivots k and k + 1 in a row whose column k + 1 sits at c1 (column k
/// before it, when pivot k reaches the row), stored in place of the entries they eliminate;
/// pivot k's update of column k + 1 is applied first, as a full factorisation does. A zero
/// multiplier leaves the row as it is.
#[inline(always)]
fn multipliers(
    row: &mut [f64],
    c1: usize,
    reaches_k: bool,
    inv_k: f64,
    inv_k1: f64,
    uk_first: f64,
) -> (f64, f64) {
    let mut l1 = 0.0;
    if reaches_k {
        l1 = row[c1 - 1] * inv_k;
        if l1 != 0.0 {
            row[c1 - 1] = l1;
            row[c1] -= l1 * uk_first;
        }
    }
    let l2 = row[c1] * inv_k1;
    if l2 != 0.0 {
        row[c1] = l2;
    }
    (l1, l2)
}

/// The W rows below pivots k and k + 1 take both pivots' updates when both pivots' rows
/// span the full band of width W (compile-time): the general path's operations in the same
/// order, over rows of fixed length (2W + 1) so that no index is checked per row. Rows
/// before r0 hold their final factors and are left alone.
#[inline(always)]
fn update_rows_full<const W: usize>(a: &mut [f64], k: usize, r0: usize, inv_k: f64, inv_k1: f64) {
    let stride = 2 * W + 1;
    let (head, tail) = a.split_at_mut((k + 2) * stride);
    // U rows k (columns k+1..=k+W) and k+1 (columns k+2..=k+1+W).
    let uk = &head[k * stride + W + 1..k * stride + 2 * W + 1];
    let uk1 = &head[(k + 1) * stride + W + 1..(k + 1) * stride + 2 * W + 1];
    let skip = r0.saturating_sub(k + 2);
    for (t, row) in tail[..W * stride]
        .chunks_exact_mut(stride)
        .enumerate()
        .skip(skip)
    {
        // Row k+2+t: column k+1 sits at c1 = W − 1 − t; pivot k reaches rows up to k + W.
        let c1 = W - 1 - t;
        let (l1, l2) = multipliers(row, c1, t + 1 < W, inv_k, inv_k1, uk[0]);
        update_pair::<W>(&mut row[c1 + 1..c1 + 1 + W], l1, l2, &uk[1..], uk1);
    }
}

/// The row update of a pivot pair over a full band of width W (x: the W columns after
/// pivot k+1): columns before the last take l1·u_k then l2·u_{k+1}, the last only
/// l2·u_{k+1} (l1 = 0 for rows below pivot k's reach). The operations of the general path in
/// the same order, with lengths fixed at compile time.
#[inline(always)]
fn update_pair<const W: usize>(x: &mut [f64], l1: f64, l2: f64, uk_tail: &[f64], uk1: &[f64]) {
    let x = &mut x[..W];
    let uk1 = &uk1[..W];
    let ukt = &uk_tail[..W - 1];
    match (l1 != 0.0, l2 != 0.0) {
        (true, true) => {
            for t in 0..W - 1 {
                x[t] = (x[t] - l1 * ukt[t]) - l2 * uk1[t];
            }
            x[W - 1] -= l2 * uk1[W - 1];
        }
        (true, false) => {
            for t in 0..W - 1 {
                x[t] -= l1 * ukt[t];
            }
        }
        (false, true) => {
            for t in 0..W {
                x[t] -= l2 * uk1[t];
            }
        }
        (false, false) => {}
    }
}

/// x −= l·u, element by element.
#[inline]
fn sub_scaled(x: &mut [f64], l: f64, u: &[f64]) {
    for (x, &u) in x.iter_mut().zip(u) {
        *x -= l * u;
    }
}
