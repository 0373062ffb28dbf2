//! The command line's arguments (clap): every flag name of texopt is here.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

use crate::time::{Approach, Fidelity, Start, TimeScheme};

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
    /// A texture for each zone of the liner over an engine cycle (an engine file: see
    /// studies/engine_gasoline.toml): each zone's design, the uniform best and the plain liner.
    Cycle(CycleArgs),
}

/// `texopt cycle ENGINE.toml`: the design's bounds, constraints and search settings come from
/// the file's `[design]` section (a `DesignFile`), flags win.
#[derive(Args, Debug)]
pub struct CycleArgs {
    /// The engine file (TOML).
    pub file: PathBuf,
    /// Crank-angle step of the report, with --quasi-steady (degrees) [default: 5].
    #[arg(long, value_name = "DEG")]
    pub step: Option<f64>,
    /// Crank-angle step of the design, with --quasi-steady (degrees) [default: 20].
    #[arg(long = "design-step", value_name = "DEG")]
    pub design_step: Option<f64>,
    #[command(flatten)]
    pub search: SearchArgs,
    /// Cache file: the searches' runs go through it, so a search repeated over it runs
    /// nothing [default: $TEXOPT_CACHE or .texopt/cache.sqlite].
    #[arg(long, value_name = "FILE")]
    pub cache: Option<PathBuf>,
    /// Directory of the report \[default: results/cycle_NAME, NAME the engine's\].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the report as JSON on stdout instead of the tables.
    #[arg(long)]
    pub json: bool,
    /// Judge the liners angle by angle, each crank angle a periodic regime at its speed and
    /// load, the dead centres and the mixed-lubrication angles excluded (the default: the
    /// whole cycle as one transient, nothing excluded). Its report goes to
    /// results/cycle_NAME_quasi_steady unless --out says otherwise.
    #[arg(long = "quasi-steady")]
    pub quasi_steady: bool,
    /// Search where to texture: a band next to each dead centre, each with its place, length
    /// and texture, plain elsewhere, judged over the engine file's \[\[operating\]\] map (or its
    /// own point) by the time-weighted friction power; the report goes to
    /// results/cycle_NAME_bands unless --out says otherwise.
    #[arg(long, conflicts_with = "quasi_steady")]
    pub bands: bool,
    /// Least band length with --bands (mm) \[default: the file's \[design\] band_min_mm, else 4\].
    #[arg(long = "band-min", value_name = "MM")]
    pub band_min: Option<f64>,
    /// Each search step's cycle runs (the zones' or, with --bands, the bands' and its
    /// report's) as a Slurm array of --tasks shares, each task into a cache of its own in
    /// DIR/caches, merged into --cache once the array is done; this command waits for each
    /// array (sbatch --wait, so run it where sbatch works) and writes the report itself.
    /// Scripts and logs in DIR. Not with --quasi-steady.
    #[arg(long, value_name = "DIR")]
    pub slurm: Option<PathBuf>,
    #[command(flatten)]
    pub cluster: ClusterArgs,
    /// A Slurm task's work (--slurm writes it): share --share of the runs in batch FILE, into
    /// --cache; nothing else is searched or written.
    #[arg(long, value_name = "FILE", hide = true, conflicts_with = "slurm")]
    pub answer: Option<PathBuf>,
    #[arg(long, value_name = "I/N", hide = true, requires = "answer", value_parser = parse_shard)]
    pub share: Option<(usize, usize)>,
}

