//! Banded LU without pivoting, for the M-matrices of the film solver.
//!
//! The film Jacobian for a fixed active set is a nonsingular M-matrix (positive diagonal,
//! non-positive off-diagonals, column diagonal dominance), so Gaussian elimination without
//! pivoting is stable and keeps the band. The matrix comes as a 5-point operator
//! ([`Stencil5`], node (i, j) at i·n2 + j), so its half bandwidth is n2. The factors are
//! stored row-major: row r holds columns r−w..=r+w.

use crate::multigrid::Stencil5;

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
/// period, run.rs): a [`BandLu`]'s own, exchanged without a copy ([`KeptLu::exchange`]), or,
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
    fn shared_rows(&self, s: &Stencil5) -> usize {
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

    /// Solves A x = b in place (after `factor`).
    pub fn solve(&self, b: &mut [f64]) {
        solve_in(&self.a, self.n, self.w, b);
    }

    /// Solves A x = b1 and A x = b2 in place together (each row of the factors is read
    /// once for both): the same arithmetic as two `solve` calls, so the same bits. `work`
    /// holds the two right-hand sides interleaved while they are solved (see [`dot_pairs`]).
    pub fn solve2(&self, b1: &mut [f64], b2: &mut [f64], work: &mut Vec<[f64; 2]>) {
        solve2_in(&self.a, self.n, self.w, b1, b2, work);
    }
}

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

    fn shared_rows(&self, s: &Stencil5) -> usize {
        shared_rows(&self.orig, self.n, self.w, s)
    }
}

