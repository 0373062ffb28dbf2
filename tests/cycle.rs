//! `texopt cycle`: bad engine files are refused; the dead centres are excluded and carry no
//! number; a zone met at one operating point only is designed as `optimise` designs for it.
//! (The slider-crank kinematics against its closed form and a finite difference: the unit
//! tests of model::engine.)

mod common;

use common::{scratch, texopt};
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;

use texopt::model::case::CaseSpec;
use texopt::model::engine::{Engine, LinerZones};
use texopt::model::operating::{Scales, Validity};
use texopt::optimise::cycle::angles::{design, evaluate, CycleSettings, Point};
use texopt::optimise::goal::Goal;
use texopt::optimise::search::{swarm_and_refine, GoalSearch, SearchSettings, SwarmSettings};
use texopt::optimise::space::{Bounds, Constraints, Space};
use texopt::study::cache::Cache;
use texopt::study::engine_file;
use texopt::time::Overrides;
use texopt::time::{Fidelity, Limits};

/// The test engine with two zones.
fn engine_text() -> String {
    common::engine("count = 2")
}

/// The quick look's numerics: 64×4 at dt 1.6e-3 (8 steps in the shortest period).
const QUICK: [&str; 4] = ["--mesh", "64x4", "--dt", "1.6e-3"];

