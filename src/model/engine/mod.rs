//! An engine's cycle as the ring sees it (docs/model.md §10): the engine file's sections
//! (`sections`) and their rules (`rules`), the slider-crank (`crank`), the gas and oil tables
//! (`tables`), the liner's zones (`zones`), the cycle sampled angle by angle for the
//! quasi-steady evaluation (`samples`) and the operating map (`map`, §13). A checked
//! [`Engine`] is the file's data with its operating map; the liner's zones
//! ([`LinerZones`]) are checked against it apart.

mod crank;
mod map;
mod rules;
mod samples;
mod sections;
mod tables;
mod zones;

pub use map::{operating_map, MapPoint, MAX_POINTS};
pub use rules::EngineError;
pub use samples::Sample;
pub use sections::{
    ContactFile, Crank, EngineFile, Gas, MapPointFile, Oil, OilSupply, RingFile, Zones,
};
pub use zones::{
    three_digits, zone_decimals, zone_label, zone_of, LinerZones, MAX_ZONES, STEP_RANGE_DEG,
};

use crate::model::case::{face_spans_ring, short};
use rules::{err, in_range};

/// A checked engine: the file's data and the operating map. The liner's zones, the file's
/// `[zones]`, are checked apart ([`LinerZones`]): they are the liner's layout to design.
#[derive(Clone, Debug)]
pub struct Engine {
    pub file: EngineFile,
    /// The `[[operating]]` points, each checked as an engine (empty: the file lists none).
    map: Vec<MapPoint>,
}

impl Engine {
    /// Checks an engine as its file gives it; errors name the file's key.
    pub fn new(file: EngineFile) -> Result<Engine, EngineError> {
        let e = &file.engine;
        let plain_name = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
        if e.name.is_empty() || !e.name.chars().all(plain_name) {
            return Err(err(
                "[engine] name",
                format!("{:?}", e.name),
                "use letters, digits, '-' or '_' (it names the report's files)",
            ));
        }
        let r = &file.ring;
        for (k, v) in [
            ("[engine] bore_mm", e.bore_mm),
            ("[engine] stroke_mm", e.stroke_mm),
            ("[engine] rod_mm", e.rod_mm),
            ("[engine] rpm", e.rpm),
            ("[ring] R_cm", r.r_cm),
            ("[ring] width_mm", r.width_mm),
            ("[ring] mass_kg_per_m", r.mass_kg_per_m),
            ("[ring] elastic_load_n_per_m", r.elastic_load_n_per_m),
            ("[oil] viscosity_pa_s", file.oil.viscosity_pa_s),
        ] {
            in_range(k, v)?;
        }
        if e.rod_mm <= 0.5 * e.stroke_mm {
            return Err(err(
                "[engine] rod_mm",
                short(e.rod_mm),
                format!(
                    "must exceed half the stroke ({} mm)",
                    short(0.5 * e.stroke_mm)
                ),
            ));
        }
        Self::check_gas(&file.gas)?;
        file.contact.check()?;
        Self::check_oil(&file.oil, e.stroke_mm)?;
        let map = operating_map(&file)?;
        let engine = Engine { file, map };
        // The ring face's radius must exceed its half width (docs/model.md §2), as `simulate`
        // asks of --R.
        let half_width_cm = 0.05 * engine.file.ring.width_mm;
        if !face_spans_ring(engine.file.ring.r_cm, half_width_cm) {
            return Err(err(
                "[ring] R_cm",
                short(engine.file.ring.r_cm),
                format!(
                    "must exceed half the ring width ({} cm for width_mm = {})",
                    short(half_width_cm),
                    short(engine.file.ring.width_mm)
                ),
            ));
        }
        Ok(engine)
    }

    /// The operating map (docs/model.md §13): the file's `[[operating]]` points, or the
    /// engine's own point alone, its share 1.
    pub fn operating_points(&self) -> Vec<MapPoint> {
        if !self.map.is_empty() {
            return self.map.clone();
        }
        vec![MapPoint {
            name: self.file.engine.name.clone(),
            share: 1.0,
            engine: self.clone(),
        }]
    }

