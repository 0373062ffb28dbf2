//! Patir–Cheng average flow model for isotropic roughness (γ = 1), docs/model.md §11 "Flow
//! factors": the pressure flow factor φx on the film's Poiseuille conductance, the shear flow
//! factor φs on its Couette flux, and the shear stress factors φf, φfs, φfp on the friction,
//! all functions of H = h/σ. The fits are Patir & Cheng's (J. Lubr. Technol. 100 (1978)
//! 12–17; 101 (1979) 220–229), valid for H ≥ 0.5: below, H is taken at 0.5. The engine
//! cycle's film carries them (§12); `simulate`'s, the paper's, is that of smooth surfaces.

use serde::{Deserialize, Serialize};

/// The liner's share of the composite roughness σ², σ_liner²/σ², of a plateau-honed liner
/// (0.25 µm) against a lapped ring face (0.15 µm), docs/model.md §9.
pub const LINER_ROUGHNESS_SHARE: f64 = 0.25 * 0.25 / (0.25 * 0.25 + 0.15 * 0.15);

/// The rough film's flow factors: composite roughness σ and the weight w of the shear flow
/// and shear stress factors φs, φfs (§11, "Flow factors").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlowFactors {
    /// Composite RMS roughness σ (µm).
    pub sigma_um: f64,
    /// w = (σ_liner² − σ_ring²)/σ²: the sliding surface's (the liner's) share of σ² less the
    /// ring's (Patir & Cheng 1979).
    pub sliding_rougher: f64,
}

impl FlowFactors {
    /// The factors of composite roughness `sigma_um` (µm) whose share `liner_share` of σ² is
    /// the liner's: w = 2·share − 1.
    pub fn new(sigma_um: f64, liner_share: f64) -> Self {
        FlowFactors {
            sigma_um,
            sliding_rougher: 2.0 * liner_share - 1.0,
        }
    }

    /// H = h/σ, at least 0.5 (the fits' range).
    #[inline(always)]
    fn film_ratio(&self, h_um: f64) -> f64 {
        (h_um / self.sigma_um).max(0.5)
    }

    /// Pressure flow factor φx = 1 − 0.90·e^(−0.56·H) (§11, γ = 1) and its slope dφx/dh (per
    /// µm; 0 where H is held at 0.5).
    #[inline(always)]
    pub fn pressure_flow(&self, h_um: f64) -> (f64, f64) {
        let h = h_um / self.sigma_um;
        let e = 0.90 * (-0.56 * h.max(0.5)).exp();
        let slope = if h > 0.5 {
            0.56 * e / self.sigma_um
        } else {
            0.0
        };
        (1.0 - e, slope)
    }

    /// κ − 1 of the Couette flux with the shear flow factor (§11, eq. F1):
    /// (u/2)·θ·(h + σ·φs) = (u/2)·κ·φ, κ − 1 = σ·φs(H)/h, φs = w·Φs(H),
    /// Φs = 1.899·H^0.98·e^(−0.92·H + 0.05·H²) for H ≤ 5, 1.126·e^(−0.25·H) beyond, H held at
    /// 0.5 below. The cavitated film's flux is taken as the full film's times θ.
    #[inline(always)]
    pub fn couette_excess(&self, h_um: f64) -> f64 {
        let hr = self.film_ratio(h_um);
        let big = if hr <= 5.0 {
            1.899 * hr.powf(0.98) * (-0.92 * hr + 0.05 * hr * hr).exp()
        } else {
            1.126 * (-0.25 * hr).exp()
        };
        self.sigma_um * self.sliding_rougher * big / h_um
    }

    /// Factor of the film's Couette shear, φf + w·φfs, φfs = 11.1·H^2.31·e^(−2.38·H + 0.11·H²)
    /// (0 from H = 7 on) (§11, γ = 1).
    #[inline(always)]
    pub fn couette_shear(&self, h_um: f64) -> f64 {
        let hr = self.film_ratio(h_um);
        let fs = if hr < 7.0 {
            11.1 * hr.powf(2.31) * (-2.38 * hr + 0.11 * hr * hr).exp()
        } else {
            0.0
        };
        couette_factor(hr) + self.sliding_rougher * fs
    }

