//! Where a benchmark run spends its time, window by window: for each periodic-test window
//! of each mesh (the coarse approach, then the tier's own), the film iterations, band
//! factorisations and rows eliminated per step, the wall time per step, Z̄, f̄ and the
//! periodic-error estimate the run stops on. A Markdown table on stdout.
//!
//!     cargo run --release --example where_time_goes                       # Case III, paper tier
//!     cargo run --release --example where_time_goes -- case-I fast
//!     cargo run --release --example where_time_goes -- case-III paper --cycles 2
//!
//! The same run as `texopt bench --case NAME --fidelity TIER` (from the paper's start), so
//! its outcome is the benchmark's to the bit; only the bookkeeping is added. `--cycles N`
//! runs the tier's own mesh on the experimental `multigrid` solver with at most N V-cycles a
//! linear solve (the coarse approach stays on the band LU, as in `texopt`): its table counts
//! multigrid setups and V-cycles a step where the band LU's counts factorisations and rows.
//! The last column is the system CPU time a step (Linux, from /proc): the kernel's cost of
//! the memory the run touches for the first time, mostly the period's kept factors.

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
    cycles: usize,
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

fn main() {
    let mut positional = Vec::new();
    let mut cycles = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--cycles" {
            match args.next().and_then(|n| n.parse::<usize>().ok()) {
                Some(n) if n > 0 => cycles = Some(n),
                _ => {
                    eprintln!("--cycles needs a whole number of V-cycles ≥ 1, e.g. --cycles 2");
                    std::process::exit(2);
                }
            }
        } else {
            positional.push(a);
        }
    }
    let mut positional = positional.into_iter();
    let name = positional.next().unwrap_or_else(|| "case-III".into());
    let tier = positional.next().unwrap_or_else(|| "paper".into());
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
    if let Some(n) = cycles {
        num.solver = texopt::film::Method::Multigrid;
        num.cycles = n;
    }
    let (solves, per_solve) = if cycles.is_some() {
        ("multigrid setups", "V-cycles")
    } else {
        ("factorisations", "rows eliminated")
    };

    let solver = cycles.map_or(String::new(), |n| {
        let unit = if n == 1 { "V-cycle" } else { "V-cycles" };
        format!(", `multigrid` ≤ {n} {unit} a solve")
    });
    println!(
        "# {name} ({}) at `{tier}`{solver}, from the paper's start\n",
        case.label()
    );
    println!("| mesh | window ends at period | it/step | {solves}/step | {per_solve}/step | ms/step | Z̄ (µm) | f̄ | periodic error | system ms/step |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    // Every step adds to the window's tally, every window end (of either mesh) prints a row
    // and starts a new tally.
    let tally = RefCell::new(Tally::default());
    let mut last = Instant::now();
    let mut last_sys = system_time_s();
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
            let sys = system_time_s();
            println!(
                "| {} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {:.6} | {:.7} | {:.2e} | {:.2} |",
                current_mesh.borrow(),
                p.period,
                w.iterations as f64 / n,
                w.factorisations as f64 / n,
                if cycles.is_some() { w.cycles } else { w.rows } as f64 / n,
                1e3 * last.elapsed().as_secs_f64() / n,
                p.z_mean,
                p.f_mean,
                p.periodic_error,
                1e3 * (sys - last_sys) / n
            );
            last = Instant::now();
            last_sys = sys;
        },
        &mut |t: &Transient| {
            let mut w = tally.borrow_mut();
            w.steps += 1;
            w.iterations += t.last.iterations;
            w.factorisations += t.last.factorisations;
            w.rows += t.last.eliminated_rows;
            w.cycles += t.last.cycles;
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
        "\nf̄ = {:.17}, C_min = {:.17} µm, {} steps ({} coarse), {} periods, {:.1} s (with this table's bookkeeping), of which {:.1} s system time",
        outcome.f_mean,
        outcome.c_min,
        outcome.steps,
        outcome.approach_steps,
        outcome.periods,
        outcome.wall_time_s,
        system_time_s()
    );
}
