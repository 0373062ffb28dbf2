//! `texopt optimise`: the searches for one ring at the search fidelity (single-objective ones
//! for the ideal point, balanced ones between), the front of every searched design confirmed
//! at the reported fidelity, and the report.

use crate::time::MissingUncertainty;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use super::design::{EvaluatedDesign, Label, Report, Role, Row};
use super::design_report::write;
use super::error::OptimiseError;
use super::front_merge::merge;
use super::goal::{pareto, Goal};
use super::search::{
    swarm_and_refine, Evaluation, Evaluator, GoalSearch, SearchSettings, SwarmSettings,
};
use super::space::{depth_ratio, wall};
use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::Scales;
use crate::study::cache::Cache;
use crate::time::{Fidelity, Outcome};

/// Everything `optimise` needs.
pub struct Settings {
    /// The ring and operating point (texture ignored).
    pub base: CaseSpec,
    /// The scales of the operating point.
    pub scales: Scales,
    pub search: SearchSettings,
    /// Weights w of the balanced (Chebyshev) searches between the two single-objective ones.
    pub balanced: Vec<f64>,
}

/// Most front points confirmed at the reported fidelity.
const MAX_CONFIRM: usize = 10;

/// Searches, confirms and reports (the files too, when `out_dir` is set), on at most
/// `jobs` threads: the searches that run side by side share them (each evaluation batch
/// has its own pool of `jobs` as well, so `--jobs 1` runs everything on one core).
pub fn optimise(
    s: &Settings,
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<Report, OptimiseError> {
    let jobs = s.search.jobs;
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .map_err(|source| OptimiseError::Threads { jobs, source })?
        .install(|| optimise_on_pool(s, cache, stop))
}

fn optimise_on_pool(
    s: &Settings,
    cache: &Mutex<Cache>,
    stop: &AtomicBool,
) -> Result<Report, OptimiseError> {
    let t0 = Instant::now();
    let ss = &s.search;
    ss.space.validate().map_err(OptimiseError::Space)?;
    let say = ss.say_since(t0);
    let ev_s = evaluator(s, ss.search_fidelity, cache, stop);
    let ev_r = evaluator(s, ss.report_fidelity, cache, stop);
    let (plain_s, plain_r) = rayon::join(|| ev_s.plain(), || ev_r.plain());
    let (plain_s, plain_r) = (plain_s?, plain_r?);
    searches(s, &ev_s, &plain_s, &say)?;
    let log_s = ev_s.log.lock().expect("lock").clone();
    let cand = front_candidates(&log_s);
    say(format!(
        "{} designs evaluated at {}; confirming {} front designs at {}",
        log_s.len(),
        ss.search_fidelity.name(),
        cand.len(),
        ss.report_fidelity.name()
    ));
    let designs: Vec<Option<Texture>> = cand.iter().cloned().map(Some).collect();
    let confirmed = ev_r.evaluate(&designs)?;
    // The reported front: confirmed designs plus the plain liner.
    let plain_label = Label::of(Role::PlainLiner);
    let tier = (ss.report_fidelity.f_error(), ss.report_fidelity.c_error());
    let mut rows: Vec<Row> = vec![row(s, tier, plain_label, None, &plain_r, &plain_r)?];
    for (t, o) in cand.iter().zip(&confirmed) {
        if let Ok(o) = o {
            rows.push(row(s, tier, Label::default(), Some(t), o, &plain_r)?);
        }
    }
    let log_r = ev_r.log.lock().expect("lock").clone();
    let run = Run {
        plain_search: plain_s,
        confirmed: cand.len(),
        simulations: *ev_s.simulations.lock().expect("lock")
            + *ev_r.simulations.lock().expect("lock"),
        t0,
    };
    let report = report(s, rows, &plain_r, [log_s, log_r], run)?;
    if let Some(dir) = &ss.out_dir {
        write(dir, &report, &ev_r)?;
    }
    Ok(report)
}

/// What a run counted besides its rows: the plain liner at the search fidelity, the designs
/// confirmed, the simulations run and when it started.
struct Run {
    plain_search: Outcome,
    confirmed: usize,
    simulations: usize,
    t0: Instant,
}

/// The evaluation service of a run at one fidelity: its ring and operating point, through
/// the cache.
pub(super) fn evaluator<'a>(
    s: &Settings,
    fidelity: Fidelity,
    cache: &'a Mutex<Cache>,
    stop: &'a AtomicBool,
) -> Evaluator<'a> {
    Evaluator {
        base: CaseSpec {
            texture: None,
            ..s.base.clone()
        },
        scales: s.scales,
        fidelity,
        overrides: s.search.overrides,
        cache,
        options: s.search.sweep_options(),
        stop,
        log: Mutex::new(Vec::new()),
        simulations: Mutex::new(0),
        progress: s.search.progress,
        name: String::new(),
    }
}

