//! `texopt cycle ENGINE [--bands] --slurm DIR`: the zone or band search's cycle runs (and the
//! band report's) as Slurm jobs. Each search step's runs that the cache does not hold form a
//! batch (DIR/batches/batch-K.json);
//! an sbatch array of --tasks shares runs it, each task this same command with `--answer`
//! and `--share I/N` into a cache of its own (DIR/caches/share-I.sqlite: SQLite's locking is
//! not safe over network file systems); this process waits for the array (`sbatch --wait`),
//! merges the shares' caches into its own and reads the answers from it. The tasks' settings
//! are this command's own flags, and a task refuses a run whose key it would compute
//! differently, so a batch is never answered under other settings.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use super::args::ClusterArgs;
use super::slurm::{
    check_cluster, sbatch, sbatch_quote, script_head, script_path, shell_quote, slurm_dir,
};
use super::CmdError;
use crate::optimise::cycle::map_runs::{lock, BatchJudge, MapBatch, Runner};
use crate::optimise::error::{OptimiseError, RunsError};

/// Flags of the driver that its tasks do not take: the cluster's, the cache's (each task has
/// its own) and the report's (a task writes none). Each takes a value but `--json`.
const DRIVER_ONLY: [&str; 7] = [
    "--slurm",
    "--tasks",
    "--partition",
    "--time",
    "--cpus",
    "--cache",
    "--out",
];

pub(super) struct SlurmRunner {
    dir: String,
    exe: String,
    cwd: String,
    /// The driver's arguments (after the program's name) that its tasks repeat.
    args: Vec<String>,
    name: String,
    tasks: usize,
    cpus: usize,
    cluster_head: String,
    batches: AtomicUsize,
}

impl SlurmRunner {
    /// Checks the cluster flags and paths, creates DIR and its folders.
    pub(super) fn new(dir: &Path, c: &ClusterArgs, name: &str) -> Result<Self, CmdError> {
        check_cluster(c)?;
        let input = |e: std::io::Error, what: &Path| {
            CmdError::Input(format!(
                "--slurm {}: cannot create {}: {e}",
                dir.display(),
                what.display()
            ))
        };
        slurm_dir(dir)?;
        let cwd = std::env::current_dir().map_err(|e| input(e, Path::new(".")))?;
        let exe = std::env::current_exe().map_err(|e| input(e, Path::new("texopt")))?;
        for d in ["logs", "caches", "batches"].map(|d| dir.join(d)) {
            std::fs::create_dir_all(&d).map_err(|e| input(e, &d))?;
        }
        let dir = dir.canonicalize().map_err(|e| input(e, dir))?;
        let args = task_args(std::env::args().skip(1))?;
        let cwd_text = script_path("the working directory", &cwd)?.to_string();
        Ok(SlurmRunner {
            dir: slurm_dir(&dir)?.to_string(),
            exe: script_path("texopt's own path", &exe)?.to_string(),
            cluster_head: script_head(c, &cwd_text),
            cwd: cwd_text,
            args,
            name: name.to_string(),
            tasks: c.tasks.unwrap_or(4),
            cpus: c.cpus.unwrap_or(1),
            batches: AtomicUsize::new(0),
        })
    }

    /// The array script of batch `k` in `tasks` shares.
    fn script(&self, k: usize, tasks: usize) -> String {
        let log = sbatch_quote(&format!(
            "{}/logs/batch-{k}-task-%a.log",
            self.dir.replace('%', "%%")
        ));
        let args: Vec<String> = self.args.iter().map(|a| shell_quote(a)).collect();
        format!(
            "{head}#SBATCH --job-name=texopt-{name}-bands\n#SBATCH --array=1-{tasks}\n#SBATCH --cpus-per-task={cpus}\n#SBATCH --output={log}\n\
# Share I of {tasks} of the band search's batch {k} (its runs in batches/batch-{k}.json), each\n\
# task into its own cache; `texopt cycle … --slurm` waits for them and merges the caches.\n\
set -euo pipefail\n\
texopt={exe}\ndir={dir}\n\
export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-1}}\"\n\
exec \"$texopt\" {args} --answer \"$dir/batches/batch-{k}.json\" --share \"$SLURM_ARRAY_TASK_ID/{tasks}\" --cache \"$dir/caches/share-$SLURM_ARRAY_TASK_ID.sqlite\"\n",
            head = self.cluster_head,
            name = self.name,
            cpus = self.cpus,
            exe = shell_quote(&self.exe),
            dir = shell_quote(&self.dir),
            args = args.join(" "),
        )
    }

