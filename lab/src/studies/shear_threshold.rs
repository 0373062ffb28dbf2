//! Where the `fast` tier's f̄ error on pockets comes from (results/shear_threshold/):
//! `texopt-lab shear-threshold`.
//!
//! The Couette term of the friction counts the shear u·θ/h only where θ > θ_s (docs/model.md
//! §5, θ_s = 0.95). In a pocket filling under the ring θ rises slowly through θ_s, so which
//! nodes count moves with the mesh: a first-order error of θ there becomes an error of the
//! switch's position. θ_s enters the friction only (the film and the ring are simulated once,
//! [`RunOptions::extra_theta_s`]), so one run per mesh gives f̄ for every θ_s. Each benchmark
//! case runs along the references' sequence (512×16 at 2e-4, 1024×16 at 1e-4, 2048×16 at
//! 5e-5: Courant number 0.5, BDF2) and at the `fast` tier (700×8, the characteristic
//! scheme); Anderson acceleration to 1e-6.

use std::fs;

use texopt::study::bench::cases;
use texopt::time::{simulate_with, Fidelity, Numerics, RunOptions, TimeScheme, Watch};

use super::parse_approach;

/// Thresholds reported besides the model's 0.95 (0: the shear counted everywhere, g = θ).
const OTHER_THETA_S: [f64; 3] = [0.0, 0.5, 0.9];

/// (label, N1, N2, dt): the `fast` tier (its own mesh and step), then the references'
/// sequence along x1.
const LEVELS: [(&str, usize, usize, f64); 4] = [
    ("fast", 0, 0, 0.0),
    ("along", 512, 16, 2e-4),
    ("along", 1024, 16, 1e-4),
    ("along", 2048, 16, 5e-5),
];

/// f̄ at θ_s = 0.95 and at each of [`OTHER_THETA_S`] for one case and level.
fn run(case: &texopt::model::case::CaseSpec, level: usize) -> Result<Vec<f64>, String> {
    let (_, n1, n2, dt) = LEVELS[level];
    let num = if level == 0 {
        Numerics {
            periodic_tol: 1e-6,
            ..Fidelity::Fast.numerics_for(case)
        }
    } else {
        Numerics {
            n1,
            n2,
            dt,
            periodic_tol: 1e-6,
            scheme: TimeScheme::Bdf2,
            approach: Some(parse_approach("512x8@4e-4")?),
            ..Numerics::default()
        }
    };
    let opts = RunOptions {
        extra_theta_s: OTHER_THETA_S.to_vec(),
        ..RunOptions::default()
    };
    let r = simulate_with(case, &num, &opts, &mut Watch::default()).map_err(|e| e.to_string())?;
    let mut f = vec![r.outcome.f_mean];
    f.extend(r.extra.iter().map(|(_, o)| o.f_mean));
    Ok(f)
}

/// The ratio of the successive changes of a three-level sequence (a → b → c), or "—" when
/// they change sign.
fn ratio(a: f64, b: f64, c: f64) -> String {
    let (d1, d2) = (b - a, c - b);
    if d1 * d2 > 0.0 {
        format!("{:.2}", d1 / d2)
    } else {
        "—".into()
    }
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let thetas: Vec<f64> = std::iter::once(0.95).chain(OTHER_THETA_S).collect();
    let mut md = String::from(
        "# The shear threshold θ_s and the convergence of f̄\n\nReproduce: `texopt-lab shear-threshold` (≈ 10 min on one core; lab/src/studies/shear_threshold.rs). The Couette term of the friction counts the shear u·θ/h only where θ > θ_s (docs/model.md §5; the model's θ_s is 0.95). θ_s enters the friction alone, so each run gives f̄ for every θ_s from one film and ring. Each benchmark case at the `fast` tier (700×8 at its characteristic step 2·dx1/u, docs/solver.md) and along the references' sequence (N1 × 16 at the Courant number 0.5, BDF2); Anderson acceleration to a periodic tolerance of 1e-6. The change of f̄ from the `fast` tier to 2048×16 is in per cent; the ratio is that of the sequence's successive changes (2: first order, 1: not converging, —: changes of alternating sign).\n\n",
    );
    md.push_str("| case | θ_s | fast | 512×16 | 1024×16 | 2048×16 | fast → 2048×16 | ratio |\n|---|---|---|---|---|---|---|---|\n");
    for c in cases().into_iter().filter(|c| c.case.texture.is_some()) {
        let f: Vec<Vec<f64>> = (0..LEVELS.len())
            .map(|l| run(&c.case, l))
            .collect::<Result<_, _>>()?;
        for (t, theta_s) in thetas.iter().enumerate() {
            let v: Vec<f64> = f.iter().map(|row| row[t]).collect();
            let row = format!(
                "| {} | {theta_s} | {:.6} | {:.6} | {:.6} | {:.6} | {:+.2} % | {} |\n",
                c.name,
                v[0],
                v[1],
                v[2],
                v[3],
                100.0 * (v[0] / v[3] - 1.0),
                ratio(v[1], v[2], v[3]),
            );
            print!("{row}");
            md.push_str(&row);
        }
    }
    fs::create_dir_all("results/shear_threshold").map_err(|e| e.to_string())?;
    fs::write("results/shear_threshold/README.md", &md).map_err(|e| e.to_string())
}
