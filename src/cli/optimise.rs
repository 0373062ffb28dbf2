//! `texopt optimise --R R`: the settings from flags, else a `--config` file, else the
//! defaults; then the optimiser's driver and its report.

use std::path::{Path, PathBuf};

use super::args::{DesignFile, DesignFileOf, Radii, SearchArgs};
use super::{
    directory_can_be_made, flag, input_message, install_ctrl_c, open_cache, CmdError,
    OperatingArgs, OptimiseArgs, STOP,
};
use crate::model::case::{CaseSpec, InputError, Texture};
use crate::model::operating::Validity;
use crate::optimise::design_report::table;
use crate::optimise::driver::{optimise, Settings};
use crate::optimise::robust::{robust, table as robust_table};
use crate::optimise::search::{SearchSettings, SwarmSettings};
use crate::optimise::space::{Bounds, Constraints, Space};
use crate::snapshot::{run_recorded, write_all, Context, Request};
use crate::time::Overrides;
use crate::time::{short, steps_per_period, Fidelity, Limits, RunOptions, MIN_STEPS_PER_PERIOD};

pub(super) fn run(a: &OptimiseArgs) -> Result<i32, CmdError> {
    let file = config(a)?;
    let radii = radii(a, &file)?;
    let all = radii
        .iter()
        .map(|&r| settings(a, &file, r))
        .collect::<Result<Vec<_>, _>>()?;
    let out_dir = all[0].search.out_dir.clone().unwrap_or_default();
    if let Some(dir) = &a.snapshots {
        if all.len() > 1 {
            return Err(CmdError::Input(format!(
                "--snapshots {}: the fields are drawn for one radius; give --R one value",
                dir.display()
            )));
        }
        for sub in SNAPSHOT_DIRS {
            crate::snapshot::prepare_dir(&dir.join(sub))
                .map_err(|e| CmdError::Input(format!("--snapshots {}: {e}", dir.display())))?;
        }
    }
    let cache = open_cache(a.cache.as_deref())?;
    install_ctrl_c();
    let cache = std::sync::Mutex::new(cache);
    if all.len() > 1 {
        let report = robust(&all, &cache, &STOP).map_err(|e| CmdError::Other(e.to_string()))?;
        if a.json {
            println!(
                "{}",
                serde_json::to_string_pretty(&report).unwrap_or_default()
            );
        } else {
            print!("{}", robust_table(&report));
            eprintln!(
                "wrote {}/{}.json, .csv, .md, .png and optimise_R<R>.* for each R",
                out_dir.display(),
                report.name
            );
        }
        return Ok(0);
    }
    let settings = &all[0];
    let report = optimise(settings, &cache, &STOP).map_err(|e| CmdError::Other(e.to_string()))?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report).unwrap_or_default()
        );
    } else {
        print!("{}", table(&report));
        eprintln!(
            "wrote {}/optimise_R{}.json, .csv, _front.png, _cells.png, _z_t.png, _f_t.png",
            out_dir.display(),
            report.r
        );
    }
    if let Some(dir) = &a.snapshots {
        let best = report.best_friction.texture.clone();
        for (sub, texture) in SNAPSHOT_DIRS.iter().zip([best, None]) {
            snapshots(settings, texture, &dir.join(sub)).map_err(CmdError::Other)?;
        }
    }
    Ok(0)
}

/// Where `--snapshots` puts the best-friction design's film and the plain liner's.
const SNAPSHOT_DIRS: [&str; 2] = ["best_friction", "plain_liner"];

/// The film of the last period of the ring on `texture` (None: the plain liner, as a 2D
/// transient) at the reported fidelity, drawn into `dir`.
fn snapshots(s: &Settings, texture: Option<Texture>, dir: &Path) -> Result<(), String> {
    let case = CaseSpec {
        texture,
        ..s.base.clone()
    };
    let num = crate::time::resolve(s.search.report_fidelity, &s.search.overrides, &case);
    let request = Request {
        frames: crate::snapshot::DEFAULT_FRAMES,
        animation_stride: None,
    };
    crate::snapshot::check_request(&request, &case, &num).map_err(|e| e.to_string())?;
    let (_, rec) = run_recorded(&case, &num, &RunOptions::default(), request, None)
        .map_err(|e| e.to_string())?;
    let written =
        write_all(dir, &rec, &Context::new(&case, s.scales, &rec)).map_err(|e| e.to_string())?;
    eprintln!(
        "snapshots: {} files in {}",
        written.files.len(),
        dir.display()
    );
    Ok(())
}

