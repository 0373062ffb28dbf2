//! Operating conditions in physical units (docs/model.md §1, §8): the paper's point in SI is
//! the paper's run to the bit; similar rings are one scaled problem; outcomes in N/m and W/m
//! are f̄ times the scales; bad inputs are refused; thin films are flagged; studies take
//! physical axes.

mod common;

use common::{scratch, texopt};
use serde_json::Value;

/// Case III's texture at a quick look's numerics.
const CASE: [&str; 12] = [
    "simulate", "--R", "3.2", "--l1", "0.03", "--per", "0.06", "--depth", "10", "--mesh", "128x4",
    "--json",
];

fn run(extra: &[&str]) -> Value {
    let args: Vec<&str> = CASE.iter().copied().chain(extra.iter().copied()).collect();
    let (code, out, err) = texopt(&args);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

/// The outcomes a run computes (wall time left out).
fn outcomes(v: &Value) -> Vec<(String, Value)> {
    [
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
    ]
    .iter()
    .map(|k| (k.to_string(), v[*k].clone()))
    .collect()
}

fn num(v: &Value, path: &[&str]) -> f64 {
    let mut x = v;
    for k in path {
        x = &x[*k];
    }
    x.as_f64()
        .unwrap_or_else(|| panic!("{path:?} is not a number: {x}"))
}

#[test]
fn the_papers_point_in_si_is_the_dimensionless_run_bit_for_bit() {
    let plain = run(&[]);
    let si = run(&[
        "--speed",
        "10",
        "--load",
        "39.84",
        "--viscosity",
        "0.004",
        "--ring-width",
        "0.8",
        "--ring-mass",
        "0.048",
        "--d-oil",
        "20",
    ]);
    assert_eq!(outcomes(&plain), outcomes(&si));
    assert_eq!(plain["inputs"]["case"], si["inputs"]["case"]);
}

#[test]
fn similar_rings_give_the_same_outcomes_and_si_figures_are_f_times_the_scales() {
    // p scales with μU and the ring's inertia with M·U²: twice the viscosity at half the
    // speed with four times the mass is the same scaled problem (docs/model.md §1).
    let a = run(&[
        "--load",
        "60",
        "--viscosity",
        "0.004",
        "--speed",
        "12",
        "--ring-mass",
        "0.03",
    ]);
    let b = run(&[
        "--load",
        "60",
        "--viscosity",
        "0.008",
        "--speed",
        "6",
        "--ring-mass",
        "0.12",
    ]);
    assert_eq!(outcomes(&a), outcomes(&b));
    for (v, speed, load) in [(&a, 12.0, 60.0), (&b, 6.0, 60.0)] {
        let f = num(v, &["f_mean"]);
        let force = num(v, &["physical", "friction_n_per_m"]);
        let power = num(v, &["physical", "power_w_per_m"]);
        // (the scaled load is the given one to 12 significant digits)
        assert!(
            ((force - f * load) / force).abs() < 1e-11,
            "{force} vs {}",
            f * load
        );
        assert!(((power - force * speed) / power).abs() < 1e-11);
        assert!((num(v, &["physical", "stribeck"]) - 0.004 * 12.0 / 60.0).abs() < 1e-12);
    }
    // Same force, half the power at half the speed.
    assert_eq!(
        num(&a, &["physical", "friction_n_per_m"]),
        num(&b, &["physical", "friction_n_per_m"])
    );
    // And a different load is a different answer (the flags reach the model).
    let c = run(&["--load", "80"]);
    assert_ne!(num(&c, &["f_mean"]), num(&run(&[]), &["f_mean"]));
}

#[test]
fn bad_physical_inputs_are_refused_with_exit_2_one_line_and_nothing_written() {
    let dir = scratch("bad-si");
    let series = dir.join("s.csv");
    let s = series.to_str().unwrap();
    for (flag, value) in [
        ("--speed", "-1"),
        ("--speed", "0"),
        ("--load", "0"),
        ("--load", "4e7"),
        ("--viscosity", "NaN"),
        ("--viscosity", "inf"),
        ("--ring-width", "50"),
        ("--ring-mass", "1e9"),
        ("--d-oil", "0"),
        ("--roughness", "-0.3"),
    ] {
        let args: Vec<&str> = CASE
            .iter()
            .copied()
            .chain([flag, value, "--series", s])
            .collect();
        let (code, out, err) = texopt(&args);
        assert_eq!(code, 2, "{flag} {value}: {err}");
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{flag} {value}: {err}");
        assert!(lines[0].contains(flag), "{flag} {value}: {err}");
        let json: Value = serde_json::from_str(&out).unwrap();
        assert_eq!(json["exit_code"], 2);
        assert!(!series.exists(), "{flag} {value} wrote the series");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_run_below_the_clearance_limit_is_flagged_in_json_and_csv() {
    // Case III's ring sits ≈ 4–6 µm above the liner: within the model at the default
    // roughness (limit 0.9 µm), outside it on a rough liner of σ = 2 µm (limit 6 µm).
    assert!(run(&[])["outside_model"].is_null());
    let rough = run(&["--roughness", "2"]);
    let why = rough["outside_model"].as_str().unwrap();
    assert!(why.contains("C_min") && why.contains("6.00 µm"), "{why}");

    let dir = scratch("flag-csv");
    let file = dir.join("flag.toml");
    std::fs::write(
        &file,
        format!(
            "[study]\nname = \"flag\"\nfidelity = \"draft\"\nuntextured = true\nroughness = 2\n[parameters]\nR = 3.2\ntexture = [{{ l1 = 0.03, per = 0.06, depth = 10 }}]\nload = [20, 39.84]\n[numerics]\nn1 = 128\nn2 = 4\n[report]\ndir = \"{}\"\n",
            dir.join("out").display()
        ),
    )
    .unwrap();
    let cache = dir.join("c.sqlite");
    let (code, _, err) = texopt(&[
        "study",
        file.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let mut rd = csv::Reader::from_path(dir.join("out/flag.csv")).unwrap();
    let head = rd.headers().unwrap().clone();
    let col = |k: &str| head.iter().position(|h| h == k).unwrap();
    let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 4);
    for r in &rows {
        let c_min: f64 = r[col("c_min")].parse().unwrap();
        let flagged = !r[col("outside_model")].is_empty();
        assert_eq!(
            flagged,
            c_min < 6.0,
            "c_min {c_min}: {:?}",
            &r[col("outside_model")]
        );
        // Load in N/m and friction force = f̄ × load.
        let load: f64 = r[col("load_n_m")].parse().unwrap();
        let f: f64 = r[col("f_mean")].parse().unwrap();
        let force: f64 = r[col("friction_n_m")].parse().unwrap();
        assert!(((force - f * load) / force).abs() < 1e-11);
    }
    assert!(rows.iter().any(|r| !r[col("outside_model")].is_empty()));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_radii_of_a_robust_design_are_refused() {
    for (args, says) in [
        (vec!["--R", "5..3"], "0 < LO < HI"),
        (vec!["--R", "5..12.8", "--radii", "1"], "--radii"),
        (vec!["--R", "5,8", "--radii", "3"], "--radii"),
        (vec!["--R", "5,inf"], "--R = inf"),
        (vec!["--R", "5,x"], "--R"),
        (vec!["--R", "5", "--load", "-3"], "--load"),
    ] {
        let dir = scratch("radii");
        let out = dir.join("out");
        let cache = dir.join("c.sqlite");
        let mut all = vec!["optimise", "--out", out.to_str().unwrap()];
        all.extend(args.iter().copied());
        all.extend(["--cache", cache.to_str().unwrap()]);
        let (code, _, err) = texopt(&all);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote its output");
        let _ = std::fs::remove_dir_all(dir);
    }
}
