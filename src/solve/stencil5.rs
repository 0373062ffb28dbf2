//! The matrix of a film problem for a fixed active set: a 5-point operator on the block of
//! node columns a solve covers (each node couples to its four neighbours, whatever its
//! unknown: p on the pressurised set, φ on the cavitated set).

/// A 5-point operator on an m1 × n2 block, node (i, j) at i·n2 + j:
/// (A x)_k = c_k x_k + w_k x_{k−n2} + e_k x_{k+n2} + s_k x_{k−1} + n_k x_{k+1}.
/// Couplings that leave the block must be zero.
#[derive(Clone, Debug, Default)]
pub struct Stencil5 {
    pub m1: usize,
    pub n2: usize,
    pub c: Vec<f64>,
    pub w: Vec<f64>,
    pub e: Vec<f64>,
    pub s: Vec<f64>,
    pub n: Vec<f64>,
}

impl Stencil5 {
    /// Resets to an all-zero operator of the given shape, reusing the allocations.
    pub fn reset(&mut self, m1: usize, n2: usize) {
        self.reshape(m1, n2);
        self.coefficients_mut()
            .into_iter()
            .for_each(|v| v.fill(0.0));
    }

    /// Sets the shape without clearing: for callers that then write every entry.
    pub fn reshape(&mut self, m1: usize, n2: usize) {
        self.m1 = m1;
        self.n2 = n2;
        for v in self.coefficients_mut() {
            v.resize(m1 * n2, 0.0);
        }
    }

    /// The five coefficient arrays (c, w, e, s, n).
    pub fn coefficients_mut(&mut self) -> [&mut Vec<f64>; 5] {
        [
            &mut self.c,
            &mut self.w,
            &mut self.e,
            &mut self.s,
            &mut self.n,
        ]
    }

    /// The five coefficient arrays (c, w, e, s, n).
    pub fn coefficients(&self) -> [&Vec<f64>; 5] {
        [&self.c, &self.w, &self.e, &self.s, &self.n]
    }

    /// Number of unknowns.
    pub fn len(&self) -> usize {
        self.m1 * self.n2
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// y = A x (row by row, without index arithmetic in the inner loop).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        let (m1, n2) = (self.m1, self.n2);
        for i in 0..m1 {
            let row = i * n2;
            for j in 0..n2 {
                let k = row + j;
                let mut v = self.c[k] * x[k];
                if i > 0 {
                    v += self.w[k] * x[k - n2];
                }
                if i + 1 < m1 {
                    v += self.e[k] * x[k + n2];
                }
                if j > 0 {
                    v += self.s[k] * x[k - 1];
                }
                if j + 1 < n2 {
                    v += self.n[k] * x[k + 1];
                }
                y[k] = v;
            }
        }
    }

    /// r = b − A x.
    pub fn residual(&self, x: &[f64], b: &[f64], r: &mut [f64]) {
        self.apply(x, r);
        for (rk, bk) in r.iter_mut().zip(b) {
            *rk = bk - *rk;
        }
    }
}