    /// Where the scripts run and log.
    pub(super) fn describe(&self) -> String {
        format!(
            "Slurm arrays of {} task(s) × {} CPU(s), scripts and logs in {} (working directory {})",
            self.tasks, self.cpus, self.dir, self.cwd
        )
    }
}

/// The driver's arguments without [`DRIVER_ONLY`]'s flags (as `--flag value` or
/// `--flag=value`) and `--json`; refused: arguments that are not UTF-8.
fn task_args(args: impl Iterator<Item = String>) -> Result<Vec<String>, CmdError> {
    let (mut out, mut skip) = (Vec::new(), false);
    for a in args {
        if std::mem::take(&mut skip) {
            continue;
        }
        if a == "--json" {
            continue;
        }
        if DRIVER_ONLY.contains(&a.as_str()) {
            skip = true;
            continue;
        }
        if DRIVER_ONLY
            .iter()
            .any(|f| a.strip_prefix(f).is_some_and(|r| r.starts_with('=')))
        {
            continue;
        }
        if a.chars().any(char::is_control) {
            return Err(CmdError::Input(format!(
                "argument {a:?}: --slurm writes the arguments into its scripts, which cannot hold control characters"
            )));
        }
        out.push(a);
    }
    Ok(out)
}

impl Runner for SlurmRunner {
    fn run(&self, judge: &dyn BatchJudge, batch: &MapBatch) -> Result<(), OptimiseError> {
        let k = self.batches.fetch_add(1, Ordering::Relaxed) + 1;
        let tasks = self.tasks.min(batch.runs.len()).max(1);
        let dir = Path::new(&self.dir);
        let runs = |why: String| OptimiseError::Runs(RunsError::Elsewhere { batch: k, why });
        let json = serde_json::to_string(batch).expect("plain data");
        let file = dir.join(format!("batches/batch-{k}.json"));
        crate::output::write(&file, json).map_err(|e| runs(e.to_string()))?;
        let script = dir.join(format!("batch-{k}.sbatch"));
        crate::output::write(&script, self.script(k, tasks)).map_err(|e| runs(e.to_string()))?;
        if judge.progress() {
            eprintln!(
                "batch {k}: {} runs in {tasks} Slurm task(s), waiting …",
                batch.runs.len()
            );
        }
        let script = script.to_string_lossy();
        let done = sbatch(&["--wait", &script]);
        // The tasks' finished runs are merged even when the array failed: a rerun then runs
        // only what is left.
        let shares: Vec<PathBuf> = (1..=self.tasks)
            .map(|i| dir.join(format!("caches/share-{i}.sqlite")))
            .filter(|p| p.is_file())
            .collect();
        lock(judge.cache()?)
            .merge(&shares)
            .map_err(|e| runs(format!("merging the tasks' caches: {e}")))?;
        done.map_err(|e| {
            let (CmdError::Input(e) | CmdError::Other(e)) = e;
            runs(format!(
                "{e}; the tasks' logs are {}/logs/batch-{k}-task-*.log",
                self.dir
            ))
        })?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tasks_repeat_the_drivers_flags_but_its_own() {
        let args = [
            "cycle",
            "e.toml",
            "--bands",
            "--slurm",
            "d",
            "--tasks=4",
            "--cache",
            "c.sqlite",
            "--json",
            "--fidelity",
            "draft",
            "--out=r",
            "--time",
            "01:00:00",
        ]
        .map(String::from);
        assert_eq!(
            task_args(args.into_iter()).ok().unwrap(),
            ["cycle", "e.toml", "--bands", "--fidelity", "draft"]
        );
        assert!(task_args(["a\nb".to_string()].into_iter()).is_err());
    }
}
