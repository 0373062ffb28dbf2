//! What the crank step and the cells do to a textured liner's cycle (results/cycle_steps/):
//! `texopt-lab cycle-steps`.
//!
//! The example engine's liner uniformly textured with the paper's Case I pocket, through the
//! cycle at `draft` until it repeats itself, on draft's cells with the texture moving 2, 3 and
//! 4 cells a step, and on coarser cells at 2 (docs/solver.md, "The engine cycle"). One core,
//! one run after the other (≈ 6 minutes): the wall times are the study's too.

use std::fmt::Write as _;
use std::fs;

use texopt::model::case::Texture;
use texopt::model::liner_layout::LinerLayout;
use texopt::study::bench::example_engine;
use texopt::time::cycle::{cycle_numerics, CycleRun, Drive};
use texopt::time::{Fidelity, Overrides};

/// (cells along x1, None: draft's own; the texture's travel a step in cells).
const RUNS: [(Option<usize>, f64); 5] = [
    (None, 2.0),
    (None, 3.0),
    (None, 4.0),
    (Some(300), 2.0),
    (Some(200), 2.0),
];

/// One run's row: cells, travel, steps a cycle, seconds a cycle, cycles, work (J/m).
struct Row {
    n1: usize,
    cells: f64,
    steps: usize,
    s_per_cycle: f64,
    cycles: usize,
    work: f64,
}

fn run(n1: Option<usize>, cells: f64) -> Result<Row, String> {
    let engine = example_engine().map_err(|e| e.to_string())?;
    let drive = Drive::new(&engine);
    let ring = drive.ring_case();
    let t = Texture::circular(0.01, 0.06, 5.0);
    let layout = LinerLayout::uniform(0.1 * engine.file.engine.stroke_mm, Some(t.clone()));
    let given = Overrides {
        n1,
        ..Overrides::default()
    };
    let mut num = cycle_numerics(Fidelity::Draft, &given, &ring, Some(&t));
    // Draft's rule is 2 cells a step: scale its texture step to `cells`.
    num.steps.texture_step *= cells / 2.0;
    let n1 = num.n1;
    let t0 = std::time::Instant::now();
    let o = CycleRun::new(&drive, ring, layout, num)
        .and_then(|r| r.run(&mut |_| {}, &mut |_| {}))
        .map_err(|e| e.to_string())?;
    let last = o.cycles.last().ok_or("no cycle ran")?;
    if !o.cyclic {
        return Err(format!(
            "{n1} cells, {cells} a step: the cycle did not repeat itself"
        ));
    }
    Ok(Row {
        n1,
        cells,
        steps: last.steps,
        s_per_cycle: t0.elapsed().as_secs_f64() / o.cycles.len() as f64,
        cycles: o.cycles.len(),
        work: last.friction_work_j_per_m,
    })
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let mut rows = Vec::new();
    for (n1, cells) in RUNS {
        let r = run(n1, cells)?;
        eprintln!(
            "{} cells, {} a step: {:?} J/m, {} steps a cycle, {:.1} s a cycle",
            r.n1, r.cells, r.work, r.steps, r.s_per_cycle
        );
        rows.push(r);
    }
    let base = rows[0].work;
    let mut md = String::from(
        "# A textured liner's cycle against its crank step and cells\n\n\
         `texopt-lab cycle-steps` (one core): the example engine (studies/engine_gasoline.toml), \
         its liner uniformly textured with the paper's Case I pocket, at `draft` until the \
         cycle repeats itself (docs/solver.md, \"The engine cycle\").\n\n\
         | cells along x1 | texture's travel a step (cells) | steps a cycle | s a cycle | cycles | friction work (J/m) | vs the first row |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.1} | {} | {:.4} | {:+.2} % |",
            r.n1,
            r.cells,
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
