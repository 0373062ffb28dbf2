//! What texopt does to the files it is given: an output never replaces what stands at its
//! path (a link is followed, a device or FIFO written through); a cache is inspected without
//! being changed, never created by a command that only reads it, and its log is refused when
//! it belongs to another database; an entry altered after it was written is reported and
//! never served; a report is not replaced by one with less in it unless asked.

mod common;

use common::{scratch, texopt};
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};

/// A study of three quick cases (R = 3.2 at `draft`: two textures and the plain liner),
/// reporting into `dir/rep`.
fn small_study(dir: &Path) -> PathBuf {
    let p = dir.join("small.toml");
    let text = format!(
        "[study]\nname = \"small\"\nfidelity = \"draft\"\nuntextured = true\n\n[parameters]\nR = [3.2]\nl1 = [0.01, 0.03]\nper = 0.06\ndepth = [5]\n\n[report]\ndir = \"{}\"\n",
        dir.join("rep").display()
    );
    std::fs::write(&p, text).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A scratch directory for `test`, the small study in it, and a cache `name` holding the
/// study's cases (run without a report).
fn studied(test: &str, name: &str) -> (PathBuf, PathBuf, PathBuf) {
    let d = scratch(test);
    let study = small_study(&d);
    let cache = d.join(name);
    assert_eq!(run_study(&study, &cache, &["--no-report"]).0, 0);
    (d, study, cache)
}

/// The study run into `cache`.
fn run_study(study: &Path, cache: &Path, extra: &[&str]) -> (i32, String, String) {
    let mut args = vec!["study", s(study), "--cache", s(cache), "--jobs", "1"];
    args.extend_from_slice(extra);
    texopt(&args)
}

/// A FIFO made at `path` and a thread that reads it to the end.
fn fifo_with_reader(path: &Path) -> std::thread::JoinHandle<String> {
    assert!(std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .unwrap()
        .success());
    let fifo = path.to_path_buf();
    std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
}

/// The bytes of a cache and of its log, if any.
fn snapshot(cache: &Path) -> (Vec<u8>, Option<Vec<u8>>) {
    let mut wal = cache.as_os_str().to_owned();
    wal.push("-wal");
    (std::fs::read(cache).unwrap(), std::fs::read(wal).ok())
}

#[test]
fn outputs_follow_links_and_write_through_devices_and_fifos() {
    let d = scratch("files-outputs");
    // A device (a null device of the test's own, so that a failure cannot replace the
    // machine's /dev/null): written through, never turned into a regular file.
    let null = d.join("null");
    let made = std::process::Command::new("mknod")
        .args([s(&null), "c", "1", "3"])
        .status()
        .is_ok_and(|st| st.success());
    if made {
        let (code, _, err) = texopt(&[
            "bench",
            "--case",
            "case-I",
            "--repeat",
            "1",
            "--fidelity",
            "draft",
            "--out",
            s(&null),
        ]);
        assert_eq!(code, 0, "{err}");
        let kind = std::fs::symlink_metadata(&null).unwrap().file_type();
        assert!(kind.is_char_device(), "the device was replaced by a file");
    } else {
        eprintln!("mknod is not allowed here: the device case is not checked");
    }

    // A link: its target gets the output, the link stays.
    let target = d.join("series-target.csv");
    let link = d.join("series.csv");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let mut args = common::case_one_draft().to_vec();
    args.extend(["--series", s(&link)]);
    let (code, _, err) = texopt(&args);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    let series = std::fs::read_to_string(&target).unwrap();
    assert!(series.lines().count() > 10, "{series}");

    // A FIFO: its reader gets the whole output, and it stays a FIFO.
    let study = small_study(&d);
    let cache = d.join("c.sqlite");
    assert_eq!(run_study(&study, &cache, &["--no-report"]).0, 0);
    let fifo = d.join("export.jsonl");
    let reader = fifo_with_reader(&fifo);
    let (code, _, err) = texopt(&["cache", "export", "--cache", s(&cache), "--out", s(&fifo)]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(reader.join().unwrap().lines().count(), 3);
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
}

/// A log of another, smaller database beside `cache` (what SQLite would replay into it).
fn plant_foreign_log(dir: &Path, cache: &Path) {
    let other = dir.join("other.sqlite");
    let c = rusqlite::Connection::open(&other).unwrap();
    c.pragma_update(None, "journal_mode", "WAL").unwrap();
    c.execute_batch("CREATE TABLE t(x); INSERT INTO t VALUES (1);")
        .unwrap();
    let mut wal = cache.as_os_str().to_owned();
    wal.push("-wal");
    std::fs::copy(dir.join("other.sqlite-wal"), wal).unwrap();
}

#[test]
fn a_foreign_log_is_refused_by_every_command_and_nothing_changes() {
    let (d, study, cache) = studied("files-wal", "c.sqlite");
    // Make the cache larger than the other database, as a real cache is.
    let c = rusqlite::Connection::open(&cache).unwrap();
    c.execute_batch("CREATE TABLE filler(x); WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 2000) INSERT INTO filler SELECT randomblob(100) FROM n; PRAGMA wal_checkpoint(TRUNCATE);")
        .unwrap();
    drop(c);
    plant_foreign_log(&d, &cache);
    let before = snapshot(&cache);
    let into = d.join("into.sqlite");
    for args in [
        vec!["cache", "stats", "--cache", s(&cache)],
        vec!["cache", "export", "--cache", s(&cache)],
        vec!["cache", "clear", "--cache", s(&cache)],
        vec!["study", s(&study), "--cache", s(&cache), "--no-report"],
        vec!["study", s(&study), "--cache", s(&cache), "--cached-only"],
        vec!["cache", "merge", s(&cache), "--into", s(&into)],
    ] {
        let (code, _, err) = texopt(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains("belongs to another database"),
            "{args:?}: {err}"
        );
        assert_eq!(
            snapshot(&cache),
            before,
            "{args:?} changed the cache or its log"
        );
    }
    assert!(!into.exists(), "a refused merge made its target");
}

#[test]
fn a_log_left_by_a_crashed_writer_is_the_caches_own() {
    let (_, _, cache) = studied("files-crash", "c.sqlite");
    // A writer that ends without its checkpoint leaves committed frames in the log.
    let c = rusqlite::Connection::open(&cache).unwrap();
    c.set_db_config(
        rusqlite::config::DbConfig::SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE,
        true,
    )
    .unwrap();
    c.execute_batch("INSERT INTO leases VALUES ('x', 'host', 1, 0.0);")
        .unwrap();
    drop(c);
    let (_, wal) = snapshot(&cache);
    assert!(wal.is_some_and(|w| w.len() > 32), "no log was left");
    let (code, out, err) = texopt(&["cache", "stats", "--cache", s(&cache)]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("3 evaluations done") && out.contains("integrity: ok"),
        "{out}"
    );
}

#[test]
fn a_report_only_run_never_creates_a_cache_nor_replaces_a_fuller_report() {
    let d = scratch("files-cached-only");
    let study = small_study(&d);
    let cache = d.join("c.sqlite");
    assert_eq!(run_study(&study, &cache, &[]).0, 0);
    let csv = d.join("rep/small.csv");
    let report = std::fs::read(&csv).unwrap();

    let typo = d.join("typo.sqlite");
    let (code, out, err) = run_study(&study, &typo, &["--cached-only"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("--cached-only") && err.contains("typo.sqlite"),
        "{err}"
    );
    assert!(!typo.exists(), "a report-only run created a cache");
    let (code, _, err) = run_study(&study, &typo, &["--cached-only", "--shard", "1/2"]);
    assert_eq!(code, 2, "{err}");
    assert!(!typo.exists());

    // A cache with less in it: the fuller report is kept unless replacing it is asked for.
    let less = d.join("less.sqlite");
    let c = rusqlite::Connection::open(&less).unwrap();
    drop(c);
    std::fs::copy(&cache, &less).unwrap();
    let c = rusqlite::Connection::open(&less).unwrap();
    c.execute(
        "DELETE FROM evaluations WHERE key LIKE '%\"texture\":null%'",
        [],
    )
    .unwrap();
    drop(c);
    let (code, _, err) = run_study(&study, &less, &["--cached-only"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--replace-report") && err.contains("holds 3"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(&csv).unwrap(),
        report,
        "the report was replaced"
    );
    let (code, _, err) = run_study(&study, &less, &["--cached-only", "--replace-report"]);
    assert_eq!(code, 0, "{err}");
    assert_ne!(std::fs::read(&csv).unwrap(), report);
    // The full cache gives the full report back.
    assert_eq!(run_study(&study, &cache, &["--cached-only"]).0, 0);
    assert_eq!(std::fs::read(&csv).unwrap(), report);
}

/// Changes one stored outcome's f_mean by one digit and makes another unparsable; returns
/// their hashes and the original f_mean of the first.
fn damage_two(cache: &Path) -> (String, String, f64) {
    let c = rusqlite::Connection::open(cache).unwrap();
    let rows: Vec<(String, String)> = c
        .prepare("SELECT hash, outcome FROM evaluations WHERE status = 'done' ORDER BY hash")
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let (h1, o1) = &rows[0];
    let v: serde_json::Value = serde_json::from_str(o1).unwrap();
    let f = v["f_mean"].as_f64().unwrap();
    let shown = format!(
        "\"f_mean\":{}",
        serde_json::to_string(&v["f_mean"]).unwrap()
    );
    let i = o1.find(&shown).unwrap() + shown.len() - 1;
    let mut altered = o1.clone().into_bytes();
    altered[i] = if altered[i] == b'1' { b'2' } else { b'1' };
    let altered = String::from_utf8(altered).unwrap();
    c.execute(
        "UPDATE evaluations SET outcome = ?1 WHERE hash = ?2",
        [&altered, h1],
    )
    .unwrap();
    let (h2, o2) = &rows[1];
    let flipped = o2.replacen('{', "[", 1);
    c.execute(
        "UPDATE evaluations SET outcome = ?1 WHERE hash = ?2",
        [&flipped, h2],
    )
    .unwrap();
    (h1.clone(), h2.clone(), f)
}

/// Each way an entry can be damaged, applied to the entry `hash` (SQL on the open file).
const DAMAGES: [(&str, &str); 8] = [
    ("a digit of the outcome", "UPDATE evaluations SET outcome = replace(outcome, '\"f_mean\":0.', '\"f_mean\":0.0') WHERE hash = ?1"),
    ("the checksum removed", "UPDATE evaluations SET checksum = NULL, outcome = replace(outcome, '\"f_mean\":0.', '\"f_mean\":0.0') WHERE hash = ?1"),
    ("bytes that are not UTF-8", "UPDATE evaluations SET outcome = CAST(X'7B22665F6D65616E223AFF7D' AS TEXT) WHERE hash = ?1"),
    ("the outcome as a BLOB", "UPDATE evaluations SET outcome = CAST(outcome AS BLOB) WHERE hash = ?1"),
    ("the key altered", "UPDATE evaluations SET key = replace(key, '\"model\"', '\"modeI\"') WHERE hash = ?1"),
    ("the wall time altered", "UPDATE evaluations SET wall_time_s = 1e300 WHERE hash = ?1"),
    ("the status altered", "UPDATE evaluations SET status = 'failed' WHERE hash = ?1"),
    ("the steps as text", "UPDATE evaluations SET steps = 'many' WHERE hash = ?1"),
];

#[test]
fn every_kind_of_damage_is_named_never_served_and_computed_again() {
    let (d, study, clean) = studied("files-damages", "clean.sqlite");
    let c = rusqlite::Connection::open(&clean).unwrap();
    let hash: String = c
        .query_row(
            "SELECT hash FROM evaluations WHERE key LIKE '%\"texture\":null%'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    drop(c);
    for (what, sql) in DAMAGES {
        let cache = d.join("damaged.sqlite");
        std::fs::copy(&clean, &cache).unwrap();
        let c = rusqlite::Connection::open(&cache).unwrap();
        assert_eq!(c.execute(sql, [&hash]).unwrap(), 1, "{what}");
        drop(c);
        let (code, out, err) = texopt(&["cache", "stats", "--cache", s(&cache)]);
        assert_eq!(code, 1, "{what}: {out}{err}");
        assert!(
            err.contains(&hash[..12]) && !out.contains("e300"),
            "{what}: {out}{err}"
        );
        let (code, _, err) = texopt(&["cache", "export", "--cache", s(&cache)]);
        assert_eq!(code, 0, "{what}: {err}");
        assert!(err.contains("left out 1 damaged"), "{what}: {err}");
        let (code, _, err) = run_study(&study, &cache, &["--cached-only", "--no-report"]);
        assert_eq!(code, 0, "{what}: {err}");
        assert!(err.contains("damaged in the cache"), "{what}: {err}");
        let into = d.join("into.sqlite");
        let _ = std::fs::remove_file(&into);
        let (code, out, err) = texopt(&["cache", "merge", s(&cache), "--into", s(&into)]);
        assert_eq!(code, 0, "{what}: {err}");
        assert!(
            out.contains("2 entries added") && err.contains("not copied: 1"),
            "{what}: {out}{err}"
        );
        let (code, out, err) = run_study(&study, &cache, &["--no-report"]);
        assert_eq!(code, 0, "{what}: {err}");
        assert!(out.contains("1 computed"), "{what}: {out}");
        let (code, out, _) = texopt(&["cache", "stats", "--cache", s(&cache)]);
        assert_eq!(code, 0, "{what}");
        assert!(out.contains("integrity: ok"), "{what}: {out}");
    }
}

#[test]
fn a_damaged_entry_is_reported_and_never_served() {
    let (d, study, cache) = studied("files-damaged", "c.sqlite");
    let (h1, h2, f) = damage_two(&cache);

    let (code, out, err) = texopt(&["cache", "stats", "--cache", s(&cache)]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.contains("2 damaged entries"), "{out}");
    assert!(err.contains(&h1[..12]) && err.contains(&h2[..12]), "{err}");

    // A report from the cache alone: the damaged cases are not run, never the altered value.
    let (code, _, err) = run_study(&study, &cache, &["--cached-only"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err.matches("damaged in the cache").count(), 2, "{err}");
    let csv = std::fs::read_to_string(d.join("rep/small.csv")).unwrap();
    assert_eq!(csv.matches(",not run,").count(), 2, "{csv}");

    // A merge does not copy them.
    let into = d.join("merged.sqlite");
    let (code, out, err) = texopt(&["cache", "merge", s(&cache), "--into", s(&into)]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("1 entries added"), "{out}");
    assert!(err.contains("not copied: 2 damaged entries"), "{err}");

    // A run computes them again, to the value first stored.
    let (code, out, err) = run_study(&study, &cache, &["--replace-report"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("2 computed"), "{out}");
    let (code, out, _) = texopt(&["cache", "stats", "--cache", s(&cache)]);
    assert_eq!(code, 0);
    assert!(out.contains("integrity: ok"), "{out}");
    let c = rusqlite::Connection::open(&cache).unwrap();
    let o: String = c
        .query_row(
            "SELECT outcome FROM evaluations WHERE hash = ?1",
            [&h1],
            |r| r.get(0),
        )
        .unwrap();
    let v: serde_json::Value = serde_json::from_str(&o).unwrap();
    assert_eq!(v["f_mean"].as_f64().unwrap(), f);
}

#[test]
fn a_log_without_its_cache_is_refused_and_kept() {
    let d = scratch("files-orphan");
    let study = small_study(&d);
    let cache = d.join("new.sqlite");
    plant_foreign_log(&d, &cache);
    let wal = snapshot_wal(&cache);
    for args in [
        vec!["study", s(&study), "--cache", s(&cache), "--no-report"],
        vec![
            "cache",
            "merge",
            s(&d.join("other.sqlite")),
            "--into",
            s(&cache),
        ],
    ] {
        let (code, _, err) = texopt(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("does not exist"), "{args:?}: {err}");
        assert!(!cache.exists(), "{args:?} made the cache");
        assert_eq!(snapshot_wal(&cache), wal, "{args:?} changed the log");
    }
}

fn snapshot_wal(cache: &Path) -> Vec<u8> {
    let mut wal = cache.as_os_str().to_owned();
    wal.push("-wal");
    std::fs::read(wal).unwrap()
}

#[test]
fn a_fifo_where_the_report_goes_is_written_not_read() {
    let (d, study, cache) = studied("files-fifo-report", "c.sqlite");
    std::fs::create_dir_all(d.join("rep")).unwrap();
    let fifo = d.join("rep/small.csv");
    let reader = fifo_with_reader(&fifo);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_texopt"))
        .args(["study", s(&study), "--cache", s(&cache), "--cached-only"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st;
        }
        if t0.elapsed().as_secs() > 60 {
            let _ = child.kill();
            panic!("the study waited on the FIFO");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    assert!(status.success());
    assert_eq!(reader.join().unwrap().lines().count(), 4);
}

#[test]
fn a_cache_written_before_entries_carried_checksums_keeps_its_results() {
    let (_, study, cache) = studied("files-legacy", "c.sqlite");
    // The file as a texopt without checksums left it.
    let c = rusqlite::Connection::open(&cache).unwrap();
    c.execute_batch("ALTER TABLE evaluations DROP COLUMN checksum; DROP TABLE meta;")
        .unwrap();
    drop(c);
    let (code, out, _) = texopt(&["cache", "stats", "--cache", s(&cache)]);
    assert_eq!(code, 0);
    assert!(
        out.contains("3 entries written before entries carried checksums"),
        "{out}"
    );
    // A run that writes to it gives every entry its checksum and computes nothing again.
    let (code, out, err) = run_study(&study, &cache, &["--no-report"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("3 from the cache, 0 computed"), "{out}");
    let (code, out, _) = texopt(&["cache", "stats", "--cache", s(&cache)]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("integrity: ok") && !out.contains("before entries"),
        "{out}"
    );
    // From then on an entry without a checksum is damaged.
    let c = rusqlite::Connection::open(&cache).unwrap();
    c.execute("UPDATE evaluations SET checksum = NULL WHERE rowid = 1", [])
        .unwrap();
    drop(c);
    assert_eq!(texopt(&["cache", "stats", "--cache", s(&cache)]).0, 1);
}