/// The searches at the search fidelity: single-objective ones give the ideal point, balanced
/// ones about it fill the front. Each swarm's best point is polished by a compass search.
/// Searches that do not need each other's answers run at once (the two single-objective ones,
/// then the balanced ones): a swarm waits for its whole population between iterations, so
/// one search alone leaves a core idle at each batch's end. Each search has its own
/// evaluator (the cache shared) and the logs are joined in the searches' order, so that the
/// log, and every design reported from it, is that of running them one after the other.
fn searches(
    s: &Settings,
    ev: &Evaluator,
    plain: &Outcome,
    say: &dyn Fn(String),
) -> Result<(), OptimiseError> {
    let ss = &s.search;
    let seed = ss.swarm.seed;
    let run = |goal: Goal, seed: u64| -> Result<(Vec<f64>, f64, Evaluator), OptimiseError> {
        let own = Evaluator {
            name: match goal {
                Goal::Friction => "friction search: ".into(),
                Goal::Clearance => "clearance search: ".into(),
                Goal::Balanced { w, .. } => format!("balanced search w = {w}: "),
            },
            ..evaluator(s, ev.fidelity, ev.cache, ev.stop)
        };
        let pb = GoalSearch {
            space: &ss.space,
            eval: &own,
            goal,
            plain: plain.clone(),
        };
        let (u, c) = swarm_and_refine(&pb, SwarmSettings { seed, ..ss.swarm }, &[])?;
        Ok((u, c, own))
    };
    let absorb = |own: Evaluator| {
        ev.log
            .lock()
            .expect("lock")
            .extend(own.log.into_inner().expect("lock"));
        *ev.simulations.lock().expect("lock") += own.simulations.into_inner().expect("lock");
        ev.log.lock().expect("lock").len()
    };
    let (f, c) = rayon::join(
        || run(Goal::Friction, seed),
        || run(Goal::Clearance, seed + 1),
    );
    let mut ideal = (1.0, 1.0);
    for (goal, r) in [(Goal::Friction, f), (Goal::Clearance, c)] {
        let (u, c, own) = r?;
        match goal {
            Goal::Friction => ideal.0 = c.min(1.0),
            _ => ideal.1 = c.min(1.0),
        }
        let so_far = absorb(own);
        say(format!(
            "{goal:?} search: best {} (relative cost {c:.4}); {so_far} evaluations so far",
            ss.space.decode(&u).rounded_label()
        ));
    }
    let balanced = side_by_side(ss.jobs, &s.balanced, |i, &w| {
        run(Goal::Balanced { w, ideal }, seed + 2 + i as u64)
    });
    for (&w, r) in s.balanced.iter().zip(balanced) {
        let (u, c, own) = r?;
        absorb(own);
        say(format!(
            "balanced search w = {w}: best {} (cost {c:.4})",
            ss.space.decode(&u).rounded_label()
        ));
    }
    Ok(())
}

/// `f` of every item, at most `jobs` at once, each on a thread of its own; the results in the
/// items' order. Why not a rayon parallel iterator: a search waits for each evaluation batch
/// on a pool of the batch's own, and a rayon worker waiting on another pool takes up further
/// items meanwhile, each on top of the last one's stack (a thousand balanced searches
/// overflowed it). A plain thread just waits.
fn side_by_side<T: Sync, R: Send>(
    jobs: usize,
    items: &[T],
    f: impl Fn(usize, &T) -> R + Sync,
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let results: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..jobs.clamp(1, items.len().max(1)) {
            scope.spawn(|| {
                while let Some((i, item)) = {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    items.get(i).map(|x| (i, x))
                } {
                    let r = f(i, item);
                    *results[i].lock().expect("lock") = Some(r);
                }
            });
        }
    });
    results
        .into_iter()
        .filter_map(|r| r.into_inner().expect("lock"))
        .collect()
}

