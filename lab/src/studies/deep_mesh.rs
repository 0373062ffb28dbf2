//! How far `fast`'s deep-pocket answers are from their refinements (results/deep_mesh/):
//! `texopt-lab deep-mesh`.
//!
//! `fast` goes on on its deep-pocket mesh (600×24) where pockets end deeper than 6·C_min.
//! Here that answer, for the paper's 0.03/0.06/20 µm pockets at R = 3.2, 12.8, 25.6 and 51.2
//! and for small pockets (0.005/0.01/10 µm) at R = 25.6, against the same tier coarsened in
//! both directions (300×12, the characteristic step doubled with the cells), refined along
//! x1 (1200×24), across x2 (600×48) and in both (1200×48): each a run of its own from the
//! tier's start and coarse approach. The two single refinements are what a per-answer
//! uncertainty from them would cost; the uniform ones are the changes a first-order scheme's
//! error is told by (halving both directions keeps the cells' shape, so the errors along and
//! across keep their balance).

use std::fmt::Write as _;
use std::fs;

use rayon::prelude::*;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{resolve, simulate, Fidelity, Outcome, Overrides, UNCERTAINTY_FLOOR};

/// (R in cm, l1, per, depth in µm).
const CASES: [(f64, f64, f64, f64); 5] = [
    (3.2, 0.03, 0.06, 20.0),
    (12.8, 0.03, 0.06, 20.0),
    (25.6, 0.03, 0.06, 20.0),
    (51.2, 0.03, 0.06, 20.0),
    (25.6, 0.005, 0.01, 10.0),
];

/// The refined meshes (N1, N2); None: the tier's own answer.
const MESHES: [Option<(usize, usize)>; 5] = [
    None,
    Some((300, 12)),
    Some((1200, 24)),
    Some((600, 48)),
    Some((1200, 48)),
];

/// The case on the tier's numerics with `mesh` given: its outcome and the mesh it is on.
fn run(case: &CaseSpec, mesh: Option<(usize, usize)>) -> Result<(Outcome, (usize, usize)), String> {
    let given = Overrides {
        n1: mesh.map(|m| m.0),
        n2: mesh.map(|m| m.1),
        ..Overrides::default()
    };
    let num = resolve(Fidelity::Fast, &given, case);
    simulate(case, &num)
        .map(|r| {
            let mesh = r.outcome.mesh((num.n1, num.n2));
            (r.outcome, mesh)
        })
        .map_err(|e| format!("{}: {e}", case.label()))
}

/// Pockets for the uniform-refinement table (results/deep_rule/): (l1, per, width, depth in
/// µm) at R = 25.6 cm, circular, from the optimiser's smallest semiaxis (0.0025 cm) to the
/// paper's largest, at depths that end deeper than 6·C_min, and two with the lattice twice as
/// wide as it is long (half the cells across along x2).
const RULE_CASES: [(f64, f64, f64, f64); 10] = [
    (0.0025, 0.005, 0.005, 5.0),
    (0.005, 0.01, 0.01, 10.0),
    (0.0075, 0.015, 0.015, 10.0),
    (0.01, 0.02, 0.02, 8.0),
    (0.01, 0.02, 0.02, 20.0),
    (0.015, 0.03, 0.03, 15.0),
    (0.03, 0.06, 0.06, 20.0),
    (0.03, 0.06, 0.06, 30.0),
    (0.01, 0.02, 0.04, 20.0),
    (0.03, 0.06, 0.12, 20.0),
];

/// The ring radius of the uniform-refinement table (cm): the large-R case.
const RULE_R: f64 = 25.6;

/// The meshes of the uniform-refinement table: the tier's own, coarsened and refined in both
/// directions (the characteristic step with the cells along).
const RULE_MESHES: [Option<(usize, usize)>; 3] = [None, Some((300, 12)), Some((1200, 48))];

/// `texopt-lab deep-rule [report]`: the deep-pocket answer's change under one uniform
/// refinement and one uniform coarsening across pocket sizes and depths (results/deep_rule/),
/// the table the measured uncertainty of deep answers is checked on (docs/validation.md):
/// runs them (deep_rule.csv) and writes the README from the CSV; `report` only the README.
pub fn rule_main(args: &[String]) -> Result<(), String> {
    if args.first().map(String::as_str) != Some("report") {
        rule_runs()?;
    }
    rule_report()
}

