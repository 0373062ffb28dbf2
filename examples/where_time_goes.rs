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
use texopt::run::{ApproachDone, Progress, Transient};

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
    let started = Instant::now();
    // Each stage runs through `run_with`'s callbacks: every step adds to the window's tally,
    // every window end prints a row and starts a new tally.
    let run_stage = |t: &mut Transient, num: &texopt::case::Numerics| {
        let mesh = format!("{}×{}", num.n1, num.n2);
        let tally = RefCell::new(Tally::default());
        let mut last = Instant::now();
        let result = t.run_with(
            num,
            false,
            &mut |p: &Progress| {
                let w = tally.take();
                let n = w.steps.max(1) as f64;
                println!(
                    "| {mesh} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {:.6} | {:.7} | {:.2e} |",
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
            },
        );
        result.unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(1);
        })
    };

    let outcome = match num.approach_numerics(case) {
        Some(mut coarse) => {
            coarse.t_max = 0.5 * num.t_max;
            let mut t = Transient::new(case, &coarse);
            let r = run_stage(&mut t, &coarse);
            let done = ApproachDone {
                steps: r.outcome.steps,
                periods: r.outcome.periods,
                wall_time_s: r.outcome.wall_time_s,
            };
            let mut fine = t.refined(&num, done);
            run_stage(&mut fine, &num).outcome
        }
        None => {
            let mut t = Transient::new(case, &num);
            run_stage(&mut t, &num).outcome
        }
    };
    println!(
        "\nf̄ = {:.17}, C_min = {:.17} µm, {} steps ({} coarse), {} periods, {:.1} s (with this table's bookkeeping)",
        outcome.f_mean,
        outcome.c_min,
        outcome.steps,
        outcome.approach_steps,
        outcome.periods,
        started.elapsed().as_secs_f64()
    );
}
