//! `texopt cache`: inspect, export or clear the evaluation cache.

use super::{cache_error, CacheAction, CacheArgs, CmdError};
use crate::study::cache::{path_from, Cache, CacheError};

pub(super) fn run(a: &CacheArgs) -> Result<i32, CmdError> {
    if let CacheAction::Merge { sources, into } = &a.action {
        return merge(sources, into);
    }
    // Inspecting or clearing must not create, initialise or convert a file: a mistyped path
    // would otherwise show an empty cache as if it were the one meant.
    let path = path_from(a.cache.as_deref()).map_err(CmdError::Input)?;
    if !path.exists() {
        return Err(CmdError::Input(format!(
            "no cache at {}: nothing has been evaluated there yet (`texopt study` and `texopt optimise` create it); check --cache or $TEXOPT_CACHE",
            path.display()
        )));
    }
    let cache = Cache::open_existing(&path).map_err(cache_error)?;
    let other = |e: CacheError| CmdError::Other(e.to_string());
    match &a.action {
        CacheAction::Stats => {
            let s = cache.stats().map_err(other)?;
            let ok = cache.integrity_check().map_err(other)?;
            println!("cache {}", cache.path().display());
            println!(
                "  {} evaluations done, {} failed; {:.1} s of compute stored; {} on disk ({} database file, {} write-ahead log); integrity: {ok}",
                s.done,
                s.failed,
                s.compute_seconds,
                size(s.file_bytes + s.wal_bytes),
                size(s.file_bytes),
                size(s.wal_bytes)
            );
        }
        CacheAction::Export { out } => {
            let n = match out {
                Some(p) => {
                    crate::output::check_writable(p)
                        .map_err(|why| CmdError::Input(format!("--out {}: {why}", p.display())))?;
                    let mut n = 0;
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
    let into =
        path_from(Some(into)).map_err(|e| CmdError::Input(e.replace("--cache", "--into")))?;
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