/// The designs to confirm: up to [`MAX_CONFIRM`] spread along the searched front (by f̄).
fn front_candidates(log: &[Evaluation]) -> Vec<Texture> {
    let ok: Vec<(&Texture, &Outcome)> = log
        .iter()
        .filter_map(|e| e.outcome.as_ref().ok().map(|o| (&e.texture, o)))
        .collect();
    let pts: Vec<(f64, f64)> = ok.iter().map(|(_, o)| (o.f_mean, o.c_min)).collect();
    let mut front = pareto(&pts);
    front.sort_by(|&a, &b| pts[a].0.total_cmp(&pts[b].0));
    front.dedup_by(|a, b| ok[*a].0 == ok[*b].0);
    let mut cand: Vec<Texture> = Vec::new();
    if !front.is_empty() {
        let k = front.len().min(MAX_CONFIRM);
        for i in 0..k {
            let idx = front[(i * (front.len() - 1)) / (k - 1).max(1)];
            if !cand.contains(ok[idx].0) {
                cand.push(ok[idx].0.clone());
            }
        }
    }
    cand
}

/// The report of the confirmed rows (the plain liner first): the front, the best designs,
/// the verdict against the fidelity's error, and every evaluation of both fidelities.
fn report(
    s: &Settings,
    mut rows: Vec<Row>,
    plain: &Outcome,
    logs: [Vec<Evaluation>; 2],
    run: Run,
) -> Result<Report, OptimiseError> {
    let ss = &s.search;
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.f_mean, r.c_min)).collect();
    for i in pareto(&pts) {
        rows[i].on_front = true;
    }
    let best_f = rows
        .iter()
        .min_by(|a, b| a.f_mean.total_cmp(&b.f_mean))
        .cloned()
        .ok_or(OptimiseError::Nothing("design"))?;
    let best_c = rows
        .iter()
        .max_by(|a, b| a.c_min.total_cmp(&b.c_min))
        .cloned()
        .ok_or(OptimiseError::Nothing("design"))?;
    let mut front: Vec<Row> = rows.iter().filter(|r| r.on_front).cloned().collect();
    front.sort_by(|a, b| a.f_mean.total_cmp(&b.f_mean));
    for r in &mut front {
        r.label = Label::of(if r.texture.is_none() {
            Role::PlainLiner
        } else if r.f_mean == best_f.f_mean {
            Role::BestFriction
        } else if r.c_min == best_c.c_min {
            Role::BestClearance
        } else {
            Role::Balanced
        });
    }
    let err = ss.report_fidelity.f_error();
    // Beyond the larger of the tier's error and the design's own (deep pockets).
    let beats =
        best_f.texture.is_some() && best_f.f_mean < plain.f_mean * (1.0 - err.max(best_f.f_error));
    let verdict = verdict(s, &rows, &best_f, beats);
    // Merged after the verdict, which is about the least f̄ found, whichever row carries it.
    let (front, merged) = merge(front, err, ss.report_fidelity.c_error());
    let carrying = |role: Role, fallback: Row| {
        front
            .iter()
            .find(|r| r.label.has(role))
            .cloned()
            .unwrap_or(fallback)
    };
    let (best_f, best_c) = (
        carrying(Role::BestFriction, best_f),
        carrying(Role::BestClearance, best_c),
    );
    let evaluated = evaluated(s, logs);
    Ok(Report {
        r: s.base.r,
        stribeck: crate::model::units::stribeck(s.base.u, s.base.w_ps),
        roughness_um: ss.validity.roughness_um,
        space: ss.space.clone(),
        search_fidelity: ss.search_fidelity.name().into(),
        report_fidelity: ss.report_fidelity.name().into(),
        fidelity_error: err,
        fidelity_c_error: ss.report_fidelity.c_error(),
        plain: rows[0].clone(),
        plain_search_f_mean: run.plain_search.f_mean,
        plain_search_c_min: run.plain_search.c_min,
        best_friction: best_f,
        best_clearance: best_c,
        front,
        merged_count: merged.len(),
        merged,
        texture_beats_plain: beats,
        verdict,
        evaluations_search: evaluated
            .iter()
            .filter(|e| e.fidelity == ss.search_fidelity.name())
            .count(),
        evaluations_confirm: run.confirmed,
        simulations: run.simulations,
        wall_time_s: run.t0.elapsed().as_secs_f64(),
        evaluated,
    })
}

