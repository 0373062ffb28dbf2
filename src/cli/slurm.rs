//! `texopt study FILE --slurm DIR`: the study as Slurm jobs. An sbatch array of N shares
//! (`--shard I/N`), each into a cache file of its own (SQLite's locking is not safe over
//! network file systems) with a log of its own, and a job that merges the shares' caches and
//! writes the report once every task has succeeded (`--dependency=afterok`). Slurm does the
//! scheduling; a failed or cancelled task is resubmitted alone and keeps what it finished.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::args::ClusterArgs;
use super::{CmdError, StudyArgs};
use crate::study::Study;

/// The files written into DIR.
struct Scripts {
    array: PathBuf,
    merge: PathBuf,
}

pub(super) fn run(a: &StudyArgs, study: &Study, dir: &Path) -> Result<i32, CmdError> {
    let tasks = a.cluster.tasks.unwrap_or(4);
    let cpus = a.cluster.cpus.unwrap_or(1);
    check_cluster(&a.cluster)?;
    let input = |e: std::io::Error, what: &Path| {
        CmdError::Input(format!(
            "--slurm {}: cannot create {}: {e}",
            dir.display(),
            what.display()
        ))
    };
    let cwd = std::env::current_dir().map_err(|e| input(e, Path::new(".")))?;
    let exe = std::env::current_exe().map_err(|e| input(e, Path::new("texopt")))?;
    // Every path is checked before anything is written, and again once canonical (a
    // symbolic link on the way may add what the given path did not have).
    slurm_dir(dir)?;
    script_path("the study file", &a.file)?;
    script_path("the working directory", &cwd)?;
    script_path("texopt's own path", &exe)?;
    slurm_dir(&cwd.join(dir))?;
    let file = a.file.canonicalize().map_err(|e| input(e, &a.file))?;
    for d in [dir.to_path_buf(), dir.join("logs"), dir.join("caches")] {
        std::fs::create_dir_all(&d).map_err(|e| input(e, &d))?;
    }
    let dir = dir.canonicalize().map_err(|e| input(e, dir))?;
    let paths = Paths {
        dir: slurm_dir(&dir)?,
        file: script_path("the study file", &file)?,
        cwd: script_path("the working directory", &cwd)?,
        exe: script_path("texopt's own path", &exe)?,
    };
    let s = write_scripts(a, study, &paths, tasks, cpus)?;
    eprintln!(
        "study {}: {} cases in {tasks} shares; scripts {} and {}",
        study.name,
        study.jobs.len(),
        s.array.display(),
        s.merge.display()
    );
    let (array, merge) = (s.array.to_string_lossy(), s.merge.to_string_lossy());
    if !a.submit {
        println!(
            "submit with:\n  id=$(sbatch --parsable {})\n  sbatch --dependency=afterok:${{id%%;*}} {}\n(a failed or cancelled task K: sbatch --array=K {} and then the merge again)",
            shell_quote(&array),
            shell_quote(&merge),
            shell_quote(&array)
        );
        return Ok(0);
    }
    let array = sbatch(&[&array])?;
    let dep = format!("--dependency=afterok:{array}");
    let merge = sbatch(&[&dep, &merge])?;
    println!("array job {array} ({tasks} tasks), merge-and-report job {merge} (after the array succeeds)");
    println!(
        "logs in {}/logs; the report goes to {}",
        dir.display(),
        study.report.dir
    );
    Ok(0)
}

/// The cluster flags checked before anything is written: a Slurm time limit, a partition
/// name.
pub(super) fn check_cluster(c: &ClusterArgs) -> Result<(), CmdError> {
    if let Some(t) = &c.time {
        check_time(t)?;
    }
    if let Some(p) = &c.partition {
        if p.is_empty()
            || !p
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c))
        {
            return Err(CmdError::Input(format!(
                "--partition {p:?}: a Slurm partition name is letters, digits, '_', '-' or '.'"
            )));
        }
    }
    Ok(())
}

/// The scripts' first lines: the shell, the partition and time limit where given, and the
/// working directory (`cwd`, a [`script_path`]).
pub(super) fn script_head(c: &ClusterArgs, cwd: &str) -> String {
    let mut head = String::from("#!/bin/bash\n");
    if let Some(part) = &c.partition {
        head += &format!("#SBATCH --partition={part}\n");
    }
    if let Some(t) = &c.time {
        head += &format!("#SBATCH --time={t}\n");
    }
    head + &format!("#SBATCH --chdir={}\n", sbatch_quote(cwd))
}

/// The paths the scripts name, each checked by [`script_path`].
struct Paths<'a> {
    dir: &'a str,
    file: &'a str,
    cwd: &'a str,
    exe: &'a str,
}

