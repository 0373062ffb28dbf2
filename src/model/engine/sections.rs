//! An engine as its file gives it (docs/model.md §10, §11, §13): the crank train, the ring,
//! the gas pressures, the oil, the zones, the asperity contact and the operating map's
//! points, each as the file's section reads.

use serde::{Deserialize, Serialize};

use super::rules::{err, EngineError};
use crate::model::asperity::Asperity;
use crate::model::case::short;
use crate::model::flow_factors::{FlowFactors, LINER_ROUGHNESS_SHARE};

/// An engine as its file gives it (`study::engine_file` reads it): the crank train, the
/// ring, the gas pressure, the oil and the zones.
#[derive(Clone, Debug, Serialize)]
pub struct EngineFile {
    pub engine: Crank,
    pub ring: RingFile,
    pub gas: Gas,
    pub oil: Oil,
    pub zones: Zones,
    /// The asperity contact's constants (docs/model.md §11); the defaults where absent.
    pub contact: ContactFile,
    /// The operating map's points (docs/model.md §13); none: the engine's own point.
    pub operating: Vec<MapPointFile>,
}

/// The asperity contact between ring face and liner (docs/model.md §11, §12): each constant
/// the default of §11 where not given (the roughness is the `[design]` section's).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    pub eta_beta_sigma: Option<f64>,
    pub sigma_over_beta: Option<f64>,
    /// The contact modulus E* (GPa), 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂.
    pub e_star_gpa: Option<f64>,
    /// Shear strength of the boundary film τ₀ (MPa) and its pressure coefficient ς.
    pub tau0_mpa: Option<f64>,
    pub varsigma: Option<f64>,
    /// No asperity contact: the film alone carries the ring.
    #[serde(default)]
    pub off: bool,
    /// The film of smooth surfaces, without the roughness's flow factors (docs/model.md §11,
    /// "Flow factors"), which the cycle's film carries by default.
    #[serde(default)]
    pub smooth_film: bool,
    /// The liner's share of the composite roughness σ², σ_liner²/σ² (0 to 1), which sets
    /// the shear flow's weight; default a plateau-honed liner's 0.25 µm against a lapped
    /// ring's 0.15 µm (0.735).
    pub liner_roughness_share: Option<f64>,
}

impl ContactFile {
    /// The contact of this section with composite roughness `sigma_um` (µm), None when off.
    pub fn asperity(&self, sigma_um: f64) -> Option<Asperity> {
        if self.off {
            return None;
        }
        let d = Asperity::default();
        Some(Asperity {
            sigma: sigma_um * 1e-6,
            eta_beta_sigma: self.eta_beta_sigma.unwrap_or(d.eta_beta_sigma),
            sigma_over_beta: self.sigma_over_beta.unwrap_or(d.sigma_over_beta),
            e_star: self.e_star_gpa.map_or(d.e_star, |e| e * 1e9),
            tau0: self.tau0_mpa.map_or(d.tau0, |t| t * 1e6),
            varsigma: self.varsigma.unwrap_or(d.varsigma),
        })
    }

    /// The film's flow factors with composite roughness `sigma_um` (µm), None for a smooth
    /// film (docs/model.md §11, "Flow factors").
    pub fn flow_factors(&self, sigma_um: f64) -> Option<FlowFactors> {
        (!self.smooth_film).then(|| {
            let share = self.liner_roughness_share.unwrap_or(LINER_ROUGHNESS_SHARE);
            FlowFactors::new(sigma_um, share)
        })
    }

    /// Each given constant within its plausible range (docs/model.md §11), else an error
    /// naming the key.
    pub(super) fn check(&self) -> Result<(), EngineError> {
        if let Some(s) = self.liner_roughness_share {
            if !(0.0..=1.0).contains(&s) {
                return Err(err(
                    "[contact] liner_roughness_share",
                    short(s),
                    "must lie in [0, 1]: the liner's share of σ² = σ_ring² + σ_liner²",
                ));
            }
        }
        let Some(a) = self.asperity(0.3) else {
            return Ok(());
        };
        a.check().map_err(|e| {
            let (key, value, unit) = match e.param.as_str() {
                "eta_beta_sigma" => ("eta_beta_sigma", a.eta_beta_sigma, ""),
                "sigma_over_beta" => ("sigma_over_beta", a.sigma_over_beta, ""),
                "e_star" => ("e_star_gpa", a.e_star * 1e-9, " GPa"),
                "tau0" => ("tau0_mpa", a.tau0 * 1e-6, " MPa"),
                _ => ("varsigma", a.varsigma, ""),
            };
            let (lo, hi) = crate::model::asperity::RANGES
                .iter()
                .find(|r| r.0 == e.param)
                .map_or((0.0, 0.0), |r| (r.1, r.2));
            let scale = match key {
                "e_star_gpa" => 1e-9,
                "tau0_mpa" => 1e-6,
                _ => 1.0,
            };
            err(
                &format!("[contact] {key}"),
                short(value),
                format!(
                    "must lie in [{}, {}]{unit}",
                    short(lo * scale),
                    short(hi * scale)
                ),
            )
        })
    }
}

/// The crank train.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Crank {
    pub name: String,
    pub bore_mm: f64,
    pub stroke_mm: f64,
    pub rod_mm: f64,
    pub rpm: f64,
}

/// The engine file's ring section (the dynamics' ring is `model::ring::Ring`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RingFile {
    /// Face radius R (cm).
    #[serde(rename = "R_cm")]
    pub r_cm: f64,
    pub width_mm: f64,
    pub mass_kg_per_m: f64,
    /// Elastic (tension) load per unit circumferential length (N/m).
    pub elastic_load_n_per_m: f64,
}

/// The gas pressure behind the ring and above it (the cylinder's; gauge, bar) against crank
/// angle from firing top dead centre (degrees, 0–720, increasing): linear between the points,
/// periodic over 720°. Below the ring: a table of its own (`below_crank_deg`,
/// `below_pressure_bar`), ambient (0) where none is given.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Gas {
    pub crank_deg: Vec<f64>,
    pub pressure_bar: Vec<f64>,
    #[serde(default)]
    pub below_crank_deg: Vec<f64>,
    #[serde(default)]
    pub below_pressure_bar: Vec<f64>,
}

/// The oil: viscosity, and the film on the liner ahead of the ring (one value: everywhere;
/// a table: against the distance from top dead centre).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Oil {
    pub viscosity_pa_s: f64,
    pub d_oil_um: OilSupply,
    #[serde(default)]
    pub position_mm: Vec<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub enum OilSupply {
    Everywhere(f64),
    Table(Vec<f64>),
}

/// The zones of the liner along the stroke: `count` equal ones, or their boundaries (mm from
/// top dead centre, from 0 to the stroke, increasing).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Zones {
    pub count: Option<usize>,
    pub boundaries_mm: Option<Vec<f64>>,
}

/// One `[[operating]]` point as the engine file gives it; what it leaves out is the engine's.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MapPointFile {
    /// Names the point in the reports (letters, digits, '-', '_').
    pub name: String,
    /// Its share of the running time: any positive numbers, normalised over the map.
    pub weight: f64,
    pub rpm: Option<f64>,
    /// A factor on the gas pressures above and below the ring (the load), 0 to 10.
    pub gas_scale: Option<f64>,
    /// The oil's viscosity there (its temperature), Pa·s.
    pub viscosity_pa_s: Option<f64>,
}
