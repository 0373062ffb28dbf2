//! A cache entry as stored, read back column by column, its checksum, and what is wrong with
//! it. Every column a reader relies on (the key and its hash, the status, the outcome or the
//! failure's reason, the run's wall time, steps and texopt version) is covered by the
//! checksum, so that a changed digit, a flipped byte or a value of the wrong type is found on
//! every read, named, and never served.

use rusqlite::types::ValueRef;
use sha2::{Digest, Sha256};

/// The columns an entry is read with, in this order (the checksum column last, or NULL for
/// a cache written before entries carried one).
pub(super) fn columns(checked: bool) -> String {
    format!(
        "hash, key, status, outcome, reason, wall_time_s, steps, texopt_version, created, {}",
        if checked { "checksum" } else { "NULL" }
    )
}

/// One entry as stored. A column holding what no texopt writes (bytes that are not UTF-8, a
/// BLOB, a number where text belongs) marks the entry `unreadable`.
#[derive(Clone, Debug, Default)]
pub(super) struct Raw {
    pub hash: String,
    pub key: String,
    pub status: String,
    pub outcome: Option<String>,
    pub reason: Option<String>,
    pub wall_time_s: f64,
    pub steps: i64,
    pub texopt_version: String,
    pub created: String,
    pub checksum: Option<String>,
    pub unreadable: Option<&'static str>,
}

impl Raw {
    /// Reads a row selected with [`columns`]; never fails on what a column holds.
    pub fn read(r: &rusqlite::Row) -> rusqlite::Result<Raw> {
        let mut raw = Raw::default();
        let mut text = |i: usize, name: &'static str| -> rusqlite::Result<Option<String>> {
            Ok(match r.get_ref(i)? {
                ValueRef::Null => None,
                ValueRef::Text(b) => match std::str::from_utf8(b) {
                    Ok(s) => Some(s.to_string()),
                    Err(_) => {
                        raw.unreadable.get_or_insert(name);
                        None
                    }
                },
                _ => {
                    raw.unreadable.get_or_insert(name);
                    None
                }
            })
        };
        let hash = text(0, "hash")?;
        let key = text(1, "key")?;
        let status = text(2, "status")?;
        let outcome = text(3, "outcome")?;
        let reason = text(4, "reason")?;
        let version = text(7, "texopt_version")?;
        let created = text(8, "created")?;
        let checksum = text(9, "checksum")?;
        let wall = match r.get_ref(5)? {
            ValueRef::Real(x) => Some(x),
            ValueRef::Integer(n) => Some(n as f64),
            _ => None,
        };
        let steps = match r.get_ref(6)? {
            ValueRef::Integer(n) => Some(n),
            _ => None,
        };
        if wall.is_none() {
            raw.unreadable.get_or_insert("wall_time_s");
        }
        if steps.is_none() {
            raw.unreadable.get_or_insert("steps");
        }
        Ok(Raw {
            hash: hash.unwrap_or_default(),
            key: key.unwrap_or_default(),
            status: status.unwrap_or_default(),
            outcome,
            reason,
            wall_time_s: wall.unwrap_or(0.0),
            steps: steps.unwrap_or(0),
            texopt_version: version.unwrap_or_default(),
            created: created.unwrap_or_default(),
            checksum,
            unreadable: raw.unreadable,
        })
    }

    /// The checksum of what this entry holds.
    pub fn computed_checksum(&self) -> String {
        checksum(&Covered {
            hash: &self.hash,
            key: &self.key,
            status: &self.status,
            outcome: self.outcome.as_deref(),
            reason: self.reason.as_deref(),
            wall_time_s: self.wall_time_s,
            steps: self.steps,
            texopt_version: &self.texopt_version,
        })
    }

    /// What is wrong with this entry, if anything. `checked`: whether the cache's entries
    /// carry checksums (then one without is damaged too; in a cache written before entries
    /// carried them there is nothing to check it against).
    pub fn damage(&self, checked: bool) -> Option<String> {
        if let Some(column) = self.unreadable {
            return Some(format!("its {column} is not what texopt writes there"));
        }
        if hash_of(&self.key) != self.hash {
            return Some("its key does not match its hash".into());
        }
        match self.status.as_str() {
            "done" if self.outcome.is_none() => {
                return Some("a finished entry without its outcome".into())
            }
            "done" | "failed" => {}
            _ => return Some("its status is neither done nor failed".into()),
        }
        match &self.checksum {
            None if checked => Some("it has no checksum".into()),
            Some(c) if *c != self.computed_checksum() => Some(
                "its checksum does not match what it holds (altered after it was written)".into(),
            ),
            _ => None,
        }
    }
}

/// An entry and what is wrong with it, if anything ([`Raw::damage`]).
pub(super) type Checked = (Raw, Option<String>);

/// What the checksum covers.
pub(super) struct Covered<'a> {
    pub hash: &'a str,
    pub key: &'a str,
    pub status: &'a str,
    pub outcome: Option<&'a str>,
    pub reason: Option<&'a str>,
    pub wall_time_s: f64,
    pub steps: i64,
    pub texopt_version: &'a str,
}

/// The hash of a key's canonical JSON (SHA-256, hex): the cache's primary key.
pub(super) fn hash_of(json: &str) -> String {
    Sha256::digest(json.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// SHA-256 over the covered columns, each framed by its length (so that moving bytes from one
/// column to the next shows), numbers by their bits.
pub(super) fn checksum(c: &Covered) -> String {
    let mut h = Sha256::new();
    let texts = [
        Some(c.hash),
        Some(c.key),
        Some(c.status),
        c.outcome,
        c.reason,
        Some(c.texopt_version),
    ];
    for part in texts {
        h.update(part.map_or(-1, |p| p.len() as i64).to_le_bytes());
        h.update(part.map_or(&[][..], str::as_bytes));
    }
    h.update(c.wall_time_s.to_bits().to_le_bytes());
    h.update(c.steps.to_le_bytes());
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sound() -> Raw {
        let key = r#"{"model":"m"}"#.to_string();
        let mut r = Raw {
            hash: hash_of(&key),
            key,
            status: "done".into(),
            outcome: Some(r#"{"f_mean":0.1059}"#.into()),
            wall_time_s: 1.5,
            steps: 10,
            texopt_version: "0.1.0".into(),
            ..Raw::default()
        };
        r.checksum = Some(r.computed_checksum());
        r
    }

    #[test]
    fn every_covered_column_changed_is_found() {
        assert_eq!(sound().damage(true), None);
        let changes: Vec<fn(&mut Raw)> = vec![
            |r| r.outcome = Some(r#"{"f_mean":0.1058}"#.into()),
            |r| r.key = r#"{"model":"n"}"#.into(),
            |r| r.status = "failed".into(),
            |r| r.reason = Some("x".into()),
            |r| r.wall_time_s = 99.0,
            |r| r.steps = 11,
            |r| r.texopt_version = "9".into(),
            |r| r.checksum = None,
            |r| r.unreadable = Some("outcome"),
            |r| r.outcome = None,
        ];
        for (i, change) in changes.iter().enumerate() {
            let mut r = sound();
            change(&mut r);
            assert!(r.damage(true).is_some(), "change {i} went unnoticed");
        }
        // A cache written before entries carried checksums has none to check.
        let mut legacy = sound();
        legacy.checksum = None;
        assert_eq!(legacy.damage(false), None);
    }
}
