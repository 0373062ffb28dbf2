//! Where a benchmark run spends its time, window by window: for each periodic-test window
//! of each mesh (the coarse approach, then the tier's own), the film iterations, band
//! factorisations and rows eliminated per step, the wall time per step, Z̄, f̄ and the
//! periodic-error estimate the run stops on. A Markdown table on stdout.
//!
//!     cargo run --release --example where_time_goes                       # Case III, paper tier
//!     cargo run --release --example where_time_goes -- case-I fast
//!
//! The same run as `texopt bench --case NAME --fidelity TIER` (from the paper's start), so
//! its outcome is the benchmark's to the bit; only the bookkeeping is added.

use std::cell::RefCell;
use std::time::Instant;
use texopt::bench::cases;
use texopt::case::{Fidelity, Start};
use texopt::run::{run_transient_with, Progress, Transient};

/// Tallies of the steps of one window.
#[derive(Default)]
struct Tally {
    steps: usize,
    iterations: usize,
    factorisations: usize,
    rows: usize,
}

fn main() {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "case-III".into());
    let tier = args.next().unwrap_or_else(|| "paper".into());
    let all = cases();
    let Some(bench) = all.iter().find(|c| c.name == name) else {
        let names: Vec<_> = all.iter().map(|c| c.name).collect();
        eprintln!("no benchmark case {name}; choose from {}", names.join(", "));
        std::process::exit(2);
    };
    let fidelity = match tier.as_str() {
        "draft" => Fidelity::Draft,
        "fast" => Fidelity::Fast,
        "paper" => Fidelity::Paper,
        "fine" => Fidelity::Fine,
        _ => {
            eprintln!("no fidelity tier {tier}; choose from draft, fast, paper, fine");
            std::process::exit(2);
        }
    };
    let case = &bench.case;
    if case.texture.is_none() {
        eprintln!("{name} is untextured: it is solved as a steady 1D problem, no transient");
        std::process::exit(2);
    }
    let mut num = fidelity.numerics_for(case);
    num.start = Start::Paper;

    println!(
        "# {name} ({}) at `{tier}`, from the paper's start\n",
        case.label()
    );
    println!("| mesh | window ends at period | it/step | factorisations/step | rows eliminated/step | ms/step | Z̄ (µm) | f̄ | periodic error |");
    println!("|---|---|---|---|---|---|---|---|---|");
    // Every step adds to the window's tally, every window end (of either mesh) prints a row
    // and starts a new tally.
    let tally = RefCell::new(Tally::default());
    let mut last = Instant::now();
    let mesh = |t: &Transient| format!("{}×{}", t.scene.grid.n1, t.scene.grid.n2);
    let current_mesh = RefCell::new(String::new());
    let result = run_transient_with(
        case,
        &num,
        false,
        &[],
        &mut |p: &Progress| {
            let w = tally.take();
            let n = w.steps.max(1) as f64;
            println!(
                "| {} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {:.6} | {:.7} | {:.2e} |",
                current_mesh.borrow(),
                p.period,
                w.iterations as f64 / n,
                w.factorisations as f64 / n,
                w.rows as f64 / n,
                1e3 * last.elapsed().as_secs_f64() / n,
                p.z_mean,
                p.f_mean,
                p.periodic_error
            );
            last = Instant::now();
        },
        &mut |t: &Transient| {
            let mut w = tally.borrow_mut();
            w.steps += 1;
            w.iterations += t.last.iterations;
            w.factorisations += t.last.factorisations;
            w.rows += t.last.eliminated_rows;
            *current_mesh.borrow_mut() = mesh(t);
        },
    );
    let outcome = result
        .unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(1);
        })
        .outcome;
    println!(
        "\nf̄ = {:.17}, C_min = {:.17} µm, {} steps ({} coarse), {} periods, {:.1} s (with this table's bookkeeping)",
        outcome.f_mean,
        outcome.c_min,
        outcome.steps,
        outcome.approach_steps,
        outcome.periods,
        outcome.wall_time_s
    );
}
