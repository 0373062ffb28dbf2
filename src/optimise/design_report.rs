//! The optimiser's report: the rows a user reads, the terminal table, and the files (JSON,
//! CSV, the front, the reported designs' texture cells and the time histories of the best
//! design against the plain liner).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::design::{labelled, table_rows, Report, Role, Row};
use super::error::OptimiseError;
use super::search::Evaluator;
use crate::model::case::Texture;
use crate::plot::{self, Chart, Scale, Series, Style};
use crate::time::SeriesRow;

/// The terminal table.
pub fn table(r: &Report) -> String {
    let mut s = String::new();
    // Room for a merged row's joined labels and the ‡ mark.
    let rows = table_rows(r);
    let width = rows
        .iter()
        .map(|(l, _)| l.chars().count() + 2)
        .fold(15, usize::max);
    let _ = writeln!(
        s,
        "texopt optimise, R = {} cm: reported at fidelity {} (searched at {}); f̄ per eq. (11)",
        r.r, r.report_fidelity, r.search_fidelity
    );
    let _ = writeln!(
        s,
        "{:width$} {:>8} {:>8} {:>6} {:>6} {:>8} {:>8} {:>8} {:>7} {:>7} {:>11}  active",
        "design",
        "l1 cm",
        "l2 cm",
        "per",
        "depth",
        "f̄",
        "Δf̄ %",
        "C_min",
        "ΔC %",
        "area",
        "walls µm"
    );
    for (label, x) in rows {
        let (l1, l2, per, depth) =
            x.texture
                .as_ref()
                .map_or(("-".into(), "-".into(), "-".into(), "-".into()), |t| {
                    (
                        format!("{:.4}", t.l1),
                        format!("{:.4}", t.l2),
                        format!("{:.4}", t.per),
                        format!("{:.1}", t.depth),
                    )
                });
        let label = match x.outside_model {
            Some(_) => format!("{label} ‡"),
            None => label.to_string(),
        };
        let _ = writeln!(
            s,
            "{:width$} {:>8} {:>8} {:>6} {:>6} {:>8.5} {:>+8.2} {:>8.4} {:>+7.2} {:>7.3} {:>11}  {}",
            label,
            l1,
            l2,
            per,
            depth,
            x.f_mean,
            x.f_change_pct,
            x.c_min,
            x.c_min_change_pct,
            x.area_fraction,
            if x.wall_x1_cm.is_finite() {
                format!("{:.1}/{:.1}", x.wall_x1_cm * 1e4, x.wall_x2_cm * 1e4)
            } else {
                "-".to_string()
            },
            x.active_constraints.join(", ")
        );
    }
    let _ = writeln!(s, "{}", r.verdict);
    merged_note(&mut s, r);
    let flagged: Vec<&Row> = r
        .front
        .iter()
        .chain([&r.best_friction, &r.best_clearance, &r.plain])
        .filter(|x| x.outside_model.is_some())
        .collect();
    if let Some(x) = flagged.first() {
        let _ = writeln!(
            s,
            "‡ outside the hydrodynamic model, not a prediction: {}",
            x.outside_model.map(|o| o.to_string()).unwrap_or_default()
        );
    }
    let _ = writeln!(
        s,
        "operating point: Stribeck number {:.3e}; plain liner {:.4} N/m, {:.3} W/m of friction; best friction {:.4} N/m, {:.3} W/m",
        r.stribeck, r.plain.friction_n_per_m, r.plain.power_w_per_m, r.best_friction.friction_n_per_m, r.best_friction.power_w_per_m
    );
    let _ = writeln!(
        s,
        "{} evaluations at {} + {} confirmed at {}; {} simulations (the rest from the cache); {:.1} s",
        r.evaluations_search, r.search_fidelity, r.evaluations_confirm, r.report_fidelity, r.simulations, r.wall_time_s
    );
    s
}

