//! The report of a study in the paper's form (§3.4): one CSV row per case, Fig. 6 (friction
//! and minimum clearance against R, one thin curve per texture, their envelopes, the plain
//! liner thick), Fig. 11 (lower friction envelopes per θ_s) and Table 1 (best textures for
//! small and large R), plus the headline figures.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::Outside;
use crate::model::operating::Physical;
use crate::output::OutputError;
use crate::plot::{self, Chart, Note, Scale, Series, Style};
use crate::study::file::{Job, Study};
use crate::study::operating_figures::{figures, Point};
use crate::study::sweep::{CaseFailure, CaseResult};
use crate::time::Outcome;

/// A case with its outcome and the plain liner's outcome for the same ring and operating
/// point (when the study has it).
struct Row<'a> {
    job: &'a Job,
    out: Option<&'a Outcome>,
    reason: Option<&'a str>,
    plain: Option<&'a Outcome>,
    /// Why the outcome is outside the hydrodynamic model (docs/model.md §9), if it is; and
    /// whether the plain liner's is (then the ratios are not predictions either).
    outside: Option<Outside>,
    plain_outside: bool,
}

impl Row<'_> {
    fn f_ratio(&self) -> Option<f64> {
        Some(self.out?.f_mean / self.plain?.f_mean)
    }
    fn c_ratio(&self) -> Option<f64> {
        Some(self.out?.c_min / self.plain?.c_min)
    }
}

/// The operating point without the texture: identifies the plain liner of a case.
fn plain_key(c: &CaseSpec) -> String {
    serde_json::to_string(&CaseSpec {
        texture: None,
        ..c.clone()
    })
    .unwrap_or_default()
}

/// Everything but R: identifies one curve of Fig. 6.
fn curve_key(c: &CaseSpec) -> String {
    serde_json::to_string(&CaseSpec {
        r: 0.0,
        ..c.clone()
    })
    .unwrap_or_default()
}

fn texture_label(t: &Texture) -> String {
    if t.l2 == t.l1 && t.width == t.per {
        format!("l1={} per={} depth={}", t.l1, t.per, t.depth)
    } else {
        format!(
            "l1={} l2={} per={} width={} depth={}",
            t.l1, t.l2, t.per, t.width, t.depth
        )
    }
}

/// Files written by `write`.
pub struct ReportFiles {
    pub files: Vec<PathBuf>,
    /// The headline lines (also in the summary file).
    pub headline: Vec<String>,
}

