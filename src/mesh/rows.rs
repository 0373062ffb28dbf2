//! The gap across a node's row (docs/model.md §3, "The gap across a cell"): a pocket's rim
//! crosses a row of cells anywhere, so the gap is sampled at `ns` points across each node's
//! cell along x2 and the film's terms that are not linear in h (face conductances, the
//! Couette shear, the asperities' pressure and shear, the flow factors) are their means over
//! the samples. The node's own gap is the samples' mean, so the film it stores and the film it
//! carries downstream stay one quantity, θ·h̄ (docs/solver.md, "Deep pockets").

use serde::{Deserialize, Serialize};

/// How the film sees the gap across a cell (docs/solver.md, "Deep pockets").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RimModel {
    /// The gap at the nodes: each row of cells is its centre line.
    #[default]
    Nodal,
    /// `samples` points across each cell ([`Rows`]): an x1 face's strips in parallel, the gap
    /// between two rows in series across an x2 face.
    Strips { samples: usize },
    /// As [`RimModel::Strips`], but an x2 face keeps the nodal mean of its two rows' gaps.
    StripsAlong { samples: usize },
}

impl RimModel {
    /// Samples across a cell (1: nodal).
    pub fn samples(self) -> usize {
        match self {
            RimModel::Nodal => 1,
            RimModel::Strips { samples } | RimModel::StripsAlong { samples } => samples,
        }
    }

    pub fn is_nodal(&self) -> bool {
        *self == RimModel::Nodal
    }
}

/// A node without samples: its row's gap is uniform across the cell (a plain liner, a row on
/// the plateau), and every term is its nodal value.
const UNIFORM: u32 = u32::MAX;

/// Per node, the deviations of the gap across its cell from the cell's mean h̄: sample s of
/// node k at x2 = y_k − dy/2 + (s + ½)·dy/ns is h̄_k + `dev[at[k] + s]`. Empty: every row
/// uniform (or a nodal mesh, `ns` = 1).
#[derive(Debug, Default, PartialEq)]
pub struct Rows {
    ns: usize,
    /// x2 faces: the samples between the two rows in series (else the nodal face).
    series: bool,
    at: Vec<u32>,
    dev: Vec<f64>,
}

impl Rows {
    /// No samples: the gap is taken at the nodes.
    pub fn nodal() -> Self {
        Rows::default()
    }

    /// Starts a placement of `nodes` nodes as `rim` samples them (none for a nodal model).
    pub fn reset(&mut self, nodes: usize, rim: RimModel) {
        let ns = rim.samples();
        self.ns = ns;
        self.series = matches!(rim, RimModel::Strips { .. });
        self.dev.clear();
        self.at.clear();
        if ns > 1 {
            self.at.resize(nodes, UNIFORM);
        }
    }

    /// Sets node k's samples `depth` (its texture depth at the sample points, µm) and
    /// returns their mean, the node's depth: exactly the samples' common value where they
    /// are all equal (no deviations kept).
    pub fn set(&mut self, k: usize, depth: &[f64]) -> f64 {
        let first = depth[0];
        if depth.iter().all(|&d| d == first) {
            return first;
        }
        let mean = depth.iter().sum::<f64>() / depth.len() as f64;
        self.at[k] = self.dev.len() as u32;
        self.dev.extend(depth.iter().map(|d| d - mean));
        mean
    }

    /// The deviations across node k's cell (None: uniform).
    #[inline(always)]
    pub fn of(&self, k: usize) -> Option<&[f64]> {
        if self.dev.is_empty() {
            return None;
        }
        match self.at.get(k) {
            Some(&a) if a != UNIFORM => {
                let a = a as usize;
                Some(&self.dev[a..a + self.ns])
            }
            _ => None,
        }
    }

    /// The deepest deviation below node k's mean (0 where the row is uniform): its least
    /// gap is h̄ + this.
    #[inline]
    pub fn min_dev(&self, k: usize) -> f64 {
        self.of(k)
            .map_or(0.0, |d| d.iter().copied().fold(0.0, f64::min))
    }

    /// Whether an x2 face takes the samples between its rows in series.
    pub fn series(&self) -> bool {
        self.series
    }

    /// Whether any node has samples.
    pub fn any(&self) -> bool {
        !self.dev.is_empty()
    }

    /// The mean over node k's samples of f(h), its gap h̄ = `h`: f(h) where the row is
    /// uniform.
    #[inline]
    pub fn mean_of(&self, k: usize, h: f64, f: impl Fn(f64) -> f64) -> f64 {
        match self.of(k) {
            None => f(h),
            Some(d) => d.iter().map(|&e| f(h + e)).sum::<f64>() / d.len() as f64,
        }
    }

