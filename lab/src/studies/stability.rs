//! Stability map: where each numerical method stops working (`texopt-lab stability`). One-
//! factor lines around two base cases — Case I's pocket (l1 = l2 = 0.01, per = 0.06, depth 5)
//! on a strongly curved ring (R = 0.8) and on a conformal one (R = 51.2) — over dt, ring
//! mass, depth, R, inlet film d_oil and θ_s, for the implicit ring coupling (texopt's) and
//! the explicit one (contrast). Each run goes to the periodic regime (draft mesh 256×8,
//! periodic_tol 1e-4, t_max 3) and records how it ended, the Newton iterations per step,
//! the largest film residual and the largest per-step mass defect.
//!
//! The contrasts (methods that fail on purpose): plain Gauss–Seidel against the direct solver
//! over meshes, and the non-mass-conserving Reynolds cut-off against Elrod–Adams.
//!
//! `runs` writes results/stability/runs.csv, `contrasts` results/stability/contrasts.csv,
//! `report` results/stability/stability.{md,png} from both; no argument does all three.

use std::fmt::Write as _;
use std::path::Path;
use texopt::model::case::{CaseSpec, Texture};
use texopt::plot::{self, Chart, Scale, Series, Style};
use texopt::time::{Numerics, Outcome, Transient, Watch};

use crate::solvers::{cutoff_transient, explicit_transient, Solver};

/// How the ring is coupled to the film.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Coupling {
    Implicit,
    Explicit,
}

/// The film model and solver of a contrast run.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Model {
    Direct,
    GaussSeidel,
    Cutoff,
}

impl Model {
    fn transient(self, case: &CaseSpec, num: &Numerics) -> Transient {
        match self {
            Model::Direct => Transient::new(case, num),
            Model::GaussSeidel => Solver::GaussSeidel.transient(case, num),
            Model::Cutoff => cutoff_transient(case, num),
        }
    }
}

const CSV: &str = "results/stability/runs.csv";
const CONTRASTS: &str = "results/stability/contrasts.csv";

struct Run {
    line: &'static str,
    value: f64,
    r: f64,
    coupling: Coupling,
    case: CaseSpec,
    num: Numerics,
}

fn base(r: f64) -> (CaseSpec, Numerics) {
    let case = CaseSpec::paper(r).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let num = Numerics {
        n1: 256,
        n2: 8,
        dt: 8e-4,
        periodic_tol: 1e-4,
        t_max: 3.0,
        ..Numerics::default()
    };
    (case, num)
}

fn runs() -> Vec<Run> {
    let mut v = Vec::new();
    for r in [0.8, 51.2] {
        for coupling in [Coupling::Implicit, Coupling::Explicit] {
            let mk = |line, value: f64, f: &dyn Fn(&mut CaseSpec, &mut Numerics)| {
                let (mut case, mut num) = base(r);
                f(&mut case, &mut num);
                Run {
                    line,
                    value,
                    r,
                    coupling,
                    case,
                    num,
                }
            };
            for dt in [1e-4, 2e-4, 4e-4, 8e-4, 1.6e-3, 3.2e-3, 4e-3] {
                v.push(mk("dt", dt, &|_, n| n.dt = dt));
            }
            for m in [2e-10, 6e-10, 2e-9, 2e-8, 2e-7] {
                v.push(mk("mass", m, &|c, _| c.mass = m));
            }
            if coupling == Coupling::Implicit {
                // Deep pockets on the widest lattice (l = 0.03 allows 60 µm thin-film valid).
                for d in [2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 100.0] {
                    v.push(mk("depth", d, &|c, _| {
                        c.texture = Some(Texture::circular(0.03, 0.06, d))
                    }));
                }
                for d_oil in [1.0, 2.0, 5.0, 10.0, 20.0, 50.0] {
                    v.push(mk("d_oil", d_oil, &|c, _| c.d_oil = d_oil));
                }
                for th in [0.05, 0.5, 0.95] {
                    v.push(mk("theta_s", th, &|c, _| c.theta_s = th));
                }
            }
        }
    }
    for rr in [
        0.2,
        0.4,
        1.6,
        3.2,
        6.4,
        12.8,
        25.6,
        102.4,
        1e3,
        f64::INFINITY,
    ] {
        let (mut case, num) = base(0.8);
        case.r = rr;
        v.push(Run {
            line: "R",
            value: rr,
            r: rr,
            coupling: Coupling::Implicit,
            case,
            num,
        });
    }
    v
}

