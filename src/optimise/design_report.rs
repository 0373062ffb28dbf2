//! The optimiser's report: the rows a user reads, the terminal table, and the files (JSON,
//! CSV, the front, the reported designs' texture cells and the time histories of the best
//! design against the plain liner).

use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::driver::Settings;
use super::error::OptimiseError;
use super::front_merge::Merged;
use super::search::Evaluator;
use super::space::{depth_ratio, wall, Space};
use crate::model::case::{CaseSpec, Texture};
use crate::plot::{self, Chart, Scale, Series, Style};
use crate::time::{Outcome, SeriesRow};

/// What a reported design is on the front, in the order a label names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    BestFriction,
    BestClearance,
    Balanced,
    PlainLiner,
}

impl Role {
    pub fn name(self) -> &'static str {
        match self {
            Role::BestFriction => "best friction",
            Role::BestClearance => "best clearance",
            Role::Balanced => "balanced",
            Role::PlainLiner => "plain liner",
        }
    }
}

/// A reported design's label: its roles (none before the front is labelled), named joined by
/// " + " (a kept design carries the roles of the designs merged into it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Label(Vec<Role>);

impl Label {
    pub fn of(role: Role) -> Label {
        Label(vec![role])
    }

    pub fn has(&self, role: Role) -> bool {
        self.0.contains(&role)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The label of a kept row carrying `labels`: each role once, the best designs first;
    /// "balanced" says nothing once a row is a best design.
    pub fn joined<'a>(labels: impl IntoIterator<Item = &'a Label>) -> Label {
        let mut roles: Vec<Role> = Vec::new();
        for &r in labels.into_iter().flat_map(|l| &l.0) {
            if !roles.contains(&r) {
                roles.push(r);
            }
        }
        roles.sort_by_key(|r| match r {
            Role::BestClearance => 1,
            Role::Balanced => 2,
            Role::BestFriction | Role::PlainLiner => 0,
        });
        if roles.len() > 1 {
            roles.retain(|r| *r != Role::Balanced);
        }
        Label(roles)
    }
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, r) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(" + ")?;
            }
            f.write_str(r.name())?;
        }
        Ok(())
    }
}

impl Serialize for Label {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// One reported design.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub label: Label,
    /// None: the plain liner.
    pub texture: Option<Texture>,
    pub f_mean: f64,
    pub c_min: f64,
    pub z_mean: f64,
    pub f_change_pct: f64,
    pub c_min_change_pct: f64,
    pub area_fraction: f64,
    pub wall_x1_cm: f64,
    pub wall_x2_cm: f64,
    pub depth_ratio: f64,
    pub active_constraints: Vec<String>,
    pub on_front: bool,
    /// Period-mean friction force and power per unit circumferential length (N/m, W/m).
    pub friction_n_per_m: f64,
    pub power_w_per_m: f64,
    /// Why the design is outside the hydrodynamic model (docs/model.md §9), if it is.
    pub outside_model: Option<String>,
}

/// The result of `optimise`.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub r: f64,
    /// The operating point: its Stribeck number (eq. 19) and the composite roughness of the
    /// clearance limit (µm).
    pub stribeck: f64,
    pub roughness_um: f64,
    pub space: Space,
    pub search_fidelity: String,
    pub report_fidelity: String,
    /// Relative error of f̄ of the reported fidelity (`Fidelity::f_error`).
    pub fidelity_error: f64,
    /// Relative error of C_min of the reported fidelity (`Fidelity::c_error`).
    pub fidelity_c_error: f64,
    pub plain: Row,
    /// The plain liner's f̄ and C_min at the search fidelity (the searched designs' changes).
    pub plain_search_f_mean: f64,
    pub plain_search_c_min: f64,
    pub best_friction: Row,
    pub best_clearance: Row,
    /// The confirmed Pareto front (plain liner included when on it), by increasing f̄.
    pub front: Vec<Row>,
    /// Front designs left out because a thicker-walled one on the front has the same f̄ and
    /// C_min within the reported tier's errors ([`super::front_merge`]), and how many.
    pub merged_count: usize,
    pub merged: Vec<Merged>,
    /// Whether a texture beats the plain liner's friction by more than the fidelity error.
    pub texture_beats_plain: bool,
    pub verdict: String,
    pub evaluations_search: usize,
    pub evaluations_confirm: usize,
    pub simulations: usize,
    pub wall_time_s: f64,
    /// Every evaluated design: (fidelity, texture, f̄, C_min, feasible) for the plot and audit.
    pub evaluated: Vec<EvaluatedDesign>,
}

#[derive(Clone, Debug, Serialize)]
pub struct EvaluatedDesign {
    pub fidelity: String,
    pub texture: Texture,
    pub f_mean: Option<f64>,
    pub c_min: Option<f64>,
    pub failure: Option<String>,
    pub active_constraints: Vec<String>,
}

