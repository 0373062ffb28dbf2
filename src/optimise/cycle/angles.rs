//! A texture for each zone of the liner over an engine cycle (docs/model.md §10). The cycle is
//! sampled in crank angle; each sample is a quasi-steady operating point (speed, load, oil
//! supply) on the zone the ring is over. Angles outside the hydrodynamic model (near the dead
//! centres, where the speed and the film vanish) are excluded and carry no number. Each zone's
//! texture minimises the zone's friction work over the cycle under a least clearance; the single
//! best texture for the whole liner and the plain liner are the references.

use std::sync::atomic::AtomicBool;
use std::sync::Mutex;
use std::time::Instant;

use crate::model::case::{CaseSpec, InputError, Texture};
use crate::model::engine::{Engine, LinerZones, Sample};
use crate::model::operating::{Outside, Scales, VALIDATED_STRIBECK};
use crate::optimise::cycle::liner::Trio;
use crate::optimise::error::OptimiseError;
use crate::optimise::goal::FAILED_COST;
use crate::optimise::search::{run_jobs, swarm_and_refine, Objective, SearchSettings};
use crate::optimise::space::Space;
use crate::study::cache::Cache;
use crate::study::sweep::CaseFailure;
use crate::study::Job;
use crate::time::{Fidelity, Outcome};

/// Everything `cycle` needs.
pub struct CycleSettings {
    pub engine: Engine,
    /// The liner's zones the design textures one by one.
    pub zones: LinerZones,
    pub search: SearchSettings,
    /// The least clearance a design must keep (µm).
    pub min_clearance_um: f64,
    /// Crank-angle steps of the report and of the design (degrees).
    pub step_deg: f64,
    pub design_step_deg: f64,
}

/// One sample of the cycle, ready to evaluate: its plain case and scales, and its sliding
/// distance v·Δt (m), the weight of its friction force in the work.
#[derive(Clone, Debug)]
pub struct Point {
    pub sample: Sample,
    pub base: CaseSpec,
    pub scales: Scales,
    pub distance_m: f64,
    /// Why the angle is outside the hydrodynamic model, if it is.
    pub excluded: Option<Exclusion>,
}

/// Why an angle of the cycle is outside the hydrodynamic model. Its words (`Display`) go into
/// the reports; its [`kind`](Exclusion::kind) is what the report counts.
#[derive(Clone, Debug, PartialEq)]
pub enum Exclusion {
    /// Slower than [`SPEED_FLOOR`] × the mean piston speed (`floor`, m/s).
    DeadCentre { speed_ms: f64, floor_ms: f64 },
    /// Speed or load change by `change` (a fraction) while the oil crosses the ring.
    NotQuasiSteady { change: f64 },
    /// A Stribeck number outside [`VALIDATED_STRIBECK`].
    Stribeck {
        stribeck: f64,
        speed_ms: f64,
        load_n_per_m: f64,
    },
    /// An operating input out of its range.
    Inputs(InputError),
    /// The plain liner's answer there is outside the model (below the least clearance).
    PlainBelowLimit(Outside),
    /// The plain liner's run failed there.
    PlainFailed(CaseFailure),
}

impl std::fmt::Display for Exclusion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Exclusion::DeadCentre { speed_ms, floor_ms } => write!(
                f,
                "speed {speed_ms:.2} m/s below {SPEED_FLOOR} × the mean piston speed ({floor_ms:.2} m/s): near a dead centre"
            ),
            Exclusion::NotQuasiSteady { change } => write!(
                f,
                "not quasi-steady: speed or load change by {:.0} % while the oil crosses the ring (limit {:.0} %)",
                100.0 * change,
                100.0 * QUASI_STEADY
            ),
            Exclusion::Stribeck {
                stribeck,
                speed_ms,
                load_n_per_m,
            } => {
                let (lo, hi) = VALIDATED_STRIBECK;
                write!(
                    f,
                    "Stribeck number {stribeck:.2e} outside {lo:e}..{hi:e} (speed {speed_ms:.2} m/s, load {load_n_per_m:.0} N/m)"
                )
            }
            Exclusion::Inputs(why) => write!(f, "{why}"),
            Exclusion::PlainBelowLimit(why) => write!(f, "plain liner: {why}"),
            Exclusion::PlainFailed(why) => write!(f, "plain liner failed: {why}"),
        }
    }
}