/// Units as in `simulate`: lengths in cm, depth in µm; ranges are LO..HI. Settings come from
/// the flags, else from `--config FILE`, else from the defaults shown.
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct OptimiseArgs {
    /// Ring face radius R in cm; a list (3.2,5,8,12.8) or a range (5..12.8, see --radii) asks
    /// for the best design at each R and a robust design for the whole range (a ring that
    /// wears flatter).
    #[arg(long = "R", value_name = "CM|LIST|LO..HI", value_parser = parse_radii)]
    pub r: Radii,
    /// Radii a range --R LO..HI is sampled at, geometrically spaced, ends included [default: 4].
    #[arg(long, value_name = "N")]
    pub radii: Option<usize>,
    /// TOML file with any of the settings below (keys as the flags, with '_' for '-';
    /// ranges as [LO, HI]); flags given on the command line win.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Range of the pocket semiaxis along sliding (cm) [default: 0.0025..0.03].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub l1: Option<(f64, f64)>,
    /// Range of the pocket semiaxis across sliding (cm) [default: 0.0025..0.03].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub l2: Option<(f64, f64)>,
    /// Range of the texture period along sliding (cm) [default: 0.005..0.06].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub per: Option<(f64, f64)>,
    /// Make the period across sliding a free variable in this range (cm) [default: width = per].
    #[arg(long = "free-width", value_name = "LO..HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub free_width: Option<(f64, f64)>,
    /// Range of the pocket depth (µm) [default: 2..30].
    #[arg(long, value_name = "LO..HI", value_parser = parse_range, allow_hyphen_values = true)]
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
    #[command(flatten)]
    pub operating: OperatingArgs,
    /// Weights on friction of the balanced searches (comma-separated, each in (0, 1), at most
    /// 100) [default: 0.5].
    #[arg(long, value_delimiter = ',')]
    pub balanced: Option<Vec<f64>>,
    #[command(flatten)]
    pub search: SearchArgs,
    /// Cache file [default: $TEXOPT_CACHE or .texopt/cache.sqlite].
    #[arg(long, value_name = "FILE")]
    pub cache: Option<PathBuf>,
    /// Directory of the report files (`optimise_R<R>.json`, .csv, _front.png, _cells.png, _z_t.png, _f_t.png)
    /// [default: results/optimise].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the report as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also write the film over the last period of the best-friction design and of the plain
    /// liner, at the reported fidelity, into DIR/best_friction and DIR/plain_liner (as
    /// `simulate --snapshots`). One radius only.
    #[arg(long, value_name = "DIR")]
    pub snapshots: Option<PathBuf>,
}

