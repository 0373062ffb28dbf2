//! `simulate --snapshots`: the instants asked for, all in the run's last period; fields that
//! integrate to the run's load at each instant; bad requests refused before any simulation.

mod common;

use common::texopt;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("texopt-snap-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Case I at `draft`, the cheapest run with a real pocket passage.
const CASE_ONE: [&str; 10] = [
    "simulate", "--R", "0.8", "--l1", "0.01", "--per", "0.06", "--depth", "5", "--json",
];

fn run_with_snapshots(dir: &Path, frames: &str) -> (serde_json::Value, serde_json::Value) {
    let d = dir.to_str().unwrap();
    let mut args = CASE_ONE.to_vec();
    args.extend(["--fidelity", "draft", "--snapshots", d, "--frames", frames]);
    let (code, out, err) = texopt(&args);
    assert_eq!(code, 0, "{err}");
    let run: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let index = std::fs::read_to_string(dir.join("snapshots.json")).unwrap();
    (run, serde_json::from_str(&index).unwrap())
}

#[test]
fn the_requested_instants_are_written_and_fall_in_the_last_period() {
    let dir = scratch("frames");
    let (run, index) = run_with_snapshots(&dir, "4");
    let frames = index["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 4);
    // The run's last step, in ms (t is in units of L/U = 1 ms at the paper's 10 m/s).
    let t_end = run["t_end"].as_f64().unwrap();
    assert!((index["t_end_ms"].as_f64().unwrap() - t_end).abs() < 1e-9);
    let period = index["period_ms"].as_f64().unwrap();
    let mut last = f64::NEG_INFINITY;
    for (k, f) in frames.iter().enumerate() {
        let t = f["t_ms"].as_f64().unwrap();
        assert!(
            t > t_end - period + 1e-12 && t <= t_end + 1e-12,
            "frame {k} at {t}"
        );
        assert!(t > last, "frames in time order");
        last = t;
        let csv = dir.join(f["file"].as_str().unwrap());
        assert!(csv.is_file(), "{}", csv.display());
    }
    // The four instants divide the period evenly and the last ends it.
    assert!((last - t_end).abs() < 1e-9);
    let t0 = frames[0]["t_ms"].as_f64().unwrap();
    assert!((last - t0 - 0.75 * period).abs() < period / 100.0);
    for png in [
        "maps_pressure.png",
        "maps_saturation.png",
        "maps_gap.png",
        "profiles.png",
        "history.png",
    ] {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{png}");
    }
    // The history covers the last period, step by step, the instants lettered in it.
    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let rows: Vec<&str> = history.lines().skip(1).collect();
    let lettered: Vec<&str> = rows.iter().filter_map(|r| r.rsplit(',').next()).collect();
    assert_eq!(
        lettered.iter().filter(|l| !l.is_empty()).count(),
        4,
        "{lettered:?}"
    );
    let t_first: f64 = rows[0].split(',').next().unwrap().parse().unwrap();
    assert!(t_first > t_end - period && t_first < t_end - period + period / 10.0);
}

/// (1/B)·∫∫ p dx1 dx2 over the ring from a frame's CSV (N/m), two ways: the nodal sum of
/// eq. (16) as the run takes it, and the trapezoidal rule along x1 between the first and the
/// last node under the ring; and the share of one cell in the ring's width.
fn load_from_csv(path: &Path, half_cell_m: f64) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut cols: Vec<(f64, f64)> = Vec::new(); // (x1 m, Σ_j p) per node column under the ring
    let mut rows_per_col = 0usize;
    for line in text.lines().skip(1) {
        let v: Vec<&str> = line.split(',').collect();
        if v[2] != "1" {
            continue;
        }
        let x1 = v[0].parse::<f64>().unwrap() * 1e-3;
        let p = v[3].parse::<f64>().unwrap() * 1e6;
        match cols.last_mut() {
            Some(c) if (c.0 - x1).abs() < 1e-12 => {
                c.1 += p;
                rows_per_col += 1;
            }
            _ => {
                cols.push((x1, p));
                rows_per_col = 1;
            }
        }
    }
    let last = cols.len() - 1;
    let dx1 = (cols[last].0 - cols[0].0) / last as f64;
    let dx2 = half_cell_m / rows_per_col as f64;
    let nodal: f64 = cols.iter().map(|c| c.1).sum::<f64>() * dx1 * dx2 / half_cell_m;
    let ends = 0.5 * (cols[0].1 + cols[last].1) * dx1 * dx2 / half_cell_m;
    (nodal, nodal - ends, 1.0 / last as f64)
}

#[test]
fn each_instants_pressure_map_integrates_to_the_runs_load_then() {
    let dir = scratch("load");
    let (_, index) = run_with_snapshots(&dir, "10");
    let half_cell_m = index["simulated_width_mm"].as_f64().unwrap() * 1e-3;
    for f in index["frames"].as_array().unwrap() {
        let w_h = f["w_h_n_per_m"].as_f64().unwrap();
        let path = dir.join(f["file"].as_str().unwrap());
        let (nodal, trapezoid, cell) = load_from_csv(&path, half_cell_m);
        // The run's own quadrature, from 7-digit pressures: to their rounding.
        assert!(
            ((nodal - w_h) / w_h).abs() < 1e-5,
            "frame {}: nodal sum {nodal} N/m against W_h {w_h} N/m",
            f["label"]
        );
        // Another quadrature differs by the end columns' half weights: at most a cell's share.
        assert!(
            ((trapezoid - w_h) / w_h).abs() < cell,
            "frame {}: trapezoid {trapezoid} N/m against W_h {w_h} N/m",
            f["label"]
        );
    }
}

#[test]
fn snapshots_to_an_unwritable_directory_fail_before_simulating() {
    let base = scratch("unwritable");
    std::fs::create_dir_all(&base).unwrap();
    let file = base.join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    let bad_dir = file.join("snaps");
    let (png, gif_in_bad, ok) = (
        base.join("film.png"),
        bad_dir.join("film.gif"),
        base.join("ok"),
    );
    let (bad_dir, file, png, gif_in_bad, ok) = (
        bad_dir.to_str().unwrap(),
        file.to_str().unwrap(),
        png.to_str().unwrap(),
        gif_in_bad.to_str().unwrap(),
        ok.to_str().unwrap(),
    );
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--snapshots", bad_dir], "--snapshots"),
        (vec!["--snapshots", file], "--snapshots"),
        (vec!["--animate", png], ".gif"),
        (vec!["--animate", gif_in_bad], "--animate"),
        (vec!["--snapshots", ok, "--frames", "0"], "--frames"),
        (vec!["--snapshots", ok, "--frames", "100000"], "--frames"),
        (vec!["--frames", "3"], "--snapshots"),
    ];
    for (extra, says) in cases {
        let mut args = CASE_ONE[..9].to_vec();
        args.extend(extra.iter().copied());
        let (code, out, err) = texopt(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?} simulated: {out}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert_eq!(std::fs::read_to_string(file).unwrap(), "not a directory");
}

#[test]
fn the_animation_has_a_frame_per_stride_of_the_period() {
    let dir = scratch("gif");
    std::fs::create_dir_all(&dir).unwrap();
    let gif = dir.join("film.gif");
    let mut args = CASE_ONE[..9].to_vec();
    let g = gif.to_str().unwrap();
    args.extend([
        "--fidelity",
        "draft",
        "--animate",
        g,
        "--animate-stride",
        "20",
    ]);
    let (code, _, err) = texopt(&args);
    assert_eq!(code, 0, "{err}");
    let mut decoder = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(&gif).unwrap())
        .unwrap();
    let mut frames = 0;
    while decoder.read_next_frame().unwrap().is_some() {
        frames += 1;
    }
    let said: usize = err
        .lines()
        .find_map(|l| l.strip_prefix("animation: "))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert_eq!(frames, said, "{err}");
    // Every 20th step of a period of 60 (0.06 cm at draft's characteristic step, 2·dx1/u =
    // 1e-3 on 400 cells).
    assert_eq!(frames, 60usize.div_ceil(20));
}

