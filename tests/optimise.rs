//! The optimiser's contract (issue: `texopt optimise`), on a coarse mesh (64×4, dt 1.6e-3) so
//! that the suite stays fast: the searches run at the same numerics as the reported designs.
//! Pockets are bounded below by 0.005 cm so that 64 cells resolve them, except in the
//! close-packed test, which keeps the paper's bounds on 128×4.

mod common;

use common::texopt;
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;

use texopt::model::case::CaseSpec;
use texopt::model::operating::{Scales, Validity};
use texopt::optimise::design::Report;
use texopt::optimise::driver::{optimise, Settings};
use texopt::optimise::goal::pareto;
use texopt::optimise::search::{SearchSettings, SwarmSettings};
use texopt::optimise::space::{Bounds, Constraints, Space};
use texopt::study::cache::Cache;
use texopt::time::Fidelity;
use texopt::time::Overrides;

fn cache(name: &str) -> Mutex<Cache> {
    let p = std::env::temp_dir().join(format!("texopt-opt-{}-{name}.sqlite", std::process::id()));
    for ext in ["", "-wal", "-shm"] {
        let _ = std::fs::remove_file(format!("{}{ext}", p.display()));
    }
    Mutex::new(Cache::open(&p).unwrap())
}

fn settings(r: f64, w_min_um: f64) -> Settings {
    let search = SearchSettings {
        validity: Validity::default(),
        space: Space {
            bounds: Bounds {
                l1: (0.005, 0.03),
                l2: (0.005, 0.03),
                // 8 steps a period at the quick look's dt = 1.6e-3 at least.
                per: (0.0128, 0.06),
                ..Bounds::default()
            },
            cons: Constraints {
                w_min: w_min_um * 1e-4,
                ..Constraints::default()
            },
        },
        search_fidelity: Fidelity::Fast,
        report_fidelity: Fidelity::Fast,
        overrides: Overrides {
            n1: Some(64),
            n2: Some(4),
            dt: Some(1.6e-3),
            ..Overrides::default()
        },
        swarm: SwarmSettings::DEFAULT,
        jobs: 2,
        limits: texopt::time::Limits::default(),
        progress: false,
        out_dir: None,
    };
    Settings {
        base: CaseSpec::paper(r),
        scales: Scales::PAPER,
        search,
        balanced: vec![0.5],
    }
}

fn run(s: &Settings, c: &Mutex<Cache>) -> Report {
    optimise(s, c, &AtomicBool::new(false)).unwrap()
}

/// Contracts every report must keep.
fn check_contracts(r: &Report) {
    for e in &r.evaluated {
        let v = r.space.violations(&e.texture);
        assert!(
            v.is_empty(),
            "evaluated an infeasible design {:?}: {v:?}",
            e.texture
        );
    }
    let pts: Vec<(f64, f64)> = r.front.iter().map(|x| (x.f_mean, x.c_min)).collect();
    assert_eq!(pareto(&pts).len(), pts.len(), "the front is non-dominated");
    let has = |x: &texopt::optimise::design::Row| {
        r.front
            .iter()
            .any(|f| f.texture == x.texture && f.f_mean == x.f_mean)
    };
    assert!(has(&r.best_friction) && has(&r.best_clearance));
}

#[test]
fn large_ring_optimum_is_a_close_packed_array_and_reruns_are_free() {
    let c = cache("large");
    // The paper's bounds (l ≥ 0.0025 cm needs 128 cells along x1 to resolve the pocket),
    // periods from 0.0128 cm (8 steps a period at the quick look's dt).
    let mut s = settings(5.0, 0.0);
    s.search.space.bounds = Bounds {
        per: (0.0128, 0.06),
        ..Bounds::default()
    };
    s.search.overrides.n1 = Some(128);
    let r = run(&s, &c);
    check_contracts(&r);
    let t = r
        .best_friction
        .texture
        .clone()
        .expect("a texture beats the plain liner");
    assert!(2.0 * t.l1 / t.per >= 0.9, "{t:?}");
    assert!(t.per >= 0.05, "{t:?}");
    assert!((5.0..=20.0).contains(&t.depth), "{t:?}");
    assert!(r.texture_beats_plain, "{}", r.verdict);
    assert!(r.best_friction.f_change_pct < -100.0 * r.fidelity_error);
    let again = run(&s, &c);
    assert_eq!(
        again.simulations, 0,
        "a second identical run simulates nothing"
    );
    assert_eq!(again.best_friction.texture, r.best_friction.texture);
}

