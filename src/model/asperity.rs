//! Asperity contact after Greenwood and Tripp (docs/model.md §11).
//!
//! J. A. Greenwood and J. H. Tripp, *The contact of two nominally flat rough surfaces*,
//! Proc. IMechE 185 (1970) 625–633 ("GT" below). Two rough surfaces at a mean separation h,
//! composite roughness σ, λ = h/σ:
//!
//! ```text
//! F_n(λ) = (2π)^(-1/2) ∫_λ^∞ (s − λ)^n e^(−s²/2) ds                      (§11, eq. A1)
//! p_a    = K·E*·F_{5/2}(λ),  K = (16√2/15)·π·(ηβσ)²·√(σ/β)                (§11, eq. A2)
//! A_a/A  = π²·(ηβσ)²·F_2(λ)                                               (§11, eq. A3)
//! τ_b    = τ₀·A_a/A + ς·p_a                                               (§11, eq. A4)
//! ```
//!
//! with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (no factor 2: texts writing E′ = 2E* use 8√2/15).
//!
//! The integrals are tabulated once (on first use) over −8 ≤ λ < 37 from an exp-sinh
//! quadrature and read back by cubic Hermite interpolation of ln F_n with the exact slopes
//! d ln F_n/dλ = −n·F_{n−1}/F_n: relative error below 2e-10 there, 30–45 ns a value. Beyond
//! λ = 37 every F_n is exactly 0 (F_{5/2}(37) ≈ 2e-303, the last normal doubles); below
//! λ = −8 (an interpenetration of 8σ, outside any use) they are computed directly, slowly.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::sync::OnceLock;

use super::input::{bad, short, InputError};
use super::scales::{Scales, COMPOSITE_ROUGHNESS_UM};
use super::units::H_M;

/// Separation λ = h/σ from which every F_n is exactly 0 (F_{5/2}(37) ≈ 2.3e-303).
pub const LAMBDA_CUT: f64 = 37.0;
/// Lowest λ of the table; below it the integrals are evaluated directly.
pub const LAMBDA_TABLE_MIN: f64 = -8.0;

/// Table step in λ: the Hermite error of ln F_n is ≈ max|d⁴ ln F_n/dλ⁴|·STEP⁴/384.
const STEP: f64 = 1.0 / 32.0;
const INTERVALS: usize = ((LAMBDA_CUT - LAMBDA_TABLE_MIN) / STEP) as usize;
/// ln √(2π).
const LN_SQRT_2PI: f64 = 0.918_938_533_204_672_8;

/// GT's F_{5/2}(λ) (§11, eq. A1): the asperity pressure's shape.
pub fn f_5_2(lambda: f64) -> f64 {
    lookup(lambda, |t| &t.f52, 2.5)
}

/// GT's F_{3/2}(λ) (§11, eq. A1): dF_{5/2}/dλ = −(5/2)·F_{3/2}.
pub fn f_3_2(lambda: f64) -> f64 {
    lookup(lambda, |t| &t.f32, 1.5)
}

/// GT's F_2(λ) (§11, eq. A1): the real contact area's shape.
pub fn f_2(lambda: f64) -> f64 {
    lookup(lambda, |t| &t.f2, 2.0)
}

/// dF_{5/2}/dλ = −(5/2)·F_{3/2}(λ) (differentiating eq. A1 under the integral).
pub fn df_5_2(lambda: f64) -> f64 {
    -2.5 * f_3_2(lambda)
}

/// F_n(λ) of §11, eq. A1 for any order n ≥ 0 by direct quadrature (about 40 µs): the
/// reference the tables are built from. 0 for λ ≥ LAMBDA_CUT, as the tables.
pub fn f_n(n: f64, lambda: f64) -> f64 {
    if lambda.is_nan() || n.is_nan() {
        return f64::NAN;
    }
    if lambda >= LAMBDA_CUT {
        return 0.0;
    }
    if lambda < LAMBDA_TABLE_MIN {
        return moment_far_below(n, lambda);
    }
    (ln_f(&[n], lambda)[0]).exp()
}