impl Exclusion {
    /// The kind, as the report counts exclusions.
    pub fn kind(&self) -> &'static str {
        match self {
            Exclusion::DeadCentre { .. } => "slow near a dead centre",
            Exclusion::NotQuasiSteady { .. } => {
                "with speed or load changing too fast for a quasi-steady film"
            }
            Exclusion::Stribeck { .. } => "with the Stribeck number outside the validated range",
            Exclusion::PlainFailed(_) => "where the plain liner's run failed",
            Exclusion::PlainBelowLimit(_) => "where the plain liner runs below the least clearance",
            Exclusion::Inputs(_) => "with inputs out of range",
        }
    }
}

impl serde::Serialize for Exclusion {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The evaluation of one liner at the points: per point, the outcome and its friction force
/// (N/m), or why there is none.
pub type Forces = Vec<Result<(Outcome, f64), CaseFailure>>;

/// The samples of the cycle every `step` degrees as points, those outside the model's range
/// of operating conditions excluded before anything is run.
pub fn points(s: &CycleSettings, step: f64) -> Vec<Point> {
    let e = &s.engine;
    let omega = e.omega_rad_s();
    let dt = (720.0 / (720.0 / step).round()).to_radians() / omega;
    e.samples(step, &s.zones)
        .into_iter()
        .map(|sample| {
            let op = e.operating(&sample);
            let mut base = CaseSpec::paper(e.file.ring.r_cm);
            let excluded = excluded_before(&op, &sample, s);
            if excluded.is_none() {
                op.apply(&mut base);
                s.search.validity.apply(&mut base);
                // The transient cycle's film, rough unless the engine file says smooth.
                base.flow = e.file.contact.flow_factors(s.search.validity.roughness_um);
            }
            Point {
                sample,
                base,
                scales: op.scales(),
                distance_m: sample.speed_ms * dt,
                excluded,
            }
        })
        .collect()
}

/// Slowest sliding the quasi-steady model takes, as a share of the mean piston speed: closer
/// to a dead centre the film is squeezed rather than dragged through the contact.
pub const SPEED_FLOOR: f64 = 0.1;

/// Largest change of speed or load, relative, over the time the oil takes to cross the ring
/// face (2·width/U) that a quasi-steady evaluation stands (docs/model.md §10).
pub const QUASI_STEADY: f64 = 0.2;

/// Why an operating point is outside the model before it is run: slower than
/// [`SPEED_FLOOR`] × the mean piston speed, speed or load changing too fast for a
/// quasi-steady film ([`QUASI_STEADY`]), a Stribeck number outside the validated range, or
/// inputs out of range.
fn excluded_before(
    op: &crate::model::operating::Operating,
    sample: &Sample,
    s: &CycleSettings,
) -> Option<Exclusion> {
    let e = &s.engine;
    let crank = &e.file.engine;
    let floor = SPEED_FLOOR * 2.0 * crank.stroke_mm * 1e-3 * crank.rpm / 60.0;
    if op.speed_ms < floor {
        return Some(Exclusion::DeadCentre {
            speed_ms: op.speed_ms,
            floor_ms: floor,
        });
    }
    // Relative rates of change per second, by central differences over ±0.05° of crank.
    let (h, omega) = (0.05f64, e.omega_rad_s());
    let dt = 2.0 * h.to_radians() / omega;
    let at = |d: f64| {
        let a = sample.crank_deg + d;
        (e.velocity_ms(a).abs(), e.load_n_per_m(a))
    };
    let ((u0, w0), (u1, w1)) = (at(-h), at(h));
    let rate = ((u1 - u0) / dt / op.speed_ms)
        .abs()
        .max(((w1 - w0) / dt / op.load_n_per_m).abs());
    let crossing = 2.0 * e.file.ring.width_mm * 1e-3 / op.speed_ms;
    if rate * crossing > QUASI_STEADY {
        return Some(Exclusion::NotQuasiSteady {
            change: rate * crossing,
        });
    }
    let st = op.stribeck();
    let (lo, hi) = VALIDATED_STRIBECK;
    if !(lo..=hi).contains(&st) {
        return Some(Exclusion::Stribeck {
            stribeck: st,
            speed_ms: op.speed_ms,
            load_n_per_m: op.load_n_per_m,
        });
    }
    op.check().err().map(Exclusion::Inputs)
}

/// Evaluates a liner (`texture` per point: None is the plain liner) at the points that are
/// not excluded, in parallel through the cache, at `fidelity`.
pub fn evaluate(
    s: &CycleSettings,
    pts: &[&Point],
    textures: &[Option<Texture>],
    fidelity: Fidelity,
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<Forces, OptimiseError> {
    let jobs: Vec<Job> = pts
        .iter()
        .zip(textures)
        .map(|(p, t)| {
            let case = CaseSpec {
                texture: t.clone(),
                ..p.base.clone()
            };
            let numerics = crate::time::resolve(fidelity, &s.search.overrides, &case);
            Job {
                case,
                numerics,
                scales: p.scales,
            }
        })
        .collect();
    let (sum, results) = run_jobs(&jobs, cache, &s.search.sweep_options(), stop)?;
    if sum.stopped {
        return Err(OptimiseError::Stopped);
    }
    Ok(results
        .into_iter()
        .zip(&jobs)
        .map(|(r, j)| {
            let o = r?;
            let force = j
                .scales
                .physical(&j.case, o.f_mean, o.c_min)
                .friction_n_per_m;
            Ok((o, force))
        })
        .collect())
}

/// The plain liner at every point; points where it fails or runs below the model's clearance
/// limit are excluded from then on (every liner is weighed on the same angles).
fn plain_and_exclude(
    s: &CycleSettings,
    pts: &mut [Point],
    fidelity: Fidelity,
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<Vec<Option<f64>>, OptimiseError> {
    let idx: Vec<usize> = (0..pts.len())
        .filter(|&k| pts[k].excluded.is_none())
        .collect();
    let sel: Vec<&Point> = idx.iter().map(|&k| &pts[k]).collect();
    let plain = evaluate(s, &sel, &vec![None; sel.len()], fidelity, cache, stop)?;
    let mut force = vec![None; pts.len()];
    for (&k, r) in idx.iter().zip(plain) {
        match r {
            Ok((o, f)) => match s.search.validity.outside(&pts[k].base, o.c_min) {
                Some(why) => pts[k].excluded = Some(Exclusion::PlainBelowLimit(why)),
                None => force[k] = Some(f),
            },
            Err(why) => pts[k].excluded = Some(Exclusion::PlainFailed(why)),
        }
    }
    Ok(force)
}

/// What a zone's design minimises: its friction work over the plain liner's, Σ F·v·Δt over
/// the zone's points; a design that fails or leaves less than the least clearance at one of
/// them is infeasible.
struct ZoneWork<'a> {
    s: &'a CycleSettings,
    pts: Vec<&'a Point>,
    plain_work: f64,
    cache: &'a Mutex<Cache>,
    stop: &'a AtomicBool,
}

impl Objective for ZoneWork<'_> {
    fn space(&self) -> &Space {
        &self.s.search.space
    }

    fn costs(&self, designs: &[Texture]) -> Result<Vec<f64>, OptimiseError> {
        let n = self.pts.len();
        let mut pts = Vec::with_capacity(n * designs.len());
        let mut tex = Vec::with_capacity(n * designs.len());
        for t in designs {
            pts.extend(self.pts.iter().copied());
            tex.extend(std::iter::repeat_n(Some(t.clone()), n));
        }
        let r = evaluate(
            self.s,
            &pts,
            &tex,
            self.s.search.search_fidelity,
            self.cache,
            self.stop,
        )?;
        Ok(r.chunks(n)
            .map(|runs| {
                let mut work = 0.0;
                for (p, run) in self.pts.iter().zip(runs) {
                    match run {
                        Ok((o, f)) if o.c_min >= self.s.min_clearance_um => {
                            work += f * p.distance_m
                        }
                        _ => return FAILED_COST,
                    }
                }
                work / self.plain_work
            })
            .collect())
    }
}

/// The texture that minimises the friction work at `pts` relative to the plain liner's
/// (`plain`: its forces there), with that ratio, or None when there is no point: a particle
/// swarm polished by a compass search, as `optimise`'s friction search.
pub fn design(
    s: &CycleSettings,
    pts: Vec<&Point>,
    plain: &[f64],
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<Option<(Texture, f64)>, OptimiseError> {
    let plain_work: f64 = pts.iter().zip(plain).map(|(p, f)| f * p.distance_m).sum();
    if pts.is_empty() || plain_work <= 0.0 {
        return Ok(None);
    }
    let problem = ZoneWork {
        s,
        pts,
        plain_work,
        cache,
        stop,
    };
    let (u, c) = swarm_and_refine(&problem, s.search.swarm, &[])?;
    Ok(Some((s.search.space.decode(&u), c)))
}

/// The designs of a cycle: each zone's texture and the uniform one where they beat the plain
/// liner at the design's points (None: the plain liner), and the best textures the searches
/// found, beating it there or not (None: no search), which the transient cycle judges.
#[derive(Clone, Debug, Default)]
pub struct Designs {
    pub zones: Vec<Option<Texture>>,
    pub uniform: Option<Texture>,
    pub candidates: Vec<Option<Texture>>,
    pub uniform_candidate: Option<Texture>,
}

/// A search's outcome in words: its best texture and ratio, and whether it beats the plain
/// liner.
fn found(d: &Option<(Texture, f64)>) -> String {
    match d {
        None => "no angle to search".into(),
        Some((t, c)) if *c < 1.0 => format!("{}, work ratio {c:.4}", t.rounded_label()),
        Some((t, c)) => format!(
            "the plain liner (the best texture, {}, has work ratio {c:.4})",
            t.rounded_label()
        ),
    }
}

/// The texture of a search's outcome where it beats the plain liner.
fn winner(d: &Option<(Texture, f64)>) -> Option<Texture> {
    d.as_ref().filter(|x| x.1 < 1.0).map(|x| x.0.clone())
}

/// Why no liner can be weighed: no angle of the cycle inside the model; it holds the first
/// (up to three) excluded angles (degrees) and their reasons.
#[derive(Clone, Debug, PartialEq)]
pub struct NoAngleInside(pub Vec<(f64, Exclusion)>);

impl NoAngleInside {
    pub fn of(pts: &[Point]) -> Self {
        NoAngleInside(
            pts.iter()
                .filter_map(|p| Some((p.sample.crank_deg, p.excluded.clone()?)))
                .take(3)
                .collect(),
        )
    }
}

impl std::fmt::Display for NoAngleInside {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let reasons: Vec<String> = self
            .0
            .iter()
            .map(|(deg, why)| format!("{deg:.0}°: {why}"))
            .collect();
        write!(
            f,
            "no crank angle of the cycle lies inside the hydrodynamic model, so no liner can be weighed; check the engine file's speed (rpm, stroke), loads, oil and ring. The first angles: {}",
            reasons.join("; ")
        )
    }
}

/// Designs every zone and the uniform liner at the design step.
pub fn design_all(
    s: &CycleSettings,
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<Designs, OptimiseError> {
    let t0 = Instant::now();
    let say = s.search.say_since(t0);
    let mut pts = points(s, s.design_step_deg);
    say(format!(
        "the plain liner at the {} design angles (every {}°) …",
        pts.len(),
        s.design_step_deg
    ));
    let plain = plain_and_exclude(s, &mut pts, s.search.search_fidelity, cache, stop)?;
    let inside: Vec<usize> = (0..pts.len()).filter(|&k| plain[k].is_some()).collect();
    if inside.is_empty() {
        return Err(OptimiseError::NoAngleInside(NoAngleInside::of(&pts)));
    }
    say(format!(
        "{} of {} design angles inside the model",
        inside.len(),
        pts.len()
    ));
    let zone_count = s.zones.count();
    let (mut zones, mut candidates) = (Vec::new(), Vec::new());
    for z in 0..zone_count {
        let at: Vec<usize> = inside
            .iter()
            .copied()
            .filter(|&k| pts[k].sample.zone == z)
            .collect();
        let f: Vec<f64> = at.iter().filter_map(|&k| plain[k]).collect();
        // A zone's search takes minutes: said as it starts, and what it found.
        say(format!(
            "zone {} of {zone_count}: searching over its {} angles …",
            z + 1,
            at.len()
        ));
        let d = design(s, at.iter().map(|&k| &pts[k]).collect(), &f, cache, stop)?;
        say(format!(
            "zone {}: {} angles; {}",
            z + 1,
            at.len(),
            found(&d)
        ));
        zones.push(winner(&d));
        candidates.push(d.map(|x| x.0));
    }
    let f: Vec<f64> = inside.iter().filter_map(|&k| plain[k]).collect();
    say(format!(
        "uniform liner: searching over all {} angles …",
        inside.len()
    ));
    let uniform = design(
        s,
        inside.iter().map(|&k| &pts[k]).collect(),
        &f,
        cache,
        stop,
    )?;
    say(format!("uniform: {}", found(&uniform)));
    Ok(Designs {
        zones,
        uniform: winner(&uniform),
        candidates,
        uniform_candidate: uniform.map(|x| x.0),
    })
}

/// The three liners at the report's points: plain, uniform best and zoned, with the points
/// (their exclusions settled by the plain liner).
pub struct LinerRuns {
    pub points: Vec<Point>,
    /// Per liner (plain, uniform, zoned), per point: the outcome and force, or none.
    pub liners: Trio<Runs>,
    /// Each zone's searched design, then the uniform one, as the report's fidelity and step
    /// found them.
    pub confirmed: Vec<Confirmation>,
}

/// A searched design at the report's fidelity and step: its change of friction work against
/// the plain liner there, or None where a run failed or left less than the least clearance.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Confirmation {
    pub searched: Option<Texture>,
    pub change_pct: Option<f64>,
    pub kept: bool,
}

pub type Runs = Vec<Option<(Outcome, f64)>>;

/// The work of `runs` over the points of `zone` (all zones: None) if every point inside the
/// model has a run that keeps the least clearance; None otherwise.
fn feasible_work(
    s: &CycleSettings,
    pts: &[Point],
    runs: &Runs,
    zone: Option<usize>,
) -> Option<f64> {
    let mut w = 0.0;
    for (p, r) in pts.iter().zip(runs) {
        if p.excluded.is_some() || zone.is_some_and(|z| p.sample.zone != z) {
            continue;
        }
        let (o, f) = r.as_ref()?;
        if o.c_min < s.min_clearance_um {
            return None;
        }
        w += f * p.distance_m;
    }
    Some(w)
}

/// Per zone, the texture of the least feasible work among its own design, the uniform one
/// and the plain liner (`runs`: theirs, plain first), and the runs that carry it. A zone with
/// no angle inside the model at the report's step has nothing to confirm its design on: it
/// keeps the plain liner.
fn choose<'a>(
    s: &CycleSettings,
    pts: &[Point],
    d: &Designs,
    runs: Trio<&'a Runs>,
) -> Vec<(Option<Texture>, &'a Runs)> {
    let Trio {
        plain,
        uniform,
        designed: own,
    } = runs;
    (0..d.zones.len())
        .map(|z| {
            let weighed = pts
                .iter()
                .any(|p| p.sample.zone == z && p.excluded.is_none());
            if !weighed {
                return (None, plain);
            }
            [
                (d.zones[z].clone(), own),
                (d.uniform.clone(), uniform),
                (None, plain),
            ]
            .into_iter()
            .filter_map(|(t, r)| Some((feasible_work(s, pts, r, Some(z))?, t, r)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map_or((None, plain), |(_, t, r)| (t, r))
        })
        .collect()
}

/// The searched designs confirmed at the report's fidelity and step: each zone keeps the best
/// of its own design, the uniform one and the plain liner there (a design found at the search
/// fidelity that does not beat them at the report's is not kept), and the uniform texture is
/// kept only if it beats the plain liner over the cycle. Returns the final designs and the
/// three liners' runs.
pub fn evaluate_liners(
    s: &CycleSettings,
    d: &Designs,
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<(Designs, LinerRuns), OptimiseError> {
    let fidelity = s.search.report_fidelity;
    let mut pts = points(s, s.step_deg);
    plain_and_exclude(s, &mut pts, fidelity, cache, stop)?;
    if pts.iter().all(|p| p.excluded.is_some()) {
        return Err(OptimiseError::NoAngleInside(NoAngleInside::of(&pts)));
    }
    let run = |pick: &dyn Fn(usize) -> Option<Texture>| -> Result<Runs, OptimiseError> {
        let inside: Vec<&Point> = pts.iter().filter(|p| p.excluded.is_none()).collect();
        let tex: Vec<Option<Texture>> = inside.iter().map(|p| pick(p.sample.zone)).collect();
        let mut it = evaluate(s, &inside, &tex, fidelity, cache, stop)?.into_iter();
        Ok(pts
            .iter()
            .map(|p| match p.excluded {
                Some(_) => None,
                None => it.next().and_then(Result::ok),
            })
            .collect())
    };
    let plain = run(&|_| None)?;
    let uniform = run(&|_| d.uniform.clone())?;
    let own = run(&|z| d.zones[z].clone())?;
    let zones = d.zones.len();
    let choice = choose(
        s,
        &pts,
        d,
        Trio {
            plain: &plain,
            uniform: &uniform,
            designed: &own,
        },
    );
    let zoned: Runs = pts
        .iter()
        .enumerate()
        .map(|(k, p)| choice[p.sample.zone].1[k].clone())
        .collect();
    let zone_textures: Vec<Option<Texture>> = choice.into_iter().map(|(t, _)| t).collect();
    let confirm =
        |t: &Option<Texture>, runs: &Runs, zone: Option<usize>, kept: bool| Confirmation {
            searched: t.clone(),
            change_pct: t.as_ref().and_then(|_| {
                let w = feasible_work(s, &pts, runs, zone)?;
                let p = feasible_work(s, &pts, &plain, zone).filter(|p| *p > 0.0)?;
                Some(100.0 * (w / p - 1.0))
            }),
            kept,
        };
    let mut confirmed: Vec<Confirmation> = (0..zones)
        .map(|z| {
            confirm(
                &d.zones[z],
                &own,
                Some(z),
                d.zones[z].is_some() && zone_textures[z] == d.zones[z],
            )
        })
        .collect();
    let uniform_kept = match (
        feasible_work(s, &pts, &uniform, None),
        feasible_work(s, &pts, &plain, None),
    ) {
        (Some(u), Some(p)) if u < p => d.uniform.clone(),
        _ => None,
    };
    confirmed.push(confirm(&d.uniform, &uniform, None, uniform_kept.is_some()));
    let uniform = if uniform_kept.is_some() {
        uniform
    } else {
        plain.clone()
    };
    let designs = Designs {
        zones: zone_textures,
        uniform: uniform_kept,
        ..Designs::default()
    };
    Ok((
        designs,
        LinerRuns {
            points: pts,
            liners: Trio {
                plain,
                uniform,
                designed: zoned,
            },
            confirmed,
        },
    ))
}
