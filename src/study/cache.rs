//! The persistent evaluation cache: an embedded SQLite database (WAL journal, so several
//! processes may share one file on a local disk and a killed writer loses at most the
//! evaluation it was writing).
//!
//! Key: SHA-256 of the canonical JSON of everything that determines the answer — the model
//! version (`MODEL_VERSION`), every physical input (CaseSpec) and the numerics (mesh, dt,
//! tolerances, solver, start). Value: the outcomes (or the failure and its reason) with run
//! metadata (wall time, steps, texopt version, date).

use rusqlite::config::DbConfig;
use rusqlite::{params, Connection, OpenFlags, OptionalExtension};
use serde::Serialize;
use std::path::{Path, PathBuf};

use super::entry::{self, checksum, Checked, Covered, Raw};
use crate::mesh::RimModel;
use crate::model::case::CaseSpec;
use crate::solve::Method;
use crate::time::{Approach, Numerics, Outcome, Start, TimeScheme};

/// The model version in every key. It changes whenever a change of the code changes the
/// answers for the same inputs beyond the tolerances they were computed to; old entries
/// then stop matching (they stay in the file until `texopt cache clear`). A change that
/// moves answers only within those tolerances (round-off, or another path to the same
/// periodic regime within its tolerance) keeps it, so that cached studies stay valid.
pub const MODEL_VERSION: &str = "texopt-model-4";

/// SQLite `application_id` of a texopt cache ("TXOP").
pub(super) const APPLICATION_ID: i32 = 0x5458_4f50;
/// Schema version (`user_version`).
const SCHEMA: i32 = 1;

/// Default cache file, relative to the working directory (git-ignored); `TEXOPT_CACHE`
/// or `--cache` choose another.
pub const DEFAULT_PATH: &str = ".texopt/cache.sqlite";

/// The cache path: the flag, else `TEXOPT_CACHE` (set and not empty), else `DEFAULT_PATH`.
/// Refused: an empty flag, SQLite's in-memory and URI names (`:memory:`, `file:…`), which
/// would store nothing a rerun finds, and a path that exists but is not a file.
pub fn path_from(flag: Option<&Path>) -> Result<PathBuf, PathError> {
    let from_env = || {
        std::env::var_os("TEXOPT_CACHE")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let (path, named_by) = match flag {
        Some(p) => (p.to_path_buf(), "--cache"),
        None => match from_env() {
            Some(p) => (p, "$TEXOPT_CACHE"),
            None => return Ok(PathBuf::from(DEFAULT_PATH)),
        },
    };
    let name = path.to_string_lossy();
    let why = if name.is_empty() {
        Some(PathProblem::Empty)
    } else if name == ":memory:" || name.starts_with("file:") {
        Some(PathProblem::NotAFile)
    } else if path.exists() && !path.is_file() {
        Some(PathProblem::NotRegular)
    } else {
        None
    };
    match why {
        Some(why) => Err(PathError {
            named_by,
            name: name.into_owned(),
            why,
        }),
        None => Ok(path),
    }
}

/// A cache path refused: where it was given (`--cache` or `$TEXOPT_CACHE`), as given, and
/// why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{named_by} = {name:?}: the cache path {why}; give a file path such as {DEFAULT_PATH}")]
pub struct PathError {
    pub named_by: &'static str,
    pub name: String,
    pub why: PathProblem,
}

/// Why a cache path is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PathProblem {
    #[error("is empty")]
    Empty,
    /// SQLite's in-memory and URI names: nothing would be kept for a rerun.
    #[error("names an SQLite database that is not a file (nothing would be kept for a rerun)")]
    NotAFile,
    #[error("exists and is not a file")]
    NotRegular,
}

#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    #[error("cache {path}: {why}; it was left untouched — move it away or choose another file with --cache")]
    Foreign { path: String, why: String },
    #[error("cache {path}: {source}")]
    Sqlite {
        path: String,
        source: rusqlite::Error,
    },
    #[error("cache {path}: {why}")]
    Io { path: String, why: String },
    #[error("cache {path}: the write-ahead log beside it ({log}) belongs to another database ({why}); nothing was read or changed — move that log (and the -shm file beside it) away, or choose another file with --cache")]
    ForeignLog {
        path: String,
        log: String,
        why: String,
    },
}

