//! Study files: a TOML file naming the model parameters and the values to combine (lists,
//! ranges or ties to another parameter), expanded into evaluations with docs/model.md §2's
//! validity rules applied — invalid combinations are skipped and counted, never simulated.
//!
//! ```toml
//! [study]
//! name = "paper"              # names the outputs: results/paper.csv, …
//! fidelity = "fast"           # draft | fast | paper | fine (case.rs, Fidelity)
//! untextured = true           # add the plain liner for every combination of the rest
//!
//! [parameters]                # a number, a list, a range, or the name of another parameter
//! R = [0.2, 0.4, 0.8]
//! l1 = { from = 0.005, to = 0.03, count = 6 }            # linear, ends included
//! per = { from = 0.005, to = 0.08, factor = 2 }          # geometric
//! l2 = "l1"
//! depth = [2, 5, 10]
//! ```
//!
//! Instead of a grid of textures, `texture` lists chosen ones
//! (`texture = [{ l1 = 0.03, per = 0.06, depth = 10 }, …]`, l2 and width defaulting to l1 and
//! per). The operating point is either the scaled parameters (u, w_ps, mass) or the physical
//! ones (speed, load, viscosity, ring_width, ring_mass: docs/model.md §1), not both.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

pub use super::file_error::{Problem, TextureProblem, ValueProblem};
pub use super::file_keys::{MAX_CASES, MAX_CASES_CEILING, MAX_VALUES, PARAMETERS};
use crate::model::case::{CaseSpec, InputError, Texture, Waiver};
use crate::model::operating::{Operating, Scales, Validity, RANGES};
use crate::solve::Method;
use crate::time::{resolve, Fidelity, Numerics, Overrides};

/// The physical operating parameters (docs/model.md §1), exclusive of the scaled ones.
const PHYSICAL: [&str; 5] = ["speed", "load", "viscosity", "ring_width", "ring_mass"];
const SCALED: [&str; 3] = ["u", "w_ps", "mass"];

const TEXTURE: [&str; 6] = ["l1", "l2", "per", "width", "depth", "phase"];

/// A study file is wrong: which file, and what is wrong in it.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {problem}")]
pub struct StudyError {
    pub file: String,
    pub problem: Problem,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    study: Header,
    parameters: toml::Table,
    #[serde(default)]
    numerics: NumericsOverride,
    #[serde(default)]
    report: ReportToml,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Header {
    name: String,
    #[serde(default)]
    description: String,
    #[serde(default = "fast")]
    fidelity: Fidelity,
    #[serde(default)]
    untextured: bool,
    #[serde(default)]
    allow_thick_pockets: bool,
    /// Most combinations the parameters may expand to (valid or not), [`MAX_CASES`] unless
    /// raised here.
    #[serde(default = "max_cases")]
    max_cases: u64,
    /// Composite RMS roughness of ring and liner (µm): cases whose minimum clearance falls
    /// below 3 times it are flagged as outside the hydrodynamic model.
    roughness: Option<f64>,
}

fn max_cases() -> u64 {
    MAX_CASES
}

fn fast() -> Fidelity {
    Fidelity::Fast
}

/// Optional changes to the tier's numerics, applied to every case.
#[derive(Deserialize, Default, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NumericsOverride {
    pub n1: Option<usize>,
    pub n2: Option<usize>,
    pub dt: Option<f64>,
    pub periodic_tol: Option<f64>,
    pub t_max: Option<f64>,
    pub solver: Option<Method>,
}

/// Where the report of a study goes and which small-/large-R classes Table 1 uses.
#[derive(Deserialize, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ReportToml {
    /// Directory of the outputs (relative to the working directory); empty in the file:
    /// `results/<study name>`.
    #[serde(default)]
    pub dir: String,
    /// File name of the best-texture table (default `<name>_table1.md`).
    pub table: Option<String>,
    /// Rings with R at most this are "small R" in the table (cm).
    #[serde(default = "small_r")]
    pub small_r_max: f64,
    /// Rings with R at least this are "large R" (cm).
    #[serde(default = "large_r")]
    pub large_r_min: f64,
}

fn small_r() -> f64 {
    0.8
}
fn large_r() -> f64 {
    3.2
}

impl Default for ReportToml {
    fn default() -> Self {
        ReportToml {
            dir: String::new(),
            table: None,
            small_r_max: small_r(),
            large_r_min: large_r(),
        }
    }
}

