//! The cycle sampled angle by angle for the quasi-steady evaluation (docs/model.md §10): at
//! each sample the ring's place, speed, load and oil supply, and its operating point.

use super::{Engine, LinerZones};
use crate::model::operating::Operating;

/// One crank angle of the cycle as the ring meets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Crank angle from firing top dead centre (degrees).
    pub crank_deg: f64,
    /// Ring's distance from its top-dead-centre position (mm) and sliding speed (m/s, ≥ 0).
    pub position_mm: f64,
    pub speed_ms: f64,
    /// Load per unit circumferential length: elastic + gas pressure × ring width (N/m).
    pub load_n_per_m: f64,
    pub d_oil_um: f64,
    /// The zone the ring is over (0 at top dead centre).
    pub zone: usize,
}

impl Engine {
    /// The cycle sampled every `step_deg` degrees, at the middles of the steps (so that no
    /// sample sits exactly on a dead centre), each with the zone of `zones` it is over.
    pub fn samples(&self, step_deg: f64, zones: &LinerZones) -> Vec<Sample> {
        let n = (720.0 / step_deg).round().max(1.0) as usize;
        let step = 720.0 / n as f64;
        (0..n)
            .map(|k| {
                let crank_deg = (k as f64 + 0.5) * step;
                let position_mm = self.position_mm(crank_deg);
                Sample {
                    crank_deg,
                    position_mm,
                    speed_ms: self.velocity_ms(crank_deg).abs(),
                    load_n_per_m: self.load_n_per_m(crank_deg),
                    d_oil_um: self.d_oil_um(position_mm),
                    zone: zones.zone(position_mm),
                }
            })
            .collect()
    }

    /// The operating point of a sample (its speed may be outside the accepted range near a
    /// dead centre: such samples are excluded before they are evaluated).
    pub fn operating(&self, s: &Sample) -> Operating {
        Operating {
            speed_ms: s.speed_ms,
            load_n_per_m: s.load_n_per_m,
            viscosity_pas: self.file.oil.viscosity_pa_s,
            ring_width_mm: self.file.ring.width_mm,
            ring_mass_kg_per_m: self.file.ring.mass_kg_per_m,
            d_oil_um: s.d_oil_um,
        }
    }
}