/// What the cache holds for one key.
#[derive(Clone, Debug, PartialEq)]
pub enum Entry {
    Done(Outcome),
    Failed(String),
    /// An entry whose checksum does not match what it holds (altered after it was written):
    /// never served; the reason says what is wrong.
    Damaged(String),
}

/// An entry as stored, its outcome read as `T`.
pub(super) enum Stored<T> {
    Done(T),
    /// An outcome that does not read as `T` (written by an older layout).
    Unreadable,
    Failed(String),
    Damaged(String),
}

/// The canonical key of an evaluation and its hash.
#[derive(Clone, Debug)]
pub struct Key {
    pub hash: String,
    pub json: String,
}

#[derive(Serialize)]
struct KeyInputs<'a> {
    model: &'a str,
    case: &'a CaseSpec,
    numerics: KeyNumerics,
}

/// The numerics as keys hold them: every field of [`Numerics`] in its order, and after
/// `solver` the film solve's tolerance and cycle count of the key format, constants
/// (changing the format would orphan every evaluation stored).
#[derive(Serialize)]
struct KeyNumerics {
    n1: usize,
    n2: usize,
    dt: f64,
    periodic_tol: f64,
    t_max: f64,
    min_periods: usize,
    solver: Method,
    solve_tol: f64,
    cycles: usize,
    start: Start,
    accelerate: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    approach: Option<Approach>,
    #[serde(skip_serializing_if = "TimeScheme::is_backward_euler")]
    scheme: TimeScheme,
    #[serde(skip_serializing_if = "Option::is_none")]
    deep: Option<Approach>,
    #[serde(skip_serializing_if = "RimModel::is_nodal")]
    rim: RimModel,
}

impl KeyNumerics {
    fn of(n: &Numerics) -> Self {
        let Numerics {
            n1,
            n2,
            dt,
            periodic_tol,
            t_max,
            min_periods,
            solver,
            start,
            accelerate,
            approach,
            scheme,
            deep,
            rim,
        } = n.clone();
        KeyNumerics {
            n1,
            n2,
            dt,
            periodic_tol,
            t_max,
            min_periods,
            solver,
            solve_tol: 1e-8,
            cycles: 8,
            start,
            accelerate,
            approach,
            scheme,
            deep,
            rim,
        }
    }
}

impl Key {
    pub fn of(case: &CaseSpec, numerics: &Numerics) -> Key {
        let json = serde_json::to_string(&KeyInputs {
            model: MODEL_VERSION,
            case,
            numerics: KeyNumerics::of(numerics),
        })
        .expect("plain data serialises");
        let hash = entry::hash_of(&json);
        Key { hash, json }
    }
}

/// Counts for `texopt cache stats`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Stats {
    pub done: usize,
    pub failed: usize,
    pub compute_seconds: f64,
    /// The database file's size and its write-ahead log's beside it (bytes): the log holds
    /// recent writes until SQLite folds them into the file, and can outgrow it.
    pub file_bytes: u64,
    /// The entries whose checksum does not match (their hashes), and those written before
    /// entries carried one (not checked).
    pub damaged: Vec<String>,
    pub unchecked: usize,
    pub wal_bytes: u64,
}

pub struct Cache {
    pub(super) conn: Connection,
    path: PathBuf,
    /// Whether the file's entries carry checksums (a cache written before they did, opened
    /// to read only, has none to check).
    checked: bool,
}

impl Cache {
    /// Opens the cache file to store results, creating it (and its directory) if missing;
    /// a cache that cannot be written is refused before anything is computed. A file that is
    /// not an SQLite database, or another application's database, is reported and left alone.
    pub fn open(path: &Path) -> Result<Cache, CacheError> {
        // The cache and its WAL beside it need a writable directory (a read-only file
        // system fails SQLite's open with a vaguer "unable to open").
        if let Some(dir) = path.parent().filter(|d| d.is_dir()) {
            crate::output::check_writable(&dir.join(".texopt-probe")).map_err(|why| {
                CacheError::Io {
                    path: path.display().to_string(),
                    why: format!("cannot be written ({why}); choose a writable file with --cache"),
                }
            })?;
        }
        let cache = Cache::open_with(path, Mode::Create)?;
        if cache.conn.is_readonly(rusqlite::MAIN_DB).unwrap_or(true) {
            return Err(CacheError::Io {
                path: cache.path.display().to_string(),
                why: "cannot be written (read-only file or directory); results would be lost — choose a writable file with --cache".into(),
            });
        }
        Ok(cache)
    }

