//! The `texopt` command line. Errors say what was wrong and how to fix it; bad input exits
//! with code 2 and writes nothing.

use clap::{Args, Parser, Subcommand};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

use crate::case::{CaseSpec, Coupling, Fidelity, InputError, Numerics, Start, Texture};
use crate::film::{Cavitation, Method};
use crate::run::{simulate, Outcome, Progress, RunResult, SeriesRow};

#[derive(Parser, Debug)]
#[command(
    name = "texopt",
    version,
    about = "Design liner textures for the piston-ring/liner contact (transient mass-conserving lubrication with ring dynamics)"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Simulate one ring/liner case to its periodic regime and report friction and clearance.
    Simulate(SimulateArgs),
    /// Time the fixed benchmark cases (Case I, Case III, R = 51.2, untextured) and write JSON.
    Bench(BenchArgs),
    /// Run every case of a study file (TOML, see studies/) through the evaluation cache, in
    /// parallel, and write its report (CSV, figures, tables) under its report directory.
    Study(StudyArgs),
    /// Inspect or manage the evaluation cache.
    Cache(CacheArgs),
    /// Find the pocket textures that lower friction and keep the film thick for one ring:
    /// particle-swarm searches through the cache, friction/clearance Pareto front, report.
    Optimise(OptimiseArgs),
}

