//! Forward and back substitution through band factors (double or single precision).

/// A stored factor entry: the arithmetic is in f64 whatever the storage.
pub(super) trait Entry: Copy {
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
pub(super) fn solve_in<T: Entry>(a: &[T], n: usize, w: usize, b: &mut [f64]) {
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
pub(super) fn solve2_in<T: Entry>(
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
/// Case III at `paper` spent 18.98 G instructions in `solve2` that way against 13.29 G
/// interleaved (valgrind); at 360 × 32 a substitution with the factors in cache takes
/// ≈ 15–25 % less time interleaved, ≈ 5–15 % less when they come from memory.
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
