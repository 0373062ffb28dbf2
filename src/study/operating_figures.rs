//! The operating-point figures of a study: the friction change a texture brings against the
//! plain liner, as the Stribeck number changes (load, speed, viscosity) and as the oil supply
//! runs short. Drawn when a study varies them (three values or more).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::model::case::CaseSpec;
use crate::model::operating::Validity;
use crate::model::units::stribeck;
use crate::output::OutputError;
use crate::plot::{self, Chart, Scale, Series, Style};

/// One textured case of the study: its friction over the plain liner's, and whether it is
/// outside the hydrodynamic model.
pub(super) struct Point<'a> {
    pub case: &'a CaseSpec,
    pub f_ratio: Option<f64>,
    pub outside: bool,
}

/// The paper's Stribeck number: the oil-supply figure is drawn at the study's nearest.
const PAPER_STRIBECK: f64 = 1e-3;

/// S to 6 significant digits: equal operating points given in different units compare equal.
fn s_of(c: &CaseSpec) -> f64 {
    let s = stribeck(c.u, c.w_ps);
    format!("{s:.5e}").parse().unwrap_or(s)
}

/// A curve's name: the ring and the texture.
fn curve_name(c: &CaseSpec) -> String {
    let t = c.texture.as_ref().map_or("plain".into(), |t| {
        format!("l1={} per={} depth={}", t.l1, t.per, t.depth)
    });
    format!("R = {} cm, {t}", c.r)
}

/// Writes `<name>_stribeck.png` and `<name>_oil.png` where the study varies them.
pub(super) fn figures(
    dir: &Path,
    name: &str,
    points: &[Point],
    validity: &Validity,
) -> Result<Vec<PathBuf>, OutputError> {
    let pts: Vec<&Point> = points.iter().filter(|p| p.case.texture.is_some()).collect();
    let distinct = |f: &dyn Fn(&CaseSpec) -> f64| {
        let mut v: Vec<f64> = pts.iter().map(|p| f(p.case)).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (ss, oils) = (distinct(&s_of), distinct(&|c: &CaseSpec| c.d_oil));
    let mut files = Vec::new();
    if ss.len() >= 3 {
        let flooded = oils.last().copied().unwrap_or(f64::NAN);
        let sel: Vec<&Point> = pts
            .iter()
            .copied()
            .filter(|p| p.case.d_oil == flooded)
            .collect();
        let path = dir.join(format!("{name}_stribeck.png"));
        let title = format!("Friction change against Stribeck number (oil supply {flooded} µm)");
        draw(
            &path,
            &title,
            "Stribeck number S = μU/W",
            Scale::Log,
            &sel,
            &s_of,
            validity,
        )?;
        files.push(path);
    }
    if oils.len() >= 3 {
        let near = ss
            .iter()
            .copied()
            .min_by(|a, b| {
                (a / PAPER_STRIBECK)
                    .ln()
                    .abs()
                    .total_cmp(&(b / PAPER_STRIBECK).ln().abs())
            })
            .unwrap_or(f64::NAN);
        let sel: Vec<&Point> = pts
            .iter()
            .copied()
            .filter(|p| s_of(p.case) == near)
            .collect();
        let path = dir.join(format!("{name}_oil.png"));
        let title = format!("Friction change against oil supply (Stribeck number {near:.2e})");
        let d_oil = |c: &CaseSpec| c.d_oil;
        draw(
            &path,
            &title,
            "inlet oil film d_oil (µm; 20 = fully flooded)",
            Scale::Log,
            &sel,
            &d_oil,
            validity,
        )?;
        files.push(path);
    }
    Ok(files)
}

/// One line per ring and texture of 100·(f̄/f̄_plain − 1) against `x`, the plain liner at 0,
/// the points outside the hydrodynamic model ringed.
fn draw(
    path: &Path,
    title: &str,
    x_label: &str,
    x_scale: Scale,
    pts: &[&Point],
    x: &dyn Fn(&CaseSpec) -> f64,
    validity: &Validity,
) -> Result<(), OutputError> {
    let mut curves: BTreeMap<(u64, String), Vec<(f64, f64)>> = BTreeMap::new();
    let mut outside = Vec::new();
    for p in pts {
        let Some(ratio) = p.f_ratio else { continue };
        let xy = (x(p.case), 100.0 * (ratio - 1.0));
        let key = (p.case.r.to_bits(), curve_name(p.case));
        curves.entry(key).or_default().push(xy);
        if p.outside {
            outside.push(xy);
        }
    }
    for c in curves.values_mut() {
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let xs: Vec<f64> = curves.values().flatten().map(|p| p.0).collect();
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let zero = vec![(lo, 0.0), (hi, 0.0)];
    let mut series: Vec<Series> = curves
        .iter()
        .enumerate()
        .map(|(i, ((_, name), c))| Series {
            name: name.clone(),
            points: c,
            style: Style::Line,
            colour: 2 + i,
        })
        .collect();
    series.push(Series {
        name: "plain liner".into(),
        points: &zero,
        style: Style::Thick,
        colour: 1,
    });
    let ring_name = format!(
        "outside the hydrodynamic model (C_min < {:.2} µm, or S outside the validated range)",
        validity.clearance_limit_um()
    );
    if !outside.is_empty() {
        series.push(Series {
            name: ring_name,
            points: &outside,
            style: Style::Rings,
            colour: 0,
        });
    }
    plot::xy(
        path,
        &Chart {
            title,
            x_label,
            y_label: "friction change against the plain liner (%)",
            x_scale,
            y_scale: Scale::Linear,
        },
        &series,
    )
}