fn rule_runs() -> Result<(), String> {
    let jobs: Vec<(usize, usize)> = (0..RULE_CASES.len())
        .flat_map(|c| (0..RULE_MESHES.len()).map(move |m| (c, m)))
        .collect();
    let case = |c: usize| {
        let (l1, per, width, depth) = RULE_CASES[c];
        let t = Texture {
            width,
            ..Texture::circular(l1, per, depth)
        };
        CaseSpec::paper(RULE_R).with_texture(t)
    };
    let outcomes: Vec<(Outcome, (usize, usize))> = jobs
        .par_iter()
        .map(|&(c, m)| run(&case(c), RULE_MESHES[m]))
        .collect::<Result<_, _>>()?;
    let mut csv = String::from(
        "R_cm,l1,per,width,depth_um,n1,n2,dt,f_mean,c_min,deep_mesh,converged,wall_s\n",
    );
    for (c, runs) in outcomes.chunks(RULE_MESHES.len()).enumerate() {
        let (l1, per, width, depth) = RULE_CASES[c];
        for (x, (a, b)) in runs {
            let _ = writeln!(
                csv,
                "{RULE_R},{l1},{per},{width},{depth},{a},{b},{},{},{},{},{},{}",
                x.dt,
                x.f_mean,
                x.c_min,
                x.deep_mesh.is_some(),
                x.converged,
                x.wall_time_s
            );
        }
    }
    fs::create_dir_all("results/deep_rule").map_err(|e| e.to_string())?;
    fs::write("results/deep_rule/deep_rule.csv", &csv).map_err(|e| e.to_string())
}

/// One run of results/deep_rule/deep_rule.csv: pockets, mesh, f̄, C_min, on the deep mesh.
struct RuleRow {
    pockets: String,
    mesh: String,
    f: f64,
    c: f64,
    deep: bool,
}

fn rule_rows() -> Result<Vec<RuleRow>, String> {
    let text = fs::read_to_string("results/deep_rule/deep_rule.csv")
        .map_err(|e| format!("results/deep_rule/deep_rule.csv: {e}; run `texopt-lab deep-rule`"))?;
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            let num = |i: usize| v.get(i).and_then(|x| x.parse::<f64>().ok());
            match (num(8), num(9), v.get(10)) {
                (Some(f), Some(c), Some(deep)) => Ok(RuleRow {
                    pockets: format!("{}/{}/{}/{}", v[1], v[2], v[3], v[4]),
                    mesh: format!("{}×{}", v[5], v[6]),
                    f,
                    c,
                    deep: *deep == "true",
                }),
                _ => Err(format!("deep_rule.csv: cannot read the line {l:?}")),
            }
        })
        .collect()
}

