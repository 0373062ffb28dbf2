//! An input that breaks a rule and how a message names it: the one error type of the
//! model's checks (cases, numerics, operating points, contact constants), and the short
//! forms of numbers the messages use. A leaf: it names no other part of the model.

/// An input that breaks a rule: names the parameter (a field of the case or of the
/// numerics, e.g. `l1`, `n1`), its value and the rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{param} = {value}: {rule}")]
pub struct InputError {
    pub param: String,
    pub value: String,
    pub rule: String,
    /// A rule the user may waive on purpose, if this is one.
    pub waiver: Option<Waiver>,
}

/// Rules a user may lift on purpose (each front end names its own switch for it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Waiver {
    /// The thin-film rule 10⁴·l ≥ 5·depth (docs/model.md §2).
    ThickPockets,
    /// The memory a run may take (time/limits.rs).
    MemoryLimit,
    /// The time steps a run may take (time/limits.rs).
    StepLimit,
    /// The asperity contact's constants (docs/model.md §11): a run without contact reads
    /// none of them.
    NoContact,
}

/// The error for `param` = `value` breaking `rule` (a number as value in short form).
pub fn bad(param: &str, value: impl std::fmt::Display, rule: impl Into<String>) -> InputError {
    let value = value.to_string();
    InputError {
        param: param.to_string(),
        value: match value.parse::<f64>() {
            Ok(x) => short(x),
            _ => value,
        },
        rule: rule.into(),
        waiver: None,
    }
}

/// A number for a message, at most about a dozen characters: as written where that is short
/// (`0.06`, `1000`), else in scientific notation with 6 significant digits at most (`1e-308`,
/// not 308 digits).
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    let a = x.abs();
    if !x.is_finite() || a == 0.0 || ((1e-4..1e9).contains(&a) && plain.len() <= 12) {
        return plain;
    }
    let sci = format!("{x:.5e}");
    match sci.split_once('e') {
        // Between 1 and 10 the exponent says nothing (`5.0000000000001` reads `5`, not `5e0`).
        Some((mantissa, "0")) => mantissa
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string(),
        Some((mantissa, exp)) if mantissa.contains('.') => {
            let m = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{m}e{exp}")
        }
        _ => sci,
    }
}

/// A file reader's message on one line, with every number of more than 15 digits written
/// short (a TOML parser quotes `1e300` back with its 301 digits).
pub fn one_line(msg: &str) -> String {
    let joined = msg
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    let mut out = String::with_capacity(joined.len());
    let mut run = String::new();
    let flush = |run: &mut String, out: &mut String| {
        let digits = run.chars().filter(char::is_ascii_digit).count();
        match run.parse::<f64>() {
            Ok(x) if digits > 15 => out.push_str(&short(x)),
            _ => out.push_str(run),
        }
        run.clear();
    };
    for c in joined.chars() {
        if c.is_ascii_digit() || (c == '.' && !run.is_empty()) {
            run.push(c);
        } else {
            flush(&mut run, &mut out);
            out.push(c);
        }
    }
    flush(&mut run, &mut out);
    out
}
