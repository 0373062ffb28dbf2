//! What the time scheme, the crank step and the cells do to a textured liner's cycle
//! (results/cycle_steps/): `texopt-lab cycle-steps`.
//!
//! The example engine's liner uniformly textured with the paper's Case I pocket, through the
//! cycle until it repeats itself: along the Couette characteristics (the cycle's scheme) at
//! `draft` and `fast`, on coarser cells and on `paper`'s 1200 cells along x1 (at `fast`'s
//! crank steps and 8 cells across), the texture moving 2 cells a step (Courant number 1) and
//! 1 (0.5); then backward Euler at `fast` and `draft` (docs/solver.md, "The engine cycle").
//! One core, one run after the other (≈ 20 minutes): the wall times are the study's too. `texopt-lab cycle-steps K [N1]` runs row K alone (on N1 cells along x1 if
//! given) and writes nothing.

use std::fmt::Write as _;
use std::fs;

use texopt::model::case::Texture;
use texopt::model::liner_layout::LinerLayout;
use texopt::study::bench::example_engine;
use texopt::time::cycle::CycleWatch;
use texopt::time::cycle::{cycle_numerics, CycleRun, Drive, TEXTURE_CELLS};
use texopt::time::{Fidelity, Overrides, TimeScheme};

/// One run: the tier whose cells it takes (along x1), the texture's travel a step in cells,
/// the scheme.
#[derive(Clone, Copy)]
struct Run {
    cells_of: Fidelity,
    /// Cells along x1 given instead of the tier's.
    n1: Option<usize>,
    travel: f64,
    scheme: TimeScheme,
}

const fn run_of(cells_of: Fidelity, n1: Option<usize>, travel: f64, scheme: TimeScheme) -> Run {
    Run {
        cells_of,
        n1,
        travel,
        scheme,
    }
}

const RUNS: [Run; 7] = [
    run_of(Fidelity::Draft, None, 2.0, TimeScheme::Characteristic),
    run_of(Fidelity::Draft, Some(200), 2.0, TimeScheme::Characteristic),
    run_of(Fidelity::Fast, None, 2.0, TimeScheme::Characteristic),
    run_of(Fidelity::Fast, Some(1200), 2.0, TimeScheme::Characteristic),
    run_of(Fidelity::Draft, None, 1.0, TimeScheme::Characteristic),
    run_of(Fidelity::Fast, None, 2.0, TimeScheme::BackwardEuler),
    run_of(Fidelity::Draft, None, 2.0, TimeScheme::BackwardEuler),
];

/// One run's row: cells, travel, scheme, steps a cycle, seconds a cycle, cycles, work (J/m).
struct Row {
    n1: usize,
    step_deg: f64,
    travel: f64,
    scheme: TimeScheme,
    steps: usize,
    s_per_cycle: f64,
    cycles: usize,
    work: f64,
}

fn run(r: &Run) -> Result<Row, String> {
    let engine = example_engine().map_err(|e| e.to_string())?;
    let drive = Drive::new(&engine);
    let ring = drive.ring_case();
    let t = Texture::circular(0.01, 0.06, 5.0);
    let layout = LinerLayout::uniform(0.1 * engine.file.engine.stroke_mm, Some(t.clone()));
    let given = Overrides {
        n1: r.n1,
        ..Overrides::default()
    };
    let mut num = cycle_numerics(r.cells_of, &given, &ring, Some(&t));
    // The tiers' texture step is TEXTURE_CELLS cells: scale it to the run's travel.
    num.steps.texture_step *= r.travel / TEXTURE_CELLS;
    num.scheme = r.scheme;
    let (n1, step_deg) = (num.n1, num.steps.step_deg);
    let t0 = std::time::Instant::now();
    let o = CycleRun::new(&drive, ring, layout, num)
        .and_then(|run| run.run(CycleWatch::default()))
        .map_err(|e| e.to_string())?;
    let last = o.cycles.last().ok_or("no cycle ran")?;
    if !o.cyclic() {
        return Err(format!(
            "{n1} cells, {} a step: the cycle did not repeat itself",
            r.travel
        ));
    }
    Ok(Row {
        n1,
        step_deg,
        travel: r.travel,
        scheme: r.scheme,
        steps: last.steps,
        s_per_cycle: t0.elapsed().as_secs_f64() / o.cycles.len() as f64,
        cycles: o.cycles.len(),
        work: last.friction_work_j_per_m,
    })
}

fn scheme_name(s: TimeScheme) -> &'static str {
    match s {
        TimeScheme::Characteristic => "characteristic",
        TimeScheme::BackwardEuler => "backward Euler",
        TimeScheme::Bdf2 => "BDF2",
    }
}

pub fn main(args: &[String]) -> Result<(), String> {
    if let Some(k) = args.first() {
        let k: usize = k
            .parse()
            .ok()
            .filter(|&k| k < RUNS.len())
            .ok_or_else(|| format!("cycle-steps: row {k:?}: give 0 to {}", RUNS.len() - 1))?;
        // A second argument gives the cells along x1 instead of the row's.
        let n1 = match args.get(1) {
            Some(n) => Some(n.parse().map_err(|_| format!("cycle-steps: cells {n:?}"))?),
            None => RUNS[k].n1,
        };
        let r = run(&Run { n1, ..RUNS[k] })?;
        println!(
            "{} cells, {} a step, {}: {:?} J/m, {} steps a cycle, {:.1} s a cycle, {} cycles",
            r.n1,
            r.travel,
            scheme_name(r.scheme),
            r.work,
            r.steps,
            r.s_per_cycle,
            r.cycles
        );
        return Ok(());
    }
    let mut rows = Vec::new();
    for (k, spec) in RUNS.iter().enumerate() {
        let r = run(spec)?;
        eprintln!(
            "{k}: {} cells, {} a step, {}: {:.5} J/m, {:.1} s a cycle",
            r.n1,
            r.travel,
            scheme_name(r.scheme),
            r.work,
            r.s_per_cycle
        );
        rows.push(r);
    }
    // The finest characteristic run is the reference.
    let base = rows[3].work;
    let mut md = String::from(
        "# A textured liner's cycle against its time scheme, crank step and cells\n\n\
         `texopt-lab cycle-steps` (one core, ≈ 20 min): the example engine \
         (studies/engine_gasoline.toml), its liner uniformly textured with the paper's Case I \
         pocket, through the cycle until it repeats itself (docs/solver.md, \"The engine \
         cycle\"). The tiers' cells along x1 and crank steps at speed: `draft` 300 and 1°, \
         `fast` 600 and 0.5° (`paper` 1200 and 0.25°, on 32 cells across); the texture moves 2 \
         cells a step, the characteristic scheme's Courant number 1, where pockets pass under \
         the ring (all the stroke here). The last column is against the characteristic scheme \
         on 1200 × 8 cells at `fast`'s crank steps.\n\n\
         | scheme | cells along x1 | crank step (°) | texture's travel a step (cells) | steps a cycle | s a cycle | cycles | friction work (J/m) | vs 1200 cells |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {:.1} | {} | {:.4} | {:+.2} % |",
            scheme_name(r.scheme),
            r.n1,
            r.step_deg,
            r.travel,
            r.steps,
            r.s_per_cycle,
            r.cycles,
            r.work,
            100.0 * (r.work / base - 1.0)
        );
    }
    fs::create_dir_all("results/cycle_steps").map_err(|e| e.to_string())?;
    fs::write("results/cycle_steps/README.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    eprintln!("wrote results/cycle_steps/README.md");
    Ok(())
}
