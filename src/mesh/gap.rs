//! The gap h over the mesh as an affine function of the ring position Z (eq. 15,
//! docs/model.md §2): only the node columns under the ring depend on Z.

use super::{FittedFaces, Grid, Rows};
use crate::model::flow_factors::FlowFactors;

/// The gap at the new time level as an affine function of the ring position:
/// h = base + Z on the node columns under the ring, h = base elsewhere (eq. 15).
#[derive(Debug, Default)]
pub struct Gap {
    /// Gap without Z (µm), per node.
    pub base: Vec<f64>,
    /// Per node column i: whether it lies under the ring (a < x_i < b), where ∂h/∂Z = 1.
    pub ring: Vec<bool>,
    /// The surfaces' roughness as the film's flow sees it (docs/model.md §11, "Flow
    /// factors"); None: smooth surfaces.
    pub flow: Option<FlowFactors>,
    /// The gap across each node's cell where it varies there (a pocket's rim); `base` holds
    /// the cells' means.
    pub rows: Rows,
    /// x1 faces fitted to the gap along x1 between their nodes, on strips across their cells
    /// (None: every x1 face as `rows` has it).
    pub fitted: Option<FittedFaces>,
    /// x2 faces fitted to the gap between their rows, on strips along x1 across their cells
    /// (None: every x2 face as `rows` has it).
    pub fitted_x2: Option<FittedFaces>,
}

impl Gap {
    /// The ring position Z a gap `h` filled from this one holds (0 without a ring column).
    pub fn z_of(&self, grid: &Grid, h: &[f64]) -> f64 {
        self.ring
            .iter()
            .position(|&r| r)
            .map_or(0.0, |i| h[i * grid.n2] - self.base[i * grid.n2])
    }

    /// The gap at every node for ring position z into `out` (column by column: no index
    /// division in the hot loop).
    pub fn fill(&self, grid: &Grid, z: f64, out: &mut Vec<f64>) {
        out.clear();
        let n2 = grid.n2;
        for (i, &under) in self.ring.iter().enumerate() {
            let col = &self.base[i * n2..(i + 1) * n2];
            if under {
                out.extend(col.iter().map(|b| b + z));
            } else {
                out.extend_from_slice(col);
            }
        }
    }

    /// Refills `out`, which holds this gap at another ring position, for `z`: only the
    /// columns under the ring depend on Z (the same values as [`Gap::fill`]). `cols`:
    /// [`Gap::ring_columns`], computed once by the caller.
    pub fn refill_ring(&self, grid: &Grid, z: f64, cols: std::ops::Range<usize>, out: &mut [f64]) {
        let n2 = grid.n2;
        let span = cols.start * n2..cols.end * n2;
        for (i, (o, col)) in out[span.clone()]
            .chunks_exact_mut(n2)
            .zip(self.base[span].chunks_exact(n2))
            .enumerate()
        {
            if self.ring[cols.start + i] {
                for (o, b) in o.iter_mut().zip(col) {
                    *o = b + z;
                }
            }
        }
    }

    /// The node columns from the first under the ring to the last (empty without one).
    pub fn ring_columns(&self) -> std::ops::Range<usize> {
        match (
            self.ring.iter().position(|&r| r),
            self.ring.iter().rposition(|&r| r),
        ) {
            (Some(a), Some(b)) => a..b + 1,
            _ => 0..0,
        }
    }

    /// The smallest gap without Z under the ring, over the samples across each cell (∞
    /// when no column lies under it).
    pub fn ring_min_base(&self, grid: &Grid) -> f64 {
        let n2 = grid.n2;
        let ring = self.ring.iter().enumerate().filter(|(_, &under)| under);
        if !self.rows.any() {
            return ring
                .flat_map(|(i, _)| self.base[i * n2..(i + 1) * n2].iter().copied())
                .fold(f64::INFINITY, f64::min);
        }
        ring.flat_map(|(i, _)| i * n2..(i + 1) * n2)
            .map(|k| self.base[k] + self.rows.min_dev(k))
            .fold(f64::INFINITY, f64::min)
    }

    /// A rough film's κ − 1 at node k of gap h̄ = `h` (docs/model.md §11): σφs(h)/h, over a
    /// row that varies across its cell the samples' mean of σφs(h) over h̄ (the shear flow
    /// each sample's film carries).
    #[inline]
    pub fn couette_excess(&self, f: &FlowFactors, k: usize, h: f64) -> f64 {
        match self.rows.of(k) {
            None => f.couette_excess(h),
            Some(_) => self.rows.mean_of(k, h, |x| f.couette_excess(x) * x) / h,
        }
    }

    #[inline]
    pub fn h(&self, grid: &Grid, k: usize, z: f64) -> f64 {
        if self.ring[k / grid.n2] {
            self.base[k] + z
        } else {
            self.base[k]
        }
    }
}

/// Field by field; `clone_from` keeps the arrays' allocations.
impl Clone for Gap {
    fn clone(&self) -> Self {
        Gap {
            base: self.base.clone(),
            ring: self.ring.clone(),
            flow: self.flow,
            rows: self.rows.clone(),
            fitted: self.fitted.clone(),
            fitted_x2: self.fitted_x2.clone(),
        }
    }

    fn clone_from(&mut self, s: &Self) {
        self.base.clone_from(&s.base);
        self.ring.clone_from(&s.ring);
        self.flow = s.flow;
        self.rows.clone_from(&s.rows);
        self.fitted.clone_from(&s.fitted);
        self.fitted_x2.clone_from(&s.fitted_x2);
    }
}
