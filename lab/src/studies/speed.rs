//! Speed against accuracy (Case I and Case III): error of f̄ against wall time per case over
//! meshes, time steps, periodicity tolerances and solvers: `texopt-lab speed`.
//!
//! `run CASE N1xN2 DT [PERIODIC_TOL] [SOLVER] [APPROACH_N2]` appends one run to
//! results/speed/runs.jsonl (`finer-run …` to results/speed/finer.jsonl, the 2048-cell
//! references); `report` writes results/speed/speed.{md,csv,png} with the Pareto-optimal
//! settings marked, the Case I runs of results/convergence/ included; `finer` writes
//! results/speed/speed_finer.md, the tiers against the 2048-cell references. CASE is a
//! benchmark case (case-I, case-III, conformal-R51.2).

use std::fs;
use std::io::Write;
use std::ops::RangeInclusive;
use std::path::Path;
use texopt::plot::{self, Chart, Scale, Series, Style};
use texopt::study::bench::cases;
use texopt::time::{Fidelity, Numerics};

use super::{convergence_runs, run_case, RunRecord as Run};
use crate::solvers::Solver;

const RUNS: &str = "results/speed/runs.jsonl";
/// The speed study's meshes along x1 (the chart's points, 1024×64 the finest); the 2048-cell
/// runs are its references (results/speed/finer.jsonl, results/convergence/).
const STUDY_N1: RangeInclusive<usize> = 0..=1024;
/// Finer references (2048 cells along x1, dt = 1e-4), kept apart from the study's runs.
const FINER: &str = "results/speed/finer.jsonl";

fn run(args: &[String], out_path: &str) -> Result<(), String> {
    let name = &args[0];
    let (a, b) = args[1].split_once('x').ok_or("mesh must be N1xN2")?;
    let mut solver = Solver::Direct;
    let mut num = Numerics {
        n1: a.parse().map_err(|_| "bad N1")?,
        n2: b.parse().map_err(|_| "bad N2")?,
        dt: args[2].parse().map_err(|_| "bad dt")?,
        ..Numerics::default()
    };
    if let Some(t) = args.get(3) {
        num.periodic_tol = t.parse().map_err(|_| "bad periodic tolerance")?;
    }
    if let Some(m) = args.get(4) {
        solver = Solver::parse(m)?;
    }
    if let Some(a) = args.get(5) {
        num.approach_n2 = Some(a.parse().map_err(|_| "bad approach N2")?);
    }
    let all = cases();
    let c = all
        .iter()
        .find(|c| c.name == name)
        .ok_or(format!("no case {name}"))?;
    num.validate(&c.case).map_err(|e| e.to_string())?;
    let out = run_case(&c.case, &num, solver, &mut |_| {}, &mut |_| {})?.outcome;
    println!(
        "{name} {}x{} dt {:e} tol {:e} {}: f {:.6} C_min {:.5} {:.2} s",
        num.n1,
        num.n2,
        num.dt,
        num.periodic_tol,
        solver.name(),
        out.f_mean,
        out.c_min,
        out.wall_time_s
    );
    fs::create_dir_all("results/speed").map_err(|e| e.to_string())?;
    let mut f = fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(out_path)
        .map_err(|e| e.to_string())?;
    let line = serde_json::to_string(&Run {
        case: name.clone(),
        numerics: num,
        solver,
        outcome: out,
    })
    .unwrap();
    // One write per line: the two cases run at once append to the same file.
    f.write_all(format!("{line}\n").as_bytes())
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// The fidelity tier a run stands for: same mesh, dt and solver, and of the case's runs with
/// those, the periodic tolerance closest to the tier's (the screening tiers moved to 1e-4
/// after this study ran most settings at 1e-5).
fn tier_name(r: &Run, case_runs: &[&Run]) -> Option<&'static str> {
    let n = &r.numerics;
    if r.solver != Solver::Direct {
        return None;
    }
    let same = |a: &Numerics, b: &Numerics| {
        (a.n1, a.n2, a.dt, a.approach_n2) == (b.n1, b.n2, b.dt, b.approach_n2)
    };
    let distance = |a: f64, b: f64| (a.ln() - b.ln()).abs();
    Fidelity::ALL
        .iter()
        .find(|f| {
            let t = f.numerics();
            same(&t, n)
                && case_runs
                    .iter()
                    .filter(|r| r.solver == Solver::Direct && same(&r.numerics, &t))
                    .map(|r| r.numerics.periodic_tol)
                    .min_by(|a, b| {
                        distance(*a, t.periodic_tol)
                            .total_cmp(&distance(*b, t.periodic_tol))
                            .then(a.total_cmp(b))
                    })
                    == Some(n.periodic_tol)
        })
        .map(|f| f.name())
}

