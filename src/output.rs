//! How texopt writes its files: each output goes to a temporary file beside its destination
//! and is renamed into place once complete, so that a full disk, a crash or Ctrl-C never
//! leaves a truncated report, and a failed rerun leaves the previous complete file as it was.
//!
//! The rename is for regular files only. A symbolic link is followed and its target is
//! replaced (the link stays a link); a device, FIFO or socket (`/dev/null`, `/dev/stdout`, a
//! named pipe a reader waits on) is written through, never replaced by a file.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The files written while [`recording`] runs (None: nobody asks).
static WRITTEN: Mutex<Option<Vec<PathBuf>>> = Mutex::new(None);

/// Runs `run` and returns, beside its result, every file it wrote through this module, in
/// the order written: how a host that runs a command in its own process (the Python
/// package) finds the command's outputs. One recording at a time: the caller serialises.
pub fn recording<T>(run: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let lock = || WRITTEN.lock().unwrap_or_else(|e| e.into_inner());
    *lock() = Some(Vec::new());
    let out = run();
    let files = lock().take().unwrap_or_default();
    (out, files)
}

/// Notes that `path` was written, for a [`recording`] under way.
fn written(path: &Path) {
    if let Some(files) = WRITTEN.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
        files.push(path.to_path_buf());
    }
}

/// What a writer reports when it fails (an I/O error, a drawing library's error, a message).
pub type Cause = Box<dyn std::error::Error + Send + Sync>;

/// An output that could not be written, or cannot be (`check_writable`).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot inspect {}: {source}", path.display())]
    Inspect {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot follow the link {}: {source}", path.display())]
    FollowLink {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{} is a directory; give a file path", .0.display())]
    Directory(PathBuf),
    #[error("{} is a loop of symbolic links; give a file path", .0.display())]
    LinkLoop(PathBuf),
    /// Where `path` leads could not be told.
    #[error("cannot write {}: {why}", path.display())]
    Unresolved {
        path: PathBuf,
        why: Box<OutputError>,
    },
    /// A regular file was not replaced; `kept`: a previous file is there, as it was.
    #[error("cannot write {}: {why}; {}", path.display(), if *kept { "the previous file was left as it was" } else { "nothing was written" })]
    NotReplaced {
        path: PathBuf,
        why: Failure,
        kept: bool,
    },
    /// A device or FIFO was not written through.
    #[error("cannot write {}: {why}", path.display())]
    NotWrittenThrough { path: PathBuf, why: Failure },
    #[error("cannot write in the directory of {}: {source}", path.display())]
    DirectoryNotWritable {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot write to {}: {source}", path.display())]
    SpecialNotWritable {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// Why an output's temporary file did not become the output.
#[derive(Debug, thiserror::Error)]
pub enum Failure {
    /// The writer failed.
    #[error("{0}")]
    Writer(Cause),
    #[error("cannot move it into place: {0}")]
    Rename(std::io::Error),
    #[error("cannot open it for writing: {0}")]
    Open(std::io::Error),
    /// Copying the complete temporary file into a device or FIFO failed.
    #[error("{0}")]
    Copy(std::io::Error),
}

/// Where an output goes once its path is resolved.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Destination {
    /// A regular file, or nothing yet: written beside it and renamed into place.
    Regular(PathBuf),
    /// A device, FIFO or socket: opened and written through.
    Special(PathBuf),
}

/// Resolves `path`: symbolic links are followed (a dangling link's target is where the file
/// will be made); what stands at the end decides how it is written.
fn destination(path: &Path) -> Result<Destination, OutputError> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        let meta = match std::fs::symlink_metadata(&p) {
            Ok(m) => m,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Ok(Destination::Regular(p))
            }
            Err(source) => return Err(OutputError::Inspect { path: p, source }),
        };
        let kind = meta.file_type();
        if kind.is_symlink() {
            let target = match std::fs::read_link(&p) {
                Ok(t) => t,
                Err(source) => return Err(OutputError::FollowLink { path: p, source }),
            };
            p = match p.parent() {
                Some(dir) if target.is_relative() => dir.join(target),
                _ => target,
            };
        } else if kind.is_dir() {
            return Err(OutputError::Directory(p));
        } else if kind.is_file() {
            return Ok(Destination::Regular(p));
        } else {
            return Ok(Destination::Special(p));
        }
    }
    Err(OutputError::LinkLoop(path.to_path_buf()))
}

