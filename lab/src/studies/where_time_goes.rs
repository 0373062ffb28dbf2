//! Where a benchmark run spends its time, window by window (`texopt-lab where-time-goes
//! [CASE [TIER]]`, default Case III at `paper`): for each periodic-test window of each mesh
//! (the coarse approach, then the tier's own), the film iterations, band factorisations and
//! rows eliminated per step, the wall time per step, Z̄, f̄ and the periodic-error estimate
//! the run stops on; a Markdown table on stdout. The same run as `texopt bench --case NAME
//! --fidelity TIER` (from the paper's start), so its outcome is the benchmark's to the bit;
//! only the bookkeeping is added. The last column is the system CPU time a step (Linux, from
//! /proc): the kernel's cost of the memory the run touches for the first time, mostly the
//! period's kept factors.

use std::cell::RefCell;
use std::time::Instant;
use texopt::study::bench::cases;
use texopt::time::{simulate_with, Fidelity, Progress, RunOptions, Start, Transient, Watch};

/// Tallies of the steps of one window.
#[derive(Default)]
struct Tally {
    steps: usize,
    iterations: usize,
    factorisations: usize,
    rows: usize,
}

/// System CPU time of this process so far (s), from /proc/self/stat (0 where unreadable).
fn system_time_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the parenthesised command name: state is field 3, stime field 15.
    let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let ticks: f64 = after
        .split_whitespace()
        .nth(12)
        .and_then(|t| t.parse().ok())
        .unwrap_or(0.0);
    // The kernel's USER_HZ is 100 on every Linux this runs on.
    ticks / 100.0
}

/// `texopt-lab where-time-goes [CASE [TIER]]`.
pub fn main(args: &[String]) -> Result<(), String> {
    let name = args.first().cloned().unwrap_or_else(|| "case-III".into());
    let tier = args.get(1).cloned().unwrap_or_else(|| "paper".into());
    let all = cases();
    let Some(bench) = all.iter().find(|c| c.name == name) else {
        let names: Vec<_> = all.iter().map(|c| c.name).collect();
        return Err(format!(
            "no benchmark case {name}; choose from {}",
            names.join(", ")
        ));
    };
    let Some(fidelity) = Fidelity::ALL.into_iter().find(|f| f.name() == tier) else {
        return Err(format!(
            "no fidelity tier {tier}; choose from draft, fast, paper, fine"
        ));
    };
    let case = &bench.case;
    if case.texture.is_none() {
        return Err(format!(
            "{name} is untextured: it is solved as a steady 1D problem, no transient"
        ));
    }
    let mut num = fidelity.numerics_for(case);
    num.start = Start::Paper;
    println!(
        "# {name} ({}) at `{tier}`, from the paper's start\n",
        case.label()
    );
    println!("| mesh | window ends at period | it/step | factorisations/step | rows eliminated/step | ms/step | Z̄ (µm) | f̄ | periodic error | system ms/step |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    // Every step adds to the window's tally, every window end (of either mesh) prints a row
    // and starts a new tally.
    let tally = RefCell::new(Tally::default());
    let mut last = Instant::now();
    let mut last_sys = system_time_s();
    let mesh = |t: &Transient| format!("{}×{}", t.scene().grid.n1, t.scene().grid.n2);
    let current_mesh = RefCell::new(String::new());
    let mut on_window = |p: &Progress| {
        let w = tally.take();
        let n = w.steps.max(1) as f64;
        let sys = system_time_s();
        println!(
            "| {} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {:.6} | {:.7} | {:.2e} | {:.2} |",
            current_mesh.borrow(),
            p.period,
            w.iterations as f64 / n,
            w.factorisations as f64 / n,
            w.rows as f64 / n,
            1e3 * last.elapsed().as_secs_f64() / n,
            p.z_mean,
            p.f_mean,
            p.periodic_error,
            1e3 * (sys - last_sys) / n
        );
        last = Instant::now();
        last_sys = sys;
    };
    let mut on_step = |t: &Transient| {
        let mut w = tally.borrow_mut();
        w.steps += 1;
        w.iterations += t.last().iterations;
        w.factorisations += t.last().factorisations;
        w.rows += t.last().eliminated_rows;
        *current_mesh.borrow_mut() = mesh(t);
    };
    let mut watch = Watch {
        on_window: Some(&mut on_window),
        on_step: Some(&mut on_step),
    };
    let outcome = simulate_with(case, &num, &RunOptions::default(), &mut watch)
        .map_err(|e| e.to_string())?
        .outcome;
    println!(
        "\nf̄ = {:.17}, C_min = {:.17} µm, {} steps ({} coarse), {} periods, {:.1} s (with this table's bookkeeping), of which {:.1} s system time",
        outcome.f_mean,
        outcome.c_min,
        outcome.steps,
        outcome.approach_steps,
        outcome.periods,
        outcome.wall_time_s,
        system_time_s()
    );
    Ok(())
}