    /// Opens an existing cache to change it (clear entries): never creates, initialises or
    /// converts a file (an empty file, or another application's empty database, is refused
    /// and left as it was).
    pub fn open_existing(path: &Path) -> Result<Cache, CacheError> {
        Cache::open_with(path, Mode::Existing)
    }

    /// Opens an existing cache to read it only (stats, export, a report from what it holds):
    /// a read-only connection that never creates a file, writes or checkpoints.
    pub fn open_read_only(path: &Path) -> Result<Cache, CacheError> {
        Cache::open_with(path, Mode::Read)
    }

    fn open_with(path: &Path, mode: Mode) -> Result<Cache, CacheError> {
        let shown = path.display().to_string();
        if mode != Mode::Create && !path.is_file() {
            return Err(CacheError::Io {
                path: shown,
                why: "no such cache file".into(),
            });
        }
        check_file(path, &shown)?;
        check_wal(path, &shown)?;
        let sql = |source| CacheError::Sqlite {
            path: shown.clone(),
            source,
        };
        let log = super::wal::wal_path(path);
        let flags = match mode {
            Mode::Create => OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_CREATE,
            Mode::Existing => OpenFlags::SQLITE_OPEN_READ_WRITE,
            Mode::Read => OpenFlags::SQLITE_OPEN_READ_ONLY,
        };
        let conn = Connection::open_with_flags(path, flags).map_err(sql)?;
        // Nothing is checkpointed into the file until it has passed every check below (a
        // damaged log must not be written into it on close).
        conn.set_db_config(DbConfig::SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, true)
            .map_err(sql)?;
        conn.busy_timeout(std::time::Duration::from_secs(120))
            .map_err(sql)?;
        check_integrity(&conn, &shown).map_err(|e| match e {
            // SQLite reads the file through its log: either may be what is damaged.
            CacheError::Foreign { path, why } if log.is_file() => CacheError::Foreign {
                path,
                why: format!(
                    "{why}, as read through the write-ahead log beside it ({}); if that log came from another database, move it (and the -shm file) away and try again",
                    log.display()
                ),
            },
            other => other,
        })?;
        // What the file holds, read in one snapshot (another process may be creating it).
        conn.execute_batch("BEGIN").map_err(sql)?;
        let seen = identity(&conn);
        conn.execute_batch("COMMIT").map_err(sql)?;
        let (app, tables) = seen.map_err(sql)?;
        check_identity(&conn, &shown, app, tables)?;
        if mode != Mode::Create && app != APPLICATION_ID {
            return Err(CacheError::Foreign {
                path: shown,
                why: "not a texopt cache (an empty file or database)".into(),
            });
        }
        if mode != Mode::Read {
            prepare_for_writing(&conn, &shown, mode, app)?;
        }
        let checked = has_checksums(&conn).map_err(sql)?;
        Ok(Cache {
            conn,
            path: path.to_path_buf(),
            checked,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    fn sql(&self, source: rusqlite::Error) -> CacheError {
        CacheError::Sqlite {
            path: self.path.display().to_string(),
            source,
        }
    }

    /// The entry stored for `key`, its checksum checked: an entry altered after it was
    /// written is [`Entry::Damaged`]; an outcome of an older layout is `None` (recomputed).
    pub fn get(&self, key: &Key) -> Result<Option<Entry>, CacheError> {
        Ok(self.get_as(key)?.and_then(|e| match e {
            Stored::Done(out) => Some(Entry::Done(out)),
            Stored::Unreadable => None, // an older layout: recompute
            Stored::Failed(why) => Some(Entry::Failed(why)),
            Stored::Damaged(why) => Some(Entry::Damaged(why)),
        }))
    }

    /// The entry stored for `key` with its outcome read as `T`, its checksum checked.
    pub(super) fn get_as<T: serde::de::DeserializeOwned>(
        &self,
        key: &Key,
    ) -> Result<Option<Stored<T>>, CacheError> {
        let raw = self
            .conn
            .query_row(
                &format!(
                    "SELECT {} FROM evaluations WHERE hash = ?1",
                    entry::columns(self.checked)
                ),
                [&key.hash],
                Raw::read,
            )
            .optional()
            .map_err(|e| self.sql(e))?;
        let Some(raw) = raw else {
            return Ok(None);
        };
        if let Some(why) = raw.damage(self.checked) {
            return Ok(Some(Stored::Damaged(why)));
        }
        Ok(Some(match (raw.status.as_str(), raw.outcome) {
            ("done", Some(o)) => serde_json::from_str(&o).map_or(Stored::Unreadable, Stored::Done),
            _ => Stored::Failed(raw.reason.unwrap_or_default()),
        }))
    }

    /// Every entry as stored, in hash order, with what is wrong with it (if anything).
    fn entries(&self) -> Result<Vec<Checked>, CacheError> {
        let mut st = self
            .conn
            .prepare(&format!(
                "SELECT {} FROM evaluations ORDER BY created, hash",
                entry::columns(self.checked)
            ))
            .map_err(|e| self.sql(e))?;
        let rows = st
            .query_map([], Raw::read)
            .map_err(|e| self.sql(e))?
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| self.sql(e))?;
        Ok(rows
            .into_iter()
            .map(|r| {
                let bad = r.damage(self.checked);
                (r, bad)
            })
            .collect())
    }

    /// Stores a finished evaluation (replacing a stored failure).
    pub fn put_done(&self, key: &Key, out: &Outcome) -> Result<(), CacheError> {
        let outcome = serde_json::to_string(out).expect("plain data");
        self.put(key, Ok(&outcome), out.wall_time_s, out.steps as i64)
    }

    /// Stores a failed evaluation with its reason (never as a result).
    pub fn put_failed(&self, key: &Key, reason: &str, wall_time_s: f64) -> Result<(), CacheError> {
        self.put(key, Err(reason), wall_time_s, 0)
    }

    /// Stores an entry: an outcome's JSON (status `done`) or a failure's reason.
    pub(super) fn put(
        &self,
        key: &Key,
        answer: Result<&str, &str>,
        wall_time_s: f64,
        steps: i64,
    ) -> Result<(), CacheError> {
        let (status, outcome, reason) = match answer {
            Ok(o) => ("done", Some(o), None),
            Err(r) => ("failed", None, Some(r)),
        };
        self.conn
            .execute(
                "INSERT OR REPLACE INTO evaluations
                 (hash, key, status, outcome, reason, wall_time_s, steps, texopt_version, checksum)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
                params![
                    key.hash,
                    key.json,
                    status,
                    outcome,
                    reason,
                    wall_time_s,
                    steps,
                    env!("CARGO_PKG_VERSION"),
                    checksum(&Covered {
                        hash: &key.hash,
                        key: &key.json,
                        status,
                        outcome,
                        reason,
                        wall_time_s,
                        steps,
                        texopt_version: env!("CARGO_PKG_VERSION"),
                    })
                ],
            )
            .map(|_| ())
            .map_err(|e| self.sql(e))
    }

    /// Claims the computation named `lease` for this process, so that processes sharing the
    /// cache (two studies, an optimiser beside a study) compute each case once: true if it is
    /// now ours (it was free, ours already, or its holder is gone), false while another live
    /// process holds it. A holder on this host is gone when its process is; one on another
    /// host after [`LEASE_STALE_S`].
    pub fn claim(&self, lease: &str) -> Result<bool, CacheError> {
        let me = Owner::this();
        let tx = || -> rusqlite::Result<bool> {
            let held: Option<(String, i64, f64)> = self
                .conn
                .query_row(
                    "SELECT host, pid, taken FROM leases WHERE lease = ?1",
                    [lease],
                    |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
                )
                .optional()?;
            let free = held.is_none_or(|(host, pid, taken)| !me.sees_alive(&host, pid, taken));
            if free {
                self.conn.execute(
                    "INSERT OR REPLACE INTO leases (lease, host, pid, taken) VALUES (?1, ?2, ?3, ?4)",
                    params![lease, me.host, me.pid, now_s()],
                )?;
            }
            Ok(free)
        };
        self.conn
            .execute_batch("BEGIN IMMEDIATE")
            .map_err(|e| self.sql(e))?;
        match tx() {
            Ok(free) => {
                self.conn.execute_batch("COMMIT").map_err(|e| self.sql(e))?;
                Ok(free)
            }
            Err(e) => {
                let _ = self.conn.execute_batch("ROLLBACK");
                Err(self.sql(e))
            }
        }
    }

    /// Drops every lease: for a cache that one process owns alone (a cluster task's share),
    /// where a lease left by a killed run on another host would otherwise hold its case for
    /// [`LEASE_STALE_S`].
    pub fn clear_leases(&self) -> Result<(), CacheError> {
        self.conn
            .execute("DELETE FROM leases", [])
            .map(|_| ())
            .map_err(|e| self.sql(e))
    }

    /// Gives up this process's lease `lease` (its results are stored).
    pub fn release(&self, lease: &str) -> Result<(), CacheError> {
        let me = Owner::this();
        self.conn
            .execute(
                "DELETE FROM leases WHERE lease = ?1 AND host = ?2 AND pid = ?3",
                params![lease, me.host, me.pid],
            )
            .map(|_| ())
            .map_err(|e| self.sql(e))
    }

    /// Counts of the sound entries, the damaged ones named, and the file's sizes.
    pub fn stats(&self) -> Result<Stats, CacheError> {
        let mut st = Stats {
            file_bytes: std::fs::metadata(&self.path).map_or(0, |m| m.len()),
            wal_bytes: std::fs::metadata(super::wal::wal_path(&self.path)).map_or(0, |m| m.len()),
            ..Stats::default()
        };
        for (r, bad) in self.entries()? {
            if bad.is_some() {
                st.damaged.push(r.hash);
                continue;
            }
            if r.checksum.is_none() {
                st.unchecked += 1;
            }
            match r.status.as_str() {
                "done" => st.done += 1,
                _ => st.failed += 1,
            }
            st.compute_seconds += r.wall_time_s;
        }
        st.damaged.sort();
        Ok(st)
    }

    /// Every sound entry as JSON lines: {hash, key, status, outcome, reason, wall_time_s,
    /// steps, texopt_version, created}; returns how many, and the damaged entries left out
    /// (their hashes).
    pub fn export(&self, out: &mut dyn std::io::Write) -> Result<(usize, Vec<String>), CacheError> {
        let json = |t: &str| {
            serde_json::from_str::<serde_json::Value>(t)
                .unwrap_or_else(|_| serde_json::Value::String(t.to_string()))
        };
        let (mut n, mut damaged) = (0, Vec::new());
        for (r, bad) in self.entries()? {
            if bad.is_some() {
                damaged.push(r.hash);
                continue;
            }
            let v = serde_json::json!({
                "hash": r.hash,
                "key": json(&r.key),
                "status": r.status,
                "outcome": r.outcome.as_deref().map(json),
                "reason": r.reason,
                "wall_time_s": r.wall_time_s,
                "steps": r.steps,
                "texopt_version": r.texopt_version,
                "created": r.created,
            });
            writeln!(out, "{v}").map_err(|e| CacheError::Io {
                path: self.path.display().to_string(),
                why: format!("export: {e}"),
            })?;
            n += 1;
        }
        damaged.sort();
        Ok((n, damaged))
    }

    /// Deletes entries: only the failures when `failed_only`. Returns how many.
    pub fn clear(&self, failed_only: bool) -> Result<usize, CacheError> {
        let sql = if failed_only {
            "DELETE FROM evaluations WHERE status = 'failed'"
        } else {
            "DELETE FROM evaluations"
        };
        self.conn.execute(sql, []).map_err(|e| self.sql(e))
    }

    /// SQLite's own integrity check: "ok" or the problems it lists.
    pub fn integrity_check(&self) -> Result<String, CacheError> {
        let mut st = self
            .conn
            .prepare("PRAGMA integrity_check")
            .map_err(|e| self.sql(e))?;
        let rows: Vec<String> = st
            .query_map([], |r| r.get(0))
            .map_err(|e| self.sql(e))?
            .collect::<Result<_, _>>()
            .map_err(|e| self.sql(e))?;
        Ok(rows.join("; "))
    }
}

/// How a cache file is opened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// To store results: created (with its directory) if missing.
    Create,
    /// To change an existing cache.
    Existing,
    /// To read an existing cache only.
    Read,
}

/// A connection that passed the checks, made ready to write: WAL journal, the schema on a
/// fresh file, the leases table, checksums for entries written before entries carried them,
/// and the checkpoint on close back on.
fn prepare_for_writing(
    conn: &Connection,
    shown: &str,
    mode: Mode,
    app: i32,
) -> Result<(), CacheError> {
    let sql = |source| CacheError::Sqlite {
        path: shown.to_string(),
        source,
    };
    // Switching a fresh file to WAL needs it to itself for a moment; SQLite may answer
    // "busy" at once instead of waiting, so wait here (bounded like the busy timeout).
    let t0 = std::time::Instant::now();
    loop {
        match conn.pragma_update(None, "journal_mode", "WAL") {
            Err(e)
                if e.sqlite_error_code() == Some(rusqlite::ErrorCode::DatabaseBusy)
                    && t0.elapsed().as_secs() < 120 =>
            {
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            r => break r.map_err(sql)?,
        }
    }
    conn.pragma_update(None, "synchronous", "NORMAL")
        .map_err(sql)?;
    if app != APPLICATION_ID {
        create_schema(conn, shown)?;
    }
    if mode == Mode::Create {
        // Leases (see [`Cache::claim`]); a table of their own, so that caches made before
        // keep their schema version and older texopt versions still read them.
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS leases (
                 lease TEXT PRIMARY KEY, host TEXT NOT NULL, pid INTEGER NOT NULL,
                 taken REAL NOT NULL)",
        )
        .map_err(sql)?;
    }
    add_checksums(conn).map_err(sql)?;
    conn.set_db_config(DbConfig::SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, false)
        .map_err(sql)?;
    Ok(())
}

/// Gives the column `checksum` to a cache made before entries carried one, and a checksum
/// to each entry that is sound otherwise (read as it stands: there is nothing older to
/// check it against), then marks the cache as checked: from then on an entry without a
/// checksum is damaged. Older texopt versions name their columns, so they still read it.
fn add_checksums(conn: &Connection) -> rusqlite::Result<()> {
    if has_checksums(conn)? {
        return Ok(());
    }
    conn.execute_batch("BEGIN IMMEDIATE")?;
    let fill = || -> rusqlite::Result<()> {
        if has_checksums(conn)? {
            return Ok(()); // another process did it meanwhile
        }
        let column: i64 = conn.query_row(
            "SELECT count(*) FROM pragma_table_info('evaluations') WHERE name = 'checksum'",
            [],
            |r| r.get(0),
        )?;
        if column == 0 {
            conn.execute_batch("ALTER TABLE evaluations ADD COLUMN checksum TEXT")?;
        }
        // Before the mark, no checksum in the file is trusted: each is written anew.
        let rows: Vec<Raw> = conn
            .prepare(&format!("SELECT {} FROM evaluations", entry::columns(true)))?
            .query_map([], Raw::read)?
            .collect::<Result<_, _>>()?;
        for r in rows {
            let unsummed = Raw {
                checksum: None,
                ..r
            };
            // An entry damaged otherwise keeps no checksum: after the mark it reads as damaged.
            let sum = unsummed
                .damage(false)
                .is_none()
                .then(|| unsummed.computed_checksum());
            conn.execute(
                "UPDATE evaluations SET checksum = ?1 WHERE hash = ?2",
                params![sum, unsummed.hash],
            )?;
        }
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS meta (name TEXT PRIMARY KEY, value TEXT NOT NULL);
             INSERT OR REPLACE INTO meta VALUES ('checksums', 'every entry');",
        )
    };
    match fill() {
        Ok(()) => conn.execute_batch("COMMIT"),
        Err(e) => {
            let _ = conn.execute_batch("ROLLBACK");
            Err(e)
        }
    }
}