/// `texopt-lab stability [runs | contrasts | report]`.
pub fn main(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("runs") => runs_csv(),
        Some("contrasts") => contrasts(),
        Some("report") => report(),
        None => {
            runs_csv();
            contrasts();
            report();
        }
        Some(other) => {
            return Err(format!(
                "no stability step {other:?}: runs, contrasts, report, or none for all three"
            ))
        }
    }
    Ok(())
}

/// The one-factor lines: results/stability/runs.csv.
fn runs_csv() {
    std::fs::create_dir_all("results/stability").unwrap();
    let mut out = String::from(
        "line,value,R,coupling,status,reason,t_end,steps,iterations_per_step,max_residual,max_mass_defect,f_mean,z_mean,c_min,wall_s\n",
    );
    let all = runs();
    for (i, run) in all.iter().enumerate() {
        let t0 = std::time::Instant::now();
        let mut sim = match run.coupling {
            Coupling::Implicit => Transient::new(&run.case, &run.num),
            Coupling::Explicit => explicit_transient(&run.case, &run.num),
        };
        let res = sim.run_to_periodic(&run.num, false, &mut Watch::default());
        let wall = t0.elapsed().as_secs_f64();
        let defect = sim.stats().max_mass_defect;
        let (status, reason, o) = match &res {
            Ok(r) if r.outcome.converged => ("periodic", String::new(), Some(&r.outcome)),
            Ok(r) => (
                "no periodic regime",
                format!(
                    "estimated distance {:.1e} at t_max",
                    r.outcome.periodic_error
                ),
                Some(&r.outcome),
            ),
            Err(e) => {
                let s = e.to_string();
                let kind = if s.contains("reached the liner") {
                    "contact (Z ≤ 1 nm)"
                } else if s.contains("unstable")
                    || s.contains("not finite")
                    || s.contains("non-finite")
                {
                    "non-finite / unstable"
                } else if s.contains("film solve failed") {
                    "film solve failed"
                } else {
                    "error"
                };
                (kind, s.replace(',', ";"), None)
            }
        };
        let g = |f: &dyn Fn(&Outcome) -> f64| o.map_or(String::new(), |o| format!("{}", f(o)));
        let _ = writeln!(
            out,
            "{},{},{},{:?},{status},{reason},{},{},{},{},{defect:e},{},{},{},{wall:.2}",
            run.line,
            run.value,
            run.r,
            run.coupling,
            sim.t(),
            sim.steps(),
            g(&|o| o.iterations_per_step),
            g(&|o| o.max_residual),
            g(&|o| o.f_mean),
            g(&|o| o.z_mean),
            g(&|o| o.c_min),
        );
        eprintln!(
            "[{}/{}] {} = {} R = {} {:?}: {status} ({wall:.1} s)",
            i + 1,
            all.len(),
            run.line,
            run.value,
            run.r,
            run.coupling
        );
        std::fs::write(CSV, &out).unwrap();
    }
}