/// The table's account of the merged designs, also when there were none (the rule ran).
fn merged_note(s: &mut String, r: &Report) {
    if r.merged.is_empty() {
        let _ = writeln!(
            s,
            "merged none: no two front designs lie within f̄ {:.2} % and C_min {:.2} % of each other (the errors of fidelity {}{})",
            100.0 * r.fidelity_error,
            100.0 * r.fidelity_c_error,
            r.report_fidelity,
            r.deep_clause()
        );
        return;
    }
    // As the tables name designs: 4 decimals in cm, 1 in µm (full doubles read as noise).
    let short = |t: &Texture| format!("{:.4}/{:.4}/{:.4}/{:.1} µm", t.l1, t.l2, t.per, t.depth);
    let _ = writeln!(
        s,
        "merged {} front design{} into thicker-walled ones with f̄ within {:.2} % and C_min within {:.2} % (the errors of fidelity {}{}; list in the JSON's \"merged\"):",
        r.merged_count,
        if r.merged_count == 1 { "" } else { "s" },
        100.0 * r.fidelity_error,
        100.0 * r.fidelity_c_error,
        r.report_fidelity,
        r.deep_clause()
    );
    for m in &r.merged {
        let _ = writeln!(
            s,
            "  {} ({}, f̄ {:.5}, C_min {:.4}) into {}",
            short(&m.texture),
            m.label,
            m.f_mean,
            m.c_min,
            short(&m.into)
        );
    }
}

fn stem(dir: &Path, r: f64) -> PathBuf {
    dir.join(format!("optimise_R{r}"))
}

/// A line of the CSV: a reported design under its label.
struct Line<'a> {
    label: String,
    row: &'a Row,
    fidelity: &'a str,
}

/// The CSV's columns, named once: each header with how its cell is written (empty where a design has no
/// texture).
fn columns<'a>() -> [Column<Line<'a>>; 21] {
    [
        ("design", |x| x.label.clone()),
        ("l1", |x| texture_cell(x, |t| t.l1)),
        ("l2", |x| texture_cell(x, |t| t.l2)),
        ("per", |x| texture_cell(x, |t| t.per)),
        ("width", |x| texture_cell(x, |t| t.width)),
        ("depth", |x| texture_cell(x, |t| t.depth)),
        ("f_mean", |x| x.row.f_mean.to_string()),
        ("f_change_pct", |x| x.row.f_change_pct.to_string()),
        ("c_min", |x| x.row.c_min.to_string()),
        ("c_min_change_pct", |x| x.row.c_min_change_pct.to_string()),
        ("area_fraction", |x| x.row.area_fraction.to_string()),
        ("wall_x1_cm", |x| texture_cell(x, |t| t.per - 2.0 * t.l1)),
        ("wall_x2_cm", |x| texture_cell(x, |t| t.width - 2.0 * t.l2)),
        ("active", |x| x.row.active_constraints.join(" ")),
        ("fidelity", |x| x.fidelity.to_string()),
        ("friction_n_per_m", |x| x.row.friction_n_per_m.to_string()),
        ("power_w_per_m", |x| x.row.power_w_per_m.to_string()),
        ("outside_model", |x| {
            x.row
                .outside_model
                .map(|o| o.to_string())
                .unwrap_or_default()
        }),
        ("f_error", |x| x.row.f_error.to_string()),
        ("c_min_error", |x| x.row.c_min_error.to_string()),
        ("error_source", |x| x.row.error_source.name().into()),
    ]
}

fn texture_cell(x: &Line, f: fn(&Texture) -> f64) -> String {
    x.row
        .texture
        .as_ref()
        .map_or(String::new(), |t| f(t).to_string())
}

/// Creates `dir` and writes the report `r` as `dir/base.json` and the tables `md` as
/// `dir/base.md`; returns the path of `dir/base` + a suffix, for the report's other files.
pub(super) fn json_and_md<'a>(
    dir: &'a Path,
    base: &'a str,
    r: &impl Serialize,
    md: String,
) -> Result<impl Fn(&str) -> PathBuf + 'a, OptimiseError> {
    crate::finite::check(r)?;
    create_dir(dir)?;
    let stem = move |ext: &str| dir.join(format!("{base}{ext}"));
    let json = serde_json::to_string_pretty(r).map_err(OptimiseError::Json)?;
    crate::output::write(&stem(".json"), json)?;
    crate::output::write(&stem(".md"), md)?;
    Ok(stem)
}

/// A report's directory, made where missing.
fn create_dir(dir: &Path) -> Result<(), OptimiseError> {
    std::fs::create_dir_all(dir).map_err(|source| OptimiseError::CreateDir {
        dir: dir.to_path_buf(),
        source,
    })
}