/// Whether a texture beats the plain liner beyond the reported fidelity's error, in words.
fn verdict(s: &Settings, rows: &[Row], best_f: &Row, beats: bool) -> String {
    let fidelity = s.search.report_fidelity;
    let err = fidelity.f_error();
    if beats {
        format!(
            "a texture beats the plain liner: f̄ {:+.1} % (beyond the {:.1} % error of fidelity {})",
            best_f.f_change_pct,
            100.0 * err,
            fidelity.name()
        )
    } else {
        format!(
            "the plain liner is best: no texture lowers f̄ by more than the {:.1} % error of fidelity {} (best texture {:+.2} %)",
            100.0 * err,
            fidelity.name(),
            rows.iter()
                .filter(|r| r.texture.is_some())
                .map(|r| r.f_change_pct)
                .fold(f64::INFINITY, f64::min)
        )
    }
}

/// Every evaluation of the search and the reported fidelity, for the plot and the audit.
fn evaluated(s: &Settings, [log_s, log_r]: [Vec<Evaluation>; 2]) -> Vec<EvaluatedDesign> {
    let ss = &s.search;
    let mut evaluated = Vec::new();
    for (fid, log) in [(ss.search_fidelity, log_s), (ss.report_fidelity, log_r)] {
        for e in log {
            evaluated.push(EvaluatedDesign {
                fidelity: fid.name().into(),
                f_mean: e.outcome.as_ref().ok().map(|o| o.f_mean),
                c_min: e.outcome.as_ref().ok().map(|o| o.c_min),
                failure: e.outcome.as_ref().err().map(ToString::to_string),
                active_constraints: ss
                    .space
                    .active(&e.texture)
                    .iter()
                    .map(|x| x.to_string())
                    .collect(),
                texture: e.texture,
            });
        }
    }
    evaluated
}

/// The row of a design (None: the plain liner) against the plain liner's outcome, with its
/// error: the reported tier's `tier` (f̄, C_min), or its deep-pocket mesh uncertainty.
fn row(
    s: &Settings,
    tier: (f64, f64),
    label: Label,
    t: Option<&Texture>,
    o: &Outcome,
    plain: &Outcome,
) -> Result<Row, MissingUncertainty> {
    let (w1, w2) = t.map_or((f64::NAN, f64::NAN), wall);
    let space = &s.search.space;
    let case = CaseSpec {
        texture: t.cloned(),
        ..s.base.clone()
    };
    let physical = s.scales.physical(&case, o.f_mean, o.c_min);
    let error = o.error(&case, tier)?;
    Ok(Row {
        f_error: error.f_mean,
        c_min_error: error.c_min,
        error_source: error.source,
        friction_n_per_m: physical.friction_n_per_m,
        power_w_per_m: physical.power_w_per_m,
        outside_model: s.search.validity.outside(&case, o.c_min),
        label,
        texture: t.cloned(),
        f_mean: o.f_mean,
        c_min: o.c_min,
        z_mean: o.z_mean,
        f_change_pct: 100.0 * (o.f_mean / plain.f_mean - 1.0),
        c_min_change_pct: 100.0 * (o.c_min / plain.c_min - 1.0),
        area_fraction: t.map_or(0.0, Texture::area_fraction),
        wall_x1_cm: w1,
        wall_x2_cm: w2,
        depth_ratio: t.map_or(0.0, depth_ratio),
        active_constraints: t.map_or(Vec::new(), |t| {
            space.active(t).iter().map(|s| s.to_string()).collect()
        }),
        on_front: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each item waits on a pool of its own, as a search waits on its evaluation batches,
    /// from inside a rayon pool, as `optimise` runs its searches.
    #[test]
    fn searches_side_by_side_run_at_most_jobs_at_once_each_on_its_own_stack() {
        let (in_flight, most) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let items: Vec<usize> = (0..64).collect();
        let outer = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool");
        let out = outer.install(|| {
            side_by_side(2, &items, |i, &x| {
                let now = in_flight.fetch_add(1, Ordering::SeqCst) + 1;
                most.fetch_max(now, Ordering::SeqCst);
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .expect("pool");
                let y = pool.install(|| {
                    std::thread::sleep(std::time::Duration::from_millis(2));
                    x * 2 + i
                });
                in_flight.fetch_sub(1, Ordering::SeqCst);
                y
            })
        });
        assert_eq!(out, items.iter().map(|x| 3 * x).collect::<Vec<_>>());
        let most = most.load(Ordering::SeqCst);
        assert!(most <= 2, "{most} items at once on 2 jobs");
    }
}