/// One evaluation of a study: the scaled case, its numerics, and the scales that turn its
/// outcomes into physical units (not part of what is computed: similar rings share a case).
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    pub case: CaseSpec,
    pub numerics: Numerics,
    pub scales: Scales,
}

/// An expanded study.
#[derive(Clone, Debug)]
pub struct Study {
    pub name: String,
    pub description: String,
    pub fidelity: Fidelity,
    pub jobs: Vec<Job>,
    /// Invalid combinations skipped, counted by the rule they break.
    pub skipped: BTreeMap<String, usize>,
    pub report: ReportToml,
    /// Where the film model stops (the `[study]` roughness).
    pub validity: Validity,
}

impl Study {
    pub fn skipped_total(&self) -> usize {
        self.skipped.values().sum()
    }
}

/// Reads and expands a study file.
pub fn load(path: &Path) -> Result<Study, StudyError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| StudyError {
        file: file.clone(),
        problem: Problem::Read(e),
    })?;
    parse(&text, &file)
}

/// Parses and expands study text (`file` names it in errors).
pub fn parse(text: &str, file: &str) -> Result<Study, StudyError> {
    let err = |problem: Problem| StudyError {
        file: file.to_string(),
        problem,
    };
    // toml's message spans several lines (a source excerpt); kept on one.
    let raw: FileToml = toml::from_str(text)
        .map_err(|e| err(Problem::Toml(crate::model::case::one_line(&e.to_string()))))?;
    check_header(&raw).map_err(&err)?;
    let validity = validity(&raw).map_err(&err)?;
    let (values, textures) = parameter_values(&raw.parameters).map_err(&err)?;
    let (mut jobs, skipped) = expand_cases(&raw, &values, &textures).map_err(&err)?;
    // The asperity contact's σ is the study's roughness (docs/model.md §11).
    for j in &mut jobs {
        validity.apply(&mut j.case);
    }
    if jobs.is_empty() {
        return Err(err(Problem::NoValidCase {
            combinations: skipped.values().sum::<usize>(),
            rules: skipped.keys().cloned().collect(),
        }));
    }
    let dir = match raw.report.dir.as_str() {
        "" => format!("results/{}", raw.study.name),
        d => d.to_string(),
    };
    Ok(Study {
        name: raw.study.name,
        description: raw.study.description,
        fidelity: raw.study.fidelity,
        jobs,
        skipped,
        report: ReportToml { dir, ..raw.report },
        validity,
    })
}

/// The `[study]` roughness, checked.
fn validity(raw: &FileToml) -> Result<Validity, Problem> {
    let mut v = Validity::default();
    if let Some(r) = raw.study.roughness {
        if !(r.is_finite() && r > 0.0 && r <= 10.0) {
            return Err(Problem::Roughness(r));
        }
        v.roughness_um = r;
    }
    Ok(v)
}

/// The `[study]` name and the `[report]` classes.
fn check_header(raw: &FileToml) -> Result<(), Problem> {
    if raw.study.name.trim().is_empty()
        || !raw
            .study
            .name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(Problem::Name(raw.study.name.clone()));
    }
    if !(1..=MAX_CASES_CEILING).contains(&raw.study.max_cases) {
        return Err(Problem::MaxCases(raw.study.max_cases));
    }
    let r = &raw.report;
    if !(r.small_r_max.is_finite() && r.large_r_min.is_finite() && r.small_r_max < r.large_r_min) {
        return Err(Problem::ReportClasses {
            small_r_max: r.small_r_max,
            large_r_min: r.large_r_min,
        });
    }
    // The table is a file of the report directory: a plain name, never a path out of it.
    if let Some(t) = &r.table {
        let plain = std::path::Path::new(t)
            .file_name()
            .is_some_and(|n| n == t.as_str());
        if t.trim().is_empty() || !plain || t == "." || t == ".." {
            return Err(Problem::Table(t.clone()));
        }
    }
    Ok(())
}

/// The `[parameters]`: known names, values expanded, the texture's defaults tied (l2 to l1,
/// width to per), every tie to a parameter that has values; and the chosen textures (the
/// `texture` axis holds their indices).
type Parameters = (BTreeMap<String, Values>, Vec<Texture>);

