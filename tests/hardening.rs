//! What a careless user, a closed pipe or a full disk must not break: each class of input
//! is refused up front with exit 2 and a one-line message naming the flag, the value and the
//! rule, or handled (a closed pipe ends quietly; an output is complete or not there).

mod common;

use common::{scratch, texopt};
use std::path::Path;
use std::process::{Command, Stdio};

/// Unmounts `0` when dropped (a failed assertion must not leave a mount behind).
struct Unmount(std::path::PathBuf);

impl Drop for Unmount {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// The base case of these tests, a quick Case I at `draft`, with extra flags.
fn simulate(extra: &[&str]) -> (i32, String, String) {
    let mut args = common::case_one_draft().to_vec();
    args.extend_from_slice(extra);
    texopt(&args)
}

/// Refused with exit 2, one line naming `needle`, no panic, nothing on stdout.
fn refused(extra: &[&str], needle: &str) {
    let (code, out, err) = simulate(extra);
    assert_eq!(code, 2, "{extra:?}: {err}");
    assert!(out.is_empty(), "{extra:?} printed {out}");
    assert!(err.contains(needle), "{extra:?}: {err:?} lacks {needle:?}");
    assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
    assert!(!err.contains("panicked"), "{extra:?}: {err}");
}

fn write_study(dir: &Path, parameters: &str, numerics: &str) -> std::path::PathBuf {
    let p = dir.join("s.toml");
    let text = format!(
        "[study]\nname = \"s\"\nfidelity = \"draft\"\n\n[parameters]\n{parameters}\n\n[numerics]\n{numerics}\n\n[report]\ndir = \"{}\"\n",
        dir.join("out").display()
    );
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn memory_is_estimated_and_bounded_before_anything_is_allocated() {
    refused(&["--mesh", "100000x100000"], "--max-memory");
    // The tier raises N2 so that a pocket in a 100 cm wide cell spans 2 cells: 400×5000.
    refused(&["--width", "100"], "--max-memory");
    // A count whose product overflows is over the limit, not a panic.
    refused(&["--mesh", "18446744073709551615x8"], "--max-memory");
    // The limit is the user's to set, both ways.
    refused(&["--max-memory", "0.001"], "over the limit of 0.001 GiB");
    refused(&["--max-memory", "-1"], "--max-memory = -1");
    // A limit above the machine's memory would let a run abort allocating.
    refused(
        &["--mesh", "3000x3000", "--max-memory", "100000"],
        "more than this machine's",
    );
    // A design space whose widest, finest corner is over the limit is refused before the
    // search starts.
    let (code, _, err) = texopt(&["optimise", "--R", "5", "--free-width", "0.1..100"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("design space reaches") && err.contains("--max-memory"),
        "{err}"
    );
}

#[test]
fn a_study_case_over_the_limits_fails_unrun_and_is_not_stored() {
    let dir = scratch("hardening-study-limit");
    let cache = dir.join("c.sqlite");
    let study = write_study(
        &dir,
        "R = 0.8\nl1 = 0.01\nper = 0.06\ndepth = 5",
        "n1 = 4096\nn2 = 4096",
    );
    let (code, out, err) = texopt(&[
        "study",
        study.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
        "--no-report",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(out.contains("1 failed"), "{out}");
    assert!(err.contains("not run") && err.contains("memory"), "{err}");
    let (_, out, _) = texopt(&["cache", "stats", "--cache", cache.to_str().unwrap()]);
    assert!(out.contains("0 evaluations done, 0 failed"), "{out}");
}

#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    for (args, close_stdout) in [
        (vec!["simulate", "--R", "0.8", "--fidelity", "draft"], true),
        (
            vec!["cache", "stats", "--cache", "/nonexistent/c.sqlite"],
            false,
        ),
    ] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_texopt"));
        cmd.args(&args);
        // The closed end: a pipe whose reader has gone before the program writes.
        if close_stdout {
            cmd.stdout(Stdio::piped()).stderr(Stdio::piped());
        } else {
            cmd.stdout(Stdio::null()).stderr(Stdio::piped());
        }
        let mut child = cmd.spawn().unwrap();
        let mut err = String::new();
        if close_stdout {
            drop(child.stdout.take());
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
        } else {
            drop(child.stderr.take());
        }
        let status = child.wait().unwrap();
        assert_ne!(status.code(), Some(101), "{args:?} panicked: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn a_time_step_must_leave_eight_steps_a_texture_period() {
    refused(&["--dt", "1e308"], "time steps per texture period");
    refused(&["--dt", "0.06"], "dt ≤ 0.0075");
    // A tier's own step is shortened to fit a short period (0.0004 cm: 8 steps of 5e-5 ms).
    let (code, out, err) = texopt(&[
        "simulate",
        "--R",
        "0.8",
        "--per",
        "0.0004",
        "--l1",
        "0.0002",
        "--depth",
        "0.4",
        "--mesh",
        "1000x8",
        "--fidelity",
        "draft",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!((v["inputs"]["numerics"]["dt"].as_f64().unwrap() - 5e-5).abs() < 1e-15);
    // And a study file's step is checked like the flag.
    let dir = scratch("hardening-study-dt");
    let study = write_study(
        &dir,
        "R = 0.8\nl1 = 0.01\nper = 0.06\ndepth = 5",
        "dt = 0.06",
    );
    let (code, _, err) = texopt(&["study", study.to_str().unwrap(), "--dry-run"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("time steps per texture period"), "{err}");
}

#[test]
fn a_huge_phase_is_taken_within_one_period() {
    let f = |phase: &str| {
        let (code, out, err) = simulate(&["--phase", phase, "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        v["f_mean"].as_f64().unwrap()
    };
    let base = f("0.01");
    // 60000.01 = 10⁶ periods + 0.01, to the double's precision (≈ 1e-11 cm).
    assert!(((f("60000.01") - base) / base).abs() < 1e-6);
    assert!(f("1e15").is_finite());
    refused(&["--phase", "inf"], "--phase = inf");
}

#[test]
fn study_sizes_are_counted_without_overflow_and_capped() {
    let dir = scratch("hardening-study-size");
    for (parameters, needle) in [
        // 10⁴ values each: 10¹⁶ combinations, once wrapped to a small number.
        (
            "R = { from = 1, to = 2, count = 10000 }\nl1 = { from = 0.005, to = 0.01, count = 10000 }\nper = { from = 0.02, to = 0.06, count = 10000 }\ndepth = { from = 2, to = 5, count = 10000 }\nd_oil = { from = 1, to = 20, count = 10000 }",
            "more than 100000 cases",
        ),
        ("R = { from = 1, to = 2, count = 1000 }\nl1 = { from = 0.005, to = 0.01, count = 1000 }\nper = 0.06\ndepth = 5", "raise max_cases"),
        ("R = { from = 1e-300, to = 1e300, count = 3, spacing = \"log\" }", "not a finite number"),
        ("R = inf\nl1 = 0.01\nper = 0.06\ndepth = nan", "not a finite number"),
    ] {
        let study = write_study(&dir, parameters, "");
        let t0 = std::time::Instant::now();
        let (code, _, err) = texopt(&["study", study.to_str().unwrap(), "--dry-run"]);
        assert_eq!(code, 2, "{parameters}: {err}");
        assert!(err.contains(needle), "{parameters}: {err}");
        assert!(t0.elapsed().as_secs() < 10, "{parameters}: counted slowly");
    }
}

#[test]
fn the_cache_path_must_name_a_file() {
    let dir = scratch("hardening-cache-path");
    for (cache, needle) in [
        (":memory:", "not a file"),
        ("file:x.sqlite?mode=memory", "not a file"),
        (dir.to_str().unwrap(), "exists and is not a file"),
        ("", "--cache"),
    ] {
        let (code, _, err) = texopt(&["cache", "stats", "--cache", cache]);
        assert_eq!(code, 2, "{cache:?}: {err}");
        assert!(err.contains(needle), "{cache:?}: {err}");
    }
    // TEXOPT_CACHE set but empty is unset: the default file, here absent.
    let out = Command::new(env!("CARGO_BIN_EXE_texopt"))
        .args(["cache", "stats"])
        .env("TEXOPT_CACHE", "")
        .current_dir(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no cache at .texopt/cache.sqlite"), "{err}");
}

#[test]
fn inspecting_a_cache_never_creates_or_converts_a_file() {
    let dir = scratch("hardening-cache-inspect");
    let empty = dir.join("empty.sqlite");
    std::fs::write(&empty, "").unwrap();
    for action in [&["stats"][..], &["clear"][..], &["export"][..]] {
        let mut args = vec!["cache"];
        args.extend_from_slice(action);
        args.extend(["--cache", empty.to_str().unwrap()]);
        let (code, _, err) = texopt(&args);
        assert_eq!(code, 2, "{action:?}: {err}");
        assert!(err.contains("not a texopt cache"), "{action:?}: {err}");
        assert_eq!(
            std::fs::metadata(&empty).unwrap().len(),
            0,
            "{action:?} wrote"
        );
    }
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "side files were made"
    );
}

#[test]
fn destinations_are_checked_before_the_run() {
    let dir = scratch("hardening-destinations");
    // --series at a directory: refused before simulating (exit 2, at once).
    refused(&["--series", dir.to_str().unwrap()], "is a directory");
    // A study table that is not a plain file name of the report directory.
    for table in ["\"\"", "\"../escape.md\"", "\"sub/t.md\""] {
        let p = dir.join("t.toml");
        std::fs::write(
            &p,
            format!("[study]\nname = \"t\"\n[parameters]\nR = 0.8\n[report]\ntable = {table}\n"),
        )
        .unwrap();
        let (code, _, err) = texopt(&["study", p.to_str().unwrap(), "--dry-run"]);
        assert_eq!(code, 2, "{table}: {err}");
        assert!(err.contains("[report] table"), "{table}: {err}");
    }
}

#[test]
fn runaway_work_is_refused() {
    refused(&["--dt", "1e-9"], "--max-steps");
    // A tolerance that would stop a run in its transient, and an animation of no frames.
    refused(&["--periodic-tol", "10"], "--periodic-tol = 10");
    let gif = std::env::temp_dir().join("texopt-hardening-never.gif");
    refused(
        &["--animate", gif.to_str().unwrap(), "--animate-stride", "0"],
        "--animate-stride",
    );
    assert!(!gif.exists());
    let (code, _, err) = texopt(&["study", "studies/paper.toml", "--jobs", "100000"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("from 1 to 256"), "{err}");
}

#[test]
fn messages_are_short_and_name_the_flag() {
    // 1e-308, not 308 digits.
    let (code, _, err) = texopt(&[
        "simulate", "--R", "0.8", "--l1", "1e-308", "--per", "0.06", "--depth", "5",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.len() < 300 && err.contains("1e-308"), "{err}");
    let (code, _, err) = texopt(&["optimise", "--R", "5", "--w-min", "1e308"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.len() < 400 && err.contains("w_min = 1e304 cm"), "{err}");
    let (code, _, err) = texopt(&["bench", "--repeat", "1000000"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--repeat 1000000: at most 100"), "{err}");
    // The least wall is said in µm, as it is given.
    let (code, _, err) = texopt(&["optimise", "--R", "5", "--w-min", "-10"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--w-min = -10 µm"), "{err}");
    // A negative range reaches the range check, not the argument parser.
    let (code, _, err) = texopt(&["optimise", "--R", "5", "--l1", "-0.01..0.03"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("0 < LO ≤ HI"), "{err}");
    // A --config range of three numbers is an error, not two of them.
    let dir = scratch("hardening-messages");
    let cfg = dir.join("c.toml");
    std::fs::write(&cfg, "l1 = [0.005, 0.01, 0.02]\n").unwrap();
    let (code, _, err) = texopt(&["optimise", "--R", "5", "--config", cfg.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("two numbers"), "{err}");
    // A flat ring has no plain liner to weigh textures against: said before any search.
    let (code, _, err) = texopt(&["optimise", "--R", "inf"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--R = inf") && !err.contains("designs at"),
        "{err}"
    );
    // A step the fast tier's characteristic scheme cannot take (dt > 2·dx1/u on 700 cells) is
    // refused before any search, not when the confirmation reaches it.
    let (code, _, err) = texopt(&["optimise", "--R", "5", "--dt", "6e-4"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--dt") && err.contains("one cell") && !err.contains("designs at"),
        "{err}"
    );
    // Narrow pockets in a wide texture cell raise N2 a long way: said before the run, and an
    // absurd width gives a count, not an overflow.
    let (_, _, err) = texopt(&[
        "simulate",
        "--R",
        "3",
        "--l1",
        "0.0025",
        "--l2",
        "0.0004",
        "--per",
        "0.06",
        "--depth",
        "0.8",
        "--fidelity",
        "draft",
        "--t-max",
        "0.01",
        "--approach",
        "off",
    ]);
    assert!(err.contains("note: 75 cells across (N2 raised"), "{err}");
    let (code, _, err) = texopt(&[
        "simulate", "--R", "3", "--l1", "0.01", "--per", "1e300", "--depth", "5",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("raise N2 to at least 5e301") && !err.contains("18446744073709551615"),
        "{err}"
    );
    // A run that misses --t-max says where it ended (runs end on whole averaging windows).
    let (code, _, err) = simulate(&["--t-max", "0.01"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("past --t-max 0.01"), "{err}");
    // An absurd value is printed short (the flat ring rests on its asperities, docs/model.md
    // §11).
    let (code, out, err) = texopt(&["simulate", "--R", "1e308"]);
    assert_eq!(code, 0, "{err}");
    let first = out.lines().next().unwrap_or_default();
    assert!(first.contains("R = 1e308 cm") && first.len() < 100, "{out}");
    // A mesh is named as it was given.
    refused(&["--mesh", "0x8"], "--mesh = 0x8");
    // Flags an untextured (steady) run does not use are said.
    let (code, _, err) = texopt(&["simulate", "--R", "0.8", "--dt", "1e-3", "--mesh", "400x8"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("--dt, --mesh's N2 not used"), "{err}");
    // A coarse approach the run cannot take as asked is said, not dropped or changed silently.
    let (code, _, err) = simulate(&["--approach", "800x16@1e-3"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("--approach 800x16@0.001 is not used"), "{err}");
    let (code, _, err) = simulate(&["--approach", "120x4@1e-5"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("--approach 120x4@1e-5 runs as 120x4@0.001"),
        "{err}"
    );
    // A failing --json run answers with a JSON object.
    let (code, out, _) = simulate(&["--dt", "0.06", "--json"]);
    assert_eq!(code, 2);
    let v: serde_json::Value = serde_json::from_str(out.trim()).expect("a JSON object");
    assert!(v["error"].as_str().unwrap().contains("--dt"), "{v}");
}

/// A full disk, on a 1 MiB tmpfs mounted for the test where the system allows it (as root);
/// the same fault injected at the write layer runs everywhere (src/output.rs).
#[test]
fn a_full_disk_leaves_the_previous_output_and_the_answer() {
    let dir = scratch("hardening-full-disk");
    let mnt = dir.join("small");
    std::fs::create_dir_all(&mnt).unwrap();
    let mounted = Command::new("mount")
        .args([
            "-t",
            "tmpfs",
            "-o",
            "size=1m",
            "tmpfs",
            mnt.to_str().unwrap(),
        ])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("no tmpfs could be mounted here; the write layer's own test covers this");
        return;
    }
    let _unmount = Unmount(mnt.clone());
    let series = mnt.join("series.csv");
    std::fs::write(&series, "previous\n").unwrap();
    // Fill the rest of the file system.
    let _ = std::fs::write(mnt.join("filler"), vec![0u8; 2 << 20]);
    let (code, out, err) = simulate(&["--series", series.to_str().unwrap()]);
    let kept = std::fs::read_to_string(&series).unwrap_or_default();
    let left = std::fs::read_dir(&mnt).map_or(0, |d| d.count());
    assert_eq!(kept, "previous\n", "the previous file was replaced");
    assert_eq!(left, 2, "a temporary file was left");
    assert_eq!(code, 1, "{err}");
    assert!(
        out.contains("mean friction coefficient"),
        "the answer was lost: {out}"
    );
    assert!(err.contains("left as it was"), "{err}");
}

#[test]
fn a_ring_that_cannot_move_is_not_taken_for_periodic() {
    // 10¹⁹ times the paper's mass (beyond what `--ring-mass` accepts, so through the
    // library): the ring stands still and every window repeats, while the film carries 0.91
    // of the load. The periodic regime must balance the mean force.
    use texopt::model::case::{CaseSpec, Texture};
    use texopt::time::{simulate_with, Fidelity, RunOptions, Start, Watch};
    for mass in [1e10, 1e6] {
        let case = CaseSpec {
            mass,
            ..CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0))
        };
        let mut num = Fidelity::Draft.numerics_for(&case);
        num.t_max = 3.0;
        num.start = Start::Equilibrium; // as `simulate`
        let o = simulate_with(&case, &num, &RunOptions::default(), &mut Watch::default())
            .unwrap()
            .outcome;
        assert!(!o.converged, "mass {mass}: {o:?}");
        assert!(o.periodic_error > 1e-2, "mass {mass}: {o:?}");
    }
}

#[test]
fn two_studies_on_one_cache_share_the_work() {
    let dir = scratch("hardening-shared-cache");
    let cache = dir.join("c.sqlite");
    // 12 simulations of ≈ 0.1–0.3 s each: long enough for the two runs to overlap.
    let study = write_study(
        &dir,
        "R = [0.8, 3.2, 12.8]\nl1 = [0.01, 0.02]\nper = 0.06\ndepth = [5, 10]",
        "n1 = 96\nn2 = 4\ndt = 1.2e-3\nperiodic_tol = 1e-3",
    );
    let start = || {
        Command::new(env!("CARGO_BIN_EXE_texopt"))
            .args([
                "study",
                study.to_str().unwrap(),
                "--jobs",
                "1",
                "--no-report",
            ])
            .arg("--cache")
            .arg(&cache)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    let (a, b) = (start(), start());
    let simulations = |c: std::process::Child| -> usize {
        let out = c.wait_with_output().unwrap();
        assert!(out.status.success());
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let n = text
            .split(" computed in ")
            .nth(1)
            .and_then(|t| t.split_whitespace().next())
            .and_then(|n| n.parse().ok());
        n.unwrap_or_else(|| panic!("no count in {text}"))
    };
    let (na, nb) = (simulations(a), simulations(b));
    assert_eq!(na + nb, 12, "each case once: {na} + {nb}");
    eprintln!("simulations: {na} + {nb}");
    let (_, out, _) = texopt(&["cache", "stats", "--cache", cache.to_str().unwrap()]);
    assert!(out.contains("12 evaluations done"), "{out}");
}

/// A cache on a read-only file system (a tmpfs the test mounts and remounts read-only, where
/// the system allows it) is refused before any case is computed.
#[test]
fn a_read_only_cache_is_refused_before_computing() {
    let dir = scratch("hardening-read-only-cache");
    let mnt = dir.join("ro");
    std::fs::create_dir_all(&mnt).unwrap();
    let mount = |args: &[&str]| {
        Command::new("mount")
            .args(args)
            .arg(&mnt)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    if !mount(&["-t", "tmpfs", "-o", "size=4m", "tmpfs"]) {
        eprintln!("no tmpfs could be mounted here");
        return;
    }
    let _unmount = Unmount(mnt.clone());
    let cache = mnt.join("c.sqlite");
    let study = write_study(
        &dir,
        "R = 0.8\nl1 = 0.01\nper = 0.06\ndepth = 5",
        "n1 = 64\nn2 = 4\ndt = 1.6e-3",
    );
    let run = || {
        texopt(&[
            "study",
            study.to_str().unwrap(),
            "--no-report",
            "--cache",
            cache.to_str().unwrap(),
        ])
    };
    // A cache made by a study of the plain liner alone.
    let other = dir.join("plain");
    std::fs::create_dir_all(&other).unwrap();
    let plain = write_study(&other, "R = 0.8", "n1 = 64\nn2 = 4");
    let (code, _, err) = texopt(&[
        "study",
        plain.to_str().unwrap(),
        "--no-report",
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let remounted = mount(&["-o", "remount,ro"]);
    let (code, out, err) = run();
    assert!(remounted, "could not remount read-only");
    assert_eq!(code, 2, "{out} {err}");
    assert!(err.contains("cannot be written"), "{err}");
    assert!(!out.contains("computed in 1"), "a case was computed: {out}");
}

/// Runs texopt in `dir` for at most `secs` seconds (killed after: work started where a
/// refusal was due): exit code (-1 when killed) and stderr.
fn texopt_within(dir: &Path, secs: u64, args: &[&str]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_texopt"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run texopt");
    let t0 = std::time::Instant::now();
    let code = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status.code().unwrap_or(-1);
        }
        if t0.elapsed().as_secs() >= secs {
            let _ = child.kill();
            let _ = child.wait();
            break -1;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = std::io::Read::read_to_string(&mut e, &mut err);
    }
    (code, err)
}

/// Refused at once (exit 2, one line naming `needle`), run in `dir`.
fn refused_at_once(dir: &Path, args: &[&str], needle: &str) {
    let (code, err) = texopt_within(dir, 10, args);
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
}

#[test]
fn search_sizes_are_capped_before_any_work() {
    let dir = scratch("hardening-search-sizes");
    let opt = |extra: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = [
            "optimise", "--R", "3.2", "--cache", "c.sqlite", "--out", "o",
        ]
        .map(String::from)
        .to_vec();
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let weights: Vec<String> = (1..=101).map(|i| format!("{}", i as f64 / 102.0)).collect();
    let weights = weights.join(",");
    for (extra, needle) in [
        (
            &["--particles", "100000000000"][..],
            "--particles = 100000000000",
        ),
        (&["--particles", "1000000000"], "from 2 to 10000"),
        (&["--particles", "1"], "--particles = 1"),
        (&["--iterations", "100000000"], "--iterations = 100000000"),
        (&["--iterations", "0"], "from 1 to 100000"),
        (&["--balanced", weights.as_str()], "--balanced: 101 weights"),
    ] {
        let args = opt(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused_at_once(&dir, &args, needle);
    }
    // A config file's sizes are named by their key.
    std::fs::write(dir.join("cfg.toml"), "particles = 20000\n").unwrap();
    refused_at_once(
        &dir,
        &opt(&["--config", "cfg.toml"])
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        "--config cfg.toml: particles = 20000",
    );
    std::fs::write(dir.join("cfg.toml"), "radii = 17\n").unwrap();
    let args = [
        "optimise", "--R", "3.2..5", "--config", "cfg.toml", "--cache", "c.sqlite",
    ];
    refused_at_once(&dir, &args, "--config cfg.toml: radii = 17");
    // cycle: the flags and the engine file's [design] keys.
    let engine = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/engine_gasoline.toml");
    let text = std::fs::read_to_string(&engine).unwrap();
    let big = text.replace("particles = 8", "particles = 100000000");
    assert_ne!(big, text, "the engine file sets particles = 8");
    std::fs::write(dir.join("e.toml"), big).unwrap();
    let e = engine.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["cycle", "e.toml"],
            "e.toml: [design] particles = 100000000",
        ),
        (
            vec!["cycle", e, "--particles", "100000"],
            "--particles = 100000",
        ),
        (
            vec!["cycle", e, "--iterations", "100000000"],
            "--iterations = 100000000",
        ),
    ] {
        let mut args = args;
        args.extend(["--cache", "c.sqlite", "--out", "o"]);
        refused_at_once(&dir, &args, needle);
    }
    assert!(!dir.join("o").exists() && !dir.join("c.sqlite").exists());
}

#[test]
fn a_study_cannot_raise_its_case_limit_without_bound() {
    let dir = scratch("hardening-max-cases");
    let p = dir.join("s.toml");
    std::fs::write(
        &p,
        "[study]\nname = \"s\"\nmax_cases = 1000000000000\n[parameters]\nR = 0.8\n",
    )
    .unwrap();
    refused_at_once(
        &dir,
        &["study", p.to_str().unwrap(), "--dry-run"],
        "[study] max_cases = 1000000000000",
    );
}

/// Case I at `draft` with a step of 1e-5: 6000 steps a texture period.
fn fine_step(extra: &[&str]) -> Vec<String> {
    let base = common::case_one_draft();
    let all = base.iter().chain(&["--dt", "1e-5"]).chain(extra);
    all.map(|s| s.to_string()).collect()
}

#[test]
fn snapshots_are_capped_and_counted_in_the_memory_estimate() {
    let dir = scratch("hardening-snapshot-memory");
    let run = |extra: &[&str], needle: &str| {
        let args = fine_step(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused_at_once(&dir, &args, needle);
    };
    run(
        &["--snapshots", "big", "--frames", "6000"],
        "--frames = 6000",
    );
    run(
        &["--snapshots", "big", "--frames", "101"],
        "1 to 100 frames",
    );
    // The recording is what puts the run over the limit: named, not the tier's mesh.
    run(
        &[
            "--snapshots",
            "big",
            "--frames",
            "100",
            "--max-memory",
            "0.01",
        ],
        "--frames = 100: 100 instants",
    );
    run(
        &["--animate", "a.gif", "--animate-stride", "1"],
        "--animate-stride = 1: gives 6000 animation frames",
    );
    assert!(std::fs::read_dir(dir.join("big")).map_or(0, |d| d.count()) == 0);
    assert!(!dir.join("a.gif").exists());
}

#[test]
fn the_memory_estimate_counts_the_period_stores_only_when_they_are_kept() {
    // 6000 steps a period on 400×8: the period's states would take over their cap, so the
    // run keeps none (a few MB in all), and 1 GiB is plenty.
    let dir = scratch("hardening-period-stores");
    let args = fine_step(&["--max-memory", "1", "--t-max", "0.001", "--approach", "off"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = texopt_within(&dir, 120, &args);
    assert!(code == 0 || code == 1, "{err}");
    assert!(!err.contains("--max-memory"), "{err}");
    // A mesh the tier chose is said to be the tier's.
    refused(
        &["--max-memory", "0.0001"],
        "--mesh = 400x8 (--fidelity draft's mesh)",
    );
}

#[test]
fn many_snapshot_frames_say_how_many_files_they_write() {
    let dir = scratch("hardening-snapshot-files");
    let out = dir.join("snaps");
    let (code, _, err) = simulate(&["--snapshots", out.to_str().unwrap(), "--frames", "20"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("note: --frames 20 writes 27 files"), "{err}");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 27);
}
