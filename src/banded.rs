//! Banded LU without pivoting, for the M-matrices of the film solver.
//!
//! The film Jacobian for a fixed active set is a nonsingular M-matrix (positive diagonal,
//! non-positive off-diagonals, column diagonal dominance), so Gaussian elimination without
//! pivoting is stable and keeps the band. Storage is row-major: row r holds columns r−w..=r+w.

#[derive(Debug, Default, Clone)]
pub struct BandLu {
    n: usize,
    w: usize,
    /// The factors (L below the diagonal, U on and above), row-major band.
    a: Vec<f64>,
    /// The matrix `a` was factored from, to find the rows a new matrix shares with it.
    orig: Vec<f64>,
    /// The matrix being assembled (`reset`, `add`) for the next `factor`.
    next: Vec<f64>,
    next_n: usize,
    next_w: usize,
    /// Whether `a` holds complete factors of `orig`.
    valid: bool,
}

/// A zero or non-finite pivot: the matrix is singular (should not happen for an M-matrix).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularPivot {
    pub row: usize,
    pub value: f64,
}

impl BandLu {
    /// Starts assembling an n×n zero matrix of half bandwidth w, reusing the allocation.
    pub fn reset(&mut self, n: usize, w: usize) {
        self.next_n = n;
        self.next_w = w;
        self.next.clear();
        self.next.resize(n * (2 * w + 1), 0.0);
    }

    /// Adds `v` to entry (r, c) of the matrix being assembled; |r − c| must be ≤ w.
    #[inline]
    pub fn add(&mut self, r: usize, c: usize, v: f64) {
        let w = self.next_w;
        debug_assert!(c + w >= r && c <= r + w);
        self.next[r * (2 * w + 1) + (c + w - r)] += v;
    }

