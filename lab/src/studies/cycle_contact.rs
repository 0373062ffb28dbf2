//! Where the asperities touch over the example engine's cycle, and what the boundary friction's
//! pressure coefficient ς does to the cycle's friction (results/cycle_contact/):
//! `texopt-lab cycle-contact`.
//!
//! The example engine (studies/engine_gasoline.toml) has its oil at 0.02 Pa·s (warming up);
//! fully warm, a 5W-30 near 110 °C is ≈ 0.007 Pa·s, and a thin oil near 150 °C ≈ 0.003
//! Pa·s. The plain liner through the cycle at `fast` (600 cells: the mixed film near the dead
//! centres is resolved better than on `draft`'s 300, and a plain run costs about a second)
//! until it repeats itself at each, the two
//! warm ones with ς = 0.08, 0.17 (the default, docs/model.md §11) and 0.3, and the hottest at
//! ς = 0.17 with the crank step's limit on the change of the asperities' share (docs/model.md
//! §12, "Crank steps") off, at 0.2, 0.1, the tiers' 0.05 and 0.02; then the hottest at `draft`
//! and on the film of smooth surfaces (no flow factors, docs/model.md §11). σ = 0.3 µm, the
//! other contact constants their defaults. Seconds a run.

use std::fmt::Write as _;
use std::fs;

use texopt::model::liner_layout::LinerLayout;
use texopt::study::bench::example_engine;
use texopt::time::cycle::CycleWatch;
use texopt::time::cycle::{
    cycle_numerics, metrics, whole_stroke, CycleMetrics, CycleRun, Drive, CONTACT_SHARE,
};
use texopt::time::{Fidelity, Overrides};

/// A run: viscosity (Pa·s), ς, largest change of the asperities' share a step, the tier,
/// and whether the film is rough (the flow factors).
struct Run(f64, f64, f64, Fidelity, bool);

/// The runs at `fast` on the rough film, the cycle's: (viscosity Pa·s, ς, largest change of
/// the asperities' share a step).
const FAST_ROUGH: [(f64, f64, f64); 11] = [
    (0.02, 0.17, CONTACT_SHARE),
    (0.007, 0.08, CONTACT_SHARE),
    (0.007, 0.17, CONTACT_SHARE),
    (0.007, 0.3, CONTACT_SHARE),
    (0.003, 0.08, CONTACT_SHARE),
    (0.003, 0.17, CONTACT_SHARE),
    (0.003, 0.3, CONTACT_SHARE),
    (0.003, 0.17, f64::INFINITY),
    (0.003, 0.17, 0.2),
    (0.003, 0.17, 0.1),
    (0.003, 0.17, 0.02),
];

/// Every run: [`FAST_ROUGH`], then the hottest oil at `draft`, and on the smooth film.
fn runs() -> Vec<Run> {
    let mut r: Vec<Run> = FAST_ROUGH
        .iter()
        .map(|&(mu, vs, share)| Run(mu, vs, share, Fidelity::Fast, true))
        .collect();
    r.push(Run(0.003, 0.17, CONTACT_SHARE, Fidelity::Draft, true));
    r.push(Run(0.003, 0.17, CONTACT_SHARE, Fidelity::Fast, false));
    r
}

/// A run's figures, its cycles and the steps of its last cycle.
fn run(
    &Run(viscosity, varsigma, share, tier, rough): &Run,
) -> Result<(CycleMetrics, usize, usize), String> {
    let mut engine = example_engine().map_err(|e| e.to_string())?;
    engine.file.oil.viscosity_pa_s = viscosity;
    engine.file.contact.varsigma = Some(varsigma);
    engine.file.contact.smooth_film = !rough;
    let drive = Drive::new(&engine);
    let ring = drive.ring_case();
    let mut num = cycle_numerics(tier, &Overrides::default(), &ring, None);
    num.steps.contact_share = share;
    let layout = LinerLayout::uniform(0.1 * engine.file.engine.stroke_mm, None);
    let o = CycleRun::new(&drive, ring, layout, num)
        .and_then(|r| r.run(CycleWatch::default()))
        .map_err(|e| e.to_string())?;
    if !o.cyclic() {
        return Err(format!(
            "{viscosity} Pa·s, ς {varsigma}: the cycle did not repeat itself"
        ));
    }
    let steps = o.cycles.last().map_or(0, |c| c.steps);
    Ok((
        metrics(&o.rows, &engine, &whole_stroke(&engine)),
        o.cycles.len(),
        steps,
    ))
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let mut md = String::from(
        "# Where the asperities touch over the cycle, and what ς does\n\n\
         `texopt-lab cycle-contact`: the example engine's plain liner \
         (studies/engine_gasoline.toml) through the cycle until it repeats itself, \
         with its oil at 0.02 Pa·s (warming up), 0.007 Pa·s (fully warm) and 0.003 Pa·s (hot and thin); σ = 0.3 µm, the boundary \
         friction τ₀·A_a + ς·W_a (docs/model.md §11), the film rough (the flow factors of §11) \
         but where it says smooth.\n\n\
         | tier | film | viscosity (Pa·s) | ς | share a step, at most | friction work (J/m) | asperities' part | FMEP (kPa) | h_min (µm) at | Λ_min | asperity load, max | time with contact | mixed / boundary | cycles | steps a cycle |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs() {
        let (m, cycles, steps) = run(&r)?;
        let Run(mu, vs, share, tier, rough) = r;
        let film = if rough { "rough" } else { "smooth" };
        eprintln!(
            "{} {film}, {mu} Pa·s, ς {vs}: {:.4} J/m ({:.4} asperities'), h_min {:.3} µm at {:.1}°",
            tier.name(),
            m.work_j_per_m,
            m.asperity_work_j_per_m,
            m.h_min_um,
            m.h_min_deg
        );
        let _ = writeln!(
            md,
            "| {} | {film} | {mu} | {vs} | {} | {:.4} | {:.1} % | {:.3} | {:.3} at {:.1}° | {:.2} | {:.1} % | {:.1} % | {:.1} % / {:.1} % | {cycles} | {steps} |",
            tier.name(),
            if share.is_finite() { share.to_string() } else { "–".into() },
            m.work_j_per_m,
            100.0 * m.asperity_work_j_per_m / m.work_j_per_m,
            m.fmep_kpa,
            m.h_min_um,
            m.h_min_deg,
            m.lambda_min,
            100.0 * m.asperity_share_max,
            100.0 * m.contact_time_fraction,
            100.0 * m.regime_time_fraction[1],
            100.0 * m.regime_time_fraction[2],
        );
    }
    fs::create_dir_all("results/cycle_contact").map_err(|e| e.to_string())?;
    fs::write("results/cycle_contact/README.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    eprintln!("wrote results/cycle_contact/README.md");
    Ok(())
}