fn setting(r: &Run) -> String {
    let n = &r.numerics;
    format!(
        "{}x{} dt={:.1e} ptol={:.0e} {}{}",
        n.n1,
        n.n2,
        n.dt,
        n.periodic_tol,
        r.solver.name(),
        n.approach_n2
            .map_or(String::new(), |a| format!(" approach N2={a}"))
    )
}

/// The runs of a JSON-lines file, plus the Case I runs of results/convergence/ with N1 in
/// `convergence_n1` (the convergence study runs Case I on the tier meshes up to 1024×64, and
/// at 2048×128, a finer reference).
fn load_runs(
    path: &str,
    convergence_n1: Option<RangeInclusive<usize>>,
) -> Result<Vec<Run>, String> {
    let mut runs = Run::load(path)?;
    if let Some(n1s) = convergence_n1 {
        for r in convergence_runs()? {
            let already = runs
                .iter()
                .any(|q| q.case == "case-I" && q.numerics == r.numerics && q.solver == r.solver);
            if !already && n1s.contains(&r.numerics.n1) {
                runs.push(r);
            }
        }
    }
    Ok(runs)
}

/// One row of the table against a reference's f̄ and C_min.
fn row(r: &Run, name: &str, fr: f64, cr: f64) -> String {
    let (f, c) = (r.outcome.f_mean, r.outcome.c_min);
    format!(
        "| {} | {name} | {f:.6} | {:.3} % | {c:.5} | {:.3} % | {:.1} |\n",
        setting(r),
        100.0 * (f - fr).abs() / fr,
        100.0 * (c - cr).abs() / cr,
        r.outcome.wall_time_s
    )
}

/// The fidelity tiers and the old reference against the finest 2048-cell, dt = 1e-4 run of
/// each case: results/speed_finer.md.
fn finer() -> Result<(), String> {
    let runs = load_runs(RUNS, Some(STUDY_N1))?;
    let finer = load_runs(FINER, Some(2048..=usize::MAX))?;
    let mut md = String::from("# Fidelity tiers against a finer reference\n\nReproduce: `bash studies/speed.sh finer` (the 2048-cell runs of each case; Case I at 2048×128 is the convergence study's finest run), then `texopt-lab speed finer`. Reference: the finest run of each case at 2048 cells along x1 and dt = 1e-4 (2048×128 where it was run, with the p–θ multigrid after a 2048×8 approach: the band LU would need ≈ 1.5 s a step). A row `(finer, coarser N2)` is the same case at 2048 cells with fewer cells across: its difference from the reference is what refining N2 alone changes there. Rows: the tiers as the speed study ran them with their own periodic tolerance and coarse approach, and 1024×64, the speed study's finest setting. Errors relative to the reference. The wall times of the 2048-cell runs are of one core beside other work and of the solver that ran them: not comparable with the tiers'.\n");
    for case in ["case-I", "case-III", "conformal-R51.2"] {
        // The finest run of the case is the reference; coarser finer runs are rows.
        let Some(reference) = finer
            .iter()
            .filter(|r| r.case == case)
            .max_by_key(|r| (r.numerics.n1 * r.numerics.n2, r.numerics.n2))
        else {
            continue;
        };
        let (fr, cr) = (reference.outcome.f_mean, reference.outcome.c_min);
        md += &format!(
            "\n## {case} (reference {}: f̄ = {fr:.6}, C_min = {cr:.5} µm, {} steps, {:.0} s)\n\n| setting | tier | f̄ | err f̄ | C_min (µm) | err C_min | wall (s) |\n|---|---|---|---|---|---|---|\n",
            setting(reference),
            reference.outcome.steps,
            reference.outcome.wall_time_s
        );
        let tiers = Fidelity::ALL.iter().map(|f| (f.name(), f.numerics()));
        let old_reference = (
            "(1024×64)",
            Numerics {
                n1: 1024,
                n2: 64,
                dt: 2e-4,
                ..Numerics::default()
            },
        );
        for (name, t) in tiers.chain(std::iter::once(old_reference)) {
            // The study's run of the tier as the product runs it (tolerance, coarse
            // approach); else its run of this mesh and dt at the tightest tolerance.
            let same_mesh = |r: &&Run| {
                r.case == case
                    && (r.numerics.n1, r.numerics.n2, r.numerics.dt) == (t.n1, t.n2, t.dt)
                    && r.solver == Solver::Direct
            };
            let exact = runs.iter().filter(same_mesh).find(|r| {
                (r.numerics.periodic_tol, r.numerics.approach_n2) == (t.periodic_tol, t.approach_n2)
            });
            let Some(r) = exact.or_else(|| {
                runs.iter()
                    .filter(same_mesh)
                    .min_by(|a, b| a.numerics.periodic_tol.total_cmp(&b.numerics.periodic_tol))
            }) else {
                continue;
            };
            md += &row(r, name, fr, cr);
        }
        for r in finer
            .iter()
            .filter(|r| r.case == case && !std::ptr::eq(*r, reference))
        {
            md += &row(r, "(finer, coarser N2)", fr, cr);
        }
    }
    fs::write("results/speed/speed_finer.md", md).map_err(|e| e.to_string())?;
    eprintln!("wrote results/speed/speed_finer.md");
    Ok(())
}

