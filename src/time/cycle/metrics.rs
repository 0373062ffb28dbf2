//! What an engine engineer reads off a cycle (docs/model.md §12): friction work, mean power
//! per ring and its share of the friction mean effective pressure, the thinnest film and Λ,
//! where the asperities carry load, and the time spent in each lubrication regime.

use super::record::{infinite_if_null, CycleRow};
use crate::model::engine::{zone_of, Engine};

/// The lubrication regimes by the film parameter Λ = h_min/σ (docs/model.md §9).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Regime {
    /// Λ ≥ 3: a full film.
    Hydrodynamic,
    /// 1 ≤ Λ < 3.
    Mixed,
    /// Λ < 1.
    Boundary,
}

impl Regime {
    pub fn of(lambda: f64) -> Regime {
        if lambda >= 3.0 {
            Regime::Hydrodynamic
        } else if lambda >= 1.0 {
            Regime::Mixed
        } else {
            Regime::Boundary
        }
    }
}

/// A cycle's figures of merit.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CycleMetrics {
    /// Friction work per unit circumferential length over the cycle (J/m), and the
    /// asperities' part of it.
    pub work_j_per_m: f64,
    pub asperity_work_j_per_m: f64,
    /// Mean friction power over the cycle, per unit length (W/m) and for the ring (W): per
    /// unit length times the bore's circumference.
    pub mean_power_w_per_m: f64,
    pub ring_power_w: f64,
    /// The ring's friction mean effective pressure: its work over the cycle over the
    /// displacement, W·πB/(πB²S/4) = 4W/(B·S) (kPa).
    pub fmep_kpa: f64,
    /// The thinnest film over the cycle (µm), where (crank angle), and the least Λ.
    pub h_min_um: f64,
    pub h_min_deg: f64,
    /// +∞ without contact: an answer, written as null (crate::finite).
    #[serde(
        deserialize_with = "infinite_if_null",
        serialize_with = "crate::finite::unbounded"
    )]
    pub lambda_min: f64,
    /// Largest share of the load the asperities carry, and the share of the cycle's time
    /// during which they carry any.
    pub asperity_share_max: f64,
    pub contact_time_fraction: f64,
    /// Share of the cycle's time in the hydrodynamic, mixed and boundary regimes.
    pub regime_time_fraction: [f64; 3],
    /// Friction work per zone of the liner (J/m), by where the ring's centre is.
    pub zone_work_j_per_m: Vec<f64>,
}

/// The stroke as one zone (mm from top dead centre): the bounds of a run whose figures are
/// read for the whole cycle only.
pub fn whole_stroke(engine: &Engine) -> [f64; 2] {
    [0.0, engine.file.engine.stroke_mm]
}

/// The figures of a cycle's `rows` (one cycle, every step) on `engine`, whose crank turns at
/// its rpm, the work split by the liner's zones of `bounds_mm` (mm from top dead centre, from
/// 0 to the stroke).
pub fn metrics(rows: &[CycleRow], engine: &Engine, bounds_mm: &[f64]) -> CycleMetrics {
    let e = &engine.file.engine;
    // Seconds per degree of crank angle.
    let s_per_deg = 60.0 / (e.rpm * 360.0);
    let cycle_s = 720.0 * s_per_deg;
    let zones = bounds_mm.len() - 1;
    let mut m = CycleMetrics {
        work_j_per_m: 0.0,
        asperity_work_j_per_m: 0.0,
        mean_power_w_per_m: 0.0,
        ring_power_w: 0.0,
        fmep_kpa: 0.0,
        h_min_um: f64::INFINITY,
        h_min_deg: 0.0,
        lambda_min: f64::INFINITY,
        asperity_share_max: 0.0,
        contact_time_fraction: 0.0,
        regime_time_fraction: [0.0; 3],
        zone_work_j_per_m: vec![0.0; zones],
    };
    for r in rows {
        let dt = r.step_deg * s_per_deg;
        let work = r.power_w_per_m * dt;
        m.work_j_per_m += work;
        m.asperity_work_j_per_m += (r.asperity_friction_n_per_m * r.u_ms).abs() * dt;
        m.zone_work_j_per_m[zone_of(bounds_mm, r.position_mm.clamp(0.0, e.stroke_mm))] += work;
        if r.h_min_um < m.h_min_um {
            (m.h_min_um, m.h_min_deg) = (r.h_min_um, r.crank_deg);
        }
        m.lambda_min = m.lambda_min.min(r.lambda);
        m.asperity_share_max = m.asperity_share_max.max(r.asperity_share);
        if r.asperity_share > 0.0 {
            m.contact_time_fraction += dt / cycle_s;
        }
        m.regime_time_fraction[Regime::of(r.lambda) as usize] += dt / cycle_s;
    }
    m.mean_power_w_per_m = m.work_j_per_m / cycle_s;
    let (bore, stroke) = (e.bore_mm * 1e-3, e.stroke_mm * 1e-3);
    m.ring_power_w = m.mean_power_w_per_m * std::f64::consts::PI * bore;
    m.fmep_kpa = 4.0 * m.work_j_per_m / (bore * stroke) * 1e-3;
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::finite::first_non_finite;

    fn no_contact() -> CycleMetrics {
        CycleMetrics {
            work_j_per_m: 1.0,
            asperity_work_j_per_m: 0.0,
            mean_power_w_per_m: 2.0,
            ring_power_w: 3.0,
            fmep_kpa: 4.0,
            h_min_um: 1.5,
            h_min_deg: 180.0,
            lambda_min: f64::INFINITY,
            asperity_share_max: 0.0,
            contact_time_fraction: 0.0,
            regime_time_fraction: [1.0, 0.0, 0.0],
            zone_work_j_per_m: vec![1.0],
        }
    }

    #[test]
    fn an_unbounded_lambda_is_an_answer_written_as_null_and_nan_is_not() {
        let m = no_contact();
        assert_eq!(first_non_finite(&m), None);
        let json = serde_json::to_string(&m).unwrap();
        assert!(json.contains(r#""lambda_min":null"#), "{json}");
        let back: CycleMetrics = serde_json::from_str(&json).unwrap();
        assert_eq!(back.lambda_min, f64::INFINITY);
        let nan = CycleMetrics {
            lambda_min: f64::NAN,
            ..no_contact()
        };
        assert_eq!(
            first_non_finite(&nan).unwrap().to_string(),
            "lambda_min = NaN"
        );
        let nan = CycleMetrics {
            zone_work_j_per_m: vec![1.0, f64::NAN],
            ..no_contact()
        };
        assert_eq!(
            first_non_finite(&nan).unwrap().to_string(),
            "zone_work_j_per_m[1] = NaN"
        );
    }
}
