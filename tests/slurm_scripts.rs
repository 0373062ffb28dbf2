//! The scripts of `texopt study FILE --slurm DIR`, without a cluster: bash runs them as
//! Slurm would (one array task at a time, then the merge), and a stand-in `sbatch` records
//! what the printed commands and `--submit` hand it. Paths hold spaces, quotes, `$`,
//! command substitutions, backquotes, `#` and `%`; none of it may run or split a word.

mod common;

use common::{scratch, texopt};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Would run if a path reached a shell unquoted.
const PAYLOAD: &str = "a b 'q' \"dq\" $(touch PWNED) `touch BQ` $HOME #h %j %a";

const TINY: &str = "[study]\nname = \"tiny\"\nfidelity = \"draft\"\nuntextured = true\n\
[parameters]\nR = [3.2, 5]\nl1 = [0.01, 0.03]\nper = 0.06\ndepth = [5, 10]\n\
[report]\ndir = \"rep\"\n";

/// A working directory and a study file in it, both named with the payload.
fn setup(test: &str) -> (PathBuf, PathBuf, PathBuf) {
    let root = scratch(test);
    let cwd = root.join(format!("cwd {PAYLOAD}"));
    std::fs::create_dir_all(&cwd).unwrap();
    let file = cwd.join(format!("study {PAYLOAD}.toml"));
    std::fs::write(&file, TINY).unwrap();
    (root, cwd, file)
}

/// $PATH with `bin` first.
fn path_with(bin: &Path) -> std::ffi::OsString {
    let old = std::env::var_os("PATH").unwrap_or_default();
    let mut dirs = vec![bin.to_path_buf()];
    dirs.extend(std::env::split_paths(&old));
    std::env::join_paths(dirs).unwrap()
}