/// Leading rows `s` shares bit for bit with `orig`, the n × (half band w) operator of some
/// complete factors (none when the band differs); a reused row must also have seen the same
/// (untruncated) elimination updates, hence the margin before the end.
fn shared_rows(orig: &Stencil5, n_orig: usize, w_orig: usize, s: &Stencil5) -> usize {
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

/// A stored factor entry: the arithmetic is in f64 whatever the storage.
trait Entry: Copy {
    fn widen(self) -> f64;
}

impl Entry for f64 {
    #[inline(always)]
    fn widen(self) -> f64 {
        self
    }
}

impl Entry for f32 {
    #[inline(always)]
    fn widen(self) -> f64 {
        f64::from(self)
    }
}

/// Forward and back substitution through the n × (half band w) factors `a`.
fn solve_in<T: Entry>(a: &[T], n: usize, w: usize, b: &mut [f64]) {
    let stride = 2 * w + 1;
    for i in 0..n {
        let first = i.saturating_sub(w);
        let row = &a[i * stride..(i + 1) * stride];
        let l = &row[first + w - i..w];
        b[i] -= dot(l, &b[first..i]);
    }
    for i in (0..n).rev() {
        let last = (i + w).min(n - 1);
        let row = &a[i * stride..(i + 1) * stride];
        let u = &row[w + 1..w + 1 + (last - i)];
        b[i] = (b[i] - dot(u, &b[i + 1..=last])) / row[w].widen();
    }
}

/// Two substitutions at once (see [`BandLu::solve2`]).
fn solve2_in<T: Entry>(
    a: &[T],
    n: usize,
    w: usize,
    b1: &mut [f64],
    b2: &mut [f64],
    work: &mut Vec<[f64; 2]>,
) {
    assert!(b1.len() >= n && b2.len() >= n);
    work.clear();
    work.extend(b1[..n].iter().zip(&b2[..n]).map(|(&x, &y)| [x, y]));
    match w {
        8 => solve_pairs::<T, 8>(a, n, w, work),
        16 => solve_pairs::<T, 16>(a, n, w, work),
        24 => solve_pairs::<T, 24>(a, n, w, work),
        32 => solve_pairs::<T, 32>(a, n, w, work),
        _ => solve_pairs::<T, 0>(a, n, w, work),
    }
    for ((x, y), &[u, v]) in b1.iter_mut().zip(b2.iter_mut()).zip(work.iter()) {
        (*x, *y) = (u, v);
    }
}

/// `solve2` on interleaved right-hand sides, with the band width W known at compile
/// time (0: only at run time): rows spanning the full band take dot products of fixed
/// length (the same sums in the same order, so the same bits).
fn solve_pairs<T: Entry, const W: usize>(a: &[T], n: usize, w: usize, xy: &mut [[f64; 2]]) {
    debug_assert!(W == 0 || W == w);
    let stride = 2 * w + 1;
    // With W known, rows whose band lies whole inside the matrix (i ≥ W forward,
    // i + W < n backward) are taken as fixed-length chunks: no index checked per row.
    let full_from = if W > 0 { W.min(n) } else { n };
    for i in 0..full_from {
        let first = i.saturating_sub(w);
        let row = &a[i * stride..(i + 1) * stride];
        let d = dot_pairs(&row[first + w - i..w], &xy[first..i]);
        xy[i] = [xy[i][0] - d[0], xy[i][1] - d[1]];
    }
    if W > 0 {
        let rows = a[full_from * stride..n * stride].chunks_exact(2 * W + 1);
        for (i, row) in (full_from..).zip(rows) {
            let d = dot_pairs(&row[..W], &xy[i - W..i]);
            xy[i] = [xy[i][0] - d[0], xy[i][1] - d[1]];
        }
    }
    let full_to = if W > 0 { n.saturating_sub(W) } else { 0 };
    for i in (full_to..n).rev() {
        let last = (i + w).min(n - 1);
        let row = &a[i * stride..(i + 1) * stride];
        let d = dot_pairs(&row[w + 1..w + 1 + (last - i)], &xy[i + 1..=last]);
        let piv = row[w].widen();
        xy[i] = [(xy[i][0] - d[0]) / piv, (xy[i][1] - d[1]) / piv];
    }
    if W > 0 {
        let rows = a[..full_to * stride].chunks_exact(2 * W + 1);
        for (i, row) in rows.enumerate().rev() {
            let d = dot_pairs(&row[W + 1..], &xy[i + 1..i + 1 + W]);
            let piv = row[W].widen();
            xy[i] = [(xy[i][0] - d[0]) / piv, (xy[i][1] - d[1]) / piv];
        }
    }
}

/// Σ a_k·x_k in four interleaved partial sums: a substitution row is a dot product of up to
/// w = N2 terms, and one running sum would chain their additions (latency-bound: the back
/// substitution's row i waits on row i + 1 from its first term). Four sums let the terms
/// proceed in parallel; the order is fixed, so the result is deterministic.
#[inline]
fn dot<T: Entry>(a: &[T], x: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (ac, ar) = a.split_at(a.len() & !3);
    let (xc, xr) = x.split_at(ac.len());
    for (a4, x4) in ac.chunks_exact(4).zip(xc.chunks_exact(4)) {
        for l in 0..4 {
            acc[l] += a4[l].widen() * x4[l];
        }
    }
    for (l, (a, x)) in ar.iter().zip(xr).enumerate() {
        acc[l] += a.widen() * x;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// `dot` for two vectors held as pairs (x_k, y_k), against the same coefficients: each
/// lane is that vector's `dot`, the same sums in the same order. Interleaved, each term is
/// one two-lane multiply and add of a_k against the pair. With the vectors apart the
/// compiler paired their lanes by shuffles on every term and spilled the partial sums:
/// Case III at `paper` spent 18.98 G instructions in `solve2`, now 13.29 G (valgrind); at
/// 360 × 32 (`examples/band_micro.rs`) a substitution with the factors in cache takes
/// ≈ 15–25 % less time, ≈ 5–15 % less when they come from memory.
#[inline(always)]
fn dot_pairs<T: Entry>(a: &[T], xy: &[[f64; 2]]) -> [f64; 2] {
    let mut acc = [[0.0f64; 2]; 4];
    let (ac, ar) = a.split_at(a.len() & !3);
    let (xc, xr) = xy.split_at(ac.len());
    for (a4, x4) in ac.chunks_exact(4).zip(xc.chunks_exact(4)) {
        for l in 0..4 {
            let a = a4[l].widen();
            acc[l][0] += a * x4[l][0];
            acc[l][1] += a * x4[l][1];
        }
    }
    for (l, (a, x)) in ar.iter().zip(xr).enumerate() {
        let a = a.widen();
        acc[l][0] += a * x[0];
        acc[l][1] += a * x[1];
    }
    let lane = |m: usize| (acc[0][m] + acc[1][m]) + (acc[2][m] + acc[3][m]);
    [lane(0), lane(1)]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5-point M-matrix on an nx×ny grid (node (i, j) at i·ny + j) whose diagonal from row
    /// `from` on is raised by `bump` (a Z change under the ring, seen by the trailing rows
    /// only). Some couplings are zero, as for cavitated neighbours in the film.
    fn laplacian(nx: usize, ny: usize, from: usize, bump: f64) -> Stencil5 {
        let mut s = Stencil5::default();
        s.reset(nx, ny);
        for i in 0..nx {
            for j in 0..ny {
                let r = i * ny + j;
                s.c[r] = 4.5 + 0.1 * (r as f64).sin() + if r >= from { bump } else { 0.0 };
                if i > 0 {
                    s.w[r] = -1.0 - 0.05 * (r as f64).cos();
                }
                if i + 1 < nx && r % 5 != 3 {
                    s.e[r] = -1.2;
                }
                if j > 0 {
                    s.s[r] = -0.9;
                }
                if j + 1 < ny && r % 7 != 2 {
                    s.n[r] = -1.0;
                }
            }
        }
        s
    }

    /// The plain band elimination, one pivot at a time (the order the factors must match).
    fn reference_factors(s: &Stencil5) -> Vec<f64> {
        let (n, w) = (s.len(), s.n2);
        let stride = 2 * w + 1;
        let mut a = vec![0.0; n * stride];
        for r in 0..n {
            a[r * stride + w] += s.c[r];
            if r >= w {
                a[r * stride] += s.w[r];
            }
            if r + w < n {
                a[r * stride + 2 * w] += s.e[r];
            }
            if r % w > 0 {
                a[r * stride + w - 1] += s.s[r];
            }
            if r % w + 1 < w {
                a[r * stride + w + 1] += s.n[r];
            }
        }
        for k in 0..n {
            let inv = 1.0 / a[k * stride + w];
            let last = (k + w).min(n - 1);
            for i in k + 1..=last {
                let l = a[i * stride + k + w - i] * inv;
                if l == 0.0 {
                    continue;
                }
                a[i * stride + k + w - i] = l;
                for c in k + 1..=last {
                    a[i * stride + c + w - i] -= l * a[k * stride + c + w - k];
                }
            }
        }
        a
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn two_pivots_at_a_time_give_the_plain_factors_bit_for_bit() {
        // Odd and even row counts (the pair loop's end), bands 1..7, zero couplings.
        // Widths 8, 16, 24 and 32 take the fixed-length path in the band's interior.
        for (nx, ny) in [
            (1, 1),
            (5, 1),
            (6, 2),
            (7, 3),
            (9, 4),
            (8, 7),
            (3, 7),
            (7, 8),
            (2, 8),
            (6, 16),
            (5, 24),
            (4, 32),
        ] {
            let s = laplacian(nx, ny, 0, 0.0);
            let mut lu = BandLu::default();
            lu.factor(&s).unwrap();
            assert_eq!(bits(&lu.a), bits(&reference_factors(&s)), "{nx}x{ny}");
        }
    }

    #[test]
    fn solves_a_2d_laplacian_band() {
        // Width 4 takes the general path, 8, 16 and 32 the fixed-length one inside the band
        // (none of it with one node column, n = W).
        for (nx, ny) in [(6, 4), (7, 8), (1, 8), (5, 16), (4, 32), (2, 32)] {
            let s = laplacian(nx, ny, 0, 0.0);
            let n = s.len();
            let x: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
            let mut b = vec![0.0; n];
            s.apply(&x, &mut b);
            let mut lu = BandLu::default();
            lu.factor(&s).unwrap();
            let (mut b1, mut b2) = (b.clone(), b.iter().map(|v| 2.0 * v).collect::<Vec<_>>());
            lu.solve(&mut b);
            lu.solve2(&mut b1, &mut b2, &mut Vec::new());
            assert_eq!(bits(&b), bits(&b1), "{nx}x{ny}");
            for (x2, x) in b2.iter().zip(&b) {
                assert_eq!(*x2, 2.0 * x);
            }
            for k in 0..n {
                assert!((b[k] - x[k]).abs() < 1e-12, "{k}: {} vs {}", b[k], x[k]);
            }
        }
    }

    #[test]
    fn refactoring_reuses_shared_leading_rows_bit_for_bit() {
        let (nx, ny) = (12, 4);
        let rhs: Vec<f64> = (0..nx * ny).map(|k| (k as f64 * 0.61).cos()).collect();
        let solve = |lu: &BandLu| {
            let mut b = rhs.clone();
            lu.solve(&mut b);
            b
        };
        let fresh = |s: &Stencil5| {
            let mut f = BandLu::default();
            f.factor(s).unwrap();
            f
        };
        // A reused factorisation: first the old matrix, then one differing from row 25 on
        // (odd: the first re-eliminated pivot pair straddles the reused rows).
        let mut reused = BandLu::default();
        reused.factor(&laplacian(nx, ny, 25, 0.0)).unwrap();
        let s = laplacian(nx, ny, 25, 0.37);
        reused.factor(&s).unwrap();
        assert_eq!(bits(&reused.a), bits(&fresh(&s).a), "factors differ");
        assert_eq!(bits(&reused.a), bits(&reference_factors(&s)));
        assert_eq!(solve(&reused), solve(&fresh(&s)));
        // A change in the first row, a smaller matrix, and back: always the fresh factors.
        for (n_x, from, bump) in [(12, 0, 0.1), (9, 5, 0.2), (12, 30, 0.3), (12, 31, 0.4)] {
            let s = laplacian(n_x, ny, from, bump);
            reused.factor(&s).unwrap();
            assert_eq!(
                bits(&reused.a),
                bits(&fresh(&s).a),
                "factors differ for {n_x} columns, change from {from}"
            );
        }
        // A change in one coupling of one row (each of the five in turn) is seen.
        for q in 0..5 {
            let base = laplacian(nx, ny, 0, 0.0);
            reused.factor(&base).unwrap();
            let mut s = base.clone();
            let r = 3 * ny + 2;
            let [c, w, e, so, no] = [&mut s.c, &mut s.w, &mut s.e, &mut s.s, &mut s.n];
            let v = [c, w, e, so, no].into_iter().nth(q).unwrap();
            v[r] *= 1.1;
            assert_ne!(v[r], 0.0);
            reused.factor(&s).unwrap();
            assert_eq!(bits(&reused.a), bits(&fresh(&s).a), "coupling {q} changed");
        }
        // A failed factorisation is never reused.
        assert!(reused.factor(&laplacian(nx, ny, 40, f64::NAN)).is_err());
        let s = laplacian(nx, ny, 40, 0.5);
        reused.factor(&s).unwrap();
        assert_eq!(bits(&reused.a), bits(&fresh(&s).a));
    }

    #[test]
    fn taking_the_operator_gives_the_copied_ones_factors_and_reuse() {
        // The film solver's use: each operator assembled into the buffer the last one left.
        let (copying, taking) = (&mut BandLu::default(), &mut BandLu::default());
        let mut buffer = Stencil5::default();
        let sequence = [
            (12, 25, 0.0),
            (12, 25, 0.37),
            (12, 0, 0.1),
            (9, 5, 0.2),
            (12, 30, 0.3),
        ];
        for (n_x, from, bump) in sequence {
            let s = laplacian(n_x, 4, from, bump);
            buffer.reshape(s.m1, s.n2);
            for (b, v) in buffer.coefficients_mut().into_iter().zip(s.coefficients()) {
                b.copy_from_slice(v);
            }
            let kept = copying.factor(&s).unwrap();
            assert_eq!(
                taking.factor_taking(&mut buffer).unwrap(),
                kept,
                "rows eliminated"
            );
            assert_eq!(
                bits(&taking.a),
                bits(&copying.a),
                "{n_x} columns, from {from}"
            );
        }
    }

    #[test]
    fn kept_factors_solve_as_the_band_lu_double_to_the_bit_single_to_1e_7() {
        for (nx, ny) in [(7, 8), (5, 16), (4, 32), (6, 4)] {
            let s = laplacian(nx, ny, 0, 0.0);
            let n = s.len();
            let x: Vec<f64> = (0..n)
                .map(|k| 1.0 + 0.5 * (k as f64 * 0.37).sin())
                .collect();
            let mut b = vec![0.0; n];
            s.apply(&x, &mut b);
            let mut lu = BandLu::default();
            lu.factor(&s).unwrap();
            let (mut e1, mut e2) = (b.clone(), b.iter().map(|v| -v).collect::<Vec<_>>());
            lu.solve2(&mut e1, &mut e2, &mut Vec::new());
            for single in [false, true] {
                let mut kept = KeptLu::default();
                if single {
                    kept.keep_single(&lu);
                } else {
                    // Exchanged: the band LU takes what the kept set held (nothing here).
                    let mut own = lu.clone();
                    kept.exchange(&mut own);
                    assert!(!own.valid && own.a.is_empty());
                }
                assert_eq!(kept.rounded(), single);
                let (mut k1, mut k2) = (b.clone(), b.iter().map(|v| -v).collect::<Vec<_>>());
                kept.solve2(&mut k1, &mut k2, &mut Vec::new());
                let mut k = b.clone();
                kept.solve(&mut k);
                assert_eq!(bits(&k), bits(&k1), "{nx}x{ny} single {single}");
                if single {
                    for (i, (a, e)) in k1.iter().zip(&x).enumerate() {
                        assert!(
                            (a - e).abs() < 1e-6 * e.abs(),
                            "{nx}x{ny} row {i}: {a} vs {e}"
                        );
                    }
                    assert!(bits(&k1) != bits(&e1), "single factors solved to the bit?");
                } else {
                    assert_eq!(bits(&k1), bits(&e1), "{nx}x{ny}");
                    assert_eq!(bits(&k2), bits(&e2), "{nx}x{ny}");
                }
            }
        }
    }

    #[test]
    fn refactoring_takes_the_rows_it_shares_with_kept_factors() {
        let (nx, ny) = (12, 8);
        let old = laplacian(nx, ny, 41, 0.0);
        let new = laplacian(nx, ny, 41, 0.37);
        let mut lu = BandLu::default();
        lu.factor(&old).unwrap();
        let mut fresh = BandLu::default();
        fresh.factor(&new).unwrap();
        for single in [false, true] {
            let mut kept = KeptLu::default();
            if single {
                kept.keep_single(&lu);
            } else {
                kept.exchange(&mut lu.clone());
            }
            // Factors at hand of another matrix (nothing shared), the kept ones lent.
            let mut other = BandLu::default();
            other.factor(&laplacian(nx, ny, 0, 0.2)).unwrap();
            let mut op = new.clone();
            let rows = other.factor_taking_reusing(&mut op, Some(&kept)).unwrap();
            assert_eq!(rows, nx * ny - 41, "single {single}: rows eliminated");
            assert_eq!(other.rounded(), single);
            if single {
                // The widened rows are the single-precision ones, the rest re-eliminated.
                let x: Vec<f64> = (0..nx * ny).map(|k| 1.5 + (k as f64 * 0.3).cos()).collect();
                let mut b = vec![0.0; nx * ny];
                new.apply(&x, &mut b);
                other.solve(&mut b);
                for (a, e) in b.iter().zip(&x) {
                    assert!((a - e).abs() < 1e-6 * e.abs(), "{a} vs {e}");
                }
                // A full refactorisation (nothing shared) is exact again.
                other.factor(&laplacian(nx, ny, 0, 0.5)).unwrap();
                assert!(!other.rounded());
            } else {
                assert_eq!(bits(&other.a), bits(&fresh.a), "double: the fresh factors");
            }
        }
    }

    #[test]
    fn exchanging_kept_factors_moves_them_whole_both_ways() {
        let (a, b) = (laplacian(6, 8, 0, 0.0), laplacian(6, 8, 20, 0.3));
        let (mut fa, mut fb) = (BandLu::default(), BandLu::default());
        fa.factor(&a).unwrap();
        fb.factor(&b).unwrap();
        let (bits_a, bits_b) = (bits(&fa.a), bits(&fb.a));
        let mut kept = KeptLu::default();
        kept.exchange(&mut fa); // kept: a's factors; fa: none
        assert!(!fa.valid);
        kept.exchange(&mut fb); // kept: b's; fb: a's
        assert!(fb.valid && !fb.rounded());
        assert_eq!(bits(&fb.a), bits_a);
        assert_eq!(
            fb.shared_rows(&a),
            a.len() - a.n2 - 1,
            "a's operator came along"
        );
        kept.exchange(&mut fa); // kept: none; fa: b's
        assert!(fa.valid && kept.n == 0);
        assert_eq!(bits(&fa.a), bits_b);
        // Single factors are not exchanged: the band LU is left with none.
        kept.keep_single(&fb);
        let mut fc = fb.clone();
        kept.exchange(&mut fc);
        assert!(!fc.valid);
    }
}
