//! `texopt study FILE --slurm DIR`: the study as Slurm jobs. An sbatch array of N shares
//! (`--shard I/N`), each into a cache file of its own (SQLite's locking is not safe over
//! network file systems) with a log of its own, and a job that merges the shares' caches and
//! writes the report once every task has succeeded (`--dependency=afterok`). Slurm does the
//! scheduling; a failed or cancelled task is resubmitted alone and keeps what it finished.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::{CmdError, StudyArgs};
use crate::study::Study;

/// The files written into DIR.
struct Scripts {
    array: PathBuf,
    merge: PathBuf,
}

pub(super) fn run(a: &StudyArgs, study: &Study, dir: &Path) -> Result<i32, CmdError> {
    let tasks = a.tasks.unwrap_or(4);
    let cpus = a.cpus.unwrap_or(1);
    if let Some(t) = &a.time {
        check_time(t)?;
    }
    if let Some(p) = &a.partition {
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
    let input = |e: std::io::Error, what: &Path| {
        CmdError::Input(format!(
            "--slurm {}: cannot create {}: {e}",
            dir.display(),
            what.display()
        ))
    };
    for d in [dir.to_path_buf(), dir.join("logs"), dir.join("caches")] {
        std::fs::create_dir_all(&d).map_err(|e| input(e, &d))?;
    }
    let dir = dir.canonicalize().map_err(|e| input(e, dir))?;
    let file = a.file.canonicalize().map_err(|e| input(e, &a.file))?;
    let cwd = std::env::current_dir().map_err(|e| input(e, Path::new(".")))?;
    let exe = std::env::current_exe().map_err(|e| input(e, Path::new("texopt")))?;
    let s = write_scripts(
        a,
        study,
        &Paths {
            dir: &dir,
            file: &file,
            cwd: &cwd,
            exe: &exe,
        },
        tasks,
        cpus,
    )?;
    eprintln!(
        "study {}: {} cases in {tasks} shares; scripts {} and {}",
        study.name,
        study.jobs.len(),
        s.array.display(),
        s.merge.display()
    );
    if !a.submit {
        println!(
            "submit with:\n  id=$(sbatch --parsable {})\n  sbatch --dependency=afterok:${{id%%;*}} {}\n(a failed or cancelled task K: sbatch --array=K {} and then the merge again)",
            s.array.display(),
            s.merge.display(),
            s.array.display()
        );
        return Ok(0);
    }
    let array = sbatch(&[s.array.to_str().unwrap_or_default()])?;
    let dep = format!("--dependency=afterok:{array}");
    let merge = sbatch(&[&dep, s.merge.to_str().unwrap_or_default()])?;
    println!("array job {array} ({tasks} tasks), merge-and-report job {merge} (after the array succeeds)");
    println!(
        "logs in {}/logs; the report goes to {}",
        dir.display(),
        study.report.dir
    );
    Ok(0)
}

struct Paths<'a> {
    dir: &'a Path,
    file: &'a Path,
    cwd: &'a Path,
    exe: &'a Path,
}

/// `sbatch --parsable ARGS`: the job id.
fn sbatch(args: &[&str]) -> Result<String, CmdError> {
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
            args.join(" "),
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

fn q(p: &Path) -> String {
    format!("'{}'", p.display().to_string().replace('\'', "'\\''"))
}

fn write_scripts(
    a: &StudyArgs,
    study: &Study,
    p: &Paths,
    tasks: usize,
    cpus: usize,
) -> Result<Scripts, CmdError> {
    let mut head = String::from("#!/bin/bash\n");
    if let Some(part) = &a.partition {
        head += &format!("#SBATCH --partition={part}\n");
    }
    if let Some(t) = &a.time {
        head += &format!("#SBATCH --time={t}\n");
    }
    head += &format!("#SBATCH --chdir={}\n", p.cwd.display());
    let (exe, file, dir) = (q(p.exe), q(p.file), p.dir.display());
    let array = format!(
        "{head}#SBATCH --job-name=texopt-{name}\n#SBATCH --array=1-{tasks}\n#SBATCH --cpus-per-task={cpus}\n#SBATCH --output={dir}/logs/task-%a.log\n\
# Share I of {tasks} of study {file_shown}, one per array task, each into its own cache.\n\
# A failed or cancelled task K runs again alone, keeping what it stored: sbatch --array=K {dir}/array.sbatch\n\
set -euo pipefail\n\
exec {exe} study {file} --shard \"$SLURM_ARRAY_TASK_ID/{tasks}\" --cache \"{dir}/caches/share-$SLURM_ARRAY_TASK_ID.sqlite\" --jobs \"${{SLURM_CPUS_PER_TASK:-1}}\"\n",
        name = study.name,
        file_shown = p.file.display(),
    );
    let merge = format!(
        "{head}#SBATCH --job-name=texopt-{name}-merge\n#SBATCH --cpus-per-task=1\n#SBATCH --output={dir}/logs/merge.log\n\
# The shares' caches merged into one, and the study's report from it (nothing simulated).\n\
set -euo pipefail\n\
{exe} cache merge {dir}/caches/share-*.sqlite --into {dir}/merged.sqlite\n\
# Exit code 1 is a study with failed cases (contact, no periodic regime): they are in the\n\
# report, which is written; the job succeeds.\n\
{exe} study {file} --cache {dir}/merged.sqlite --cached-only || test $? -eq 1\n",
        name = study.name,
    );
    let s = Scripts {
        array: p.dir.join("array.sbatch"),
        merge: p.dir.join("merge.sbatch"),
    };
    for (path, text) in [(&s.array, array), (&s.merge, merge)] {
        crate::output::write(path, text).map_err(CmdError::Other)?;
    }
    Ok(s)
}