/// `optimise --snapshots`: refused before the search when it cannot write (no cache made);
/// otherwise the best-friction design's film and the plain liner's, ten instants each.
#[test]
fn optimise_draws_the_best_design_and_the_plain_liner() {
    let base = scratch("optimise");
    std::fs::create_dir_all(&base).unwrap();
    let cache = base.join("cache.sqlite");
    let blocker = base.join("a-file");
    std::fs::write(&blocker, "").unwrap();
    let small = |snapshots: &Path| -> (i32, String) {
        let (code, _, err) = texopt(&[
            "optimise",
            "--R",
            "5",
            "--particles",
            "2",
            "--iterations",
            "1",
            "--l1",
            "0.01..0.03",
            "--mesh",
            "64x4",
            "--out",
            base.join("report").to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
            "--snapshots",
            snapshots.to_str().unwrap(),
        ]);
        (code, err)
    };
    let (code, err) = small(&blocker.join("snaps"));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--snapshots"), "{err}");
    assert!(!cache.exists(), "the search ran: its cache was made");
    let snaps = base.join("snaps");
    let (code, err) = small(&snaps);
    assert_eq!(code, 0, "{err}");
    for sub in ["best_friction", "plain_liner"] {
        let index = std::fs::read_to_string(snaps.join(sub).join("snapshots.json")).unwrap();
        let index: serde_json::Value = serde_json::from_str(&index).unwrap();
        assert_eq!(index["frames"].as_array().unwrap().len(), 10, "{sub}");
        assert_eq!(index["mesh"], "64x4", "{sub}: the report's numerics");
        assert!(snaps.join(sub).join("maps_pressure.png").is_file(), "{sub}");
    }
}
