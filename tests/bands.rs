//! `texopt cycle --bands`: a liner in bands judged over the engine's operating map. Each
//! point's plain liner is the engine run directly at that point; the map's mean power is the
//! shares' weighting of the points' powers; the bands lie in their halves of the stroke, at
//! least the least length long; bad maps and band lengths are refused naming the key.

mod common;

use common::{scratch, texopt};
use std::path::Path;

/// The band search's report without its wall time, and its progress lines (stderr).
fn quick_bands(dir: &Path, file: &Path, out: &str) -> (serde_json::Value, String) {
    let mut extra = common::QUICK_SEARCH.to_vec();
    extra.extend(["--bands", "--band-min", "6", "--mesh", "96x4", "--out", out]);
    let cache = dir.join("c.sqlite");
    let mut args = vec!["cycle", file.to_str().unwrap(), "--cache"];
    args.push(cache.to_str().unwrap());
    args.extend(extra);
    let (code, _, err) = texopt(&args);
    assert_eq!(code, 0, "{err}");
    (
        common::report_without_wall_time(Path::new(out), "cycle_t_bands"),
        err,
    )
}

#[test]
fn a_search_again_over_the_same_cache_runs_nothing_and_finds_the_same() {
    let dir = scratch("bands-cache");
    let file = dir.join("e.toml");
    std::fs::write(&file, common::mapped_engine()).unwrap();
    let first = dir.join("first");
    let again = dir.join("again");
    let (cold, log) = quick_bands(&dir, &file, first.to_str().unwrap());
    let (warm, log_again) = quick_bands(&dir, &file, again.to_str().unwrap());
    assert_eq!(cold, warm);
    // Every line of the second search's progress: all from the cache, none run.
    let counts = |log: &str| -> Vec<(usize, usize)> {
        log.lines()
            .filter_map(|l| {
                let (_, tail) = l.split_once(" (")?;
                let (held, rest) = tail.split_once(" runs from the cache, ")?;
                let ran = rest.strip_suffix(" run)")?;
                Some((held.parse().ok()?, ran.parse().ok()?))
            })
            .collect()
    };
    let (c, w) = (counts(&log), counts(&log_again));
    assert!(
        !c.is_empty() && c.len() == w.len(),
        "{log}\n---\n{log_again}"
    );
    let ran_cold = c.last().unwrap().1;
    assert!(ran_cold > 0, "{log}");
    assert_eq!(
        w.last().unwrap(),
        &(ran_cold + c.last().unwrap().0, 0),
        "{log_again}"
    );
}

#[test]
fn a_banded_liner_is_judged_at_every_point_of_the_map_and_weighed_by_its_time() {
    let dir = scratch("bands");
    let file = dir.join("e.toml");
    std::fs::write(&file, common::mapped_engine()).unwrap();
    let mut extra = common::QUICK_SEARCH.to_vec();
    extra.extend(["--bands", "--band-min", "6", "--mesh", "96x4"]);
    let (code, _, err, _) = common::cycle(&dir, &file, &extra);
    assert_eq!(code, 0, "{err}");
    let out = dir.join("out");
    let suffixes = [
        ".md",
        "_front.csv",
        "_steps.csv",
        "_front.png",
        "_bands.png",
        "_force_idle.png",
        "_force_cruise.png",
    ];
    let r = common::report_files(&out, "cycle_t_bands", &suffixes);
    let shares: Vec<f64> = r["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["share"].as_f64().unwrap())
        .collect();
    assert_eq!(shares, [0.25, 0.75]);
    // The bands: top dead centre's in the first half, bottom's in the second, each ≥ 6 mm.
    let bands = r["banded"]["bands"].as_array().unwrap();
    let span = |b: &serde_json::Value| {
        (
            b["start_mm"].as_f64().unwrap(),
            b["end_mm"].as_f64().unwrap(),
        )
    };
    let ((a0, e0), (a1, e1)) = (span(&bands[0]), span(&bands[1]));
    assert!(
        a0 >= 0.0 && e0 <= 40.5 + 1e-9 && e0 - a0 >= 6.0 - 1e-9,
        "{a0} {e0}"
    );
    assert!(
        a1 >= 40.5 - 1e-9 && e1 <= 81.0 + 1e-9 && e1 - a1 >= 6.0 - 1e-9,
        "{a1} {e1}"
    );

    // The plain liner's mean power is the shares' weighting of its points' powers, each
    // its work times the cycles a second, rpm/120.
    let plain = &r["liners"][0];
    let work: Vec<f64> = plain["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["Ok"]["work_j_per_m"].as_f64().unwrap())
        .collect();
    let power = 0.25 * work[0] * 800.0 / 120.0 + 0.75 * work[1] * 3000.0 / 120.0;
    let reported = plain["mean_power_w_per_m"].as_f64().unwrap();
    assert!((reported / power - 1.0).abs() < 1e-12, "{reported} {power}");

    // Idle's plain liner is the engine run directly at idle.
    let text = common::mapped_engine()
        .replace("rpm = 3000", "rpm = 800")
        .replace("viscosity_pa_s = 0.007", "viscosity_pa_s = 0.02")
        .replace(
            "pressure_bar = [15, 35, 12, 2, 0.2, 0, 8]",
            "pressure_bar = [7.5, 17.5, 6, 1, 0.1, 0, 4]",
        );
    let text = text.split("[[operating]]").next().unwrap().to_string() + "[zones]\ncount = 2\n";
    assert_eq!(work[0], common::plain_cycle_work(&text, (96, 4)));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_maps_and_band_lengths_are_refused_with_exit_2_naming_the_key() {
    let dir = scratch("bands-bad");
    let file = dir.join("e.toml");
    for (text, extra, says) in [
        (
            common::mapped_engine(),
            vec![],
            "[[operating]]: the operating map is what --bands",
        ),
        (
            common::mapped_engine().replace("weight = 1", "weight = 0"),
            vec!["--bands"],
            "[[operating]] idle weight",
        ),
        (
            common::mapped_engine().replace("rpm = 800", "rpm = 1e9"),
            vec!["--bands"],
            "[[operating]] idle rpm",
        ),
        (
            common::mapped_engine().replace("name = \"cruise\"", "name = \"idle\""),
            vec!["--bands"],
            "[[operating]] name",
        ),
        (
            common::mapped_engine(),
            vec!["--bands", "--band-min", "50"],
            "--band-min 50",
        ),
        (
            common::engine("count = 2"),
            vec!["--band-min", "5"],
            "--band-min: the least band length of --bands",
        ),
        (
            common::mapped_engine().replace("[design]", "[design]\nband_min_mm = 0"),
            vec!["--bands"],
            "[design] band_min_mm = 0",
        ),
    ] {
        std::fs::write(&file, &text).unwrap();
        let (code, _, err, wrote) = common::cycle(&dir, &file, &extra);
        assert_eq!(code, 2, "{says}: {err}");
        assert_eq!(err.lines().count(), 1, "{says}: {err}");
        assert!(err.contains(says), "expected {says:?} in {err}");
        assert!(!wrote, "{says}: something was written");
    }
    std::fs::write(&file, common::mapped_engine()).unwrap();
    let f = file.to_str().unwrap();
    let (code, _, err) = texopt(&["cycle", f, "--bands", "--quasi-steady"]);
    assert_eq!(code, 2, "{err}");
    let _ = std::fs::remove_dir_all(dir);
}
