//! `texopt cache`: inspect, export or clear the evaluation cache.

use super::{cache_error, CacheAction, CacheArgs, CmdError};
use crate::study::cache::{path_from, Cache, CacheError};

pub(super) fn run(a: &CacheArgs) -> Result<i32, CmdError> {
    if let CacheAction::Merge { sources, into } = &a.action {
        return merge(sources, into);
    }
    // Inspecting or clearing must not create, initialise or convert a file: a mistyped path
    // would otherwise show an empty cache as if it were the one meant.
    let path = path_from(a.cache.as_deref()).map_err(|e| CmdError::Input(e.to_string()))?;
    if !path.exists() {
        return Err(CmdError::Input(format!(
            "no cache at {}: nothing has been evaluated there yet (`texopt study` and `texopt optimise` create it); check --cache or $TEXOPT_CACHE",
            path.display()
        )));
    }
    // Inspection reads only: it never writes, nor checkpoints a log into the file.
    let cache = match a.action {
        CacheAction::Clear { .. } => Cache::open_existing(&path),
        _ => Cache::open_read_only(&path),
    }
    .map_err(cache_error)?;
    let other = |e: CacheError| CmdError::Other(e.to_string());
    match &a.action {
        CacheAction::Stats => {
            let s = cache.stats().map_err(other)?;
            let ok = cache.integrity_check().map_err(other)?;
            println!("cache {}", cache.path().display());
            println!(
                "  {} evaluations done, {} failed; {:.1} s of compute stored; {} on disk ({} database file, {} write-ahead log); integrity: {}",
                s.done,
                s.failed,
                s.compute_seconds,
                size(s.file_bytes + s.wal_bytes),
                size(s.file_bytes),
                size(s.wal_bytes),
                integrity(&ok, &s.damaged)
            );
            if s.unchecked > 0 {
                println!(
                    "  {} entries written before entries carried checksums (checked from the next run that writes to this cache)",
                    s.unchecked
                );
            }
            if !s.damaged.is_empty() {
                return Err(CmdError::Other(format!(
                    "cache {}: {} damaged entries (never served: a study or optimise run computes them again, `texopt cache merge` does not copy them): {}",
                    cache.path().display(),
                    s.damaged.len(),
                    short_hashes(&s.damaged)
                )));
            }
        }
        CacheAction::Export { out } => {
            let (n, damaged) = match out {
                Some(p) => {
                    crate::output::check_writable(p)
                        .map_err(|why| CmdError::Input(format!("--out {}: {why}", p.display())))?;
                    let mut n = (0, Vec::new());
                    crate::output::write_with(p, |w| {
                        n = cache.export(w).map_err(std::io::Error::other)?;
                        Ok(())
                    })
                    .map_err(|e| CmdError::Other(format!("--out: {e}")))?;
                    n
                }
                None => cache.export(&mut std::io::stdout().lock()).map_err(other)?,
            };
            eprintln!("exported {n} evaluations");
            if !damaged.is_empty() {
                eprintln!(
                    "left out {} damaged entries (their checksum does not match): {}",
                    damaged.len(),
                    short_hashes(&damaged)
                );
            }
        }
        CacheAction::Merge { .. } => unreachable!("handled above"),
        CacheAction::Clear { failed } => {
            let n = cache.clear(*failed).map_err(other)?;
            println!(
                "deleted {n} {}evaluations from {}",
                if *failed { "failed " } else { "" },
                cache.path().display()
            );
        }
    }
    Ok(0)
}

/// SQLite's verdict on the file, and the entries whose checksum does not match.
fn integrity(sqlite: &str, damaged: &[String]) -> String {
    match (sqlite, damaged.len()) {
        ("ok", 0) => "ok".into(),
        ("ok", n) => format!("{n} damaged entries"),
        (s, 0) => s.into(),
        (s, n) => format!("{s}; {n} damaged entries"),
    }
}

