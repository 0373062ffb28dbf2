//! Studies and the evaluation cache: the paper's study expands to docs/model.md §7's 720 + 10
//! cases; bad study files are refused; a rerun computes nothing; θ_s variants share one
//! simulation; a study killed with SIGKILL loses no finished case and its cache stays intact.
//! The studies here run on coarse meshes (64×4): they test contracts, not physics.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;

use common::{scratch, texopt};
use texopt::study::cache::{Cache, Entry, Key};

/// `texopt study FILE --cache CACHE`.
fn run_study(study: &Path, cache: &Path) -> (i32, String, String) {
    texopt(&[
        "study",
        study.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ])
}

/// A small study on a coarse mesh writing its report into `dir/out`.
fn small_study(dir: &Path, radii: &str, extra: &str) -> PathBuf {
    let text = format!(
        r#"
[study]
name = "small"
fidelity = "draft"
untextured = true

[parameters]
R = {radii}
l1 = [0.02, 0.03]
per = 0.06
depth = [5, 10]
{extra}

[numerics]
n1 = 64
n2 = 4
dt = 1.6e-3
periodic_tol = 1e-3

[report]
dir = "{}"
"#,
        dir.join("out").display()
    );
    let p = dir.join("small.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_paper_study_is_720_textured_cases_and_10_plain_liners() {
    let s = texopt::study::load(Path::new("studies/paper.toml")).unwrap();
    let textured = s.jobs.iter().filter(|j| j.case.texture.is_some()).count();
    assert_eq!(textured, 720);
    assert_eq!(s.jobs.len() - textured, 10);
    let mut textures: Vec<String> = s
        .jobs
        .iter()
        .filter_map(|j| j.case.texture.as_ref().map(|t| format!("{t:?}")))
        .collect();
    textures.sort();
    textures.dedup();
    assert_eq!(textures.len(), 72);
    // 5 × 7 × 5 combinations per radius, 72 valid: 103 skipped per radius.
    assert_eq!(s.skipped_total(), 1030);
    for j in &s.jobs {
        if let Some(t) = &j.case.texture {
            assert!(2.0 * t.l1 <= t.per && 1e4 * t.l1 >= 5.0 * t.depth);
            // Every pocket is resolved by at least 4 cells across.
            assert!(2.0 * t.l2 / (0.5 * t.width / j.numerics.n2 as f64) >= 4.0 - 1e-9);
        }
    }
}

#[test]
fn bad_study_files_are_refused_with_exit_2_and_nothing_written() {
    let dir = scratch("bad");
    let cache = dir.join("cache.sqlite");
    let ok_head = "[study]\nname = \"x\"\n[parameters]\n";
    // (file text, text the one-line message must contain)
    let cases: Vec<(String, &str)> = vec![
        ("[study\nname = \"x\"".into(), "TOML parse error"),
        (format!("{ok_head}R = 0.8\nl1 = 0.01\n"), "per is missing"),
        (format!("{ok_head}R = [0.8]\ncolour = 3\n"), "unknown parameter \"colour\""),
        ("[study]\nname = \"x\"\nspeed = 2\n[parameters]\nR = 1\n".into(), "unknown field `speed`"),
        (format!("{ok_head}R = []\n"), "the list is empty"),
        (format!("{ok_head}R = {{ from = 3, to = 1, count = 3 }}\n"), "empty or inverted"),
        (format!("{ok_head}R = {{ from = 1, to = 3 }}\n"), "exactly one of count, step or factor"),
        (format!("{ok_head}R = 0.8\nl1 = \"10 um\"\nper = 0.06\ndepth = 5\n"), "not a number nor another parameter"),
        (format!("{ok_head}R = 0.8\nl1 = 0.01\nper = 0.06\ndepth = \"five\"\n"), "not a number nor another parameter"),
        (format!("{ok_head}l1 = 0.01\n"), "R is missing"),
        (format!("{ok_head}R = 0.8\nl1 = 0.04\nper = 0.06\ndepth = 5\n"), "no valid case"),
        (format!("{ok_head}R = 0.8\nl1 = 0.01\nl2 = \"width\"\nwidth = \"per\"\nper = 0.06\ndepth = 5\n"), "is itself a tie"),
        ("[study]\nname = \"a b\"\n[parameters]\nR = 1\n".into(), "use letters, digits"),
        ("[study]\nname = \"x\"\nfidelity = \"ultra\"\n[parameters]\nR = 1\n".into(), "unknown variant `ultra`"),
        (format!("{ok_head}R = 0.8\n[numerics]\nmesh = 3\n"), "unknown field `mesh`"),
        (format!("{ok_head}R = {{ from = 0.2, to = 1, factor = 1 }}\n"), "factor > 1"),
        (format!("{ok_head}R = 0.8\n[report]\nsmall_r_max = 5\nlarge_r_min = 1\n"), "must be below"),
        (format!("{ok_head}R = 0.8\nl1 = 0.01\nper = 0.06\ndepth = 5\n[numerics]\nn1 = 16\n"), "cells across the pocket"),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let f = dir.join(format!("bad{i}.toml"));
        std::fs::write(&f, text).unwrap();
        let (code, out, err) = run_study(&f, &cache);
        assert_eq!(code, 2, "case {i} ({want}): exit {code}, stderr {err}");
        assert!(
            err.contains(want),
            "case {i}: {err:?} should contain {want:?}"
        );
        assert_eq!(
            err.trim().lines().count(),
            1,
            "case {i}: one line, got {err:?}"
        );
        assert!(out.is_empty());
        assert!(!cache.exists(), "case {i}: nothing may be written");
    }
    // A file that is no cache is reported and left as it was.
    let foreign = dir.join("notes.txt");
    std::fs::write(&foreign, "my notes, not a database").unwrap();
    let study = small_study(&dir, "[0.8]", "");
    let (code, _, err) = run_study(&study, &foreign);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not a texopt cache"), "{err}");
    assert_eq!(
        std::fs::read_to_string(&foreign).unwrap(),
        "my notes, not a database"
    );
    assert!(!dir.join("out").exists());
}

#[test]
fn a_rerun_computes_nothing_and_reports_the_same() {
    let dir = scratch("rerun");
    let cache = dir.join("c.sqlite");
    let study = small_study(&dir, "[0.8, 3.2]", "");
    let args = [
        "study",
        study.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
        "--jobs",
        "2",
    ];
    let (code, out, err) = texopt(&args);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("10 cases: 0 from the cache, 10 computed in 10 simulations, 0 failed"),
        "{out}"
    );
    let csv1 = std::fs::read_to_string(dir.join("out/small.csv")).unwrap();
    assert_eq!(csv1.lines().count(), 11);
    assert!(dir.join("out/small_fig6_friction.png").exists());
    assert!(dir.join("out/small_table1.md").exists());
    let (code, out, _) = texopt(&args);
    assert_eq!(code, 0);
    assert!(
        out.contains("10 cases: 10 from the cache, 0 computed in 0 simulations"),
        "{out}"
    );
    // The report from the cache is the same file, wall times included.
    assert_eq!(
        std::fs::read_to_string(dir.join("out/small.csv")).unwrap(),
        csv1
    );
    let (code, out, _) = texopt(&["cache", "stats", "--cache", cache.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(
        out.contains("10 evaluations done, 0 failed") && out.contains("integrity: ok"),
        "{out}"
    );
}

#[test]
fn theta_s_variants_share_one_simulation() {
    let dir = scratch("theta");
    let cache = dir.join("c.sqlite");
    let study = small_study(&dir, "[0.8, 3.2]", "theta_s = [0.5, 0.95]");
    let (code, out, err) = run_study(&study, &cache);
    assert_eq!(code, 0, "{err}");
    // 2 R × 2 θ_s × (4 textures + plain) = 20 cases, 10 simulations.
    assert!(out.contains("20 computed in 10 simulations"), "{out}");
    assert!(dir.join("out/small_fig11.png").exists());
    let s = texopt::study::load(&study).unwrap();
    let c = Cache::open(&cache).unwrap();
    let get = |theta: f64| {
        let j = s
            .jobs
            .iter()
            .find(|j| j.case.texture.is_some() && j.case.theta_s == theta)
            .unwrap();
        match c.get(&Key::of(&j.case, &j.numerics)).unwrap() {
            Some(Entry::Done(o)) => o,
            other => panic!("{other:?}"),
        }
    };
    let (a, b) = (get(0.5), get(0.95));
    assert_eq!(
        (a.z_mean, a.c_min, a.f_poiseuille),
        (b.z_mean, b.c_min, b.f_poiseuille)
    );
    assert!(
        a.f_couette > b.f_couette,
        "a lower threshold shears more of the film"
    );
    // And the shared run equals a run of that θ_s alone.
    let j = s
        .jobs
        .iter()
        .find(|j| j.case.texture.is_some() && j.case.theta_s == 0.5)
        .unwrap();
    let alone = texopt::time::simulate(&j.case, &j.numerics)
        .unwrap()
        .outcome;
    assert_eq!((alone.f_mean, alone.z_mean), (a.f_mean, a.z_mean));
}

#[test]
fn sigkill_loses_no_finished_case_and_the_cache_stays_intact() {
    let dir = scratch("kill");
    let cache = dir.join("c.sqlite");
    // 9 radii × 5 cases = 45 cases of ≈ 0.1–0.3 s.
    let study = small_study(&dir, "{ from = 0.4, to = 102.4, factor = 2 }", "");
    let total = texopt::study::load(&study).unwrap().jobs.len();
    let mut done_before = Vec::new();
    for round in 0..3 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_texopt"))
            .args([
                "study",
                study.to_str().unwrap(),
                "--cache",
                cache.to_str().unwrap(),
                "--jobs",
                "2",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // Kill once a few more cases are stored than before (a different moment each round).
        let target = done_before.len() + 2 + round;
        let t0 = Instant::now();
        loop {
            std::thread::sleep(Duration::from_millis(20));
            let n = Cache::open(&cache)
                .ok()
                .and_then(|c| c.stats().ok())
                .map_or(0, |s| s.done);
            if n >= target || t0.elapsed() > Duration::from_secs(60) {
                break;
            }
        }
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        let c = Cache::open(&cache).unwrap();
        assert_eq!(c.integrity_check().unwrap(), "ok");
        let mut buf = Vec::new();
        c.export(&mut buf).unwrap();
        let done: Vec<String> = String::from_utf8(buf)
            .unwrap()
            .lines()
            .filter(|l| l.contains("\"status\":\"done\""))
            .map(str::to_string)
            .collect();
        for d in &done_before {
            assert!(
                done.contains(d),
                "round {round}: a finished case was lost or changed"
            );
        }
        assert!(done.len() < total, "killed before the end");
        done_before = done;
    }
    let (code, out, err) = run_study(&study, &cache);
    assert_eq!(code, 0, "{err}");
    let want = format!(
        "{total} cases: {} from the cache, {} computed",
        done_before.len(),
        total - done_before.len()
    );
    assert!(out.contains(&want), "{out} should say {want}");
}

#[test]
fn one_and_two_threads_give_bit_identical_outcomes() {
    let dir = scratch("threads");
    let study = small_study(&dir, "[0.8, 6.4]", "");
    let mut csvs = Vec::new();
    for jobs in ["1", "2"] {
        let cache = dir.join(format!("c{jobs}.sqlite"));
        let (code, _, err) = texopt(&[
            "study",
            study.to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
            "--jobs",
            jobs,
        ]);
        assert_eq!(code, 0, "{err}");
        let c = Cache::open(&cache).unwrap();
        let s = texopt::study::load(&study).unwrap();
        let outs: Vec<String> = s
            .jobs
            .iter()
            .map(|j| match c.get(&Key::of(&j.case, &j.numerics)).unwrap() {
                Some(Entry::Done(mut o)) => {
                    o.wall_time_s = 0.0;
                    format!("{:?}", serde_json::to_string(&o).unwrap())
                }
                other => panic!("{other:?}"),
            })
            .collect();
        csvs.push(outs);
    }
    assert_eq!(csvs[0], csvs[1]);
}

#[test]
fn a_damaged_cache_is_reported_and_left_untouched() {
    let dir = scratch("damaged");
    let cache = dir.join("c.sqlite");
    drop(Cache::open(&cache).unwrap()); // a valid, empty cache (closed: WAL checkpointed)
    let mut bytes = std::fs::read(&cache).unwrap();
    assert!(bytes.len() >= 8192);
    for (i, b) in bytes[4096..8192].iter_mut().enumerate() {
        *b = (i * 7 % 251) as u8; // garble the table's root page, keep the header
    }
    std::fs::write(&cache, &bytes).unwrap();
    let study = small_study(&dir, "[0.8]", "");
    let (code, _, err) = run_study(&study, &cache);
    assert_eq!(code, 2, "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert!(errors.len() == 1 && errors[0].contains("damaged"), "{err}");
    assert_eq!(
        std::fs::read(&cache).unwrap(),
        bytes,
        "the damaged file is left as it was"
    );
    assert!(!dir.join("out").exists());
}

#[test]
fn failed_cases_are_stored_as_failures_and_not_retried_unless_asked() {
    let dir = scratch("failed");
    let cache = dir.join("c.sqlite");
    // Deep close-packed pockets under a curved ring: the ring reaches the plateau (contact).
    let text = format!(
        "[study]\nname = \"deep\"\n[parameters]\nR = 0.8\nl1 = 0.03\nper = 0.06\ndepth = [10, 30]\n[numerics]\nn1 = 64\nn2 = 4\ndt = 1.6e-3\nperiodic_tol = 1e-3\n[report]\ndir = \"{}\"\n",
        dir.join("out").display()
    );
    let study = dir.join("deep.toml");
    std::fs::write(&study, text).unwrap();
    let args = [
        "study",
        study.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ];
    let (code, out, err) = texopt(&args);
    assert_eq!(code, 1, "a failed case makes the exit code 1: {out}{err}");
    assert!(
        out.contains("2 computed in 2 simulations, 1 failed"),
        "{out}"
    );
    let csv = std::fs::read_to_string(dir.join("out/deep.csv")).unwrap();
    let failed: Vec<&str> = csv.lines().filter(|l| l.contains(",failed,")).collect();
    assert_eq!(failed.len(), 1);
    assert!(failed[0].contains("reached the liner"), "{}", failed[0]);
    let c = Cache::open(&cache).unwrap();
    let s = c.stats().unwrap();
    assert_eq!(
        (s.done, s.failed),
        (1, 1),
        "the failure is stored as a failure"
    );
    drop(c);
    let (_, out, _) = texopt(&args);
    assert!(
        out.contains("2 from the cache, 0 computed"),
        "not retried: {out}"
    );
    let mut retry = args.to_vec();
    retry.push("--retry-failed");
    let (_, out, _) = texopt(&retry);
    assert!(
        out.contains("1 from the cache, 1 computed"),
        "retried on request: {out}"
    );
}

#[test]
fn a_report_directory_that_cannot_be_made_stops_the_study_before_it_runs() {
    let dir = scratch("blocked");
    let blocker = dir.join("a-file");
    std::fs::write(&blocker, "").unwrap();
    let study = small_study(&dir, "[0.8]", "");
    let text = std::fs::read_to_string(&study).unwrap().replace(
        &dir.join("out").display().to_string(),
        &blocker.join("out").display().to_string(),
    );
    std::fs::write(&study, text).unwrap();
    let cache = dir.join("c.sqlite");
    let (code, _, err) = run_study(&study, &cache);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("report directory"), "{err}");
    assert!(!cache.exists(), "the study ran: its cache was made");
}