fn rule_report() -> Result<(), String> {
    let rows = rule_rows()?;
    let floor = 100.0 * UNCERTAINTY_FLOOR;
    let mut md = format!(
        "# Deep pockets: the measured uncertainty against one uniform refinement\n\n\
         Reproduce: `texopt-lab deep-rule` (≈ 25 min on two cores; `texopt-lab deep-rule report` \
         rewrites this file from deep_rule.csv). R = {RULE_R} cm, circular pockets \
         (l1/per/width/depth in cm and µm), `fast`: its answer (600×24 where the pockets end \
         deeper than 6·C_min, else 700×8), the same tier coarsened in both directions (300×12) \
         and refined in both (1200×48), the step with the cells along, each a run of its own \
         (lab/src/studies/deep_mesh.rs). Δ: change in per cent from the tier's answer. The \
         uncertainty texopt gives a deep answer is u = max(2·|Δ coarsened|, {floor:.1} %) \
         (time/uncertainty.rs); a first-order scheme's error on the tier's mesh is 2·|Δ refined|, \
         which u must cover.\n\n\
         | pockets | mesh | f̄ | C_min (µm) | Δ coarsened f̄, C_min | Δ refined f̄, C_min | u: f̄, C_min | 2·|Δ refined| | covered |\n\
         |---|---|---|---|---|---|---|---|---|\n"
    );
    for t in rows.chunks(3) {
        let [a, c, r] = t else {
            return Err("deep_rule.csv: a case without its three meshes".into());
        };
        let d = |x: f64, y: f64| 100.0 * (y / x - 1.0);
        let (dcf, dcc) = (d(a.f, c.f), d(a.c, c.c));
        let (drf, drc) = (d(a.f, r.f), d(a.c, r.c));
        let u = |x: f64| (2.0 * x.abs()).max(floor);
        let covered = if !a.deep {
            "not deep".to_string()
        } else if u(dcf) >= 2.0 * drf.abs() && u(dcc) >= 2.0 * drc.abs() {
            "yes".into()
        } else {
            "**no**".into()
        };
        let _ = writeln!(
            md,
            "| {} | {} | {:.5} | {:.4} | {dcf:+.2}, {dcc:+.2} | {drf:+.2}, {drc:+.2} | {:.2}, {:.2} | {:.2}, {:.2} | {covered} |",
            a.pockets,
            a.mesh,
            a.f,
            a.c,
            u(dcf),
            u(dcc),
            2.0 * drf.abs(),
            2.0 * drc.abs()
        );
    }
    fs::write("results/deep_rule/README.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    eprintln!("wrote results/deep_rule/README.md");
    Ok(())
}

/// Relative change from `a` to `b` in per cent.
fn pct(a: f64, b: f64) -> String {
    format!("{:+.2}", 100.0 * (b / a - 1.0))
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let jobs: Vec<(usize, usize)> = (0..CASES.len())
        .flat_map(|c| (0..MESHES.len()).map(move |m| (c, m)))
        .collect();
    let case = |c: usize| {
        let (r, l1, per, depth) = CASES[c];
        CaseSpec::paper(r).with_texture(Texture::circular(l1, per, depth))
    };
    let outcomes: Vec<(Outcome, (usize, usize))> = jobs
        .par_iter()
        .map(|&(c, m)| run(&case(c), MESHES[m]))
        .collect::<Result<_, _>>()?;
    let mut md = String::from(
        "# Deep pockets: the deep-pocket mesh against its refinements\n\n\
         Reproduce: `texopt-lab deep-mesh` (≈ 25 min on two cores). `fast`'s answer where \
         pockets end deeper than 6·C_min (700×8 going on on 600×24), and the same tier on \
         300×12, 1200×24, 600×48 and 1200×48 (the characteristic step with the cells along), \
         each from the tier's start and coarse approach (lab/src/studies/deep_mesh.rs). \
         Changes in per cent of f̄ and C_min from the tier's answer; wall times on one core.\n\n\
         | R (cm) | pockets l1/per/depth | tier: mesh, f̄, C_min (µm), s | 300×12: f̄, C_min | 1200×24: f̄, C_min | 600×48: f̄, C_min | 1200×48: f̄, C_min | the four runs' s |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let mut csv = String::from("R_cm,l1,per,depth_um,n1,n2,dt,f_mean,c_min,wall_s\n");
    for (c, runs) in outcomes.chunks(MESHES.len()).enumerate() {
        let (r, l1, per, depth) = CASES[c];
        let (o, (n1, n2)) = &runs[0];
        let _ = write!(
            md,
            "| {r} | {l1}/{per}/{depth} | {n1}×{n2}, {:.5}, {:.4}, {:.1} |",
            o.f_mean, o.c_min, o.wall_time_s
        );
        for (x, _) in &runs[1..] {
            let _ = write!(
                md,
                " {}, {} |",
                pct(o.f_mean, x.f_mean),
                pct(o.c_min, x.c_min)
            );
        }
        let walls: Vec<String> = runs[1..]
            .iter()
            .map(|(x, _)| format!("{:.0}", x.wall_time_s))
            .collect();
        let _ = writeln!(md, " {} |", walls.join(" / "));
        for (x, (a, b)) in runs {
            let _ = writeln!(
                csv,
                "{r},{l1},{per},{depth},{a},{b},{},{},{},{}",
                x.dt, x.f_mean, x.c_min, x.wall_time_s
            );
        }
    }
    fs::create_dir_all("results/deep_mesh").map_err(|e| e.to_string())?;
    fs::write("results/deep_mesh/deep_mesh.csv", csv).map_err(|e| e.to_string())?;
    fs::write("results/deep_mesh/README.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    eprintln!("wrote results/deep_mesh/README.md and deep_mesh.csv");
    Ok(())
}