/// Why a study's report was not written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("cannot create the report directory {}: {source}", dir.display())]
    CreateDir {
        dir: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Writes the report of a finished study into `study.report.dir`.
pub fn write(
    study: &Study,
    results: &[CaseResult],
    wall_note: &str,
) -> Result<ReportFiles, ReportError> {
    let dir = Path::new(&study.report.dir);
    std::fs::create_dir_all(dir).map_err(|source| ReportError::CreateDir {
        dir: dir.to_path_buf(),
        source,
    })?;
    let rows = rows(study, results);
    let mut files = Vec::new();
    let name = &study.name;

    let csv_path = dir.join(format!("{name}.csv"));
    write_csv(&csv_path, study, &rows)?;
    files.push(csv_path);

    let scope = Scope::of(study, &rows);
    files.extend(paper_figures(dir, name, &rows, &scope)?);
    let points: Vec<Point> = scope
        .main
        .iter()
        .map(|r| Point {
            case: &r.job.case,
            f_ratio: r.f_ratio(),
            // A ratio is outside the model where either of its runs is.
            outside: r.outside.is_some() || r.plain_outside,
        })
        .collect();
    files.extend(figures(dir, name, &points, &study.validity)?);
    let headline = headline(&scope.main, scope.main_theta, study.fidelity);
    let md = summary(study, &rows, scope.main_theta, &headline, wall_note) + &captions(&files);
    let summary_path = dir.join(format!("{name}_summary.md"));
    crate::output::write(&summary_path, md)?;
    files.push(summary_path);
    if scope.textured && !scope.radii.is_empty() {
        let table = study
            .report
            .table
            .clone()
            .unwrap_or_else(|| format!("{name}_table1.md"));
        let p = dir.join(table);
        crate::output::write(&p, table1(study, &scope.main, &scope.radii))?;
        files.push(p);
    }
    Ok(ReportFiles { files, headline })
}

/// Each case of the study with its result and its plain liner's.
fn rows<'a>(study: &'a Study, results: &'a [CaseResult]) -> Vec<Row<'a>> {
    let mut plain: BTreeMap<String, &Outcome> = BTreeMap::new();
    for (j, r) in study.jobs.iter().zip(results) {
        if let (None, Some(Ok(o))) = (&j.case.texture, r) {
            plain.insert(plain_key(&j.case), o);
        }
    }
    study
        .jobs
        .iter()
        .zip(results)
        .map(|(job, r)| Row {
            job,
            out: r.as_ref().and_then(|r| r.as_ref().ok()),
            reason: r
                .as_ref()
                .and_then(|r| r.as_ref().err())
                .map(CaseFailure::words),
            plain: plain.get(&plain_key(&job.case)).copied(),
            outside: r
                .as_ref()
                .and_then(|r| r.as_ref().ok())
                .and_then(|o| study.validity.outside(&job.case, o.c_min)),
            plain_outside: plain.get(&plain_key(&job.case)).is_some_and(|p| {
                let c = CaseSpec {
                    texture: None,
                    ..job.case.clone()
                };
                study.validity.outside(&c, p.c_min).is_some()
            }),
        })
        .collect()
}

/// What of a study the paper's form (Fig. 6, 11, Table 1) shows.
struct Scope<'r, 'a> {
    /// The θ_s values of the study in file order; the first is the one of Fig. 6 and Table 1.
    thetas: Vec<f64>,
    main_theta: f64,
    /// The rows at that θ_s, and their radii (ascending, distinct).
    main: Vec<&'r Row<'a>>,
    radii: Vec<f64>,
    /// Whether they hold textured cases at one operating point (the paper's form is for one:
    /// a study that varies it is read through its operating figures instead).
    textured: bool,
}

impl<'r, 'a> Scope<'r, 'a> {
    fn of(study: &Study, rows: &'r [Row<'a>]) -> Self {
        let mut thetas: Vec<f64> = Vec::new();
        for j in &study.jobs {
            if !thetas.contains(&j.case.theta_s) {
                thetas.push(j.case.theta_s);
            }
        }
        let main_theta = thetas[0];
        let main: Vec<&Row> = rows
            .iter()
            .filter(|r| r.job.case.theta_s == main_theta)
            .collect();
        let textured = main.iter().any(|r| r.job.case.texture.is_some());
        let mut radii: Vec<f64> = main.iter().map(|r| r.job.case.r).collect();
        radii.sort_by(f64::total_cmp);
        radii.dedup();
        let op = |c: &CaseSpec| {
            plain_key(&CaseSpec {
                r: 0.0,
                theta_s: 0.0,
                ..c.clone()
            })
        };
        let one_point = rows
            .iter()
            .all(|r| op(&r.job.case) == op(&rows[0].job.case));
        Scope {
            thetas,
            main_theta,
            main,
            radii,
            textured: textured && one_point,
        }
    }
}

/// Fig. 6 (friction and clearance) and Fig. 11, where the study has what they show.
fn paper_figures(
    dir: &Path,
    name: &str,
    rows: &[Row],
    scope: &Scope,
) -> Result<Vec<PathBuf>, OutputError> {
    let mut files = Vec::new();
    if scope.textured && scope.radii.len() >= 2 {
        for (what, file) in [
            ("friction", "fig6_friction"),
            ("clearance", "fig6_clearance"),
        ] {
            let p = dir.join(format!("{name}_{file}.png"));
            fig6(&p, &scope.main, what == "friction", scope.main_theta)?;
            files.push(p);
        }
    }
    if scope.textured && scope.thetas.len() >= 2 && scope.radii.len() >= 2 {
        let p = dir.join(format!("{name}_fig11.png"));
        fig11(&p, rows, &scope.thetas)?;
        files.push(p);
    }
    Ok(files)
}