#[test]
fn bad_engine_files_are_refused_with_exit_2_one_line_and_nothing_written() {
    let dir = scratch("cycle-bad");
    for (from, to, says) in [
        ("rpm = 3000\n", "", "missing field `rpm`"),
        (
            "[0, 15, 60, 180, 360, 540, 690]",
            "[0, 15, 60, 50, 360, 540, 690]",
            "[gas] crank_deg",
        ),
        (
            "count = 2",
            "boundaries_mm = [0, 40, 90]",
            "[zones] boundaries_mm",
        ),
        ("bore_mm = 79", "bore_mm = -79", "[engine] bore_mm"),
        (
            "elastic_load_n_per_m = 150",
            "elastic_load_n_per_m = -1",
            "[ring] elastic_load_n_per_m",
        ),
        (
            "viscosity_pa_s = 0.007",
            "viscosity_pa_s = 70",
            "[oil] viscosity_pa_s",
        ),
        ("per = [0.0128, 0.06]", "per = [0.0128]", "[design]"),
        ("l1 = [0.005, 0.03]", "pitch = 3", "[design]"),
        ("R_cm = 5", "R_cm = 0.05", "must exceed half the ring width"),
        (
            "[gas]\n",
            "[gas]\nbelow_crank_deg = [0, 360]\n",
            "[gas] below_crank_deg",
        ),
        (
            "[gas]\n",
            "[gas]\nbelow_crank_deg = [0, 360]\nbelow_pressure_bar = [1, -2]\n",
            "[gas] below_pressure_bar",
        ),
        (
            "[gas]\n",
            "[gas]\nbelow_crank_deg = [360, 0]\nbelow_pressure_bar = [1, 2]\n",
            "[gas] below_crank_deg",
        ),
        (
            "[gas]\n",
            "[gas]\nbelow_crank_deg = [0, 800]\nbelow_pressure_bar = [1, 2]\n",
            "[gas] below_crank_deg",
        ),
        (
            "[gas]\n",
            "[gas]\nbelow_pressure_bar = [1, 2]\n",
            "[gas] below_crank_deg",
        ),
        (
            "[gas]\n",
            "[contact]\nliner_roughness_share = 1.5\n\n[gas]\n",
            "[contact] liner_roughness_share",
        ),
        // So slow that every angle's Stribeck number is below the validated range: refused
        // by the quasi-steady path (the transient one has no such range).
        (
            "rpm = 3000",
            "rpm = 10",
            "no crank angle of the cycle lies inside",
        ),
    ] {
        let quasi_steady = to == "rpm = 10";
        assert!(engine_text().contains(from), "{from}");
        let file = dir.join("e.toml");
        std::fs::write(&file, engine_text().replace(from, to)).unwrap();
        let out = dir.join("out");
        let cache = dir.join("c.sqlite");
        let mut args = vec![
            "cycle",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
        ];
        if quasi_steady {
            args.push("--quasi-steady");
        }
        let (code, _, err) = texopt(&args);
        assert_eq!(code, 2, "{to}: {err}");
        assert_eq!(err.lines().count(), 1, "{to}: {err}");
        assert!(err.contains(says), "{to}: expected {says:?} in {err}");
        assert!(
            !out.exists() && !cache.exists(),
            "{to}: something was written"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_dead_centres_are_excluded_and_carry_no_number() {
    let dir = scratch("cycle-dc");
    let file = dir.join("e.toml");
    std::fs::write(&file, engine_text()).unwrap();
    let mut extra = vec![
        "--quasi-steady",
        "--step",
        "10",
        "--design-step",
        "90",
        "--particles",
        "2",
        "--iterations",
        "1",
    ];
    extra.extend(QUICK);
    let (code, _, err, _) = common::cycle(&dir, &file, &extra);
    let out = dir.join("out");
    assert_eq!(code, 0, "{err}");
    // Each zone's search is announced as it starts (it can take minutes).
    assert!(err.contains("zone 1 of 2: searching over its"), "{err}");
    let json = std::fs::read_to_string(out.join("cycle_t.json")).unwrap();
    let r: serde_json::Value = serde_json::from_str(&json).unwrap();
    let samples = r["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 72);
    // The angles on either side of each dead centre: 0/720 and 360 (top), 180 and 540 (bottom).
    for dc in [0.0, 180.0, 360.0, 540.0, 720.0] {
        for s in samples {
            let a = s["crank_deg"].as_f64().unwrap();
            if (a - dc).abs() < 6.0 {
                assert!(s["excluded"].is_string(), "{a}° is not excluded: {s}");
                for k in 0..3 {
                    assert!(
                        s["force_n_per_m"][k].is_null() && s["c_min_um"][k].is_null(),
                        "{a}°: {s}"
                    );
                }
            }
        }
    }
    let excluded = r["excluded_cycle_fraction"].as_f64().unwrap();
    assert!(excluded > 0.0 && excluded < 1.0, "{excluded}");
    // The CSV leaves the excluded angles' numbers empty, and the report says how much is out.
    let csv = std::fs::read_to_string(out.join("cycle_t.csv")).unwrap();
    let row = csv
        .lines()
        .find(|l| l.starts_with("5,"))
        .expect("the 5° row");
    assert!(row.ends_with(",,,,,,"), "{row}");
    let md = std::fs::read_to_string(out.join("cycle_t.md")).unwrap();
    assert!(md.contains("% of the cycle's time"), "{md}");
    // It says why, counted by kind: as many angles slow near a dead centre as the samples say.
    let slow = samples
        .iter()
        .filter(|s| {
            s["excluded"]
                .as_str()
                .is_some_and(|w| w.contains("near a dead centre"))
        })
        .count();
    assert!(slow > 0);
    assert!(
        md.contains(&format!("{slow} angles slow near a dead centre")),
        "{md}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_transient_cycle_reports_three_liners_and_the_plain_ones_work_is_a_direct_runs() {
    let dir = scratch("cycle-transient");
    let file = dir.join("e.toml");
    std::fs::write(&file, engine_text()).unwrap();
    let mut extra = common::QUICK_SEARCH.to_vec();
    extra.extend(["--mesh", "192x8"]);
    let t0 = std::time::Instant::now();
    let (code, _, err, _) = common::cycle(&dir, &file, &extra);
    eprintln!("texopt cycle: {:.1} s", t0.elapsed().as_secs_f64());
    assert_eq!(code, 0, "{err}");
    let out = dir.join("out");
    let suffixes = [".md", "_steps.csv", "_cycles.csv", "_oil.csv", "_force.png"];
    let r = common::report_files(&out, "cycle_t", &suffixes);
    assert_eq!(r["excluded_cycle_fraction"].as_f64(), Some(0.0));
    // A mesh given in place of the tier's is said beside the tier.
    assert_eq!(r["mesh"].as_str(), Some("192×8"));
    let md = std::fs::read_to_string(out.join("cycle_t.md")).unwrap();
    assert!(md.contains("at draft on the mesh given, 192×8"), "{md}");
    let liners = r["liners"].as_array().unwrap();
    assert_eq!(liners.len(), 3);
    let work: Vec<f64> = liners
        .iter()
        .map(|l| l["work_j_per_m"].as_f64().unwrap())
        .collect();
    assert!(work.iter().all(|w| w.is_finite() && *w > 0.0), "{work:?}");

    // The plain liner run directly, on the command's --mesh.
    assert_eq!(work[0], common::plain_cycle_work(&engine_text(), (192, 8)));

    // The zones' search through the cache: run again over it, it runs nothing and finds the
    // same liners (the report's runs are made again).
    let ran = |log: &str| -> Option<(usize, usize)> {
        let line = log
            .lines()
            .rev()
            .find(|l| l.contains(" runs from the cache, "))?;
        let (_, tail) = line.rsplit_once(" (")?;
        let (held, rest) = tail.split_once(" runs from the cache, ")?;
        Some((
            held.parse().ok()?,
            rest.strip_suffix(" run)")?.parse().ok()?,
        ))
    };
    let (held, made) = ran(&err).expect("the search's cache counts");
    assert!(made > 0, "{err}");
    // Every number but the wall times (the report's and each liner's).
    let timeless = |mut r: serde_json::Value| {
        r.as_object_mut().unwrap().remove("wall_time_s");
        for l in r["liners"].as_array_mut().unwrap() {
            l.as_object_mut().unwrap().remove("wall_s");
        }
        r
    };
    let first = timeless(common::report_files(&out, "cycle_t", &[]));
    let (code, _, again, _) = common::cycle(&dir, &file, &extra);
    assert_eq!(code, 0, "{again}");
    assert_eq!(ran(&again), Some((held + made, 0)), "{again}");
    assert_eq!(timeless(common::report_files(&out, "cycle_t", &[])), first);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_zone_met_at_one_operating_point_gets_the_design_of_optimise_there() {
    // The paper's operating point at R = 5, met three times in the zone.
    let (engine, zones, _): (Engine, LinerZones, serde::de::IgnoredAny) =
        engine_file::parse(&engine_text()).unwrap();
    let space = Space {
        bounds: Bounds {
            l1: (0.005, 0.03),
            l2: (0.005, 0.03),
            per: (0.0128, 0.06),
            ..Bounds::default()
        },
        cons: Constraints::default(),
    };
    let overrides = Overrides {
        n1: Some(64),
        n2: Some(4),
        dt: Some(1.6e-3),
        ..Overrides::default()
    };
    let swarm = SwarmSettings {
        particles: 4,
        iterations: 2,
        seed: 3,
    };
    let sample = engine.samples(90.0, &zones)[1];
    let s = CycleSettings {
        engine,
        zones,
        search: SearchSettings {
            space: space.clone(),
            validity: Validity::default(),
            search_fidelity: Fidelity::Draft,
            report_fidelity: Fidelity::Draft,
            overrides,
            swarm,
            jobs: 2,
            limits: Limits::default(),
            progress: false,
            out_dir: None,
        },
        min_clearance_um: 0.9,
        step_deg: 90.0,
        design_step_deg: 90.0,
    };
    let path = std::env::temp_dir().join(format!("texopt-cycle-{}.sqlite", std::process::id()));
    let _ = std::fs::remove_file(&path);
    let cache = Mutex::new(Cache::open(&path).unwrap());
    let stop = AtomicBool::new(false);
    let point = Point {
        sample,
        base: CaseSpec::paper(5.0),
        scales: Scales::PAPER,
        distance_m: 0.01,
        excluded: None,
    };
    let pts = vec![&point, &point, &point];
    let plain: Vec<f64> = evaluate(
        &s,
        &pts,
        &[None, None, None],
        Fidelity::Draft,
        &cache,
        &stop,
    )
    .unwrap()
    .into_iter()
    .map(|r| r.unwrap().1)
    .collect();
    let (zoned, _) = design(&s, pts, &plain, &cache, &stop)
        .unwrap()
        .expect("a texture pays at R = 5");

    // optimise's friction search at the same operating point, settings and seed.
    let ev = common::evaluator(
        CaseSpec::paper(5.0),
        Scales::PAPER,
        Fidelity::Draft,
        overrides,
        (&cache, &stop),
        2,
    );
    let plain = ev.plain().unwrap();
    let pb = GoalSearch {
        space: &space,
        eval: &ev,
        goal: Goal::Friction,
        plain,
    };
    let (u, _) = swarm_and_refine(&pb, swarm, &[]).unwrap();
    assert_eq!(zoned, space.decode(&u));
    let _ = std::fs::remove_file(&path);
}

#[test]
fn the_angle_by_angle_steps_are_refused_without_quasi_steady() {
    let dir = scratch("cycle-steps-refused");
    let file = dir.join("e.toml");
    std::fs::write(&file, engine_text()).unwrap();
    // The transient cycle's steps follow the crank, the band search's too: --dt, the
    // periodic runs' time step, would be ignored as the angle steps would.
    for (flag, value, bands) in [
        ("--step", "30", false),
        ("--design-step", "30", false),
        ("--dt", "1e-3", false),
        ("--dt", "1e-3", true),
        ("--step", "30", true),
    ] {
        let mut args = vec![flag, value];
        if bands {
            args.push("--bands");
        }
        let (code, _, err, wrote) = common::cycle(&dir, &file, &args);
        assert_eq!(code, 2, "{flag}: {err}");
        assert_eq!(err.lines().count(), 1, "{flag}: {err}");
        assert!(
            err.contains(flag) && err.contains("--quasi-steady"),
            "{err}"
        );
        assert!(!wrote, "{flag}: something was written");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_transient_cycle_modes_are_held_to_the_run_limits_before_anything_runs() {
    let dir = scratch("cycle-limits");
    let file = dir.join("e.toml");
    std::fs::write(&file, engine_text()).unwrap();
    // The plain liner's crank steps over its most cycles already pass 100 steps, and its
    // film of 96×4 cells a few kilobytes; both searches refuse before a run, naming the mesh,
    // the liner and the limit to raise.
    for (limit, value, bands) in [
        ("--max-steps", "100", false),
        ("--max-steps", "100", true),
        ("--max-memory", "1e-6", false),
    ] {
        let mut args = vec!["--mesh", "96x4", limit, value];
        if bands {
            args.push("--bands");
        }
        let (code, _, err, wrote) = common::cycle(&dir, &file, &args);
        assert_eq!(code, 2, "{limit}: {err}");
        assert_eq!(err.lines().count(), 1, "{limit}: {err}");
        assert!(
            err.contains("--mesh = 96x4") && err.contains(limit) && err.contains("plain liner"),
            "{err}"
        );
        assert!(!wrote, "{limit}: something was written");
    }
    let _ = std::fs::remove_dir_all(dir);
}
