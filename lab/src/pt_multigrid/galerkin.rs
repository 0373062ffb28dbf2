//! Galerkin coarse levels for the pressure correction: the coarse
//! operators are A_c = Pᵀ·A·P of the fine Poiseuille operator on the pressurised set, with a
//! prolongation P truncated to that set (Kornhuber's truncated basis functions: a coarse
//! correction never reaches a cavitated node, and the coarse operator knows it) and
//! operator-dependent along x1 (an odd node takes its two coarse neighbours in proportion to
//! its couplings to them, exact in 1D), so the jump of h³ at the ring's edges is carried
//! into the coarse operators instead of being interpolated across.

use super::Halving;

/// A sparse matrix in compressed rows.
#[derive(Clone, Debug, Default)]
pub(crate) struct Csr {
    pub ncols: usize,
    pub ptr: Vec<usize>,
    pub col: Vec<usize>,
    pub val: Vec<f64>,
}

impl Csr {
    /// An empty matrix of `ncols` columns, rows to be pushed.
    fn with_columns(ncols: usize) -> Csr {
        Csr {
            ncols,
            ptr: vec![0],
            ..Default::default()
        }
    }

    /// Appends a row given as (column, value) pairs in any order.
    fn push_row(&mut self, mut row: Vec<(usize, f64)>) {
        row.sort_unstable_by_key(|&(c, _)| c);
        for (c, v) in row {
            self.col.push(c);
            self.val.push(v);
        }
        self.ptr.push(self.col.len());
    }

    fn rows(&self) -> usize {
        self.ptr.len() - 1
    }

    fn row(&self, r: usize) -> (&[usize], &[f64]) {
        let s = self.ptr[r]..self.ptr[r + 1];
        (&self.col[s.clone()], &self.val[s])
    }

    /// self · b.
    pub fn mul(&self, b: &Csr) -> Csr {
        let mut out = Csr::with_columns(b.ncols);
        let mut acc = vec![0.0; b.ncols];
        let mut seen = vec![usize::MAX; b.ncols];
        let mut cols = Vec::new();
        for r in 0..self.rows() {
            cols.clear();
            let (ac, av) = self.row(r);
            for (&k, &a) in ac.iter().zip(av) {
                let (bc, bv) = b.row(k);
                for (&c, &v) in bc.iter().zip(bv) {
                    if seen[c] != r {
                        seen[c] = r;
                        acc[c] = 0.0;
                        cols.push(c);
                    }
                    acc[c] += a * v;
                }
            }
            cols.sort_unstable();
            for &c in &cols {
                out.col.push(c);
                out.val.push(acc[c]);
            }
            out.ptr.push(out.col.len());
        }
        out
    }

    pub fn transpose(&self) -> Csr {
        let mut count = vec![0usize; self.ncols + 1];
        for &c in &self.col {
            count[c + 1] += 1;
        }
        for c in 0..self.ncols {
            count[c + 1] += count[c];
        }
        let mut next = count.clone();
        let mut col = vec![0; self.col.len()];
        let mut val = vec![0.0; self.val.len()];
        for r in 0..self.rows() {
            let (rc, rv) = self.row(r);
            for (&c, &v) in rc.iter().zip(rv) {
                col[next[c]] = r;
                val[next[c]] = v;
                next[c] += 1;
            }
        }
        Csr {
            ncols: self.rows(),
            ptr: count,
            col,
            val,
        }
    }

    /// y += self · x.
    pub fn add_mul(&self, x: &[f64], y: &mut [f64]) {
        for (r, y) in y.iter_mut().enumerate() {
            let (c, v) = self.row(r);
            *y += c.iter().zip(v).map(|(&c, &v)| v * x[c]).sum::<f64>();
        }
    }

    /// Gauss–Seidel sweeps on self · x = b, rows in order.
    fn gauss_seidel(&self, x: &mut [f64], b: &[f64], sweeps: usize) {
        for _ in 0..sweeps {
            for r in 0..self.rows() {
                let (c, v) = self.row(r);
                let (mut s, mut d) = (b[r], 0.0);
                for (&c, &v) in c.iter().zip(v) {
                    if c == r {
                        d = v;
                    } else {
                        s -= v * x[c];
                    }
                }
                x[r] = s / d;
            }
        }
    }

    /// b − self · x.
    fn residual(&self, x: &[f64], b: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(b);
        for (r, o) in out.iter_mut().enumerate() {
            let (c, v) = self.row(r);
            *o -= c.iter().zip(v).map(|(&c, &v)| v * x[c]).sum::<f64>();
        }
    }
}