    /// An x1 face between nodes k (gap `a`) and kn (gap `b`): the mean over the strips across
    /// it of c(h_f), h_f the mean of the two nodes' samples at the same x2 (strips in
    /// parallel, each as the nodal face along x1).
    #[inline]
    pub fn across_x1_face(
        &self,
        (k, a): (usize, f64),
        (kn, b): (usize, f64),
        c: impl Fn(f64) -> f64,
    ) -> f64 {
        match (self.of(k), self.of(kn)) {
            (None, None) => c(0.5 * (a + b)),
            (da, db) => {
                let ns = self.ns;
                let at = |d: Option<&[f64]>, h: f64, s: usize| d.map_or(h, |d| h + d[s]);
                (0..ns)
                    .map(|s| c(0.5 * (at(da, a, s) + at(db, b, s))))
                    .sum::<f64>()
                    / ns as f64
            }
        }
    }

    /// An x2 face between node k (gap `a`) and its neighbour k + 1 (gap `b`) along x2: the
    /// samples between the two nodes (the upper half of k's, the lower half of k + 1's) in
    /// series, 1/mean(1/c(h)); the nodal face c((a + b)/2) where both rows are uniform.
    #[inline]
    pub fn along_x2_face(&self, (k, a): (usize, f64), b: f64, c: impl Fn(f64) -> f64) -> f64 {
        match (self.of(k), self.of(k + 1)) {
            (None, None) => c(0.5 * (a + b)),
            _ if !self.series => c(0.5 * (a + b)),
            (da, db) => 1.0 / self.between_rows((da, a), (db, b), |h| 1.0 / c(h)),
        }
    }

    /// The mean of r(h) over the samples between node k (`a`, deviations `da`) and k + 1.
    #[inline]
    pub fn between_rows(
        &self,
        (da, a): (Option<&[f64]>, f64),
        (db, b): (Option<&[f64]>, f64),
        r: impl Fn(f64) -> f64,
    ) -> f64 {
        let (ns, half) = (self.ns, self.ns / 2);
        let upper: f64 = (half..ns).map(|s| r(da.map_or(a, |d| a + d[s]))).sum();
        let lower: f64 = (0..half).map(|s| r(db.map_or(b, |d| b + d[s]))).sum();
        (upper + lower) / ns as f64
    }
}

/// The texture depth at `ns` points across a cell of width `dy` centred at `y` (the
/// midpoints of equal parts), into `out`.
pub fn sample_across(y: f64, dy: f64, ns: usize, depth: impl Fn(f64) -> f64, out: &mut Vec<f64>) {
    out.clear();
    let h = dy / ns as f64;
    out.extend((0..ns).map(|s| depth(y - 0.5 * dy + (s as f64 + 0.5) * h)));
}

/// Field by field; `clone_from` keeps the arrays' allocations.
impl Clone for Rows {
    fn clone(&self) -> Self {
        Rows {
            ns: self.ns,
            series: self.series,
            at: self.at.clone(),
            dev: self.dev.clone(),
        }
    }

    fn clone_from(&mut self, s: &Self) {
        (self.ns, self.series) = (s.ns, s.series);
        self.at.clone_from(&s.at);
        self.dev.clone_from(&s.dev);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_row_keeps_no_samples_and_its_exact_value() {
        let mut r = Rows::nodal();
        r.reset(3, RimModel::Strips { samples: 4 });
        assert_eq!(r.set(0, &[0.3; 4]).to_bits(), 0.3f64.to_bits());
        assert_eq!(r.of(0), None);
        assert!(!r.any());
    }

    #[test]
    fn an_x1_face_is_the_mean_of_its_strips_and_an_x2_face_their_series() {
        let mut r = Rows::nodal();
        r.reset(2, RimModel::Strips { samples: 2 });
        // Node 0: samples 1 and 3 (mean 2); node 1 uniform at 2.
        assert_eq!(r.set(0, &[1.0, 3.0]), 2.0);
        assert_eq!(r.set(1, &[2.0, 2.0]), 2.0);
        let cube = |h: f64| h * h * h;
        // Strips: h_f = 1.5 and 2.5.
        let x1 = r.across_x1_face((0, 2.0), (1, 2.0), cube);
        assert!((x1 - 0.5 * (1.5f64.powi(3) + 2.5f64.powi(3))).abs() < 1e-12);
        // Between the nodes: node 0's upper sample (3) and node 1's lower one (2), in series.
        let x2 = r.along_x2_face((0, 2.0), 2.0, cube);
        assert!((x2 - 2.0 / (1.0 / 27.0 + 1.0 / 8.0)).abs() < 1e-12);
    }
}