/// Units as in `simulate`: lengths in cm, depth in µm; ranges are LO..HI. Settings come from
/// the flags, else from `--config FILE`, else from the defaults shown.
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct OptimiseArgs {
    /// Ring face radius R in cm ("inf" for a flat ring).
    #[arg(long = "R", value_name = "CM", value_parser = parse_radius)]
    pub r: f64,
    /// TOML file with any of the settings below (keys as the flags, with '_' for '-';
    /// ranges as [LO, HI]); flags given on the command line win.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Range of the pocket semiaxis along sliding (cm) [default: 0.0025..0.03].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range)]
    pub l1: Option<(f64, f64)>,
    /// Range of the pocket semiaxis across sliding (cm) [default: 0.0025..0.03].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range)]
    pub l2: Option<(f64, f64)>,
    /// Range of the texture period along sliding (cm) [default: 0.005..0.06].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range)]
    pub per: Option<(f64, f64)>,
    /// Make the period across sliding a free variable in this range (cm) [default: width = per].
    #[arg(long = "free-width", value_name = "LO..HI", value_parser = parse_range)]
    pub free_width: Option<(f64, f64)>,
    /// Range of the pocket depth (µm) [default: 2..30].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range)]
    pub depth: Option<(f64, f64)>,
    /// Least wall thickness between neighbouring pockets (µm): per − 2·l1 and width − 2·l2
    /// [default: 10].
    #[arg(long = "w-min", value_name = "UM")]
    pub w_min: Option<f64>,
    /// Largest textured area fraction π·l1·l2/(per·width).
    #[arg(long, value_name = "FRACTION")]
    pub max_area: Option<f64>,
    /// Largest depth-to-diameter ratio of a pocket.
    #[arg(long, value_name = "RATIO")]
    pub max_depth_ratio: Option<f64>,
    /// Lift the thin-film rule 10⁴·l ≥ 5·depth.
    #[arg(long)]
    pub allow_thick_pockets: bool,
    /// Fidelity of the reported designs (each is evaluated at it) [default: fast].
    #[arg(long, value_enum)]
    pub fidelity: Option<Fidelity>,
    /// Fidelity of the searches (screening) [default: draft].
    #[arg(long, value_enum)]
    pub search_fidelity: Option<Fidelity>,
    /// Override the mesh of both fidelities (N2 is still raised to resolve small pockets).
    #[arg(long, value_name = "N1xN2", value_parser = parse_mesh)]
    pub mesh: Option<(usize, usize)>,
    /// Override the time step of both fidelities (ms).
    #[arg(long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Particles per swarm [default: 8].
    #[arg(long)]
    pub particles: Option<usize>,
    /// Swarm iterations per search (each evaluates every particle) [default: 3].
    #[arg(long)]
    pub iterations: Option<u64>,
    /// Weights on friction of the balanced searches (comma-separated, each in (0, 1))
    /// [default: 0.5].
    #[arg(long, value_delimiter = ',')]
    pub balanced: Option<Vec<f64>>,
    /// Random seed of the swarms (the same seed repeats the same designs, all from the
    /// cache) [default: 1].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads [default: all cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Cache file [default: $TEXOPT_CACHE or .texopt/cache.sqlite].
    #[arg(long, value_name = "FILE")]
    pub cache: Option<PathBuf>,
    /// Directory of the report files (optimise_R<R>.json/.csv/_front.png/_z_t.png/_f_t.png)
    /// [default: results].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the report as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// The settings of `optimise` a `--config` file may hold (same names as the flags).
#[derive(serde::Deserialize, Default, Debug)]
#[serde(deny_unknown_fields)]
struct OptimiseFile {
    l1: Option<(f64, f64)>,
    l2: Option<(f64, f64)>,
    per: Option<(f64, f64)>,
    free_width: Option<(f64, f64)>,
    depth: Option<(f64, f64)>,
    w_min: Option<f64>,
    max_area: Option<f64>,
    max_depth_ratio: Option<f64>,
    allow_thick_pockets: Option<bool>,
    fidelity: Option<Fidelity>,
    search_fidelity: Option<Fidelity>,
    particles: Option<usize>,
    iterations: Option<u64>,
    balanced: Option<Vec<f64>>,
    seed: Option<u64>,
    out: Option<PathBuf>,
}

fn parse_range(s: &str) -> Result<(f64, f64), String> {
    let err = || format!("expected a range LO..HI of numbers, e.g. 0.0025..0.03, got {s:?}");
    let (a, b) = s.split_once("..").ok_or_else(err)?;
    let lo = a.trim().parse::<f64>().map_err(|_| err())?;
    let hi = b.trim().parse::<f64>().map_err(|_| err())?;
    Ok((lo, hi))
}

#[derive(Args, Debug)]
pub struct StudyArgs {
    /// The study file (TOML), e.g. studies/paper.toml.
    pub file: PathBuf,
    /// Worker threads [default: all cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Cache file [default: $TEXOPT_CACHE or .texopt/cache.sqlite].
    #[arg(long, value_name = "FILE")]
    pub cache: Option<PathBuf>,
    /// Simulate again the cases the cache holds as failed.
    #[arg(long)]
    pub retry_failed: bool,
    /// Only expand the study and print what it would run (no simulation, nothing written).
    #[arg(long)]
    pub dry_run: bool,
    /// Do not write the report (CSV, figures, tables).
    #[arg(long)]
    pub no_report: bool,
    /// Simulate nothing: report what the cache already holds (e.g. while the study runs
    /// elsewhere); missing cases appear as "not run".
    #[arg(long)]
    pub cached_only: bool,
}

#[derive(Args, Debug)]
pub struct CacheArgs {
    #[command(subcommand)]
    pub action: CacheAction,
    /// Cache file [default: $TEXOPT_CACHE or .texopt/cache.sqlite].
    #[arg(long, value_name = "FILE", global = true)]
    pub cache: Option<PathBuf>,
}

#[derive(Subcommand, Debug)]
pub enum CacheAction {
    /// Counts of stored evaluations, compute time they hold, file size, integrity.
    Stats,
    /// Every entry as one JSON object per line (inputs, outcomes or failure, metadata).
    Export {
        /// Write to this file instead of stdout.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Delete stored evaluations.
    Clear {
        /// Only the failures (so that they are retried).
        #[arg(long)]
        failed: bool,
    },
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Fidelity tier of every case.
    #[arg(long, value_enum, default_value_t = Fidelity::Paper)]
    pub fidelity: Fidelity,
    /// Only the named cases (repeatable): case-I, case-III, conformal-R51.2, untextured-R0.8.
    #[arg(long = "case", value_name = "NAME")]
    pub cases: Vec<String>,
    /// Film linear solver.
    #[arg(long, value_enum, default_value_t = Method::Direct)]
    pub solver: Method,
    /// Initial state of every case: the paper's (the speed targets are stated from it) or
    /// the untextured equilibrium.
    #[arg(long, value_enum, default_value_t = Start::Paper)]
    pub start: Start,
    /// Coarse approach to the periodic regime: N2 of the mesh the ring's transient runs on
    /// before the tier's mesh takes over, or `off` [default: the tier's: 8 for paper and fine]
    #[arg(long = "approach-n2", value_name = "N2|off", value_parser = parse_approach)]
    pub approach_n2: Option<ApproachN2>,
    /// Runs of each case: its row reports the shortest wall time and lists all (this VM's
    /// timings vary by ±20 % from run to run; the outcomes must not vary at all).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub repeat: usize,
    /// Where to write the results (JSON) [default: results/bench.json, or
    /// results/bench-<what differs>.json for a partial or variant run]
    ///
    /// results/bench.json is the benchmark itself: every case, `paper`, the direct solver,
    /// the paper's start, the tier's approach. Any other run goes to
    /// results/bench-<what differs>.json (git-ignored, e.g. bench-fast-case-III.json), so
    /// that it never replaces the committed benchmark.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

impl BenchArgs {
    /// The file the results go to: `--out`, else the default above.
    fn out_path(&self) -> PathBuf {
        if let Some(out) = &self.out {
            return out.clone();
        }
        let mut tags = Vec::new();
        if self.fidelity != Fidelity::Paper {
            tags.push(self.fidelity.name().to_string());
        }
        if self.solver != Method::Direct {
            tags.push(self.solver.name().to_string());
        }
        if self.start == Start::Equilibrium {
            tags.push("from-equilibrium".into());
        }
        if let Some(ApproachN2(n2)) = self.approach_n2 {
            tags.push(n2.map_or("approach-off".into(), |n| format!("approach-{n}")));
        }
        tags.extend(self.cases.iter().cloned());
        let name = match tags.is_empty() {
            true => "bench.json".to_string(),
            false => format!("bench-{}.json", tags.join("-")),
        };
        PathBuf::from("results").join(name)
    }
}

/// Units: lengths along the liner in cm, gaps and depths in µm, time in ms (L/U), friction
/// coefficients per eq. (11) of the paper (the paper prints them divided by 10).
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct SimulateArgs {
    /// Ring face radius R in cm ("inf" for a flat ring); must exceed 0.04 (half the ring width).
    #[arg(long = "R", value_name = "CM", allow_hyphen_values = true, value_parser = parse_radius)]
    pub r: f64,
    /// Pocket semiaxis along the sliding direction (cm).
    #[arg(long, value_name = "CM", allow_hyphen_values = true)]
    pub l1: Option<f64>,
    /// Pocket semiaxis across the sliding direction (cm) [default: l1].
    #[arg(long, value_name = "CM", allow_hyphen_values = true)]
    pub l2: Option<f64>,
    /// Texture period along the sliding direction (cm).
    #[arg(long, value_name = "CM", allow_hyphen_values = true)]
    pub per: Option<f64>,
    /// Texture period across the sliding direction (cm) [default: per].
    #[arg(long, value_name = "CM", allow_hyphen_values = true)]
    pub width: Option<f64>,
    /// Pocket depth (µm); absent or 0: untextured liner (solved as a steady 1D problem).
    #[arg(long, value_name = "UM", allow_hyphen_values = true)]
    pub depth: Option<f64>,
    /// x1 position of a pocket centre at t = 0 (cm): the texture's initial phase.
    #[arg(
        long,
        value_name = "CM",
        allow_hyphen_values = true,
        default_value_t = 0.0
    )]
    pub phase: f64,
    /// Fidelity tier: draft (256x8, dt 8e-4), fast (512x8, 4e-4), paper (512x32, 4e-4) or
    /// fine (1024x16, 2e-4). --mesh and --dt override its parts.
    #[arg(long, value_enum, default_value_t = Fidelity::Paper)]
    pub fidelity: Fidelity,
    /// Mesh N1xN2: cells along x1 over 0.2 cm and along x2 over half a texture cell
    /// [default: from --fidelity, N2 raised where a pocket would span fewer than 4 cells
    /// across (2 at draft), as in studies].
    #[arg(long, value_name = "N1xN2", value_parser = parse_mesh)]
    pub mesh: Option<(usize, usize)>,
    /// Largest time step (ms); the step used divides the texture period exactly
    /// [default: from --fidelity].
    #[arg(long, value_name = "DT", allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Shear threshold θ_s of the Couette friction switch.
    #[arg(
        long = "theta-s",
        value_name = "THETA",
        allow_hyphen_values = true,
        default_value_t = 0.95
    )]
    pub theta_s: f64,
    /// Inlet oil film thickness (µm); 20 is fully flooded.
    #[arg(
        long = "d-oil",
        value_name = "UM",
        allow_hyphen_values = true,
        default_value_t = 20.0
    )]
    pub d_oil: f64,
    /// Ring mass per unit width (units of 2.4e7 kg/m; the paper's compression ring: 2e-9).
    #[arg(long, value_name = "M", default_value_t = 2.0e-9)]
    pub mass: f64,
    /// Relative tolerance of the periodic-regime test (estimated distance of the period-mean
    /// friction and Z from their periodic limits) [default: the tier's: 1e-4 for draft and
    /// fast, 1e-5 for paper and fine, as studies use them]
    #[arg(long = "periodic-tol", value_name = "TOL", allow_hyphen_values = true)]
    pub periodic_tol: Option<f64>,
    /// Give up after this much simulated time (ms) and report converged = false.
    #[arg(
        long = "t-max",
        value_name = "T",
        allow_hyphen_values = true,
        default_value_t = 30.0
    )]
    pub t_max: f64,
    /// Film solver: direct (band LU, default), multigrid (experimental) or gauss-seidel (contrast only: plain sweeps, fail on fine meshes).
    #[arg(long, value_enum, default_value_t = Method::Direct)]
    pub solver: Method,
    /// Film solve tolerance (multigrid): largest nodal mass residual relative to the Couette
    /// flux through the thinnest film under the ring.
    #[arg(
        long = "solve-tol",
        value_name = "TOL",
        allow_hyphen_values = true,
        default_value_t = 1e-8
    )]
    pub solve_tol: f64,
    /// Most multigrid V-cycles (GMRES iterations) per linear solve of the film iteration.
    #[arg(long, value_name = "N", default_value_t = 8)]
    pub cycles: usize,
    /// Initial state of the transient: equilibrium (untextured force balance, default) or
    /// paper (Z = 2.5 µm at rest, model.md §4). The periodic answer does not depend on it.
    #[arg(long, value_enum, default_value_t = Start::Equilibrium)]
    pub start: Start,
    /// Do not jump the state along a dominant slow mode (simulate every period of the approach).
    #[arg(long = "no-extrapolate")]
    pub no_extrapolate: bool,
    /// Coarse approach to the periodic regime: run the ring's transient on a mesh of N2 cells
    /// along x2 (same N1 and dt), then carry the state over to the full mesh and run on to
    /// its own periodic regime (the answer is the full mesh's); `off` to run every step on
    /// the full mesh. Only meshes with more x2 cells use it. [default: the tier's: 8 for
    /// paper and fine, off for draft and fast]
    #[arg(long = "approach-n2", value_name = "N2|off", value_parser = parse_approach)]
    pub approach_n2: Option<ApproachN2>,
    /// Ring coupling: implicit (Newmark inside the film iteration, default) or explicit
    /// (for stability studies: it fails at the paper's dt, model.md §4).
    #[arg(long, value_enum, default_value_t = Coupling::Implicit)]
    pub coupling: Coupling,
    /// Cavitation model: elrod-adams (mass-conserving, default) or reynolds-cutoff (for
    /// contrast only: it does not conserve mass, which the run detects and reports).
    #[arg(long, value_enum, default_value_t = Cavitation::ElrodAdams)]
    pub cavitation: Cavitation,
    /// Accept pockets that break thin-film validity (10⁴·l < 5·depth).
    #[arg(long = "allow-thick-pockets")]
    pub allow_thick_pockets: bool,
    /// Solve an untextured liner with the 2D transient too (default: steady 1D force balance).
    #[arg(long)]
    pub transient: bool,
    /// Print one JSON object (inputs and outcomes) instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Write the time series (t, Z, W_h, f and its three terms per step) as CSV to FILE.
    #[arg(long, value_name = "FILE")]
    pub series: Option<PathBuf>,
    /// When stderr is not a terminal (a log, a batch job) or with --json: print the progress
    /// line (period, t, f̄, Z̄, estimated periodic error) at the end of a period at most this
    /// often, in seconds (0: every period). On a terminal without --json the line updates
    /// in place at every period.
    #[arg(long = "progress-every", value_name = "S", default_value_t = 10.0, value_parser = parse_seconds)]
    pub progress_every: f64,
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!(
            "expected a number of seconds ≥ 0 (e.g. 10), got {s:?}"
        )),
    }
}

