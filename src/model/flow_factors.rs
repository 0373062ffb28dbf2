//! Patir–Cheng average flow model for isotropic roughness (γ = 1), an experiment behind the
//! cargo feature `flow-factors` (docs/model.md §11, "Flow factors"): the pressure flow factor
//! φx on the film's Poiseuille conductance, the shear flow factor φs on its Couette flux (in
//! the ring-frame schemes: backward Euler, BDF2), and the shear stress factors φf, φfs, φfp on
//! the friction. H = h/σ with σ the default composite roughness; the fits are Patir & Cheng's
//! (J. Lubr. Technol. 100 (1978) 12–17; 101 (1979) 220–229), valid for H ≥ 0.5: below, H is
//! taken at 0.5.

use super::scales::COMPOSITE_ROUGHNESS_UM;

/// Liner σ² − ring σ² over σ² (0.25 and 0.15 µm, docs/model.md §9): the weight of the
/// shear stress factor φfs when the liner, the rougher surface, slides (Patir & Cheng 1979).
const SLIDING_ROUGHER: f64 =
    (0.25 * 0.25 - 0.15 * 0.15) / (COMPOSITE_ROUGHNESS_UM * COMPOSITE_ROUGHNESS_UM);

/// H = h/σ, at least 0.5 (the fits' range).
#[inline(always)]
fn film_ratio(h_um: f64) -> f64 {
    (h_um / COMPOSITE_ROUGHNESS_UM).max(0.5)
}

/// Pressure flow factor φx = 1 − 0.90·e^(−0.56·H) (Patir & Cheng 1978, γ = 1) and its slope
/// dφx/dh (per µm; 0 where H is held at 0.5).
#[inline(always)]
pub fn pressure_flow(h_um: f64) -> (f64, f64) {
    let h = h_um / COMPOSITE_ROUGHNESS_UM;
    let e = 0.90 * (-0.56 * h.max(0.5)).exp();
    let slope = if h > 0.5 {
        0.56 * e / COMPOSITE_ROUGHNESS_UM
    } else {
        0.0
    };
    (1.0 - e, slope)
}

/// The Couette flux's factor on the film content with the shear flow factor:
/// (u/2)·θ·(h + σ·φs) = (u/2)·φ·κ, κ = 1 + σ·φs(H)/h, with φs = w·Φs(H) (w: [`SLIDING_ROUGHER`],
/// the liner sliding) and Φs = 1.899·H^0.98·e^(−0.92·H + 0.05·H²) for H ≤ 5, 1.126·e^(−0.25·H)
/// beyond (Patir & Cheng 1979, γ = 1), H held at 0.5 below. The cavitated film's flux is taken
/// as the full film's times θ.
#[inline(always)]
pub fn couette_content_factor(h_um: f64) -> f64 {
    let hr = film_ratio(h_um);
    let big = if hr <= 5.0 {
        1.899 * hr.powf(0.98) * (-0.92 * hr + 0.05 * hr * hr).exp()
    } else {
        1.126 * (-0.25 * hr).exp()
    };
    1.0 + COMPOSITE_ROUGHNESS_UM * SLIDING_ROUGHER * big / h_um
}

/// Shear stress factor φf of the Couette shear (Patir & Cheng 1979, γ = 1): with z = H/3,
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

/// Factor of the film's Couette shear, φf + φfs, with φfs = 11.1·H^2.31·e^(−2.38·H + 0.11·H²)
/// (0 from H = 7 on) weighted by [`SLIDING_ROUGHER`] (Patir & Cheng 1979, γ = 1).
#[inline(always)]
pub fn couette_shear_factor(h_um: f64) -> f64 {
    let hr = film_ratio(h_um);
    let fs = if hr < 7.0 {
        11.1 * hr.powf(2.31) * (-2.38 * hr + 0.11 * hr * hr).exp()
    } else {
        0.0
    };
    couette_factor(hr) + SLIDING_ROUGHER * fs
}

/// Factor of the film's Poiseuille shear, φfp = 1 − 1.40·e^(−0.66·H) (Patir & Cheng 1979,
/// γ = 1).
#[inline(always)]
pub fn poiseuille_shear_factor(h_um: f64) -> f64 {
    1.0 - 1.40 * (-0.66 * film_ratio(h_um)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factors_tend_to_the_smooth_film_and_the_slope_is_the_derivative() {
        let h = 10.0 * COMPOSITE_ROUGHNESS_UM;
        assert!((pressure_flow(h).0 - (1.0 - 0.9 * (-5.6f64).exp())).abs() < 1e-15);
        assert!((couette_shear_factor(40.0 * COMPOSITE_ROUGHNESS_UM) - 1.0).abs() < 1e-3);
        assert!((poiseuille_shear_factor(40.0 * COMPOSITE_ROUGHNESS_UM) - 1.0).abs() < 1e-10);
        // φf is continuous at z = 1 (H = 3).
        let (a, b) = (couette_factor(3.0 - 1e-9), couette_factor(3.0 + 1e-9));
        assert!((a - b).abs() < 1e-6, "{a} {b}");
        let d = 1e-6;
        let fd = (pressure_flow(1.0 + d).0 - pressure_flow(1.0 - d).0) / (2.0 * d);
        assert!((fd - pressure_flow(1.0).1).abs() < 1e-8);
        // Φs's two fits meet at H = 5 to their 3 digits; κ → 1 on a thick film.
        let at5 = |e: f64| couette_content_factor((5.0 + e) * COMPOSITE_ROUGHNESS_UM);
        assert!(
            (at5(-1e-9) - at5(1e-9)).abs() < 2e-4 * (at5(0.0) - 1.0),
            "{} {}",
            at5(-1e-9),
            at5(1e-9)
        );
        assert!((couette_content_factor(100.0) - 1.0).abs() < 1e-6);
    }
}
