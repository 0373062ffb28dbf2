//! An engine's cycle as the ring sees it (docs/model.md §10): the slider-crank kinematics,
//! the ring's load (elastic tension and the gas pressure behind it) and the oil supply over
//! the four strokes, and the zones of the liner. Each crank angle is one operating point of a
//! quasi-steady evaluation: its speed, load and oil supply, on the zone the ring is over.

use serde::{Deserialize, Serialize};

use super::asperity::Asperity;
use super::case::{face_spans_ring, short};
use super::engine_map::{operating_map, MapPoint, MapPointFile};
use super::flow_factors::{FlowFactors, LINER_ROUGHNESS_SHARE};
use super::operating::Operating;

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
    fn check(&self) -> Result<(), EngineError> {
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

/// An input that breaks a rule: the key (`[section] name`), its value (empty where the
/// rule is about the section) and the rule.
#[derive(Clone, Debug, PartialEq)]
pub struct EngineError {
    pub key: String,
    pub value: String,
    pub rule: String,
}

impl std::fmt::Display for EngineError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.value.as_str() {
            "" => write!(f, "{}: {}", self.key, self.rule),
            v => write!(f, "{} = {v}: {}", self.key, self.rule),
        }
    }
}

impl std::error::Error for EngineError {}

fn err(key: &str, value: impl std::fmt::Display, rule: impl Into<String>) -> EngineError {
    EngineError {
        key: key.into(),
        value: value.to_string(),
        rule: rule.into(),
    }
}

/// A checked engine: the file's data, the zone boundaries and the operating map.
#[derive(Clone, Debug)]
pub struct Engine {
    pub file: EngineFile,
    /// Zone boundaries (mm from top dead centre), from 0 to the stroke.
    pub bounds_mm: Vec<f64>,
    /// The `[[operating]]` points, each checked as an engine (empty: the file lists none).
    map: Vec<MapPoint>,
}

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

/// The physical inputs of an engine file and their ranges: from a model engine's to a large
/// four-stroke's (a value outside is a slip of the unit, not an engine). The ring's width,
/// mass, load and the oil's viscosity are those `simulate` takes.
const RANGES: [(&str, &str, f64, f64); 9] = [
    ("[engine] bore_mm", "mm", 5.0, 1000.0),
    ("[engine] stroke_mm", "mm", 5.0, 1000.0),
    ("[engine] rod_mm", "mm", 5.0, 5000.0),
    ("[engine] rpm", "rpm", 10.0, 30_000.0),
    ("[ring] R_cm", "cm", 0.01, 1000.0),
    ("[ring] width_mm", "mm", 0.1, 10.0),
    ("[ring] mass_kg_per_m", "kg/m", 1e-5, 10.0),
    ("[ring] elastic_load_n_per_m", "N/m", 1e-2, 1e6),
    ("[oil] viscosity_pa_s", "Pa·s", 1e-4, 10.0),
];

/// Most zones a liner is divided into (each is a design search of minutes).
pub const MAX_ZONES: usize = 50;

/// Finest and coarsest crank-angle steps a cycle is sampled at (degrees).
pub const STEP_RANGE_DEG: (f64, f64) = (0.5, 90.0);

/// A pressure table against crank angle (`keys`: its angles' and its pressures' keys): at
/// least two points, as many pressures as angles, angles increasing within 0–720°, gauge
/// pressures in [0, 500] bar.
fn check_table(keys: (&str, &str), deg: &[f64], bar: &[f64]) -> Result<(), EngineError> {
    let (deg_key, bar_key) = keys;
    if deg.len() < 2 || deg.len() != bar.len() {
        return Err(err(
            deg_key,
            format!("{} values", deg.len()),
            format!(
                "needs at least 2 values, as many as {} ({})",
                bar_key.trim_start_matches("[gas] "),
                bar.len()
            ),
        ));
    }
    increasing(deg_key, deg)?;
    let (lo, hi) = (deg[0], deg[deg.len() - 1]);
    if lo < 0.0 || hi > 720.0 {
        return Err(err(
            deg_key,
            format!("{}..{}", short(lo), short(hi)),
            "must lie within 0–720° (a four-stroke cycle from firing top dead centre)",
        ));
    }
    if let Some(p) = bar
        .iter()
        .find(|p| !(p.is_finite() && **p >= 0.0 && **p <= 500.0))
    {
        return Err(err(
            bar_key,
            short(*p),
            "must be a gauge pressure in [0, 500] bar",
        ));
    }
    Ok(())
}

