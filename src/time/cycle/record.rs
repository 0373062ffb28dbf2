//! What a cycle run records: each crank step's row, each cycle's summary and the oil it
//! exchanged, in the engine's units (docs/model.md §12).

/// Λ as JSON holds it: serde_json writes +∞ (no contact model) as null.
pub(super) fn infinite_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    <Option<f64> as serde::Deserialize>::deserialize(d).map(|v| v.unwrap_or(f64::INFINITY))
}

/// One step of the cycle, in the engine's units.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CycleRow {
    /// Crank angle at the step's end (degrees, in [0, 720)) and the step's length (degrees).
    pub crank_deg: f64,
    pub step_deg: f64,
    /// The ring's distance from its top-dead-centre position (mm).
    pub position_mm: f64,
    /// The liner's velocity under the ring over the step (m/s, positive towards the
    /// crankcase): −(the piston's).
    pub u_ms: f64,
    /// The ring's load per unit circumferential length (N/m).
    pub load_n_per_m: f64,
    /// Gas pressures above and below the ring (bar).
    pub p_above_bar: f64,
    pub p_below_bar: f64,
    /// Ring position Z and minimum film (µm).
    pub z_um: f64,
    pub h_min_um: f64,
    /// Friction force of the film on the ring per unit circumferential length (N/m), signed
    /// as the liner's motion: positive towards the crankcase.
    pub friction_n_per_m: f64,
    /// Its part carried by the asperities (boundary friction, docs/model.md §11), signed
    /// alike; the film's is the rest.
    pub asperity_friction_n_per_m: f64,
    /// Share of the ring's load the asperities carry, W_a/W.
    pub asperity_share: f64,
    /// Film parameter Λ = h_min/σ (infinite without a contact model).
    #[serde(deserialize_with = "infinite_if_null")]
    pub lambda: f64,
    /// Friction power per unit circumferential length, |F·U| (W/m).
    pub power_w_per_m: f64,
    /// Oil the leading edge met (µm, the liner's layer) and the trailing edge left.
    pub oil_met_um: f64,
    pub oil_left_um: f64,
}

/// The oil exchanged over a cycle (µm·cm per unit circumferential length) and what film and
/// liner held at its start and end.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct OilBalance {
    pub film_start: f64,
    pub film_end: f64,
    pub liner_start: f64,
    pub liner_end: f64,
    /// Laid by the supply, scraped off by the rings below, thrown off at the leading edge.
    pub supplied: f64,
    pub scraped: f64,
    pub thrown: f64,
}

impl OilBalance {
    /// (film + liner) at the end − at the start − (supplied − scraped − thrown), relative to
    /// the oil held: round-off when conserved.
    pub fn defect(&self) -> f64 {
        let change = (self.film_end - self.film_start) + (self.liner_end - self.liner_start);
        let net = self.supplied - self.scraped - self.thrown;
        (change - net).abs()
            / (self.film_end + self.liner_end)
                .abs()
                .max(f64::MIN_POSITIVE)
    }
}

/// One cycle's summary.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CycleSummary {
    /// Which cycle of the run (0: the first).
    pub index: usize,
    /// Friction work per unit circumferential length over the cycle (J/m).
    pub friction_work_j_per_m: f64,
    /// Its relative change from the cycle before, and the oil map's (infinite for the first).
    pub work_change: f64,
    pub oil_change: f64,
    pub oil: OilBalance,
    pub steps: usize,
}