/// One contrast run: `steps` time steps (0: to the periodic regime) of `case` with `num`,
/// the mass guard off when `measure_mass` (to see how far a non-conserving model drifts).
/// Returns (status, f̄ or last f, C_min or last Z, max mass defect, iterations/step, wall s).
fn contrast_run(
    case: &CaseSpec,
    num: &Numerics,
    model: Model,
    steps: usize,
    measure_mass: bool,
) -> (String, f64, f64, f64, f64, f64) {
    let t0 = std::time::Instant::now();
    let mut sim = model.transient(case, num);
    if measure_mass {
        sim.set_mass_tolerance(f64::INFINITY);
    }
    let mut its = 0usize;
    let res = if steps == 0 {
        sim.run_to_periodic(num, false, &mut Watch::default())
            .map(|r| (r.outcome.f_mean, r.outcome.c_min))
    } else {
        (0..steps)
            .try_for_each(|_| {
                sim.step()?;
                its += sim.last().iterations;
                Ok(())
            })
            .map(|()| (sim.friction().total(), sim.ring_state().z))
    };
    let wall = t0.elapsed().as_secs_f64();
    let per_step = if steps == 0 {
        0.0
    } else {
        its as f64 / sim.steps().max(1) as f64
    };
    match res {
        Ok((f, c)) => (
            "ok".into(),
            f,
            c,
            sim.stats().max_mass_defect,
            per_step,
            wall,
        ),
        Err(e) => (
            e.to_string().replace(',', ";"),
            f64::NAN,
            f64::NAN,
            sim.stats().max_mass_defect,
            per_step,
            wall,
        ),
    }
}

/// The contrasts' section of results/stability.md.
fn contrast_report(md: &mut String) {
    let Ok(text) = std::fs::read_to_string(CONTRASTS) else {
        return;
    };
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let status = |s: &str| {
        if s == "ok" {
            "ok".to_string()
        } else {
            // The error's cause, after the case label and time.
            let cause = s.split(": ").skip(2).collect::<Vec<_>>().join(": ");
            format!("**error**: {}", cause.split(';').next().unwrap_or(""))
        }
    };
    let val = |s: &str, p: usize| {
        s.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .map_or("–".to_string(), |v| format!("{v:.p$}"))
    };
    md.push_str("## Contrasts: methods that fail on purpose\n\n`texopt-lab stability contrasts` (contrasts.csv). Tests: lab/tests/contrasts.rs.\n\n");
    md.push_str("### Plain Gauss–Seidel (no acceleration) against the direct solver\n\nCase I (R = 0.8, l = 0.01, per = 0.06, depth 5), the first 10 steps at dt = 4e-4 from the equilibrium start; iterations are Newton iterations (direct) or sweeps (Gauss–Seidel, budget 20 000 per film solve, ring by secant iteration around it).\n\n| mesh | method | status | f after 10 steps | Z (µm) | iterations/step | wall s |\n|---|---|---|---|---|---|---|\n");
    for r in rows.iter().filter(|r| r[0] == "gauss-seidel") {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r[2],
            r[4],
            status(r[5]),
            val(r[6], 7),
            val(r[7], 6),
            if r[5] == "ok" {
                val(r[9], 1)
            } else {
                "–".into()
            },
            r[10]
        );
    }
    md.push_str("\n### Reynolds cut-off (not mass-conserving) against Elrod–Adams\n\nTo the periodic regime at 256×8, dt = 8e-4. The run's mass guard (relative defect per step ≤ 1e-6) refuses the cut-off; with the guard off, its answer against the mass-conserving one:\n\n| R | model | status | f̄ | C_min (µm) | Δf̄, ΔC_min against Elrod–Adams | largest mass defect per step | wall s |\n|---|---|---|---|---|---|---|---|\n");
    let cut: Vec<_> = rows.iter().filter(|r| r[0] == "reynolds-cutoff").collect();
    for r in &cut {
        let reference = cut
            .iter()
            .find(|x| x[1] == r[1] && x[4] == "elrod-adams")
            .map(|x| {
                (
                    x[6].parse::<f64>().unwrap_or(f64::NAN),
                    x[7].parse::<f64>().unwrap_or(f64::NAN),
                )
            });
        let rel = |v: &str, reference: f64| {
            let d = (v.parse::<f64>().unwrap_or(f64::NAN) - reference) / reference;
            if d.is_finite() {
                format!("{:+.1} %", 100.0 * d)
            } else {
                "–".into()
            }
        };
        let delta = match reference {
            Some((f, c)) if r[4] != "elrod-adams" && r[5] == "ok" => {
                format!("{}, {}", rel(r[6], f), rel(r[7], c))
            }
            _ => "–".into(),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {delta} | {} | {} |",
            r[1],
            r[4],
            status(r[5]),
            val(r[6], 5),
            val(r[7], 4),
            r[8].parse::<f64>()
                .map_or("–".into(), |v| format!("{v:.1e}")),
            r[10]
        );
    }
    md.push('\n');
}

