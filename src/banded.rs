//! Banded LU without pivoting, for the M-matrices of the film solver.
//!
//! The film Jacobian for a fixed active set is a nonsingular M-matrix (positive diagonal,
//! non-positive off-diagonals, column diagonal dominance), so Gaussian elimination without
//! pivoting is stable and keeps the band. Storage is row-major: row r holds columns r−w..=r+w.

#[derive(Debug, Default, Clone)]
pub struct BandLu {
    n: usize,
    w: usize,
    a: Vec<f64>,
}

/// A zero or non-finite pivot: the matrix is singular (should not happen for an M-matrix).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularPivot {
    pub row: usize,
    pub value: f64,
}

impl BandLu {
    /// Resets to an n×n zero matrix of half bandwidth w, reusing the allocation.
    pub fn reset(&mut self, n: usize, w: usize) {
        self.n = n;
        self.w = w;
        let len = n * (2 * w + 1);
        self.a.clear();
        self.a.resize(len, 0.0);
    }

    #[inline]
    fn at(&self, r: usize, c: usize) -> usize {
        debug_assert!(c + self.w >= r && c <= r + self.w);
        r * (2 * self.w + 1) + (c + self.w - r)
    }

    /// Adds `v` to entry (r, c); |r − c| must be ≤ w.
    #[inline]
    pub fn add(&mut self, r: usize, c: usize, v: f64) {
        let k = self.at(r, c);
        self.a[k] += v;
    }

    /// In-place LU factorisation (unit lower L below the diagonal, U on and above).
    pub fn factor(&mut self) -> Result<(), SingularPivot> {
        let (n, w) = (self.n, self.w);
        let stride = 2 * w + 1;
        for k in 0..n {
            let piv = self.a[k * stride + w];
            if !(piv.is_finite() && piv != 0.0) {
                return Err(SingularPivot { row: k, value: piv });
            }
            let inv = 1.0 / piv;
            let last = (k + w).min(n - 1);
            let (head, tail) = self.a.split_at_mut((k + 1) * stride);
            // Row k of U, columns k+1..=last.
            let urow = &head[k * stride + w + 1..k * stride + w + 1 + (last - k)];
            for i in k + 1..=last {
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
        lu.solve(&mut b);
        for k in 0..n {
            assert!((b[k] - x[k]).abs() < 1e-12, "{k}: {} vs {}", b[k], x[k]);
        }
    }
}