fn parse_radius(s: &str) -> Result<f64, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("inf") || t.eq_ignore_ascii_case("infinity") {
        return Ok(f64::INFINITY);
    }
    t.parse::<f64>()
        .map_err(|_| format!("expected a radius in cm (e.g. 0.8) or \"inf\", got {s:?}"))
}

/// `--approach-n2`: a cell count, or `off`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApproachN2(pub Option<usize>);

fn parse_approach(s: &str) -> Result<ApproachN2, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("off") {
        return Ok(ApproachN2(None));
    }
    match t.parse::<usize>() {
        Ok(n) if n > 0 => Ok(ApproachN2(Some(n))),
        _ => Err(format!(
            "expected a number of x2 cells ≥ 1 (e.g. 8) or \"off\", got {s:?}"
        )),
    }
}

fn parse_mesh(s: &str) -> Result<(usize, usize), String> {
    let err = || format!("expected N1xN2 with whole numbers, e.g. 512x32, got {s:?}");
    let (a, b) = s.split_once(['x', 'X']).ok_or_else(err)?;
    let n1 = a.trim().parse::<usize>().map_err(|_| err())?;
    let n2 = b.trim().parse::<usize>().map_err(|_| err())?;
    Ok((n1, n2))
}

/// Exit codes: 0 done, 1 the solve failed or did not reach the periodic regime, 2 bad input.
pub fn main_with(cli: Cli) -> i32 {
    let result = match cli.command {
        Command::Simulate(a) => simulate_cmd(&a),
        Command::Bench(a) => bench_cmd(&a),
        Command::Study(a) => study_cmd(&a),
        Command::Cache(a) => cache_cmd(&a),
        Command::Optimise(a) => optimise_cmd(&a),
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

fn bench_cmd(a: &BenchArgs) -> Result<i32, CmdError> {
    let all = crate::bench::cases();
    for name in &a.cases {
        if !all.iter().any(|c| c.name == name) {
            let names: Vec<_> = all.iter().map(|c| c.name).collect();
            return Err(CmdError::Input(format!(
                "--case {name}: no such benchmark case; choose from {}",
                names.join(", ")
            )));
        }
    }
    if a.repeat == 0 {
        return Err(CmdError::Input(
            "--repeat 0: each case must run at least once; give 1 or more".into(),
        ));
    }
    let out = a.out_path();
    let dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    if !dir.is_dir() {
        return Err(CmdError::Input(format!(
            "--out {}: the directory {} does not exist; create it or choose another path",
            out.display(),
            dir.display()
        )));
    }
    let fidelity = a.fidelity;
    let tier = fidelity.numerics();
    let num = Numerics {
        solver: a.solver,
        start: a.start,
        approach_n2: a.approach_n2.map_or(tier.approach_n2, |x| x.0),
        ..tier
    };
    let mut rows = Vec::new();
    let mut failed = 0;
    for c in all
        .iter()
        .filter(|c| a.cases.is_empty() || a.cases.iter().any(|n| n == c.name))
    {
        eprintln!("running {} ({}) …", c.name, c.case.label());
        match crate::bench::run_case(c, fidelity, &num, a.repeat) {
            Ok(row) => {
                println!("{}", row.line());
                rows.push(row);
            }
            Err(e) => {
                failed += 1;
                println!("{:16} FAILED: {e}", c.name);
            }
        }
    }
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let report = serde_json::json!({
        "texopt_version": env!("CARGO_PKG_VERSION"),
        "unix_time": secs,
        "threads_available": std::thread::available_parallelism().map_or(1, |n| n.get()),
        "threads_used": 1,
        "repeat": a.repeat,
        "fidelity": fidelity.name(),
        "numerics": num,
        "cases": rows,
    });
    std::fs::write(
        &out,
        serde_json::to_string_pretty(&report).unwrap_or_default(),
    )
    .map_err(|e| CmdError::Other(format!("could not write --out {}: {e}", out.display())))?;
    eprintln!("wrote {}", out.display());
    Ok(if failed > 0 { 1 } else { 0 })
}

/// Set by Ctrl-C: a running study starts no new case; a second Ctrl-C exits at once (the
/// cache keeps every finished case).
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn install_ctrl_c() {
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

fn open_cache(flag: Option<&std::path::Path>) -> Result<crate::cache::Cache, CmdError> {
    let path = crate::cache::path_from(flag);
    crate::cache::Cache::open(&path).map_err(|e| match e {
        crate::cache::CacheError::Foreign { .. } => CmdError::Input(e.to_string()),
        other => CmdError::Other(other.to_string()),
    })
}

fn study_cmd(a: &StudyArgs) -> Result<i32, CmdError> {
    let study = crate::study::load(&a.file).map_err(|e| CmdError::Input(e.to_string()))?;
    if a.jobs == Some(0) {
        return Err(CmdError::Input(
            "--jobs 0: need at least one worker thread".into(),
        ));
    }
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    eprintln!(
        "study {}: {} cases at fidelity {} ({} invalid combinations skipped)",
        study.name,
        study.jobs.len(),
        study.fidelity.name(),
        study.skipped_total()
    );
    for (rule, n) in &study.skipped {
        eprintln!("  skipped {n} × {rule}");
    }
    if a.dry_run {
        for j in &study.jobs {
            println!(
                "{}  [{}x{}, dt {}]",
                j.case.label(),
                j.numerics.n1,
                j.numerics.n2,
                j.numerics.dt
            );
        }
        return Ok(0);
    }
    // A report directory that cannot be made stops the study now, not after its simulations.
    if !a.no_report {
        let dir = std::path::Path::new(&study.report.dir);
        directory_can_be_made(dir).map_err(|why| {
            CmdError::Input(format!(
                "{}: the report directory {} cannot be made: {why}; change [report] dir, or run with --no-report",
                a.file.display(),
                dir.display()
            ))
        })?;
    }
    let cache = open_cache(a.cache.as_deref())?;
    eprintln!("cache {}", cache.path().display());
    install_ctrl_c();
    let cache = std::sync::Mutex::new(cache);
    let opt = crate::sweep::Options {
        jobs,
        retry_failed: a.retry_failed,
        progress: true,
    };
    let stop_now = std::sync::atomic::AtomicBool::new(true);
    let stop = if a.cached_only { &stop_now } else { &STOP };
    let (sum, results) = crate::sweep::run(&study.jobs, &cache, &opt, stop)
        .map_err(|e| CmdError::Other(e.to_string()))?;
    let threads = if jobs == 1 { "thread" } else { "threads" };
    let note = format!(
        "{} cases: {} from the cache, {} computed in {} simulations, {} failed, {} not run; {:.1} s wall time with {jobs} worker {threads}",
        sum.cases, sum.cached, sum.computed, sum.simulations, sum.failed, sum.not_run, sum.wall_time_s
    );
    println!("{note}");
    if sum.stopped && !a.cached_only {
        println!("stopped before the end: run the same command again to compute the rest");
        return Ok(130);
    }
    if !a.no_report {
        let w = crate::report::write(&study, &results, &note).map_err(CmdError::Other)?;
        for l in &w.headline {
            println!("  {l}");
        }
        for f in &w.files {
            eprintln!("wrote {}", f.display());
        }
    }
    Ok(if sum.failed > 0 { 1 } else { 0 })
}

fn optimise_cmd(a: &OptimiseArgs) -> Result<i32, CmdError> {
    use crate::optimise::{Bounds, Constraints, Space, SwarmSettings};
    let base = CaseSpec::paper(a.r);
    base.validate(false)?;
    let file: OptimiseFile = match &a.config {
        None => OptimiseFile::default(),
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| {
                CmdError::Input(format!("--config {}: cannot read it: {e}", p.display()))
            })?;
            toml::from_str(&text).map_err(|e| {
                CmdError::Input(format!(
                    "--config {}: {}",
                    p.display(),
                    e.to_string()
                        .lines()
                        .map(str::trim)
                        .filter(|l| !l.is_empty())
                        .collect::<Vec<_>>()
                        .join(" ")
                ))
            })?
        }
    };
    let d = Bounds::default();
    let space = Space {
        bounds: Bounds {
            l1: a.l1.or(file.l1).unwrap_or(d.l1),
            l2: a.l2.or(file.l2).unwrap_or(d.l2),
            per: a.per.or(file.per).unwrap_or(d.per),
            width: a.free_width.or(file.free_width),
            depth: a.depth.or(file.depth).unwrap_or(d.depth),
        },
        cons: Constraints {
            w_min: a.w_min.or(file.w_min).unwrap_or(10.0) * 1e-4,
            max_area: a.max_area.or(file.max_area),
            max_depth_ratio: a.max_depth_ratio.or(file.max_depth_ratio),
            allow_thick: a.allow_thick_pockets || file.allow_thick_pockets.unwrap_or(false),
        },
    };
    let particles = a.particles.or(file.particles).unwrap_or(8);
    let iterations = a.iterations.or(file.iterations).unwrap_or(3);
    let balanced = a
        .balanced
        .clone()
        .or(file.balanced)
        .unwrap_or_else(|| vec![0.5]);
    let seed = a.seed.or(file.seed).unwrap_or(1);
    let fidelity = a.fidelity.or(file.fidelity).unwrap_or(Fidelity::Fast);
    let search_fidelity = a
        .search_fidelity
        .or(file.search_fidelity)
        .unwrap_or(Fidelity::Draft);
    let out_dir = a
        .out
        .clone()
        .or(file.out)
        .unwrap_or_else(|| PathBuf::from("results"));
    space.validate()?;
    if particles < 2 || iterations == 0 {
        return Err(CmdError::Input(
            "--particles must be ≥ 2 and --iterations ≥ 1".into(),
        ));
    }
    if let Some(w) = balanced.iter().find(|w| !(**w > 0.0 && **w < 1.0)) {
        return Err(CmdError::Input(format!(
            "--balanced {w}: each weight must lie strictly between 0 and 1"
        )));
    }
    if a.jobs == Some(0) {
        return Err(CmdError::Input(
            "--jobs 0: need at least one worker thread".into(),
        ));
    }
    if let Some(dt) = a.dt {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(CmdError::Input(format!(
                "--dt {dt}: must be a finite number > 0"
            )));
        }
    }
    if let Some((n1, n2)) = a.mesh {
        if n1 < 16 || n2 < 1 {
            return Err(CmdError::Input(format!(
                "--mesh {n1}x{n2}: needs at least 16 cells along x1 and 1 along x2"
            )));
        }
    }
    // A directory that cannot be made stops the search now, not after its simulations.
    directory_can_be_made(&out_dir).map_err(|why| {
        CmdError::Input(format!(
            "--out {}: cannot create it: {why}; choose another directory",
            out_dir.display()
        ))
    })?;
    let overrides = crate::study::NumericsOverride {
        n1: a.mesh.map(|m| m.0),
        n2: a.mesh.map(|m| m.1),
        dt: a.dt,
        ..Default::default()
    };
    let cache = open_cache(a.cache.as_deref())?;
    install_ctrl_c();
    let cache = std::sync::Mutex::new(cache);
    let settings = crate::optimise_report::Settings {
        base,
        space,
        search_fidelity,
        report_fidelity: fidelity,
        overrides,
        swarm: SwarmSettings {
            particles,
            iterations,
            seed,
        },
        balanced,
        jobs: a
            .jobs
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
        progress: true,
        out_dir: Some(out_dir.clone()),
    };
    let report =
        crate::optimise_report::optimise(&settings, &cache, &STOP).map_err(CmdError::Other)?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report).unwrap_or_default()
        );
    } else {
        print!("{}", crate::optimise_report::table(&report));
        eprintln!(
            "wrote {}/optimise_R{}.json, .csv, _front.png, _z_t.png, _f_t.png",
            out_dir.display(),
            report.r
        );
    }
    Ok(0)
}