/// The methods that fail on purpose, against texopt's.
fn contrasts() {
    std::fs::create_dir_all("results/stability").unwrap();
    let mut out = String::from(
        "contrast,R,mesh,steps,method,status,f,c_or_z,max_mass_defect,iterations_per_step,wall_s\n",
    );
    let mut push = |contrast: &str,
                    r: f64,
                    num: &Numerics,
                    steps: usize,
                    method: &str,
                    res: (String, f64, f64, f64, f64, f64)| {
        let line = format!(
            "{contrast},{r},{}x{},{steps},{method},{},{},{},{:e},{},{:.3}\n",
            num.n1, num.n2, res.0, res.1, res.2, res.3, res.4, res.5
        );
        eprint!("{line}");
        out.push_str(&line);
        std::fs::write(CONTRASTS, &out).unwrap();
    };
    // 1. Plain Gauss–Seidel: sweeps per step grow as N², so at fine meshes it exhausts its
    //    sweep budget (an error) where the direct solver takes a few iterations.
    let (case, _) = base(0.8);
    for (n1, n2) in [(32, 2), (64, 4), (128, 8), (256, 16), (512, 32)] {
        let num = Numerics {
            n1,
            n2,
            dt: 4e-4,
            periodic_tol: 1e-4,
            t_max: 3.0,
            ..Numerics::default()
        };
        let steps = 10;
        push(
            "gauss-seidel",
            0.8,
            &num,
            steps,
            "direct",
            contrast_run(&case, &num, Model::Direct, steps, false),
        );
        push(
            "gauss-seidel",
            0.8,
            &num,
            steps,
            "gauss-seidel",
            contrast_run(&case, &num, Model::GaussSeidel, steps, false),
        );
    }
    // 2. Reynolds cut-off against Elrod–Adams on textured cases, to the periodic regime: the
    //    guard refuses it; with the guard off, how far its answer is.
    for (r, tex) in [
        (0.8, Texture::circular(0.01, 0.06, 5.0)),
        (3.2, Texture::circular(0.03, 0.06, 10.0)),
        (51.2, Texture::circular(0.01, 0.06, 5.0)),
    ] {
        let case = CaseSpec::paper(r).with_texture(tex);
        let (_, num) = base(r);
        push(
            "reynolds-cutoff",
            r,
            &num,
            0,
            "elrod-adams",
            contrast_run(&case, &num, Model::Direct, 0, false),
        );
        push(
            "reynolds-cutoff",
            r,
            &num,
            0,
            "reynolds-cutoff (guarded)",
            contrast_run(&case, &num, Model::Cutoff, 0, false),
        );
        push(
            "reynolds-cutoff",
            r,
            &num,
            0,
            "reynolds-cutoff (guard off)",
            contrast_run(&case, &num, Model::Cutoff, 0, true),
        );
    }
}