/// Most radii one run designs for (each is a full optimisation).
const MAX_RADII: usize = 16;
/// The largest face radius designed for (cm): 100 m, flat to any film.
const MAX_R_CM: f64 = 1e4;

/// The radii of `--R`: one, a list (sorted, repeats dropped), or a range sampled at
/// `--radii` geometrically spaced values rounded to 3 significant digits (so that the file
/// names read well and a rerun finds its designs in the cache).
fn radii(a: &OptimiseArgs, file: &DesignFile) -> Result<Vec<f64>, CmdError> {
    let count = a.radii.or(file.radii);
    let count_name = match a.radii {
        Some(_) => "--radii".to_string(),
        None => config_key(a, "radii"),
    };
    let mut v = match &a.r {
        Radii::List(v) => {
            if count.is_some() {
                return Err(CmdError::Input(format!(
                    "{count_name}: applies to a range of radii (--R LO..HI); a list gives its radii itself"
                )));
            }
            v.clone()
        }
        Radii::Range(lo, hi) => range_radii(*lo, *hi, count.unwrap_or(4), &count_name)?,
    };
    // Every design is weighed against the plain liner on the same ring; under a flat ring the
    // plain liner has no converging wedge and carries no load, so there is nothing to weigh
    // against (a textured flat ring simulates: `texopt simulate --R inf …`).
    if v.iter().any(|r| r.is_infinite()) {
        return Err(CmdError::Input(
            "--R = inf: the optimiser weighs each texture against the plain liner, which under a flat ring carries no load (no converging wedge); give a finite face radius, or simulate textured flat rings with `texopt simulate --R inf`".into(),
        ));
    }
    if let Some(r) = v.iter().find(|r| **r > MAX_R_CM) {
        return Err(CmdError::Input(format!(
            "--R = {}: above {} cm a ring is flat to the film (its crown over the ring's width is far below any film), and the plain liner it is weighed against carries no load; give a face radius up to {} cm",
            short(*r),
            short(MAX_R_CM),
            short(MAX_R_CM)
        )));
    }
    v.sort_by(f64::total_cmp);
    // Reports and file names give radii to 3 significant digits: two radii alike to those
    // digits would be designed twice under one name.
    if let Some(w) = v
        .windows(2)
        .find(|w| format!("{:.2e}", w[0]) == format!("{:.2e}", w[1]))
    {
        return Err(CmdError::Input(format!(
            "--R: {} and {} are one radius to the 3 significant digits reports name radii by; give distinct radii",
            w[0], w[1]
        )));
    }
    if v.len() > MAX_RADII {
        return Err(CmdError::Input(format!(
            "--R: {} radii; give at most {MAX_RADII}",
            v.len()
        )));
    }
    Ok(v)
}