/// The temporary file for `path`: hidden, in the same directory (a rename within one file
/// system is atomic), named for this process, and ending like `path` (plotters picks the
/// image format from the extension).
fn temporary(path: &Path) -> PathBuf {
    temporary_as(path, path)
}

/// The temporary file beside `target` that ends like `named` (a link's name gives the format
/// when its target's name has none).
fn temporary_as(target: &Path, named: &Path) -> PathBuf {
    let name = target
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let stem = name
        .rsplit_once('.')
        .map_or(name.as_str(), |(stem, _)| stem);
    let tmp = match named.extension() {
        Some(ext) => format!(
            ".{stem}.tmp-{}.{}",
            std::process::id(),
            ext.to_string_lossy()
        ),
        None => format!(".{name}.tmp-{}", std::process::id()),
    };
    target.with_file_name(tmp)
}

/// The text of the regular file at `path` (links followed), or None: a device or FIFO is
/// never read (a FIFO would wait for a writer), nor is what cannot be read.
pub fn read_regular(path: &Path) -> Option<String> {
    match destination(path).ok()? {
        Destination::Regular(p) => std::fs::read_to_string(p).ok(),
        Destination::Special(_) => None,
    }
}

/// Runs `write` on a temporary file and renames it to `path` if it succeeds; otherwise
/// removes it and says that `path` was left untouched. A link at `path` is followed and its
/// target replaced; a device or FIFO is written through (see the module's doc).
pub fn atomically<T, E: Into<Cause>>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, OutputError> {
    let resolved = destination(path).map_err(|why| OutputError::Unresolved {
        path: path.to_path_buf(),
        why: Box::new(why),
    })?;
    let out = match resolved {
        Destination::Regular(target) => replace(path, &target, write),
        Destination::Special(target) => write_through(path, &target, write),
    }?;
    written(path);
    Ok(out)
}

