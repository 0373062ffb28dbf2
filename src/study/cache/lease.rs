//! Leases: a computation claimed by one process, so that processes sharing a cache compute
//! each case once; a holder that is gone loses its claims.

use rusqlite::{params, OptionalExtension};
use std::path::Path;

use super::{Cache, CacheError};

impl Cache {
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
}

/// Seconds after which a lease taken on another host is taken over (its holder cannot be
/// seen from here): 6 h, longer than any one case runs (2048×128 at dt = 1e-4: 72 min).
pub const LEASE_STALE_S: f64 = 6.0 * 3600.0;

/// A process that can hold leases: its host and process id.
pub(super) struct Owner {
    host: String,
    pid: i64,
}

impl Owner {
    pub(super) fn this() -> Owner {
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
    pub(super) fn sees_alive(&self, host: &str, pid: i64, taken: f64) -> bool {
        if host != self.host {
            return now_s() - taken < LEASE_STALE_S;
        }
        pid != self.pid && Path::new(&format!("/proc/{pid}")).exists()
    }
}

pub(super) fn now_s() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}