/// Whether the cache's entries carry checksums (every entry, since the mark was set).
pub(super) fn has_checksums(conn: &Connection) -> rusqlite::Result<bool> {
    let meta: i64 = conn.query_row(
        "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'meta'",
        [],
        |r| r.get(0),
    )?;
    if meta == 0 {
        return Ok(false);
    }
    conn.query_row(
        "SELECT count(*) FROM meta WHERE name = 'checksums'",
        [],
        |r| r.get::<_, i64>(0).map(|n| n > 0),
    )
}

/// A write-ahead log beside the cache that belongs to another database is refused before
/// SQLite reads it (it would be replayed into the cache; see [`super::wal`]). Checked twice,
/// a moment apart, so that a log another process is restarting at that instant is not taken
/// for a foreign one.
pub(super) fn check_wal(path: &Path, shown: &str) -> Result<(), CacheError> {
    let log = super::wal::wal_path(path);
    if !path.exists() && std::fs::symlink_metadata(&log).is_ok() {
        // SQLite would take a log it finds beside a new file as the file's own, or delete it.
        return Err(CacheError::ForeignLog {
            path: shown.to_string(),
            log: log.display().to_string(),
            why: "the cache file it would belong to does not exist".into(),
        });
    }
    let Err(first) = super::wal::check(path, APPLICATION_ID) else {
        return Ok(());
    };
    std::thread::sleep(std::time::Duration::from_millis(50));
    if super::wal::check(path, APPLICATION_ID).is_ok() {
        return Ok(());
    }
    Err(CacheError::ForeignLog {
        path: shown.to_string(),
        log: super::wal::wal_path(path).display().to_string(),
        why: first.to_string(),
    })
}