fn parameter_values(parameters: &toml::Table) -> Result<Parameters, Problem> {
    let mut values: BTreeMap<String, Values> = BTreeMap::new();
    let mut textures = Vec::new();
    for (key, v) in parameters {
        if !PARAMETERS.iter().any(|(n, _)| n == key) {
            return Err(Problem::UnknownParameter(key.clone()));
        }
        if key == "texture" {
            textures = texture_list(v)?;
            let index = (0..textures.len()).map(|i| i as f64).collect();
            values.insert(key.clone(), Values::List(index));
            continue;
        }
        values.insert(key.clone(), expand(key, v)?);
    }
    exclusive(&values)?;
    if !values.contains_key("R") {
        return Err(Problem::MissingR);
    }
    if TEXTURE.iter().any(|k| values.contains_key(*k)) && !values.contains_key("texture") {
        for k in ["l1", "per", "depth"] {
            if !values.contains_key(k) {
                return Err(Problem::MissingTexture(k));
            }
        }
        values
            .entry("l2".into())
            .or_insert(Values::Tie("l1".into()));
        values
            .entry("width".into())
            .or_insert(Values::Tie("per".into()));
    }
    for (k, v) in &values {
        if let Values::Tie(other) = v {
            match values.get(other) {
                None => {
                    return Err(Problem::TieToNothing {
                        key: k.clone(),
                        other: other.clone(),
                    })
                }
                Some(Values::Tie(_)) => {
                    return Err(Problem::TieToTie {
                        key: k.clone(),
                        other: other.clone(),
                    })
                }
                Some(Values::List(_)) => {}
            }
        }
    }
    Ok((values, textures))
}

/// Keys that cannot go together: chosen textures and a texture grid; scaled and physical
/// operating parameters. Physical values outside their ranges are refused (a unit slip).
fn exclusive(values: &BTreeMap<String, Values>) -> Result<(), Problem> {
    let has = |k: &&&str| values.contains_key(**k);
    if values.contains_key("texture") {
        if let Some(k) = TEXTURE.iter().find(has) {
            return Err(Problem::ListAndGrid(k));
        }
    }
    if let (Some(a), Some(b)) = (SCALED.iter().find(has), PHYSICAL.iter().find(has)) {
        return Err(Problem::ScaledAndPhysical(a, b));
    }
    for (name, unit, lo, hi) in RANGES {
        if let Some(Values::List(v)) = values.get(name) {
            if let Some(x) = v.iter().find(|x| !(**x > 0.0 && (lo..=hi).contains(*x))) {
                return Err(Problem::OutOfRange {
                    name,
                    value: *x,
                    unit,
                    lo,
                    hi,
                });
            }
        }
    }
    Ok(())
}

/// `texture = [{ l1, per, depth [, l2, width, phase] }, …]`.
fn texture_list(v: &toml::Value) -> Result<Vec<Texture>, Problem> {
    let err = Problem::Texture;
    let Some(list) = v.as_array().filter(|a| !a.is_empty()) else {
        return Err(err(TextureProblem::Empty));
    };
    let mut out = Vec::new();
    for (i, item) in list.iter().enumerate() {
        let Some(t) = item.as_table() else {
            return Err(err(TextureProblem::NotATable { item: i + 1 }));
        };
        if let Some(k) = t.keys().find(|k| !TEXTURE.contains(&k.as_str())) {
            return Err(err(TextureProblem::UnknownKey {
                item: i + 1,
                key: k.clone(),
            }));
        }
        let get = |k: &str| t.get(k).map(|x| number(k, x)).transpose();
        let need = |k: &'static str| {
            get(k)?.ok_or(err(TextureProblem::Needs {
                item: i + 1,
                key: k,
            }))
        };
        let (l1, per) = (need("l1")?, need("per")?);
        out.push(Texture {
            l1,
            l2: get("l2")?.unwrap_or(l1),
            per,
            width: get("width")?.unwrap_or(per),
            depth: need("depth")?,
            phase: get("phase")?.unwrap_or(0.0),
        });
    }
    Ok(out)
}