/// The value at `deg` of a table linear between its points and periodic over 720° (the
/// last point joins the first one 720° later).
fn periodic_table(deg: &[f64], val: &[f64], at_deg: f64) -> f64 {
    let n = deg.len();
    let xs: Vec<f64> = deg.iter().copied().chain([deg[0] + 720.0]).collect();
    let ys: Vec<f64> = val.iter().copied().chain([val[0]]).collect();
    let x = at_deg.rem_euclid(720.0);
    let x = if x < xs[0] { x + 720.0 } else { x };
    let k = (0..n).find(|&k| x <= xs[k + 1]).unwrap_or(n - 1);
    let s = (x - xs[k]) / (xs[k + 1] - xs[k]);
    ys[k] + s * (ys[k + 1] - ys[k])
}

/// `v` finite and within `key`'s range of [`RANGES`].
fn in_range(key: &str, v: f64) -> Result<(), EngineError> {
    let Some(&(_, unit, lo, hi)) = RANGES.iter().find(|r| r.0 == key) else {
        return Ok(());
    };
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(err(
            key,
            short(v),
            format!(
                "must lie in [{}, {}] {unit}; check the unit",
                short(lo),
                short(hi)
            ),
        ))
    }
}

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

/// `xs` finite and strictly increasing.
fn increasing(key: &str, xs: &[f64]) -> Result<(), EngineError> {
    if let Some(x) = xs.iter().find(|x| !x.is_finite()) {
        return Err(err(key, short(*x), "must be finite"));
    }
    if let Some(w) = xs.windows(2).find(|w| w[1] <= w[0]) {
        return Err(err(
            key,
            format!("[… {}, {} …]", short(w[0]), short(w[1])),
            "must increase strictly",
        ));
    }
    Ok(())
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
        let bounds_mm = Self::zone_bounds(&file.zones, e.stroke_mm)?;
        Self::check_oil(&file.oil, e.stroke_mm)?;
        let map = operating_map(&file)?;
        let engine = Engine {
            file,
            bounds_mm,
            map,
        };
        engine.check_zone_spans()?;
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

    fn check_gas(g: &Gas) -> Result<(), EngineError> {
        check_table(
            ("[gas] crank_deg", "[gas] pressure_bar"),
            &g.crank_deg,
            &g.pressure_bar,
        )?;
        if !(g.below_crank_deg.is_empty() && g.below_pressure_bar.is_empty()) {
            check_table(
                ("[gas] below_crank_deg", "[gas] below_pressure_bar"),
                &g.below_crank_deg,
                &g.below_pressure_bar,
            )?;
        }
        Ok(())
    }

    fn check_oil(o: &Oil, stroke: f64) -> Result<(), EngineError> {
        let ok = |v: f64| v.is_finite() && v > 0.0 && v <= 1000.0;
        match &o.d_oil_um {
            OilSupply::Everywhere(v) if ok(*v) => Ok(()),
            OilSupply::Everywhere(v) => {
                Err(err("[oil] d_oil_um", short(*v), "must lie in (0, 1000] µm"))
            }
            OilSupply::Table(t) => {
                if t.len() != o.position_mm.len() || t.len() < 2 {
                    return Err(err(
                        "[oil] position_mm",
                        format!("{} values", o.position_mm.len()),
                        format!(
                            "a table of d_oil_um needs as many positions ({}), at least 2",
                            t.len()
                        ),
                    ));
                }
                increasing("[oil] position_mm", &o.position_mm)?;
                // The value named is the one outside (positions are increasing).
                let (first, last) = (o.position_mm[0], o.position_mm[t.len() - 1]);
                if first < 0.0 || last > stroke {
                    return Err(err(
                        "[oil] position_mm",
                        short(if first < 0.0 { first } else { last }),
                        format!("must lie within the stroke (0–{} mm)", short(stroke)),
                    ));
                }
                match t.iter().find(|v| !ok(**v)) {
                    Some(v) => Err(err("[oil] d_oil_um", short(*v), "must lie in (0, 1000] µm")),
                    None => Ok(()),
                }
            }
        }
    }

    fn zone_bounds(z: &Zones, stroke: f64) -> Result<Vec<f64>, EngineError> {
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

    /// Every zone spans at least the finest step of crank angle, so that some step samples it.
    fn check_zone_spans(&self) -> Result<(), EngineError> {
        let finest = STEP_RANGE_DEG.0;
        match (0..self.bounds_mm.len() - 1).find(|&z| self.step_to_sample(z) < finest) {
            None => Ok(()),
            Some(z) => Err(err(
                "[zones] boundaries_mm",
                format!("[… {}, {} …]", short(self.bounds_mm[z]), short(self.bounds_mm[z + 1])),
                format!(
                    "zone {} is crossed in {}° of crank angle, too little for the finest step ({finest}°) to be sure to sample it; widen it",
                    z + 1,
                    three_digits(self.zone_span_deg(z))
                ),
            )),
        }
    }

    /// The crank angle of the down stroke (0–180°) at which the ring is `x` mm from top dead
    /// centre (the position increases over it).
    fn crank_at(&self, x: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, 180.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.position_mm(mid) < x {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// The crank angle the ring takes to cross zone `z` (degrees): a zone at a dead centre is
    /// crossed down and back up in one go, around it. Samples closer than this meet the zone.
    pub fn zone_span_deg(&self, z: usize) -> f64 {
        let last = self.bounds_mm.len() - 2;
        let (a, b) = (self.bounds_mm[z], self.bounds_mm[z + 1]);
        match (z == 0, z == last) {
            (true, true) => 720.0,
            (true, false) => 2.0 * self.crank_at(b),
            (false, true) => 2.0 * (180.0 - self.crank_at(a)),
            (false, false) => self.crank_at(b) - self.crank_at(a),
        }
    }

    /// The first zone no sample at `step_deg` meets, if any.
    pub fn unsampled_zone(&self, step_deg: f64) -> Option<usize> {
        let mut met = vec![false; self.bounds_mm.len() - 1];
        for s in self.samples(step_deg) {
            met[s.zone] = true;
        }
        met.iter().position(|m| !m)
    }

    /// The largest step under which every step samples zone `z` (degrees, 3 significant
    /// digits, rounded down): the span of [`Engine::zone_span_deg`] holds a sample of any
    /// step shorter than it, and a step is taken as 720°/n.
    pub fn step_to_sample(&self, z: usize) -> f64 {
        let n = (720.0 / self.zone_span_deg(z)).floor() + 1.0;
        let step = 720.0 / n;
        // Rounded down to 3 significant digits; an exact power of ten divides, so that the
        // value prints as those digits.
        let d = (2.0 - step.log10().floor()).clamp(0.0, 15.0);
        let p = 10f64.powf(d);
        (step * p).floor() / p
    }

    /// Crank radius and rod length (mm), and the crank's angular speed (rad/s).
    fn crank(&self) -> (f64, f64, f64) {
        let e = &self.file.engine;
        (
            0.5 * e.stroke_mm,
            e.rod_mm,
            e.rpm * std::f64::consts::PI / 30.0,
        )
    }

    /// The piston's (and ring's) distance from top dead centre (mm) at crank angle θ:
    /// x = r(1 − cos θ) + l − √(l² − r² sin² θ) (docs/model.md §10).
    pub fn position_mm(&self, crank_deg: f64) -> f64 {
        let (r, l, _) = self.crank();
        let t = crank_deg.to_radians();
        r * (1.0 - t.cos()) + l - (l * l - (r * t.sin()).powi(2)).sqrt()
    }

    /// Its velocity (m/s, positive away from top dead centre): dx/dt = ω·r·sin θ·(1 +
    /// r·cos θ / √(l² − r² sin² θ)).
    pub fn velocity_ms(&self, crank_deg: f64) -> f64 {
        let (r, l, w) = self.crank();
        let t = crank_deg.to_radians();
        let root = (l * l - (r * t.sin()).powi(2)).sqrt();
        1e-3 * w * r * t.sin() * (1.0 + r * t.cos() / root)
    }

    /// The gas pressure behind and above the ring (bar), linear in the table, periodic over
    /// 720°.
    pub fn gas_bar(&self, crank_deg: f64) -> f64 {
        let g = &self.file.gas;
        periodic_table(&g.crank_deg, &g.pressure_bar, crank_deg)
    }

    /// The gas pressure below the ring (bar): its table, or ambient (0) without one.
    pub fn below_bar(&self, crank_deg: f64) -> f64 {
        let g = &self.file.gas;
        if g.below_crank_deg.is_empty() {
            0.0
        } else {
            periodic_table(&g.below_crank_deg, &g.below_pressure_bar, crank_deg)
        }
    }

    /// The oil film ahead of the ring at `position_mm` (µm).
    pub fn d_oil_um(&self, position_mm: f64) -> f64 {
        match &self.file.oil.d_oil_um {
            OilSupply::Everywhere(v) => *v,
            OilSupply::Table(t) => {
                let xs = &self.file.oil.position_mm;
                let x = position_mm.clamp(xs[0], xs[xs.len() - 1]);
                let k = (0..xs.len() - 1)
                    .find(|&k| x <= xs[k + 1])
                    .unwrap_or(xs.len() - 2);
                let s = (x - xs[k]) / (xs[k + 1] - xs[k]);
                t[k] + s * (t[k + 1] - t[k])
            }
        }
    }

    /// The zone over `position_mm` (the last one owns the stroke's end).
    pub fn zone(&self, position_mm: f64) -> usize {
        let b = &self.bounds_mm;
        (1..b.len())
            .find(|&k| position_mm < b[k])
            .unwrap_or(b.len() - 1)
            - 1
    }

    /// The cycle sampled every `step_deg` degrees, at the middles of the steps (so that no
    /// sample sits exactly on a dead centre).
    pub fn samples(&self, step_deg: f64) -> Vec<Sample> {
        let n = (720.0 / step_deg).round().max(1.0) as usize;
        let step = 720.0 / n as f64;
        let ring = &self.file.ring;
        (0..n)
            .map(|k| {
                let crank_deg = (k as f64 + 0.5) * step;
                let position_mm = self.position_mm(crank_deg);
                // 1 bar on the ring's back, over its width: 1e5 Pa × width (m) per metre.
                let gas = self.gas_bar(crank_deg) * 1e5 * ring.width_mm * 1e-3;
                Sample {
                    crank_deg,
                    position_mm,
                    speed_ms: self.velocity_ms(crank_deg).abs(),
                    load_n_per_m: ring.elastic_load_n_per_m + gas,
                    d_oil_um: self.d_oil_um(position_mm),
                    zone: self.zone(position_mm),
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

    fn four_zones() -> Engine {
        Engine::new(example(Zones {
            count: Some(4),
            boundaries_mm: None,
        }))
        .unwrap()
    }

    fn bounds(b: &[f64]) -> Result<Engine, EngineError> {
        Engine::new(example(Zones {
            count: None,
            boundaries_mm: Some(b.to_vec()),
        }))
    }

    #[test]
    fn slider_crank_against_the_closed_form_and_a_finite_difference() {
        let e = four_zones();
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
        let e = four_zones();
        assert!((e.gas_bar(15.0) - 40.0).abs() < 1e-12);
        // Between 690° and 720° + 0°: 10 → 30 bar.
        assert!((e.gas_bar(705.0) - 20.0).abs() < 1e-12);
        assert!((e.gas_bar(705.0 - 720.0) - 20.0).abs() < 1e-12);
        assert_eq!(e.bounds_mm, vec![0.0, 21.5, 43.0, 64.5, 86.0]);
        assert_eq!((e.zone(0.0), e.zone(21.5), e.zone(86.0)), (0, 1, 3));
        let s = e.samples(10.0);
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
        let e = bounds(&[0.0, 0.001, 86.0]).unwrap();
        let span = e.zone_span_deg(0);
        assert!(span > 0.6 && span < 0.8, "{span}");
        assert_eq!(e.unsampled_zone(45.0), Some(0));
        assert_eq!(e.unsampled_zone(5.0), Some(0));
        let step = e.step_to_sample(0);
        assert!(step <= span && step >= 0.5, "{step}");
        assert_eq!(e.unsampled_zone(step), None);
        // Every zone of every layout is sampled by its suggested step and any finer one.
        let e = bounds(&[0.0, 0.5, 10.0, 43.0, 43.6, 85.9, 86.0]).unwrap();
        for z in 0..6 {
            let s = e.step_to_sample(z);
            for k in 0..40 {
                let step = s * (1.0 - k as f64 / 80.0);
                if step >= 0.5 {
                    assert!(
                        !e.samples(step).iter().all(|x| x.zone != z),
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