/// Entries named by the first 12 digits of their hash: the first ten, and how many more.
fn short_hashes(hashes: &[String]) -> String {
    let mut s: Vec<&str> = hashes
        .iter()
        .take(10)
        .map(|h| &h[..h.len().min(12)])
        .collect();
    let more = format!("and {} more", hashes.len().saturating_sub(10));
    if hashes.len() > 10 {
        s.push(&more);
    }
    s.join(", ")
}

/// A size on disk: bytes below a kilobyte, else kB, MB or GB (decimal) to 3 digits or so.
fn size(bytes: u64) -> String {
    let b = bytes as f64;
    match ["kB", "MB", "GB", "TB"]
        .iter()
        .enumerate()
        .rev()
        .find(|(i, _)| b >= 1e3f64.powi(*i as i32 + 1))
    {
        None => format!("{bytes} bytes"),
        Some((i, unit)) => {
            let x = b / 1e3f64.powi(i as i32 + 1);
            format!("{x:.prec$} {unit}", prec = if x < 100.0 { 1 } else { 0 })
        }
    }
}

/// Removes a cache file this command created, with SQLite's journal files beside it.
fn drop_new_cache(path: &std::path::Path) {
    for suffix in ["", "-wal", "-shm", "-journal"] {
        let mut p = path.as_os_str().to_owned();
        p.push(suffix);
        let _ = std::fs::remove_file(p);
    }
}

/// `texopt cache merge A B … --into C`.
fn merge(sources: &[std::path::PathBuf], into: &std::path::Path) -> Result<i32, CmdError> {
    let into = path_from(Some(into))
        .map_err(|e| CmdError::Input(e.to_string().replace("--cache", "--into")))?;
    for s in sources {
        if !s.is_file() {
            return Err(CmdError::Input(format!(
                "cache merge: {} is not a file; give the cache files to merge",
                s.display()
            )));
        }
    }
    let existed = into.exists();
    let cache = Cache::open(&into).map_err(|e| match cache_error(e) {
        CmdError::Input(m) => CmdError::Input(m.replace("--cache", "--into")),
        other => other,
    })?;
    let merged = cache.merge(sources);
    drop(cache);
    let m = merged.map_err(|e| {
        // A merge that fails leaves no new file behind (nor SQLite's journal files).
        if !existed {
            drop_new_cache(&into);
        }
        match e {
            CacheError::Sqlite { .. } => CmdError::Other(e.to_string()),
            _ => CmdError::Input(format!("cache merge: {e}")),
        }
    })?;
    println!(
        "merged {} caches into {}: {} entries added, {} already there, {} failures replaced by results, {} failures not copied over results, {} of another model version skipped",
        sources.len(),
        into.display(),
        m.added,
        m.same,
        m.replaced_failures,
        m.kept_done,
        m.other_model
    );
    if m.repaired > 0 {
        println!(
            "  {} damaged entries of {} replaced by sound ones",
            m.repaired,
            into.display()
        );
    }
    if !m.damaged.is_empty() {
        let hashes: Vec<String> = m.damaged.iter().map(|(_, h)| h.clone()).collect();
        let from: std::collections::BTreeSet<&str> =
            m.damaged.iter().map(|(f, _)| f.as_str()).collect();
        eprintln!(
            "not copied: {} damaged entries of {} (their checksum does not match; a run computes them again): {}",
            m.damaged.len(),
            from.into_iter().collect::<Vec<_>>().join(", "),
            short_hashes(&hashes)
        );
    }
    Ok(0)
}

#[cfg(test)]
mod tests {
    #[test]
    fn sizes_read_at_a_glance() {
        assert_eq!(super::size(0), "0 bytes");
        assert_eq!(super::size(999), "999 bytes");
        assert_eq!(super::size(241_664), "242 kB");
        assert_eq!(super::size(430_000_000), "430 MB");
        assert_eq!(super::size(4_300_000), "4.3 MB");
        assert_eq!(super::size(2_500_000_000), "2.5 GB");
    }
}