/// `n` radii from `lo` to `hi`, geometrically spaced, ends included, rounded to 3 significant
/// digits; a range so narrow that rounding would merge some is refused (it would design for
/// fewer radii than asked, or for one).
fn range_radii(lo: f64, hi: f64, n: usize, count_name: &str) -> Result<Vec<f64>, CmdError> {
    let (lo_s, hi_s) = (short(lo), short(hi));
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi) {
        return Err(CmdError::Input(format!(
            "--R {lo_s}..{hi_s}: a range of radii needs 0 < LO < HI, both finite (cm)"
        )));
    }
    if hi > MAX_R_CM {
        return Err(CmdError::Input(format!(
            "--R {lo_s}..{hi_s}: above {} cm a ring is flat to the film, and the plain liner it is weighed against carries no load; end the range at most at {} cm",
            short(MAX_R_CM),
            short(MAX_R_CM)
        )));
    }
    if n == 1 {
        return Err(CmdError::Input(format!(
            "{count_name} = 1: a range is sampled at 2 to {MAX_RADII} radii; for one radius give --R alone (e.g. --R {lo_s})"
        )));
    }
    if !(2..=MAX_RADII).contains(&n) {
        return Err(CmdError::Input(format!(
            "{count_name} = {n}: sample a range at 2 to {MAX_RADII} radii"
        )));
    }
    let sample = |n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| {
                let x = lo * (hi / lo).powf(i as f64 / (n - 1) as f64);
                format!("{x:.2e}").parse().unwrap_or(x)
            })
            .collect()
    };
    let distinct = |v: &[f64]| v.windows(2).all(|w| w[0] != w[1]);
    let v = sample(n);
    if distinct(&v) {
        return Ok(v);
    }
    let kept: Vec<String> = {
        let mut u = v.clone();
        u.dedup();
        u.iter().map(|r| short(*r)).collect()
    };
    Err(CmdError::Input(
        match (2..n).rev().find(|&m| distinct(&sample(m))) {
            Some(m) => format!(
                "--R {lo_s}..{hi_s} --radii {n}: radii are rounded to 3 significant digits (as the reports name them), which leaves only {} distinct ones here ({}); ask --radii {m}, or widen the range",
                kept.len(),
                kept.join(", ")
            ),
            None => format!(
                "--R {lo_s}..{hi_s}: the range is narrower than the rounding of radii to 3 significant digits (both ends give R = {}); give one radius (--R {}) or a wider range",
                kept[0], kept[0]
            ),
        },
    ))
}

/// The operating flags, else the config file's.
fn operating(a: &OptimiseArgs, f: &DesignFile) -> OperatingArgs {
    a.operating.or(OperatingArgs {
        speed: f.speed,
        load: f.load,
        viscosity: f.viscosity,
        ring_width: f.ring_width,
        ring_mass: f.ring_mass,
        d_oil: f.d_oil,
        roughness: f.roughness,
    })
}

/// The settings of a run for ring radius `r`: each from its flag, else the config file, else
/// its default; every one checked before anything runs.
fn settings(a: &OptimiseArgs, file: &DesignFile, r: f64) -> Result<Settings, CmdError> {
    let (op, validity) = operating(a, file).resolve()?;
    let mut base = CaseSpec::paper(r);
    op.apply(&mut base);
    validity.apply(&mut base);
    base.validate(false)?;
    let space = space(a, file);
    space.validate().map_err(|e| space_error(&e))?;
    let in_file = |key: &str| config_key(a, key);
    let balanced = balanced(a, file, &in_file)?;
    let out_dir = a
        .out
        .clone()
        .or(file.out.clone())
        .unwrap_or_else(|| PathBuf::from("results/optimise"));
    let search = search_settings(
        &a.search,
        SearchKeys::of(file),
        &in_file,
        (space, validity),
        out_dir,
        true,
    )?;
    let settings = Settings {
        base,
        scales: op.scales(),
        search,
        balanced,
    };
    check_corners(&settings)?;
    Ok(settings)
}

/// The search keys of a `--config` file or an engine file's `[design]`.
pub(super) struct SearchKeys {
    fidelity: Option<Fidelity>,
    search_fidelity: Option<Fidelity>,
    particles: Option<usize>,
    iterations: Option<u64>,
    seed: Option<u64>,
}

impl SearchKeys {
    pub(super) fn of(f: &DesignFile) -> SearchKeys {
        SearchKeys {
            fidelity: f.fidelity,
            search_fidelity: f.search_fidelity,
            particles: f.particles,
            iterations: f.iterations,
            seed: f.seed,
        }
    }
}

