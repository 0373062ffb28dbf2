//! The `texopt` command line: the only layer that knows flag names. Errors say what was
//! wrong and how to fix it; bad input exits with code 2 and writes nothing.

mod args;
mod bench;
mod cache;
mod cycle;
mod cycle_slurm;
mod optimise;
mod simulate;
mod slurm;
mod snapshots;
mod study;
mod values;

pub use args::{
    ApproachArg, BenchArgs, CacheAction, CacheArgs, Cli, Command, ContactArgs, CycleArgs,
    LimitArgs, OperatingArgs, OptimiseArgs, SimulateArgs, StudyArgs,
};
pub use simulate::case_from_args;

use crate::api::OperatingInputs;
use crate::model::case::{InputError, Waiver};
use crate::model::operating::{Operating, Validity};
use crate::study::cache::{path_from, Cache, CacheError};

pub fn main_with(cli: Cli) -> i32 {
    // A command asked for JSON answers with JSON on stdout even when it fails, so that a
    // script reading it gets an object to test, not an empty line.
    let json = match &cli.command {
        Command::Simulate(a) => a.json,
        Command::Optimise(a) => a.json,
        Command::Cycle(a) => a.json,
        _ => false,
    };
    let (code, message) = match run_command(cli) {
        Ok(code) => return code,
        Err(CmdError::Input(e)) => (2, e),
        Err(CmdError::Other(e)) => (1, e),
    };
    eprintln!("error: {message}");
    if json {
        println!(
            "{}",
            serde_json::json!({ "error": message, "exit_code": code })
        );
    }
    code
}

/// The command's run.
fn run_command(cli: Cli) -> Result<i32, CmdError> {
    match cli.command {
        Command::Simulate(a) => simulate::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::Study(a) => study::run(&a),
        Command::Cache(a) => cache::run(&a),
        Command::Optimise(a) => optimise::run(&a),
        Command::Cycle(a) => cycle::run(&a),
    }
}

/// Why a command failed: its input (exit 2: the user's to fix), or the run (exit 1).
#[derive(Debug, Clone, PartialEq)]
pub enum CmdError {
    Input(String),
    Other(String),
}

/// Why a command run inside another program did not run.
#[derive(Debug, Clone, PartialEq)]
pub enum Embedded {
    /// The command line did not parse (clap's message: what was wrong and the usage).
    Usage(String),
    /// The command failed.
    Failed(CmdError),
}

/// Serialises the commands run inside one process: they share the Ctrl-C stop and the
/// record of the files written.
static EMBEDDED_RUN: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Whether a command runs inside another program, which then owns Ctrl-C.
static HOSTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Runs the command line `argv` (program name first) inside this process, as the Python
/// package does: the same commands, checks and files as the `texopt` program, its lines on
/// stderr and stdout, and no Ctrl-C handler of its own ([`stop_embedded`] stops a study the
/// way Ctrl-C does). Returns the exit code and the files the command wrote; failures typed.
pub fn run_embedded(argv: &[String]) -> Result<(i32, Vec<std::path::PathBuf>), Embedded> {
    use clap::Parser;
    let cli = Cli::try_parse_from(argv).map_err(|e| Embedded::Usage(e.render().to_string()))?;
    let _one = EMBEDDED_RUN.lock().unwrap_or_else(|e| e.into_inner());
    HOSTED.store(true, std::sync::atomic::Ordering::SeqCst);
    STOP.store(false, std::sync::atomic::Ordering::SeqCst);
    let (result, files) = crate::output::recording(|| run_command(cli));
    match result {
        Ok(code) => Ok((code, files)),
        Err(e) => Err(Embedded::Failed(e)),
    }
}

/// Asks the command running in this process to stop as Ctrl-C does: a study starts no new
/// case, and the cases running finish and are stored.
pub fn stop_embedded() {
    STOP.store(true, std::sync::atomic::Ordering::SeqCst);
}

impl From<InputError> for CmdError {
    fn from(e: InputError) -> Self {
        CmdError::Input(input_message(&e, flag))
    }
}

/// The one guard over a report before anything of it is printed or written: every number
/// finite, or marked as an answer where it is not (crate::finite).
pub(super) fn checked<T: serde::Serialize>(report: &T) -> Result<(), CmdError> {
    crate::finite::check(report).map_err(|bad| {
        CmdError::Other(format!(
            "the report's {bad} is not a finite number; nothing printed or written"
        ))
    })
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
        Some(Waiver::MemoryLimit) => ", or raise the limit with --max-memory GIB",
        Some(Waiver::StepLimit) => ", or raise the limit with --max-steps N",
        Some(Waiver::NoContact) => "; --no-contact runs without asperity contact",
        None => "",
    };
    format!("{} = {}: {}{waiver}", to_flag(&e.param), e.value, e.rule)
}