fn lookup(lambda: f64, table: fn(&Tables) -> &Table, n: f64) -> f64 {
    if (LAMBDA_TABLE_MIN..LAMBDA_CUT).contains(&lambda) {
        table(tables()).eval(lambda).exp()
    } else if lambda >= LAMBDA_CUT {
        0.0
    } else {
        f_n(n, lambda) // below the table, or NaN
    }
}

/// ln F_n and its slope d ln F_n/dλ at the nodes λ_i = LAMBDA_TABLE_MIN + i·STEP.
struct Table {
    nodes: Vec<[f64; 2]>,
}

impl Table {
    /// Cubic Hermite interpolation of ln F_n (value and exact slope at both nodes).
    #[inline]
    fn eval(&self, lambda: f64) -> f64 {
        let x = (lambda - LAMBDA_TABLE_MIN) * (1.0 / STEP);
        let i = (x as usize).min(INTERVALS - 1);
        let t = x - i as f64;
        let [g0, s0] = self.nodes[i];
        let [g1, s1] = self.nodes[i + 1];
        let u = 1.0 - t;
        let h00 = (1.0 + 2.0 * t) * u * u;
        let h10 = t * u * u;
        let h01 = t * t * (3.0 - 2.0 * t);
        let h11 = -t * t * u;
        h00 * g0 + h01 * g1 + STEP * (h10 * s0 + h11 * s1)
    }
}

struct Tables {
    f52: Table,
    f32: Table,
    f2: Table,
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(build_tables)
}

/// Orders computed at each node: F_{5/2}, F_{3/2}, F_{1/2} (the slope of F_{3/2}), F_2, F_1.
const ORDERS: [f64; 5] = [2.5, 1.5, 0.5, 2.0, 1.0];

fn build_tables() -> Tables {
    let rule = ExpSinh::new(&ORDERS);
    let mut f52 = Vec::with_capacity(INTERVALS + 1);
    let mut f32 = Vec::with_capacity(INTERVALS + 1);
    let mut f2 = Vec::with_capacity(INTERVALS + 1);
    for i in 0..=INTERVALS {
        let lambda = LAMBDA_TABLE_MIN + i as f64 * STEP;
        let [g52, g32, g12, g2, g1] = rule.ln_f(lambda);
        // d ln F_n/dλ = −n·F_{n−1}/F_n (dF_n/dλ = −n·F_{n−1}).
        f52.push([g52, -2.5 * (g32 - g52).exp()]);
        f32.push([g32, -1.5 * (g12 - g32).exp()]);
        f2.push([g2, -2.0 * (g1 - g2).exp()]);
    }
    Tables {
        f52: Table { nodes: f52 },
        f32: Table { nodes: f32 },
        f2: Table { nodes: f2 },
    }
}

/// ln F_n(λ) for each order in `orders`, −8 ≤ λ < 37.
fn ln_f(orders: &[f64], lambda: f64) -> Vec<f64> {
    let rule = ExpSinh::new(orders);
    let mut out = vec![0.0; orders.len()];
    rule.ln_f_into(lambda, &mut out);
    out
}

/// Exp-sinh quadrature of I_n(λ) = ∫_0^∞ t^n e^(−λt − t²/2) dt, with
/// F_n(λ) = e^(−λ²/2)·I_n(λ)/√(2π) (eq. A1 with s = λ + t): t = exp((π/2)·sinh x) on a
/// uniform grid in x, which resolves the t^n end point and every scale of e^(−λt) at once.
/// Nodes from x = −4 (t ≈ 2e-19) to where e^(−t²/2) underflows; step 1/32 gives ≈ 1e-14.
struct ExpSinh {
    /// (weight·tⁿ for each order, t) at each node.
    nodes: Vec<(Vec<f64>, f64)>,
}

impl ExpSinh {
    const H: f64 = 1.0 / 32.0;
    const X_MAX: f64 = 4.0;

    fn new(orders: &[f64]) -> Self {
        let k_max = (Self::X_MAX / Self::H) as i32;
        let nodes = (-k_max..=k_max)
            .filter_map(|k| {
                let x = k as f64 * Self::H;
                let ln_t = 0.5 * PI * x.sinh();
                let t = ln_t.exp();
                // Past t = 60, e^(−λt − t²/2) < e^(−1300) for every λ ≥ −8 (its peak ≤ e^32).
                (t < 60.0).then(|| {
                    let w = Self::H * 0.5 * PI * x.cosh() * t;
                    (orders.iter().map(|&n| w * (n * ln_t).exp()).collect(), t)
                })
            })
            .collect();
        ExpSinh { nodes }
    }