/// The flags of every search (`optimise`, `cycle`): fidelities, numerics, swarm, threads and
/// run limits.
#[derive(Args, Debug, Clone, Copy)]
pub struct SearchArgs {
    /// Fidelity of the reported designs (each is evaluated at it) [default: fast].
    #[arg(long, value_enum)]
    pub fidelity: Option<Fidelity>,
    /// Fidelity of the searches [default: draft, within 2 % of the converged answer on the
    /// benchmark cases; the reported designs are then confirmed at --fidelity].
    #[arg(long, value_enum)]
    pub search_fidelity: Option<Fidelity>,
    /// Override the mesh of both fidelities (N2 is still raised to resolve small pockets).
    #[arg(long, value_name = "N1xN2", value_parser = parse_mesh)]
    pub mesh: Option<(usize, usize)>,
    /// Override the time step of both fidelities (units of L/U: ms at 10 m/s).
    #[arg(long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Particles per swarm, 2 to 10000 [default: 8].
    #[arg(long)]
    pub particles: Option<usize>,
    /// Swarm iterations per search (each evaluates every particle), 1 to 100000 [default: 3]. Each
    /// search's best is then refined by a local pattern search, whose evaluations come on top
    /// of the swarm's.
    #[arg(long)]
    pub iterations: Option<u64>,
    /// Random seed of the swarms (the same seed repeats the same designs, all from the
    /// cache) [default: 1].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads, 1 to 256 [default: all cores].
    #[arg(long, value_name = "N", value_parser = parse_jobs)]
    pub jobs: Option<usize>,
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// The settings of a search in a file: `optimise --config FILE` (same names as the flags) and
/// an engine file's `[design]` section. The design space and the search keys are common; the
/// rest is one command's ([`DesignFile::foreign_key`]).
#[derive(serde::Deserialize, Default, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct DesignFile {
    #[serde(default, deserialize_with = "bounds")]
    pub(super) l1: Option<(f64, f64)>,
    #[serde(default, deserialize_with = "bounds")]
    pub(super) l2: Option<(f64, f64)>,
    #[serde(default, deserialize_with = "bounds")]
    pub(super) per: Option<(f64, f64)>,
    #[serde(default, deserialize_with = "bounds")]
    pub(super) free_width: Option<(f64, f64)>,
    #[serde(default, deserialize_with = "bounds")]
    pub(super) depth: Option<(f64, f64)>,
    pub(super) w_min: Option<f64>,
    pub(super) max_area: Option<f64>,
    pub(super) max_depth_ratio: Option<f64>,
    pub(super) allow_thick_pockets: Option<bool>,
    pub(super) fidelity: Option<Fidelity>,
    pub(super) search_fidelity: Option<Fidelity>,
    pub(super) particles: Option<usize>,
    pub(super) iterations: Option<u64>,
    pub(super) seed: Option<u64>,
    // `optimise --config` only: the balanced searches, files, radii and operating point.
    pub(super) balanced: Option<Vec<f64>>,
    pub(super) out: Option<PathBuf>,
    pub(super) radii: Option<usize>,
    pub(super) speed: Option<f64>,
    pub(super) load: Option<f64>,
    pub(super) viscosity: Option<f64>,
    pub(super) ring_width: Option<f64>,
    pub(super) ring_mass: Option<f64>,
    pub(super) d_oil: Option<f64>,
    pub(super) roughness: Option<f64>,
    // An engine file's `[design]` only (the engine gives the operating points).
    /// Least clearance every design keeps (µm) [default: the model's limit, 3 × roughness].
    pub(super) min_clearance_um: Option<f64>,
    pub(super) roughness_um: Option<f64>,
    pub(super) step_deg: Option<f64>,
    pub(super) design_step_deg: Option<f64>,
    /// Least band length of `cycle --bands` (mm).
    pub(super) band_min_mm: Option<f64>,
}

/// Which file a [`DesignFile`] was read from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum DesignFileOf {
    Optimise,
    Engine,
}

impl DesignFile {
    /// A key given that belongs to the other kind of file, if any.
    pub(super) fn foreign_key(&self, of: DesignFileOf) -> Option<&'static str> {
        let optimise_only = [
            ("balanced", self.balanced.is_some()),
            ("out", self.out.is_some()),
            ("radii", self.radii.is_some()),
            ("speed", self.speed.is_some()),
            ("load", self.load.is_some()),
            ("viscosity", self.viscosity.is_some()),
            ("ring_width", self.ring_width.is_some()),
            ("ring_mass", self.ring_mass.is_some()),
            ("d_oil", self.d_oil.is_some()),
            ("roughness", self.roughness.is_some()),
        ];
        let engine_only = [
            ("min_clearance_um", self.min_clearance_um.is_some()),
            ("roughness_um", self.roughness_um.is_some()),
            ("step_deg", self.step_deg.is_some()),
            ("design_step_deg", self.design_step_deg.is_some()),
            ("band_min_mm", self.band_min_mm.is_some()),
        ];
        let foreign: &[(&'static str, bool)] = match of {
            DesignFileOf::Optimise => &engine_only,
            DesignFileOf::Engine => &optimise_only,
        };
        foreign.iter().find(|(_, given)| *given).map(|(k, _)| *k)
    }
}

