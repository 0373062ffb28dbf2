//! Studies on a real Slurm (a single node: `ci/slurm-up.sh`, which `.ci/run` starts and
//! points these tests at with `TEXOPT_SLURM=1` and `SLURM_CONF`). Without it they say so and
//! pass: the other tests of sharding and merging need no cluster (tests/study.rs, and the
//! unit tests of study::shard and study::cache_merge).

mod common;

use common::{scratch, texopt};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

fn slurm_up() -> bool {
    if std::env::var_os("TEXOPT_SLURM").is_some() {
        return true;
    }
    eprintln!(
        "skipped: no Slurm here (run ci/slurm-up.sh and set TEXOPT_SLURM=1, as .ci/run does)"
    );
    false
}

/// Runs texopt in `dir` (the scripts' working directory).
fn texopt_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_texopt"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A job's state as `scontrol` tells it (COMPLETED, RUNNING, PENDING, FAILED, …).
fn state(job: &str) -> String {
    let out = Command::new("scontrol")
        .args(["show", "job", job])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let states: Vec<&str> = text
        .split_whitespace()
        .filter_map(|w| w.strip_prefix("JobState="))
        .collect();
    // An array shows one record per task: finished when every one is.
    if states.iter().all(|s| *s == "COMPLETED") && !states.is_empty() {
        "COMPLETED".into()
    } else if let Some(s) = states
        .iter()
        .find(|s| **s != "COMPLETED" && **s != "PENDING" && **s != "RUNNING")
    {
        s.to_string()
    } else {
        states.first().map_or("GONE".into(), |s| s.to_string())
    }
}

