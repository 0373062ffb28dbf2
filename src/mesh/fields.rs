//! The film fields on the mesh at one time level: pressure, film content and active set.

use super::{Gap, Grid};
use crate::model::film::Boundary;

/// The film fields at one time level.
#[derive(Clone, Debug)]
pub struct FilmState {
    /// Pressure p (units of 6μUL/H²).
    pub p: Vec<f64>,
    /// Film content φ = hθ (µm).
    pub phi: Vec<f64>,
    /// Active set: node pressurised (θ = 1).
    pub pressurised: Vec<bool>,
}

impl FilmState {
    /// Takes `other`'s values (same grid), reusing the allocations.
    pub fn assign(&mut self, other: &FilmState) {
        self.p.copy_from_slice(&other.p);
        self.phi.copy_from_slice(&other.phi);
        self.pressurised.copy_from_slice(&other.pressurised);
    }

    /// Zero pressure and film φ_0 everywhere (capped at the local gap), nothing pressurised.
    /// A film solve lays the cavity pressures of its boundary data on the cavitated nodes
    /// ([`FilmState::lay_cavity_pressure`]).
    pub fn cavitated(grid: &Grid, gap: &Gap, z: f64, phi0: f64) -> Self {
        let n = grid.nodes();
        let phi = (0..n).map(|k| phi0.min(gap.h(grid, k, z))).collect();
        FilmState {
            p: vec![0.0; n],
            phi,
            pressurised: vec![false; n],
        }
    }
    /// p = p_c, the cavity pressure of `bc` (docs/model.md §3), on every cavitated node of
    /// the interior columns 1..n1 − 1.
    pub fn lay_cavity_pressure(&mut self, grid: &Grid, bc: &Boundary) {
        let n2 = grid.n2;
        for i in 1..grid.n1 {
            let pc = bc.cavity_pressure(i, grid.n1);
            let span = i * n2..(i + 1) * n2;
            for (p, &pr) in self.p[span.clone()].iter_mut().zip(&self.pressurised[span]) {
                if !pr {
                    *p = pc;
                }
            }
        }
    }

    /// A full film (θ = 1, p = 0) everywhere.
    pub fn flooded(grid: &Grid, gap: &Gap, z: f64) -> Self {
        Self::cavitated(grid, gap, z, f64::INFINITY)
    }
    /// Saturation θ = φ/h at node k.
    pub fn theta(&self, grid: &Grid, gap: &Gap, z: f64, k: usize) -> f64 {
        self.phi[k] / gap.h(grid, k, z)
    }
}
