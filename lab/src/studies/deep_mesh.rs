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
use texopt::time::{resolve, simulate, Fidelity, Outcome, Overrides};

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
