//! Scales and nondimensional units (paper §2.5, docs/model.md §1).
//!
//! Every quantity inside texopt is nondimensional with these scales:
//! lengths along the liner (x1, x2, R, per, l1, l2) in cm, gaps (h, Z, e, d_oil, depth) in µm,
//! time in L/U = 1 ms, pressure in 6μUL/H² = 2.4e9 Pa, forces per unit width in
//! 6μUL²/H² = 2.4e7 N/m, friction per unit width in μUL/H = 400 N/m, mass per unit width in
//! 6L⁴μ/(H³U) = 2.4e7 kg/m.

/// Length scale L in metres (1 cm).
pub const L_M: f64 = 1e-2;
/// Gap scale H in metres (1 µm).
pub const H_M: f64 = 1e-6;
/// Velocity scale U in m/s.
pub const U_MS: f64 = 10.0;
/// Oil viscosity μ in Pa·s.
pub const MU_PAS: f64 = 0.004;

/// Number of gap units (µm) in one length unit (cm): converts a ring sag from cm to µm.
pub const UM_PER_CM: f64 = 1e4;

/// Pressure scale 6μUL/H² in Pa.
pub const PRESSURE_PA: f64 = 6.0 * MU_PAS * U_MS * L_M / (H_M * H_M);

/// Friction coefficient from nondimensional friction and load per unit width, eq. (11):
/// f = (H / 6L)·F / W_ps (H/L = 1e-4).
pub fn friction_coefficient(friction_per_width: f64, w_ps: f64) -> f64 {
    (H_M / (6.0 * L_M)) * friction_per_width / w_ps
}

/// Stribeck number of eq. (19): S = (H²/6L²)·u / W_ps, with L and H in the same unit.
pub fn stribeck(u: f64, w_ps: f64) -> f64 {
    (H_M / L_M).powi(2) / 6.0 * u / w_ps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_match_model_md() {
        assert!((PRESSURE_PA - 2.4e9).abs() < 1.0);
        // docs/model.md §1: u = 1, W_ps = 1.66e-6 gives S ≈ 1e-3.
        let s = stribeck(1.0, 1.66e-6);
        assert!((s - 1.004e-3).abs() < 1e-5, "S = {s}");
    }
}
