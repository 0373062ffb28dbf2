//! The scales of a run (docs/model.md §1): the sliding speed U and the oil's viscosity μ
//! that make an operating point nondimensional, and the units they give; the composite
//! roughness the model's limits and contact take by default. A leaf of the model.

use serde::{Deserialize, Serialize};

use super::units::{H_M, L_M, MU_PAS, U_MS};

/// The scales of a run (docs/model.md §1): sliding speed U (m/s) and viscosity μ (Pa·s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scales {
    pub speed_ms: f64,
    pub viscosity_pas: f64,
}

impl Scales {
    /// The paper's scales: U = 10 m/s, μ = 0.004 Pa·s (the scales of a run given in
    /// nondimensional units).
    pub const PAPER: Scales = Scales {
        speed_ms: U_MS,
        viscosity_pas: MU_PAS,
    };

    /// Force per unit circumferential length, 6μUL²/H² (N/m): the unit of W_ps and W_h.
    pub fn load_n_per_m(&self) -> f64 {
        6.0 * self.viscosity_pas * self.speed_ms * L_M * L_M / (H_M * H_M)
    }

    /// Mass per unit circumferential length, 6L⁴μ/(H³U) (kg/m): the unit of m.
    pub fn mass_kg_per_m(&self) -> f64 {
        6.0 * L_M.powi(4) * self.viscosity_pas / (H_M.powi(3) * self.speed_ms)
    }

    /// Pressure 6μUL/H² (Pa): the unit of p (docs/model.md §1).
    pub fn pressure_pa(&self) -> f64 {
        6.0 * self.viscosity_pas * self.speed_ms * L_M / (H_M * H_M)
    }

    /// Time L/U in ms: the unit of t.
    pub fn time_ms(&self) -> f64 {
        1e3 * L_M / self.speed_ms
    }
}

/// Composite RMS roughness of a plateau-honed liner against a lapped ring face (µm):
/// σ = √(σ_liner² + σ_ring²) with plateau σ_liner ≈ 0.25 µm and σ_ring ≈ 0.15 µm
/// (docs/model.md §9).
pub const COMPOSITE_ROUGHNESS_UM: f64 = 0.3;
