//! The command-line contract: bad input is refused with a one-line message naming the
//! parameter, exit code 2, nothing written; `--json` and `--series` deliver what they promise.

mod common;

use common::texopt;
use std::process::Command;

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("texopt-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn bad_inputs_are_refused_with_exit_2_and_a_message_naming_the_parameter() {
    let series = scratch("refused.csv");
    let s = series.to_str().unwrap();
    let tex = ["--l1", "0.01", "--per", "0.06", "--depth", "5"];
    let with_tex = |extra: &[&'static str]| -> Vec<String> {
        let mut v: Vec<String> = ["simulate", "--R", "0.8"]
            .iter()
            .map(|x| x.to_string())
            .collect();
        v.extend(tex.iter().map(|x| x.to_string()));
        v.extend(extra.iter().map(|x| x.to_string()));
        v.extend(["--series".to_string(), s.to_string()]);
        v
    };
    // (arguments, text the one-line error must contain)
    let cases: Vec<(Vec<String>, &str)> = vec![
        (to(&["simulate", "--R", "0.03"]), "--R"),
        (to(&["simulate", "--R", "-2"]), "--R"),
        (to(&["simulate", "--R", "nan"]), "--R"),
        (to(&["simulate", "--R", "abc"]), "--R"),
        (to(&["simulate"]), "--R"),
        (
            to(&[
                "simulate", "--R", "0.8", "--l1", "0.04", "--per", "0.06", "--depth", "5",
            ]),
            "--l1",
        ),
        (
            to(&[
                "simulate", "--R", "0.8", "--l1", "0.01", "--l2", "0.04", "--per", "0.06",
                "--depth", "5",
            ]),
            "--l2",
        ),
        (
            to(&[
                "simulate", "--R", "0.8", "--l1", "0.0025", "--per", "0.06", "--depth", "10",
            ]),
            "thin-film",
        ),
        (
            to(&[
                "simulate", "--R", "0.8", "--l1", "-0.01", "--per", "0.06", "--depth", "5",
            ]),
            "--l1",
        ),
        (
            to(&[
                "simulate", "--R", "0.8", "--l1", "0.01", "--per", "0", "--depth", "5",
            ]),
            "--per",
        ),
        (
            to(&[
                "simulate", "--R", "0.8", "--l1", "0.01", "--per", "inf", "--depth", "5",
            ]),
            "--per",
        ),
        (
            to(&["simulate", "--R", "0.8", "--per", "0.06", "--depth", "5"]),
            "--l1",
        ),
        (
            to(&["simulate", "--R", "0.8", "--l1", "0.01", "--depth", "5"]),
            "--per",
        ),
        (to(&["simulate", "--R", "0.8", "--depth", "-1"]), "--depth"),
        (with_tex(&["--mesh", "16x32"]), "--mesh"),
        (with_tex(&["--mesh", "8x32"]), "--mesh"),
        (with_tex(&["--mesh", "512"]), "--mesh"),
        (with_tex(&["--mesh", "ax3"]), "--mesh"),
        (with_tex(&["--dt", "0"]), "--dt"),
        (with_tex(&["--dt", "-1e-4"]), "--dt"),
        (with_tex(&["--theta-s", "1.5"]), "--theta-s"),
        (with_tex(&["--d-oil", "0"]), "--d-oil"),
        (with_tex(&["--t-max", "0"]), "--t-max"),
        (with_tex(&["--periodic-tol", "-1"]), "--periodic-tol"),
        (with_tex(&["--width", "0.01"]), "--l2"),
        (
            to(&["simulate", "--R", "0.8", "--series", s]),
            "--transient",
        ),
        (
            to(&[
                "simulate",
                "--R",
                "0.8",
                "--l1",
                "0.01",
                "--per",
                "0.06",
                "--depth",
                "5",
                "--series",
                "/nonexistent-dir/x.csv",
            ]),
            "does not exist",
        ),
        (with_tex(&["--fidelity", "coarse"]), "--fidelity"),
        (with_tex(&["--solver", "jacobi"]), "--solver"),
        (with_tex(&["--start", "cold"]), "--start"),
        (with_tex(&["--solve-tol", "0"]), "--solve-tol"),
        (with_tex(&["--cycles", "0"]), "cycles"),
        (with_tex(&["--approach", "0"]), "--approach"),
        (with_tex(&["--approach", "8x4@1e-3"]), "--approach"),
        (with_tex(&["--approach", "128x4@-1"]), "--approach"),
        (with_tex(&["--approach", "coarse"]), "--approach"),
        (with_tex(&["--progress-every", "-1"]), "--progress-every"),
        (with_tex(&["--progress-every", "soon"]), "--progress-every"),
        (
            to(&["bench", "--case", "case-IV", "--out", s]),
            "no such benchmark case",
        ),
        (
            to(&["bench", "--out", "/nonexistent-dir/bench.json"]),
            "does not exist",
        ),
        (to(&["bench", "--repeat", "0", "--out", s]), "--repeat 0"),
        (
            to(&[
                "bench",
                "--fidelity",
                "fast",
                "--case",
                "cycle-plain",
                "--out",
                s,
            ]),
            "the cycle cases run at draft",
        ),
    ];
    for (args, needle) in &cases {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, out, err) = texopt(&a);
        assert_eq!(code, 2, "{a:?} exited {code}: {err}");
        assert!(out.is_empty(), "{a:?} printed to stdout: {out}");
        assert!(
            err.contains(needle),
            "{a:?}: message {err:?} lacks {needle:?}"
        );
        assert!(!err.contains("panicked"), "{a:?} panicked: {err}");
        assert!(!series.exists(), "{a:?} wrote {}", series.display());
    }
    // Our own messages are one line (clap's usage errors carry their usage hint).
    let (_, _, err) = texopt(&a2(&[
        "simulate", "--R", "0.8", "--l1", "0.04", "--per", "0.06", "--depth", "5",
    ]));
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("0.04") && err.contains("2·l1"));
}