/// The settings every search shares: each from its flag, else the file's key (named by
/// `in_file`), else its default; the numerics' overrides, the swarm's sizes, the output
/// directory and the limits checked before anything runs.
pub(super) fn search_settings(
    a: &SearchArgs,
    file: SearchKeys,
    in_file: &dyn Fn(&str) -> String,
    (space, validity): (Space, Validity),
    out_dir: PathBuf,
    progress: bool,
) -> Result<SearchSettings, CmdError> {
    let (particles, iterations) = swarm_sizes(
        (a.particles, file.particles),
        (a.iterations, file.iterations),
        in_file,
    )?;
    let overrides = overrides(a.mesh, a.dt, &space)?;
    // A directory that cannot be made stops the search now, not after its simulations.
    directory_can_be_made(&out_dir).map_err(|why| {
        CmdError::Input(format!(
            "--out {}: cannot create it: {why}; choose another directory",
            out_dir.display()
        ))
    })?;
    Ok(SearchSettings {
        space,
        validity,
        search_fidelity: a
            .search_fidelity
            .or(file.search_fidelity)
            .unwrap_or(SearchSettings::SEARCH_FIDELITY),
        report_fidelity: a
            .fidelity
            .or(file.fidelity)
            .unwrap_or(SearchSettings::REPORT_FIDELITY),
        overrides,
        swarm: SwarmSettings {
            particles,
            iterations,
            seed: a.seed.or(file.seed).unwrap_or(SwarmSettings::DEFAULT.seed),
        },
        jobs: a.jobs.unwrap_or_else(SearchSettings::default_jobs),
        limits: a.limits.limits()?,
        progress,
        out_dir: Some(out_dir),
    })
}

/// Most particles a swarm, iterations a search and balanced searches a run: typo guards,
/// checked before anything runs (every particle of every iteration is a simulation; the
/// defaults are in `SwarmSettings::DEFAULT`, one balanced search).
pub(super) const MAX_PARTICLES: usize = 10_000;
pub(super) const MAX_ITERATIONS: u64 = 100_000;
pub(super) const MAX_BALANCED: usize = 100;

/// The `--config` file's key `key`, as an error names it.
fn config_key(a: &OptimiseArgs, key: &str) -> String {
    let file = a.config.as_deref().unwrap_or(Path::new("-"));
    format!("--config {}: {key}", file.display())
}

/// Particles per swarm and iterations per search: each its flag's value, else the file's
/// (named by `in_file` of its key), else the default; within [2, MAX_PARTICLES] and
/// [1, MAX_ITERATIONS].
pub(super) fn swarm_sizes(
    (particles_flag, particles_file): (Option<usize>, Option<usize>),
    (iterations_flag, iterations_file): (Option<u64>, Option<u64>),
    in_file: &dyn Fn(&str) -> String,
) -> Result<(usize, u64), CmdError> {
    let particles = within(
        (
            particles_flag.map(|n| n as u64),
            particles_file.map(|n| n as u64),
        ),
        ("--particles", "particles"),
        in_file,
        (
            2,
            SwarmSettings::DEFAULT.particles as u64,
            MAX_PARTICLES as u64,
        ),
        "particles per swarm",
    )?;
    let iterations = within(
        (iterations_flag, iterations_file),
        ("--iterations", "iterations"),
        in_file,
        (1, SwarmSettings::DEFAULT.iterations, MAX_ITERATIONS),
        "swarm iterations per search",
    )?;
    Ok((particles as usize, iterations))
}

/// A count from its flag, else its file key, else the default (`lo, default, hi`), checked
/// to lie in lo..=hi; the error names where it came from.
fn within(
    (flag, file): (Option<u64>, Option<u64>),
    (flag_name, key): (&str, &str),
    in_file: &dyn Fn(&str) -> String,
    (lo, default, hi): (u64, u64, u64),
    what: &str,
) -> Result<u64, CmdError> {
    let (n, name) = match (flag, file) {
        (Some(n), _) => (n, flag_name.to_string()),
        (None, Some(n)) => (n, in_file(key)),
        (None, None) => return Ok(default),
    };
    if (lo..=hi).contains(&n) {
        Ok(n)
    } else {
        Err(CmdError::Input(format!(
            "{name} = {n}: {what} must be a whole number from {lo} to {hi}"
        )))
    }
}