/// The operating point in physical units (defaults: the paper's, Stribeck number 1e-3), and
/// the roughness that says where the film model stops.
#[derive(Args, Debug, Clone, Copy, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatingArgs {
    /// Sliding speed of the liner under the ring (m/s) [default: 10].
    #[arg(long, value_name = "M/S", allow_hyphen_values = true)]
    pub speed: Option<f64>,
    /// Ring load per unit circumferential length, elastic and gas (N/m) [default: 39.84].
    #[arg(long, value_name = "N/M", allow_hyphen_values = true)]
    pub load: Option<f64>,
    /// Dynamic viscosity of the oil in the contact (Pa·s) [default: 0.004].
    #[arg(long, value_name = "PA_S", allow_hyphen_values = true)]
    pub viscosity: Option<f64>,
    /// Axial width of the ring face (mm) [default: 0.8].
    #[arg(long = "ring-width", value_name = "MM", allow_hyphen_values = true)]
    pub ring_width: Option<f64>,
    /// Ring mass per unit circumferential length (kg/m) [default: 0.048].
    #[arg(long = "ring-mass", value_name = "KG/M", allow_hyphen_values = true)]
    pub ring_mass: Option<f64>,
    /// Inlet oil film (µm): 20 is fully flooded, a few µm starved [default: 20].
    #[arg(long = "d-oil", value_name = "UM", allow_hyphen_values = true)]
    pub d_oil: Option<f64>,
    /// Composite RMS roughness of ring and liner (µm): a minimum clearance below 3 times it
    /// is flagged as outside the hydrodynamic model [default: 0.3].
    #[arg(long, value_name = "UM", allow_hyphen_values = true)]
    pub roughness: Option<f64>,
}

/// The asperity contact of ring face and liner plateau (Greenwood–Tripp, docs/model.md §11);
/// σ is --roughness. Defaults: a plateau-honed cast-iron liner against a steel ring.
#[derive(Args, Debug, Clone, Copy, Default)]
pub struct ContactArgs {
    /// No asperity contact: the film alone carries the ring (the contact flags are not used).
    #[arg(long = "no-contact")]
    pub no_contact: bool,
    /// Roughness parameter ηβσ (summit density × summit radius × σ) [default: 0.04].
    #[arg(long = "eta-beta-sigma", value_name = "X", allow_hyphen_values = true)]
    pub eta_beta_sigma: Option<f64>,
    /// Summit slope measure σ/β [default: 1e-3].
    #[arg(long = "sigma-over-beta", value_name = "X", allow_hyphen_values = true)]
    pub sigma_over_beta: Option<f64>,
    /// Composite contact modulus E* in GPa, 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (not E′ = 2E*)
    /// [default: 82.9, grey cast iron on steel].
    #[arg(long = "e-star", value_name = "GPA", allow_hyphen_values = true)]
    pub e_star: Option<f64>,
    /// Shear strength of the boundary film on the asperity tips τ₀ (MPa) [default: 2].
    #[arg(long = "tau0", value_name = "MPA", allow_hyphen_values = true)]
    pub tau0: Option<f64>,
    /// Pressure coefficient ς of the boundary shear strength, τ_b = τ₀·A_a/A + ς·p_a
    /// [default: 0.17].
    #[arg(long = "varsigma", value_name = "X", allow_hyphen_values = true)]
    pub varsigma: Option<f64>,
}

/// The limits a run is checked against before it starts (time/limits.rs).
#[derive(Args, Debug, Clone, Copy)]
pub struct LimitArgs {
    /// Most memory one run may take, in GiB (estimated before it starts from its mesh and what
    /// --snapshots, --animate and --series keep; at most the machine's memory) [default: 8].
    #[arg(long = "max-memory", value_name = "GIB")]
    pub max_memory: Option<f64>,
    /// Most time steps one run may take up to t_max [default: 1e7].
    #[arg(long = "max-steps", value_name = "N")]
    pub max_steps: Option<f64>,
}

/// Most worker threads: more than this is a typo (each thread holds a run's memory).
pub(super) const MAX_JOBS: usize = 256;

fn parse_jobs(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if (1..=MAX_JOBS).contains(&n) => Ok(n),
        _ => Err(format!("must be a whole number from 1 to {MAX_JOBS}")),
    }
}