/// An existing file must begin as an SQLite database does; a missing one gets its directory.
pub(super) fn check_file(path: &Path, shown: &str) -> Result<(), CacheError> {
    if path.exists() {
        let mut head = [0u8; 16];
        use std::io::Read;
        let n = std::fs::File::open(path)
            .and_then(|mut f| f.read(&mut head))
            .map_err(|e| CacheError::Io {
                path: shown.to_string(),
                why: e.to_string(),
            })?;
        if n > 0 && (n < 16 || &head != b"SQLite format 3\0") {
            return Err(CacheError::Foreign {
                path: shown.to_string(),
                why: "not a texopt cache (not an SQLite database)".into(),
            });
        }
    } else if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| CacheError::Io {
            path: shown.to_string(),
            why: format!("cannot create directory {}: {e}", dir.display()),
        })?;
    }
    Ok(())
}

/// The first read: a file that is not a database, or a damaged one, fails here and is
/// reported before anything is written to it.
pub(super) fn check_integrity(conn: &Connection, shown: &str) -> Result<(), CacheError> {
    let damaged = |e: rusqlite::Error| match e.sqlite_error_code() {
        Some(rusqlite::ErrorCode::DatabaseCorrupt | rusqlite::ErrorCode::NotADatabase) => {
            CacheError::Foreign {
                path: shown.to_string(),
                why: format!("the cache file is damaged ({e})"),
            }
        }
        _ => CacheError::Sqlite {
            path: shown.to_string(),
            source: e,
        },
    };
    conn.query_row("PRAGMA application_id", [], |r| r.get::<_, i32>(0))
        .map_err(damaged)?;
    let check: String = conn
        .query_row("PRAGMA quick_check", [], |r| r.get(0))
        .map_err(damaged)?;
    if check != "ok" {
        let first = check.lines().find(|l| !l.starts_with("***")).unwrap_or("");
        return Err(CacheError::Foreign {
            path: shown.to_string(),
            why: format!(
                "the cache file is damaged (SQLite quick_check: {first}; {} problems)",
                check.lines().count()
            ),
        });
    }
    Ok(())
}