/// The weights of the balanced searches: the flag's, else the file's, else one of 0.5; at
/// most [`MAX_BALANCED`], each strictly between 0 and 1.
fn balanced(
    a: &OptimiseArgs,
    file: &DesignFile,
    in_file: &dyn Fn(&str) -> String,
) -> Result<Vec<f64>, CmdError> {
    let (weights, name) = match (&a.balanced, &file.balanced) {
        (Some(w), _) => (w.clone(), "--balanced".to_string()),
        (None, Some(w)) => (w.clone(), in_file("balanced")),
        (None, None) => return Ok(vec![0.5]),
    };
    if weights.is_empty() || weights.len() > MAX_BALANCED {
        return Err(CmdError::Input(format!(
            "{name}: {} weights; give 1 to {MAX_BALANCED} (each a balanced search)",
            weights.len()
        )));
    }
    if let Some(w) = weights.iter().find(|w| !(**w > 0.0 && **w < 1.0)) {
        return Err(CmdError::Input(format!(
            "{name} = {w}: each weight must lie strictly between 0 and 1"
        )));
    }
    Ok(weights)
}

/// The dearest designs sit at the corners of the design space (widest cells, smallest
/// pockets: the tiers raise N2 to resolve them): each corner's run at either tier must stay
/// within the run limits, or the search is refused before it starts.
fn check_corners(s: &Settings) -> Result<(), CmdError> {
    let ss = &s.search;
    check_design_space(
        &s.base,
        &ss.space,
        [ss.search_fidelity, ss.report_fidelity],
        &ss.overrides,
        &ss.limits,
    )
}

/// Every corner of the design space on `base`, at each fidelity with the overrides: within
/// the run limits and valid numerics (a `--dt` above the characteristic step 2·dx1/u of a
/// tier's mesh, a `--mesh` too coarse for a corner's pockets), checked before any search.
pub(super) fn check_design_space(
    base: &CaseSpec,
    space: &Space,
    fidelities: [Fidelity; 2],
    overrides: &Overrides,
    limits: &Limits,
) -> Result<(), CmdError> {
    let n = space.dim();
    for corner in 0..(1usize << n) {
        let u: Vec<f64> = (0..n).map(|k| ((corner >> k) & 1) as f64).collect();
        let case = CaseSpec {
            texture: Some(space.decode(&u)),
            ..base.clone()
        };
        for fidelity in fidelities {
            let num = crate::time::resolve(fidelity, overrides, &case);
            // Over the run limits the bounds are the fix; invalid numerics say their own.
            let checked = match crate::time::limits::check(&case, &num, limits) {
                Err(e) => Err((e, "; narrow the bounds")),
                Ok(()) => num.validate(&case).map_err(|e| (e, "")),
            };
            if let Err((e, fix)) = checked {
                return Err(CmdError::Input(format!(
                    "the design space reaches {} (at fidelity {}): {}{fix}",
                    case.label(),
                    fidelity.name(),
                    input_message(&e, flag)
                )));
            }
        }
    }
    Ok(())
}

/// The `--config` file's settings (none without one).
fn config(a: &OptimiseArgs) -> Result<DesignFile, CmdError> {
    let Some(p) = &a.config else {
        return Ok(DesignFile::default());
    };
    let text = std::fs::read_to_string(p)
        .map_err(|e| CmdError::Input(format!("--config {}: cannot read it: {e}", p.display())))?;
    let file: DesignFile = toml::from_str(&text).map_err(|e| {
        CmdError::Input(format!(
            "--config {}: {}",
            p.display(),
            crate::model::case::one_line(&e.to_string())
        ))
    })?;
    match file.foreign_key(DesignFileOf::Optimise) {
        Some(k) => Err(CmdError::Input(format!(
            "--config {}: unknown field `{k}`: a key of an engine file's [design], not of `optimise --config`",
            p.display()
        ))),
        None => Ok(file),
    }
}

/// The design space: bounds and constraints from the flags, the file, the defaults.
fn space(a: &OptimiseArgs, file: &DesignFile) -> Space {
    SpaceKeys {
        l1: a.l1.or(file.l1),
        l2: a.l2.or(file.l2),
        per: a.per.or(file.per),
        free_width: a.free_width.or(file.free_width),
        depth: a.depth.or(file.depth),
        w_min_um: a.w_min.or(file.w_min),
        max_area: a.max_area.or(file.max_area),
        max_depth_ratio: a.max_depth_ratio.or(file.max_depth_ratio),
        allow_thick: a.allow_thick_pockets || file.allow_thick_pockets.unwrap_or(false),
    }
    .space()
}