/// Whether `dir` is, or could be made as, a directory, without making anything (bad input
/// must leave no trace): its nearest existing ancestor must be a directory. (Permissions are
/// left to the write itself.)
fn directory_can_be_made(dir: &std::path::Path) -> Result<(), String> {
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

fn cache_cmd(a: &CacheArgs) -> Result<i32, CmdError> {
    // Inspecting or clearing must not create a cache (nor its directories): a mistyped path
    // would otherwise show an empty cache as if it were the one meant.
    let path = crate::cache::path_from(a.cache.as_deref());
    if !path.exists() {
        return Err(CmdError::Input(format!(
            "no cache at {}: nothing has been evaluated there yet (`texopt study` and `texopt optimise` create it); check --cache or $TEXOPT_CACHE",
            path.display()
        )));
    }
    let cache = open_cache(Some(&path))?;
    let other = |e: crate::cache::CacheError| CmdError::Other(e.to_string());
    match &a.action {
        CacheAction::Stats => {
            let s = cache.stats().map_err(other)?;
            let ok = cache.integrity_check().map_err(other)?;
            println!("cache {}", cache.path().display());
            println!(
                "  {} evaluations done, {} failed; {:.1} s of compute stored; {} bytes; integrity: {ok}",
                s.done, s.failed, s.compute_seconds, s.file_bytes
            );
        }
        CacheAction::Export { out } => {
            let n = match out {
                Some(p) => {
                    let mut f = std::fs::File::create(p).map_err(|e| {
                        CmdError::Input(format!("--out {}: cannot create it: {e}", p.display()))
                    })?;
                    cache.export(&mut f).map_err(other)?
                }
                None => cache.export(&mut std::io::stdout().lock()).map_err(other)?,
            };
            eprintln!("exported {n} evaluations");
        }
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

enum CmdError {
    Input(String),
    Other(String),
}

impl From<InputError> for CmdError {
    fn from(e: InputError) -> Self {
        CmdError::Input(e.to_string())
    }
}

/// The case and numerics named by the flags, validated.
pub fn case_from_args(a: &SimulateArgs) -> Result<(CaseSpec, Numerics), InputError> {
    let mut case = CaseSpec::paper(a.r);
    case.theta_s = a.theta_s;
    case.d_oil = a.d_oil;
    case.mass = a.mass;
    let depth = a.depth.unwrap_or(0.0);
    if !depth.is_finite() || depth < 0.0 {
        return Err(InputError {
            param: "--depth".into(),
            value: depth.to_string(),
            rule: "must be a finite depth ≥ 0 µm (0 or absent: untextured)".into(),
        });
    }
    if depth > 0.0 {
        let need = |name: &str, v: Option<f64>| {
            v.ok_or_else(|| InputError {
                param: name.into(),
                value: "missing".into(),
                rule: format!("a textured liner (--depth {depth}) needs {name}"),
            })
        };
        let l1 = need("--l1", a.l1)?;
        let per = need("--per", a.per)?;
        case.texture = Some(Texture {
            l1,
            l2: a.l2.unwrap_or(l1),
            per,
            width: a.width.unwrap_or(per),
            depth,
            phase: a.phase,
        });
    }
    // The tier as studies use it: N2 raised where a pocket would span too few cells across,
    // so that `simulate` reproduces a study's row.
    let tier = a.fidelity.numerics_for(&case);
    let num = Numerics {
        n1: a.mesh.map_or(tier.n1, |m| m.0),
        n2: a.mesh.map_or(tier.n2, |m| m.1),
        dt: a.dt.unwrap_or(tier.dt),
        periodic_tol: a.periodic_tol.unwrap_or(tier.periodic_tol),
        t_max: a.t_max,
        solver: a.solver,
        solve_tol: a.solve_tol,
        cycles: a.cycles,
        start: a.start,
        extrapolate: !a.no_extrapolate,
        approach_n2: a.approach_n2.map_or(tier.approach_n2, |x| x.0),
        coupling: a.coupling,
        cavitation: a.cavitation,
        ..Numerics::default()
    };
    case.validate(a.allow_thick_pockets)?;
    num.validate(&case)?;
    Ok((case, num))
}

/// Rings at least this flat (cm) get a note when the time step exceeds [`CONFORMAL_DT`]: the
/// time-step error of the film grows with R (stop 29, `fast` against 2048×8 at dt = 1e-4 with
/// the Case I pocket: 0.3 % at R = 5, 0.8–1.0 % at R = 12.8, 3 % at R = 51.2; README,
/// "Speed and accuracy"), while the tiers keep the paper's dt = 4e-4.
const CONFORMAL_R_CM: f64 = 10.0;
/// The time step (L/U units) that keeps R = 51.2 within ≈ 0.7 % of the 2048-cell reference.
const CONFORMAL_DT: f64 = 1e-4;

fn simulate_cmd(a: &SimulateArgs) -> Result<i32, CmdError> {
    let (case, num) = case_from_args(a)?;
    if case.texture.is_none()
        && (a.l1.is_some() || a.per.is_some() || a.l2.is_some() || a.width.is_some())
    {
        eprintln!("note: --depth is 0 or absent, so the liner is untextured; the pocket flags are not used");
    }
    if case.texture.is_some() && case.r >= CONFORMAL_R_CM && num.dt > CONFORMAL_DT {
        eprintln!(
            "note: R = {} cm is a conformal ring, where the time step sets the error: dt = {:.0e} can be several % off in f and C_min; --dt {CONFORMAL_DT:.0e} keeps it near 1 % (README, \"Speed and accuracy\")",
            case.r, num.dt
        );
    }
    let transient = case.texture.is_some() || a.transient;
    if let Some(path) = &a.series {
        if !transient {
            return Err(CmdError::Input(format!(
                "--series {}: an untextured liner is solved as a steady 1D problem with no time series; add --transient to run it as a 2D transient",
                path.display()
            )));
        }
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        if !dir.is_dir() {
            return Err(CmdError::Input(format!(
                "--series {}: the directory {} does not exist; create it or choose another path",
                path.display(),
                dir.display()
            )));
        }
    }

    // On a terminal the line is redrawn every period; elsewhere (or beside --json output) a
    // plain line at most every `--progress-every` seconds, so that long runs in batch jobs
    // show that they advance without flooding the log.
    let show = std::io::stderr().is_terminal() && !a.json;
    // Beyond what a Duration holds (1e300 s): never, as far as a run can tell.
    let every = std::time::Duration::try_from_secs_f64(a.progress_every)
        .unwrap_or(std::time::Duration::MAX);
    let began = std::time::Instant::now();
    let mut last_line = began;
    let mut observe = |p: &Progress| {
        let line = format!(
            "  period {:4}  t = {:7.3}  f̄ = {:.5}  Z̄ = {:.4} µm  est. periodic error {:.1e}",
            p.period, p.t, p.f_mean, p.z_mean, p.periodic_error
        );
        if show {
            eprint!("\r{line}   ");
            let _ = std::io::stderr().flush();
        } else if last_line.elapsed() >= every {
            last_line = std::time::Instant::now();
            eprintln!("{line}  ({:.0} s)", began.elapsed().as_secs_f64());
        }
    };
    let result = if transient {
        crate::run::run_transient(&case, &num, a.series.is_some(), &[], &mut observe)
    } else {
        simulate(&case, &num, false)
    };
    if show && transient {
        eprintln!();
    }
    let RunResult {
        outcome, series, ..
    } = result.map_err(|e| CmdError::Other(e.to_string()))?;

    if let (Some(path), Some(rows)) = (&a.series, &series) {
        write_series(path, rows).map_err(|e| {
            CmdError::Other(format!("could not write --series {}: {e}", path.display()))
        })?;
    }
    if a.json {
        let report = serde_json::json!({
            "inputs": { "case": case, "numerics": num, "mesh": format!("{}x{}", num.n1, num.n2) },
        });
        let mut obj = report.as_object().cloned().unwrap_or_default();
        if let serde_json::Value::Object(o) = serde_json::to_value(&outcome).unwrap_or_default() {
            obj.extend(o);
        }
        println!("{}", serde_json::Value::Object(obj));
    } else {
        print_summary(&case, &num, &outcome);
    }
    if !outcome.converged {
        eprintln!(
            "warning: the periodic regime was not reached by t = {} (estimated error {:.1e} > tolerance {:.1e}); the numbers above are not final. Raise --t-max or loosen --periodic-tol.",
            num.t_max, outcome.periodic_error, num.periodic_tol
        );
        return Ok(1);
    }
    Ok(0)
}

fn write_series(path: &std::path::Path, rows: &[SeriesRow]) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "t,Z,W_h,f,f_couette,f_poiseuille,f_pressure")?;
    for r in rows {
        writeln!(
            w,
            "{},{},{},{},{},{},{}",
            r.t, r.z, r.w_h, r.f, r.f_couette, r.f_poiseuille, r.f_pressure
        )?;
    }
    w.flush()
}

fn print_summary(case: &CaseSpec, num: &Numerics, o: &Outcome) {
    let ring = if case.r.is_infinite() {
        "flat ring".to_string()
    } else {
        format!("ring face radius R = {} cm", case.r)
    };
    match &case.texture {
        None => println!("texopt simulate: {ring}, untextured liner"),
        Some(t) => println!(
            "texopt simulate: {ring}; pockets l1 = {} cm, l2 = {} cm, depth = {} µm on a {} × {} cm lattice (textured area {:.1} %)",
            t.l1, t.l2, t.depth, t.per, t.width, 100.0 * t.area_fraction()
        ),
    }
    if o.method == "steady-1d" {
        println!("  steady 1D force balance on {} cells", num.n1);
    } else {
        println!(
            "  transient on {}x{} cells, dt = {:.4e} ms: {} periods, {} steps, t = {:.3} ms; periodic regime {} (est. error {:.1e})",
            num.n1,
            num.n2,
            o.dt,
            o.periods,
            o.steps,
            o.t_end,
            if o.converged { "reached" } else { "NOT reached" },
            o.periodic_error
        );
        if let (true, Some(coarse)) = (o.approach_steps > 0, num.approach_numerics(case)) {
            println!(
                "  (the first {} steps on {}x{} cells, the coarse approach: the outcomes are those of the full mesh; --approach-n2 off to run every step on it)",
                o.approach_steps, coarse.n1, coarse.n2
            );
        }
    }
    println!(
        "  mean friction coefficient  f = {:.5}   (eq. 11; the paper prints f/10 = {:.6})",
        o.f_mean,
        o.f_mean / 10.0
    );
    println!(
        "    Couette {:.5}, Poiseuille {:.5}, pressure {:.5}",
        o.f_couette, o.f_poiseuille, o.f_pressure
    );
    println!(
        "  ring position Z: mean {:.4} µm, min {:.4} µm, max {:.4} µm",
        o.z_mean, o.z_min, o.z_max
    );
    println!("  minimum clearance C_min = {:.4} µm", o.c_min);
    if o.method == "steady-1d" {
        println!("  wall time {:.3} s", o.wall_time_s);
    } else {
        println!(
            "  wall time {:.2} s ({:.2} ms/step, {:.2} active-set iterations per step)",
            o.wall_time_s,
            1e3 * o.wall_time_s / o.steps.max(1) as f64,
            o.iterations_per_step
        );
    }
}