/// The file's application id and its number of tables.
pub(super) fn identity(conn: &Connection) -> rusqlite::Result<(i32, i64)> {
    let app: i32 = conn.query_row("PRAGMA application_id", [], |r| r.get(0))?;
    let tables: i64 = conn.query_row("SELECT count(*) FROM sqlite_master", [], |r| r.get(0))?;
    Ok((app, tables))
}

/// Seconds after which a lease taken on another host is taken over (its holder cannot be
/// seen from here): 6 h, longer than any one case runs (2048×128 at dt = 1e-4: 72 min).
pub const LEASE_STALE_S: f64 = 6.0 * 3600.0;

/// A process that can hold leases: its host and process id.
struct Owner {
    host: String,
    pid: i64,
}

impl Owner {
    fn this() -> Owner {
        // The host name is read once per process, not at every claim.
        static HOST: std::sync::OnceLock<String> = std::sync::OnceLock::new();
        let host = HOST.get_or_init(|| {
            std::fs::read_to_string("/proc/sys/kernel/hostname")
                .ok()
                .or_else(|| std::env::var("HOSTNAME").ok())
                .unwrap_or_default()
                .trim()
                .to_string()
        });
        Owner {
            host: host.clone(),
            pid: std::process::id() as i64,
        }
    }

    /// Whether the holder (`host`, `pid`, since `taken`) of a lease is another live process.
    fn sees_alive(&self, host: &str, pid: i64, taken: f64) -> bool {
        if host != self.host {
            return now_s() - taken < LEASE_STALE_S;
        }
        pid != self.pid && Path::new(&format!("/proc/{pid}")).exists()
    }
}