    /// LU factorisation of the assembled matrix (unit lower L below the diagonal, U on and
    /// above). Elimination never changes a row from the rows after it, so the leading rows
    /// the matrix shares bit for bit with the last one factored keep their factors and only
    /// the rest is eliminated: the film's flooded inlet bank, untouched by Z, is factored
    /// once per time step instead of once per Newton iteration. Same bits as a full
    /// factorisation.
    pub fn factor(&mut self) -> Result<(), SingularPivot> {
        let (n, w) = (self.next_n, self.next_w);
        let stride = 2 * w + 1;
        // Rows before r0 are unchanged; a reused row must also have seen the same
        // (untruncated) elimination updates, hence the margin before the end.
        let mut r0 = 0;
        if self.valid && w == self.w {
            let limit = n.min(self.n).saturating_sub(w + 1);
            let same =
                |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(a, b)| a.to_bits() == b.to_bits());
            while r0 < limit
                && same(
                    &self.next[r0 * stride..(r0 + 1) * stride],
                    &self.orig[r0 * stride..(r0 + 1) * stride],
                )
            {
                r0 += 1;
            }
        }
        self.n = n;
        self.w = w;
        // The new matrix becomes the reference (its rows before r0 equal the old ones).
        std::mem::swap(&mut self.orig, &mut self.next);
        self.a.resize(n * stride, 0.0);
        self.a[r0 * stride..].copy_from_slice(&self.orig[r0 * stride..]);
        self.valid = false;
        self.eliminate_from(r0)?;
        self.valid = true;
        Ok(())
    }

    /// Right-looking elimination of rows r0.. (rows before r0 hold their final factors):
    /// the pivots k < r0 first update the rows ≥ r0 within their band, then elimination
    /// proceeds as usual; each row sees its updates in the same order as in a full pass.
    fn eliminate_from(&mut self, r0: usize) -> Result<(), SingularPivot> {
        let (n, w) = (self.n, self.w);
        let stride = 2 * w + 1;
        for k in r0.saturating_sub(w)..n {
            let piv = self.a[k * stride + w];
            if !(piv.is_finite() && piv != 0.0) {
                return Err(SingularPivot { row: k, value: piv });
            }
            let inv = 1.0 / piv;
            let last = (k + w).min(n - 1);
            let (head, tail) = self.a.split_at_mut((k + 1) * stride);
            // Row k of U, columns k+1..=last.
            let urow = &head[k * stride + w + 1..k * stride + w + 1 + (last - k)];
            for i in (k + 1).max(r0)..=last {
                let row = &mut tail[(i - k - 1) * stride..(i - k) * stride];
                let lik_idx = k + w - i;
                let lik = row[lik_idx] * inv;
                if lik == 0.0 {
                    continue;
                }
                row[lik_idx] = lik;
                // Columns k+1..=last of row i start at offset (k+1)+w−i.
                let start = lik_idx + 1;
                for (x, &u) in row[start..start + (last - k)].iter_mut().zip(urow) {
                    *x -= lik * u;
                }
            }
        }
        Ok(())
    }

    /// Solves A x = b in place (after `factor`).
    pub fn solve(&self, b: &mut [f64]) {
        let (n, w) = (self.n, self.w);
        let stride = 2 * w + 1;
        for i in 0..n {
            let first = i.saturating_sub(w);
            let row = &self.a[i * stride..];
            let mut s = b[i];
            for k in first..i {
                s -= row[k + w - i] * b[k];
            }
            b[i] = s;
        }
        for i in (0..n).rev() {
            let last = (i + w).min(n - 1);
            let row = &self.a[i * stride..];
            let mut s = b[i];
            for j in i + 1..=last {
                s -= row[j + w - i] * b[j];
            }
            b[i] = s / row[w];
        }
    }

    /// Solves A x = b1 and A x = b2 in place together: the same arithmetic as two `solve`
    /// calls (bit-identical results), but the two independent substitution chains
    /// interleave, which hides the floating-point latency of each.
    pub fn solve2(&self, b1: &mut [f64], b2: &mut [f64]) {
        let (n, w) = (self.n, self.w);
        let stride = 2 * w + 1;
        assert!(b1.len() >= n && b2.len() >= n);
        for i in 0..n {
            let first = i.saturating_sub(w);
            let row = &self.a[i * stride..];
            let (mut s1, mut s2) = (b1[i], b2[i]);
            for k in first..i {
                let l = row[k + w - i];
                s1 -= l * b1[k];
                s2 -= l * b2[k];
            }
            b1[i] = s1;
            b2[i] = s2;
        }
        for i in (0..n).rev() {
            let last = (i + w).min(n - 1);
            let row = &self.a[i * stride..];
            let (mut s1, mut s2) = (b1[i], b2[i]);
            for j in i + 1..=last {
                let u = row[j + w - i];
                s1 -= u * b1[j];
                s2 -= u * b2[j];
            }
            b1[i] = s1 / row[w];
            b2[i] = s2 / row[w];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_2d_laplacian_band() {
        // 5-point M-matrix on a 6×4 grid, ordered with the short direction fastest.
        let (nx, ny) = (6, 4);
        let n = nx * ny;
        let mut lu = BandLu::default();
        lu.reset(n, ny);
        let mut dense = vec![vec![0.0; n]; n];
        for i in 0..nx {
            for j in 0..ny {
                let r = i * ny + j;
                let mut put = |c: usize, v: f64| {
                    lu.add(r, c, v);
                    dense[r][c] += v;
                };
                put(r, 4.5);
                if i > 0 {
                    put(r - ny, -1.0);
                }
                if i + 1 < nx {
                    put(r + ny, -1.2);
                }
                if j > 0 {
                    put(r - 1, -0.9);
                }
                if j + 1 < ny {
                    put(r + 1, -1.0);
                }
            }
        }
        let x: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|r| (0..n).map(|c| dense[r][c] * x[c]).sum())
            .collect();
        lu.factor().unwrap();
        let (mut b1, mut b2) = (b.clone(), b.iter().map(|v| 2.0 * v).collect::<Vec<_>>());
        lu.solve(&mut b);
        lu.solve2(&mut b1, &mut b2);
        assert_eq!(b, b1);
        for (x2, x) in b2.iter().zip(&b) {
            assert_eq!(*x2, 2.0 * x);
        }
        for k in 0..n {
            assert!((b[k] - x[k]).abs() < 1e-12, "{k}: {} vs {}", b[k], x[k]);
        }
    }

    /// A 5-point M-matrix on an nx×ny grid whose diagonal from row `from` on is raised by
    /// `bump` (a Z change under the ring, seen by the trailing rows only).
    fn laplacian(lu: &mut BandLu, nx: usize, ny: usize, from: usize, bump: f64) {
        lu.reset(nx * ny, ny);
        for i in 0..nx {
            for j in 0..ny {
                let r = i * ny + j;
                let d = 4.5 + 0.1 * (r as f64).sin() + if r >= from { bump } else { 0.0 };
                lu.add(r, r, d);
                if i > 0 {
                    lu.add(r, r - ny, -1.0);
                }
                if i + 1 < nx {
                    lu.add(r, r + ny, -1.2);
                }
                if j > 0 {
                    lu.add(r, r - 1, -0.9);
                }
                if j + 1 < ny {
                    lu.add(r, r + 1, -1.0);
                }
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
        // A reused factorisation: first the old matrix, then one differing from row 25 on.
        let mut reused = BandLu::default();
        laplacian(&mut reused, nx, ny, 25, 0.0);
        reused.factor().unwrap();
        laplacian(&mut reused, nx, ny, 25, 0.37);
        reused.factor().unwrap();
        // ... against a fresh one of the new matrix.
        let mut fresh = BandLu::default();
        laplacian(&mut fresh, nx, ny, 25, 0.37);
        fresh.factor().unwrap();
        assert_eq!(reused.a, fresh.a, "factors differ");
        assert_eq!(solve(&reused), solve(&fresh));
        // A change in the first row, a smaller matrix, and back: always the fresh factors.
        for (n_x, from, bump) in [(12, 0, 0.1), (9, 5, 0.2), (12, 30, 0.3)] {
            laplacian(&mut reused, n_x, ny, from, bump);
            reused.factor().unwrap();
            let mut f = BandLu::default();
            laplacian(&mut f, n_x, ny, from, bump);
            f.factor().unwrap();
            assert_eq!(
                reused.a, f.a,
                "factors differ for {n_x} columns, change from {from}"
            );
        }
        // A failed factorisation is never reused.
        laplacian(&mut reused, nx, ny, 40, f64::NAN);
        assert!(reused.factor().is_err());
        laplacian(&mut reused, nx, ny, 40, 0.5);
        reused.factor().unwrap();
        laplacian(&mut fresh, nx, ny, 40, 0.5);
        fresh.factor().unwrap();
        assert_eq!(reused.a, fresh.a);
    }
}