/// The keys of a design space as flags, `--config` files and engine files give them (ranges
/// in cm and µm, the least wall in µm); absent ones take `optimise`'s defaults.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SpaceKeys {
    pub(super) l1: Option<(f64, f64)>,
    pub(super) l2: Option<(f64, f64)>,
    pub(super) per: Option<(f64, f64)>,
    pub(super) free_width: Option<(f64, f64)>,
    pub(super) depth: Option<(f64, f64)>,
    pub(super) w_min_um: Option<f64>,
    pub(super) max_area: Option<f64>,
    pub(super) max_depth_ratio: Option<f64>,
    pub(super) allow_thick: bool,
}

impl SpaceKeys {
    pub(super) fn space(self) -> Space {
        let (d, c) = (Bounds::default(), Constraints::default());
        Space {
            bounds: Bounds {
                l1: self.l1.unwrap_or(d.l1),
                l2: self.l2.unwrap_or(d.l2),
                per: self.per.unwrap_or(d.per),
                width: self.free_width,
                depth: self.depth.unwrap_or(d.depth),
            },
            cons: Constraints {
                w_min: self.w_min_um.map_or(c.w_min, |um| um * 1e-4),
                max_area: self.max_area,
                max_depth_ratio: self.max_depth_ratio,
                allow_thick: self.allow_thick,
            },
        }
    }
}

/// A design-space error in flag names (the free width across sliding is `--free-width`).
pub(super) fn space_error(e: &InputError) -> CmdError {
    space_error_named(e, |p| match p {
        "width" => "--free-width".into(),
        "constraints" => "constraints".into(),
        other => flag(other),
    })
}

/// A design space's error, its inputs named by `name` (flags, or a file's keys).
pub(super) fn space_error_named(e: &InputError, name: impl Fn(&str) -> String) -> CmdError {
    // The least wall is given in µm (the space holds cm): said in the unit it was given in.
    let in_um;
    let e = match e.value.parse::<f64>() {
        Ok(cm) if e.param == "w_min" => {
            in_um = InputError {
                value: format!("{} µm", short(cm * 1e4)),
                rule: "the least wall thickness must be ≥ 0".into(),
                ..e.clone()
            };
            &in_um
        }
        _ => e,
    };
    CmdError::Input(input_message(e, name))
}

/// `--mesh` and `--dt` as the numerics' overrides, checked before any search (`--dt` against
/// the shortest texture period of the design space: u = 1 in every scaled case, the speed
/// being the velocity scale, docs/model.md §1).
pub(super) fn overrides(
    mesh: Option<(usize, usize)>,
    dt: Option<f64>,
    space: &Space,
) -> Result<Overrides, CmdError> {
    if let Some(dt) = dt {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(CmdError::Input(format!(
                "--dt {}: must be a finite number > 0",
                short(dt)
            )));
        }
        let period = space.bounds.per.0;
        let steps = steps_per_period(period, dt);
        if steps < MIN_STEPS_PER_PERIOD as f64 {
            return Err(CmdError::Input(format!(
                "--dt {}: gives only {steps} time steps per texture period at the shortest period (per from {} cm), where at least {MIN_STEPS_PER_PERIOD} are needed: --dt ≤ {}",
                short(dt),
                short(period),
                short(period / MIN_STEPS_PER_PERIOD as f64)
            )));
        }
    }
    if let Some((n1, n2)) = mesh {
        if n1 < 16 || n2 < 1 {
            return Err(CmdError::Input(format!(
                "--mesh {n1}x{n2}: needs at least 16 cells along x1 and 1 along x2"
            )));
        }
    }
    Ok(Overrides {
        n1: mesh.map(|m| m.0),
        n2: mesh.map(|m| m.1),
        dt,
        ..Default::default()
    })
}