/// The summary file: the run, the compute behind it, the cases, the headline, the failures.
fn summary(
    study: &Study,
    rows: &[Row],
    main_theta: f64,
    headline: &[String],
    wall_note: &str,
) -> String {
    let mut md = String::new();
    let name = &study.name;
    let _ = writeln!(md, "# Study `{name}`: summary\n");
    if !study.description.is_empty() {
        let _ = writeln!(md, "{}\n", study.description);
    }
    let _ = writeln!(md, "This run: {wall_note}\n");
    // (An empty f64 sum is −0.0: printed "-0 s" when nothing ran.)
    let compute: f64 = rows
        .iter()
        .filter_map(|r| r.out)
        .map(|o| o.wall_time_s)
        .sum::<f64>()
        .max(0.0);
    let _ = writeln!(
        md,
        "Compute behind these results: {:.0} s of single-core simulation (sum of the cases' wall times; cases that differ only in θs share one simulation and count it each).\n",
        compute
    );
    let failed = rows.iter().filter(|r| r.reason.is_some()).count();
    let run = rows.iter().filter(|r| r.out.is_some()).count() + failed;
    let not_run = match study.jobs.len() - run {
        0 => String::new(),
        n => format!(", {n} not run (not in the cache, or stopped)"),
    };
    let _ = writeln!(
        md,
        "Cases: {run} simulated or cached ({failed} failed){not_run}; {} combinations skipped as invalid:",
        study.skipped_total()
    );
    for (rule, n) in &study.skipped {
        let _ = writeln!(md, "- {n} × {rule}");
    }
    let _ = writeln!(md, "\n## Headline (θ_s = {main_theta})\n");
    for l in headline {
        let _ = writeln!(md, "- {l}");
    }
    let failures: Vec<&Row> = rows.iter().filter(|r| r.reason.is_some()).collect();
    if !failures.is_empty() {
        let _ = writeln!(md, "\n## Failed cases ({})\n", failures.len());
        for r in failures {
            let _ = writeln!(md, "- {}", r.reason.unwrap_or_default());
        }
    }
    md
}

/// One line per figure written: what to read from it.
fn captions(files: &[PathBuf]) -> String {
    let mut md = String::new();
    for p in files {
        let Some(name) = p.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        if let Some(caption) = caption(name) {
            if md.is_empty() {
                md.push_str("\n## Figures\n\n");
            }
            let _ = writeln!(md, "- `{name}`: {caption}");
        }
    }
    md
}

/// What to read from a figure of the study's report, by its file name.
fn caption(file: &str) -> Option<&'static str> {
    let ends = |s: &str| file.ends_with(s);
    Some(if ends("_fig6_friction.png") {
        "mean friction against R, one grey curve per texture; where the lower envelope (each R's least-friction texture named at its point) runs under the untextured liner's thick line, texturing lowers friction at that R."
    } else if ends("_fig6_clearance.png") {
        "minimum clearance against R, one grey curve per texture; where the upper envelope (each R's largest-clearance texture named at its point) runs over the untextured liner's thick line, texturing thickens the film at that R."
    } else if ends("_fig11.png") {
        "the least-friction envelope and the untextured liner for each shear threshold θs of the Couette term (eq. 9): how far the gain of texturing depends on θs."
    } else if ends("_stribeck.png") {
        "each ring and texture's change of friction against the plain liner (%) over the Stribeck number: below zero the texture lowers friction at that speed and load."
    } else if ends("_oil.png") {
        "each ring and texture's change of friction against the plain liner (%) over the inlet oil film: below zero the texture lowers friction at that oil supply."
    } else {
        return None;
    })
}

/// What the study's CSV in place holds: its cases done and its cases evaluated (done or
/// failed), if there is a regular file that can be read.
pub struct InPlace {
    pub path: PathBuf,
    pub done: usize,
    pub evaluated: usize,
}

impl InPlace {
    /// Whether a report of `done` cases done and `evaluated` evaluated holds less than this
    /// one: fewer cases done, or fewer evaluated (a failure turned into "not run").
    pub fn holds_more_than(&self, done: usize, evaluated: usize) -> bool {
        done < self.done || evaluated < self.evaluated
    }
}

/// The report in place (see [`InPlace`]).
pub fn in_place(study: &Study) -> Option<InPlace> {
    let path = Path::new(&study.report.dir).join(format!("{}.csv", study.name));
    let text = crate::output::read_regular(&path)?;
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let status = r.headers().ok()?.iter().position(|h| h == "status")?;
    let (mut done, mut evaluated) = (0, 0);
    for rec in r.records().filter_map(Result::ok) {
        match rec.get(status) {
            Some("done") => {
                done += 1;
                evaluated += 1;
            }
            Some("failed") => evaluated += 1,
            _ => {}
        }
    }
    Some(InPlace {
        path,
        done,
        evaluated,
    })
}