#[test]
fn with_a_least_wall_the_optimum_sits_on_the_wall_constraint() {
    let c = cache("wall");
    let w_min_um = 100.0;
    let r = run(&settings(5.0, w_min_um), &c);
    check_contracts(&r);
    let t = r.best_friction.texture.clone().unwrap();
    let wall = (t.per - 2.0 * t.l1).min(t.width - 2.0 * t.l2);
    assert!(wall >= w_min_um * 1e-4 * (1.0 - 1e-9), "{t:?}");
    assert!(
        wall <= w_min_um * 1e-4 * 1.05,
        "wall {wall} cm not on the constraint: {t:?}"
    );
}

#[test]
fn small_ring_plain_liner_is_best() {
    let c = cache("small");
    let r = run(&settings(0.4, 10.0), &c);
    check_contracts(&r);
    assert!(!r.texture_beats_plain, "{}", r.verdict);
    assert!(r.verdict.contains("plain liner is best"), "{}", r.verdict);
}

#[test]
fn bad_optimiser_inputs_are_refused_with_exit_2_and_nothing_written() {
    let dir = std::env::temp_dir().join(format!("texopt-opt-bad-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("out");
    let cache = dir.join("c.sqlite");
    let bad_config = dir.join("bad.toml");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(&bad_config, "l1 = [0.005, 0.03]\ncolour = 3\n").unwrap();
    let missing = dir.join("missing.toml");
    let cases: [(&[&str], &str); 16] = [
        (
            &["--config", bad_config.to_str().unwrap()],
            "unknown field `colour`",
        ),
        (&["--config", missing.to_str().unwrap()], "cannot read it"),
        (&["--l1", "0.03..0.01"], "--l1"),
        (&["--depth", "0..5"], "--depth"),
        (
            &["--per", "0.005..0.006", "--w-min", "20"],
            "no feasible texture",
        ),
        (&["--l1", "abc"], "expected a range LO..HI"),
        (&["--balanced", "1.5"], "strictly between 0 and 1"),
        (&["--particles", "1"], "--particles"),
        (&["--max-area", "0.9"], "--max-area"),
        (
            &["--jobs", "0"],
            "'--jobs <N>': must be a whole number from 1 to 256",
        ),
        (&["--jobs", "100000"], "from 1 to 256"),
        (&["--dt", "0.06"], "--dt 0.06: gives only 1 time steps"),
        (&["--w-min", "-5"], "--w-min"),
        (&["--max-depth-ratio", "0"], "--max-depth-ratio"),
        (&["--mesh", "8x2"], "--mesh"),
        (&["--dt", "-1"], "--dt"),
    ];
    for (extra, want) in cases {
        let mut args = vec![
            "optimise",
            "--R",
            "5",
            "--out",
            out.to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, _, err) = texopt(&args);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert!(
            err.contains(want),
            "{extra:?}: {err:?} should contain {want:?}"
        );
        assert!(
            !out.exists() && !cache.exists(),
            "{extra:?}: nothing may be written"
        );
    }
    let (code, _, _) = texopt(&[
        "optimise",
        "--R",
        "0.01",
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(!cache.exists());
    // An --out that cannot be made (under a file) stops it before the search, not after
    // (a small search, so that a broken check costs seconds).
    let blocker = dir.join("a-file");
    std::fs::write(&blocker, "").unwrap();
    let blocked = blocker.join("report");
    let (code, _, err) = texopt(&[
        "optimise",
        "--R",
        "5",
        "--particles",
        "2",
        "--iterations",
        "1",
        "--mesh",
        "64x4",
        "--out",
        blocked.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot create"), "{err}");
    assert!(!cache.exists(), "the search ran: its cache was made");
}

/// A search killed (SIGKILL) mid-way and started again with the same flags resumes through
/// the cache: it simulates only what the killed one had not finished, and reports exactly
/// what an uninterrupted search reports.
#[test]
fn a_killed_search_resumes_through_the_cache_with_the_same_answer() {
    let dir = std::env::temp_dir().join(format!("texopt-opt-kill-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let cmd = |cache: &str| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_texopt"));
        c.args([
            "optimise",
            "--R",
            "5",
            "--mesh",
            "64x4",
            "--dt",
            "1.6e-3",
            "--l1",
            "0.005..0.03",
            "--l2",
            "0.005..0.03",
            "--per",
            "0.0128..0.06",
            "--search-fidelity",
            "fast",
            "--jobs",
            "2",
            "--json",
            "--cache",
        ])
        .arg(dir.join(cache))
        .arg("--out")
        .arg(dir.join(format!("out-{cache}")))
        .stderr(std::process::Stdio::null());
        c
    };
    let json = |out: std::process::Output| -> serde_json::Value {
        assert!(out.status.success());
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let whole = json(cmd("a.sqlite").output().unwrap());

    // Killed once it has stored some evaluations (of the 200 or so it makes).
    let mut child = cmd("b.sqlite")
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let stored = |n: usize| {
        Cache::open(&dir.join("b.sqlite"))
            .ok()
            .and_then(|c| c.stats().ok())
            .is_some_and(|s| s.done >= n)
    };
    let t0 = std::time::Instant::now();
    while !stored(20) {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the search ended ({status}) before it could be killed mid-way");
        }
        assert!(
            t0.elapsed().as_secs() < 900,
            "no evaluation stored in 15 min"
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    child.kill().unwrap();
    child.wait().unwrap();

    let resumed = json(cmd("b.sqlite").output().unwrap());
    let sims = |v: &serde_json::Value| v["simulations"].as_u64().unwrap();
    assert!(
        sims(&resumed) < sims(&whole),
        "resumed {} vs whole {}",
        sims(&resumed),
        sims(&whole)
    );
    for key in [
        "best_friction",
        "best_clearance",
        "front",
        "plain",
        "evaluated",
    ] {
        assert_eq!(resumed[key], whole[key], "{key} differs after the kill");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// f̄ of `t` (None: the plain liner) on ring `r`, simulated directly at `s`'s numerics: an
/// evaluation that shares nothing with the optimiser's cache.
fn f_direct(s: &Settings, r: f64, t: Option<&texopt::model::case::Texture>) -> f64 {
    let case = CaseSpec {
        texture: t.cloned(),
        ..CaseSpec::paper(r)
    };
    let num = texopt::time::resolve(s.search.report_fidelity, &s.search.overrides, &case);
    let opts = texopt::time::RunOptions::default();
    texopt::time::simulate_with(&case, &num, &opts, &mut Default::default())
        .unwrap()
        .outcome
        .f_mean
}

#[test]
fn the_robust_design_is_no_worse_over_the_range_than_any_radius_optimum() {
    let c = cache("robust");
    let radii = [3.2, 12.8];
    let dir = common::scratch("robust");
    let per_r: Vec<Settings> = radii
        .iter()
        .map(|&r| {
            let mut s = settings(r, 10.0);
            s.search.swarm.particles = 4;
            s.search.swarm.iterations = 2;
            s.search.out_dir = Some(dir.clone());
            s
        })
        .collect();
    let rep = texopt::optimise::robust::robust(&per_r, &c, &AtomicBool::new(false)).unwrap();
    assert_eq!(rep.radii, radii);
    // Each radius's report and the robust one, named with the whole radius.
    for f in [
        "optimise_R3.2.json",
        "optimise_R12.8.json",
        "optimise_R12.8_front.png",
        "robust_R3.2-12.8.json",
        "robust_R3.2-12.8.csv",
        "robust_R3.2-12.8.png",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let _ = std::fs::remove_dir_all(&dir);
    // Every ratio recomputed from direct simulations, outside the optimiser.
    let plain: Vec<f64> = radii
        .iter()
        .map(|&r| f_direct(&per_r[0], r, None))
        .collect();
    let worst = |t: &texopt::model::case::Texture| {
        radii
            .iter()
            .zip(&plain)
            .map(|(&r, p)| f_direct(&per_r[0], r, Some(t)) / p)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let robust = worst(&rep.robust.texture);
    assert_eq!(
        robust, rep.robust.worst,
        "the report's worst ratio is the simulated one"
    );
    for a in &rep.at_radius {
        if let Some(t) = &a.optimum {
            let w = worst(t);
            assert!(
                robust <= w,
                "robust worst ratio {robust} above that of R = {}'s optimum {t:?}: {w}",
                a.r
            );
        }
    }
    assert!(rep.robust.worst < 1.0, "{}", rep.verdict);
}