/// A CSV column: its header, and its cell of a record.
pub(super) type Column<R> = (&'static str, fn(&R) -> String);

/// The CSV of `records` in `columns` (its error: the CSV writer's, in words).
pub(super) fn csv_bytes<'a, R: 'a>(
    columns: &[Column<R>],
    records: impl IntoIterator<Item = &'a R>,
) -> Result<Vec<u8>, OptimiseError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(columns.iter().map(|c| c.0));
    for x in records {
        let _ = w.write_record(columns.iter().map(|c| (c.1)(x)));
    }
    w.into_inner()
        .map_err(|e| OptimiseError::Csv(e.into_error()))
}

/// Writes the report's files under `dir`: JSON (everything), CSV (the table), the front, and
/// Z(t), f(t) over a period of the best design against the plain liner (`ev`: the evaluation
/// service at the reported fidelity).
pub(super) fn write(dir: &Path, r: &Report, ev: &Evaluator) -> Result<(), OptimiseError> {
    crate::finite::check(r)?;
    create_dir(dir)?;
    let stem = stem(dir, r.r);
    // Not `with_extension`: R = 6.84 would lose its ".84".
    let p = PathBuf::from(format!("{}.json", stem.display()));
    let json = serde_json::to_string_pretty(r).map_err(|source| OptimiseError::JsonAt {
        path: p.clone(),
        source,
    })?;
    crate::output::write(&p, json)?;
    let p = PathBuf::from(format!("{}.csv", stem.display()));
    let mut rows = vec![
        (
            labelled(&r.best_friction, Role::BestFriction),
            &r.best_friction,
        ),
        (
            labelled(&r.best_clearance, Role::BestClearance),
            &r.best_clearance,
        ),
    ];
    rows.extend(r.front.iter().map(|x| (x.label.to_string(), x)));
    rows.push((r.plain.label.to_string(), &r.plain));
    let lines: Vec<Line> = rows
        .into_iter()
        .map(|(label, row)| Line {
            label,
            row,
            fidelity: &r.report_fidelity,
        })
        .collect();
    let bytes = csv_bytes(&columns(), &lines).map_err(|e| match e {
        OptimiseError::Csv(source) => OptimiseError::CsvAt {
            path: p.clone(),
            source,
        },
        e => e,
    })?;
    crate::output::write(&p, bytes)?;
    super::figures::front(&PathBuf::from(format!("{}_front.png", stem.display())), r)?;
    super::figures::cells(&PathBuf::from(format!("{}_cells.png", stem.display())), r)?;
    period_plots(&stem, r, ev)
}

/// Z(t) and f(t) over one period: the best-friction design against the plain liner.
fn period_plots(stem: &Path, r: &Report, ev: &Evaluator) -> Result<(), OptimiseError> {
    if let Some(t) = &r.best_friction.texture {
        let period = t.per / ev.base.u;
        let kept = ev.last_period(
            t,
            period,
            &PathBuf::from(format!("{}_series.json", stem.display())),
        )?;
        let last: Vec<&SeriesRow> = kept.iter().collect();
        let t0 = last.first().map_or(0.0, |x| x.t);
        let z: Vec<(f64, f64)> = last.iter().map(|x| ((x.t - t0) / period, x.z)).collect();
        let f: Vec<(f64, f64)> = last.iter().map(|x| ((x.t - t0) / period, x.f)).collect();
        let zp = vec![(0.0, r.plain.z_mean), (1.0, r.plain.z_mean)];
        let fp = vec![(0.0, r.plain.f_mean), (1.0, r.plain.f_mean)];
        for (name, best, pl, ylab) in [
            ("z", &z, &zp, "ring position Z (µm)"),
            ("f", &f, &fp, "friction coefficient f (eq. 11)"),
        ] {
            plot::xy(
                &PathBuf::from(format!("{}_{name}_t.png", stem.display())),
                &Chart {
                    title: &format!(
                        "{} over one texture period, R = {} cm",
                        if name == "z" { "Z(t)" } else { "f(t)" },
                        r.r
                    ),
                    x_label: "t / period",
                    y_label: ylab,
                    x_scale: Scale::Linear,
                    y_scale: Scale::Linear,
                },
                &[
                    Series {
                        name: match r.best_friction.outside_model {
                            None => "best-friction texture".into(),
                            Some(_) => {
                                "best-friction texture (outside the hydrodynamic model)".into()
                            }
                        },
                        points: best,
                        style: Style::Line,
                        colour: 0,
                    },
                    Series {
                        name: "plain liner".into(),
                        points: pl,
                        style: Style::Thick,
                        colour: 1,
                    },
                ],
            )?;
        }
    }
    Ok(())
}
