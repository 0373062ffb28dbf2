//! The operating point in physical units (docs/model.md §1, §9): what an engineer gives
//! (speed, load, viscosity, ring width and mass, oil supply), the scales that make it
//! nondimensional, the outcomes back in N/m and W/m, and where the film model stops.
//!
//! The scales follow the run: U is the sliding speed and μ the oil's viscosity, L = 1 cm and
//! H = 1 µm always. Then the scaled speed is u = 1 and only two groups reach the equations,
//! W_ps = W·H²/(6μUL²) and m = M·H³U/(6L⁴μ) (with the ring width): two rings with the same
//! groups are the same scaled problem, to the bit.

use serde::{Deserialize, Serialize};

use super::case::{bad, short, CaseSpec, InputError};
pub use super::scales::{Scales, COMPOSITE_ROUGHNESS_UM};
use super::units::{stribeck, H_M};

impl Scales {
    /// The outcomes of `case` in physical units, from its mean friction coefficient and
    /// minimum clearance.
    pub fn physical(&self, case: &CaseSpec, f_mean: f64, c_min_um: f64) -> Physical {
        // f = (H/6L)·F/W_ps (eq. 11) and F is in units of μUL/H, so F·μUL/H = f·W_ps·6μUL²/H²:
        // the friction force is f times the load.
        let force = f_mean * case.w_ps * self.load_n_per_m();
        Physical {
            stribeck: stribeck(case.u, case.w_ps),
            load_n_per_m: case.w_ps * self.load_n_per_m(),
            speed_ms: case.u * self.speed_ms,
            friction_n_per_m: force,
            power_w_per_m: force * case.u * self.speed_ms,
            c_min_um,
        }
    }
}

/// A run's outcomes in physical units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Physical {
    /// Stribeck number S = μU/W (eq. 19).
    pub stribeck: f64,
    /// Ring load per unit circumferential length (N/m) and sliding speed (m/s).
    pub load_n_per_m: f64,
    pub speed_ms: f64,
    /// Period-mean friction force per unit circumferential length (N/m).
    pub friction_n_per_m: f64,
    /// Friction power per unit circumferential length (W/m): force × speed.
    pub power_w_per_m: f64,
    /// Minimum clearance (µm).
    pub c_min_um: f64,
}

/// An operating point in physical units. Defaults: the paper's (docs/model.md §1, §4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Operating {
    /// Sliding speed of the liner under the ring (m/s).
    pub speed_ms: f64,
    /// Ring load per unit circumferential length (N/m).
    pub load_n_per_m: f64,
    /// Dynamic viscosity of the oil (Pa·s).
    pub viscosity_pas: f64,
    /// Axial width of the ring face (mm).
    pub ring_width_mm: f64,
    /// Ring mass per unit circumferential length (kg/m).
    pub ring_mass_kg_per_m: f64,
    /// Inlet oil film (µm).
    pub d_oil_um: f64,
}

/// One physical input: its name (as `Operating`'s fields are checked), its unit and the
/// range accepted. The ranges hold every engine ring with room to spare; a value beyond them
/// is a slip of unit or of digits (a load of 40 kN/m, a viscosity of 4 Pa·s), not a ring.
pub const RANGES: [(&str, &str, f64, f64); 6] = [
    ("speed", "m/s", 1e-3, 100.0),
    ("load", "N/m", 1e-2, 1e6),
    ("viscosity", "Pa·s", 1e-4, 10.0),
    ("ring_width", "mm", 0.1, 10.0),
    ("ring_mass", "kg/m", 1e-5, 10.0),
    ("d_oil", "µm", 0.01, 1000.0),
];

impl Default for Operating {
    fn default() -> Self {
        Self::paper()
    }
}

impl Operating {
    /// The paper's operating point: 10 m/s, W_ps = 1.66e-6 (39.84 N/m) at 0.004 Pa·s, a ring
    /// 0.8 mm wide of m = 2e-9 (0.048 kg/m), fully flooded (20 µm). Stribeck number 1.0e-3.
    pub fn paper() -> Self {
        Operating {
            speed_ms: 10.0,
            load_n_per_m: 39.84,
            viscosity_pas: 0.004,
            ring_width_mm: 0.8,
            ring_mass_kg_per_m: 0.048,
            d_oil_um: 20.0,
        }
    }

    fn values(&self) -> [f64; 6] {
        [
            self.speed_ms,
            self.load_n_per_m,
            self.viscosity_pas,
            self.ring_width_mm,
            self.ring_mass_kg_per_m,
            self.d_oil_um,
        ]
    }

