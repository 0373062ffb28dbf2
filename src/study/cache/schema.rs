//! The cache file's schema and checks: its identity (application id, schema version), the
//! tables created once, checksums added to older entries, and the checks a file must pass
//! before it is read or written (a regular file, its write-ahead log its own, integrity).

use rusqlite::config::DbConfig;
use rusqlite::{params, Connection};
use std::path::Path;

use super::CacheError;
use crate::study::entry::{self, Raw};

/// SQLite `application_id` of a texopt cache ("TXOP").
pub(in crate::study) const APPLICATION_ID: i32 = 0x5458_4f50;
/// Schema version (`user_version`).
const SCHEMA: i32 = 1;

/// How a cache file is opened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Mode {
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
pub(super) fn prepare_for_writing(
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
pub(super) fn add_checksums(conn: &Connection) -> rusqlite::Result<()> {
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
pub(in crate::study) fn has_checksums(conn: &Connection) -> rusqlite::Result<bool> {
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
pub(in crate::study) fn check_wal(path: &Path, shown: &str) -> Result<(), CacheError> {
    let log = crate::study::wal::wal_path(path);
    if !path.exists() && std::fs::symlink_metadata(&log).is_ok() {
        // SQLite would take a log it finds beside a new file as the file's own, or delete it.
        return Err(CacheError::ForeignLog {
            path: shown.to_string(),
            log: log.display().to_string(),
            why: "the cache file it would belong to does not exist".into(),
        });
    }
    let Err(first) = crate::study::wal::check(path, APPLICATION_ID) else {
        return Ok(());
    };
    std::thread::sleep(std::time::Duration::from_millis(50));
    if crate::study::wal::check(path, APPLICATION_ID).is_ok() {
        return Ok(());
    }
    Err(CacheError::ForeignLog {
        path: shown.to_string(),
        log: crate::study::wal::wal_path(path).display().to_string(),
        why: first.to_string(),
    })
}

/// An existing file must begin as an SQLite database does; a missing one gets its directory.
pub(in crate::study) fn check_file(path: &Path, shown: &str) -> Result<(), CacheError> {
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
pub(in crate::study) fn check_integrity(conn: &Connection, shown: &str) -> Result<(), CacheError> {
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
pub(in crate::study) fn identity(conn: &Connection) -> rusqlite::Result<(i32, i64)> {
    let app: i32 = conn.query_row("PRAGMA application_id", [], |r| r.get(0))?;
    let tables: i64 = conn.query_row("SELECT count(*) FROM sqlite_master", [], |r| r.get(0))?;
    Ok((app, tables))
}

/// A database of another application, or a texopt cache of another schema, is refused.
pub(super) fn check_identity(
    conn: &Connection,
    shown: &str,
    app: i32,
    tables: i64,
) -> Result<(), CacheError> {
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
pub(super) fn create_schema(conn: &Connection, shown: &str) -> Result<(), CacheError> {
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