    fn ln_f(&self, lambda: f64) -> [f64; 5] {
        let mut out = [0.0; 5];
        self.ln_f_into(lambda, &mut out);
        out
    }

    fn ln_f_into(&self, lambda: f64, out: &mut [f64]) {
        let mut sums = vec![0.0; out.len()];
        for (wt, t) in &self.nodes {
            let e = (-lambda * t - 0.5 * t * t).exp();
            for (s, w) in sums.iter_mut().zip(wt) {
                *s += w * e;
            }
        }
        for (o, s) in out.iter_mut().zip(sums) {
            *o = s.ln() - 0.5 * lambda * lambda - LN_SQRT_2PI;
        }
    }
}

/// F_n(λ) for λ < −8 from eq. A1 on −12 ≤ s ≤ 12 by the trapezoidal rule (step 1/8): the
/// integrand is smooth there but within e^(−32) of the lower limit, whose neighbourhood
/// the truncation drops.
fn moment_far_below(n: f64, lambda: f64) -> f64 {
    const H: f64 = 0.125;
    let sum: f64 = (-96..=96)
        .map(|k| {
            let s = k as f64 * H;
            if s > lambda {
                (s - lambda).powf(n) * (-0.5 * s * s).exp()
            } else {
                0.0
            }
        })
        .sum();
    H * sum * (-LN_SQRT_2PI).exp()
}

/// The composite contact modulus E* of §11: 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (Pa).
pub fn composite_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// The rough contact between ring face and liner plateau (§11), in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Asperity {
    /// Composite RMS roughness σ = √(σ_ring² + σ_liner²) (m).
    pub sigma: f64,
    /// Roughness parameter ηβσ: asperity density × summit radius × σ [-].
    pub eta_beta_sigma: f64,
    /// Asperity slope measure σ/β [-].
    pub sigma_over_beta: f64,
    /// Composite modulus E* with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (Pa).
    pub e_star: f64,
    /// Shear strength of the boundary film on the asperity tips τ₀ (Pa).
    pub tau0: f64,
    /// Pressure coefficient of the boundary shear strength ς [-].
    pub varsigma: f64,
}

impl Default for Asperity {
    /// A plateau-honed grey cast-iron liner against a steel ring (docs/model.md §11, table).
    fn default() -> Self {
        Asperity {
            // The validity's roughness (µm) in m, computed as `Validity::apply` does.
            sigma: COMPOSITE_ROUGHNESS_UM * H_M,
            eta_beta_sigma: 0.04,
            sigma_over_beta: 1e-3,
            e_star: composite_modulus(120e9, 0.28, 210e9, 0.28),
            tau0: 2e6,
            varsigma: 0.17,
        }
    }
}

/// Plausible ranges (SI): outside them a value is a slip of unit or digits, not a surface.
pub const RANGES: [(&str, f64, f64); 6] = [
    ("sigma", 1e-9, 1e-5),
    ("eta_beta_sigma", 1e-3, 1.0),
    ("sigma_over_beta", 1e-6, 0.1),
    ("e_star", 1e9, 1e12),
    ("tau0", 0.0, 1e9),
    ("varsigma", 0.0, 1.0),
];

