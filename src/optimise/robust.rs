//! A texture for a ring that wears: the face radius R grows as the ring wears in, so a liner
//! texture should stay good over a range of R. For each R the usual optimisation
//! (`driver::optimise`), then a robust design that minimises the worst friction ratio to the
//! plain liner over the range, max over R of f̄(R)/f̄_plain(R), under the same constraints.
//!
//! The robust design is chosen at the reported fidelity among the robust search's best and
//! every R's own optimum, so its worst ratio is never above that of an R's optimum.

use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;
use std::time::Instant;

use super::design::Report;
use super::design_report::{csv_bytes, Column};
use super::driver::{evaluator, optimise, Settings};
use super::error::OptimiseError;
use super::goal::FAILED_COST;
use super::search::{swarm_and_refine, Evaluator, Objective, SwarmSettings};
use super::space::Space;
use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::Outside;
use crate::plot::{self, Chart, Scale, Series, Style};
use crate::study::cache::Cache;
use crate::time::Outcome;

/// One candidate design over every R of the range.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// "robust search", or "optimum at R = …".
    pub origin: String,
    pub texture: Texture,
    /// Per R (in the report's order): f̄, and f̄ over the plain liner's (NaN where it failed,
    /// written as null).
    #[serde(serialize_with = "crate::finite::absent_each")]
    pub f_mean: Vec<f64>,
    #[serde(serialize_with = "crate::finite::absent_each")]
    pub ratio: Vec<f64>,
    /// Worst and mean ratio over the range: +∞ and NaN where a run failed.
    #[serde(serialize_with = "crate::finite::unbounded")]
    pub worst: f64,
    #[serde(serialize_with = "crate::finite::absent")]
    pub mean: f64,
    /// Per R: why the design is outside the hydrodynamic model there, if it is.
    pub outside_model: Vec<Option<Outside>>,
}

/// One R of the range: the plain liner, R's own optimum and the robust design.
#[derive(Clone, Debug, Serialize)]
pub struct AtRadius {
    pub r: f64,
    pub plain_f_mean: f64,
    pub optimum: Option<Texture>,
    pub optimum_f_mean: f64,
    pub robust_f_mean: f64,
    /// How much friction the robust design gives up against R's own optimum (%).
    pub robust_gives_up_pct: f64,
}

/// The result of `optimise` over a range of radii.
#[derive(Clone, Debug, Serialize)]
pub struct RobustReport {
    /// Stem of the files, e.g. `robust_R5-12.8`.
    pub name: String,
    pub radii: Vec<f64>,
    pub search_fidelity: String,
    pub report_fidelity: String,
    pub robust: Candidate,
    pub at_radius: Vec<AtRadius>,
    /// Every candidate at the reported fidelity (the robust design among them).
    pub candidates: Vec<Candidate>,
    pub verdict: String,
    pub wall_time_s: f64,
}

/// What the robust search minimises: the worst friction ratio over the range.
struct WorstRatio<'a> {
    space: &'a Space,
    evals: Vec<Evaluator<'a>>,
    plains: Vec<Outcome>,
}

impl Objective for WorstRatio<'_> {
    fn space(&self) -> &Space {
        self.space
    }

    fn costs(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        let runs = outcomes(&self.evals, designs)?;
        Ok(runs
            .iter()
            .map(|r| worst(&ratios(r, &self.plains)).min(FAILED_COST))
            .collect())
    }
}

/// The outcome of each design at each R (None where a run failed): one batch per R.
fn outcomes(
    evals: &[Evaluator],
    designs: &[Texture],
) -> Result<Vec<Vec<Option<Outcome>>>, OptimiseError> {
    let mut out = vec![Vec::with_capacity(evals.len()); designs.len()];
    let batch: Vec<Option<Texture>> = designs.iter().cloned().map(Some).collect();
    for ev in evals {
        for (row, o) in out.iter_mut().zip(ev.evaluate(&batch)?) {
            row.push(o.ok());
        }
    }
    Ok(out)
}

/// f̄/f̄_plain at each R (NaN where the run failed).
fn ratios(runs: &[Option<Outcome>], plains: &[Outcome]) -> Vec<f64> {
    runs.iter()
        .zip(plains)
        .map(|(o, p)| o.as_ref().map_or(f64::NAN, |o| o.f_mean / p.f_mean))
        .collect()
}