/// A `--config` range: exactly two numbers `[LO, HI]` (a list of three is an error, not two
/// of them).
fn bounds<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<(f64, f64)>, D::Error> {
    let v: Vec<f64> = serde::Deserialize::deserialize(d)?;
    match v[..] {
        [lo, hi] => Ok(Some((lo, hi))),
        _ => Err(serde::de::Error::custom(format!(
            "a range is two numbers [LO, HI], found {} numbers",
            v.len()
        ))),
    }
}

pub(super) fn parse_range(s: &str) -> Result<(f64, f64), String> {
    let err = || format!("expected a range LO..HI of numbers, e.g. 0.0025..0.03, got {s:?}");
    // "5...8" would split as 5..0.8: a slip of the dots, not a range to read.
    if s.contains("...") {
        return Err(format!(
            "{s:?} has three dots; write a range LO..HI with two, e.g. 5..8"
        ));
    }
    let (a, b) = s.split_once("..").ok_or_else(err)?;
    let lo = a.trim().parse::<f64>().map_err(|_| err())?;
    let hi = b.trim().parse::<f64>().map_err(|_| err())?;
    Ok((lo, hi))
}

#[derive(Args, Debug)]
pub struct StudyArgs {
    /// The study file (TOML), e.g. studies/paper.toml.
    pub file: PathBuf,
    /// Worker threads, 1 to 256 [default: all cores].
    #[arg(long, value_name = "N", value_parser = parse_jobs)]
    pub jobs: Option<usize>,
    #[command(flatten)]
    pub limits: LimitArgs,
    /// Cache file [default: $TEXOPT_CACHE or .texopt/cache.sqlite]. Not with --slurm, whose
    /// tasks keep their caches in DIR/caches and merge them into DIR/merged.sqlite.
    #[arg(long, value_name = "FILE", conflicts_with = "slurm")]
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
    /// elsewhere); missing cases appear as "not run". The cache is only read: it must exist.
    #[arg(long, conflicts_with = "shard")]
    pub cached_only: bool,
    /// Replace the study's report even where the one in place holds more results (by
    /// default such a report is kept and the command refused).
    #[arg(long)]
    pub replace_report: bool,
    /// Run only share I of N of the cases (1 ≤ I ≤ N): a split balanced by expected cost that
    /// depends on the study file alone, so every machine agrees on it; into --cache, a file
    /// of this share's own; no report (merge the shares with `texopt cache merge`, then
    /// report with --cached-only).
    #[arg(long, value_name = "I/N", value_parser = parse_shard, conflicts_with = "slurm")]
    pub shard: Option<(usize, usize)>,
    /// Write Slurm scripts into DIR instead of running: an sbatch array of --tasks shares,
    /// each into its own cache and log, and a merge-and-report job that runs after them.
    /// The paths the scripts name cannot hold control characters, nor DIR a backslash.
    #[arg(long, value_name = "DIR")]
    pub slurm: Option<PathBuf>,
    #[command(flatten)]
    pub cluster: ClusterArgs,
    /// Submit the scripts with sbatch and print the job ids (else: print how to).
    #[arg(long, requires = "slurm")]
    pub submit: bool,
}

/// The Slurm jobs of `--slurm`: how many tasks, where and how long.
#[derive(Args, Debug, Default)]
pub struct ClusterArgs {
    /// Array tasks (shares) of --slurm [default: 4].
    #[arg(long, value_name = "N", requires = "slurm", value_parser = parse_tasks)]
    pub tasks: Option<usize>,
    /// Slurm partition of the jobs [default: the cluster's default].
    #[arg(long, value_name = "P", requires = "slurm")]
    pub partition: Option<String>,
    /// Time limit of each task and of the merge ([D-]HH:MM:SS) [default: the partition's].
    #[arg(long, value_name = "HH:MM:SS", requires = "slurm")]
    pub time: Option<String>,
    /// CPUs per task, its worker threads [default: 1].
    #[arg(long, value_name = "C", requires = "slurm", value_parser = parse_jobs)]
    pub cpus: Option<usize>,
}

