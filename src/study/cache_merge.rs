//! Merging caches: the evaluations of caches written elsewhere (one per cluster task, since
//! SQLite's locking is not safe over network file systems) copied into one. Every source is
//! read and checked before anything is written; the copy is one transaction, so a refused
//! merge changes nothing, and merging the same file twice changes nothing the second time.

use rusqlite::{params, Connection, OpenFlags, OptionalExtension};
use std::path::{Path, PathBuf};

use super::cache::{
    check_file, check_integrity, check_wal, has_checksums, identity, Cache, CacheError,
    APPLICATION_ID, MODEL_VERSION,
};
use super::entry::{self, Checked, Raw};

/// An entry the cache merged into already holds.
enum Have {
    Sound(String, Option<String>),
    Damaged,
}

/// What a merge did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MergeCounts {
    /// Entries copied in (new keys).
    pub added: usize,
    /// Entries already there with the same outcome (or the same failure).
    pub same: usize,
    /// Failures replaced by a finished evaluation of the same key.
    pub replaced_failures: usize,
    /// Failures not copied because the key is already finished.
    pub kept_done: usize,
    /// Entries of another model version, not copied (they would never be read).
    pub other_model: usize,
    /// Entries whose checksum does not match what they hold (source, hash), not copied.
    pub damaged: Vec<(String, String)>,
    /// Damaged entries of the cache merged into, replaced by a source's sound one.
    pub repaired: usize,
}

/// The entries of a source cache, read without writing to it (a read-only connection: no
/// journal mode is set, nothing is created). A file that is not a texopt cache, or damaged,
/// is refused and left untouched.
fn read(path: &Path) -> Result<Vec<Checked>, CacheError> {
    let shown = path.display().to_string();
    if !path.is_file() {
        return Err(CacheError::Io {
            path: shown,
            why: "no such file".into(),
        });
    }
    check_file(path, &shown)?;
    check_wal(path, &shown)?;
    let sql = |source| CacheError::Sqlite {
        path: shown.clone(),
        source,
    };
    let conn = Connection::open_with_flags(path, OpenFlags::SQLITE_OPEN_READ_ONLY).map_err(sql)?;
    check_integrity(&conn, &shown)?;
    let (app, _) = identity(&conn).map_err(sql)?;
    if app != APPLICATION_ID {
        return Err(CacheError::Foreign {
            path: shown,
            why: "not a texopt cache".into(),
        });
    }
    let checked = has_checksums(&conn).map_err(sql)?;
    let mut st = conn
        .prepare(&format!(
            "SELECT {} FROM evaluations ORDER BY hash",
            entry::columns(checked)
        ))
        .map_err(sql)?;
    let rows = st
        .query_map([], Raw::read)
        .map_err(sql)?
        .collect::<Result<Vec<_>, _>>()
        .map_err(sql)?;
    Ok(rows
        .into_iter()
        .map(|r| {
            let bad = r.damage(checked);
            (r, bad)
        })
        .collect())
}

/// The model version a key was computed with.
fn model_of(key: &str) -> Option<String> {
    let v: serde_json::Value = serde_json::from_str(key).ok()?;
    v.get("model")?.as_str().map(str::to_string)
}

/// An outcome without its run metadata (the wall time differs from machine to machine; the
/// numbers must not).
fn numbers(outcome: &str) -> Option<serde_json::Value> {
    let mut v: serde_json::Value = serde_json::from_str(outcome).ok()?;
    v.as_object_mut()?.remove("wall_time_s");
    Some(v)
}

impl Cache {
    /// Copies every evaluation of `sources` into this cache (see the module). Refused, with
    /// nothing written: a source that is not a texopt cache or is damaged, a source that is
    /// this cache, and two different outcomes under one key.
    pub fn merge(&self, sources: &[PathBuf]) -> Result<MergeCounts, CacheError> {
        let me = self.path().canonicalize().ok();
        let mut all = Vec::new();
        for p in sources {
            if p.canonicalize().ok() == me {
                return Err(CacheError::Io {
                    path: p.display().to_string(),
                    why: "is the cache merged into; give it only as --into".into(),
                });
            }
            all.push((p.display().to_string(), read(p)?));
        }
        let sql = |e| CacheError::Sqlite {
            path: self.path().display().to_string(),
            source: e,
        };
        self.conn.execute_batch("BEGIN IMMEDIATE").map_err(sql)?;
        let res = self.copy(&all);
        match res {
            Ok(m) => {
                self.conn.execute_batch("COMMIT").map_err(sql)?;
                Ok(m)
            }
            Err(e) => {
                let _ = self.conn.execute_batch("ROLLBACK");
                Err(e)
            }
        }
    }

    fn copy(&self, all: &[(String, Vec<Checked>)]) -> Result<MergeCounts, CacheError> {
        let mut m = MergeCounts::default();
        let sql = |e| CacheError::Sqlite {
            path: self.path().display().to_string(),
            source: e,
        };
        for (from, rows) in all {
            for (r, bad) in rows {
                if bad.is_some() {
                    m.damaged.push((from.clone(), r.hash.clone()));
                    continue;
                }
                if model_of(&r.key).as_deref() != Some(MODEL_VERSION) {
                    m.other_model += 1;
                    continue;
                }
                let have = self.stored(&r.hash).map_err(sql)?;
                match (have, r.status.as_str()) {
                    (Some(Have::Damaged), _) => {
                        self.insert(r).map_err(sql)?;
                        m.repaired += 1;
                    }
                    (None, _) => {
                        self.insert(r).map_err(sql)?;
                        m.added += 1;
                    }
                    (Some(Have::Sound(s, _)), "failed") if s == "done" => m.kept_done += 1,
                    (Some(Have::Sound(s, _)), "done") if s == "failed" => {
                        self.insert(r).map_err(sql)?;
                        m.replaced_failures += 1;
                    }
                    (Some(Have::Sound(_, mine)), _) => {
                        let theirs = r.outcome.as_deref().and_then(numbers);
                        if mine.as_deref().and_then(numbers) != theirs {
                            return Err(CacheError::Io {
                                path: from.clone(),
                                why: format!(
                                    "entry {} has another outcome than the one already merged for the same inputs; the caches disagree (different builds?) — nothing was merged",
                                    &r.hash[..12]
                                ),
                            });
                        }
                        m.same += 1;
                    }
                }
            }
        }
        Ok(m)
    }

    /// What this cache holds under `hash`: a sound entry's status and outcome, or a damaged
    /// one (replaced by the source's).
    fn stored(&self, hash: &str) -> rusqlite::Result<Option<Have>> {
        let raw = self
            .conn
            .query_row(
                &format!(
                    "SELECT {} FROM evaluations WHERE hash = ?1",
                    entry::columns(true)
                ),
                [hash],
                Raw::read,
            )
            .optional()?;
        Ok(raw.map(|r| match r.damage(true) {
            Some(_) => Have::Damaged,
            None => Have::Sound(r.status, r.outcome),
        }))
    }

    fn insert(&self, r: &Raw) -> rusqlite::Result<usize> {
        self.conn.execute(
            "INSERT OR REPLACE INTO evaluations
             (hash, key, status, outcome, reason, wall_time_s, steps, texopt_version, created,
              checksum)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
            params![
                r.hash,
                r.key,
                r.status,
                r.outcome,
                r.reason,
                r.wall_time_s,
                r.steps,
                r.texopt_version,
                r.created,
                r.computed_checksum()
            ],
        )
    }
}
