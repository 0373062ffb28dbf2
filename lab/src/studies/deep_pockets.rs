//! What makes deep pockets hard to converge (results/deep_pockets/): `texopt-lab
//! deep-pockets`.
//!
//! Case III's ring and lattice (R = 3.2, per = width = 0.06) with pockets 5 to 30 µm deep,
//! touching (l1 = 0.03: the plateau between neighbours narrows to a point) and with walls of
//! 10 and 60 µm between them (l1 = 0.0295, 0.027). For each: the change of f̄ and C_min as
//! the cells across double (N2 = 8 → 16 → 32 at 512 cells along and dt = 1e-4), and as the
//! time step halves on 512×8 (dt = 4e-4 → 2e-4 → 1e-4). The ring-frame BDF2, Anderson
//! acceleration to 1e-6 after a coarse approach on 128×4 at dt = 1.6e-3.

use std::fs;

use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, Numerics, Outcome, TimeScheme, APPROACH};

/// (label, l1 in cm, depth in µm).
const POCKETS: [(&str, f64, f64); 7] = [
    ("touching, 5 µm", 0.03, 5.0),
    ("touching, 10 µm (Case III)", 0.03, 10.0),
    ("touching, 20 µm", 0.03, 20.0),
    ("touching, 30 µm", 0.03, 30.0),
    ("10 µm wall, 20 µm", 0.0295, 20.0),
    ("60 µm wall, 20 µm", 0.027, 20.0),
    ("60 µm wall, 10 µm", 0.027, 10.0),
];

fn run(case: &CaseSpec, n2: usize, dt: f64) -> Result<Outcome, String> {
    // The ring's frame: 512 cells along, BDF2, after 128×4 at 1.6e-3.
    let num = Numerics {
        n1: 512,
        n2,
        dt,
        periodic_tol: 1e-6,
        scheme: TimeScheme::Bdf2,
        approach: Some(APPROACH),
        ..Numerics::default()
    };
    simulate(case, &num)
        .map(|r| r.outcome)
        .map_err(|e| e.to_string())
}

/// Relative change from `a` to `b` in per cent.
fn pct(a: f64, b: f64) -> String {
    format!("{:+.2}", 100.0 * (b - a) / a)
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let mut md = String::from(
        "# Deep pockets: what the error grows with\n\nReproduce: `texopt-lab deep-pockets` (≈ 10 min on one core). Case III's ring and lattice (R = 3.2, per = width = 0.06), circular pockets touching (2·l1 = per) or with a wall between neighbours, 5–30 µm deep. Changes in per cent of f̄ and C_min as the cells across double at 512 cells along and dt = 1e-4 (BDF2), and as the time step halves on 512×8 (the ring-frame BDF2; the characteristic scheme of the tiers: results/speed/). Periodic tolerance 1e-6 (lab/src/studies/deep_pockets.rs).\n\n| pockets | f̄ at 512×32, 1e-4 | N2 8→16: f̄, C_min | N2 16→32: f̄, C_min | dt 4e-4→2e-4: f̄, C_min | dt 2e-4→1e-4: f̄, C_min |\n|---|---|---|---|---|---|\n",
    );
    for (label, l1, depth) in POCKETS {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(l1, 0.06, depth));
        let across: Vec<Outcome> = [8, 16, 32]
            .iter()
            .map(|&n2| run(&case, n2, 1e-4))
            .collect::<Result<_, _>>()?;
        let in_time: Vec<Outcome> = [4e-4, 2e-4, 1e-4]
            .iter()
            .map(|&dt| run(&case, 8, dt))
            .collect::<Result<_, _>>()?;
        let pair = |a: &Outcome, b: &Outcome| {
            format!("{}, {}", pct(a.f_mean, b.f_mean), pct(a.c_min, b.c_min))
        };
        let row = format!(
            "| {label} | {:.5} | {} | {} | {} | {} |\n",
            across[2].f_mean,
            pair(&across[0], &across[1]),
            pair(&across[1], &across[2]),
            pair(&in_time[0], &in_time[1]),
            pair(&in_time[1], &in_time[2]),
        );
        print!("{row}");
        md.push_str(&row);
    }
    fs::create_dir_all("results/deep_pockets").map_err(|e| e.to_string())?;
    fs::write("results/deep_pockets/README.md", &md).map_err(|e| e.to_string())
}