/// The cases of the Cartesian product over the free parameters (in [`PARAMETERS`] order, R
/// outermost, the last fastest), the plain liner once per combination of the rest: the valid
/// ones as jobs, the others counted by the rule they break.
fn expand_cases(
    raw: &FileToml,
    values: &BTreeMap<String, Values>,
    textures: &[Texture],
) -> Result<(Vec<Job>, BTreeMap<String, usize>), Problem> {
    let textured = TEXTURE.iter().any(|k| values.contains_key(*k)) || !textures.is_empty();
    let free: Vec<(&str, &Vec<f64>)> = PARAMETERS
        .iter()
        .filter_map(|(n, _)| match values.get(*n) {
            Some(Values::List(v)) => Some((*n, v)),
            _ => None,
        })
        .collect();
    let mut jobs = Vec::new();
    let mut skipped = BTreeMap::new();
    let mut seen = std::collections::HashSet::new();
    // Counted before anything is expanded (checked: ranges whose product passes 2⁶⁴ must
    // not wrap around to a small number).
    let total = free
        .iter()
        .try_fold(1u64, |n, (_, v)| n.checked_mul(v.len() as u64))
        .filter(|n| *n <= raw.study.max_cases)
        .ok_or_else(|| Problem::TooManyCases {
            max_cases: raw.study.max_cases,
            sizes: free.iter().map(|(n, v)| (*n, v.len())).collect(),
        })?;
    let mut index = vec![0usize; free.len()];
    for _ in 0..total {
        let mut point: BTreeMap<&str, f64> = BTreeMap::new();
        for (d, (n, v)) in free.iter().enumerate() {
            point.insert(n, v[index[d]]);
        }
        for (k, v) in values {
            if let Values::Tie(other) = v {
                let x = point[other.as_str()];
                point.insert(k.as_str(), x);
            }
        }
        let mut cases = Vec::new();
        if textured {
            cases.push(case_at(&point, textures, true));
        }
        if raw.study.untextured || !textured {
            cases.push(case_at(&point, textures, false));
        }
        for (case, scales) in cases {
            let key = serde_json::to_string(&(&case, &scales)).unwrap_or_default();
            if !seen.insert(key) {
                continue; // the plain liner repeats across texture combinations
            }
            match broken_rule(&case, raw.study.allow_thick_pockets) {
                Some(rule) => *skipped.entry(rule).or_insert(0) += 1,
                None => {
                    let numerics = resolve(raw.study.fidelity, &(&raw.numerics).into(), &case);
                    if let Err(e) = numerics.validate(&case) {
                        return Err(Problem::Numerics {
                            case: case.label(),
                            rule: e.rule,
                        });
                    }
                    jobs.push(Job {
                        case,
                        numerics,
                        scales,
                    });
                }
            }
        }
        // Next index (odometer, last parameter fastest).
        for d in (0..free.len()).rev() {
            index[d] += 1;
            if index[d] < free[d].1.len() {
                break;
            }
            index[d] = 0;
        }
    }
    Ok((jobs, skipped))
}

impl From<&NumericsOverride> for Overrides {
    /// The file's `[numerics]` as given beside the tier ([`crate::time::resolve`]).
    fn from(o: &NumericsOverride) -> Self {
        Overrides {
            n1: o.n1,
            n2: o.n2,
            dt: o.dt,
            periodic_tol: o.periodic_tol,
            t_max: o.t_max,
            solver: o.solver,
            ..Overrides::default()
        }
    }
}

/// The rule a case breaks, if any, in words that group alike cases ("2·l1 > per", "thin
/// film"): the skipped cases are counted by it.
fn broken_rule(case: &CaseSpec, allow_thick: bool) -> Option<String> {
    case.validate(allow_thick).err().map(|e: InputError| {
        if e.rule.contains("overlap") {
            format!(
                "{} too large for the period (pockets would overlap)",
                e.param
            )
        } else if e.waiver == Some(Waiver::ThickPockets) {
            "thin-film validity 10⁴·l ≥ 5·depth".to_string()
        } else {
            format!("{} {}", e.param, e.rule)
        }
    })
}

/// The case at one point of the parameters, with its scales: physical parameters, where
/// the study gives any, set the operating point (the paper's for those it leaves out).
fn case_at(p: &BTreeMap<&str, f64>, textures: &[Texture], textured: bool) -> (CaseSpec, Scales) {
    let mut c = CaseSpec::paper(p["R"]);
    let get = |k: &str, d: f64| p.get(k).copied().unwrap_or(d);
    let mut scales = Scales::PAPER;
    if PHYSICAL.iter().any(|k| p.contains_key(k)) {
        let d = Operating::paper();
        let op = Operating {
            speed_ms: get("speed", d.speed_ms),
            load_n_per_m: get("load", d.load_n_per_m),
            viscosity_pas: get("viscosity", d.viscosity_pas),
            ring_width_mm: get("ring_width", d.ring_width_mm),
            ring_mass_kg_per_m: get("ring_mass", d.ring_mass_kg_per_m),
            d_oil_um: get("d_oil", d.d_oil_um),
        };
        op.apply(&mut c);
        scales = op.scales();
    }
    c.u = get("u", c.u);
    c.w_ps = get("w_ps", c.w_ps);
    c.mass = get("mass", c.mass);
    c.d_oil = get("d_oil", c.d_oil);
    c.theta_s = get("theta_s", c.theta_s);
    c.e = get("e", c.e);
    c.z0 = get("z0", c.z0);
    c.v0 = get("v0", c.v0);
    if let (true, Some(i)) = (textured, p.get("texture")) {
        c.texture = textures.get(*i as usize).cloned();
    } else if textured {
        c.texture = Some(Texture {
            l1: p["l1"],
            l2: p["l2"],
            per: p["per"],
            width: p["width"],
            depth: p["depth"],
            phase: get("phase", 0.0),
        });
    }
    (c, scales)
}