fn now_s() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// A database of another application, or a texopt cache of another schema, is refused.
fn check_identity(conn: &Connection, shown: &str, app: i32, tables: i64) -> Result<(), CacheError> {
    if app != APPLICATION_ID && tables > 0 {
        return Err(CacheError::Foreign {
            path: shown.to_string(),
            why: "not a texopt cache (an SQLite database of another application)".into(),
        });
    }
    if app == APPLICATION_ID {
        let v: i32 = conn
            .query_row("PRAGMA user_version", [], |r| r.get(0))
            .map_err(|source| CacheError::Sqlite {
                path: shown.to_string(),
                source,
            })?;
        if v != SCHEMA {
            return Err(CacheError::Foreign {
                path: shown.to_string(),
                why: format!(
                    "a texopt cache of schema version {v}; this texopt reads {SCHEMA} (export it with the texopt that wrote it)"
                ),
            });
        }
    }
    Ok(())
}

/// The cache's table, created under the write lock after checking again that nobody else
/// did.
fn create_schema(conn: &Connection, shown: &str) -> Result<(), CacheError> {
    let sql = |source| CacheError::Sqlite {
        path: shown.to_string(),
        source,
    };
    conn.execute_batch("BEGIN IMMEDIATE").map_err(sql)?;
    let create = match identity(conn) {
        Ok((APPLICATION_ID, _)) => Ok(()),
        Ok((_, 0)) => conn.execute_batch(&format!(
            "CREATE TABLE IF NOT EXISTS evaluations (
                 hash TEXT PRIMARY KEY,
                 key TEXT NOT NULL,
                 status TEXT NOT NULL CHECK (status IN ('done', 'failed')),
                 outcome TEXT,
                 reason TEXT,
                 wall_time_s REAL NOT NULL,
                 steps INTEGER NOT NULL,
                 texopt_version TEXT NOT NULL,
                 created TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),
                 checksum TEXT
             );
             PRAGMA application_id = {APPLICATION_ID};
             PRAGMA user_version = {SCHEMA};"
        )),
        Ok(_) => {
            let _ = conn.execute_batch("ROLLBACK");
            return Err(CacheError::Foreign {
                path: shown.to_string(),
                why: "not a texopt cache (an SQLite database of another application)".into(),
            });
        }
        Err(e) => Err(e),
    };
    match create {
        Ok(()) => conn.execute_batch("COMMIT").map_err(sql),
        Err(e) => {
            let _ = conn.execute_batch("ROLLBACK");
            Err(sql(e))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Processes (here: threads with their own connections) opening one fresh cache file at
    /// the same moment all get it: no "database is locked" from the one-time set-up.
    #[test]
    fn many_openers_of_a_fresh_cache_all_succeed() {
        for round in 0..20 {
            let p = std::env::temp_dir().join(format!(
                "texopt-cache-race-{}-{round}.sqlite",
                std::process::id()
            ));
            for ext in ["", "-wal", "-shm"] {
                let _ = std::fs::remove_file(format!("{}{ext}", p.display()));
            }
            let barrier = std::sync::Barrier::new(6);
            let results: Vec<Result<(), CacheError>> = std::thread::scope(|s| {
                let handles: Vec<_> = (0..6)
                    .map(|_| {
                        s.spawn(|| {
                            barrier.wait();
                            let c = Cache::open(&p)?;
                            c.stats().map(|_| ())
                        })
                    })
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap()).collect()
            });
            for r in &results {
                assert!(r.is_ok(), "round {round}: {r:?}");
            }
            for ext in ["", "-wal", "-shm"] {
                let _ = std::fs::remove_file(format!("{}{ext}", p.display()));
            }
        }
    }
}
