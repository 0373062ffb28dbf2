//! `texopt cycle ENGINE.toml`: the engine file checked, the design settings from its
//! `[design]` section and the flags, then the zones' designs, the three liners over the cycle
//! and the report.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::args::{CycleArgs, DesignFile, DesignFileOf};
use super::cycle_slurm::SlurmRunner;
use super::optimise::{
    check_design_space, search_settings, space_error_named, SearchKeys, SpaceKeys,
};
use super::{checked, flag, input_message, install_ctrl_c, open_cache, CmdError, STOP};
use crate::model::case::short;
use crate::model::engine::{three_digits, zone_label, Engine, LinerZones, STEP_RANGE_DEG};
use crate::model::operating::Validity;
use crate::optimise::cycle::angles::{
    design_all, evaluate_liners, points, CycleSettings, NoAngleInside,
};
use crate::optimise::cycle::angles_report::{assemble, table, write};
use crate::optimise::cycle::bands::BandSpace;
use crate::optimise::cycle::map_report;
use crate::optimise::cycle::map_runs::{lock, run_here, Here, MapBatch, Runner};
use crate::optimise::cycle::map_search::{design_over_map, evaluate_over_map, MapJudge};
use crate::optimise::cycle::transient_liners::{evaluate_transient, ring_case};
use crate::optimise::cycle::transient_report;
use crate::optimise::cycle::transient_search::design_over_cycle;
use crate::optimise::error::OptimiseError;
use crate::optimise::space::Space;
use crate::study::engine_file;
use crate::time::cycle::{cycle_numerics, Drive};

pub(super) fn run(a: &CycleArgs) -> Result<i32, CmdError> {
    let (s, band_min_file) = settings(a)?;
    if s.engine.has_map() && !a.bands {
        return Err(input(
            &a.file,
            "[[operating]]: the operating map is what --bands designs for; add --bands, or remove the map to design the zones at the engine's own point",
        ));
    }
    if !a.bands && a.band_min.is_some() {
        return Err(CmdError::Input(
            "--band-min: the least band length of --bands; add --bands, or drop --band-min".into(),
        ));
    }
    if !a.quasi_steady {
        refuse_angle_by_angle_flags(a)?;
    } else if a.slurm.is_some() || a.answer.is_some() {
        return Err(CmdError::Input(
            "--slurm: the transient searches' runs (the zones' and --bands'); the angle-by-angle evaluation runs here. Drop --quasi-steady, or drop --slurm".into(),
        ));
    }
    if let Some(batch) = &a.answer {
        return answer_share(a, &s, batch);
    }
    if a.bands {
        let space = band_space(a, &s, band_min_file)?;
        check_cycle_limits(&s)?;
        return run_bands(a, &s, &space);
    }
    if !a.quasi_steady {
        check_cycle_limits(&s)?;
        return run_transient(a, &s);
    }
    // A cycle whose every design angle is outside the model before anything runs (an engine
    // far too fast or too loaded for the validated Stribeck range) is an input error.
    let design_points = points(&s, s.design_step_deg);
    if design_points.iter().all(|p| p.excluded.is_some()) {
        return Err(input(&a.file, NoAngleInside::of(&design_points)));
    }
    // The design space on the first point inside the model (u = 1 and the ring's width in
    // every scaled case: one case stands for all).
    if let Some(p) = points(&s, s.step_deg).iter().find(|p| p.excluded.is_none()) {
        let ss = &s.search;
        check_design_space(
            &p.base,
            &ss.space,
            [ss.search_fidelity, ss.report_fidelity],
            &ss.overrides,
            &ss.limits,
        )?;
    }
    let cache = open_cache(a.cache.as_deref())?;
    install_ctrl_c();
    let cache = std::sync::Mutex::new(cache);
    let t0 = std::time::Instant::now();
    let searched = design_all(&s, &cache, &STOP).map_err(|e| CmdError::Other(e.to_string()))?;
    if s.search.progress {
        eprintln!(
            "[{:6.1} s] the three liners at {} every {}°",
            t0.elapsed().as_secs_f64(),
            s.search.report_fidelity.name(),
            s.step_deg
        );
    }
    let (d, ev) = evaluate_liners(&s, &searched, &cache, &STOP)
        .map_err(|e| CmdError::Other(e.to_string()))?;
    let r = assemble(&s, &d, &ev, t0.elapsed().as_secs_f64());
    report_out(a, &s, &r, table, |dir| write(dir, &r))
}

