//! The `texopt` command line: the only layer that knows flag names. Errors say what was
//! wrong and how to fix it; bad input exits with code 2 and writes nothing.

mod args;
mod bench;
mod cache;
mod optimise;
mod simulate;
mod study;

pub use args::{
    ApproachArg, BenchArgs, CacheAction, CacheArgs, Cli, Command, OptimiseArgs, SimulateArgs,
    StudyArgs,
};
pub use simulate::case_from_args;

use crate::model::case::{InputError, Waiver};
use crate::study::cache::{path_from, Cache, CacheError};

pub fn main_with(cli: Cli) -> i32 {
    let result = match cli.command {
        Command::Simulate(a) => simulate::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::Study(a) => study::run(&a),
        Command::Cache(a) => cache::run(&a),
        Command::Optimise(a) => optimise::run(&a),
    };
    match result {
        Ok(code) => code,
        Err(CmdError::Input(e)) => {
            eprintln!("error: {e}");
            2
        }
        Err(CmdError::Other(e)) => {
            eprintln!("error: {e}");
            1
        }
    }
}

pub(super) enum CmdError {
    Input(String),
    Other(String),
}

impl From<InputError> for CmdError {
    fn from(e: InputError) -> Self {
        CmdError::Input(input_message(&e, flag))
    }
}

/// The flag of a case's or numerics' field: `--` and its name with '-' for '_' (`R`: `--R`).
pub(super) fn flag(param: &str) -> String {
    format!("--{}", param.replace('_', "-"))
}

/// An input error in the words of the command line: the flag (`to_flag` of the field), the
/// value, the rule, and how to waive a rule that may be waived.
pub(super) fn input_message(e: &InputError, to_flag: impl Fn(&str) -> String) -> String {
    let waiver = match e.waiver {
        Some(Waiver::ThickPockets) => "; pass --allow-thick-pockets to run anyway",
        None => "",
    };
    format!("{} = {}: {}{waiver}", to_flag(&e.param), e.value, e.rule)
}

/// Set by Ctrl-C: a running study starts no new case; a second Ctrl-C exits at once (the
/// cache keeps every finished case).
pub(super) static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

pub(super) fn install_ctrl_c() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if STOP.swap(true, std::sync::atomic::Ordering::SeqCst) {
                eprintln!("\nstopped; finished cases are in the cache");
                std::process::exit(130);
            }
            eprintln!(
                "\nstopping: no new case starts; the cases running finish and are stored (Ctrl-C again to quit now)"
            );
        });
    });
}

pub(super) fn open_cache(flag: Option<&std::path::Path>) -> Result<Cache, CmdError> {
    let path = path_from(flag);
    Cache::open(&path).map_err(|e| match e {
        CacheError::Foreign { .. } => CmdError::Input(e.to_string()),
        other => CmdError::Other(other.to_string()),
    })
}

/// Whether `dir` is, or could be made as, a directory, without making anything (bad input/// must leave no trace): its nearest existing ancestor must be a directory. (Permissions are
/// left to the write itself.)
pub(super) fn directory_can_be_made(dir: &std::path::Path) -> Result<(), String> {
    let mut p = dir;
    loop {
        if p.exists() {
            return if p.is_dir() {
                Ok(())
            } else {
                Err(format!("{} is not a directory", p.display()))
            };
        }
        match p.parent() {
            Some(q) if !q.as_os_str().is_empty() => p = q,
            _ => return Ok(()),
        }
    }
}