/// One level: its mesh, which of its nodes carry a correction, its operator on them and the
/// prolongation from the next coarser level.
pub(super) struct Level {
    pub n1: usize,
    pub n2: usize,
    /// Mesh node of each unknown (row order = mesh order).
    pub nodes: Vec<usize>,
    pub a: Csr,
    /// Rows: this level's unknowns; columns: the next coarser level's; and its transpose
    /// (the restriction).
    pub p: Csr,
    pub pt: Csr,
    pub b: Vec<f64>,
    pub e: Vec<f64>,
}

/// The fine level's operator: the Poiseuille part of the stencil on the pressurised interior
/// nodes (∂balance/∂p; the faces to cavitated and boundary nodes stay on the diagonal).
pub(super) fn fine_level(n1: usize, n2: usize, cx: &[f64], cy: &[f64], active: &[bool]) -> Level {
    let ny = n2.saturating_sub(1);
    let mut index = vec![usize::MAX; (n1 + 1) * n2];
    let mut nodes = Vec::new();
    for i in 1..n1 {
        for j in 0..n2 {
            let k = i * n2 + j;
            if active[k] {
                index[k] = nodes.len();
                nodes.push(k);
            }
        }
    }
    let mut a = Csr::with_columns(nodes.len());
    for &k in &nodes {
        let (i, j) = (k / n2, k % n2);
        let mut nb = vec![(k - n2, cx[k - n2]), (k + n2, cx[k])];
        if j > 0 {
            nb.push((k - 1, cy[i * ny + j - 1]));
        }
        if j + 1 < n2 {
            nb.push((k + 1, cy[i * ny + j]));
        }
        let diag: f64 = nb.iter().map(|&(_, c)| c).sum();
        let mut row: Vec<(usize, f64)> = nb
            .iter()
            .filter(|&&(m, _)| index[m] != usize::MAX)
            .map(|&(m, c)| (index[m], -c))
            .collect();
        row.push((index[k], diag));
        a.push_row(row);
    }
    let m = nodes.len();
    Level {
        n1,
        n2,
        nodes,
        a,
        p: Csr::default(),
        pt: Csr::default(),
        b: vec![0.0; m],
        e: vec![0.0; m],
    }
}

/// The next coarser level of `fine` halved by `hv`: its prolongation (set on `fine`) and its
/// Galerkin operator. None when no coarse node would carry a correction.
pub(super) fn coarsen(fine: &mut Level, hv: Halving) -> Option<Level> {
    let (n1, n2) = (fine.n1, fine.n2);
    let m1 = if hv.x1 { n1 / 2 } else { n1 };
    let m2 = if hv.x2 { n2 / 2 } else { n2 };
    let mut index = vec![usize::MAX; (n1 + 1) * n2];
    for (u, &k) in fine.nodes.iter().enumerate() {
        index[k] = u;
    }
    // x1 couplings of each unknown to its west and east neighbours, lumped over x2 (0 to
    // nodes without a correction).
    let coupling = |u: usize, west: bool| -> f64 {
        let (c, v) = fine.a.row(u);
        let i = fine.nodes[u] / n2;
        c.iter()
            .zip(v)
            .filter(|(&c, _)| {
                let ic = fine.nodes[c] / n2;
                if west {
                    ic + 1 == i
                } else {
                    ic == i + 1
                }
            })
            // A Galerkin operator need not be an M-matrix: a positive off-diagonal entry
            // is no coupling (a weight of either sign could blow a correction up).
            .map(|(_, &v)| (-v).max(0.0))
            .sum()
    };
    // Prolongation rows over coarse mesh nodes, then compressed to the nodes used.
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::with_capacity(fine.nodes.len());
    for (u, &k) in fine.nodes.iter().enumerate() {
        let (i, j) = (k / n2, k % n2);
        let x1: Vec<(usize, f64)> = if !hv.x1 {
            vec![(i, 1.0)]
        } else if i % 2 == 0 {
            vec![(i / 2, 1.0)]
        } else {
            let (w, e) = (coupling(u, true), coupling(u, false));
            if w + e > 0.0 {
                vec![(i / 2, w / (w + e)), (i / 2 + 1, e / (w + e))]
            } else {
                vec![(i / 2, 0.5), (i / 2 + 1, 0.5)]
            }
        };
        let x2: Vec<(usize, f64)> = if !hv.x2 {
            vec![(j, 1.0)]
        } else {
            let jc = j / 2;
            let nb = if j % 2 == 0 {
                jc.checked_sub(1)
            } else {
                Some(jc + 1).filter(|&n| n < m2)
            };
            match nb {
                Some(nb) => vec![(jc, 0.75), (nb, 0.25)],
                None => vec![(jc, 1.0)],
            }
        };
        let mut row = Vec::new();
        for &(ic, wi) in &x1 {
            // No correction on the Dirichlet columns.
            if ic == 0 || ic == m1 {
                continue;
            }
            for &(jc, wj) in &x2 {
                if wi * wj > 0.0 {
                    row.push((ic * m2 + jc, wi * wj));
                }
            }
        }
        rows.push(row);
    }
    let mut cindex = vec![usize::MAX; (m1 + 1) * m2];
    for row in &rows {
        for &(c, _) in row {
            cindex[c] = 0;
        }
    }
    let mut nodes = Vec::new();
    for (c, ix) in cindex.iter_mut().enumerate() {
        if *ix == 0 {
            *ix = nodes.len();
            nodes.push(c);
        }
    }
    if nodes.is_empty() {
        return None;
    }
    let mut p = Csr::with_columns(nodes.len());
    for row in rows {
        p.push_row(row.into_iter().map(|(c, w)| (cindex[c], w)).collect());
    }
    let pt = p.transpose();
    let a = pt.mul(&fine.a.mul(&p));
    fine.p = p;
    fine.pt = pt;
    let m = nodes.len();
    Some(Level {
        n1: m1,
        n2: m2,
        nodes,
        a,
        p: Csr::default(),
        pt: Csr::default(),
        b: vec![0.0; m],
        e: vec![0.0; m],
    })
}