/// A cycle report out, the same for the three modes: checked (crate::finite), printed (its
/// JSON with --json, else its table), then its files written under the output directory.
fn report_out<R: serde::Serialize>(
    a: &CycleArgs,
    s: &CycleSettings,
    r: &R,
    table: fn(&R) -> String,
    write: impl FnOnce(&Path) -> Result<Vec<PathBuf>, OptimiseError>,
) -> Result<i32, CmdError> {
    checked(r)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(r).unwrap_or_default());
    } else {
        print!("{}", table(r));
    }
    if let Some(dir) = &s.search.out_dir {
        for f in write(dir).map_err(|e| CmdError::Other(e.to_string()))? {
            eprintln!("wrote {}", f.display());
        }
    }
    Ok(0)
}

/// Every transient cycle run a search may make, against the run limits before anything runs:
/// the plain liner and the design space's corners (its finest textures) at the search's and
/// the report's fidelity, each bounded by its crank steps with pockets under the ring all
/// the way.
fn check_cycle_limits(s: &CycleSettings) -> Result<(), CmdError> {
    let ss = &s.search;
    let drive = Drive::new(&s.engine);
    let ring = ring_case(s, &drive);
    let n = ss.space.dim();
    let corners = (0..1usize << n).map(|c| {
        let u: Vec<f64> = (0..n).map(|k| ((c >> k) & 1) as f64).collect();
        Some(ss.space.decode(&u))
    });
    for texture in std::iter::once(None).chain(corners) {
        for fidelity in [ss.search_fidelity, ss.report_fidelity] {
            let num = cycle_numerics(fidelity, &ss.overrides, &ring, texture.as_ref());
            num.check(&drive, &ss.limits).map_err(|e| {
                let liner = match &texture {
                    None => "the plain liner".to_string(),
                    Some(t) => format!("the design space reaches {}", t.rounded_label()),
                };
                CmdError::Input(format!(
                    "{liner} (at fidelity {}): {}",
                    fidelity.name(),
                    input_message(&e, flag)
                ))
            })?;
        }
    }
    Ok(())
}

/// The transient cycle: the zones' designs searched over the whole cycle as one transient,
/// then the plain, uniform and zoned liners judged over it at the report's fidelity.
fn run_transient(a: &CycleArgs, s: &CycleSettings) -> Result<i32, CmdError> {
    let t0 = std::time::Instant::now();
    let cache = Mutex::new(open_cache(a.cache.as_deref())?);
    let slurm = slurm_runner(a, s)?;
    let runner: &dyn Runner = match &slurm {
        Some(r) => r,
        None => &Here,
    };
    let judge = MapJudge::new(s).through(&cache, runner);
    let designs = design_over_cycle(s, &judge).map_err(|e| CmdError::Other(e.to_string()))?;
    if s.search.progress {
        eprintln!(
            "[{:6.1} s] the liners through the cycle at {} …",
            t0.elapsed().as_secs_f64(),
            s.search.report_fidelity.name()
        );
    }
    let (d, liners) =
        evaluate_transient(s, &designs).map_err(|e| CmdError::Other(e.to_string()))?;
    let r = transient_report::assemble(s, &d, &liners, t0.elapsed().as_secs_f64());
    report_out(a, s, &r, transient_report::table, |dir| {
        transient_report::write(dir, &r)
    })
}

/// The liner in bands: searched over the map, then plain, uniform and banded at the report's
/// fidelity.
fn run_bands(a: &CycleArgs, s: &CycleSettings, space: &BandSpace) -> Result<i32, CmdError> {
    let t0 = std::time::Instant::now();
    let other = |e: OptimiseError| CmdError::Other(e.to_string());
    let cache = Mutex::new(open_cache(a.cache.as_deref())?);
    let slurm = slurm_runner(a, s)?;
    let runner: &dyn Runner = match &slurm {
        Some(r) => r,
        None => &Here,
    };
    let designs = design_over_map(s, space, &cache, runner).map_err(other)?;
    let liners = evaluate_over_map(s, &designs, &cache, runner).map_err(other)?;
    let r = map_report::assemble(s, &designs, &liners, t0.elapsed().as_secs_f64());
    report_out(a, s, &r, map_report::table, |dir| {
        map_report::write(dir, &r, &liners)
    })
}

/// The Slurm runner `--slurm DIR` asks for, if it does.
fn slurm_runner(a: &CycleArgs, s: &CycleSettings) -> Result<Option<SlurmRunner>, CmdError> {
    let Some(dir) = &a.slurm else {
        return Ok(None);
    };
    let runner = SlurmRunner::new(dir, &a.cluster, &s.engine.file.engine.name)?;
    if s.search.progress {
        eprintln!("the searches' runs as {}", runner.describe());
    }
    Ok(Some(runner))
}