/// The row of a design (None: the plain liner) against the plain liner's outcome.
pub(super) fn row(
    s: &Settings,
    label: Label,
    t: Option<&Texture>,
    o: &Outcome,
    plain: &Outcome,
) -> Row {
    let (w1, w2) = t.map_or((f64::NAN, f64::NAN), wall);
    let space = &s.search.space;
    let case = CaseSpec {
        texture: t.cloned(),
        ..s.base.clone()
    };
    let physical = s.scales.physical(&case, o.f_mean, o.c_min);
    Row {
        friction_n_per_m: physical.friction_n_per_m,
        power_w_per_m: physical.power_w_per_m,
        outside_model: s.search.validity.outside(&case, o.c_min),
        label,
        texture: t.cloned(),
        f_mean: o.f_mean,
        c_min: o.c_min,
        z_mean: o.z_mean,
        f_change_pct: 100.0 * (o.f_mean / plain.f_mean - 1.0),
        c_min_change_pct: 100.0 * (o.c_min / plain.c_min - 1.0),
        area_fraction: t.map_or(0.0, Texture::area_fraction),
        wall_x1_cm: w1,
        wall_x2_cm: w2,
        depth_ratio: t.map_or(0.0, depth_ratio),
        active_constraints: t.map_or(Vec::new(), |t| {
            space.active(t).iter().map(|s| s.to_string()).collect()
        }),
        on_front: false,
    }
}

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
            x.outside_model.as_deref().unwrap_or_default()
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

/// The table's rows with their labels: the best designs, the other front designs by f̄,
/// the plain liner.
pub fn table_rows(r: &Report) -> Vec<(String, &Row)> {
    let mut rows: Vec<(String, &Row)> = Vec::new();
    for (x, role) in [
        (&r.best_friction, Role::BestFriction),
        (&r.best_clearance, Role::BestClearance),
    ] {
        if x.texture.is_some() && !rows.iter().any(|(_, y)| y.texture == x.texture) {
            rows.push((labelled(x, role), x));
        }
    }
    for x in &r.front {
        if x.texture.is_some() && !rows.iter().any(|(_, y)| y.texture == x.texture) {
            rows.push((x.label.to_string(), x));
        }
    }
    rows.push((Role::PlainLiner.name().into(), &r.plain));
    rows
}

/// A best design's label: its own, or its role where it has none (a best design off the
/// front after merging).
fn labelled(x: &Row, role: Role) -> String {
    if x.label.is_empty() {
        role.name().into()
    } else {
        x.label.to_string()
    }
}

/// The table's account of the merged designs, also when there were none (the rule ran).
fn merged_note(s: &mut String, r: &Report) {
    if r.merged.is_empty() {
        let _ = writeln!(
            s,
            "merged none: no two front designs lie within f̄ {:.2} % and C_min {:.2} % of each other (the errors of fidelity {})",
            100.0 * r.fidelity_error,
            100.0 * r.fidelity_c_error,
            r.report_fidelity
        );
        return;
    }
    // As the tables name designs: 4 decimals in cm, 1 in µm (full doubles read as noise).
    let short = |t: &Texture| format!("{:.4}/{:.4}/{:.4}/{:.1} µm", t.l1, t.l2, t.per, t.depth);
    let _ = writeln!(
        s,
        "merged {} front design{} into thicker-walled ones with f̄ within {:.2} % and C_min within {:.2} % (the errors of fidelity {}; list in the JSON's \"merged\"):",
        r.merged_count,
        if r.merged_count == 1 { "" } else { "s" },
        100.0 * r.fidelity_error,
        100.0 * r.fidelity_c_error,
        r.report_fidelity
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
fn columns<'a>() -> [Column<Line<'a>>; 18] {
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
            x.row.outside_model.clone().unwrap_or_default()
        }),
    ]
}

fn texture_cell(x: &Line, f: fn(&Texture) -> f64) -> String {
    x.row
        .texture
        .as_ref()
        .map_or(String::new(), |t| f(t).to_string())
}

/// A CSV column: its header, and its cell of a record.
pub(super) type Column<R> = (&'static str, fn(&R) -> String);

/// The CSV of `records` in `columns`.
pub(super) fn csv_bytes<'a, R: 'a>(
    columns: &[Column<R>],
    records: impl IntoIterator<Item = &'a R>,
) -> Result<Vec<u8>, String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(columns.iter().map(|c| c.0));
    for x in records {
        let _ = w.write_record(columns.iter().map(|c| (c.1)(x)));
    }
    w.into_inner().map_err(|e| e.error().to_string())
}

/// Writes the report's files under `dir`: JSON (everything), CSV (the table), the front, and
/// Z(t), f(t) over a period of the best design against the plain liner (`ev`: the evaluation
/// service at the reported fidelity).
pub(super) fn write(dir: &Path, r: &Report, ev: &Evaluator) -> Result<(), OptimiseError> {
    let files = OptimiseError::Files;
    std::fs::create_dir_all(dir)
        .map_err(|e| files(format!("cannot create {}: {e}", dir.display())))?;
    let stem = stem(dir, r.r);
    // Not `with_extension`: R = 6.84 would lose its ".84".
    let p = PathBuf::from(format!("{}.json", stem.display()));
    let json =
        serde_json::to_string_pretty(r).map_err(|e| files(format!("{}: {e}", p.display())))?;
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
    let bytes =
        csv_bytes(&columns(), &lines).map_err(|e| files(format!("{}: {e}", p.display())))?;
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