fn report() {
    let text = std::fs::read_to_string(CSV).expect("run the study first");
    let rows: Vec<Vec<String>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let mut md = String::from("# Stability map\n\nWhere each numerical method stops working (`texopt-lab stability`: runs.csv, contrasts.csv, then this report). Base cases: Case I's pocket (l1 = l2 = 0.01, per = 0.06, depth 5) on R = 0.8 and R = 51.2; one factor varied at a time; draft mesh 256×8, periodic tolerance 1e-4, t_max = 3 ms. \"mass defect\" is the largest per-step relative mass-balance error of the run (round-off for a converged conservative solve).\n\n");
    let num = |x: &str, p: usize| {
        x.parse::<f64>()
            .map_or(x.to_string(), |v| format!("{v:.p$e}"))
    };
    let fixed = |x: &str, p: usize| {
        x.parse::<f64>()
            .map_or(x.to_string(), |v| format!("{v:.p$}"))
    };
    // Headline: every run that did not reach the periodic regime.
    md.push_str("## Where runs fail\n\n");
    for r in rows.iter().filter(|r| r[4] != "periodic") {
        let _ = writeln!(
            md,
            "- {} = {} (R = {}, {} coupling): {}",
            r[0],
            r[1],
            r[2],
            r[3].to_lowercase(),
            r[4]
        );
    }
    let worst_defect = rows
        .iter()
        .filter_map(|r| r[10].parse::<f64>().ok())
        .fold(0.0, f64::max);
    let worst_res = rows
        .iter()
        .filter_map(|r| r[9].parse::<f64>().ok())
        .fold(0.0, f64::max);
    let film_failures = rows.iter().filter(|r| r[4] == "film solve failed").count();
    let _ = writeln!(
        md,
        "\nOver all {} runs: largest per-step mass defect {worst_defect:.1e}, largest film residual {worst_res:.1e}; film solves that failed: {film_failures}.\n",
        rows.len()
    );
    for line in ["dt", "mass", "depth", "d_oil", "theta_s", "R"] {
        let _ = writeln!(md, "## {line}\n\n| {line} | R | coupling | status | it/step | max residual | max mass defect | f̄ | C_min (µm) | wall s |\n|---|---|---|---|---|---|---|---|---|---|");
        for r in rows.iter().filter(|r| r[0] == line) {
            let reason = if r[5].is_empty() {
                String::new()
            } else {
                format!(" ({})", r[5].chars().take(90).collect::<String>())
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {}{} | {} | {} | {} | {} | {} | {} |",
                r[1].parse::<f64>().map_or(r[1].clone(), |v| format!("{v}")),
                r[2],
                r[3].to_lowercase(),
                r[4],
                reason,
                fixed(&r[8], 2),
                num(&r[9], 1),
                num(&r[10], 1),
                fixed(&r[11], 5),
                fixed(&r[13], 4),
                r[14]
            );
        }
        md.push('\n');
    }
    contrast_report(&mut md);
    std::fs::write("results/stability/stability.md", md).unwrap();
    // Plot: Newton iterations per step against dt, by R and coupling; failures at 0.
    let mut data: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for r in ["0.8", "51.2"] {
        for c in ["Implicit", "Explicit"] {
            let pts = rows
                .iter()
                .filter(|x| x[0] == "dt" && x[2] == r && x[3] == c)
                .map(|x| {
                    (
                        x[1].parse().unwrap_or(f64::NAN),
                        x[8].parse().unwrap_or(0.0),
                    )
                })
                .collect();
            data.push((
                format!("R = {r}, {} coupling (0: failed)", c.to_lowercase()),
                pts,
            ));
        }
    }
    let series: Vec<Series> = data
        .iter()
        .enumerate()
        .map(|(i, (n, p))| Series {
            name: n.clone(),
            points: p,
            style: Style::Line,
            colour: i,
        })
        .collect();
    plot::xy(
        Path::new("results/stability/stability.png"),
        &Chart {
            title: "Film iterations per step against the time step",
            x_label: "dt (ms)",
            y_label: "Newton iterations per step",
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
        },
        &series,
    )
    .unwrap();
    eprintln!("wrote results/stability/stability.md and stability.png");
}