/// A Slurm task of `--slurm`: its share of a batch's runs into its cache.
fn answer_share(a: &CycleArgs, s: &CycleSettings, file: &Path) -> Result<i32, CmdError> {
    let (i, n) = a.share.unwrap_or((1, 1));
    let read = std::fs::read_to_string(file)
        .map_err(|e| e.to_string())
        .and_then(|t| serde_json::from_str::<MapBatch>(&t).map_err(|e| e.to_string()));
    let batch = read.map_err(|e| {
        CmdError::Input(format!(
            "--answer {}: {e}; give a batch that `cycle --bands --slurm` wrote",
            file.display()
        ))
    })?;
    let cache = Mutex::new(open_cache(a.cache.as_deref())?);
    let share = batch.share(i, n);
    let judge = match batch.report {
        true => MapJudge::new(s).reporting(),
        false => MapJudge::new(s),
    };
    let ran =
        run_here(&judge, &batch, share, &cache).map_err(|e| CmdError::Other(e.to_string()))?;
    eprintln!(
        "share {i}/{n} of {}: {} runs, {ran} run here, {} found in {}",
        file.display(),
        share.len(),
        share.len() - ran,
        lock(&cache).path().display()
    );
    Ok(0)
}

/// The band space: the design space's textures, the least band length from --band-min, else
/// the file's `[design] band_min_mm`, else [`BAND_MIN_MM`].
fn band_space(a: &CycleArgs, s: &CycleSettings, file: Option<f64>) -> Result<BandSpace, CmdError> {
    let stroke = s.engine.file.engine.stroke_mm;
    let min = a.band_min.or(file).unwrap_or(BAND_MIN_MM);
    BandSpace::new(s.search.space.clone(), stroke, min).map_err(|e| {
        let named = match (a.band_min, file) {
            (None, Some(_)) => input(&a.file, format!("[design] band_min_mm = {}", short(min))),
            _ => CmdError::Input(format!("--band-min {}", short(min))),
        };
        match named {
            CmdError::Input(m) => CmdError::Input(format!("{m}: {e}")),
            other => other,
        }
    })
}

/// Default least band length (mm): a laser-textured band's least practical width, several
/// texture periods (the longest period of the design space is 0.6 mm).
pub const BAND_MIN_MM: f64 = 4.0;

fn input(file: &Path, m: impl std::fmt::Display) -> CmdError {
    CmdError::Input(format!("{}: {m}", file.display()))
}

/// The engine and the design's settings: each from its flag, else the file's `[design]`,
/// else its default; all checked before anything runs.
fn settings(a: &CycleArgs) -> Result<(CycleSettings, Option<f64>), CmdError> {
    let text = std::fs::read_to_string(&a.file)
        .map_err(|e| input(&a.file, format!("cannot read the engine file: {e}")))?;
    let (engine, zones, d): (Engine, LinerZones, DesignFile) =
        engine_file::parse(&text).map_err(|e| input(&a.file, e))?;
    if let Some(k) = d.foreign_key(DesignFileOf::Engine) {
        return Err(input(
            &a.file,
            format!("[design] unknown field `{k}`: a key of `optimise --config`, not of an engine file's [design]"),
        ));
    }
    let (validity, min_clearance_um) = validity(&a.file, &d)?;
    // A step is named where it came from: the flag, else the engine file's key.
    let named = |flag: Option<f64>, file: Option<f64>, name: &'static str, key: &'static str| match (
        flag, file,
    ) {
        (None, Some(_)) => key,
        _ => name,
    };
    let step_deg = step(
        (&engine, &zones),
        named(a.step, d.step_deg, "--step", "[design] step_deg"),
        a.step.or(d.step_deg),
        5.0,
    )?;
    let design_step_deg = step(
        (&engine, &zones),
        named(
            a.design_step,
            d.design_step_deg,
            "--design-step",
            "[design] design_step_deg",
        ),
        a.design_step.or(d.design_step_deg),
        20.0,
    )?;
    let space = space(&d);
    // The design space is the engine file's: its errors name the file's keys.
    space
        .validate()
        .map_err(|e| {
            space_error_named(&e, |p| match p {
                "width" => "[design] free_width".into(),
                "constraints" => "[design] constraints".into(),
                other => format!("[design] {other}"),
            })
        })
        .map_err(|e| match e {
            CmdError::Input(m) => input(&a.file, m),
            other => other,
        })?;
    let in_file = |key: &str| format!("{}: [design] {key}", a.file.display());
    let out_dir = a.out.clone().unwrap_or_else(|| {
        let kind = match (a.quasi_steady, a.bands) {
            (true, _) => "_quasi_steady",
            (false, true) => "_bands",
            (false, false) => "",
        };
        PathBuf::from(format!("results/cycle_{}{kind}", engine.file.engine.name))
    });
    let search = search_settings(
        &a.search,
        SearchKeys::of(&d),
        &in_file,
        (space, validity),
        out_dir,
        !a.json,
    )?;
    Ok((
        CycleSettings {
            search,
            min_clearance_um,
            step_deg,
            design_step_deg,
            engine,
            zones,
        },
        d.band_min_mm,
    ))
}