/// The linear correction cycle from level `l` (its b set) down: Gauss–Seidel before and
/// after, the coarsest level solved exactly (dense elimination).
pub(super) fn cycle(levels: &mut [Level], l: usize, pre: usize, post: usize) {
    levels[l].e.iter_mut().for_each(|e| *e = 0.0);
    if l + 1 == levels.len() {
        let lv = &mut levels[l];
        let n = lv.nodes.len();
        // Dense Gaussian elimination without pivoting: the operator is symmetric positive
        // semi-definite. Semi: truncation can leave two coarse nodes whose basis functions
        // are the same fine node's (a lone pressurised node), so Pᵀ·A·P can be singular; a
        // pivot that vanishes against its row's diagonal marks such a direction, which gets
        // no correction (without this check the elimination made NaNs).
        let mut m = vec![0.0; n * n];
        for r in 0..n {
            let (c, v) = lv.a.row(r);
            for (&c, &v) in c.iter().zip(v) {
                m[r * n + c] = v;
            }
        }
        let diag: Vec<f64> = (0..n).map(|k| m[k * n + k]).collect();
        let mut null = vec![false; n];
        let mut x = lv.b.clone();
        for k in 0..n {
            if m[k * n + k] <= 1e-12 * diag[k] {
                null[k] = true;
                continue;
            }
            for r in k + 1..n {
                let f = m[r * n + k] / m[k * n + k];
                if f != 0.0 {
                    for c in k..n {
                        m[r * n + c] -= f * m[k * n + c];
                    }
                    x[r] -= f * x[k];
                }
            }
        }
        for k in (0..n).rev() {
            if null[k] {
                x[k] = 0.0;
                continue;
            }
            let s: f64 = (k + 1..n).map(|c| m[k * n + c] * x[c]).sum();
            x[k] = (x[k] - s) / m[k * n + k];
        }
        lv.e.copy_from_slice(&x);
        return;
    }
    {
        let lv = &mut levels[l];
        lv.a.gauss_seidel(&mut lv.e, &lv.b, pre);
    }
    let mut r = Vec::new();
    levels[l].a.residual(&levels[l].e, &levels[l].b, &mut r);
    {
        let (a, b) = levels.split_at_mut(l + 1);
        let coarse = &mut b[0];
        coarse.b.iter_mut().for_each(|x| *x = 0.0);
        a[l].pt.add_mul(&r, &mut coarse.b);
    }
    cycle(levels, l + 1, pre, post);
    {
        let (a, b) = levels.split_at_mut(l + 1);
        let lv = &mut a[l];
        lv.p.add_mul(&b[0].e, &mut lv.e);
        lv.a.gauss_seidel(&mut lv.e, &lv.b, post);
    }
}