    /// Factor of the film's Poiseuille shear, φfp = 1 − 1.40·e^(−0.66·H) (§11, γ = 1).
    #[inline(always)]
    pub fn poiseuille_shear(&self, h_um: f64) -> f64 {
        1.0 - 1.40 * (-0.66 * self.film_ratio(h_um)).exp()
    }
}

/// "a rough film (…)" as a report's header says it, or the film of smooth surfaces for None.
pub fn film_label(flow: Option<&FlowFactors>) -> String {
    flow.map_or("the film of smooth surfaces".into(), |f| {
        format!(
            "a rough film (Patir–Cheng flow factors, σ = {} µm, w = {:.2})",
            f.sigma_um, f.sliding_rougher
        )
    })
}

/// Shear stress factor φf of the Couette shear (§11, γ = 1): with z = H/3,
/// (35/32)·z·[(1 − z²)³·ln((z + 1)/ε*) + P(z)] for z ≤ 1 (ε* = 1/300) and the closed form
/// with ln((z + 1)/(z − 1)) beyond; 1 from z = 10 on.
#[inline(always)]
fn couette_factor(hr: f64) -> f64 {
    let z = hr / 3.0;
    let c3 = (1.0 - z * z).powi(3);
    if z <= 1.0 {
        let poly = -55.0
            + z * (132.0 + z * (345.0 + z * (-160.0 + z * (-405.0 + z * (60.0 + 147.0 * z)))));
        35.0 / 32.0 * z * (c3 * (300.0 * (z + 1.0)).ln() + poly / 60.0)
    } else if z < 10.0 {
        let z2 = z * z;
        35.0 / 32.0
            * z
            * (c3 * ((z + 1.0) / (z - 1.0)).ln() + z / 15.0 * (66.0 + z2 * (30.0 * z2 - 80.0)))
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIGMA: f64 = 0.3;

    fn ff() -> FlowFactors {
        FlowFactors::new(SIGMA, LINER_ROUGHNESS_SHARE)
    }

    #[test]
    fn the_factors_tend_to_the_smooth_film_and_the_slope_is_the_derivative() {
        let f = ff();
        let h = 10.0 * SIGMA;
        assert!((f.pressure_flow(h).0 - (1.0 - 0.9 * (-5.6f64).exp())).abs() < 1e-15);
        assert!((f.couette_shear(40.0 * SIGMA) - 1.0).abs() < 1e-3);
        assert!((f.poiseuille_shear(40.0 * SIGMA) - 1.0).abs() < 1e-10);
        // φf is continuous at z = 1 (H = 3).
        let (a, b) = (couette_factor(3.0 - 1e-9), couette_factor(3.0 + 1e-9));
        assert!((a - b).abs() < 1e-6, "{a} {b}");
        let d = 1e-6;
        let fd = (f.pressure_flow(1.0 + d).0 - f.pressure_flow(1.0 - d).0) / (2.0 * d);
        assert!((fd - f.pressure_flow(1.0).1).abs() < 1e-8);
        // Φs's two fits meet at H = 5 to their 3 digits; κ → 1 on a thick film.
        let at5 = |e: f64| f.couette_excess((5.0 + e) * SIGMA);
        assert!(
            (at5(-1e-9) - at5(1e-9)).abs() < 2e-4 * at5(0.0),
            "{} {}",
            at5(-1e-9),
            at5(1e-9)
        );
        assert!(f.couette_excess(100.0).abs() < 1e-6);
    }

    #[test]
    fn equal_roughnesses_carry_no_shear_flow() {
        // w = 0 when the ring is as rough as the liner: φs and φfs vanish.
        let f = FlowFactors::new(SIGMA, 0.5);
        assert_eq!(f.sliding_rougher, 0.0);
        assert_eq!(f.couette_excess(0.6), 0.0);
        assert_eq!(f.couette_shear(1.2), couette_factor(4.0));
        // The default split: w = (0.25² − 0.15²)/(0.25² + 0.15²).
        assert!((ff().sliding_rougher - 0.04 / 0.085).abs() < 1e-15);
    }
}
