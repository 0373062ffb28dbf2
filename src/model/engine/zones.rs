//! The liner's zones along the stroke: their bounds as the engine file gives them, the crank
//! angle the ring takes to cross each, the steps that sample every zone, and their labels.

use super::rules::{err, increasing, EngineError};
use super::sections::Zones;
use super::Engine;
use crate::model::case::short;

/// Most zones a liner is divided into (each is a design search of minutes).
pub const MAX_ZONES: usize = 50;

/// Finest and coarsest crank-angle steps a cycle is sampled at (degrees).
pub const STEP_RANGE_DEG: (f64, f64) = (0.5, 90.0);

/// A positive number to about 3 significant digits (`0.347`, `12.5`, `180`).
pub fn three_digits(x: f64) -> String {
    let d = if x > 0.0 && x.is_finite() {
        (2.0 - x.log10().floor()).clamp(0.0, 15.0) as usize
    } else {
        0
    };
    format!("{x:.d$}")
}

/// Decimals that tell the zone boundaries `bounds` (mm) apart: at least one, more where two
/// would otherwise print alike.
pub fn zone_decimals(bounds: &[f64]) -> usize {
    (1..=9)
        .find(|&d| {
            bounds
                .windows(2)
                .all(|w| format!("{:.d$}", w[0]) != format!("{:.d$}", w[1]))
        })
        .unwrap_or(9)
}

/// Zone `z` of `bounds` as `from–to` (mm), with [`zone_decimals`].
pub fn zone_label(bounds: &[f64], z: usize) -> String {
    let d = zone_decimals(bounds);
    format!("{:.d$}–{:.d$}", bounds[z], bounds[z + 1])
}

/// The liner's zones along the stroke (the liner's layout to design, not the engine's): the
/// engine file's `[zones]`, checked against the engine's crank so that every zone spans at
/// least the finest step of crank angle.
#[derive(Clone, Debug, PartialEq)]
pub struct LinerZones {
    /// Zone boundaries (mm from top dead centre), from 0 to the stroke.
    bounds_mm: Vec<f64>,
    /// The crank angle the ring takes to cross each zone (degrees, [`LinerZones::span_deg`]).
    span_deg: Vec<f64>,
}

impl LinerZones {
    /// The zones `engine`'s file gives; errors name the file's key.
    pub fn new(engine: &Engine) -> Result<LinerZones, EngineError> {
        let bounds_mm = bounds(&engine.file.zones, engine.file.engine.stroke_mm)?;
        let last = bounds_mm.len() - 2;
        let span_deg = (0..=last)
            .map(|z| {
                let (a, b) = (bounds_mm[z], bounds_mm[z + 1]);
                match (z == 0, z == last) {
                    (true, true) => 720.0,
                    (true, false) => 2.0 * engine.crank_at(b),
                    (false, true) => 2.0 * (180.0 - engine.crank_at(a)),
                    (false, false) => engine.crank_at(b) - engine.crank_at(a),
                }
            })
            .collect();
        let zones = LinerZones {
            bounds_mm,
            span_deg,
        };
        zones.check_spans()?;
        Ok(zones)
    }

    /// Zone boundaries (mm from top dead centre), from 0 to the stroke.
    pub fn bounds_mm(&self) -> &[f64] {
        &self.bounds_mm
    }

    /// Zone boundaries (cm from top dead centre), as a liner's layout takes them.
    pub fn bounds_cm(&self) -> Vec<f64> {
        self.bounds_mm.iter().map(|b| 0.1 * b).collect()
    }

    /// How many zones.
    pub fn count(&self) -> usize {
        self.bounds_mm.len() - 1
    }

    /// Every zone spans at least the finest step of crank angle, so that some step samples it.
    fn check_spans(&self) -> Result<(), EngineError> {
        let finest = STEP_RANGE_DEG.0;
        match (0..self.count()).find(|&z| self.step_to_sample(z) < finest) {
            None => Ok(()),
            Some(z) => Err(err(
                "[zones] boundaries_mm",
                format!("[… {}, {} …]", short(self.bounds_mm[z]), short(self.bounds_mm[z + 1])),
                format!(
                    "zone {} is crossed in {}° of crank angle, too little for the finest step ({finest}°) to be sure to sample it; widen it",
                    z + 1,
                    three_digits(self.span_deg(z))
                ),
            )),
        }
    }

    /// The crank angle the ring takes to cross zone `z` (degrees): a zone at a dead centre is
    /// crossed down and back up in one go, around it. Samples closer than this meet the zone.
    pub fn span_deg(&self, z: usize) -> f64 {
        self.span_deg[z]
    }

    /// The first zone no sample of `engine`'s cycle at `step_deg` meets, if any.
    pub fn unsampled(&self, engine: &Engine, step_deg: f64) -> Option<usize> {
        let mut met = vec![false; self.count()];
        for s in engine.samples(step_deg, self) {
            met[s.zone] = true;
        }
        met.iter().position(|m| !m)
    }

    /// The largest step under which every step samples zone `z` (degrees, 3 significant
    /// digits, rounded down): the span of [`LinerZones::span_deg`] holds a sample of any
    /// step shorter than it, and a step is taken as 720°/n.
    pub fn step_to_sample(&self, z: usize) -> f64 {
        let n = (720.0 / self.span_deg(z)).floor() + 1.0;
        let step = 720.0 / n;
        // Rounded down to 3 significant digits; an exact power of ten divides, so that the
        // value prints as those digits.
        let d = (2.0 - step.log10().floor()).clamp(0.0, 15.0);
        let p = 10f64.powf(d);
        (step * p).floor() / p
    }

    /// The zone over `position_mm` (the last one owns the stroke's end).
    pub fn zone(&self, position_mm: f64) -> usize {
        zone_of(&self.bounds_mm, position_mm)
    }
}

/// The boundaries of the file's `[zones]` over a stroke of `stroke` mm.
fn bounds(z: &Zones, stroke: f64) -> Result<Vec<f64>, EngineError> {
    match (z.count, &z.boundaries_mm) {
        (Some(n), None) if (1..=MAX_ZONES).contains(&n) => {
            Ok((0..=n).map(|i| stroke * i as f64 / n as f64).collect())
        }
        (Some(n), None) => Err(err("[zones] count", n, format!("must be 1 to {MAX_ZONES}"))),
        (None, Some(b)) => {
            if b.len() > MAX_ZONES + 1 {
                return Err(err(
                    "[zones] boundaries_mm",
                    format!("{} values", b.len()),
                    format!(
                        "give at most {} boundaries ({MAX_ZONES} zones, as count)",
                        MAX_ZONES + 1
                    ),
                ));
            }
            increasing("[zones] boundaries_mm", b)?;
            let ends = b.len() >= 2 && b[0] == 0.0 && (b[b.len() - 1] - stroke).abs() < 1e-9;
            if !ends {
                return Err(err(
                    "[zones] boundaries_mm",
                    format!("{b:?}"),
                    format!("must run from 0 to the stroke ({} mm)", short(stroke)),
                ));
            }
            Ok(b.clone())
        }
        _ => Err(err("[zones]", "", "give either count or boundaries_mm")),
    }
}

/// The zone of `bounds` (mm, increasing from 0 to the stroke) over `position_mm`, the last one
/// owning the stroke's end.
pub fn zone_of(bounds: &[f64], position_mm: f64) -> usize {
    (1..bounds.len())
        .find(|&k| position_mm < bounds[k])
        .unwrap_or(bounds.len() - 1)
        - 1
}