enum Values {
    List(Vec<f64>),
    Tie(String),
}

fn number(key: &str, v: &toml::Value) -> Result<f64, Problem> {
    let bad = |problem| Problem::parameter(key, problem);
    match v {
        toml::Value::Float(x) if x.is_finite() || (key == "R" && *x == f64::INFINITY) => Ok(*x),
        toml::Value::Float(x) => Err(bad(ValueProblem::NotFinite {
            value: *x,
            unit: unit(key),
        })),
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::String(s) if s == "inf" && key == "R" => Ok(f64::INFINITY),
        toml::Value::String(s) => Err(bad(ValueProblem::NotANumber {
            text: s.clone(),
            unit: unit(key),
        })),
        other => Err(bad(ValueProblem::WrongType {
            found: other.type_str(),
            unit: unit(key),
        })),
    }
}

fn unit(key: &str) -> &'static str {
    PARAMETERS
        .iter()
        .find(|(n, _)| *n == key)
        .map_or("", |(_, u)| u)
}

fn expand(key: &str, v: &toml::Value) -> Result<Values, Problem> {
    let bad = |problem| Problem::parameter(key, problem);
    let list = match v {
        toml::Value::String(s) if s != "inf" => {
            if PARAMETERS.iter().any(|(n, _)| n == s) && s != key {
                return Ok(Values::Tie(s.clone()));
            }
            return Err(bad(ValueProblem::NeitherNumberNorName {
                text: s.clone(),
                unit: unit(key),
            }));
        }
        toml::Value::Array(a) => {
            if a.is_empty() {
                return Err(bad(ValueProblem::EmptyList));
            }
            a.iter()
                .map(|x| number(key, x))
                .collect::<Result<Vec<_>, _>>()?
        }
        toml::Value::Table(t) => {
            let values = range(key, t)?;
            // Ranges can overflow (a log range from 1e-300 to 1e300): every value finite.
            if let Some(x) = values.iter().find(|x| !x.is_finite()) {
                return Err(bad(ValueProblem::RangeNotFinite(*x)));
            }
            values
        }
        other => vec![number(key, other)?],
    };
    if let Some(x) = list
        .iter()
        .find(|x| !(x.is_finite() || (key == "R" && **x == f64::INFINITY)))
    {
        return Err(bad(ValueProblem::ValueNotFinite(*x)));
    }
    Ok(Values::List(list))
}