/// The worst ratio; a failed run (NaN) is worst of all.
fn worst(r: &[f64]) -> f64 {
    r.iter()
        .map(|x| if x.is_nan() { f64::INFINITY } else { *x })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Optimises at each R of `per_r` (one `Settings` per radius, alike but for the ring), then
/// searches the robust design and reports; files under the first settings' `out_dir`.
pub fn robust(
    per_r: &[Settings],
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<RobustReport, OptimiseError> {
    let t0 = Instant::now();
    let first = per_r.first().ok_or(OptimiseError::Nothing("radius"))?;
    let mut reports = Vec::new();
    for (i, s) in per_r.iter().enumerate() {
        if first.search.progress {
            eprintln!(
                "== R = {} cm ({} of {}) ==",
                crate::time::short(s.base.r),
                i + 1,
                per_r.len()
            );
        }
        reports.push(optimise(s, cache, stop)?);
    }
    if first.search.progress {
        eprintln!("== robust design over R = {:?} cm ==", radii(per_r));
    }
    let optima: Vec<Texture> = reports
        .iter()
        .filter_map(|r| r.best_friction.texture.clone())
        .collect();
    let found = search_robust(per_r, cache, stop, &optima)?;
    let mut designs: Vec<(String, Texture)> = vec![("robust search".into(), found)];
    for rep in &reports {
        if let Some(t) = &rep.best_friction.texture {
            let origin = format!("optimum at R = {}", rep.r);
            match designs.iter_mut().find(|(_, d)| d == t) {
                Some((o, _)) => *o = format!("{o} = {origin}"),
                None => designs.push((origin, t.clone())),
            }
        }
    }
    let candidates = confirm(per_r, cache, stop, &designs)?;
    let best = candidates
        .iter()
        .min_by(|a, b| a.worst.total_cmp(&b.worst).then(a.mean.total_cmp(&b.mean)))
        .cloned()
        .ok_or(OptimiseError::Nothing("robust candidate"))?;
    let report = assemble(per_r, &reports, best, candidates, t0);
    if let Some(dir) = &first.search.out_dir {
        write(dir, &report)?;
    }
    Ok(report)
}

fn radii(per_r: &[Settings]) -> Vec<f64> {
    per_r.iter().map(|s| s.base.r).collect()
}

/// The robust search at the search fidelity: a swarm on the worst ratio; the best of its
/// answer and the radii's own optima is then polished by a compass search. Why the optima:
/// the good designs fill a thin corner of the space (close-packed pockets), which a small
/// swarm may miss on a max of ratios while each single-R search found it.
fn search_robust(
    per_r: &[Settings],
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
    optima: &[Texture],
) -> Result<Texture, OptimiseError> {
    let s = &per_r[0].search;
    let evals: Vec<Evaluator> = per_r
        .iter()
        .map(|x| evaluator(x, x.search.search_fidelity, cache, stop))
        .collect();
    let plains = evals
        .iter()
        .map(Evaluator::plain)
        .collect::<Result<Vec<_>, _>>()?;
    let problem = WorstRatio {
        space: &s.space,
        evals,
        plains,
    };
    // A seed of its own: the robust swarm explores other points than the single-R ones.
    let settings = SwarmSettings {
        seed: s.swarm.seed + 1000,
        ..s.swarm
    };
    let starts: Vec<Vec<f64>> = optima.iter().map(|t| s.space.encode(t)).collect();
    let (u, c) = swarm_and_refine(&problem, settings, &starts)?;
    if s.progress {
        eprintln!(
            "  robust search: worst ratio {c:.4} at {}",
            s.search_fidelity.name()
        );
    }
    Ok(s.space.decode(&u))
}

/// Each candidate at every R, at the reported fidelity.
fn confirm(
    per_r: &[Settings],
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
    designs: &[(String, Texture)],
) -> Result<Vec<Candidate>, OptimiseError> {
    let evals: Vec<Evaluator> = per_r
        .iter()
        .map(|x| evaluator(x, x.search.report_fidelity, cache, stop))
        .collect();
    let plains = evals
        .iter()
        .map(Evaluator::plain)
        .collect::<Result<Vec<_>, _>>()?;
    let textures: Vec<Texture> = designs.iter().map(|(_, t)| t.clone()).collect();
    let runs = outcomes(&evals, &textures)?;
    Ok(designs
        .iter()
        .zip(runs)
        .map(|((origin, t), runs)| {
            let ratio = ratios(&runs, &plains);
            let outside_model = per_r
                .iter()
                .zip(&runs)
                .map(|(s, o)| {
                    let case = CaseSpec {
                        texture: Some(t.clone()),
                        ..s.base.clone()
                    };
                    match o {
                        Some(o) => s.search.validity.outside(&case, o.c_min),
                        None => Some(Outside::NoOutcome),
                    }
                })
                .collect();
            Candidate {
                origin: origin.clone(),
                texture: t.clone(),
                f_mean: runs
                    .iter()
                    .map(|o| o.as_ref().map_or(f64::NAN, |o| o.f_mean))
                    .collect(),
                worst: worst(&ratio),
                mean: ratio.iter().sum::<f64>() / ratio.len() as f64,
                ratio,
                outside_model,
            }
        })
        .collect())
}

fn assemble(
    per_r: &[Settings],
    reports: &[Report],
    robust: Candidate,
    candidates: Vec<Candidate>,
    t0: Instant,
) -> RobustReport {
    let radii = radii(per_r);
    let at_radius: Vec<AtRadius> = reports
        .iter()
        .enumerate()
        .map(|(i, rep)| AtRadius {
            r: rep.r,
            plain_f_mean: rep.plain.f_mean,
            optimum: rep.best_friction.texture.clone(),
            optimum_f_mean: rep.best_friction.f_mean,
            robust_f_mean: robust.f_mean[i],
            robust_gives_up_pct: 100.0 * (robust.f_mean[i] / rep.best_friction.f_mean - 1.0),
        })
        .collect();
    let verdict = if robust.worst < 1.0 {
        format!(
            "the robust design lowers friction at every R of the range: worst ratio to the plain liner {:.4}, mean {:.4}",
            robust.worst, robust.mean
        )
    } else {
        format!(
            "no texture lowers friction at every R of the range: the robust design's worst ratio to the plain liner is {:.4} (mean {:.4}); the plain liner is the robust choice",
            robust.worst, robust.mean
        )
    };
    let (lo, hi) = (radii[0], radii[radii.len() - 1]);
    RobustReport {
        name: format!("robust_R{lo}-{hi}"),
        radii,
        search_fidelity: per_r[0].search.search_fidelity.name().into(),
        report_fidelity: per_r[0].search.report_fidelity.name().into(),
        robust,
        at_radius,
        candidates,
        verdict,
        wall_time_s: t0.elapsed().as_secs_f64(),
    }
}

/// The terminal table (also the Markdown file): per R, and the candidates.
pub fn table(r: &RobustReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "texopt optimise over R = {:?} cm: reported at fidelity {} (searched at {}); f̄ per eq. (11)\n",
        r.radii, r.report_fidelity, r.search_fidelity
    );
    let _ = writeln!(s, "robust design: {}\n", r.robust.texture.rounded_label());
    let _ = writeln!(
        s,
        "| R (cm) | plain f̄ | own optimum | its f̄ | robust f̄ | robust / plain | robust gives up |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (i, a) in r.at_radius.iter().enumerate() {
        let flag = if r.robust.outside_model[i].is_some() {
            " ‡"
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "| {} | {:.5} | {} | {:.5} | {:.5}{flag} | {:.4} | {:+.2} % |",
            a.r,
            a.plain_f_mean,
            a.optimum
                .as_ref()
                .map_or("plain liner".into(), Texture::rounded_label),
            a.optimum_f_mean,
            a.robust_f_mean,
            r.robust.ratio[i],
            a.robust_gives_up_pct
        );
    }
    let _ = writeln!(s, "\n| candidate | texture | worst ratio | mean ratio |");
    let _ = writeln!(s, "|---|---|---|---|");
    for c in &r.candidates {
        let _ = writeln!(
            s,
            "| {}{} | {} | {:.4} | {:.4} |",
            c.origin,
            if c.texture == r.robust.texture {
                " (robust)"
            } else {
                ""
            },
            c.texture.rounded_label(),
            c.worst,
            c.mean
        );
    }
    let _ = writeln!(s, "\n{}", r.verdict);
    if let Some(why) = r.robust.outside_model.iter().flatten().next() {
        let _ = writeln!(
            s,
            "‡ outside the hydrodynamic model, not a prediction: {why}"
        );
    }
    let _ = writeln!(
        s,
        "{:.1} s for this run (evaluations found in the cache cost nothing)",
        r.wall_time_s
    );
    s
}

/// JSON, CSV (every candidate at every R), the table as Markdown, and f̄ against R.
fn write(dir: &Path, r: &RobustReport) -> Result<(), OptimiseError> {
    crate::finite::check(r)?;
    let stem = dir.join(&r.name);
    let path = |ext: &str| PathBuf::from(format!("{}.{ext}", stem.display()));
    let json = serde_json::to_string_pretty(r).map_err(OptimiseError::Json)?;
    crate::output::write(&path("json"), json)?;
    crate::output::write(&path("md"), format!("# {}\n\n{}", r.name, table(r)))?;
    let lines: Vec<AtOneRadius> = r
        .candidates
        .iter()
        .flat_map(|c| (0..r.radii.len()).map(move |i| AtOneRadius { r, c, i }))
        .collect();
    crate::output::write(&path("csv"), csv_bytes(&columns(), &lines)?)?;
    plot_f_against_r(&path("png"), r)
}

/// A line of the CSV: candidate `c` at the `i`-th radius of `r`.
struct AtOneRadius<'a> {
    r: &'a RobustReport,
    c: &'a Candidate,
    i: usize,
}