    /// Every input finite, positive and within [`RANGES`]; the error names the input.
    pub fn check(&self) -> Result<(), InputError> {
        for ((name, unit, lo, hi), v) in RANGES.iter().zip(self.values()) {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(
                    name,
                    v,
                    format!("must be a finite number > 0 ({unit})"),
                ));
            }
            if !(*lo..=*hi).contains(&v) {
                return Err(bad(
                    name,
                    v,
                    format!(
                        "must lie in [{}, {}] {unit}; check the unit",
                        short(*lo),
                        short(*hi)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The scales of this point: its speed and viscosity.
    pub fn scales(&self) -> Scales {
        Scales {
            speed_ms: self.speed_ms,
            viscosity_pas: self.viscosity_pas,
        }
    }

    /// Stribeck number μU/W (eq. 19).
    pub fn stribeck(&self) -> f64 {
        self.viscosity_pas * self.speed_ms / self.load_n_per_m
    }

    /// Sets the case's operating point to this one, scaled (docs/model.md §1): u = 1,
    /// W_ps, m, the ring width in cm and d_oil. Scaled values are rounded to 12 significant
    /// digits, far below any input's precision, so that the paper's point in SI is the
    /// paper's scaled case exactly and equal physical groups give one scaled case.
    pub fn apply(&self, case: &mut CaseSpec) {
        let s = self.scales();
        case.u = 1.0;
        case.w_ps = canonical(self.load_n_per_m / s.load_n_per_m());
        case.mass = canonical(self.ring_mass_kg_per_m / s.mass_kg_per_m());
        case.ring_width = canonical(self.ring_width_mm / 10.0);
        case.d_oil = self.d_oil_um;
        case.scales = s;
    }
}

/// `x` rounded to 12 significant digits.
fn canonical(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// Where the film model stops (docs/model.md §9): it has no asperity contact, so a film
/// thinner than a few composite roughnesses is mixed lubrication, outside it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Validity {
    /// Composite RMS roughness of ring and liner σ (µm).
    pub roughness_um: f64,
}

/// Film parameter Λ = h/σ above which the surfaces run on a full film (Hamrock, Schmid &
/// Jacobson, *Fundamentals of Fluid Film Lubrication*, 2004: Λ > 3 full film, 1 < Λ < 3
/// mixed).
pub const FULL_FILM_LAMBDA: f64 = 3.0;

/// Film parameter Λ below which the asperities carry most of the load: boundary lubrication
/// (Hamrock, Schmid & Jacobson, 2004, ch. 1: Λ < 1).
pub const BOUNDARY_LAMBDA: f64 = 1.0;

/// The lubrication regime of a film parameter Λ = h_min/σ (docs/model.md §9): "hydrodynamic"
/// for Λ ≥ 3, "mixed" for 1 ≤ Λ < 3, "boundary" below.
pub fn regime(lambda: f64) -> &'static str {
    if lambda >= FULL_FILM_LAMBDA {
        "hydrodynamic"
    } else if lambda >= BOUNDARY_LAMBDA {
        "mixed"
    } else {
        "boundary"
    }
}

/// Stribeck numbers over which the tiers' accuracy was checked (docs/validation.md).
pub const VALIDATED_STRIBECK: (f64, f64) = (1e-4, 1e-2);

impl Default for Validity {
    fn default() -> Self {
        Validity {
            roughness_um: COMPOSITE_ROUGHNESS_UM,
        }
    }
}

impl Validity {
    /// Sets the case's asperity contact (if it has one) to this composite roughness σ
    /// (docs/model.md §9, §11).
    pub fn apply(&self, case: &mut CaseSpec) {
        if let Some(a) = case.contact.as_mut() {
            a.sigma = self.roughness_um * H_M;
        }
    }

    /// The least clearance of a full film (µm): Λ·σ.
    pub fn clearance_limit_um(&self) -> f64 {
        FULL_FILM_LAMBDA * self.roughness_um
    }

    /// Why an outcome is outside the hydrodynamic model, if it is: a minimum clearance below
    /// [`Self::clearance_limit_um`], or a Stribeck number outside [`VALIDATED_STRIBECK`].
    pub fn outside(&self, case: &CaseSpec, c_min_um: f64) -> Option<Outside> {
        let limit_um = self.clearance_limit_um();
        if c_min_um.is_nan() || c_min_um < limit_um {
            return Some(Outside::BelowClearance {
                c_min_um,
                limit_um,
                roughness_um: self.roughness_um,
            });
        }
        let stribeck = stribeck(case.u, case.w_ps);
        let (lo, hi) = VALIDATED_STRIBECK;
        if !(lo * (1.0 - 1e-9)..=hi * (1.0 + 1e-9)).contains(&stribeck) {
            return Some(Outside::Stribeck { stribeck });
        }
        None
    }
}

/// Why an answer is not a prediction of the hydrodynamic model. Its words (`Display`) are what
/// the reports print and the JSON/CSV rows hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outside {
    /// The least clearance below Λ·σ (docs/model.md §11): the asperities carry part of the load.
    BelowClearance {
        c_min_um: f64,
        limit_um: f64,
        roughness_um: f64,
    },
    /// A Stribeck number outside [`VALIDATED_STRIBECK`].
    Stribeck { stribeck: f64 },
    /// No outcome to judge: the run failed.
    NoOutcome,
}

impl std::fmt::Display for Outside {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Outside::BelowClearance {
                c_min_um,
                limit_um,
                roughness_um,
            } => write!(
                f,
                "C_min {c_min_um:.3} µm < {limit_um:.2} µm ({FULL_FILM_LAMBDA} × composite roughness {} µm): mixed lubrication: the asperities carry part of the load (docs/model.md §11) on a film without roughness flow factors",
                short(roughness_um)
            ),
            Outside::Stribeck { stribeck } => {
                let (lo, hi) = VALIDATED_STRIBECK;
                write!(
                    f,
                    "Stribeck number {} outside the validated {}..{}",
                    short(stribeck),
                    short(lo),
                    short(hi)
                )
            }
            Outside::NoOutcome => write!(f, "the run failed"),
        }
    }
}

