//! The film fields on the mesh at one time level: pressure, film content and active set.

use super::{Gap, Grid};

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
    pub fn cavitated(grid: &Grid, gap: &Gap, z: f64, phi0: f64) -> Self {
        let n = grid.nodes();
        let phi = (0..n).map(|k| phi0.min(gap.h(grid, k, z))).collect();
        FilmState {
            p: vec![0.0; n],
            phi,
            pressurised: vec![false; n],
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