fn to(a: &[&str]) -> Vec<String> {
    a.iter().map(|x| x.to_string()).collect()
}

fn a2<'a>(a: &'a [&'a str]) -> Vec<&'a str> {
    a.to_vec()
}

#[test]
fn fidelity_tiers_set_mesh_and_step_unless_overridden() {
    let (code, out, err) = texopt(&["simulate", "--R", "0.8", "--fidelity", "draft", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["inputs"]["mesh"], "400x8");
    // The characteristic step of the mesh: 2·dx1/u = 2·0.2/400.
    let dt = |v: &serde_json::Value| v["inputs"]["numerics"]["dt"].as_f64().unwrap();
    assert!((dt(&v) - 1e-3).abs() < 1e-15, "{}", dt(&v));
    // The tier's periodic tolerance too, so that `simulate` reproduces a study's row.
    assert_eq!(v["inputs"]["numerics"]["periodic_tol"], 1e-3);
    let (code, out, err) = texopt(&[
        "simulate",
        "--R",
        "0.8",
        "--fidelity",
        "draft",
        "--mesh",
        "64x4",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["inputs"]["mesh"], "64x4");
    // The step follows the mesh asked for, unless given.
    assert!((dt(&v) - 6.25e-3).abs() < 1e-15, "{}", dt(&v));
    let (code, out, err) = texopt(&[
        "simulate", "--R", "0.8", "--mesh", "64x4", "--dt", "5e-4", "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(dt(&v), 5e-4);
    // A step that would move the film more than a cell along the characteristics is refused.
    let (code, _, err) = texopt(&["simulate", "--R", "0.8", "--dt", "1e-3"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("dt") && err.contains("one cell"), "{err}");
    let (code, out, err) = texopt(&[
        "simulate",
        "--R",
        "0.8",
        "--fidelity",
        "fast",
        "--periodic-tol",
        "3e-6",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["inputs"]["numerics"]["periodic_tol"], 3e-6);
    // `fast` approaches the periodic regime on 120×4 cells at their characteristic step
    // unless told otherwise; `simulate` runs `fast` unless told otherwise.
    for (extra, want) in [
        (None, Some((120, 4, 2.0 * 0.2 / 120.0))),
        (Some("off"), None),
        (Some("64x2@8e-4"), Some((64, 2, 8e-4))),
    ] {
        let mut args = vec!["simulate", "--R", "0.8", "--json"];
        if let Some(x) = extra {
            args.extend(["--approach", x]);
        }
        let (code, out, err) = texopt(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        assert_eq!(v["inputs"]["mesh"], "700x8");
        assert_eq!(v["inputs"]["numerics"]["periodic_tol"], 1e-4);
        assert_eq!(v["inputs"]["numerics"]["scheme"], "characteristic");
        let a = &v["inputs"]["numerics"]["approach"];
        let got = a.is_object().then(|| {
            (
                a["n1"].as_u64().unwrap(),
                a["n2"].as_u64().unwrap(),
                a["dt"].as_f64().unwrap(),
            )
        });
        assert_eq!(got, want, "{extra:?}");
    }
}

#[test]
fn simulate_resolves_small_pockets_as_studies_do() {
    // l2 = 0.005 in a 0.05-wide cell spans 3.2 of the fast tier's 8 cells across: the tier
    // raises N2 to 10 (4 cells a pocket), as `study` and `optimise` do, a --mesh's N2 too.
    let run = |mesh: Option<&str>| {
        let mut args = vec![
            "simulate",
            "--R",
            "3.2",
            "--l1",
            "0.005",
            "--per",
            "0.05",
            "--depth",
            "10",
            "--fidelity",
            "fast",
            "--t-max",
            "0.05",
            "--json",
        ];
        if let Some(m) = mesh {
            args.extend(["--mesh", m]);
        }
        let (code, out, err) = texopt(&args);
        assert_ne!(code, 2, "{err}");
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        v["inputs"]["mesh"].as_str().unwrap().to_string()
    };
    assert_eq!(run(None), "700x10");
    assert_eq!(run(Some("512x8")), "512x10");
    assert_eq!(run(Some("512x2")), "512x10");
    assert_eq!(run(Some("512x12")), "512x12");
}

#[test]
fn bench_runs_the_engine_cycle_only_when_named() {
    let path = scratch("bench-cycle.json");
    let p = path.to_str().unwrap();
    let (code, out, err) = texopt(&[
        "bench",
        "--case",
        "cycle-plain",
        "--case",
        "untextured-R0.8",
        "--repeat",
        "2",
        "--out",
        p,
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 2, "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(v["cases"].as_array().unwrap().len(), 1);
    let rows = v["cycle_cases"].as_array().unwrap();
    assert_eq!(rows.len(), 1);
    let c = &rows[0];
    assert_eq!(c["name"], "cycle-plain");
    assert_eq!(c["fidelity"], "draft");
    assert!(c["cyclic"].as_bool().unwrap(), "{c}");
    assert!(c["cycles"].as_u64().unwrap() >= 2, "{c}");
    assert!(c["last_cycle_steps"].as_u64().unwrap() > 0, "{c}");
    assert!(c["work_j_per_m"].as_f64().unwrap() > 0.0, "{c}");
    assert_eq!(c["wall_times_s"].as_array().unwrap().len(), 2);
    // Judged against `fast` (measured −0.07 %: the plain liner's tier error).
    assert_eq!(c["finer"]["fidelity"], "fast", "{c}");
    assert!(c["work_error"].as_f64().unwrap().abs() < 5e-3, "{c}");

    // A film case alone writes no cycle rows: the benchmark's own file keeps its form.
    let (code, _, err) = texopt(&[
        "bench",
        "--fidelity",
        "draft",
        "--case",
        "untextured-R0.8",
        "--repeat",
        "1",
        "--out",
        p,
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert!(v.get("cycle_cases").is_none(), "{v}");
}

#[test]
fn bench_writes_one_row_per_case_with_timings() {
    let path = scratch("bench.json");
    let p = path.to_str().unwrap();
    let (code, out, err) = texopt(&[
        "bench",
        "--fidelity",
        "draft",
        "--case",
        "untextured-R0.8",
        "--case",
        "case-III",
        "--repeat",
        "2",
        "--out",
        p,
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 2, "{out}");
    assert!(out.contains("best of 2"), "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 2);
    let c3 = cases.iter().find(|c| c["name"] == "case-III").unwrap();
    for key in [
        "wall_time_s",
        "steps",
        "periods",
        "iterations_per_step",
        "ms_per_step",
    ] {
        assert!(c3[key].as_f64().unwrap() > 0.0, "{key}: {}", c3[key]);
    }
    assert!(c3["outcome"]["converged"].as_bool().unwrap());
    // Each case ran twice (with the same outcome, else it would have failed); its row
    // reports the shorter wall time and lists both.
    let walls: Vec<f64> = c3["wall_times_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_f64().unwrap())
        .collect();
    assert_eq!(walls.len(), 2);
    let best = walls.iter().cloned().fold(f64::INFINITY, f64::min);
    assert_eq!(c3["wall_time_s"].as_f64().unwrap(), best);
    assert_eq!(c3["outcome"]["wall_time_s"].as_f64().unwrap(), best);
    assert_eq!(v["repeat"], 2);
    assert_eq!(c3["fidelity"], "draft");
    // The speed targets are stated from the paper's initial state: that is the default.
    assert_eq!(v["start"], "paper");
    assert_eq!(c3["numerics"]["start"], "paper");
    // Case III has a converged reference: its errors against it are reported (draft's are
    // a few per cent, never zero); the untextured ring has none.
    let e = c3["f_error"].as_f64().unwrap();
    assert!(e != 0.0 && e.abs() < 0.1, "{e}");
    let plain = cases
        .iter()
        .find(|c| c["name"] == "untextured-R0.8")
        .unwrap();
    assert!(plain["f_error"].is_null());
}

#[test]
fn json_and_series_deliver_the_promised_fields() {
    let series = scratch("series.csv");
    let case_three = |extra: &[&str]| {
        let mut args = vec![
            "simulate", "--R", "3.2", "--l1", "0.03", "--per", "0.06", "--depth", "10", "--mesh",
            "64x4", "--dt", "8e-4", "--json", "--series",
        ];
        args.push(series.to_str().unwrap());
        args.extend_from_slice(extra);
        texopt(&args)
    };
    let (code, out, err) = case_three(&["--approach", "off"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).expect("one JSON object");
    for key in [
        "f_mean",
        "f_couette",
        "f_poiseuille",
        "f_pressure",
        "z_mean",
        "z_min",
        "z_max",
        "c_min",
        "periods",
        "steps",
        "converged",
        "wall_time_s",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {out}");
    }
    assert_eq!(v["inputs"]["case"]["R"], 3.2);
    assert_eq!(v["inputs"]["mesh"], "64x4");
    assert_eq!(v["converged"], true);
    let csv = std::fs::read_to_string(&series).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,t_ms,Z,W_h,f,f_couette,f_poiseuille,f_pressure"
    );
    assert_eq!(lines.count() as u64, v["steps"].as_u64().unwrap());
    assert!(
        v.get("approach_steps").is_none(),
        "no approach was asked for"
    );

    // With a coarse approach (32x2 at twice the step first): its steps are counted and in
    // the series too.
    let (code, out, err) = case_three(&["--approach", "32x2@1.6e-3"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).expect("one JSON object");
    let (steps, coarse) = (
        v["steps"].as_u64().unwrap(),
        v["approach_steps"].as_u64().unwrap(),
    );
    assert!(
        coarse > 0 && coarse < steps,
        "{coarse} of {steps} steps coarse"
    );
    let csv = std::fs::read_to_string(&series).unwrap();
    assert_eq!(csv.lines().count() as u64, steps + 1);

    // The untextured liner: steady 1D, human summary with units.
    let (code, out, _) = texopt(&["simulate", "--R", "0.8"]);
    assert_eq!(code, 0);
    assert!(out.contains("µm") && out.contains("steady 1D"), "{out}");
    // --allow-thick-pockets lifts the thin-film rule.
    let (code, _, err) = texopt(&[
        "simulate",
        "--R",
        "0.8",
        "--l1",
        "0.0025",
        "--per",
        "0.06",
        "--depth",
        "10",
        "--mesh",
        "128x16",
        "--allow-thick-pockets",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn progress_reaches_a_log_at_the_rate_asked() {
    // The tests' stderr is a pipe, as in a batch job: no in-place line, plain lines instead.
    let run = |extra: &[&str]| {
        let mut args = vec![
            "simulate", "--R", "3.2", "--l1", "0.03", "--per", "0.06", "--depth", "10", "--mesh",
            "64x4", "--json",
        ];
        args.extend_from_slice(extra);
        let (code, out, err) = texopt(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(out.trim()).expect("one JSON object");
        (v["periods"].as_u64().unwrap(), err)
    };
    // Every period (one period a window here: per = 0.06): one line each, the last at the
    // run's final period; the JSON on stdout stays one object.
    let (periods, err) = run(&["--progress-every", "0"]);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("period")).collect();
    assert_eq!(lines.len() as u64, periods, "{err}");
    let last: u64 = lines[lines.len() - 1]
        .split_whitespace()
        .nth(1)
        .and_then(|x| x.parse().ok())
        .expect("a period number");
    assert_eq!(last, periods);
    // The default (a line at most every 10 s): a run of a fraction of a second prints none;
    // nor does a rate beyond what a duration holds (no panic either).
    for extra in [&[][..], &["--progress-every", "1e300"][..]] {
        let (_, err) = run(extra);
        assert!(!err.contains("period") && !err.contains("panic"), "{err}");
    }
}

#[test]
fn cache_commands_refuse_a_missing_cache_and_create_nothing() {
    let dir = scratch("no-such-dir");
    let path = dir.join("c.sqlite");
    for action in ["stats", "export", "clear"] {
        let (code, _, err) = texopt(&["cache", action, "--cache", path.to_str().unwrap()]);
        assert_eq!(code, 2, "{action}: {err}");
        assert!(err.contains("no cache at"), "{action}: {err}");
        assert!(!dir.exists(), "{action} created {}", dir.display());
    }
}

#[test]
fn a_partial_bench_run_never_replaces_the_benchmark_file() {
    // Run where a committed benchmark sits: a partial run writes its own file beside it.
    let dir = scratch("bench-default-out");
    std::fs::create_dir_all(dir.join("results/bench")).unwrap();
    let committed = dir.join("results/bench/bench.json");
    std::fs::write(&committed, "{\"committed\": true}").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_texopt"))
        .args([
            "bench",
            "--fidelity",
            "draft",
            "--case",
            "untextured-R0.8",
            "--repeat",
            "1",
        ])
        .current_dir(&dir)
        .output()
        .expect("run texopt");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let own = dir.join("results/bench/bench-draft-x1-untextured-R0.8.json");
    assert!(
        err.contains("wrote results/bench/bench-draft-x1-untextured-R0.8.json"),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(own).unwrap()).unwrap();
    assert_eq!(v["cases"].as_array().unwrap().len(), 1);
    assert_eq!(
        std::fs::read_to_string(&committed).unwrap(),
        "{\"committed\": true}"
    );
}

/// A conformal ring under backward Euler at the tiers' time step is told that dt sets its
/// error (docs/validation.md: R = 51.2 at dt = 4e-4 is ≈ 3 % off); a ring that is not, the
/// smaller dt, or BDF2 (the tiers' default but paper's) is not.
#[test]
fn a_conformal_ring_at_a_coarse_time_step_gets_a_note() {
    let run = |r: &str, extra: &[&str]| {
        let mut args: Vec<&str> = "simulate --l1 0.01 --per 0.06 --depth 5 --fidelity draft --json"
            .split(' ')
            .collect();
        args.extend(["--R", r]);
        args.extend_from_slice(extra);
        let (code, _, err) = texopt(&args);
        assert_eq!(code, 0, "{err}");
        err.contains("conformal ring")
    };
    let be = ["--time-scheme", "backward-euler"];
    assert!(run("51.2", &be), "no note at R = 51.2, dt = 5.4e-4");
    assert!(
        !run("51.2", &[&be[..], &["--dt", "1e-4"]].concat()),
        "a note at dt = 1e-4"
    );
    assert!(!run("0.8", &be), "a note at R = 0.8");
    assert!(!run("51.2", &[]), "a note with BDF2");
}

/// Pockets far deeper than the film is thick get a note, at a tier that stays on its mesh, that
/// its cells do not resolve their rims (results/deep_pockets/); Case III's 10 µm pockets do not.
#[test]
fn pockets_far_deeper_than_the_film_get_a_note() {
    let run = |depth: &str| {
        let (code, _, err) = texopt(&[
            "simulate",
            "--R",
            "3.2",
            "--l1",
            "0.03",
            "--per",
            "0.06",
            "--depth",
            depth,
            "--fidelity",
            "draft",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        err.contains("rims are narrower than the cells")
    };
    assert!(run("20"), "no note for 20 µm pockets");
    assert!(!run("10"), "a note for Case III");
}
