//! Fig. 6 (friction and least clearance against R, a curve per texture, the envelopes, the
//! plain liner) and Fig. 11 (the lower friction envelope per θ_s).

use std::collections::BTreeMap;
use std::path::Path;

use super::{curve_key, Row};
use crate::output::OutputError;
use crate::plot::{self, Chart, Note, Scale, Series, Style};
use crate::time::{ErrorSource, Outcome, DEEP_POCKET_RATIO};

/// Per R: the textured rows' values and the plain liner's, for one operating point.
struct Family {
    curves: Vec<Vec<(f64, f64)>>,
    lower: Vec<(f64, f64)>,
    upper: Vec<(f64, f64)>,
    plain: Vec<(f64, f64)>,
}

fn family(rows: &[&Row], value: &dyn Fn(&Outcome) -> f64) -> Family {
    let mut curves: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut plain: BTreeMap<u64, (f64, f64)> = BTreeMap::new();
    let mut lo: BTreeMap<u64, (f64, f64)> = BTreeMap::new();
    let mut hi: BTreeMap<u64, (f64, f64)> = BTreeMap::new();
    for r in rows {
        let Some(o) = r.out else { continue };
        let (x, y) = (r.job.case.r, value(o));
        let k = x.to_bits();
        if r.job.case.texture.is_none() {
            plain.insert(k, (x, y));
            continue;
        }
        curves
            .entry(curve_key(&r.job.case))
            .or_default()
            .push((x, y));
        let e = lo.entry(k).or_insert((x, y));
        if y < e.1 {
            *e = (x, y);
        }
        let e = hi.entry(k).or_insert((x, y));
        if y > e.1 {
            *e = (x, y);
        }
    }
    let sorted = |m: BTreeMap<u64, (f64, f64)>| {
        let mut v: Vec<_> = m.into_values().collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    Family {
        curves: curves
            .into_values()
            .map(|mut c| {
                c.sort_by(|a, b| a.0.total_cmp(&b.0));
                c
            })
            .collect(),
        lower: sorted(lo),
        upper: sorted(hi),
        plain: sorted(plain),
    }
}

/// The error bars of the rows whose pockets end deeper than the tiers resolve: their value
/// ± its mesh uncertainty (docs/validation.md), as pairs of ends.
fn deep_bars(rows: &[&Row], friction: bool) -> Vec<(f64, f64)> {
    rows.iter()
        .filter_map(|r| {
            let (o, e) = (r.out?, r.error?);
            if e.source != ErrorSource::DeepMesh {
                return None;
            }
            let (y, u) = if friction {
                (o.f_mean, e.f_mean)
            } else {
                (o.c_min, e.c_min)
            };
            let x = r.job.case.r;
            Some([(x, y * (1.0 - u)), (x, y * (1.0 + u))])
        })
        .flatten()
        .collect()
}

pub(super) fn fig6(
    path: &Path,
    rows: &[&Row],
    friction: bool,
    theta_s: f64,
) -> Result<(), OutputError> {
    let fam = family(rows, &|o: &Outcome| {
        if friction {
            o.f_mean
        } else {
            o.c_min
        }
    });
    let n = fam.curves.len();
    let mut series = Series::faint_family(&fam.curves, format!("{n} textures"));
    let env = if friction { &fam.lower } else { &fam.upper };
    let notes = envelope_notes(rows, env, friction);
    series.push(Series {
        name: if friction {
            "lower envelope (least friction), named l1/per (cm)/depth of its texture".into()
        } else {
            "upper envelope (largest clearance), named l1/per (cm)/depth of its texture".into()
        },
        points: env,
        style: Style::Line,
        colour: 0,
    });
    series.push(Series {
        name: "untextured liner".into(),
        points: &fam.plain,
        style: Style::Thick,
        colour: 1,
    });
    let bars = deep_bars(rows, friction);
    if !bars.is_empty() {
        series.push(Series {
            name: format!(
                "mesh uncertainty, pockets deeper than {DEEP_POCKET_RATIO}·C_min ({} cases)",
                bars.len() / 2
            ),
            points: &bars,
            style: Style::Segments,
            colour: 2,
        });
    }
    let outside: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.outside.is_some())
        .filter_map(|r| {
            let o = r.out?;
            Some((r.job.case.r, if friction { o.f_mean } else { o.c_min }))
        })
        .collect();
    if !outside.is_empty() {
        series.push(Series {
            name: format!("outside the hydrodynamic model ({} cases)", outside.len()),
            points: &outside,
            style: Style::Rings,
            colour: 3,
        });
    }
    let title = if friction {
        format!("Mean friction coefficient against ring radius (θs = {theta_s})")
    } else {
        format!("Minimum clearance against ring radius (θs = {theta_s})")
    };
    plot::xy_noted(
        path,
        &Chart {
            title: &title,
            x_label: "ring face radius R (cm)",
            y_label: if friction {
                "mean friction coefficient f (eq. 11)"
            } else {
                "minimum clearance C_min (µm)"
            },
            x_scale: Scale::Log,
            y_scale: Scale::Log,
        },
        &series,
        &notes,
    )
}

/// The texture of each point of an envelope, shortly: l1/per/depth (cm, cm, µm) for the
/// paper's round pockets on square cells, l1×l2/per×width/depth otherwise.
fn envelope_notes(rows: &[&Row], env: &[(f64, f64)], friction: bool) -> Vec<Note> {
    env.iter()
        .filter_map(|&(r, v)| {
            let t = rows.iter().find_map(|x| {
                let o = x.out?;
                let y = if friction { o.f_mean } else { o.c_min };
                (x.job.case.r == r && y == v).then_some(x.job.case.texture.as_ref()?)
            })?;
            let text = if t.l2 == t.l1 && t.width == t.per {
                format!("{}/{}/{}µm", t.l1, t.per, t.depth)
            } else {
                format!("{}×{}/{}×{}/{}µm", t.l1, t.l2, t.per, t.width, t.depth)
            };
            Some(Note { at: (r, v), text })
        })
        .collect()
}

pub(super) fn fig11(path: &Path, rows: &[Row], thetas: &[f64]) -> Result<(), OutputError> {
    let mut fams = Vec::new();
    for &th in thetas {
        let sel: Vec<&Row> = rows.iter().filter(|r| r.job.case.theta_s == th).collect();
        fams.push((th, family(&sel, &|o: &Outcome| o.f_mean)));
    }
    let mut series = Vec::new();
    for (i, (th, f)) in fams.iter().enumerate() {
        series.push(Series {
            name: format!("θs = {th}: lower envelope"),
            points: &f.lower,
            style: Style::Line,
            colour: i,
        });
        series.push(Series {
            name: format!("θs = {th}: untextured"),
            points: &f.plain,
            style: Style::Thick,
            colour: i,
        });
    }
    plot::xy(
        path,
        &Chart {
            title: "Lower friction envelopes for several θs, with their untextured liners",
            x_label: "ring face radius R (cm)",
            y_label: "mean friction coefficient f (eq. 11)",
            x_scale: Scale::Log,
            y_scale: Scale::Log,
        },
        &series,
    )
}
