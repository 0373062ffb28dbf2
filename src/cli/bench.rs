//! `texopt bench`: the fixed benchmark cases, timed, into results/bench/.

use super::{BenchArgs, CmdError};
use crate::study::bench::{
    cycle_cases, default_runs, run_case, run_cycle_case, BenchCase, BenchRow, CycleBenchCase,
    CycleBenchRow, CYCLE_FIDELITY,
};
use crate::time::cycle::CycleSummary;
use crate::time::{Fidelity, Numerics, Overrides};

/// Most runs of each case `--repeat` takes: more is a typo, not a benchmark.
const MAX_REPEAT: usize = 100;

pub(super) fn run(a: &BenchArgs) -> Result<i32, CmdError> {
    let all = crate::study::bench::cases();
    let cycles = cycle_cases();
    check_choice(a, &all, &cycles)?;
    let out = out_path(a)?;
    let runs: Vec<(&str, Fidelity)> = match a.fidelity {
        Some(f) => all.iter().map(|c| (c.name, f)).collect(),
        None => default_runs(),
    };
    let mut rows = Vec::new();
    let mut failed = 0;
    for (name, fidelity) in runs
        .into_iter()
        .filter(|(n, _)| a.cases.is_empty() || a.cases.iter().any(|c| c == n))
    {
        let c = all
            .iter()
            .find(|c| c.name == name)
            .expect("a benchmark case");
        match bench_one(a, c, fidelity) {
            Some(row) => rows.push(row),
            None => failed += 1,
        }
    }
    // The cycle cases run only when named: the uniform one takes minutes.
    let mut cycle_rows = Vec::new();
    for c in cycles
        .iter()
        .filter(|c| a.cases.iter().any(|n| n == c.name))
    {
        match bench_cycle(a, c) {
            Some(row) => cycle_rows.push(row),
            None => failed += 1,
        }
    }
    write_json(a, &out, &rows, &cycle_rows)?;
    eprintln!("wrote {}", out.display());
    Ok(if failed > 0 { 1 } else { 0 })
}

/// The cases asked for exist, and each runs at least once and at most `MAX_REPEAT` times.
fn check_choice(
    a: &BenchArgs,
    all: &[BenchCase],
    cycles: &[CycleBenchCase],
) -> Result<(), CmdError> {
    for name in &a.cases {
        let cycle = cycles.iter().any(|c| c.name == name);
        if !cycle && !all.iter().any(|c| c.name == name) {
            let names: Vec<_> = all
                .iter()
                .map(|c| c.name)
                .chain(cycles.iter().map(|c| c.name))
                .collect();
            return Err(CmdError::Input(format!(
                "--case {name}: no such benchmark case; choose from {}",
                names.join(", ")
            )));
        }
        if let (true, Some(f)) = (cycle, a.fidelity) {
            if f != CYCLE_FIDELITY {
                return Err(CmdError::Input(format!(
                    "--fidelity {} --case {name}: the cycle cases run at {} (their finer tier is part of the case); drop --fidelity or run the cycle case on its own",
                    f.name(),
                    CYCLE_FIDELITY.name()
                )));
            }
        }
    }
    if a.repeat == 0 {
        return Err(CmdError::Input(
            "--repeat 0: each case must run at least once; give 1 or more".into(),
        ));
    }
    if a.repeat > MAX_REPEAT {
        return Err(CmdError::Input(format!(
            "--repeat {}: at most {MAX_REPEAT} runs of each case (the best of a few is the benchmark's time)",
            a.repeat
        )));
    }
    Ok(())
}

/// Where the JSON goes, checked writable before anything runs.
fn out_path(a: &BenchArgs) -> Result<std::path::PathBuf, CmdError> {
    let out = a.out_path();
    let dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    // The default directory is made; one the user names must exist.
    if a.out.is_none() {
        std::fs::create_dir_all(dir)
            .map_err(|e| CmdError::Other(format!("cannot create {}: {e}", dir.display())))?;
    }
    if !dir.is_dir() {
        return Err(CmdError::Input(format!(
            "--out {}: the directory {} does not exist; create it or choose another path",
            out.display(),
            dir.display()
        )));
    }
    crate::output::check_writable(&out)
        .map_err(|why| CmdError::Input(format!("--out {}: {why}", out.display())))?;
    Ok(out)
}

/// One case at one fidelity, timed and printed; None if it failed (printed as such).
fn bench_one(a: &BenchArgs, c: &BenchCase, fidelity: Fidelity) -> Option<(BenchRow, Numerics)> {
    let given = Overrides {
        start: Some(a.start),
        approach: a.approach.map(|x| x.0),
        ..Overrides::default()
    };
    let num = crate::time::resolve(fidelity, &given, &c.case);
    eprintln!(
        "running {} at {} ({}) …",
        c.name,
        fidelity.name(),
        c.case.label()
    );
    match run_case(c, fidelity, &num, a.repeat) {
        Ok(row) => {
            println!("{}", row.line());
            Some((row, num))
        }
        Err(e) => {
            println!("{:17} FAILED: {e}", c.name);
            None
        }
    }
}

/// One cycle case, timed and printed, each cycle's end on stderr as it comes; None if it
/// failed (printed as such).
fn bench_cycle(a: &BenchArgs, c: &CycleBenchCase) -> Option<CycleBenchRow> {
    eprintln!("running {} at {} …", c.name, CYCLE_FIDELITY.name());
    let t0 = std::time::Instant::now();
    let mut progress = |f: Fidelity, s: &CycleSummary| {
        eprintln!(
            "[{:7.1} s] {} at {}: cycle {}, {} steps, friction work {:.5} J/m (change {:.2e})",
            t0.elapsed().as_secs_f64(),
            c.name,
            f.name(),
            1 + s.index,
            s.steps,
            s.friction_work_j_per_m,
            s.work_change
        )
    };
    match run_cycle_case(c, a.repeat, &mut progress) {
        Ok(row) => {
            println!("{}", row.line());
            Some(row)
        }
        Err(e) => {
            println!("{:17} FAILED: {e}", c.name);
            None
        }
    }
}

/// The benchmark's JSON: the machine and settings, then each case's row with its numerics,
/// and the cycle cases' rows if any ran.
fn write_json(
    a: &BenchArgs,
    out: &std::path::Path,
    rows: &[(BenchRow, Numerics)],
    cycle_rows: &[CycleBenchRow],
) -> Result<(), CmdError> {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let mut report = serde_json::json!({
        "texopt_version": env!("CARGO_PKG_VERSION"),
        "unix_time": secs,
        "threads_available": std::thread::available_parallelism().map_or(1, |n| n.get()),
        "threads_used": 1,
        "repeat": a.repeat,
        "start": a.start,
        "cases": rows
            .iter()
            .map(|(row, num)| {
                let mut v = serde_json::to_value(row).unwrap_or_default();
                v["numerics"] = serde_json::to_value(num).unwrap_or_default();
                v
            })
            .collect::<Vec<_>>(),
    });
    if !cycle_rows.is_empty() {
        report["cycle_cases"] = serde_json::to_value(cycle_rows).unwrap_or_default();
    }
    let json = serde_json::to_string_pretty(&report).map_err(|e| CmdError::Other(e.to_string()))?;
    crate::output::write(out, json).map_err(|e| CmdError::Other(format!("--out: {e}")))
}