    /// Whether the file lists an operating map.
    pub fn has_map(&self) -> bool {
        !self.map.is_empty()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    #[test]
    fn the_film_is_rough_unless_the_file_says_smooth() {
        let mut c = ContactFile::default();
        let f = c.flow_factors(0.4).unwrap();
        assert_eq!(f.sigma_um, 0.4);
        // w = 2·share − 1 with the default share 0.25²/(0.25² + 0.15²).
        assert!((f.sliding_rougher - 0.04 / 0.085).abs() < 1e-15);
        c.liner_roughness_share = Some(0.5);
        assert_eq!(c.flow_factors(0.4).unwrap().sliding_rougher, 0.0);
        c.liner_roughness_share = Some(f64::NAN);
        assert!(c.check().is_err());
        c.smooth_film = true;
        assert_eq!(c.flow_factors(0.4), None);
    }

    /// The example engine of `study::engine_file`'s tests, with these zones.
    pub(crate) fn example(zones: Zones) -> EngineFile {
        EngineFile {
            contact: ContactFile::default(),
            operating: Vec::new(),
            engine: Crank {
                name: "test".into(),
                bore_mm: 80.0,
                stroke_mm: 86.0,
                rod_mm: 140.0,
                rpm: 2000.0,
            },
            ring: RingFile {
                r_cm: 5.0,
                width_mm: 1.2,
                mass_kg_per_m: 0.02,
                elastic_load_n_per_m: 100.0,
            },
            gas: Gas {
                crank_deg: vec![0.0, 30.0, 180.0, 360.0, 690.0],
                pressure_bar: vec![30.0, 50.0, 2.0, 0.0, 10.0],
                below_crank_deg: Vec::new(),
                below_pressure_bar: Vec::new(),
            },
            oil: Oil {
                viscosity_pa_s: 0.006,
                d_oil_um: OilSupply::Everywhere(20.0),
                position_mm: Vec::new(),
            },
            zones,
        }
    }

    fn four_zones() -> (Engine, LinerZones) {
        let e = Engine::new(example(Zones {
            count: Some(4),
            boundaries_mm: None,
        }))
        .unwrap();
        let z = LinerZones::new(&e).unwrap();
        (e, z)
    }

    fn bounds(b: &[f64]) -> Result<(Engine, LinerZones), EngineError> {
        let e = Engine::new(example(Zones {
            count: None,
            boundaries_mm: Some(b.to_vec()),
        }))?;
        LinerZones::new(&e).map(|z| (e, z))
    }

    #[test]
    fn slider_crank_against_the_closed_form_and_a_finite_difference() {
        let (e, _) = four_zones();
        let (r, l) = (43.0, 140.0);
        for deg in [0.0, 30.0, 90.0, 135.0, 180.0, 270.0, 359.0, 400.0, 700.0] {
            let t: f64 = f64::to_radians(deg);
            // x = l + r − (r cos θ + √(l² − r² sin² θ)): the pin's distance from TDC.
            let closed = l + r - (r * t.cos() + (l * l - r * r * t.sin() * t.sin()).sqrt());
            assert!((e.position_mm(deg) - closed).abs() < 1e-12, "{deg}°");
            // dx/dt from a central difference in time (θ = ωt).
            let h = 1e-4;
            let w = 2000.0 * std::f64::consts::PI / 30.0;
            let fd = (e.position_mm(deg + h) - e.position_mm(deg - h)) / (2.0 * h.to_radians() / w);
            assert!(
                (e.velocity_ms(deg) - 1e-3 * fd).abs() < 1e-6,
                "{deg}°: {} vs {}",
                e.velocity_ms(deg),
                1e-3 * fd
            );
        }
        assert_eq!(e.position_mm(0.0), 0.0);
        assert!((e.position_mm(180.0) - 86.0).abs() < 1e-12);
        assert!(e.velocity_ms(0.0).abs() < 1e-12 && e.velocity_ms(180.0).abs() < 1e-9);
    }

    #[test]
    fn gas_table_is_linear_and_periodic_and_zones_cover_the_stroke() {
        let (e, z) = four_zones();
        assert!((e.gas_bar(15.0) - 40.0).abs() < 1e-12);
        // Between 690° and 720° + 0°: 10 → 30 bar.
        assert!((e.gas_bar(705.0) - 20.0).abs() < 1e-12);
        assert!((e.gas_bar(705.0 - 720.0) - 20.0).abs() < 1e-12);
        assert_eq!(z.bounds_mm(), [0.0, 21.5, 43.0, 64.5, 86.0]);
        assert_eq!((z.zone(0.0), z.zone(21.5), z.zone(86.0)), (0, 1, 3));
        let s = e.samples(10.0, &z);
        assert_eq!(s.len(), 72);
        assert!(s.iter().all(|x| x.crank_deg > 0.0 && x.crank_deg < 720.0));
        // Elastic + 40 bar × 1.2 mm = 100 + 4800 N/m at 15°... at the sample 5°: 30 + 5/30·20 bar.
        let p = 30.0 + 5.0 / 30.0 * 20.0;
        assert!((s[0].load_n_per_m - (100.0 + p * 1e5 * 1.2e-3)).abs() < 1e-9);
    }

    #[test]
    fn zones_are_capped_and_each_wide_enough_for_the_finest_step() {
        let many: Vec<f64> = (0..=51).map(|i| 86.0 * i as f64 / 51.0).collect();
        let e = bounds(&many).unwrap_err();
        assert_eq!(e.key, "[zones] boundaries_mm", "{e}");
        assert!(e.to_string().contains("at most 51 boundaries"), "{e}");
        // 0.1 µm at top dead centre, 1 µm mid-stroke: crossed in well under half a degree.
        for b in [&[0.0, 0.0001, 86.0][..], &[0.0, 40.0, 40.001, 86.0]] {
            let e = bounds(b).unwrap_err();
            assert!(e.to_string().contains("finest step"), "{b:?}: {e}");
        }
        // 1 µm at top dead centre is crossed down and back up in 0.7°: accepted, and no
        // step coarser than that is sure to sample it.
        let (e, zones) = bounds(&[0.0, 0.001, 86.0]).unwrap();
        let span = zones.span_deg(0);
        assert!(span > 0.6 && span < 0.8, "{span}");
        assert_eq!(zones.unsampled(&e, 45.0), Some(0));
        assert_eq!(zones.unsampled(&e, 5.0), Some(0));
        let step = zones.step_to_sample(0);
        assert!(step <= span && step >= 0.5, "{step}");
        assert_eq!(zones.unsampled(&e, step), None);
        // Every zone of every layout is sampled by its suggested step and any finer one.
        let (e, zones) = bounds(&[0.0, 0.5, 10.0, 43.0, 43.6, 85.9, 86.0]).unwrap();
        for z in 0..6 {
            let s = zones.step_to_sample(z);
            for k in 0..40 {
                let step = s * (1.0 - k as f64 / 80.0);
                if step >= 0.5 {
                    assert!(
                        !e.samples(step, &zones).iter().all(|x| x.zone != z),
                        "zone {z} at {step}"
                    );
                }
            }
        }
    }

    #[test]
    fn zone_labels_tell_distinct_boundaries_apart() {
        assert_eq!(zone_label(&[0.0, 20.25, 40.5], 0), "0.0–20.2");
        assert_eq!(zone_label(&[0.0, 0.001, 81.0], 0), "0.000–0.001");
        assert_eq!(zone_label(&[0.0, 0.001, 81.0], 1), "0.001–81.000");
        assert_eq!(zone_label(&[0.0, 40.0, 40.04, 81.0], 1), "40.00–40.04");
    }
}
