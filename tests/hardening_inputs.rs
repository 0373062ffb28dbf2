//! Inputs that must be refused up front or reported in words, never as NaN, inf or hundreds
//! of digits: `cycle`'s zones, steps and engine values; `optimise`'s range of radii; a study
//! file's absurd values; the cache's size on disk.

mod common;

use common::{cycle, engine, scratch, texopt};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Refused: exit 2, one line containing every one of `says`, nothing written.
fn cycle_refused(dir: &Path, text: &str, extra: &[&str], says: &[&str]) {
    let file = dir.join("e.toml");
    std::fs::write(&file, text).unwrap();
    let (code, out, err, wrote) = cycle(dir, &file, extra);
    assert_eq!(code, 2, "{extra:?}: {err}");
    assert!(out.is_empty(), "{extra:?}: {out}");
    assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
    for s in says {
        assert!(err.contains(s), "{extra:?}: {s:?} not in {err}");
    }
    assert!(!wrote, "{extra:?}: something was written");
}

#[test]
fn a_zone_no_crank_angle_samples_is_refused_with_the_step_it_needs() {
    let dir = scratch("inputs-zones");
    let example = std::fs::read_to_string("studies/engine_gasoline.toml").unwrap();
    // The example at --step 45: its third zone (40.5–60.8 mm) is crossed in 30.2°.
    cycle_refused(
        &dir,
        &example,
        &["--step", "45"],
        &["--step = 45", "zone 3 (40.5–60.8 mm)", "--step 30 or less"],
    );
    // 1 µm at top dead centre: crossed down and back up in 0.7°, missed at the default step
    // and at the design step alike.
    let tiny = example.replace("count = 4", "boundaries_mm = [0, 0.001, 81]");
    cycle_refused(
        &dir,
        &tiny,
        &[],
        &[
            "--step = 5",
            "zone 1 (0.000–0.001 mm)",
            "--step 0.703 or less",
        ],
    );
    cycle_refused(
        &dir,
        &tiny,
        &["--step", "0.5"],
        &[
            "[design] design_step_deg = 30",
            "zone 1",
            "[design] design_step_deg 0.703 or less",
        ],
    );
    // A zone too narrow for the finest step, and more zones than `count` takes.
    cycle_refused(
        &dir,
        &engine("boundaries_mm = [0, 40, 40.0001, 81]"),
        &[],
        &["[zones] boundaries_mm", "zone 2", "finest step"],
    );
    let many: Vec<String> = (0..=5000)
        .map(|i| format!("{}", 81.0 * i as f64 / 5000.0))
        .collect();
    cycle_refused(
        &dir,
        &engine(&format!("boundaries_mm = [{}]", many.join(", "))),
        &[],
        &["[zones] boundaries_mm = 5001 values", "at most 51"],
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn absurd_engine_values_are_refused_in_short_form() {
    let dir = scratch("inputs-engine");
    for (from, to, key) in [
        (
            "bore_mm = 79",
            "bore_mm = 1e300",
            "[engine] bore_mm = 1e300",
        ),
        (
            "bore_mm = 79",
            "bore_mm = 1e-300",
            "[engine] bore_mm = 1e-300",
        ),
        (
            "stroke_mm = 81",
            "stroke_mm = 1e300",
            "[engine] stroke_mm = 1e300",
        ),
        ("rpm = 3000", "rpm = 1e300", "[engine] rpm = 1e300"),
        ("R_cm = 5", "R_cm = 1e300", "[ring] R_cm = 1e300"),
        (
            "mass_kg_per_m = 0.03",
            "mass_kg_per_m = 1e-300",
            "[ring] mass_kg_per_m = 1e-300",
        ),
        (
            "elastic_load_n_per_m = 150",
            "elastic_load_n_per_m = 1e-300",
            "[ring] elastic_load_n_per_m = 1e-300",
        ),
    ] {
        let text = engine("count = 2").replace(from, to);
        cycle_refused(&dir, &text, &[], &[key, "must lie in ["]);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A zone whose angles are all outside the model of the quasi-steady evaluation (the first
/// millimetre, met only near top dead centre) has no numbers there: the report says so in
/// words and prints no NaN or inf.
#[test]
fn a_zone_with_no_angle_inside_the_model_is_reported_in_words() {
    let dir = scratch("inputs-unweighed");
    let file = dir.join("e.toml");
    std::fs::write(&file, engine("boundaries_mm = [0, 1, 81]")).unwrap();
    let (code, stdout, err, _) = cycle(
        &dir,
        &file,
        &[
            "--step",
            "10",
            "--design-step",
            "20",
            "--particles",
            "2",
            "--iterations",
            "1",
            "--mesh",
            "64x4",
            "--dt",
            "1.6e-3",
            "--quasi-steady",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let md = std::fs::read_to_string(dir.join("out/cycle_t.md")).unwrap();
    let json = std::fs::read_to_string(dir.join("out/cycle_t.json")).unwrap();
    for (what, text) in [("stdout", &stdout), ("md", &md), ("json", &json)] {
        for bad in ["NaN", "inf", "-0.0"] {
            assert!(!text.contains(bad), "{what} has {bad}: {text}");
        }
    }
    assert!(
        md.contains("| 1 | 0.0–1.0 | plain liner | 0 / ") && md.contains("| – | – | – | – |"),
        "{md}"
    );
    assert!(
        md.contains("No angle of zone 1 lies inside the model"),
        "{md}"
    );
    let r: serde_json::Value = serde_json::from_str(&json).unwrap();
    let z = &r["zones"][0];
    assert_eq!(z["angles_inside"], 0, "{z}");
    for k in ["work_plain_j_per_m", "change_pct", "c_min_um"] {
        assert!(z[k].is_null(), "{k}: {z}");
    }
    assert!(r["zones"][1]["change_pct"].is_number(), "{r}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Refused: exit 2, nothing on stdout, a message containing every one of `says` in a first
/// line that holds all of it (clap adds a hint line to its own errors).
fn refused(args: &[&str], says: &[&str]) {
    // An output and a cache of its own, should it be taken and run.
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let dir = scratch(&format!(
        "inputs-refused-{}",
        CALLS.fetch_add(1, Ordering::Relaxed)
    ));
    let (out_dir, cache) = (dir.join("out"), dir.join("c.sqlite"));
    let mut args = args.to_vec();
    if args[0] == "optimise" {
        args.extend(["--out", out_dir.to_str().unwrap()]);
        args.extend(["--cache", cache.to_str().unwrap()]);
    }
    let (code, out, err) = texopt(&args);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(out.is_empty(), "{args:?}: {out}");
    let first = err.lines().next().unwrap_or_default();
    for s in says {
        assert!(first.contains(s), "{args:?}: {s:?} not in {err}");
    }
    assert!(first.len() < 400, "{args:?}: {err}");
}

#[test]
fn a_range_of_radii_that_rounding_would_merge_is_refused() {
    // Every radius of the range rounds to 5 (3 significant digits): one radius, not 16.
    for n in ["16", "2"] {
        refused(
            &["optimise", "--R", "5..5.001", "--radii", n],
            &["--R 5..5.001", "narrower than the rounding", "--R 5"],
        );
    }
    // 16 radii over 5–5.1 round to 11 distinct ones: the count that stays distinct is named.
    refused(
        &["optimise", "--R", "5..5.1", "--radii", "16"],
        &["--radii 16", "only 11 distinct", "ask --radii 11"],
    );
    // One radius of a range: give it alone.
    refused(
        &["optimise", "--R", "5..5.001", "--radii", "1"],
        &["--radii = 1", "--R alone"],
    );
    // Absurd ends print short.
    refused(
        &["optimise", "--R", "8e300..5"],
        &["--R 8e300..5", "0 < LO < HI"],
    );
    refused(
        &["optimise", "--R", "5..1e300"],
        &["--R 5..1e300", "at most at 10000 cm"],
    );
    // A list whose radii are one radius to the digits reports name them by.
    for list in ["3.2,5,5.0000001", "5,5"] {
        refused(
            &["optimise", "--R", list],
            &["--R", "one radius", "distinct"],
        );
    }
}

#[test]
fn sizes_and_positions_have_ranges_on_every_path() {
    refused(
        &["optimise", "--R", "5", "--l1", "0.02..1e300"],
        &["--l1 = 0.02..1e300", "at most at 100 cm"],
    );
    refused(
        &["optimise", "--R", "5", "--depth", "1e-300..1e300"],
        &["--depth", "1000 µm"],
    );
    // A plain liner has no texture to place: a phase given is said to be unused.
    let (code, _, err) = texopt(&["simulate", "--R", "0.8", "--phase", "1e300"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("--phase") && err.contains("not used"), "{err}");
    refused(
        &["simulate", "--R", "0.8", "--max-steps", "1e300"],
        &["--max-steps = 1e300", "at most 1e10"],
    );
    let dir = scratch("inputs-design");
    let base = engine("count = 2");
    // A whole number given as an absurd float is quoted back short.
    let text = base.replace("count = 2", "count = 1e300");
    cycle_refused(&dir, &text, &[], &["1e300", "expected usize"]);
    let text = base.replace("[design]\n", "[design]\nmin_clearance_um = 1e300\n");
    cycle_refused(
        &dir,
        &text,
        &[],
        &["[design] min_clearance_um = 1e300", "(0, 100] µm"],
    );
    // The design space's inputs are named by the file's keys, not by optimise's flags.
    let text = base.replace("[design]\n", "[design]\nw_min = -1\n");
    cycle_refused(&dir, &text, &[], &["[design] w_min = -1 µm"]);
    let text = base.replace("l1 = [0.005, 0.03]", "l1 = [0.03, 0.005]");
    cycle_refused(&dir, &text, &[], &["[design] l1 = 0.03..0.005"]);
    // A step from the file is named by its key.
    let text = base.replace("[design]\n", "[design]\ndesign_step_deg = 0\n");
    cycle_refused(&dir, &text, &[], &["[design] design_step_deg = 0"]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn ranges_are_echoed_as_given() {
    // Three dots would split as 5..0.8: refused as written.
    refused(&["optimise", "--R", "5...8"], &["\"5...8\" has three dots"]);
    refused(
        &["optimise", "--R", "5", "--l1", "0.01...03"],
        &["\"0.01...03\" has three dots"],
    );
}

#[test]
fn a_study_file_says_absurd_values_short() {
    let dir = scratch("inputs-study");
    for (line, says) in [
        (
            "speed = 1e300",
            "[parameters] speed = 1e300: must lie in [0.001, 100] m/s",
        ),
        (
            "ring_width = 1e-300",
            "[parameters] ring_width = 1e-300: must lie in [0.1, 10] mm",
        ),
        (
            "load = { from = 1e300, to = 1, count = 2 }",
            "range from = 1e300 to = 1",
        ),
        (
            "speed = { from = 1, to = 2, count = 1e300 }",
            "count = 1e300 must be",
        ),
        (
            "speed = { from = 1, to = 2, step = 1e-300 }",
            "step = 1e-300 must be",
        ),
    ] {
        let p = dir.join("s.toml");
        std::fs::write(
            &p,
            format!(
                "[study]\nname = \"tiny\"\nfidelity = \"draft\"\nuntextured = true\n[parameters]\nR = [3.2, 5]\nl1 = [0.01, 0.03]\nper = 0.06\ndepth = [5, 10]\n{line}\n[report]\ndir = \"rep\"\n"
            ),
        )
        .unwrap();
        refused(&["study", p.to_str().unwrap(), "--dry-run"], &[says]);
    }
    let p = dir.join("s.toml");
    std::fs::write(
        &p,
        "[study]\nname = \"tiny\"\nroughness = 1e300\n[parameters]\nR = 5\nl1 = 0.01\nper = 0.06\ndepth = 5\n",
    )
    .unwrap();
    refused(
        &["study", p.to_str().unwrap(), "--dry-run"],
        &["[study] roughness = 1e300:"],
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// The write-ahead log beside a cache holds recent writes until SQLite folds them into the
/// file; while another process keeps it open it can outgrow the file: stats count both.
#[test]
fn cache_stats_count_the_write_ahead_log() {
    let dir = scratch("inputs-wal");
    let path = dir.join("c.sqlite");
    drop(texopt::study::cache::Cache::open(&path).unwrap());
    // A writer that keeps its connection open and does not fold its log in.
    let conn = rusqlite::Connection::open(&path).unwrap();
    conn.pragma_update(None, "wal_autocheckpoint", 0).unwrap();
    conn.execute_batch(
        "CREATE TABLE ballast (b BLOB); INSERT INTO ballast VALUES (zeroblob(3000000));",
    )
    .unwrap();
    let (code, out, err) = texopt(&["cache", "stats", "--cache", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let line = out.lines().nth(1).unwrap_or_default();
    // 3 MB in the log, a few kB in the file.
    assert!(line.contains("write-ahead log"), "{out}");
    let wal = line
        .split(" database file, ")
        .nth(1)
        .and_then(|x| x.split(" write-ahead log").next())
        .unwrap_or_default();
    assert!(wal.ends_with("MB") && wal.starts_with('3'), "{out}");
    assert!(line.contains(" MB on disk ("), "{out}");
    drop(conn);
    let _ = std::fs::remove_dir_all(dir);
}