fn write_csv(path: &Path, study: &Study, rows: &[Row]) -> Result<(), OutputError> {
    crate::output::atomically(path, |tmp| csv_rows(tmp, study, rows))
}

fn csv_rows(path: &Path, study: &Study, rows: &[Row]) -> Result<(), csv::Error> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record(CSV_COLUMNS.iter().map(|(name, _)| name))?;
    for row in rows {
        let (c, o) = (&row.job.case, row.out);
        let line = Line {
            fidelity: study.fidelity.name(),
            row,
            physical: row.job.scales.physical(
                c,
                o.map_or(f64::NAN, |o| o.f_mean),
                o.map_or(f64::NAN, |o| o.c_min),
            ),
        };
        w.write_record(CSV_COLUMNS.iter().map(|(_, cell)| cell(&line)))?;
    }
    Ok(w.flush()?)
}

/// What one row of the study's CSV is written from.
struct Line<'a> {
    fidelity: &'a str,
    row: &'a Row<'a>,
    physical: Physical,
}

impl Line<'_> {
    fn case(&self) -> &CaseSpec {
        &self.row.job.case
    }
    fn texture(&self, value: fn(&Texture) -> f64) -> String {
        num(self.case().texture.as_ref().map(value))
    }
    fn outcome(&self, value: fn(&Outcome) -> f64) -> String {
        num(self.row.out.map(value))
    }
    /// The mesh of the answer (the deep-pocket mesh where the run went on).
    fn mesh(&self) -> (usize, usize) {
        let n = &self.row.job.numerics;
        self.row.out.map_or((n.n1, n.n2), |o| o.mesh((n.n1, n.n2)))
    }
}

/// A number, or an empty cell.
fn num(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| format!("{v}"))
}

/// How a cell of the study's CSV is written.
type Cell = fn(&Line) -> String;

/// The study CSV's columns: each header with how its cell is written.
const CSV_COLUMNS: [(&str, Cell); 40] = [
    ("R", |l| format!("{}", l.case().r)),
    ("textured", |l| format!("{}", l.case().texture.is_some())),
    ("l1", |l| l.texture(|t| t.l1)),
    ("l2", |l| l.texture(|t| t.l2)),
    ("per", |l| l.texture(|t| t.per)),
    ("width", |l| l.texture(|t| t.width)),
    ("depth", |l| l.texture(|t| t.depth)),
    ("area_fraction", |l| {
        num(Some(
            l.case()
                .texture
                .as_ref()
                .map_or(0.0, Texture::area_fraction),
        ))
    }),
    ("theta_s", |l| format!("{}", l.case().theta_s)),
    ("d_oil", |l| format!("{}", l.case().d_oil)),
    ("u", |l| format!("{}", l.case().u)),
    ("w_ps", |l| format!("{}", l.case().w_ps)),
    ("mass", |l| format!("{}", l.case().mass)),
    ("e", |l| format!("{}", l.case().e)),
    ("fidelity", |l| l.fidelity.to_string()),
    ("n1", |l| format!("{}", l.mesh().0)),
    ("n2", |l| format!("{}", l.mesh().1)),
    // The step of the answer (the deep-pocket mesh's where the run went on).
    ("dt", |l| {
        let o = l.row.out.filter(|o| o.deep_mesh.is_some());
        format!("{}", o.map_or(l.row.job.numerics.dt, |o| o.dt))
    }),
    ("status", |l| {
        match (l.row.out, l.row.reason) {
            (Some(_), _) => "done",
            (None, Some(_)) => "failed",
            _ => "not run",
        }
        .into()
    }),
    ("f_mean", |l| l.outcome(|o| o.f_mean)),
    ("f_couette", |l| l.outcome(|o| o.f_couette)),
    ("f_poiseuille", |l| l.outcome(|o| o.f_poiseuille)),
    ("f_pressure", |l| l.outcome(|o| o.f_pressure)),
    ("z_mean", |l| l.outcome(|o| o.z_mean)),
    ("z_min", |l| l.outcome(|o| o.z_min)),
    ("z_max", |l| l.outcome(|o| o.z_max)),
    ("c_min", |l| l.outcome(|o| o.c_min)),
    ("f_over_plain", |l| num(l.row.f_ratio())),
    ("c_min_over_plain", |l| num(l.row.c_ratio())),
    ("periods", |l| l.outcome(|o| o.periods as f64)),
    ("steps", |l| l.outcome(|o| o.steps as f64)),
    ("wall_time_s", |l| l.outcome(|o| o.wall_time_s)),
    ("reason", |l| l.row.reason.unwrap_or_default().to_string()),
    ("ring_width", |l| format!("{}", l.case().ring_width)),
    ("stribeck", |l| format!("{}", l.physical.stribeck)),
    ("speed_m_s", |l| format!("{}", l.physical.speed_ms)),
    ("load_n_m", |l| format!("{}", l.physical.load_n_per_m)),
    ("friction_n_m", |l| {
        num(l.row.out.map(|_| l.physical.friction_n_per_m))
    }),
    ("power_w_m", |l| {
        num(l.row.out.map(|_| l.physical.power_w_per_m))
    }),
    ("outside_model", |l| {
        l.row.outside.map(|o| o.to_string()).unwrap_or_default()
    }),
];

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

