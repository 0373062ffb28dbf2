//! Speed against accuracy (Case I, Case III, the conformal R = 51.2): the error of f̄ and
//! C_min against each case's converged reference (results/references/) over meshes, time
//! steps and the accelerators, against the wall time from the paper's start:
//! `texopt-lab speed`.
//!
//! `run CASE N1xN2 DT [KEY=VALUE …]` appends one run to results/speed/runs.jsonl: the `fast`
//! tier's numerics with that mesh and step (`c` for the characteristic step 2·dx1/u of the
//! mesh), changed by `tol=` (periodic tolerance), `scheme=be|bdf2|char`,
//! `approach=off|N1xN2@DT`, `accelerate=no`, `deep=off` (no deep-pocket mesh), `solver=NAME`. `report`
//! writes results/speed/speed.{md,csv,png}: every setting with its errors and time, the
//! Pareto-optimal ones (no other setting both faster and more accurate) marked, the tiers
//! named.

use std::fs;
use std::path::Path;
use texopt::plot::{self, Chart, Scale, Series, Style};
use texopt::study::bench::case;
use texopt::time::{Fidelity, Numerics, Start, TimeScheme};

use super::{parse_approach, run_case, RunRecord as Run};
use crate::solvers::Solver;

const RUNS: &str = "results/speed/runs.jsonl";

/// The cases of the chart.
const CASES: [&str; 3] = ["case-I", "case-III", "conformal-R51.2"];

/// Cases tabled but off the chart's scale: the deep close-packed pockets, whose errors at 8
/// cells across are several times the others'.
const TABLED: [&str; 1] = ["deep-close-packed"];

fn run(args: &[String]) -> Result<(), String> {
    let [name, mesh, dt, options @ ..] = args else {
        return Err("usage: texopt-lab speed run CASE N1xN2 DT [KEY=VALUE …]".into());
    };
    let (a, b) = mesh.split_once('x').ok_or("mesh must be N1xN2")?;
    let mut solver = Solver::Direct;
    let mut num = Numerics {
        n1: a.parse().map_err(|_| "bad N1")?,
        n2: b.parse().map_err(|_| "bad N2")?,
        dt: if dt == "c" {
            0.0
        } else {
            dt.parse().map_err(|_| "bad dt (a number, or c)")?
        },
        start: Start::Paper,
        ..Fidelity::Fast.numerics()
    };
    for o in options {
        let bad = || {
            format!("option {o}: tol=X | scheme=be|bdf2|char | approach=off|N1xN2@DT | accelerate=no | deep=off | solver=NAME")
        };
        let (k, v) = o.split_once('=').ok_or_else(bad)?;
        match (k, v) {
            ("tol", v) => num.periodic_tol = v.parse().map_err(|_| bad())?,
            ("scheme", "be") => num.scheme = TimeScheme::BackwardEuler,
            ("scheme", "bdf2") => num.scheme = TimeScheme::Bdf2,
            ("scheme", "char") => num.scheme = TimeScheme::Characteristic,
            ("approach", "off") => num.approach = None,
            ("approach", v) => num.approach = Some(parse_approach(v)?),
            ("accelerate", "no") => num.accelerate = false,
            ("deep", "off") => num.deep = None,
            ("solver", v) => solver = Solver::parse(v)?,
            _ => return Err(bad()),
        }
    }
    let c = case(name).ok_or(format!("no case {name}"))?;
    if dt == "c" {
        num.fit_characteristic_step(&c.case);
        num.fit_step_to_period(&c.case);
    }
    num.validate(&c.case).map_err(|e| e.to_string())?;
    let out = run_case(&c.case, &num, solver, &mut |_| {}, &mut |_| {})?.outcome;
    println!(
        "{name} {mesh} dt {dt} {}: f {:.6} C_min {:.5} ({} periods, {:.2} s)",
        options.join(" "),
        out.f_mean,
        out.c_min,
        out.periods,
        out.wall_time_s
    );
    Run {
        case: name.clone(),
        numerics: num,
        solver,
        outcome: out,
    }
    .append(RUNS)
}

/// The fidelity tier a run is, as the product runs it (mesh, step, scheme, tolerance,
/// accelerators, direct solver), if any.
fn tier_name(r: &Run) -> Option<&'static str> {
    let n = &r.numerics;
    let c = case(&r.case)?;
    Fidelity::ALL
        .into_iter()
        .find(|f| {
            let t = f.numerics_for(&c.case);
            r.solver == Solver::Direct
                && (
                    t.n1,
                    t.n2,
                    t.dt,
                    t.periodic_tol,
                    t.approach,
                    t.scheme,
                    t.accelerate,
                    t.deep,
                ) == (
                    n.n1,
                    n.n2,
                    n.dt,
                    n.periodic_tol,
                    n.approach,
                    n.scheme,
                    n.accelerate,
                    n.deep,
                )
        })
        .map(Fidelity::name)
}

/// A run's setting as the table names it: what differs from the `fast` tier besides the mesh
/// and step.
fn setting(r: &Run) -> String {
    let n = &r.numerics;
    let fast = Fidelity::Fast.numerics();
    let mut s = format!("{}×{}, dt {:.1e}", n.n1, n.n2, n.dt);
    if n.scheme != fast.scheme {
        s += match n.scheme {
            TimeScheme::BackwardEuler => ", backward Euler",
            TimeScheme::Bdf2 => ", BDF2",
            TimeScheme::Characteristic => ", characteristic",
        };
    }
    if n.periodic_tol != fast.periodic_tol {
        s += &format!(", tol {:.0e}", n.periodic_tol);
    }
    if n.approach != fast.approach {
        s += &n.approach.as_ref().map_or(", no approach".into(), |a| {
            format!(", approach {}", super::approach_name(a))
        });
    }
    if !n.accelerate {
        s += ", plain march";
    }
    if let Some((n1, n2)) = r.outcome.deep_mesh {
        s += &format!(", then {n1}×{n2} (deep pockets)");
    }
    if r.solver != Solver::Direct {
        s += &format!(", {}", r.solver.name());
    }
    s
}

