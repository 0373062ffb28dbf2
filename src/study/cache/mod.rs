//! The persistent evaluation cache: an embedded SQLite database (WAL journal, so several
//! processes may share one file on a local disk and a killed writer loses at most the
//! evaluation it was writing).
//!
//! Key: SHA-256 of the canonical JSON of everything that determines the answer — the model
//! version (`MODEL_VERSION`), every physical input (CaseSpec) and the numerics (mesh, dt,
//! tolerances, solver, start). Value: the outcomes (or the failure and its reason) with run
//! metadata (wall time, steps, texopt version, date).
//!
//! The parts: the key (`key`), the leases that let processes share a cache (`lease`), where
//! the file is (`path`), and its schema and checks (`schema`).

use rusqlite::config::DbConfig;
use rusqlite::{params, Connection, OpenFlags, OptionalExtension};
use serde::Serialize;
use std::path::{Path, PathBuf};

use super::entry::{self, checksum, Checked, Covered, Raw};
use crate::time::Outcome;

mod key;
mod lease;
mod path;
mod schema;

pub use key::Key;
pub use lease::LEASE_STALE_S;
pub use path::{path_from, PathError, PathProblem, DEFAULT_PATH};
pub(super) use schema::{
    check_file, check_integrity, check_wal, has_checksums, identity, APPLICATION_ID,
};
use schema::{check_identity, prepare_for_writing, Mode};

/// The model version in every key. It changes whenever a change of the code changes the
/// answers for the same inputs beyond the tolerances they were computed to; old entries
/// then stop matching (they stay in the file until `texopt cache clear`). A change that
/// moves answers only within those tolerances (round-off, or another path to the same
/// periodic regime within its tolerance) keeps it, so that cached studies stay valid.
pub const MODEL_VERSION: &str = "texopt-model-4";

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

/// The cache behind `cache`, whichever thread panicked while holding it (its entries are
/// each one write).
pub fn lock(cache: &std::sync::Mutex<Cache>) -> std::sync::MutexGuard<'_, Cache> {
    cache.lock().unwrap_or_else(|e| e.into_inner())
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