/// Most shares of a study (a typo guard: each is a job with its own cache file).
pub(super) const MAX_SHARDS: usize = 10_000;

fn parse_tasks(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_SHARDS).contains(&n) => Ok(n),
        _ => Err(format!("must be a whole number from 1 to {MAX_SHARDS}")),
    }
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("expected I/N with 1 ≤ I ≤ N ≤ {MAX_SHARDS}, e.g. 2/8, got {s:?}");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n) = (
        i.trim().parse::<usize>().map_err(|_| bad())?,
        n.trim().parse::<usize>().map_err(|_| bad())?,
    );
    if 1 <= i && i <= n && n <= MAX_SHARDS {
        Ok((i, n))
    } else {
        Err(bad())
    }
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
    /// Copy every evaluation of other caches into one (e.g. the shares of a study run on a
    /// cluster): checks each file, refuses two different outcomes under one key (nothing is
    /// written then), and merging twice changes nothing.
    Merge {
        /// The caches to copy from.
        #[arg(required = true)]
        sources: Vec<PathBuf>,
        /// The cache to copy into (created if missing).
        #[arg(long, value_name = "FILE")]
        into: PathBuf,
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
    /// Run every case at this tier [default: the benchmark's runs: the four reference cases
    /// and the untextured ring at fast, Case III at paper]
    #[arg(long, value_enum)]
    pub fidelity: Option<Fidelity>,
    /// Only the named cases (repeatable): case-I, case-III, conformal-R51.2,
    /// deep-close-packed, untextured-R0.8; or the engine cycle's (never run by default):
    /// cycle-plain (the example engine's plain liner through its cycle at draft, then at fast
    /// for the friction work's error: seconds) and cycle-uniform (its liner textured with Case
    /// I's pocket, the same way: minutes). --start and --approach are the film cases' only.
    #[arg(long = "case", value_name = "NAME")]
    pub cases: Vec<String>,
    /// Initial state of every case: the paper's (the speed targets are stated from it) or
    /// the untextured equilibrium.
    #[arg(long, value_enum, default_value_t = Start::Paper)]
    pub start: Start,
    /// Coarse approach to the periodic regime: the mesh and time step the ring's transient
    /// runs on before the tier's mesh takes over (e.g. 120x4@3.3e-3), or `off` [default: the
    /// tier's: 120x4 at its characteristic step 3.3e-3 for draft and fast, 128x4 at 1.6e-3
    /// for fine, 512x8 at 4e-4 for paper]
    #[arg(long = "approach", value_name = "N1xN2@DT|off", value_parser = parse_approach)]
    pub approach: Option<ApproachArg>,
    /// Runs of each case: its row reports the shortest wall time and lists all (this VM's
    /// timings vary by ±20 % from run to run; the outcomes must not vary at all).
    #[arg(long, value_name = "N", default_value_t = 3)]
    pub repeat: usize,
    /// Where to write the results (JSON) \[default: results/bench/bench.json, or
    /// `results/bench/bench-<what differs>.json` for a partial or variant run\]
    ///
    /// results/bench/bench.json is the benchmark itself: its default runs, best of 3, the
    /// paper's start, the tiers' approach. Any other run goes to
    /// `results/bench/bench-<what differs>.json` (git-ignored, e.g. bench-fast-case-III.json), so
    /// that it never replaces the committed benchmark.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

impl BenchArgs {
    /// The file the results go to: `--out`, else the default above.
    pub(super) fn out_path(&self) -> PathBuf {
        if let Some(out) = &self.out {
            return out.clone();
        }
        let mut tags = Vec::new();
        if let Some(f) = self.fidelity {
            tags.push(f.name().to_string());
        }
        if self.repeat != 3 {
            tags.push(format!("x{}", self.repeat));
        }
        if self.start == Start::Equilibrium {
            tags.push("from-equilibrium".into());
        }
        if let Some(ApproachArg(a)) = self.approach {
            tags.push(a.map_or("approach-off".into(), |a| {
                format!("approach-{}x{}-{}", a.n1, a.n2, a.dt)
            }));
        }
        tags.extend(self.cases.iter().cloned());
        let name = match tags.is_empty() {
            true => "bench.json".to_string(),
            false => format!("bench-{}.json", tags.join("-")),
        };
        PathBuf::from("results/bench").join(name)
    }
}

/// Units: lengths along the liner in cm, gaps and depths in µm, time in units of L/U
/// (1 cm over the sliding speed: 1 ms at 10 m/s; reports convert to ms), friction
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
    /// Fidelity tier: draft (400x8, characteristic, dt 1e-3), fast (700x8, characteristic,
    /// 5.7e-4; pockets deeper than 6×C_min go on on 600x24), paper (512x32, 4e-4, the paper's
    /// numerics) or fine (1024x16, BDF2, 2e-4); errors in docs/validation.md. --mesh, --dt and --time-scheme override its parts (with
    /// the characteristic scheme the step follows the mesh: 2·dx1/u).
    #[arg(long, value_enum, default_value_t = Fidelity::Fast)]
    pub fidelity: Fidelity,
    /// Mesh N1xN2: cells along x1 over 0.2 cm and along x2 over half a texture cell; the
    /// run stays on it (no deep-pocket mesh; nor with --dt or --time-scheme), N2 raised where a
    /// pocket would span fewer than 4 cells across (2 at draft), as in studies [default: from
    /// --fidelity].
    #[arg(long, value_name = "N1xN2", value_parser = parse_mesh)]
    pub mesh: Option<(usize, usize)>,
    /// Largest time step (units of L/U: ms at 10 m/s); the step used divides the texture
    /// period exactly. The characteristic scheme needs dt ≤ 2·dx1/u
    /// [default: from --fidelity; with the characteristic scheme 2·dx1/u of the mesh].
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
    #[command(flatten)]
    pub operating: OperatingArgs,
    #[command(flatten)]
    pub contact: ContactArgs,
    /// Relative tolerance of the periodic-regime test (estimated distance of the period-mean
    /// friction and Z from their periodic limits) [default: the tier's: 1e-3 for draft, 1e-4
    /// for fast, 1e-5 for paper and fine, as studies use them]
    #[arg(long = "periodic-tol", value_name = "TOL", allow_hyphen_values = true)]
    pub periodic_tol: Option<f64>,
    /// Give up after this much simulated time (units of L/U: ms at 10 m/s) and report
    /// converged = false.
    #[arg(
        long = "t-max",
        value_name = "T",
        allow_hyphen_values = true,
        default_value_t = 30.0
    )]
    pub t_max: f64,
    /// Initial state of the transient: equilibrium (untextured force balance, default) or
    /// paper (Z = 2.5 µm at rest, docs/model.md §4). The periodic answer does not depend on it.
    #[arg(long, value_enum, default_value_t = Start::Equilibrium)]
    pub start: Start,
    /// Time scheme of the film: characteristic (backward Euler along the Couette
    /// characteristics, at dt ≤ 2·dx1/u), bdf2 (second order) or backward-euler (first
    /// order), the last two in the ring's frame, where draft's and fast's step becomes dx1/u
    /// unless --dt is given [default: the tier's]
    #[arg(long = "time-scheme", value_enum)]
    pub time_scheme: Option<TimeScheme>,
    /// March every window plainly (no Anderson acceleration of the approach to the periodic
    /// regime; the stopping rule then reads the slow modes of the window means).
    #[arg(long = "no-accelerate")]
    pub no_accelerate: bool,
    /// Coarse approach to the periodic regime: run the ring's transient on a cheaper mesh and
    /// time step first (e.g. 120x4@3.3e-3), then carry the state over to the full mesh and run
    /// on to its own periodic regime (the answer is the full mesh's); `off` to run every step
    /// on the full mesh. [default: the tier's: 120x4 at its characteristic step 3.3e-3 for
    /// draft and fast, 128x4 at 1.6e-3 for fine, 512x8 at 4e-4 for paper]
    #[arg(long = "approach", value_name = "N1xN2@DT|off", value_parser = parse_approach)]
    pub approach: Option<ApproachArg>,
    /// Accept pockets that break thin-film validity (10⁴·l < 5·depth).
    #[arg(long = "allow-thick-pockets")]
    pub allow_thick_pockets: bool,
    #[command(flatten)]
    pub limits: LimitArgs,
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
    /// Write the film over the last period into DIR (created if missing): maps of the
    /// pressure, saturation and gap, centre-line profiles of p and h, Z(t) and f(t) with the
    /// instants marked (PNG), and each instant's fields as CSV. Runs the 2D transient.
    #[arg(long, value_name = "DIR")]
    pub snapshots: Option<PathBuf>,
    /// Instants of the last period that --snapshots draws, 1 to 100 (the paper's figures show
    /// ten, a–j).
    #[arg(long, value_name = "N", default_value_t = crate::snapshot::DEFAULT_FRAMES, requires = "snapshots")]
    pub frames: usize,
    /// Write an animation of the last period to FILE.gif: the pressure map and the
    /// centre-line profiles as the pockets pass under the ring. Runs the 2D transient.
    #[arg(long, value_name = "FILE.gif")]
    pub animate: Option<PathBuf>,
    /// Steps of the period between animation frames (at most 1000 frames a period) [default:
    /// about 30 frames a period].
    #[arg(long = "animate-stride", value_name = "K", requires = "animate")]
    pub animate_stride: Option<usize>,
}