/// texopt in `cwd`, with `path` first on $PATH if given.
fn run_in(cwd: &Path, path: Option<&Path>, args: &[&str]) -> (i32, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_texopt"));
    cmd.args(args).current_dir(cwd);
    if let Some(p) = path {
        cmd.env("PATH", path_with(p));
    }
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// bash running `script` in `cwd` (where `#SBATCH --chdir` would start it) with `env`.
fn bash(cwd: &Path, script: &Path, env: &[(&str, &str)]) {
    let out = Command::new("bash")
        .arg(script)
        .current_dir(cwd)
        .envs(env.iter().copied())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "bash {}: {}\n{}",
        script.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every file under `root` whose name the payload's commands would create.
fn injected(root: &Path) -> Vec<PathBuf> {
    let mut found = vec![];
    let mut todo = vec![root.to_path_buf(), std::env::current_dir().unwrap()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if matches!(e.file_name().to_str(), Some("PWNED" | "BQ")) {
                found.push(p.clone());
            }
            if p.is_dir() && p.starts_with(root) {
                todo.push(p);
            }
        }
    }
    found
}

/// The arguments of an `#SBATCH` line as sbatch splits them: unquoted whitespace ends a
/// word, `'…'` and `"…"` quote, a backslash takes the next character as it is, an unquoted
/// `#` ends the line.
fn sbatch_words(line: &str) -> Vec<String> {
    let (mut words, mut w) = (vec![], String::new());
    let (mut quote, mut escape) = (None, false);
    for c in line.chars() {
        if quote.is_none() && c.is_whitespace() {
            escape = false;
            if !w.is_empty() {
                words.push(std::mem::take(&mut w));
            }
            continue;
        }
        if escape {
            escape = false;
        } else if c == '\\' {
            escape = true;
            continue;
        } else if let Some(q) = quote {
            if c == q {
                quote = None;
                continue;
            }
        } else if c == '"' || c == '\'' {
            quote = Some(c);
            continue;
        } else if c == '#' {
            break;
        }
        w.push(c);
    }
    assert!(quote.is_none(), "unmatched quote in #SBATCH{line}");
    if !w.is_empty() {
        words.push(w);
    }
    words
}

/// The value of `--NAME=` among a script's `#SBATCH` lines.
fn directive(script: &str, name: &str) -> String {
    let words: Vec<String> = script
        .lines()
        .filter_map(|l| l.strip_prefix("#SBATCH"))
        .flat_map(sbatch_words)
        .collect();
    let prefix = format!("--{name}=");
    let found: Vec<&String> = words.iter().filter(|w| w.starts_with(&prefix)).collect();
    assert_eq!(found.len(), 1, "one --{name} in {words:?}");
    found[0][prefix.len()..].to_string()
}

#[test]
fn the_scripts_run_on_paths_with_spaces_quotes_dollars_and_backquotes() {
    let (root, cwd, file) = setup("slurm-quoting");
    let dir = format!("run {PAYLOAD}");
    let (code, out, err) = run_in(
        &cwd,
        None,
        &[
            "study",
            file.to_str().unwrap(),
            "--slurm",
            &dir,
            "--tasks",
            "2",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let run = cwd.canonicalize().unwrap().join(&dir);
    let (array, merge) = (run.join("array.sbatch"), run.join("merge.sbatch"));

    // What sbatch reads: the working directory and the logs' paths, `%` kept for Slurm's
    // patterns only where texopt put one.
    let text = std::fs::read_to_string(&array).unwrap();
    assert_eq!(
        directive(&text, "chdir"),
        cwd.canonicalize().unwrap().to_str().unwrap()
    );
    let logs = run.join("logs").to_str().unwrap().replace('%', "%%");
    assert_eq!(directive(&text, "output"), format!("{logs}/task-%a.log"));
    let text = std::fs::read_to_string(&merge).unwrap();
    assert_eq!(directive(&text, "output"), format!("{logs}/merge.log"));

    // The array's tasks one after another, then the merge, as Slurm would run them.
    for task in ["1", "2"] {
        bash(
            &cwd,
            &array,
            &[("SLURM_ARRAY_TASK_ID", task), ("SLURM_CPUS_PER_TASK", "1")],
        );
    }
    bash(&cwd, &merge, &[]);
    let merged = run.join("merged.sqlite");
    let (code, export, err) = texopt(&["cache", "export", "--cache", merged.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(export.lines().count(), 10, "every case in the merged cache");
    assert!(cwd.join("rep/tiny.csv").is_file(), "the report is written");

    // The printed commands, run by bash with a stand-in sbatch: each gets the script's path
    // as one word.
    let bin = root.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let calls = root.join("calls");
    let fake = bin.join("sbatch");
    std::fs::write(
        &fake,
        format!(
            "#!/bin/bash\nprintf '%s\\n' \"$@\" '--' >> '{}'\necho 42\n",
            calls.display()
        ),
    )
    .unwrap();
    Command::new("chmod").arg("+x").arg(&fake).status().unwrap();
    let commands: String = out
        .lines()
        .filter(|l| l.trim_start().starts_with("id=") || l.trim_start().starts_with("sbatch "))
        .map(|l| format!("{}\n", l.trim()))
        .collect();
    let status = Command::new("bash")
        .args(["-c", &commands])
        .current_dir(&cwd)
        .env("PATH", path_with(&bin))
        .output()
        .unwrap()
        .status;
    assert!(status.success(), "the printed commands:\n{commands}");
    let (a, m) = (array.to_str().unwrap(), merge.to_str().unwrap());
    let expect = format!("--parsable\n{a}\n--\n--dependency=afterok:42\n{m}\n--\n");
    assert_eq!(std::fs::read_to_string(&calls).unwrap(), expect);

    // --submit hands sbatch the same paths.
    std::fs::remove_file(&calls).unwrap();
    let (code, _, err) = run_in(
        &cwd,
        Some(&bin),
        &[
            "study",
            file.to_str().unwrap(),
            "--slurm",
            &dir,
            "--tasks",
            "2",
            "--submit",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let expect = format!("--parsable\n{a}\n--\n--parsable\n--dependency=afterok:42\n{m}\n--\n");
    assert_eq!(std::fs::read_to_string(&calls).unwrap(), expect);

    assert_eq!(
        injected(&root),
        Vec::<PathBuf>::new(),
        "a path ran as a command"
    );
    let _ = std::fs::remove_dir_all(root);
}

#[test]
fn a_path_the_scripts_cannot_hold_is_refused_before_anything_is_written() {
    let (root, cwd, file) = setup("slurm-refused");
    let f = file.to_str().unwrap();
    let refused = |cwd: &Path, args: &[&str], needle: &str| {
        let (code, out, err) = run_in(cwd, None, args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    };
    for dir in ["new\nline", "tab\there", "cr\rhere", "del\u{7f}here"] {
        refused(&cwd, &["study", f, "--slurm", dir], "--slurm");
        assert!(!cwd.join(dir).exists(), "{dir:?} was created");
    }
    refused(&cwd, &["study", f, "--slurm", "back\\slash"], "backslash");
    {
        use std::os::unix::ffi::OsStrExt;
        let dir = std::ffi::OsStr::from_bytes(b"not\xffutf8");
        let out = Command::new(env!("CARGO_BIN_EXE_texopt"))
            .args(["study", f, "--slurm"])
            .arg(dir)
            .current_dir(&cwd)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("--slurm") && err.contains("UTF-8"), "{err}");
        assert!(!cwd.join(dir).exists());
    }
    assert!(!cwd.join("back\\slash").exists());
    // A cache of one's own has no place beside the tasks' caches: refused, not ignored.
    let (code, _, err) = run_in(
        &cwd,
        None,
        &["study", f, "--slurm", "sl", "--cache", "c.sqlite"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--cache"), "{err}");
    assert!(!cwd.join("sl").exists() && !cwd.join("c.sqlite").exists());

    // The study file's path, and the working directory a relative DIR is under.
    let odd = cwd.join("study\nfile.toml");
    std::fs::copy(&file, &odd).unwrap();
    refused(
        &cwd,
        &["study", odd.to_str().unwrap(), "--slurm", "run"],
        "study file",
    );
    let odd_cwd = root.join("work\ndir");
    std::fs::create_dir_all(&odd_cwd).unwrap();
    refused(
        &odd_cwd,
        &["study", f, "--slurm", "run"],
        "working directory",
    );
    let slashed = root.join("back\\slash");
    std::fs::create_dir_all(&slashed).unwrap();
    refused(&slashed, &["study", f, "--slurm", "run"], "backslash");
    for d in [&cwd, &odd_cwd, &slashed] {
        assert!(
            !d.join("run").exists(),
            "{} got a run directory",
            d.display()
        );
    }
    let _ = std::fs::remove_dir_all(root);
}