/// `sbatch --parsable ARGS`: the job id.
pub(super) fn sbatch(args: &[&str]) -> Result<String, CmdError> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .output()
        .map_err(|e| {
            CmdError::Other(format!(
                "cannot run sbatch ({e}): submit from a Slurm login node, or without --submit to only write the scripts"
            ))
        })?;
    if !out.status.success() {
        return Err(CmdError::Other(format!(
            "sbatch {}: {}",
            args.iter()
                .map(|a| shell_quote(a))
                .collect::<Vec<_>>()
                .join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let id = String::from_utf8_lossy(&out.stdout);
    // `--parsable` prints "id" or "id;cluster".
    Ok(id.trim().split(';').next().unwrap_or_default().to_string())
}

/// Slurm's time formats: MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS.
fn check_time(t: &str) -> Result<(), CmdError> {
    let (days, rest) = match t.split_once('-') {
        Some((d, r)) => (Some(d), r),
        None => (None, t),
    };
    let parts: Vec<&str> = rest.split(':').collect();
    let digits = |x: &str| !x.is_empty() && x.len() <= 4 && x.chars().all(|c| c.is_ascii_digit());
    let ok = days.is_none_or(digits) && parts.len() <= 3 && parts.iter().all(|p| digits(p));
    if ok {
        Ok(())
    } else {
        Err(CmdError::Input(format!(
            "--time {t:?}: give a Slurm time limit such as 02:00:00 or 1-00:00:00"
        )))
    }
}

/// `path` as text for a script, or why it cannot be: it must be UTF-8 (the scripts are text)
/// and hold no control character (a newline would end a line of the script, or of an
/// `#SBATCH` directive, early).
pub(super) fn script_path<'a>(what: &str, path: &'a Path) -> Result<&'a str, CmdError> {
    let refuse = |rule: &str| {
        CmdError::Input(format!(
            "{what} {:?}: {rule}, as it is written into the Slurm scripts; use another path",
            path.as_os_str()
        ))
    };
    let text = path
        .to_str()
        .ok_or_else(|| refuse("the path must be valid UTF-8"))?;
    if text.chars().any(char::is_control) {
        return Err(refuse(
            "the path cannot hold control characters (newline, tab, ...)",
        ));
    }
    Ok(text)
}

/// `--slurm DIR` as text for the scripts: a [`script_path`] without a backslash, since
/// Slurm drops every backslash of a log file's path (it reads one as "no %-patterns here").
pub(super) fn slurm_dir(dir: &Path) -> Result<&str, CmdError> {
    let text = script_path("--slurm", dir)?;
    if text.contains('\\') {
        return Err(CmdError::Input(format!(
            "--slurm {text:?}: Slurm cannot write logs under a path with a backslash; use another directory"
        )));
    }
    Ok(text)
}

/// `s` as one word for a POSIX shell: in single quotes, each `'` written `'\''`, so
/// nothing in it (`$`, backquotes, `"`, spaces, globs) is expanded or split.
pub(super) fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// `s` as one argument of an `#SBATCH` line, which sbatch splits itself (no shell reads
/// it): in double quotes, with `\`, `"`, `'` and `#` escaped by a backslash. That is what
/// every sbatch reads alike: older ones know only double quotes and end the line at any
/// unescaped `#`, even in quotes; newer ones take single quotes too.
pub(super) fn sbatch_quote(s: &str) -> String {
    let mut out = String::from('"');
    for c in s.chars() {
        if matches!(c, '\\' | '"' | '\'' | '#') {
            out.push('\\');
        }
        out.push(c);
    }
    out.push('"');
    out
}

/// The scripts. Every path in a shell line is [`shell_quote`]d; the two on `#SBATCH` lines
/// are [`sbatch_quote`]d, and the logs' directory has its `%` doubled, since Slurm expands
/// `%`-patterns (`%a`, `%j`, …) in a log file's whole path.
fn write_scripts(
    a: &StudyArgs,
    study: &Study,
    p: &Paths,
    tasks: usize,
    cpus: usize,
) -> Result<Scripts, CmdError> {
    let head = script_head(&a.cluster, p.cwd);
    let log = |name: &str| sbatch_quote(&format!("{}/logs/{name}", p.dir.replace('%', "%%")));
    // The paths once, as shell variables; the lines below only use them in double quotes.
    let vars = format!(
        "texopt={}\nstudy={}\ndir={}\n",
        shell_quote(p.exe),
        shell_quote(p.file),
        shell_quote(p.dir)
    );
    let array_sbatch = shell_quote(&format!("{}/array.sbatch", p.dir));
    let array = format!(
        "{head}#SBATCH --job-name=texopt-{name}\n#SBATCH --array=1-{tasks}\n#SBATCH --cpus-per-task={cpus}\n#SBATCH --output={out}\n\
# Share I of {tasks} of study {file}, one per array task, each into its own cache.\n\
# A failed or cancelled task K runs again alone, keeping what it stored: sbatch --array=K {array_sbatch}\n\
set -euo pipefail\n\
{vars}\
exec \"$texopt\" study \"$study\" --shard \"$SLURM_ARRAY_TASK_ID/{tasks}\" --cache \"$dir/caches/share-$SLURM_ARRAY_TASK_ID.sqlite\" --jobs \"${{SLURM_CPUS_PER_TASK:-1}}\"\n",
        name = study.name,
        out = log("task-%a.log"),
        file = shell_quote(p.file),
    );
    let merge = format!(
        "{head}#SBATCH --job-name=texopt-{name}-merge\n#SBATCH --cpus-per-task=1\n#SBATCH --output={out}\n\
# The shares' caches merged into one, and the study's report from it (nothing simulated).\n\
set -euo pipefail\n\
{vars}\
\"$texopt\" cache merge \"$dir\"/caches/share-*.sqlite --into \"$dir/merged.sqlite\"\n\
# Exit code 1 is a study with failed cases (contact, no periodic regime): they are in the\n\
# report, which is written; the job succeeds.\n\
\"$texopt\" study \"$study\" --cache \"$dir/merged.sqlite\" --cached-only || test $? -eq 1\n",
        name = study.name,
        out = log("merge.log"),
    );
    let dir = Path::new(p.dir);
    let s = Scripts {
        array: dir.join("array.sbatch"),
        merge: dir.join("merge.sbatch"),
    };
    for (path, text) in [(&s.array, array), (&s.merge, merge)] {
        crate::output::write(path, text).map_err(|e| CmdError::Other(e.to_string()))?;
    }
    Ok(s)
}