impl Asperity {
    /// Refuses a constant outside its plausible range, naming it.
    pub fn check(&self) -> Result<(), InputError> {
        let values = [
            self.sigma,
            self.eta_beta_sigma,
            self.sigma_over_beta,
            self.e_star,
            self.tau0,
            self.varsigma,
        ];
        for ((name, lo, hi), v) in RANGES.into_iter().zip(values) {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(bad(
                    name,
                    v,
                    format!("must lie in {} to {} (SI units)", short(lo), short(hi)),
                ));
            }
        }
        Ok(())
    }

    /// λ = h/σ for a separation h (m) of the mean planes.
    pub fn lambda(&self, h: f64) -> f64 {
        h / self.sigma
    }

    /// K·E* of eq. A2 (Pa), K = (16√2/15)·π·(ηβσ)²·√(σ/β).
    pub fn pressure_scale(&self) -> f64 {
        16.0 * std::f64::consts::SQRT_2 / 15.0
            * PI
            * self.eta_beta_sigma.powi(2)
            * self.sigma_over_beta.sqrt()
            * self.e_star
    }

    /// Asperity contact pressure p_a = K·E*·F_{5/2}(h/σ) (eq. A2) (Pa).
    pub fn pressure(&self, h: f64) -> f64 {
        self.pressure_scale() * f_5_2(self.lambda(h))
    }

    /// dp_a/dh = −(5/2)·K·E*·F_{3/2}(h/σ)/σ (Pa/m), for a Newton step on the ring's balance.
    pub fn pressure_dh(&self, h: f64) -> f64 {
        self.pressure_scale() * df_5_2(self.lambda(h)) / self.sigma
    }

    /// p_a and dp_a/dh together [Pa, Pa/m].
    pub fn pressure_and_dh(&self, h: f64) -> (f64, f64) {
        (self.pressure(h), self.pressure_dh(h))
    }

    /// Real contact area per nominal area A_a/A = π²·(ηβσ)²·F_2(h/σ) (eq. A3) [-].
    pub fn area_fraction(&self, h: f64) -> f64 {
        PI * PI * self.eta_beta_sigma.powi(2) * f_2(self.lambda(h))
    }

    /// Boundary shear stress τ_b = τ₀·A_a/A + ς·p_a (eq. A4) (Pa): friction force per nominal
    /// area, against the sliding.
    pub fn shear_stress(&self, h: f64) -> f64 {
        self.tau0 * self.area_fraction(h) + self.varsigma * self.pressure(h)
    }
}

/// Separation λ = h/σ from which the contact law of a run ([`ContactLaw`]) carries nothing:
/// p_a and A_a are shifted by their values here and cut to 0 beyond (docs/model.md §11).
pub const LAMBDA_CONTACT: f64 = 4.0;

/// The asperity contact of one run in its scaled units (docs/model.md §1, §11): gaps h in µm,
/// pressure in 6μUL/H², shear stress in μU/H (so that its integral over the ring, lengths in
/// L, is a friction force in μUL/H, eq. 17's unit). Exactly zero from λ = h/σ ≥ 4 on
/// ([`LAMBDA_CONTACT`]): p_a = K·E*·(F_{5/2}(λ) − F_{5/2}(4)) and
/// A_a/A = π²(ηβσ)²·(F_2(λ) − F_2(4)) below, 0 above (eqs. A2, A3 shifted; continuous), so
/// a film thicker than 4σ everywhere under the ring sees no contact at all, to the bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// Composite roughness σ (µm).
    sigma: f64,
    /// K·E* (eq. A2) in pressure units 6μUL/H².
    pressure_scale: f64,
    /// π²·(ηβσ)² (eq. A3).
    area_scale: f64,
    /// τ₀ in shear units μU/H.
    tau0: f64,
    /// ς times the pressure unit over the shear unit, 6ς·L/H: τ_b per scaled p_a (eq. A4).
    varsigma: f64,
    /// F_{5/2}(4) and F_2(4): the shifts that make p_a and A_a vanish at λ = 4.
    f52_cut: f64,
    f2_cut: f64,
}

impl ContactLaw {
    /// The contact of `asperity` (SI) at the run's `scales` (its speed U and viscosity μ).
    pub fn new(asperity: &Asperity, scales: &Scales) -> Self {
        let shear_unit = scales.viscosity_pas * scales.speed_ms / H_M;
        ContactLaw {
            sigma: asperity.sigma / H_M,
            pressure_scale: asperity.pressure_scale() / scales.pressure_pa(),
            area_scale: PI * PI * asperity.eta_beta_sigma.powi(2),
            tau0: asperity.tau0 / shear_unit,
            varsigma: asperity.varsigma * scales.pressure_pa() / shear_unit,
            f52_cut: f_5_2(LAMBDA_CONTACT),
            f2_cut: f_2(LAMBDA_CONTACT),
        }
    }

    /// Composite roughness σ (µm).
    pub fn sigma_um(&self) -> f64 {
        self.sigma
    }

