//! How texopt writes its files: each output goes to a temporary file beside its destination
//! and is renamed into place once complete, so that a full disk, a crash or Ctrl-C never
//! leaves a truncated report, and a failed rerun leaves the previous complete file as it was.

use std::path::{Path, PathBuf};

/// The temporary file for `path`: hidden, in the same directory (a rename within one file
/// system is atomic), named for this process, and ending like `path` (plotters picks the
/// image format from the extension).
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let tmp = match name.rsplit_once('.') {
        Some((stem, ext)) => format!(".{stem}.tmp-{}.{ext}", std::process::id()),
        None => format!(".{name}.tmp-{}", std::process::id()),
    };
    path.with_file_name(tmp)
}

/// Runs `write` on a temporary file and renames it to `path` if it succeeds; otherwise
/// removes it and says that `path` was left untouched.
pub fn atomically<T>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<T, String>,
) -> Result<T, String> {
    let tmp = temporary(path);
    let result = write(&tmp).and_then(|v| {
        std::fs::rename(&tmp, path).map_err(|e| format!("cannot move it into place: {e}"))?;
        Ok(v)
    });
    result.map_err(|why| {
        let _ = std::fs::remove_file(&tmp);
        let kept = if path.exists() {
            "the previous file was left as it was"
        } else {
            "nothing was written"
        };
        format!("cannot write {}: {why}; {kept}", path.display())
    })
}

/// Writes `bytes` to `path` atomically (see [`atomically`]).
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), String> {
    atomically(path, |tmp| {
        write_synced(tmp, bytes.as_ref()).map_err(|e| e.to_string())
    })
}

/// Writes and flushes to the disk (a full disk shows here, not after the rename).
fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut f = std::fs::File::create(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

/// Writes what `fill` writes to a buffered file at `path` atomically (see [`atomically`]).
pub fn write_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), String> {
    atomically(path, |tmp| {
        let f = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        let mut w = std::io::BufWriter::new(f);
        fill(&mut w).map_err(|e| e.to_string())?;
        let f = w.into_inner().map_err(|e| e.error().to_string())?;
        f.sync_all().map_err(|e| e.to_string())
    })
}

/// Checks, before any work, that a file can be created in `path`'s directory (a probe file
/// is made and removed there): so that a run does not end unable to store what it computed.
pub fn check_writable(path: &Path) -> Result<(), String> {
    if path.is_dir() {
        return Err(format!(
            "{} is a directory; give a file path",
            path.display()
        ));
    }
    let probe = temporary(path).with_extension("probe");
    std::fs::File::create(&probe)
        .map(|_| {
            let _ = std::fs::remove_file(&probe);
        })
        .map_err(|e| format!("cannot write in the directory of {}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("texopt-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_failed_write_leaves_the_previous_file_and_no_temporary() {
        let d = dir("failed");
        let p = d.join("report.csv");
        write(&p, "complete\n").unwrap();
        let e = atomically(&p, |tmp| {
            std::fs::write(tmp, "trunc").unwrap();
            Err::<(), _>("disk full".to_string())
        })
        .unwrap_err();
        assert!(
            e.contains("disk full") && e.contains("left as it was"),
            "{e}"
        );
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "complete\n");
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            1,
            "a temporary was left"
        );
    }

    #[test]
    fn the_temporary_keeps_the_extension() {
        let t = temporary(Path::new("results/x/front.png"));
        assert_eq!(t.extension().unwrap(), "png");
        assert_eq!(t.parent().unwrap(), Path::new("results/x"));
    }
}