/// Set by Ctrl-C: a running study starts no new case; a second Ctrl-C exits at once (the
/// cache keeps every finished case).
pub(super) static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

pub(super) fn install_ctrl_c() {
    // A host program (the Python package) keeps its own Ctrl-C and stops us through STOP.
    if HOSTED.load(std::sync::atomic::Ordering::SeqCst) {
        return;
    }
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

impl LimitArgs {
    /// The limits these flags set (the defaults where absent).
    pub(super) fn limits(&self) -> Result<crate::time::Limits, CmdError> {
        let mut l = crate::time::Limits::default();
        for (name, v) in [
            ("--max-memory", self.max_memory),
            ("--max-steps", self.max_steps),
        ] {
            if let Some(x) = v.filter(|x| !(x.is_finite() && *x > 0.0)) {
                return Err(CmdError::Input(format!(
                    "{name} = {}: must be a finite number > 0",
                    crate::time::short(x)
                )));
            }
        }
        if let Some(g) = self.max_memory {
            // A limit above what the machine has would let a run abort allocating.
            if let Some(total) = machine_memory_gib().filter(|&t| g > t) {
                return Err(CmdError::Input(format!(
                    "--max-memory = {}: more than this machine's {total:.1} GiB of memory; give at most {total:.1}",
                    crate::time::short(g)
                )));
            }
            l = l.with_memory_gib(g);
        }
        if let Some(n) = self.max_steps {
            // 1e10 steps are weeks of computing at the fastest step; more is a typo.
            if n > 1e10 {
                return Err(CmdError::Input(format!(
                    "--max-steps = {}: at most 1e10 steps (weeks of computing); give a smaller limit",
                    crate::time::short(n)
                )));
            }
            l.steps = n;
        }
        Ok(l)
    }
}

/// The machine's memory in GiB (`MemTotal` of /proc/meminfo), where it can be read.
fn machine_memory_gib() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: f64 = info
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib / (1024.0 * 1024.0))
}

impl OperatingArgs {
    /// Each setting from these flags, else from `other` (a config file's).
    pub(super) fn or(self, other: OperatingArgs) -> OperatingArgs {
        OperatingArgs::from(self.inputs().or(other.inputs()))
    }

    /// The operating point these flags name.
    pub(super) fn inputs(&self) -> OperatingInputs {
        OperatingInputs {
            speed: self.speed,
            load: self.load,
            viscosity: self.viscosity,
            ring_width: self.ring_width,
            ring_mass: self.ring_mass,
            d_oil: self.d_oil,
            roughness: self.roughness,
        }
    }

    /// The operating point and the validity limit these flags set (the paper's where
    /// absent), checked: errors name the setting, the value and the rule.
    pub(super) fn resolve(&self) -> Result<(Operating, Validity), InputError> {
        self.inputs().resolve()
    }
}

impl From<OperatingInputs> for OperatingArgs {
    fn from(o: OperatingInputs) -> Self {
        OperatingArgs {
            speed: o.speed,
            load: o.load,
            viscosity: o.viscosity,
            ring_width: o.ring_width,
            ring_mass: o.ring_mass,
            d_oil: o.d_oil,
            roughness: o.roughness,
        }
    }
}

/// The cache a command stores results in (created if missing, refused if not writable).
pub(super) fn open_cache(flag: Option<&std::path::Path>) -> Result<Cache, CmdError> {
    let path = path_from(flag).map_err(|e| CmdError::Input(e.to_string()))?;
    Cache::open(&path).map_err(cache_error)
}

/// A cache error as a command reports it: a file that is not ours, or cannot be written, is
/// the user's to fix (exit 2).
pub(super) fn cache_error(e: CacheError) -> CmdError {
    match e {
        CacheError::Foreign { .. } | CacheError::ForeignLog { .. } | CacheError::Io { .. } => {
            CmdError::Input(e.to_string())
        }
        other => CmdError::Other(other.to_string()),
    }
}

/// Whether `dir` is, or could be made as, a directory we can write in, without making it
/// (bad input must leave no trace): its nearest existing ancestor must be a directory in
/// which a file can be created (a probe file is made and removed there).
pub(super) fn directory_can_be_made(dir: &std::path::Path) -> Result<(), String> {
    let mut p = dir;
    loop {
        if p.exists() {
            return if p.is_dir() {
                crate::output::check_writable(&p.join(".texopt-probe")).map_err(|e| e.to_string())
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
