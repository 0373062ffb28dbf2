//! Merging caches: the evaluations of caches written elsewhere (one per cluster task, since
//! SQLite's locking is not safe over network file systems) copied into one. Every source is
//! read and checked before anything is written; the copy is one transaction, so a refused
//! merge changes nothing, and merging the same file twice changes nothing the second time.

use rusqlite::{params, Connection, OpenFlags, OptionalExtension};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

use super::cache::{
    check_file, check_integrity, check_wal, checksum, damage, identity, Cache, CacheError,
    APPLICATION_ID, MODEL_VERSION,
};

/// One stored evaluation, as the `evaluations` table holds it.
#[derive(Clone, Debug)]
struct Row {
    hash: String,
    key: String,
    status: String,
    outcome: Option<String>,
    reason: Option<String>,
    wall_time_s: f64,
    steps: i64,
    texopt_version: String,
    created: String,
    /// None for an entry written before entries carried a checksum.
    checksum: Option<String>,
}

/// An entry the cache merged into already holds.
enum Have {
    Sound(String, Option<String>),
    Damaged,
}

/// What a merge did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Merged {
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
fn read(path: &Path) -> Result<Vec<Row>, CacheError> {
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
    let has_checksums: bool = conn
        .query_row(
            "SELECT count(*) FROM pragma_table_info('evaluations') WHERE name = 'checksum'",
            [],
            |r| r.get::<_, i64>(0).map(|n| n > 0),
        )
        .map_err(sql)?;
    let mut st = conn
        .prepare(&format!(
            "SELECT hash, key, status, outcome, reason, wall_time_s, steps, texopt_version, created, {}
             FROM evaluations ORDER BY hash",
            if has_checksums { "checksum" } else { "NULL" }
        ))
        .map_err(sql)?;
    let rows = st
        .query_map([], |r| {
            Ok(Row {
                hash: r.get(0)?,
                key: r.get(1)?,
                status: r.get(2)?,
                outcome: r.get(3)?,
                reason: r.get(4)?,
                wall_time_s: r.get(5)?,
                steps: r.get(6)?,
                texopt_version: r.get(7)?,
                created: r.get(8)?,
                checksum: r.get(9)?,
            })
        })
        .map_err(sql)?
        .collect::<Result<Vec<_>, _>>()
        .map_err(sql)?;
    // A key whose hash is not its SHA-256 was altered after it was written.
    if let Some(r) = rows.iter().find(|r| hash(&r.key) != r.hash) {
        return Err(CacheError::Foreign {
            path: shown,
            why: format!(
                "the cache file is damaged (entry {} does not match its key)",
                &r.hash[..r.hash.len().min(12)]
            ),
        });
    }
    Ok(rows)
}

fn hash(key: &str) -> String {
    Sha256::digest(key.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
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
    pub fn merge(&self, sources: &[PathBuf]) -> Result<Merged, CacheError> {
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

    fn copy(&self, all: &[(String, Vec<Row>)]) -> Result<Merged, CacheError> {
        let mut m = Merged::default();
        let sql = |e| CacheError::Sqlite {
            path: self.path().display().to_string(),
            source: e,
        };
        for (from, rows) in all {
            for r in rows {
                let bad = damage(
                    &r.hash,
                    &r.status,
                    r.outcome.as_deref(),
                    r.reason.as_deref(),
                    r.checksum.as_deref(),
                );
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
        let row: Option<super::cache::Stored> = self
            .conn
            .query_row(
                "SELECT status, outcome, reason, checksum FROM evaluations WHERE hash = ?1",
                [hash],
                |x| Ok((x.get(0)?, x.get(1)?, x.get(2)?, x.get(3)?)),
            )
            .optional()?;
        Ok(row.map(|(status, outcome, reason, sum)| {
            match damage(
                hash,
                &status,
                outcome.as_deref(),
                reason.as_deref(),
                sum.as_deref(),
            ) {
                Some(_) => Have::Damaged,
                None => Have::Sound(status, outcome),
            }
        }))
    }

    fn insert(&self, r: &Row) -> rusqlite::Result<usize> {
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
                checksum(
                    &r.hash,
                    &r.status,
                    r.outcome.as_deref(),
                    r.reason.as_deref()
                )
            ],
        )
    }
}
