//! The report of a study in the paper's form (§3.4): one CSV row per case, Fig. 6 (friction
//! and minimum clearance against R, one thin curve per texture, their envelopes, the plain
//! liner thick), Fig. 11 (lower friction envelopes per θ_s) and Table 1 (best textures for
//! small and large R), plus the headline figures.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::Outside;
use crate::output::OutputError;
use crate::study::file::{Job, Study};
use crate::study::operating_figures::{figures, Point};
use crate::study::sweep::{CaseFailure, CaseResult};
use crate::time::{AnswerError, MissingUncertainty, Outcome};

mod charts;
mod csv_rows;
mod headline;

use charts::{fig11, fig6};
use csv_rows::write_csv;
use headline::{headline, ranking_csv, table1};

/// A case with its outcome and the plain liner's outcome for the same ring and operating
/// point (when the study has it).
struct Row<'a> {
    job: &'a Job,
    out: Option<&'a Outcome>,
    /// How well `out` is known (the tier's error, or its deep-pocket mesh uncertainty).
    error: Option<AnswerError>,
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
    #[error(transparent)]
    Uncertainty(#[from] MissingUncertainty),
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
    let rows = rows(study, results)?;
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
        let p = dir.join(format!("{name}_ranking.csv"));
        crate::output::write(&p, ranking_csv(study, &scope.main, &scope.radii))?;
        files.push(p);
    }
    Ok(ReportFiles { files, headline })
}

/// Each case of the study with its result and its plain liner's; an answer whose pockets end
/// deeper than the tiers resolve and that carries no mesh uncertainty is refused.
fn rows<'a>(
    study: &'a Study,
    results: &'a [CaseResult],
) -> Result<Vec<Row<'a>>, MissingUncertainty> {
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
        .map(|(job, r)| {
            let out = r.as_ref().and_then(|r| r.as_ref().ok());
            let tier = (study.fidelity.f_error(), study.fidelity.c_error());
            let error = out.map(|o| o.error(&job.case, tier)).transpose()?;
            Ok(Row {
                job,
                out,
                error,
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

/// Where a study's table (one row a case) is written: `<report dir>/<name>.csv`.
pub fn table_path(study: &Study) -> std::path::PathBuf {
    Path::new(&study.report.dir).join(format!("{}.csv", study.name))
}

/// The report in place (see [`InPlace`]).
pub fn in_place(study: &Study) -> Option<InPlace> {
    let path = table_path(study);
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