/// The atomic write of a regular file at `target` (`path`, or the end of the link at it).
fn replace<T, E: Into<Cause>>(
    path: &Path,
    target: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, OutputError> {
    let tmp = temporary_as(target, path);
    let result = write(&tmp)
        .map_err(|e| Failure::Writer(e.into()))
        .and_then(|v| {
            std::fs::rename(&tmp, target).map_err(Failure::Rename)?;
            Ok(v)
        });
    result.map_err(|why| {
        let _ = std::fs::remove_file(&tmp);
        OutputError::NotReplaced {
            path: path.to_path_buf(),
            why,
            kept: target.exists(),
        }
    })
}

/// A device, FIFO or socket at `target`: the output is made complete in a private temporary
/// file first (so a failed write sends nothing), then copied into `target`, which stays what
/// it is.
fn write_through<T, E: Into<Cause>>(
    path: &Path,
    target: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, OutputError> {
    let name = target
        .file_name()
        .map_or_else(|| std::ffi::OsString::from("output"), |n| n.to_os_string());
    let tmp = temporary(&std::env::temp_dir().join(name));
    let result = write(&tmp)
        .map_err(|e| Failure::Writer(e.into()))
        .and_then(|v| {
            let mut from = std::fs::File::open(&tmp).map_err(Failure::Copy)?;
            let mut to = std::fs::OpenOptions::new()
                .write(true)
                .open(target)
                .map_err(Failure::Open)?;
            std::io::copy(&mut from, &mut to).map_err(Failure::Copy)?;
            Ok(v)
        });
    let _ = std::fs::remove_file(&tmp);
    result.map_err(|why| OutputError::NotWrittenThrough {
        path: path.to_path_buf(),
        why,
    })
}

/// Writes `bytes` to `path` atomically (see [`atomically`]).
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputError> {
    atomically(path, |tmp| write_synced(tmp, bytes.as_ref()))
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
) -> Result<(), OutputError> {
    atomically(path, |tmp| {
        let f = std::fs::File::create(tmp)?;
        let mut w = std::io::BufWriter::new(f);
        fill(&mut w)?;
        let f = w.into_inner().map_err(|e| e.into_error())?;
        f.sync_all()
    })
}

/// Checks, before any work, that `path` can be written: a file can be created in the
/// directory of the regular file it names (a probe file is made and removed there), or the
/// device or FIFO it names can be opened for writing — so that a run does not end unable to
/// store what it computed.
pub fn check_writable(path: &Path) -> Result<(), OutputError> {
    match destination(path)? {
        Destination::Regular(target) => {
            let probe = temporary(&target).with_extension("probe");
            std::fs::File::create(&probe)
                .map(|_| {
                    let _ = std::fs::remove_file(&probe);
                })
                .map_err(|source| OutputError::DirectoryNotWritable {
                    path: path.to_path_buf(),
                    source,
                })
        }
        Destination::Special(target) => {
            special_writable(&target).map_err(|source| OutputError::SpecialNotWritable {
                path: path.to_path_buf(),
                source,
            })
        }
    }
}

/// Whether a device or FIFO has a write permission at all, checked without opening it
/// (opening a FIFO waits for its reader, which may only come once the run has its answer);
/// anything finer shows when it is opened.
fn special_writable(target: &Path) -> std::io::Result<()> {
    if std::fs::metadata(target)?.permissions().readonly() {
        return Err(std::io::Error::from(std::io::ErrorKind::PermissionDenied));
    }
    Ok(())
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
        let e = e.to_string();
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

    #[test]
    fn a_link_is_followed_and_stays_a_link() {
        let d = dir("link");
        let target = d.join("real.csv");
        std::fs::write(&target, "old\n").unwrap();
        let link = d.join("link.csv");
        std::os::unix::fs::symlink("real.csv", &link).unwrap();
        write(&link, "new\n").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new\n");
        // A link whose target's name has no extension: the link's name gives the format.
        let bare = d.join("bare");
        let png = d.join("picture.png");
        std::os::unix::fs::symlink("bare", &png).unwrap();
        atomically(&png, |tmp| {
            assert_eq!(tmp.extension().unwrap(), "png", "{}", tmp.display());
            std::fs::write(tmp, "image")
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&bare).unwrap(), "image");
        // A dangling link makes its target.
        let dangling = d.join("dangling.json");
        std::os::unix::fs::symlink(d.join("made.json"), &dangling).unwrap();
        write(&dangling, "{}").unwrap();
        assert_eq!(std::fs::read_to_string(d.join("made.json")).unwrap(), "{}");
        assert!(std::fs::symlink_metadata(&dangling)
            .unwrap()
            .file_type()
            .is_symlink());
    }

    #[test]
    fn a_device_is_written_through_not_replaced() {
        // A null device of the test's own: a failure must not replace the machine's.
        let d = dir("device");
        let null = d.join("null");
        let made = std::process::Command::new("mknod")
            .arg(&null)
            .args(["c", "1", "3"])
            .status()
            .is_ok_and(|s| s.success());
        if !made {
            return; // not allowed to make a device here: nothing to check
        }
        check_writable(&null).unwrap();
        write(&null, "discarded\n").unwrap();
        write_with(&null, |w| w.write_all(b"discarded too\n")).unwrap();
        use std::os::unix::fs::FileTypeExt;
        let kind = std::fs::symlink_metadata(&null).unwrap().file_type();
        assert!(kind.is_char_device(), "the device was replaced");
    }

    #[test]
    fn a_fifo_gets_the_whole_output_and_stays_a_fifo() {
        let d = dir("fifo");
        let fifo = d.join("pipe.json");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // no mkfifo here: nothing to check
        }
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        write(&fifo, "whole\n").unwrap();
        assert_eq!(reader.join().unwrap(), "whole\n");
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo());
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            1,
            "a temporary was left"
        );
    }

    #[test]
    fn only_a_regular_file_is_read_back() {
        let d = dir("read");
        let fifo = d.join("pipe.csv");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            assert_eq!(read_regular(&fifo), None); // and no wait for a writer
        }
        let f = d.join("f.csv");
        std::fs::write(&f, "x").unwrap();
        std::os::unix::fs::symlink("f.csv", d.join("l.csv")).unwrap();
        assert_eq!(read_regular(&d.join("l.csv")).as_deref(), Some("x"));
    }

    #[test]
    fn a_directory_or_a_link_loop_is_refused() {
        let d = dir("loop");
        assert!(check_writable(&d)
            .unwrap_err()
            .to_string()
            .contains("is a directory"));
        let a = d.join("a");
        std::os::unix::fs::symlink("b", &a).unwrap();
        std::os::unix::fs::symlink("a", d.join("b")).unwrap();
        assert!(write(&a, "x")
            .unwrap_err()
            .to_string()
            .contains("loop of symbolic links"));
    }
}