fn report() -> Result<(), String> {
    let runs = Run::load(RUNS)?;
    let mut csv = String::from(
        "case,setting,tier,n1,n2,dt,f_mean,c_min,err_f,err_c,wall_s,steps,periods,pareto\n",
    );
    let mut md = String::from("# Speed against accuracy\n\nReproduce: `bash studies/speed.sh` (the runs, ≈ 2.5 min on one core), then `texopt-lab speed report`. Errors: signed, relative to each case's converged reference (results/references/); `error` = the larger of |f̄| and |C_min|'s. Wall time: one core of the 2-core machine, from the paper's initial state to the detected periodic regime, coarse approach included. Every run is the `fast` tier's numerics (the characteristic scheme, Anderson acceleration, the coarse approach on 120×4 at its characteristic step 3.3e-3, periodic tolerance 1e-4) with the mesh and step of its row and what else the row says (a row that went on on the deep-pocket mesh, as `fast` does where pockets end deeper than 6·C_min, says `then 600×24`; the other rows stay on their mesh; a row naming `multigrid` or `pt-multigrid` solved every film problem with that lab solver, the same discrete problem, instead of the band LU). ★ = Pareto-optimal in error and time; tier names mark the fidelity tiers as the product runs them.\n");
    let mut series_data = Vec::new();
    let mut tier_rings = Vec::new();
    for (ci, name) in CASES.iter().chain(&TABLED).enumerate() {
        let charted = ci < CASES.len();
        let Some(r0) = case(name).and_then(|c| c.reference) else {
            continue;
        };
        let mut pts: Vec<(f64, f64, f64, &Run)> = runs
            .iter()
            .filter(|r| r.case == *name)
            .map(|r| {
                let o = &r.outcome;
                (
                    o.wall_time_s,
                    (o.f_mean - r0.f_mean) / r0.f_mean,
                    (o.c_min - r0.c_min) / r0.c_min,
                    r,
                )
            })
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let error = |p: &(f64, f64, f64, &Run)| p.1.abs().max(p.2.abs());
        let pareto = |i: usize| {
            !pts.iter().enumerate().any(|(j, q)| {
                j != i
                    && q.0 <= pts[i].0
                    && error(q) <= error(&pts[i])
                    && (q.0 < pts[i].0 || error(q) < error(&pts[i]))
            })
        };
        md += &format!(
            "\n## {name} (reference f̄ = {:.6} ± {:.2} %, C_min = {:.5} µm ± {:.2} %)\n\n| setting | f̄ | err f̄ | C_min (µm) | err C_min | wall (s) | periods | |\n|---|---|---|---|---|---|---|---|\n",
            r0.f_mean, 100.0 * r0.f_uncertainty, r0.c_min, 100.0 * r0.c_uncertainty
        );
        let (mut all_pts, mut front) = (Vec::new(), Vec::new());
        for (i, p) in pts.iter().enumerate() {
            let (w, ef, ec, r) = *p;
            let on_front = pareto(i);
            let tier = tier_name(r);
            md += &format!(
                "| {} | {:.6} | {:+.2} % | {:.5} | {:+.2} % | {:.2} | {} | {}{} |\n",
                setting(r),
                r.outcome.f_mean,
                100.0 * ef,
                r.outcome.c_min,
                100.0 * ec,
                w,
                r.outcome.periods,
                if on_front { "★ " } else { "" },
                tier.unwrap_or("")
            );
            csv += &format!(
                "{name},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{}\n",
                setting(r),
                tier.unwrap_or(""),
                r.numerics.n1,
                r.numerics.n2,
                r.numerics.dt,
                r.outcome.f_mean,
                r.outcome.c_min,
                ef,
                ec,
                w,
                r.outcome.steps,
                r.outcome.periods,
                on_front
            );
            let e = 100.0 * error(p).max(1e-5);
            all_pts.push((w, e));
            if on_front {
                front.push((w, e));
            }
            if tier.is_some() && charted {
                tier_rings.push((w, e));
            }
        }
        if !charted {
            continue;
        }
        series_data.push((
            format!("{name}: all settings"),
            all_pts,
            Style::Markers,
            2 * ci,
        ));
        series_data.push((
            format!("{name}: Pareto front"),
            front,
            Style::Line,
            2 * ci + 1,
        ));
    }
    series_data.push((
        "fidelity tiers (draft, fast, paper, fine)".into(),
        tier_rings,
        Style::Rings,
        6,
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
            title: "Error against wall time from the paper's start (one core)",
            x_label: "wall time to the periodic regime (s)",
            y_label: "larger of |error f̄|, |error C_min| (%)",
            x_scale: Scale::Log,
            y_scale: Scale::Log,
        },
        &series,
    )
    .map_err(|e| e.to_string())?;
    fs::write("results/speed/speed.csv", csv).map_err(|e| e.to_string())?;
    fs::write("results/speed/speed.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    Ok(())
}

/// `texopt-lab speed run … | report`.
pub fn main(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("run") => run(&args[1..]),
        Some("report") => report(),
        _ => Err("usage: texopt-lab speed run CASE N1xN2 DT [KEY=VALUE …] | speed report".into()),
    }
}