    /// The gap (µm) from which the contact carries nothing: 4σ.
    pub fn reach_um(&self) -> f64 {
        LAMBDA_CONTACT * self.sigma
    }

    /// Whether a gap h (µm) touches: λ = h/σ < 4 (a NaN gap does, and gives NaN).
    #[inline]
    pub fn touches(&self, h: f64) -> bool {
        let lambda = h / self.sigma;
        lambda < LAMBDA_CONTACT || lambda.is_nan()
    }

    /// Asperity pressure p_a at gap h (µm), in pressure units (eq. A2, cut at λ = 4).
    #[inline]
    pub fn pressure(&self, h: f64) -> f64 {
        let lambda = h / self.sigma;
        if lambda >= LAMBDA_CONTACT {
            return 0.0;
        }
        self.pressure_scale * (f_5_2(lambda) - self.f52_cut)
    }

    /// p_a and dp_a/dh (per µm) at gap h: dp_a/dh = −(5/2)·K·E*·F_{3/2}(λ)/σ below λ = 4
    /// (eq. A1's derivative), 0 beyond.
    #[inline]
    pub fn pressure_and_dh(&self, h: f64) -> (f64, f64) {
        let lambda = h / self.sigma;
        if lambda >= LAMBDA_CONTACT {
            return (0.0, 0.0);
        }
        (
            self.pressure_scale * (f_5_2(lambda) - self.f52_cut),
            self.pressure_scale * df_5_2(lambda) / self.sigma,
        )
    }

    /// Real contact area per nominal area A_a/A at gap h (eq. A3, cut at λ = 4).
    #[inline]
    pub fn area_fraction(&self, h: f64) -> f64 {
        let lambda = h / self.sigma;
        if lambda >= LAMBDA_CONTACT {
            return 0.0;
        }
        self.area_scale * (f_2(lambda) - self.f2_cut)
    }