pub(super) fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!(
            "expected a number of seconds ≥ 0 (e.g. 10), got {s:?}"
        )),
    }
}

pub(super) fn parse_radius(s: &str) -> Result<f64, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("inf") || t.eq_ignore_ascii_case("infinity") {
        return Ok(f64::INFINITY);
    }
    t.parse::<f64>()
        .map_err(|_| format!("expected a radius in cm (e.g. 0.8) or \"inf\", got {s:?}"))
}

/// `--R` of `optimise`: radii listed, or a range to sample.
#[derive(Clone, Debug, PartialEq)]
pub enum Radii {
    List(Vec<f64>),
    Range(f64, f64),
}

pub(super) fn parse_radii(s: &str) -> Result<Radii, String> {
    if s.contains("..") {
        let (lo, hi) = parse_range(s)?;
        return Ok(Radii::Range(lo, hi));
    }
    s.split(',')
        .map(parse_radius)
        .collect::<Result<Vec<_>, _>>()
        .map(Radii::List)
}

/// `--approach`: a mesh and time step, or `off`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApproachArg(pub Option<Approach>);

pub(super) fn parse_approach(s: &str) -> Result<ApproachArg, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("off") {
        return Ok(ApproachArg(None));
    }
    let bad = || {
        format!("expected a mesh and time step like 128x4@1.6e-3 (N1 ≥ 16, N2 ≥ 1, dt > 0), or \"off\", got {s:?}")
    };
    let (mesh, dt) = t.split_once('@').ok_or_else(bad)?;
    let (n1, n2) = parse_mesh(mesh).map_err(|_| bad())?;
    let dt: f64 = dt.trim().parse().map_err(|_| bad())?;
    if n1 < 16 || n2 < 1 || !(dt > 0.0 && dt.is_finite()) {
        return Err(bad());
    }
    Ok(ApproachArg(Some(Approach { n1, n2, dt })))
}

pub(super) fn parse_mesh(s: &str) -> Result<(usize, usize), String> {
    let err = || format!("expected N1xN2 with whole numbers, e.g. 512x32, got {s:?}");
    let (a, b) = s.split_once(['x', 'X']).ok_or_else(err)?;
    let n1 = a.trim().parse::<usize>().map_err(|_| err())?;
    let n2 = b.trim().parse::<usize>().map_err(|_| err())?;
    Ok((n1, n2))
}