/// The CSV's columns, named once: each header with how its cell is written.
fn columns<'a>() -> [Column<AtOneRadius<'a>>; 11] {
    [
        ("candidate", |x| x.c.origin.clone()),
        ("robust", |x| {
            (x.c.texture == x.r.robust.texture).to_string()
        }),
        ("l1", |x| x.c.texture.l1.to_string()),
        ("l2", |x| x.c.texture.l2.to_string()),
        ("per", |x| x.c.texture.per.to_string()),
        ("width", |x| x.c.texture.width.to_string()),
        ("depth", |x| x.c.texture.depth.to_string()),
        ("R", |x| x.r.radii[x.i].to_string()),
        ("f_mean", |x| x.c.f_mean[x.i].to_string()),
        ("f_over_plain", |x| x.c.ratio[x.i].to_string()),
        ("outside_model", |x| {
            x.c.outside_model[x.i]
                .map(|o| o.to_string())
                .unwrap_or_default()
        }),
    ]
}

/// f̄ against R: the plain liner, the robust design, each R's own optimum over the range
/// (faint) and at its own R (rings).
fn plot_f_against_r(path: &Path, r: &RobustReport) -> Result<(), OptimiseError> {
    let plain: Vec<(f64, f64)> = r.at_radius.iter().map(|a| (a.r, a.plain_f_mean)).collect();
    let own: Vec<(f64, f64)> = r
        .at_radius
        .iter()
        .map(|a| (a.r, a.optimum_f_mean))
        .collect();
    let curve = |c: &Candidate| -> Vec<(f64, f64)> {
        r.radii
            .iter()
            .copied()
            .zip(c.f_mean.iter().copied())
            .collect()
    };
    let robust = curve(&r.robust);
    let others: Vec<Vec<(f64, f64)>> = r
        .candidates
        .iter()
        .filter(|c| c.texture != r.robust.texture)
        .map(curve)
        .collect();
    let outside: Vec<(f64, f64)> = robust
        .iter()
        .zip(&r.robust.outside_model)
        .filter(|(_, o)| o.is_some())
        .map(|(p, _)| *p)
        .collect();
    let mut series = Series::faint_family(&others, "each R's optimum, over the range".into());
    series.push(Series {
        name: "each R's own optimum".into(),
        points: &own,
        style: Style::Rings,
        colour: 2,
    });
    series.push(Series {
        name: "robust design".into(),
        points: &robust,
        style: Style::Line,
        colour: 0,
    });
    series.push(Series {
        name: "plain liner".into(),
        points: &plain,
        style: Style::Thick,
        colour: 1,
    });
    if !outside.is_empty() {
        series.push(Series {
            name: "outside the hydrodynamic model".into(),
            points: &outside,
            style: Style::Rings,
            colour: 3,
        });
    }
    plot::xy(
        path,
        &Chart {
            title: &format!(
                "Mean friction against ring radius: robust design over R = {}..{} cm",
                r.radii[0],
                r.radii[r.radii.len() - 1]
            ),
            x_label: "ring face radius R (cm)",
            y_label: "mean friction coefficient f (eq. 11)",
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
        },
        &series,
    )
    .map_err(OptimiseError::Output)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_run_is_the_worst_ratio() {
        assert_eq!(worst(&[0.9, 0.95]), 0.95);
        assert_eq!(worst(&[0.9, f64::NAN]), f64::INFINITY);
    }
}
