//! Mesh and time-step convergence for the paper's convergence case (§3.3: Case I texture,
//! R = 0.8), meshes refined together with dt (dt ∝ dx): `texopt-lab convergence`.
//!
//! `run MESH DT [--solver NAME] [--approach N1xN2@DT]` runs one mesh into results/convergence/
//! (`--solver pt-multigrid` for the finest, where the band LU is too slow; `--approach`
//! reaches the periodic regime first on that coarser mesh and step: the answer does not depend on
//! the start); `report` writes the table and Fig. 4 from the runs there.
//!
//! Each run writes `run_<mesh>.json` (outcome, numerics, solver) and `boundary_<mesh>.csv`: per
//! step the x1 of the cavitation (rupture) boundary along the row nearest the pocket-centre
//! line (x2 = B − dy/2), the first cavitated node downstream of the first pressurised node
//! under the ring, as in the paper's Fig. 4.

use std::fs;
use std::io::Write;
use std::path::PathBuf;
use texopt::model::case::{CaseSpec, Texture};
use texopt::plot::{self, Chart, Scale, Series};
use texopt::time::{Numerics, Progress, Transient};

use super::{run_case, RunRecord};
use crate::solvers::Solver;

fn case() -> CaseSpec {
    CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0))
}

fn dir() -> PathBuf {
    PathBuf::from("results/convergence")
}

fn rupture_x(tr: &Transient) -> f64 {
    let g = &tr.scene().grid;
    let j = g.n2 - 1;
    let mut seen_pressure = false;
    for i in 1..g.n1 {
        if !tr.scene().gap.ring[i] {
            continue;
        }
        let pr = tr.state().pressurised[g.idx(i, j)];
        if pr {
            seen_pressure = true;
        } else if seen_pressure {
            return g.x(i);
        }
    }
    f64::NAN
}

fn run(mesh: &str, dt: f64, opts: &[String]) -> Result<(), String> {
    let mut solver = Solver::Direct;
    let (a, b) = mesh.split_once('x').ok_or("mesh must be N1xN2")?;
    let mut num = Numerics {
        n1: a.parse().map_err(|_| "bad N1")?,
        n2: b.parse().map_err(|_| "bad N2")?,
        dt,
        ..Numerics::default()
    };
    for pair in opts.chunks(2) {
        match pair {
            [k, v] if k == "--solver" => solver = Solver::parse(v)?,
            [k, v] if k == "--approach" => num.approach = Some(super::parse_approach(v)?),
            _ => {
                return Err(format!(
                    "unknown option {pair:?}: --solver NAME | --approach N1xN2@DT"
                ))
            }
        }
    }
    let case = case();
    num.validate(&case).map_err(|e| e.to_string())?;
    fs::create_dir_all(dir()).map_err(|e| e.to_string())?;
    // `--approach` runs its coarse mesh first; the rows of the last periods are the full
    // mesh's.
    let mut rows = Vec::new();
    let mut steps_per_period = 1;
    let res = run_case(
        &case,
        &num,
        solver,
        &mut |p: &Progress| {
            eprintln!(
                "{mesh}: period {} t = {:.3} f = {:.6} Z = {:.5} est {:.1e}",
                p.period, p.t, p.f_mean, p.z_mean, p.periodic_error
            )
        },
        &mut |t: &Transient| {
            steps_per_period = t.steps_per_period();
            rows.push((t.t(), rupture_x(t)));
        },
    )?;
    let json = serde_json::json!({ "mesh": mesh, "numerics": num, "solver": solver, "outcome": res.outcome });
    fs::write(
        dir().join(format!("run_{mesh}.json")),
        serde_json::to_string_pretty(&json).unwrap(),
    )
    .map_err(|e| e.to_string())?;
    let mut f = fs::File::create(dir().join(format!("boundary_{mesh}.csv"))).unwrap();
    writeln!(f, "t,x_rupture_cm").unwrap();
    // The last texture periods only (the periodic regime), to keep the file small.
    let keep = 3 * steps_per_period;
    for (t, x) in rows.iter().skip(rows.len().saturating_sub(keep)) {
        writeln!(f, "{t:.6},{x:.6}").unwrap();
    }
    println!(
        "{mesh} dt {dt:e}: f = {:.6}, C_min = {:.5}, {} steps, {:.1} s",
        res.outcome.f_mean, res.outcome.c_min, res.outcome.steps, res.outcome.wall_time_s
    );
    Ok(())
}

/// The solver of a run as the table names it: the film method, and the coarse approach's
/// mesh and steps when the run had one (they count in the run's steps and time).
fn solver_name(r: &RunRecord) -> String {
    match &r.numerics.approach {
        Some(a) => format!(
            "{} after {} steps on {}",
            r.solver.name(),
            r.outcome.approach_steps,
            super::approach_name(a)
        ),
        None => r.solver.name().to_string(),
    }
}