    /// Boundary shear stress τ_b = τ₀·A_a/A + ς·p_a at gap h (eq. A4), in shear units μU/H:
    /// its magnitude, against the sliding.
    #[inline]
    pub fn shear(&self, h: f64) -> f64 {
        if !self.touches(h) {
            return 0.0;
        }
        self.tau0 * self.area_fraction(h) + self.varsigma * self.pressure(h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// erfc by its positive series, erf x = (2/√π)·e^(−x²)·Σ 2^k x^(2k+1)/(2k+1)!!: good to
    /// ≈ 1e-12 relative for 0 ≤ x ≤ 3 (independent of the module).
    fn erfc(x: f64) -> f64 {
        let (mut term, mut sum) = (x, x);
        for k in 1..200 {
            term *= 2.0 * x * x / (2 * k + 1) as f64;
            sum += term;
        }
        1.0 - 2.0 / PI.sqrt() * (-x * x).exp() * sum
    }

    /// F_0, F_1, F_2 in closed form: F_0 = ½erfc(λ/√2), F_1 = φ − λF_0,
    /// F_2 = (1 + λ²)F_0 − λφ, φ = e^(−λ²/2)/√(2π).
    fn closed(lambda: f64) -> [f64; 3] {
        let f0 = 0.5 * erfc(lambda / std::f64::consts::SQRT_2);
        let phi = (-0.5 * lambda * lambda).exp() / (2.0 * PI).sqrt();
        [
            f0,
            phi - lambda * f0,
            (1.0 + lambda * lambda) * f0 - lambda * phi,
        ]
    }

    /// F_{5/2}, F_{3/2}, F_2 at 40 digits (17 shown) from mpmath: the closed form
    /// F_n(λ) = Γ(n+1)·e^(−λ²/4)·D_{−n−1}(λ)/√(2π) (D the parabolic cylinder function),
    /// which matches an adaptive quadrature of eq. A1 to 3e-39 at every point.
    const REFERENCE: [(f64, [f64; 3]); 20] = [
        (
            -20.0,
            [1.797_238_324_662_026_8e3, 8.952_661_109_945_504e1, 401.0],
        ),
        (
            -8.0,
            [1.863_174_056_108_2e2, 2.276_039_726_005_812_4e1, 65.0],
        ),
        (
            -3.0,
            [
                1.881_132_983_241_576_2e1,
                5.418_377_276_511_696,
                9.999_796_564_919_513,
            ],
        ),
        (
            -1.0,
            [
                2.755_501_867_379_427,
                1.404_597_470_473_952_4,
                1.924_660_216_656_229_2,
            ],
        ),
        (
            0.0,
            [6.166_342_189_968_439e-1, 4.300_199_936_622_598e-1, 0.5],
        ),
        (
            0.5,
            [
                2.404_015_706_740_721e-1,
                1.952_036_037_437_906_3e-1,
                2.096_392_600_253_338_8e-1,
            ],
        ),
        (
            1.0,
            [
                8.056_233_557_081_147e-2,
                7.566_817_739_097_507e-2,
                7.533_978_334_377_075e-2,
            ],
        ),
        (
            1.5,
            [
                2.286_305_602_081_809e-2,
                2.463_948_030_748_373_6e-2,
                2.284_701_062_495_112_3e-2,
            ],
        ),
        (
            2.0,
            [
                5.423_705_197_484_414e-3,
                6.648_177_623_587_093e-3,
                5.768_726_714_519_932e-3,
            ],
        ),
        (
            2.5,
            [
                1.063_688_950_133_278_7e-3,
                1.469_938_239_537_991_5e-3,
                1.199_322_377_955_636_6e-3,
            ],
        ),
        (
            3.0,
            [
                1.708_729_962_144_243_7e-4,
                2.639_675_542_694_673e-4,
                2.034_350_804_869_237_4e-4,
            ],
        ),
        (
            3.5,
            [
                2.231_240_719_823_469e-5,
                3.822_707_776_096_11e-5,
                2.794_586_456_054_650_2e-5,
            ],
        ),
        (
            4.0,
            [
                2.353_381_052_587_606e-6,
                4.439_155_958_539_252e-6,
                3.090_208_103_497_254e-6,
            ],
        ),
        (
            5.0,
            [
                1.352_592_002_291_496_7e-8,
                3.033_850_561_878_485e-8,
                1.934_329_518_755_316_4e-8,
            ],
        ),
        (
            6.0,
            [
                3.142_968_531_919_884e-11,
                8.203_580_589_815_165e-11,
                4.844_576_745_511_828e-11,
            ],
        ),
        (
            8.0,
            [
                1.033_917_602_809_632_7e-17,
                3.478_399_792_218_691e-17,
                1.807_506_447_145_85e-17,
            ],
        ),
        (
            12.0,
            [
                1.130_252_757_733_646_2e-35,
                5.553_217_240_644_714e-35,
                2.385_797_169_621_326_2e-35,
            ],
        ),
        (
            20.0,
            [
                5.029_667_393_262_765e-92,
                4.058_555_079_262_784_3e-91,
                1.359_912_914_707_381e-91,
            ],
        ),
        (
            30.0,
            [
                3.282_961_968_135_747e-201,
                3.954_799_087_029_980_8e-200,
                1.084_372_487_398_349e-200,
            ],
        ),
        (
            36.9,
            [
                9.237_120_735_933_605e-302,
                1.366_892_121_115_883_3e-300,
                3.381_417_205_950_123e-301,
            ],
        ),
    ];

    #[test]
    fn integrals_match_high_precision_quadrature() {
        for (lambda, [f52, f32, f2]) in REFERENCE {
            for (got, want, name) in [
                (f_5_2(lambda), f52, "F5/2"),
                (f_3_2(lambda), f32, "F3/2"),
                (f_2(lambda), f2, "F2"),
                (f_n(2.5, lambda), f52, "direct F5/2"),
                (f_n(2.0, lambda), f2, "direct F2"),
            ] {
                assert!(
                    rel(got, want) < 1e-9,
                    "{name}({lambda}) = {got:e}, want {want:e}"
                );
            }
        }
    }

    #[test]
    fn five_digit_values_at_lambda_0_to_4() {
        let f52 = [6.16634e-1, 8.05623e-2, 5.42371e-3, 1.70873e-4, 2.35338e-6];
        let f2 = [5.00000e-1, 7.53398e-2, 5.76873e-3, 2.03435e-4, 3.09021e-6];
        for (i, (a, b)) in f52.iter().zip(f2).enumerate() {
            let lambda = i as f64;
            assert!(rel(f_5_2(lambda), *a) < 1e-5, "F5/2({lambda})");
            assert!(rel(f_2(lambda), b) < 1e-5, "F2({lambda})");
        }
    }

    #[test]
    fn values_at_contact_in_closed_form() {
        // F_n(0) = 2^((n−1)/2)·Γ((n+1)/2)/√(2π); Γ(7/4) = (3/4)Γ(3/4), Γ(5/4) = (1/4)Γ(1/4).
        let gamma_3_4 = 1.225_416_702_465_177_6;
        let gamma_1_4 = 3.625_609_908_221_908;
        let s2pi = (2.0 * PI).sqrt();
        assert!(rel(f_5_2(0.0), 2f64.powf(0.75) * 0.75 * gamma_3_4 / s2pi) < 1e-9);
        assert!(rel(f_3_2(0.0), 2f64.powf(0.25) * 0.25 * gamma_1_4 / s2pi) < 1e-9);
        assert!(rel(f_2(0.0), 0.5) < 1e-9);
    }

    #[test]
    fn integer_orders_match_erfc_closed_forms() {
        for i in 0..=32 {
            let lambda = 0.125 * i as f64;
            let c = closed(lambda);
            for (n, want) in c.iter().enumerate() {
                let got = f_n(n as f64, lambda);
                assert!(
                    rel(got, *want) < 1e-9,
                    "F{n}({lambda}) = {got:e}, want {want:e}"
                );
            }
            assert!(rel(f_2(lambda), c[2]) < 1e-7, "table F2({lambda})");
        }
    }

    #[test]
    fn tables_match_direct_quadrature_on_a_dense_grid() {
        let mut worst: f64 = 0.0;
        for i in 0..=6000 {
            // Off the nodes: an irrational stride.
            let lambda = -8.0 + 44.9 * (i as f64 * 0.618_034).fract();
            worst = worst
                .max(rel(f_5_2(lambda), f_n(2.5, lambda)))
                .max(rel(f_3_2(lambda), f_n(1.5, lambda)))
                .max(rel(f_2(lambda), f_n(2.0, lambda)));
        }
        // 1e-6 is required; 1.5e-10 is measured.
        assert!(worst < 1e-8, "worst relative error {worst:e}");
    }

    #[test]
    fn derivative_matches_finite_difference() {
        for i in 0..=48 {
            let lambda = -2.0 + 0.25 * i as f64;
            let d = 1e-4;
            let fd = (f_5_2(lambda + d) - f_5_2(lambda - d)) / (2.0 * d);
            assert!(rel(df_5_2(lambda), fd) < 1e-6, "dF5/2({lambda})");
        }
    }

    #[test]
    fn decreasing_and_clean_beyond_the_cut() {
        let mut last = [f64::INFINITY; 3];
        for i in 0..=47_000 {
            let lambda = -10.0 + 1e-3 * i as f64;
            let now = [f_5_2(lambda), f_3_2(lambda), f_2(lambda)];
            for k in 0..3 {
                assert!(
                    now[k] < last[k] || now[k] == 0.0,
                    "not decreasing at {lambda}"
                );
                assert!(now[k] > 0.0 || lambda >= LAMBDA_CUT, "zero at {lambda}");
            }
            last = now;
        }
        for lambda in [LAMBDA_CUT, 40.0, 1e3, f64::INFINITY] {
            assert_eq!([f_5_2(lambda), f_3_2(lambda), f_2(lambda)], [0.0; 3]);
        }
        assert!(f_5_2(f64::NAN).is_nan());
        assert!(f_5_2(36.999) > 1e-303);
    }

    #[test]
    fn pressure_at_the_scale_of_a_honed_liner() {
        let a = Asperity {
            eta_beta_sigma: 0.04,
            sigma_over_beta: 1e-3,
            e_star: 73e9,
            ..Asperity::default()
        };
        // K·E* = (16√2/15)·π·0.04²·√1e-3·73 GPa = 17.50 MPa.
        assert!(
            rel(a.pressure_scale(), 17.504e6) < 1e-4,
            "{}",
            a.pressure_scale()
        );
        let h = a.sigma; // λ = 1
        assert!(rel(a.pressure(h), 1.4102e6) < 1e-4, "{}", a.pressure(h));
        let (p, dp) = a.pressure_and_dh(h);
        let dh = 1e-12;
        let fd = (a.pressure(h + dh) - a.pressure(h - dh)) / (2.0 * dh);
        assert_eq!(p, a.pressure(h));
        assert!(rel(dp, fd) < 1e-5 && dp < 0.0, "{dp} vs {fd}");
        assert!(rel(a.area_fraction(h), PI * PI * 0.0016 * 7.533_978e-2) < 1e-6);
        let tau = a.shear_stress(h);
        assert!(rel(tau, 2e6 * a.area_fraction(h) + 0.17 * p) < 1e-12);
        assert_eq!(a.pressure(37.0 * a.sigma), 0.0);
    }

    #[test]
    fn the_runs_law_is_the_si_law_shifted_and_cut_at_lambda_4() {
        let a = Asperity::default();
        let s = Scales {
            speed_ms: 7.0,
            viscosity_pas: 0.01,
        };
        let law = ContactLaw::new(&a, &s);
        let shear_unit = s.viscosity_pas * s.speed_ms / H_M;
        for lambda in [0.0, 0.5, 1.0, 2.0, 3.0, 3.9] {
            let (h_um, h_m) = (lambda * law.sigma_um(), lambda * a.sigma);
            let p = law.pressure(h_um) * s.pressure_pa();
            let want = a.pressure(h_m) - a.pressure_scale() * f_5_2(4.0);
            assert!(rel(p, want) < 1e-12, "λ = {lambda}: {p} vs {want}");
            let area = a.area_fraction(h_m) - PI * PI * 0.04f64.powi(2) * f_2(4.0);
            assert!(rel(law.area_fraction(h_um), area) < 1e-12);
            let tau = a.tau0 * area + a.varsigma * want;
            assert!(rel(law.shear(h_um) * shear_unit, tau) < 1e-12);
            let (p2, dp) = law.pressure_and_dh(h_um);
            assert_eq!(p2, law.pressure(h_um));
            let d = 1e-6;
            let fd = (law.pressure(h_um + d) - law.pressure(h_um - d)) / (2.0 * d);
            assert!(rel(dp, fd) < 1e-6, "λ = {lambda}: {dp} vs {fd}");
        }
        // Exactly nothing from λ = 4 on, continuously.
        let reach = law.reach_um();
        assert_eq!(reach, 4.0 * law.sigma_um());
        for h in [reach, 1.0001 * reach, 10.0, 1e3, f64::INFINITY] {
            assert!(!law.touches(h));
            assert_eq!(law.pressure_and_dh(h), (0.0, 0.0));
            assert_eq!(
                (law.pressure(h), law.area_fraction(h), law.shear(h)),
                (0.0, 0.0, 0.0)
            );
        }
        let below = 4.0 * (1.0 - 1e-9) * law.sigma_um();
        assert!(law.touches(below) && law.pressure(below) >= 0.0);
        assert!(law.pressure(below) < 1e-12 * law.pressure(law.sigma_um()));
        // The cut's share at λ = 3, 2, 1 (docs/model.md §11): 1.4 %, 0.043 %, 0.0029 %.
        for (lambda, share) in [(3.0, 1.377e-2), (2.0, 4.339e-4), (1.0, 2.921e-5)] {
            assert!(
                rel(f_5_2(4.0) / f_5_2(lambda), share) < 1e-3,
                "λ = {lambda}"
            );
        }
    }

    #[test]
    fn default_is_plausible_and_absurd_constants_are_refused() {
        let d = Asperity::default();
        assert_eq!(d.check(), Ok(()));
        // E* of cast iron (120 GPa, ν 0.28) on steel (210 GPa, ν 0.28): 82.9 GPa.
        assert!(rel(d.e_star, 82.86e9) < 1e-3, "{}", d.e_star);
        let err = Asperity { e_star: 2.1e5, ..d }.check().unwrap_err();
        assert_eq!(err.param, "e_star");
        let err = Asperity { sigma: 0.3, ..d }.check().unwrap_err();
        assert_eq!(err.param, "sigma");
        let err = Asperity {
            varsigma: f64::NAN,
            ..d
        }
        .check()
        .unwrap_err();
        assert_eq!(err.param, "varsigma");
    }
}
