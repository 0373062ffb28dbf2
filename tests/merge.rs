//! `texopt cache merge` and the shares of a study: shares are disjoint and cover it (see also
//! study::shard's unit test); merging is idempotent, refuses two outcomes under one key and
//! leaves foreign or damaged files untouched; failures are merged as failures.

mod common;

use common::{scratch, texopt};
use std::path::{Path, PathBuf};

use texopt::model::case::CaseSpec;
use texopt::study::cache::{Cache, Key};
use texopt::time::{simulate_with, Fidelity, Outcome, RunOptions, Watch};

/// A cache at `path` holding the plain liner of each radius (steady runs: instant).
fn cache_with(path: &Path, radii: &[f64]) -> Vec<(Key, Outcome)> {
    let c = Cache::open(path).unwrap();
    radii
        .iter()
        .map(|&r| {
            let case = CaseSpec::paper(r);
            let num = Fidelity::Draft.numerics_for(&case);
            let o = simulate_with(&case, &num, &RunOptions::default(), &mut Watch::default())
                .unwrap()
                .outcome;
            let k = Key::of(&case, &num);
            c.put_done(&k, &o).unwrap();
            (k, o)
        })
        .collect()
}

/// Every entry of a cache as `cache export` prints it, without the run metadata that
/// differs from run to run.
fn export(path: &Path) -> Vec<String> {
    let (code, out, err) = texopt(&["cache", "export", "--cache", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let mut v: Vec<String> = out.lines().map(str::to_string).collect();
    v.sort();
    v
}

fn merge(sources: &[&Path], into: &Path) -> (i32, String, String) {
    let mut args = vec!["cache", "merge"];
    args.extend(sources.iter().map(|p| p.to_str().unwrap()));
    args.extend(["--into", into.to_str().unwrap()]);
    texopt(&args)
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap()
}

#[test]
fn merging_copies_the_union_once_and_twice_changes_nothing() {
    let dir = scratch("merge-union");
    let (a, b, c) = (
        dir.join("a.sqlite"),
        dir.join("b.sqlite"),
        dir.join("c.sqlite"),
    );
    cache_with(&a, &[0.4, 0.8, 1.6]);
    cache_with(&b, &[1.6, 3.2]);
    let (code, out, err) = merge(&[&a, &b], &c);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("4 entries added, 1 already there"), "{out}");
    let first = export(&c);
    assert_eq!(first.len(), 4);
    let (code, out, _) = merge(&[&a, &b], &c);
    assert_eq!(code, 0);
    assert!(out.contains("0 entries added, 5 already there"), "{out}");
    assert_eq!(export(&c), first, "merging twice changed the cache");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn two_outcomes_under_one_key_are_refused_and_nothing_is_written() {
    let dir = scratch("merge-conflict");
    let (a, b, c) = (
        dir.join("a.sqlite"),
        dir.join("b.sqlite"),
        dir.join("c.sqlite"),
    );
    cache_with(&a, &[0.8, 3.2]);
    let (k, mut o) = cache_with(&b, &[0.8]).remove(0);
    cache_with(&c, &[12.8]);
    // The same inputs with another answer (a different build, say).
    o.f_mean *= 1.0 + 1e-9;
    Cache::open(&b).unwrap().put_done(&k, &o).unwrap();
    let before = export(&c);
    let (code, _, err) = merge(&[&a, &b], &c);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("another outcome") && err.contains("nothing was merged"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(export(&c), before, "a refused merge wrote to the cache");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn failures_merge_as_failures_and_give_way_to_results() {
    let dir = scratch("merge-failed");
    let (a, b, c) = (
        dir.join("a.sqlite"),
        dir.join("b.sqlite"),
        dir.join("c.sqlite"),
    );
    let (k, o) = cache_with(&a, &[0.8]).remove(0);
    Cache::open(&b)
        .unwrap()
        .put_failed(&k, "the ring reached the liner", 1.0)
        .unwrap();
    let (code, out, err) = merge(&[&b], &c);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("1 entries added"), "{out}");
    let e = export(&c);
    assert!(
        e[0].contains("\"status\":\"failed\"") && e[0].contains("reached the liner"),
        "{e:?}"
    );
    // A result for the same inputs replaces the failure; the failure never replaces it.
    let (_, out, _) = merge(&[&a], &c);
    assert!(out.contains("1 failures replaced by results"), "{out}");
    let (_, out, _) = merge(&[&b], &c);
    assert!(out.contains("1 failures not copied over results"), "{out}");
    let got = Cache::open(&c).unwrap().get(&k).unwrap();
    assert!(matches!(got, Some(texopt::study::cache::Entry::Done(x)) if x == o));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn foreign_or_damaged_files_are_refused_and_left_untouched() {
    let dir = scratch("merge-foreign");
    let c = dir.join("c.sqlite");
    cache_with(&c, &[0.8]);
    let before = export(&c);
    let text = dir.join("notes.txt");
    std::fs::write(&text, "not a cache\n").unwrap();
    let other = dir.join("other.sqlite");
    {
        let db = rusqlite::Connection::open(&other).unwrap();
        db.execute_batch("CREATE TABLE t (x); INSERT INTO t VALUES (1);")
            .unwrap();
    }
    // A cache whose entry no longer matches its key.
    let altered = dir.join("altered.sqlite");
    cache_with(&altered, &[3.2]);
    {
        let db = rusqlite::Connection::open(&altered).unwrap();
        db.execute_batch(
            "PRAGMA wal_checkpoint(TRUNCATE); UPDATE evaluations SET key = replace(key, '3.2', '3.3'); PRAGMA wal_checkpoint(TRUNCATE);",
        )
        .unwrap();
    }
    // A cache cut short.
    let cut = dir.join("cut.sqlite");
    cache_with(&cut, &[6.4]);
    {
        let db = rusqlite::Connection::open(&cut).unwrap();
        db.execute_batch("PRAGMA wal_checkpoint(TRUNCATE);")
            .unwrap();
    }
    let full = bytes(&cut);
    std::fs::write(&cut, &full[..full.len() / 2 + 100]).unwrap();
    // An entry altered after it was written is named and left out; the rest is merged.
    {
        let was = bytes(&altered);
        let into = dir.join("from-altered.sqlite");
        let (code, _, err) = merge(&[&altered], &into);
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("not copied: 1 damaged"), "{err}");
        assert_eq!(bytes(&altered), was, "the source was changed");
        assert!(
            !export(&into).iter().any(|l| l.contains("3.3")),
            "the altered key was copied"
        );
    }
    let files: [(PathBuf, &str); 3] = [
        (text.clone(), "not a texopt cache"),
        (other, "not a texopt cache"),
        (cut, "damaged"),
    ];
    for (f, says) in &files {
        let was = bytes(f);
        let (code, _, err) = merge(&[f], &c);
        assert_eq!(code, 2, "{}: {err}", f.display());
        assert!(err.contains(says), "{}: {err}", f.display());
        assert_eq!(bytes(f), was, "{} was changed", f.display());
        assert_eq!(export(&c), before);
        // Into a new file, a refused merge leaves no file behind.
        let new = dir.join("new.sqlite");
        let (code, _, err) = merge(&[f], &new);
        assert_eq!(code, 2, "{}: {err}", f.display());
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| n.starts_with("new.sqlite"))
            .collect();
        assert!(left.is_empty(), "{}: left {left:?}", f.display());
    }
    // A destination that is not a cache is named by the flag that gave it.
    let (code, _, err) = merge(&[&c], &text);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--into") && !err.contains("--cache"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_study_run_in_shares_and_merged_reports_as_one_run() {
    let dir = scratch("shares");
    let file = dir.join("s.toml");
    std::fs::write(
        &file,
        format!(
            "[study]\nname = \"s\"\nfidelity = \"draft\"\nuntextured = true\n[parameters]\nR = [0.8, 3.2]\nl1 = [0.01, 0.03]\nper = 0.06\ndepth = [2, 5]\ntheta_s = [0.5, 0.95]\n[numerics]\nn1 = 64\nn2 = 4\ndt = 1.6e-3\n[report]\ndir = \"{}\"\n",
            dir.join("report").display()
        ),
    )
    .unwrap();
    let f = file.to_str().unwrap();
    // --cached-only reads a cache: one that is not there is refused, not created.
    let empty = dir.join("empty.sqlite");
    let report_only = |cache: &std::path::Path| {
        texopt(&[
            "study",
            f,
            "--cache",
            cache.to_str().unwrap(),
            "--cached-only",
        ])
    };
    let (code, _, err) = report_only(&empty);
    assert_eq!(code, 2, "{err}");
    assert!(!empty.exists(), "a report-only run created a cache");
    // From a cache that holds none of the study's cases nothing runs: the summary says so
    // and concludes nothing.
    let other = dir.join("other.toml");
    std::fs::write(
        &other,
        "[study]\nname = \"o\"\nfidelity = \"draft\"\n[parameters]\nR = [0.5]\nl1 = [0.01]\nper = 0.06\ndepth = [2]\n[numerics]\nn1 = 64\nn2 = 4\ndt = 1.6e-3\n",
    )
    .unwrap();
    let (code, _, err) = texopt(&[
        "study",
        other.to_str().unwrap(),
        "--cache",
        empty.to_str().unwrap(),
        "--no-report",
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = report_only(&empty);
    assert_eq!(code, 0, "{err}");
    let summary = std::fs::read_to_string(dir.join("report/s_summary.md")).unwrap();
    assert!(
        summary.contains("Cases: 0 simulated or cached (0 failed), 20 not run"),
        "{summary}"
    );
    assert!(summary.contains("nothing to compare"), "{summary}");
    assert!(summary.contains(": 0 s of single-core"), "{summary}");
    assert!(!summary.contains("no texture beats"), "{summary}");
    std::fs::remove_dir_all(dir.join("report")).unwrap();
    let mut shares = Vec::new();
    for i in 1..=3 {
        let share = dir.join(format!("share-{i}.sqlite"));
        let (code, _, err) = texopt(&[
            "study",
            f,
            "--shard",
            &format!("{i}/3"),
            "--cache",
            share.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(!dir.join("report").exists(), "a share wrote a report");
        shares.push(share);
    }
    // Disjoint shares covering the study: their entries add up to its cases.
    let counts: Vec<usize> = shares.iter().map(|s| export(s).len()).collect();
    assert_eq!(counts.iter().sum::<usize>(), 20, "{counts:?}");
    assert!(counts.iter().all(|&n| n > 0), "{counts:?}");
    let merged = dir.join("merged.sqlite");
    let refs: Vec<&Path> = shares.iter().map(PathBuf::as_path).collect();
    assert_eq!(merge(&refs, &merged).0, 0);
    let (code, out, err) = texopt(&[
        "study",
        f,
        "--cache",
        merged.to_str().unwrap(),
        "--cached-only",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("20 from the cache, 0 computed"), "{out}");
    assert!(dir.join("report/s.csv").exists());
    for bad in ["0/3", "4/3", "1/0", "x/3"] {
        let (code, _, err) = texopt(&["study", f, "--shard", bad]);
        assert_eq!(code, 2, "{bad}: {err}");
    }
    let _ = std::fs::remove_dir_all(dir);
}