fn fig6(path: &Path, rows: &[&Row], friction: bool, theta_s: f64) -> Result<(), OutputError> {
    let fam = family(rows, &|o: &Outcome| {
        if friction {
            o.f_mean
        } else {
            o.c_min
        }
    });
    let n = fam.curves.len();
    let mut series: Vec<Series> = fam
        .curves
        .iter()
        .enumerate()
        .map(|(i, c)| Series {
            name: if i == 0 {
                format!("{n} textures")
            } else {
                String::new()
            },
            points: c,
            style: Style::Faint,
            colour: 0,
        })
        .collect();
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

fn fig11(path: &Path, rows: &[Row], thetas: &[f64]) -> Result<(), OutputError> {
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

/// The largest friction reduction and clearance gain against the plain liner, and the R
/// below which no texture beats it.
fn headline(rows: &[&Row], theta_s: f64, fidelity: crate::time::Fidelity) -> Vec<String> {
    // Nothing to weigh (every textured case or its plain liner failed or was not run): no
    // conclusion, rather than "no texture beats it".
    if !rows
        .iter()
        .any(|r| r.job.case.texture.is_some() && r.f_ratio().is_some())
    {
        return vec![
            "no textured case has a result beside its untextured liner's (they failed or were not run): nothing to compare"
                .into(),
        ];
    }
    let mut out = best_against_plain(rows);
    let mut radii: Vec<f64> = rows.iter().map(|r| r.job.case.r).collect();
    radii.sort_by(f64::total_cmp);
    radii.dedup();
    type Gain<'a> = &'a dyn Fn(&Row) -> Option<f64>;
    let f_gain: Gain = &|r: &Row| r.f_ratio().map(|x| 1.0 - x);
    let c_gain: Gain = &|r: &Row| r.c_ratio().map(|x| x - 1.0);
    for (what, gain, err) in [
        ("friction", f_gain, fidelity.f_error()),
        ("clearance", c_gain, fidelity.c_error()),
    ] {
        out.push(first_r_beating(rows, &radii, what, gain, err, fidelity));
    }
    out.push(format!(
        "(friction per eq. 11 with θs = {theta_s}; the paper prints f/10)"
    ));
    out
}

/// The headline's largest friction reduction and clearance gain against the plain liner
/// (or, when no texture gains, the least loss).
fn best_against_plain(rows: &[&Row]) -> Vec<String> {
    let mut out = Vec::new();
    // The best within the hydrodynamic model: a flagged case is not a prediction.
    let best = |ratio: &dyn Fn(&Row) -> Option<f64>, lower: bool| {
        rows.iter()
            .filter(|r| r.job.case.texture.is_some() && r.outside.is_none() && !r.plain_outside)
            .filter_map(|r| Some((ratio(r)?, *r)))
            .filter(|(x, _)| x.is_finite())
            .min_by(|a, b| {
                if lower {
                    a.0.total_cmp(&b.0)
                } else {
                    b.0.total_cmp(&a.0)
                }
            })
    };
    if let Some((x, r)) = best(&|r: &Row| r.f_ratio(), true) {
        out.push(format!(
            "{}: {:.1} % ({}, f = {:.5} vs {:.5})",
            if x < 1.0 {
                "largest friction reduction against the untextured liner (within the hydrodynamic model)"
            } else {
                "no texture lowers friction; the least increase"
            },
            100.0 * (1.0 - x).abs(),
            r.job.case.label(),
            r.out.map_or(f64::NAN, |o| o.f_mean),
            r.plain.map_or(f64::NAN, |o| o.f_mean)
        ));
    }
    if let Some((x, r)) = best(&|r: &Row| r.c_ratio(), false) {
        out.push(format!(
            "{}: {:.1} % ({}, C_min = {:.4} vs {:.4} µm)",
            if x > 1.0 {
                "largest minimum-clearance increase against the untextured liner (within the hydrodynamic model)"
            } else {
                "no texture raises the minimum clearance; the least decrease"
            },
            100.0 * (x - 1.0).abs(),
            r.job.case.label(),
            r.out.map_or(f64::NAN, |o| o.c_min),
            r.plain.map_or(f64::NAN, |o| o.c_min)
        ));
    }
    out
}

/// The headline's line on the first R (of `radii`, ascending) where some texture beats the
/// plain liner in `what`. "Beats" means a `gain` over the fidelity's measured error `err`;
/// smaller gains are reported but not counted (they are not resolved).
fn first_r_beating(
    rows: &[&Row],
    radii: &[f64],
    what: &str,
    gain: &dyn Fn(&Row) -> Option<f64>,
    err: f64,
    fidelity: crate::time::Fidelity,
) -> String {
    let textured = || rows.iter().filter(|r| r.job.case.texture.is_some());
    let first = radii
        .iter()
        .copied()
        .find(|&rr| textured().any(|r| r.job.case.r == rr && gain(r).is_some_and(|g| g > err)));
    let best_below = textured()
        .filter(|r| first.is_none_or(|f| r.job.case.r < f))
        .filter_map(|r| Some((gain(r)?, r)))
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let margin = format!(
        "by more than the {} tier's error ({:.2} %)",
        fidelity.name(),
        100.0 * err
    );
    let mut line = match first {
        Some(rr) if rr == radii[0] => format!(
            "{what}: some texture beats the untextured liner {margin} already at the smallest R = {rr}"
        ),
        Some(rr) => format!(
            "{what}: no texture beats the untextured liner {margin} below R = {rr} (the first R where one does)"
        ),
        None => format!("{what}: no texture beats the untextured liner {margin} at any R"),
    };
    if let (Some((g, r)), true) = (best_below, first != Some(radii[0])) {
        line += &format!(
            "; {} the largest gain is {:+.2} % ({})",
            if first.is_some() {
                "below it"
            } else {
                "at best"
            },
            100.0 * g,
            r.job.case.label()
        );
    }
    line
}

/// (f̄/f̄_plain, C_min/C_min,plain, outside the model) of one texture by R (as f64 bits).
type RatiosByR = BTreeMap<u64, (f64, f64, bool)>;

/// Each texture (by curve key) with its ratios to the plain liner by R.
type ByTexture = BTreeMap<String, (Texture, RatiosByR)>;

/// Table 1: the best textures for small and large R, ranked by the class mean of the ratio
/// to the plain liner; and the best texture at each R.
fn table1(study: &Study, rows: &[&Row], radii: &[f64]) -> String {
    let (small, large) = (study.report.small_r_max, study.report.large_r_min);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Best textures of study `{}` (Table 1 of the paper)\n",
        study.name
    );
    let _ = writeln!(
        md,
        "Ranking rule: for each texture, the mean over the rings of a class of the ratio of its outcome to the untextured liner's on the same ring — f̄/f̄_plain (lower is better) for friction, C_min/C_min,plain (higher is better) for clearance. Small R: R ≤ {small} cm; large R: R ≥ {large} cm. A texture enters a class only if every ring of the class has a result for it. Fidelity `{}` (see {}.csv for the mesh of each case). Ratios below 1 (friction) or above 1 (clearance) beat the plain liner.\n",
        study.fidelity.name(),
        study.name
    );
    let classes: [(&str, Vec<f64>); 2] = [
        (
            "Small R",
            radii.iter().copied().filter(|&r| r <= small).collect(),
        ),
        (
            "Large R",
            radii.iter().copied().filter(|&r| r >= large).collect(),
        ),
    ];
    let by_tex = ratios_by_texture(rows);
    for (title, friction) in [
        ("(a) Best textures in terms of friction", true),
        ("(b) Best textures in terms of clearance", false),
    ] {
        let _ = writeln!(md, "## {title}\n");
        for (class, rs) in &classes {
            if !rs.is_empty() {
                md += &class_ranking(&by_tex, class, rs, friction);
            }
        }
    }
    md += &best_at_each_r(&by_tex, radii);
    if !md.contains(" ‡") {
        return md;
    }
    let _ = writeln!(
        md,
        "\n‡ at least one case behind the value is outside the hydrodynamic model: its minimum clearance is below {:.2} µm ({} × a composite roughness of {} µm, docs/model.md §9), where the surfaces touch; such values are not predictions. The CSV says which case and why (column outside_model).",
        study.validity.clearance_limit_um(),
        crate::model::operating::FULL_FILM_LAMBDA,
        study.validity.roughness_um
    );
    md
}

/// The ratios to the plain liner of each textured row that has both.
fn ratios_by_texture(rows: &[&Row]) -> ByTexture {
    let mut by_tex = ByTexture::new();
    for r in rows {
        let (Some(t), Some(fr), Some(cr)) = (&r.job.case.texture, r.f_ratio(), r.c_ratio()) else {
            continue;
        };
        by_tex
            .entry(curve_key(&r.job.case))
            .or_insert_with(|| (t.clone(), BTreeMap::new()))
            .1
            .insert(r.job.case.r.to_bits(), (fr, cr, r.outside.is_some()));
    }
    by_tex
}

/// One class of Table 1: its five best textures by the mean ratio over the class's radii
/// `rs` (friction: lowest first; clearance: highest first).
fn class_ranking(by_tex: &ByTexture, class: &str, rs: &[f64], friction: bool) -> String {
    let mut md = String::new();
    let mut ranked: Vec<(f64, &Texture, bool)> = by_tex
        .values()
        .filter_map(|(t, m)| {
            let v: Option<Vec<&(f64, f64, bool)>> =
                rs.iter().map(|r| m.get(&r.to_bits())).collect();
            let v = v?;
            let x = v.iter().map(|p| if friction { p.0 } else { p.1 });
            let flagged = v.iter().any(|p| p.2);
            Some((x.sum::<f64>() / v.len() as f64, t, flagged))
        })
        .collect();
    if friction {
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    } else {
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    }
    let rlist: Vec<String> = rs.iter().map(|r| format!("{r}")).collect();
    let _ = writeln!(
        md,
        "{class} (R = {}; {} textures ranked)\n\n| # | l1 = l2 | per | depth | mean ratio |\n|---|---|---|---|---|",
        rlist.join(", "),
        ranked.len()
    );
    for (i, (m, t, flagged)) in ranked.iter().take(5).enumerate() {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.4}{} |",
            i + 1,
            t.l1,
            t.per,
            t.depth,
            m,
            if *flagged { " ‡" } else { "" }
        );
    }
    let _ = writeln!(md);
    md
}

