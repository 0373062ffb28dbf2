//! What can be wrong in a study file (`study::file`), each with the message that says where
//! and how to fix it.

use std::fmt;

use super::file_keys::{MAX_CASES_CEILING, MAX_VALUES, PARAMETERS};
use crate::model::case::short;

/// What is wrong in a study file.
#[derive(Debug, thiserror::Error)]
pub enum Problem {
    #[error("cannot read the study file: {0}")]
    Read(std::io::Error),
    /// Not TOML, or a section of the wrong shape: the parser's message on one line.
    #[error("{0}")]
    Toml(String),
    /// Every combination breaks a rule: how many there are, and the rules.
    #[error("no valid case: all {combinations} combinations break a rule ({}); widen the ranges", rules.join("; "))]
    NoValidCase {
        combinations: usize,
        rules: Vec<String>,
    },
    #[error("[study] roughness = {}: give the composite RMS roughness in (0, 10] µm", short(*.0))]
    Roughness(f64),
    #[error("[study] name = {0:?}: use letters, digits, '-' or '_' (it names the output files)")]
    Name(String),
    #[error("[study] max_cases = {0}: must be a whole number from 1 to {MAX_CASES_CEILING}; split a larger study into several files")]
    MaxCases(u64),
    #[error("[report] small_r_max = {} must be below large_r_min = {}", short(*small_r_max), short(*large_r_min))]
    ReportClasses { small_r_max: f64, large_r_min: f64 },
    #[error("[report] table = {0:?}: give a file name such as \"table1.md\" (it is written in the report directory)")]
    Table(String),
    #[error("[parameters] unknown parameter {:?}; known: {}", .0, known_parameters())]
    UnknownParameter(String),
    #[error("[parameters] R is missing: give the ring radius (cm) or a list of radii")]
    MissingR,
    #[error("[parameters] {0} is missing: a textured study needs l1, per and depth (l2 defaults to l1, width to per)")]
    MissingTexture(&'static str),
    /// `key` is tied to `other`, which is not given.
    #[error(
        "[parameters] {key} = {other:?}: {other} is not given; tie to a parameter that has values"
    )]
    TieToNothing { key: String, other: String },
    /// `key` is tied to `other`, itself a tie.
    #[error(
        "[parameters] {key} = {other:?}: {other} is itself a tie; tie to a parameter with values"
    )]
    TieToTie { key: String, other: String },
    /// Chosen textures and this key of a texture grid.
    #[error("[parameters] texture and {0}: give the textures either as a list (texture) or as a grid (l1, per, depth, …), not both")]
    ListAndGrid(&'static str),
    /// A scaled and a physical operating parameter.
    #[error("[parameters] {0} and {1}: give the operating point either in scaled units (u, w_ps, mass) or in physical units (speed, load, viscosity, ring_width, ring_mass), not both")]
    ScaledAndPhysical(&'static str, &'static str),
    /// A physical value outside its range (a slip of the unit).
    #[error("[parameters] {name} = {}: must lie in [{}, {}] {unit}; check the unit", short(*value), short(*lo), short(*hi))]
    OutOfRange {
        name: &'static str,
        value: f64,
        unit: &'static str,
        lo: f64,
        hi: f64,
    },
    #[error("[parameters] texture: {0}")]
    Texture(TextureProblem),
    /// A parameter's value or range.
    #[error("[parameters] {key}{problem}")]
    Parameter { key: String, problem: ValueProblem },
    /// More combinations than `max_cases`: each free parameter's count of values.
    #[error("the parameters combine into more than {max_cases} cases ({}); narrow the lists and ranges, or raise max_cases in [study]", sizes_text(sizes))]
    TooManyCases {
        max_cases: u64,
        sizes: Vec<(&'static str, usize)>,
    },
    /// The numerics break a rule for this case (its label).
    #[error("[numerics] for case {case}: {rule}")]
    Numerics { case: String, rule: String },
}

impl Problem {
    /// The problem `problem` with parameter `key`.
    pub fn parameter(key: &str, problem: ValueProblem) -> Problem {
        Problem::Parameter {
            key: key.to_string(),
            problem,
        }
    }
}

fn known_parameters() -> String {
    let names: Vec<_> = PARAMETERS.iter().map(|(n, _)| *n).collect();
    names.join(", ")
}

fn sizes_text(sizes: &[(&str, usize)]) -> String {
    let sizes: Vec<String> = sizes.iter().map(|(n, k)| format!("{n}: {k}")).collect();
    sizes.join(", ")
}

/// What is wrong in one of the chosen textures (items counted from 1).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TextureProblem {
    #[error("give a non-empty list of {{ l1, per, depth }} tables")]
    Empty,
    #[error("item {item} is not a table {{ l1, per, depth }}")]
    NotATable { item: usize },
    #[error("item {item}: unknown key {key:?}; a texture has l1, l2, per, width, depth, phase")]
    UnknownKey { item: usize, key: String },
    #[error("item {item} needs {key}")]
    Needs { item: usize, key: &'static str },
}

/// What is wrong in a parameter's value or range (`unit`: the parameter's, in words).
#[derive(Debug, Clone, PartialEq)]
pub enum ValueProblem {
    NotFinite {
        value: f64,
        unit: &'static str,
    },
    NotANumber {
        text: String,
        unit: &'static str,
    },
    WrongType {
        found: &'static str,
        unit: &'static str,
    },
    NeitherNumberNorName {
        text: String,
        unit: &'static str,
    },
    EmptyList,
    /// A range that overflows.
    RangeNotFinite(f64),
    /// A value that is not finite once expanded.
    ValueNotFinite(f64),
    UnknownRangeKey(String),
    RangeEnds,
    RangeInverted {
        from: f64,
        to: f64,
    },
    Spacing,
    /// Not exactly one of count, step and factor.
    RangeKinds,
    Count(f64),
    LogFrom,
    Step(f64),
    Factor(f64),
}

/// The text after `[parameters] KEY`.
impl fmt::Display for ValueProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ValueProblem::*;
        match self {
            NotFinite { value, unit } => write!(
                f,
                ": {value} is not a finite number; write a finite value in {unit}"
            ),
            NotANumber { text, unit } => write!(
                f,
                ": {text:?} is not a number; write plain numbers in the parameter's unit ({unit})"
            ),
            WrongType { found, unit } => {
                write!(f, ": expected a number in {unit}, found {found}")
            }
            NeitherNumberNorName { text, unit } => write!(
                f,
                " = {text:?}: not a number nor another parameter's name; write a number in {unit} (units are implied) or the name of the parameter it equals"
            ),
            EmptyList => write!(f, " = []: the list is empty; give at least one value"),
            RangeNotFinite(x) => write!(
                f,
                ": the range gives {x}, not a finite number; narrow the range"
            ),
            ValueNotFinite(x) => write!(f, ": {x} is not a finite number; narrow the range"),
            UnknownRangeKey(k) => write!(
                f,
                ": unknown range key {k:?}; a range is {{ from, to, count [, spacing = \"log\"] }}, {{ from, to, step }} or {{ from, to, factor }}"
            ),
            RangeEnds => write!(f, ": a range needs both from and to"),
            RangeInverted { from, to } => write!(
                f,
                ": range from = {} to = {} is empty or inverted; need from ≤ to",
                short(*from),
                short(*to)
            ),
            Spacing => write!(f, ": spacing must be \"linear\" or \"log\""),
            RangeKinds => write!(
                f,
                ": give exactly one of count, step or factor in a range"
            ),
            Count(c) => write!(
                f,
                ": count = {} must be a whole number from 1 to {MAX_VALUES}",
                short(*c)
            ),
            LogFrom => write!(f, ": a log range needs from > 0"),
            Step(s) => write!(
                f,
                ": step = {} must be > 0 and give at most {MAX_VALUES} values",
                short(*s)
            ),
            Factor(x) => write!(
                f,
                ": factor = {} needs factor > 1 and from > 0",
                short(*x)
            ),
        }
    }
}