/// `{ from, to, count }` (linear, `spacing = "log"` for geometric), `{ from, to, step }` or
/// `{ from, to, factor }`; ends included.
fn range(key: &str, t: &toml::Table) -> Result<Vec<f64>, Problem> {
    let bad = |problem| Problem::parameter(key, problem);
    for k in t.keys() {
        if !["from", "to", "count", "step", "factor", "spacing"].contains(&k.as_str()) {
            return Err(bad(ValueProblem::UnknownRangeKey(k.clone())));
        }
    }
    let get = |k: &str| t.get(k).map(|v| number(key, v)).transpose();
    let (from, to) = match (get("from")?, get("to")?) {
        (Some(a), Some(b)) => (a, b),
        _ => return Err(bad(ValueProblem::RangeEnds)),
    };
    if !(from.is_finite() && to.is_finite()) || from > to {
        return Err(bad(ValueProblem::RangeInverted { from, to }));
    }
    let log = match t.get("spacing").map(|v| v.as_str()) {
        None => false,
        Some(Some("linear")) => false,
        Some(Some("log")) => true,
        Some(_) => return Err(bad(ValueProblem::Spacing)),
    };
    let mut out = Vec::new();
    let n_given = [
        t.contains_key("count"),
        t.contains_key("step"),
        t.contains_key("factor"),
    ]
    .iter()
    .filter(|x| **x)
    .count();
    if n_given != 1 {
        return Err(bad(ValueProblem::RangeKinds));
    }
    if let Some(c) = get("count")? {
        if !(c >= 1.0 && c.fract() == 0.0 && c as usize <= MAX_VALUES) {
            return Err(bad(ValueProblem::Count(c)));
        }
        let n = c as usize;
        if log && from <= 0.0 {
            return Err(bad(ValueProblem::LogFrom));
        }
        for i in 0..n {
            let s = if n == 1 {
                0.0
            } else {
                i as f64 / (n - 1) as f64
            };
            out.push(if log {
                from * (to / from).powf(s)
            } else {
                from + s * (to - from)
            });
        }
    } else if let Some(step) = get("step")? {
        if step.is_nan() || step <= 0.0 || ((to - from) / step) as usize > MAX_VALUES {
            return Err(bad(ValueProblem::Step(step)));
        }
        let n = ((to - from) / step + 1e-9).floor() as usize;
        out.extend((0..=n).map(|i| from + i as f64 * step));
    } else if let Some(f) = get("factor")? {
        if f.is_nan() || f <= 1.0 || from <= 0.0 || (to / from).ln() / f.ln() > MAX_VALUES as f64 {
            return Err(bad(ValueProblem::Factor(f)));
        }
        let mut x = from;
        while x <= to * (1.0 + 1e-9) {
            out.push(x);
            x *= f;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn physical_axes_and_chosen_textures_expand() {
        let s = parse(
            r#"
            [study]
            name = "op"
            untextured = true
            [parameters]
            R = 5
            texture = [{ l1 = 0.03, per = 0.06, depth = 10 }, { l1 = 0.0025, per = 0.06, depth = 2 }]
            load = { from = 4, to = 400, count = 3, spacing = "log" }
            viscosity = 0.008
            "#,
            "op.toml",
        )
        .unwrap();
        // 2 textures × 3 loads, and the plain liner once per load.
        assert_eq!(s.jobs.len(), 9);
        let loads: Vec<f64> = s
            .jobs
            .iter()
            .map(|j| j.case.w_ps * j.scales.load_n_per_m())
            .collect();
        for (got, want) in loads
            .iter()
            .zip([4.0, 4.0, 40.0, 40.0, 400.0, 400.0, 4.0, 40.0, 400.0])
        {
            assert!((got / want - 1.0).abs() < 1e-9, "{got} vs {want}");
        }
        assert!(s
            .jobs
            .iter()
            .all(|j| j.case.u == 1.0 && j.scales.viscosity_pas == 0.008));
        assert!(s.jobs[1].case.texture.is_none());
        let t = s.jobs[6].case.texture.as_ref().unwrap();
        assert_eq!((t.l1, t.l2, t.width, t.depth), (0.0025, 0.0025, 0.06, 2.0));
    }

    #[test]
    fn scaled_and_physical_keys_or_list_and_grid_do_not_mix() {
        let head = "[study]\nname = \"x\"\n[parameters]\nR = 5\n";
        for (body, says) in [
            ("w_ps = 1e-6\nload = 40", "not both"),
            (
                "texture = [{ l1 = 0.03, per = 0.06, depth = 10 }]\ndepth = 5",
                "not both",
            ),
            ("load = [40, 4e7]", "check the unit"),
            ("viscosity = -1", "check the unit"),
            ("texture = [{ l1 = 0.03, depth = 10 }]", "needs per"),
            (
                "texture = [{ l1 = 0.03, per = 0.06, depth = 10, pitch = 1 }]",
                "unknown key",
            ),
            ("texture = []", "non-empty"),
        ] {
            let e = parse(&format!("{head}{body}"), "x.toml").unwrap_err();
            let m = e.problem.to_string();
            assert!(m.contains(says), "{body}: {m}");
        }
    }

    #[test]
    fn ranges_and_ties_expand() {
        let s = parse(
            r#"
            [study]
            name = "t"
            untextured = true
            [parameters]
            R = { from = 0.2, to = 0.8, factor = 2 }
            l1 = { from = 0.01, to = 0.02, count = 2 }
            per = 0.06
            depth = [2, 5]
            "#,
            "t.toml",
        )
        .unwrap();
        // 3 R × 2 l1 × 2 depth textured + 3 plain liners.
        assert_eq!(s.jobs.len(), 15);
        let t = s.jobs[0].case.texture.as_ref().unwrap();
        assert_eq!((t.l2, t.width), (t.l1, t.per));
    }
}