fn report() -> Result<(), String> {
    let mut runs: Vec<(usize, usize, RunRecord)> = super::convergence_runs()?
        .into_iter()
        .map(|r| (r.numerics.n1, r.numerics.n2, r))
        .collect();
    runs.sort_by_key(|r| r.0);
    let finest = runs.last().ok_or("no runs in results/convergence")?;
    let (f_ref, c_ref) = (finest.2.outcome.f_mean, finest.2.outcome.c_min);
    let mut md = String::new();
    md += "# Mesh and time-step convergence (paper §3.3: Case I, R = 0.8)\n\n";
    md += "Reproduce: `bash studies/convergence.sh` (one `texopt-lab convergence run MESH DT` per row, then `texopt-lab convergence report`).\n\n";
    md += &format!(
        "Errors are relative to the finest mesh run here ({}×{}, dt = {:e}).\n\n",
        finest.0, finest.1, finest.2.numerics.dt
    );
    md += "| mesh | dt | solver | f̄ | C_min (µm) | err f̄ | err C_min | periods | steps | wall (s) | ms/step |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    let mut errs = Vec::new();
    for (n1, n2, r) in &runs {
        let (num, o) = (&r.numerics, &r.outcome);
        let ef = (o.f_mean - f_ref).abs() / f_ref;
        let ec = (o.c_min - c_ref).abs() / c_ref;
        errs.push((*n1, o.f_mean, o.c_min, ef, ec));
        md += &format!(
            "| {n1}×{n2} | {:.1e} | {} | {:.6} | {:.5} | {:.2} % | {:.2} % | {} | {} | {:.1} | {:.2} |\n",
            num.dt,
            solver_name(r),
            o.f_mean,
            o.c_min,
            100.0 * ef,
            100.0 * ec,
            o.periods,
            o.steps,
            o.wall_time_s,
            1e3 * o.wall_time_s / o.steps.max(1) as f64
        );
    }
    // Observed order from three successive meshes (Richardson): p = log2(|q1−q2|/|q2−q3|).
    md += "\nObserved order (three successive refinements, p = log₂(|q_h − q_h/2| / |q_h/2 − q_h/4|)):\n\n";
    for w in errs.windows(3) {
        let pf = ((w[0].1 - w[1].1).abs() / (w[1].1 - w[2].1).abs()).log2();
        let pc = ((w[0].2 - w[1].2).abs() / (w[1].2 - w[2].2).abs()).log2();
        md += &format!(
            "- N1 = {}, {}, {}: order of f̄ {:.2}, of C_min {:.2}\n",
            w[0].0, w[1].0, w[2].0, pf, pc
        );
    }
    // Paper §3.3: "The relative errors in the average friction force in the periodic regime
    // on the meshes with 512×32 and 1024×64 cells, as compared to those computed on the
    // 2048×128 mesh, are of 0.72% and 0.27%": both are errors of f̄ (no C_min is given).
    let paper = [((512, 32), 0.72), ((1024, 64), 0.27)];
    md += "\nAgainst the paper (§3.3: its error of f̄ on 512×32 and 1024×64 against its 2048×128; it gives none for C_min):\n\n| mesh | paper: err f̄ | here: err f̄ |\n|---|---|---|\n";
    for ((n1, n2), pct) in paper {
        let here =
            runs.iter()
                .find(|r| (r.0, r.1) == (n1, n2))
                .map_or("not run".to_string(), |r| {
                    format!(
                        "{:.2} %",
                        100.0 * (r.2.outcome.f_mean - f_ref).abs() / f_ref
                    )
                });
        md += &format!("| {n1}×{n2} | {pct:.2} % | {here} |\n");
    }
    fs::write(dir().join("convergence.md"), &md).map_err(|e| e.to_string())?;
    print!("{md}");

    // Fig. 4: the rupture boundary along the pocket-centre line over the last periods.
    let mut data = Vec::new();
    for (n1, n2, _) in runs.iter().rev().take(3) {
        let p = dir().join(format!("boundary_{n1}x{n2}.csv"));
        let text = fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
        let raw: Vec<(f64, f64)> = text
            .lines()
            .skip(1)
            .filter_map(|l| {
                let (a, b) = l.split_once(',')?;
                Some((a.parse().ok()?, b.parse().ok()?))
            })
            .collect();
        // Time since the start of the recorded periods: every run's period ends fall at the
        // same texture phase, so the meshes line up.
        let per = case().texture.map_or(1.0, |t| t.per / case().u);
        let t0 = raw.first().map_or(0.0, |p| (p.0 / per).floor() * per);
        let pts: Vec<(f64, f64)> = raw.iter().map(|p| (p.0 - t0, p.1)).collect();
        data.push((format!("{n1}×{n2}"), pts));
    }
    let series: Vec<Series> = data
        .iter()
        .enumerate()
        .map(|(i, (name, pts))| Series {
            name: name.clone(),
            points: pts,
            style: texopt::plot::Style::Line,
            colour: i,
        })
        .collect();
    plot::xy(
        &dir().join("convergence_fig4.png"),
        &Chart {
            title: "Cavitation (rupture) boundary on the pocket-centre line, Case I",
            x_label: "t − t₀ (L/U) over the last three texture periods",
            y_label: "x1 of rupture boundary (cm)",
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
        },
        &series,
    )
    .map_err(|e| e.to_string())?;
    Ok(())
}

/// `texopt-lab convergence run MESH DT [...] | report`.
pub fn main(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("run") if args.len() >= 3 => match args[2].parse::<f64>() {
            Ok(dt) => run(&args[1], dt, &args[3..]),
            Err(_) => Err(format!("dt must be a number, got {:?}", args[2])),
        },
        Some("report") => report(),
        _ => Err(
            "usage: texopt-lab convergence run N1xN2 DT [--solver NAME] [--approach N2] | texopt-lab convergence report"
                .into(),
        ),
    }
}