fn report() -> Result<(), String> {
    let runs = load_runs(RUNS, Some(STUDY_N1))?;
    let finer = load_runs(FINER, Some(2048..=usize::MAX))?;
    let mut csv = String::from("case,setting,n1,n2,dt,periodic_tol,solver,f_mean,c_min,err_f,err_c,wall_s,steps,periods,pareto\n");
    let mut md = String::from("# Speed against accuracy\n\nReproduce: `bash studies/speed.sh` (the settings; then `texopt-lab speed report`). Error: relative to the reference in each table's heading, the finest run of the case: 2048×128 at dt = 1e-4 (run by `bash studies/speed.sh finer` for Case III and `bash studies/convergence.sh` for Case I, with the p–θ multigrid after a 2048×8 approach: the same discretisation; its time is not comparable). Wall time: one core of the 2-core machine, from the equilibrium start (the untextured force balance) to the detected periodic regime, with the solver of the commit that ran the row. `approach N2=8`: the coarse approach of the `paper` and `fine` tiers (the ring's transient on 512×8 or 1024×8 first; the answer is the full mesh's). ★ = Pareto-optimal in f̄ error and time (no other setting is both faster and more accurate); tier names mark the fidelity tiers. The tiers against the 2048-cell runs with fewer cells across, and the conformal R = 51.2: `speed_finer.md`.\n");
    let mut series_data = Vec::new();
    let mut tier_rings = Vec::new();
    for (ci, case) in ["case-I", "case-III"].iter().enumerate() {
        let mut rs: Vec<&Run> = runs.iter().filter(|r| r.case == *case).collect();
        if rs.is_empty() {
            continue;
        }
        // Finest first: most cells, then smallest dt, then tightest periodic tolerance.
        rs.sort_by(|a, b| {
            let key = |r: &Run| {
                (
                    r.numerics.n1 * r.numerics.n2,
                    r.numerics.dt,
                    r.numerics.periodic_tol,
                )
            };
            let (ka, kb) = (key(a), key(b));
            kb.0.cmp(&ka.0)
                .then(ka.1.total_cmp(&kb.1))
                .then(ka.2.total_cmp(&kb.2))
        });
        // The reference: the case's finest 2048-cell run (the 2048×128 where it was
        // run), else the study's own finest run, which is then no point of the chart.
        let finest_finer = finer
            .iter()
            .filter(|r| r.case == *case)
            .max_by_key(|r| (r.numerics.n1 * r.numerics.n2, r.numerics.n2));
        let (reference, points) = match finest_finer {
            Some(r) => (r, &rs[..]),
            None => (rs[0], &rs[1..]),
        };
        let (fr, cr) = (reference.outcome.f_mean, reference.outcome.c_min);
        let pts: Vec<(f64, f64, f64, &Run)> = points
            .iter()
            .map(|r| {
                (
                    r.outcome.wall_time_s,
                    ((r.outcome.f_mean - fr) / fr).abs().max(1e-7),
                    ((r.outcome.c_min - cr) / cr).abs(),
                    *r,
                )
            })
            .collect();
        let pareto = |i: usize| {
            !pts.iter().enumerate().any(|(j, q)| {
                j != i && q.0 <= pts[i].0 && q.1 <= pts[i].1 && (q.0 < pts[i].0 || q.1 < pts[i].1)
            })
        };
        md += &format!(
            "\n## {case} (reference {}: f̄ = {:.6}, C_min = {:.5} µm, {:.0} s)\n\n| setting | f̄ | err f̄ | err C_min | wall (s) | steps | periods | |\n|---|---|---|---|---|---|---|---|\n",
            setting(reference), fr, cr, reference.outcome.wall_time_s
        );
        let (mut all_pts, mut front) = (Vec::new(), Vec::new());
        let mut order: Vec<usize> = (0..pts.len()).collect();
        order.sort_by(|&a, &b| pts[a].0.total_cmp(&pts[b].0));
        for i in order {
            let (w, ef, ec, r) = pts[i];
            let p = pareto(i);
            md += &format!(
                "| {} | {:.6} | {:.3} % | {:.3} % | {:.2} | {} | {} | {} |\n",
                setting(r),
                r.outcome.f_mean,
                100.0 * ef,
                100.0 * ec,
                w,
                r.outcome.steps,
                r.outcome.periods,
                match (p, tier_name(r, &rs)) {
                    (true, Some(t)) => format!("★ {t}"),
                    (false, Some(t)) => t.to_string(),
                    (true, None) => "★".to_string(),
                    (false, None) => String::new(),
                }
            );
            csv += &format!(
                "{case},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                setting(r),
                r.numerics.n1,
                r.numerics.n2,
                r.numerics.dt,
                r.numerics.periodic_tol,
                r.solver.name(),
                r.outcome.f_mean,
                r.outcome.c_min,
                ef,
                ec,
                w,
                r.outcome.steps,
                r.outcome.periods,
                p
            );
            all_pts.push((w, 100.0 * ef));
            if p {
                front.push((w, 100.0 * ef));
            }
        }
        // The fidelity tiers, as run with default tolerances and solver.
        let tiers: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| {
                p.3.solver == Solver::Direct
                    && Fidelity::ALL.iter().any(|f| {
                        let t = f.numerics();
                        let n = &p.3.numerics;
                        (t.n1, t.n2, t.dt, t.periodic_tol, t.approach_n2)
                            == (n.n1, n.n2, n.dt, n.periodic_tol, n.approach_n2)
                    })
            })
            .map(|p| (p.0, 100.0 * p.1))
            .collect();
        // Tiers last, as rings around their settings' points (drawn first, they were hidden).
        series_data.push((
            format!("{case}: all settings"),
            all_pts,
            Style::Markers,
            2 * ci,
        ));
        series_data.push((
            format!("{case}: Pareto front"),
            front,
            Style::Line,
            2 * ci + 1,
        ));
        tier_rings.extend(tiers);
    }
    series_data.push((
        "fidelity tiers (draft, fast, paper, fine)".into(),
        tier_rings,
        Style::Rings,
        5,
    ));
    let series: Vec<Series> = series_data
        .iter()
        .map(|(n, p, style, c)| Series {
            name: n.clone(),
            points: p,
            style: *style,
            colour: *c,
        })
        .collect();
    plot::xy(
        Path::new("results/speed/speed.png"),
        &Chart {
            title: "Error of mean friction against wall time (one core)",
            x_label: "wall time to periodic regime (s)",
            y_label: "|error of mean f| (%)",
            x_scale: Scale::Log,
            y_scale: Scale::Log,
        },
        &series,
    )?;
    fs::write("results/speed/speed.csv", csv).map_err(|e| e.to_string())?;
    fs::write("results/speed/speed.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    Ok(())
}

/// `texopt-lab speed run … | finer-run … | report | finer`.
pub fn main(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("run") if (4..=7).contains(&args.len()) => run(&args[1..], RUNS),
        Some("finer-run") if (4..=7).contains(&args.len()) => run(&args[1..], FINER),
        Some("report") => report(),
        Some("finer") => finer(),
        _ => Err(
            "usage: texopt-lab speed run CASE N1xN2 DT [PERIODIC_TOL] [SOLVER] [APPROACH_N2] | speed report | speed finer-run CASE N1xN2 DT [PERIODIC_TOL] [SOLVER] [APPROACH_N2] | speed finer"
                .into(),
        ),
    }
}