fn wait_for(job: &str, logs: &Path) {
    let t0 = Instant::now();
    loop {
        let s = state(job);
        match s.as_str() {
            "COMPLETED" => return,
            "PENDING" | "RUNNING" | "COMPLETING" | "CONFIGURING" => {}
            other => {
                let logs: Vec<String> = std::fs::read_dir(logs)
                    .map(|d| {
                        d.filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok())
                            .collect()
                    })
                    .unwrap_or_default();
                panic!("job {job} ended {other}; logs:\n{}", logs.join("\n---\n"));
            }
        }
        assert!(
            t0.elapsed() < Duration::from_secs(600),
            "job {job} still {s}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn study_file(dir: &Path, name: &str, body: &str) -> String {
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(
        &file,
        format!(
            "[study]\nname = \"{name}\"\nfidelity = \"draft\"\nuntextured = true\n{body}\n[report]\ndir = \"{}\"\n",
            dir.join("report").display()
        ),
    )
    .unwrap();
    file.to_str().unwrap().to_string()
}

/// hash → outcome without its wall time, for every entry of a cache.
fn entries(cache: &Path) -> BTreeMap<String, String> {
    let (code, out, err) = texopt(&["cache", "export", "--cache", cache.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    out.lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            let hash = v["hash"].as_str().unwrap().to_string();
            if let Some(o) = v["outcome"].as_object_mut() {
                o.remove("wall_time_s");
            }
            (
                hash,
                format!("{} {} {}", v["status"], v["outcome"], v["reason"]),
            )
        })
        .collect()
}

/// The report's CSV without the wall-time column.
fn csv_without_wall_time(path: &Path) -> Vec<Vec<String>> {
    let mut rd = csv::Reader::from_path(path).unwrap();
    let head = rd.headers().unwrap().clone();
    let wall = head.iter().position(|h| h == "wall_time_s").unwrap();
    let mut rows = vec![head.iter().map(str::to_string).collect::<Vec<_>>()];
    for r in rd.records() {
        let r = r.unwrap();
        rows.push(
            r.iter()
                .enumerate()
                .filter(|(i, _)| *i != wall)
                .map(|(_, x)| x.to_string())
                .collect(),
        );
    }
    rows
}

/// "array job A (…), merge-and-report job M (…)" → (A, M).
fn job_ids(stdout: &str) -> (String, String) {
    let words: Vec<&str> = stdout.split_whitespace().collect();
    let id_after = |w: &str| {
        let i = words.iter().position(|x| *x == w).unwrap();
        words[i + 2].to_string() // "<w> job <id>"
    };
    (id_after("array"), id_after("merge-and-report"))
}

/// `texopt study FILE --slurm RUN --tasks N --submit` in `dir`, then waits for the array and
/// the merge job to end.
fn submit_and_wait(dir: &Path, file: &str, run: &Path, tasks: usize) {
    let tasks = tasks.to_string();
    let (code, out, err) = texopt_in(
        dir,
        &[
            "study",
            file,
            "--slurm",
            run.to_str().unwrap(),
            "--tasks",
            &tasks,
            "--submit",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let (array, merge) = job_ids(&out);
    wait_for(&array, &run.join("logs"));
    wait_for(&merge, &run.join("logs"));
}

#[test]
fn a_study_on_slurm_gives_the_local_report_and_cache_bit_for_bit() {
    if !slurm_up() {
        return;
    }
    let dir = scratch("slurm-study");
    let file = study_file(
        &dir,
        "sl12",
        "[parameters]\nR = [0.8, 3.2, 12.8]\nl1 = [0.01, 0.03]\nper = 0.06\ndepth = [2, 5]\n[numerics]\nn1 = 128\nn2 = 4",
    );
    let run = dir.join("run");
    let t0 = Instant::now();
    submit_and_wait(&dir, &file, &run, 3);
    let on_slurm = t0.elapsed().as_secs_f64();
    let csv = dir.join("report/sl12.csv");
    let slurm_csv = csv_without_wall_time(&csv);
    let slurm_cache = entries(&run.join("merged.sqlite"));

    let t0 = Instant::now();
    let local = dir.join("local.sqlite");
    let (code, _, err) = texopt_in(&dir, &["study", &file, "--cache", local.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    eprintln!(
        "15 cases: {on_slurm:.1} s through Slurm (3 tasks and the merge), {:.1} s locally",
        t0.elapsed().as_secs_f64()
    );
    assert_eq!(slurm_cache.len(), 15);
    assert_eq!(
        slurm_cache,
        entries(&local),
        "the merged cache is the local one"
    );
    assert_eq!(
        slurm_csv,
        csv_without_wall_time(&csv),
        "the report is the local one"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_cancelled_task_resubmitted_loses_nothing_and_computes_nothing_twice() {
    if !slurm_up() {
        return;
    }
    let dir = scratch("slurm-cancel");
    // One task of 14 cases at the draft tier's own mesh (≈ 0.3 s each).
    let file = study_file(
        &dir,
        "slc",
        "[parameters]\nR = [3.2, 12.8]\nl1 = [0.02, 0.03]\nper = 0.06\ndepth = [2, 5, 8]",
    );
    let run = dir.join("run");
    let (code, out, err) = texopt_in(
        &dir,
        &[
            "study",
            &file,
            "--slurm",
            run.to_str().unwrap(),
            "--tasks",
            "1",
            "--submit",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let (array, merge) = job_ids(&out);
    let share = run.join("caches/share-1.sqlite");
    let stored = || {
        rusqlite::Connection::open_with_flags(&share, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
            .and_then(|c| {
                c.query_row("SELECT count(*) FROM evaluations", [], |r| {
                    r.get::<_, i64>(0)
                })
            })
            .unwrap_or(0)
    };
    let t0 = Instant::now();
    while stored() < 3 {
        assert!(
            t0.elapsed() < Duration::from_secs(300),
            "the task stored nothing"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    Command::new("scancel")
        .args([&array, &merge])
        .status()
        .unwrap();
    while !matches!(state(&array).as_str(), "CANCELLED" | "GONE" | "COMPLETED") {
        std::thread::sleep(Duration::from_millis(100));
    }
    std::thread::sleep(Duration::from_millis(500));
    let before = entries(&share);
    assert!(
        before.len() < 14,
        "cancelled too late to test: {} stored",
        before.len()
    );

    // The task alone again, then the merge.
    let sub = |args: &[&str]| {
        let out = Command::new("sbatch")
            .arg("--parsable")
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    };
    let again = sub(&["--array=1", run.join("array.sbatch").to_str().unwrap()]);
    wait_for(&again, &run.join("logs"));
    let log = std::fs::read_to_string(run.join("logs/task-1.log")).unwrap();
    let expect = format!(
        "14 cases: {} in the cache, {} to compute",
        before.len(),
        14 - before.len()
    );
    assert!(
        log.contains(&expect),
        "expected {expect:?} in the log:\n{log}"
    );
    let after = entries(&share);
    assert_eq!(after.len(), 14);
    for (k, v) in &before {
        assert_eq!(
            after.get(k),
            Some(v),
            "an entry finished before the cancel changed"
        );
    }
    let m = sub(&[run.join("merge.sbatch").to_str().unwrap()]);
    wait_for(&m, &run.join("logs"));
    assert_eq!(entries(&run.join("merged.sqlite")), after);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_study_under_paths_with_quotes_dollars_and_patterns_runs_on_slurm() {
    if !slurm_up() {
        return;
    }
    // sbatch reads the #SBATCH lines (its own quoting, %-patterns in the logs' paths), bash
    // the rest: neither may split these paths or run what is in them.
    let payload = "a b 'q' \"dq\" $(touch PWNED) `touch BQ` #h %j %a";
    let root = scratch("slurm-quoting");
    let dir = root.join(format!("cwd {payload}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("slq {payload}.toml"));
    std::fs::write(
        &path,
        "[study]\nname = \"slq\"\nfidelity = \"draft\"\nuntextured = true\n\
         [parameters]\nR = [3.2]\nl1 = [0.01, 0.03]\nper = 0.06\ndepth = [5]\n\
         [report]\ndir = \"report\"\n",
    )
    .unwrap();
    let file = path.to_str().unwrap().to_string();
    let run = dir.join(format!("run {payload}"));
    submit_and_wait(&dir, &file, &run, 2);
    for log in ["task-1.log", "task-2.log", "merge.log"] {
        assert!(run.join("logs").join(log).is_file(), "{log} not in logs/");
    }
    assert_eq!(entries(&run.join("merged.sqlite")).len(), 3);
    assert!(dir.join("report/slq.csv").is_file());
    for name in ["PWNED", "BQ"] {
        assert!(!dir.join(name).exists() && !run.join(name).exists());
    }
    let _ = std::fs::remove_dir_all(root);
}

/// `texopt cycle e.toml` with `mode` (`--bands …`, or none: the zones) and the least search,
/// into `cache` and `out`, and `more`: its report `base`, wall times removed (the zones'
/// report runs its liners where the command runs).
fn cycle_search(
    dir: &Path,
    (mode, base): (&[&str], &str),
    (cache, out): (&Path, &Path),
    more: &[&str],
) -> serde_json::Value {
    let mut args = vec!["cycle", "e.toml", "--mesh", "96x4"];
    args.extend(mode);
    args.extend(common::QUICK_SEARCH);
    args.extend([
        "--cache",
        cache.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    args.extend(more);
    let (code, _, err) = texopt_in(dir, &args);
    assert_eq!(code, 0, "{err}");
    let mut r = common::report_without_wall_time(out, base);
    for l in r["liners"].as_array_mut().into_iter().flatten() {
        l.as_object_mut().unwrap().remove("wall_s");
    }
    r
}

/// The band search's report.
fn band_search(dir: &Path, cache: &Path, out: &Path, more: &[&str]) -> serde_json::Value {
    let bands: &[&str] = &["--bands", "--band-min", "6"];
    cycle_search(dir, (bands, "cycle_t_bands"), (cache, out), more)
}

#[test]
fn a_band_search_through_slurm_finds_what_it_finds_here_bit_for_bit() {
    if !slurm_up() {
        return;
    }
    let dir = scratch("slurm-bands");
    std::fs::write(dir.join("e.toml"), common::mapped_engine()).unwrap();
    let t0 = Instant::now();
    let (local, here) = (dir.join("local.sqlite"), dir.join("here"));
    let report_here = band_search(&dir, &local, &here, &[]);
    let on_two_cores = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let (merged, there) = (dir.join("merged.sqlite"), dir.join("there"));
    let run = dir.join("run");
    let slurm = ["--slurm", run.to_str().unwrap(), "--tasks", "2"];
    let report_there = band_search(&dir, &merged, &there, &slurm);
    eprintln!(
        "band search: {:.1} s through Slurm (2 tasks a step), {on_two_cores:.1} s here",
        t0.elapsed().as_secs_f64()
    );
    assert_eq!(report_here, report_there);
    // Every run of the search, in both caches, alike to the last bit.
    let runs = entries(&local);
    assert!(runs.len() >= 10, "{} runs", runs.len());
    assert_eq!(runs, entries(&merged));
    assert!(run.join("logs/batch-1-task-2.log").is_file());

    // A task under other settings (another mesh) refuses the batch: its keys differ.
    let batch = run.join("batches/batch-1.json");
    let (code, _, err) = texopt_in(
        &dir,
        &[
            "cycle",
            "e.toml",
            "--bands",
            "--mesh",
            "96x8",
            "--fidelity",
            "draft",
            "--answer",
            batch.to_str().unwrap(),
            "--share",
            "1/2",
            "--cache",
            dir.join("other.sqlite").to_str().unwrap(),
        ],
    );
    assert_ne!(code, 0);
    assert!(err.contains("another key than the batch's"), "{err}");
}

/// The zone search's report.
fn zone_search(dir: &Path, cache: &Path, out: &Path, more: &[&str]) -> serde_json::Value {
    cycle_search(dir, (&[], "cycle_t"), (cache, out), more)
}

#[test]
fn a_zone_search_through_slurm_finds_what_it_finds_here_bit_for_bit() {
    if !slurm_up() {
        return;
    }
    let dir = scratch("slurm-zones");
    std::fs::write(dir.join("e.toml"), common::engine("count = 2")).unwrap();
    let (local, here) = (dir.join("local.sqlite"), dir.join("here"));
    let report_here = zone_search(&dir, &local, &here, &[]);
    let (merged, there) = (dir.join("merged.sqlite"), dir.join("there"));
    let run = dir.join("run");
    let slurm = ["--slurm", run.to_str().unwrap(), "--tasks", "2"];
    let report_there = zone_search(&dir, &merged, &there, &slurm);
    assert_eq!(report_here, report_there);
    // Every run of the search, in both caches, alike to the last bit.
    let runs = entries(&local);
    assert!(runs.len() >= 5, "{} runs", runs.len());
    assert_eq!(runs, entries(&merged));
    assert!(run.join("logs/batch-1-task-2.log").is_file());
}
