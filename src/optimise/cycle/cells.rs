//! The cells the cycle reports share: a liner's change against a reference, and an optional
//! number written or left as a dash.

/// The change of `w` against `reference` (%), if there is a reference to compare with.
pub fn change_pct(w: f64, reference: f64) -> Option<f64> {
    (reference > 0.0).then(|| 100.0 * (w / reference - 1.0))
}

/// An optional number in a table as `f` writes it, or a dash.
pub fn or_dash(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map_or("–".into(), f)
}

/// An optional number to `digits` decimals, or a dash.
pub fn fixed(x: Option<f64>, digits: usize) -> String {
    or_dash(x, |v| format!("{v:.digits$}"))
}

/// An optional change to `digits` decimals with its sign, or a dash.
pub fn signed(x: Option<f64>, digits: usize) -> String {
    or_dash(x, |v| format!("{v:+.digits$}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_write_a_change_a_number_or_a_dash() {
        // The change of a liner or zone with nothing to compare with is none, not NaN.
        assert_eq!(change_pct(0.0, 0.0), None);
        assert_eq!(change_pct(1.5, 1.0), Some(50.0));
        assert_eq!(fixed(Some(0.12345), 3), "0.123");
        assert_eq!(signed(Some(-1.25), 1), "-1.2");
        assert_eq!(signed(Some(2.0), 2), "+2.00");
        assert_eq!(fixed(None, 3), "–");
        assert_eq!(or_dash(None, |v| v.to_string()), "–");
    }
}