impl serde::Serialize for Outside {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_papers_point_in_si_is_the_papers_scaled_case() {
        let mut c = CaseSpec::paper(0.8);
        Operating::paper().apply(&mut c);
        assert_eq!(c, CaseSpec::paper(0.8));
        assert!((Operating::paper().stribeck() - 1.004e-3).abs() < 1e-6);
    }

    #[test]
    fn similar_points_share_one_scaled_case() {
        // p ∝ μU and Z'' ∝ U²: twice the viscosity at half the speed with four times the mass
        // is the same scaled problem.
        let a = Operating::paper();
        let b = Operating {
            viscosity_pas: 2.0 * a.viscosity_pas,
            speed_ms: 0.5 * a.speed_ms,
            ring_mass_kg_per_m: 4.0 * a.ring_mass_kg_per_m,
            ..a
        };
        let (mut ca, mut cb) = (CaseSpec::paper(5.0), CaseSpec::paper(5.0));
        a.apply(&mut ca);
        b.apply(&mut cb);
        // The asperities' pressure and shear in scaled units depend on μU alone (docs/model.md
        // §11), the same here: the contact is one scaled problem too.
        assert_eq!(
            CaseSpec {
                scales: Scales::PAPER,
                ..ca.clone()
            },
            CaseSpec {
                scales: Scales::PAPER,
                ..cb.clone()
            }
        );
        assert_eq!(ca.contact_law(), cb.contact_law());
        // Twice the speed with twice the load and the same mass group is one scaled film
        // problem but not one contact problem.
        let c = Operating {
            speed_ms: 2.0 * a.speed_ms,
            load_n_per_m: 2.0 * a.load_n_per_m,
            ring_mass_kg_per_m: 0.5 * a.ring_mass_kg_per_m,
            ..a
        };
        let mut cc = CaseSpec::paper(5.0);
        c.apply(&mut cc);
        assert_eq!((cc.w_ps, cc.mass), (ca.w_ps, ca.mass));
        assert_ne!(cc.contact_law(), ca.contact_law());
        // and its friction power halves with the speed.
        let (pa, pb) = (
            a.scales().physical(&ca, 0.1, 1.0),
            b.scales().physical(&cb, 0.1, 1.0),
        );
        assert!((pa.friction_n_per_m - pb.friction_n_per_m).abs() < 1e-9 * pa.friction_n_per_m);
        assert!((pb.power_w_per_m - 0.5 * pa.power_w_per_m).abs() < 1e-9 * pa.power_w_per_m);
    }

    #[test]
    fn friction_force_is_f_times_the_load() {
        let c = CaseSpec::paper(3.2);
        let p = Scales::PAPER.physical(&c, 0.0754, 2.0);
        assert!((p.friction_n_per_m - 0.0754 * 39.84).abs() < 1e-9);
        assert!((p.power_w_per_m - 10.0 * 0.0754 * 39.84).abs() < 1e-8);
    }

    #[test]
    fn bad_inputs_name_themselves() {
        for (field, v) in [
            ("speed", -1.0),
            ("load", 0.0),
            ("viscosity", f64::NAN),
            ("load", 4e7),
        ] {
            let mut o = Operating::paper();
            match field {
                "speed" => o.speed_ms = v,
                "load" => o.load_n_per_m = v,
                _ => o.viscosity_pas = v,
            }
            assert_eq!(o.check().unwrap_err().param, field);
        }
        assert!(Operating::paper().check().is_ok());
    }

    #[test]
    fn thin_films_are_outside_the_model() {
        let v = Validity::default();
        let c = CaseSpec::paper(5.0);
        assert!(v.outside(&c, 0.5).is_some());
        assert!(v.outside(&c, 2.0).is_none());
        assert!(v.outside(&c, f64::NAN).is_some());
        let light = CaseSpec { w_ps: 1e-8, ..c };
        assert!(matches!(
            v.outside(&light, 20.0),
            Some(Outside::Stribeck { .. })
        ));
    }
}
