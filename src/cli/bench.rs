//! `texopt bench`: the fixed benchmark cases, timed, into results/bench/.

use super::{BenchArgs, CmdError};
use crate::study::bench::{default_runs, run_case, BenchCase, BenchRow};
use crate::time::{Fidelity, Numerics, Overrides};

/// Most runs of each case `--repeat` takes: more is a typo, not a benchmark.
const MAX_REPEAT: usize = 100;

pub(super) fn run(a: &BenchArgs) -> Result<i32, CmdError> {
    let all = crate::study::bench::cases();
    check_choice(a, &all)?;
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
    write_json(a, &out, &rows)?;
    eprintln!("wrote {}", out.display());
    Ok(if failed > 0 { 1 } else { 0 })
}

/// The cases asked for exist, and each runs at least once and at most `MAX_REPEAT` times.
fn check_choice(a: &BenchArgs, all: &[BenchCase]) -> Result<(), CmdError> {
    for name in &a.cases {
        if !all.iter().any(|c| c.name == name) {
            let names: Vec<_> = all.iter().map(|c| c.name).collect();
            return Err(CmdError::Input(format!(
                "--case {name}: no such benchmark case; choose from {}",
                names.join(", ")
            )));
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

/// The benchmark's JSON: the machine and settings, then each case's row with its numerics.
fn write_json(
    a: &BenchArgs,
    out: &std::path::Path,
    rows: &[(BenchRow, Numerics)],
) -> Result<(), CmdError> {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let report = serde_json::json!({
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
    let json = serde_json::to_string_pretty(&report).map_err(|e| CmdError::Other(e.to_string()))?;
    crate::output::write(out, json).map_err(|e| CmdError::Other(format!("--out: {e}")))
}