/// The last part of Table 1: the least-friction and the largest-clearance texture at each R.
fn best_at_each_r(by_tex: &ByTexture, radii: &[f64]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Best texture at each R\n\n| R | least friction | f̄/f̄_plain | largest clearance | C_min/C_min,plain |\n|---|---|---|---|---|"
    );
    for &rr in radii {
        let at: Vec<(&Texture, &(f64, f64, bool))> = by_tex
            .values()
            .filter_map(|(t, m)| m.get(&rr.to_bits()).map(|p| (t, p)))
            .collect();
        let bf = at.iter().min_by(|a, b| a.1 .0.total_cmp(&b.1 .0));
        let bc = at.iter().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        let mark = |p: &(f64, f64, bool)| if p.2 { " ‡" } else { "" };
        if let (Some(bf), Some(bc)) = (bf, bc) {
            let _ = writeln!(
                md,
                "| {rr} | {} | {:.4}{} | {} | {:.4}{} |",
                texture_label(bf.0),
                bf.1 .0,
                mark(bf.1),
                texture_label(bc.0),
                bc.1 .1,
                mark(bc.1)
            );
        }
    }
    md
}

#[cfg(test)]
mod in_place_tests {
    use super::InPlace;

    #[test]
    fn a_report_with_fewer_cases_done_or_evaluated_holds_less() {
        let before = InPlace {
            path: "r.csv".into(),
            done: 10,
            evaluated: 10,
        };
        assert!(!before.holds_more_than(10, 10));
        assert!(
            before.holds_more_than(5, 10),
            "failures in place of results"
        );
        assert!(before.holds_more_than(10, 9));
        assert!(before.holds_more_than(0, 0));
        assert!(!before.holds_more_than(12, 12));
    }
}