/// The angle-by-angle steps and the periodic runs' time step mean nothing to the transient
/// cycle, whose steps follow the crank (docs/model.md §12): a flag that would be ignored is
/// refused.
fn refuse_angle_by_angle_flags(a: &CycleArgs) -> Result<(), CmdError> {
    for (flag, given, what) in [
        ("--step", a.step, "the angle-by-angle evaluation's step"),
        (
            "--design-step",
            a.design_step,
            "the angle-by-angle design's step",
        ),
        (
            "--dt",
            a.search.dt,
            "the time step of the angle-by-angle periodic runs",
        ),
    ] {
        if let Some(v) = given {
            return Err(CmdError::Input(format!(
                "{flag} {}: {what}; the transient cycle steps with the crank (its steps are the tier's, refined near the dead centres) and searches over the whole cycle. Add --quasi-steady, or drop {flag}",
                short(v)
            )));
        }
    }
    Ok(())
}

/// The file's `[design]` roughness (the film's validity) and least clearance, each checked.
fn validity(file: &Path, d: &DesignFile) -> Result<(Validity, f64), CmdError> {
    let roughness = d.roughness_um.unwrap_or(Validity::default().roughness_um);
    if !(roughness > 0.0 && roughness <= 10.0) {
        return Err(input(
            file,
            format!(
                "[design] roughness_um = {}: must lie in (0, 10] µm",
                short(roughness)
            ),
        ));
    }
    let validity = Validity {
        roughness_um: roughness,
    };
    let min_clearance_um = d.min_clearance_um.unwrap_or(validity.clearance_limit_um());
    if !(min_clearance_um.is_finite() && min_clearance_um > 0.0 && min_clearance_um <= 100.0) {
        return Err(input(
            file,
            format!(
                "[design] min_clearance_um = {}: must lie in (0, 100] µm (a film above 100 µm is no ring's)",
                short(min_clearance_um)
            ),
        ));
    }
    Ok((validity, min_clearance_um))
}

/// A crank-angle step (`flag`, else the file's, else `def`): within [`STEP_RANGE_DEG`], and
/// fine enough that some angle falls in every zone (a zone with none would have no design
/// and no work to report).
fn step(
    (engine, zones): (&Engine, &LinerZones),
    flag: &str,
    v: Option<f64>,
    def: f64,
) -> Result<f64, CmdError> {
    let x = v.unwrap_or(def);
    let (lo, hi) = STEP_RANGE_DEG;
    if !(x.is_finite() && (lo..=hi).contains(&x)) {
        return Err(CmdError::Input(format!(
            "{flag} = {}: a crank-angle step from {lo} to {hi} degrees",
            short(x)
        )));
    }
    match zones.unsampled(engine, x) {
        None => Ok(x),
        Some(z) => Err(CmdError::Input(format!(
            "{flag} = {}: no crank angle at this step falls in zone {} ({} mm), which the ring crosses in {}° of crank angle; give {flag} {} or less, or widen the zone",
            short(x),
            z + 1,
            zone_label(zones.bounds_mm(), z),
            three_digits(zones.span_deg(z)),
            zones.step_to_sample(z)
        ))),
    }
}

/// The design space of the `[design]` section (`optimise`'s defaults where absent).
fn space(d: &DesignFile) -> Space {
    SpaceKeys {
        l1: d.l1,
        l2: d.l2,
        per: d.per,
        free_width: d.free_width,
        depth: d.depth,
        w_min_um: d.w_min,
        max_area: d.max_area,
        max_depth_ratio: d.max_depth_ratio,
        allow_thick: d.allow_thick_pockets.unwrap_or(false),
    }
    .space()
}
