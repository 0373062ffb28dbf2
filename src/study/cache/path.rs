//! Where the cache file is: the flag, else `TEXOPT_CACHE`, else the default; names that
//! would store nothing a rerun finds are refused.

use std::path::{Path, PathBuf};

/// Default cache file, relative to the working directory (git-ignored); `TEXOPT_CACHE`
/// or `--cache` choose another.
pub const DEFAULT_PATH: &str = ".texopt/cache.sqlite";

/// The cache path: the flag, else `TEXOPT_CACHE` (set and not empty), else `DEFAULT_PATH`.
/// Refused: an empty flag, SQLite's in-memory and URI names (`:memory:`, `file:…`), which
/// would store nothing a rerun finds, and a path that exists but is not a file.
pub fn path_from(flag: Option<&Path>) -> Result<PathBuf, PathError> {
    let from_env = || {
        std::env::var_os("TEXOPT_CACHE")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let (path, named_by) = match flag {
        Some(p) => (p.to_path_buf(), "--cache"),
        None => match from_env() {
            Some(p) => (p, "$TEXOPT_CACHE"),
            None => return Ok(PathBuf::from(DEFAULT_PATH)),
        },
    };
    let name = path.to_string_lossy();
    let why = if name.is_empty() {
        Some(PathProblem::Empty)
    } else if name == ":memory:" || name.starts_with("file:") {
        Some(PathProblem::NotAFile)
    } else if path.exists() && !path.is_file() {
        Some(PathProblem::NotRegular)
    } else {
        None
    };
    match why {
        Some(why) => Err(PathError {
            named_by,
            name: name.into_owned(),
            why,
        }),
        None => Ok(path),
    }
}

/// A cache path refused: where it was given (`--cache` or `$TEXOPT_CACHE`), as given, and
/// why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{named_by} = {name:?}: the cache path {why}; give a file path such as {DEFAULT_PATH}")]
pub struct PathError {
    pub named_by: &'static str,
    pub name: String,
    pub why: PathProblem,
}

/// Why a cache path is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PathProblem {
    #[error("is empty")]
    Empty,
    /// SQLite's in-memory and URI names: nothing would be kept for a rerun.
    #[error("names an SQLite database that is not a file (nothing would be kept for a rerun)")]
    NotAFile,
    #[error("exists and is not a file")]
    NotRegular,
}
