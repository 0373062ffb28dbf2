//! An engine file's rules: the error that names the key a value breaks, the physical
//! ranges of its inputs, and the checks its tables share.

use crate::model::case::short;

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

pub(super) fn err(
    key: &str,
    value: impl std::fmt::Display,
    rule: impl Into<String>,
) -> EngineError {
    EngineError {
        key: key.into(),
        value: value.to_string(),
        rule: rule.into(),
    }
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

/// `v` finite and within `key`'s range of [`RANGES`].
pub(super) fn in_range(key: &str, v: f64) -> Result<(), EngineError> {
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

/// `xs` finite and strictly increasing.
pub(super) fn increasing(key: &str, xs: &[f64]) -> Result<(), EngineError> {
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
