//! Many evaluations through the cache, in parallel (rayon): each missing case is simulated
//! once and stored as soon as it finishes, so an interrupted sweep loses at most the cases
//! in flight. Cases that differ only in θ_s share one simulation (docs/model.md §5: θ_s enters
//! only the Couette friction term).

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::model::case::CaseSpec;
use crate::model::case::Waiver;
use crate::study::cache::{Cache, CacheError, Entry, Key};
use crate::study::file::Job;
use crate::time::{limits, simulate_with, Limits, Numerics, Outcome, RunOptions, Watch};

/// How a sweep runs.
#[derive(Clone, Debug)]
pub struct Options {
    /// Worker threads (≥ 1).
    pub jobs: usize,
    /// Simulate again the cases stored as failed.
    pub retry_failed: bool,
    /// Show progress on stderr (a bar on a terminal, a line every 10 s otherwise).
    pub progress: bool,
    /// What one run may cost: a case over them fails unrun, and is not stored (raising the
    /// limits runs it).
    pub limits: Limits,
}

/// Why a case has no outcome. A failed case is data (reported, counted, stored), not an
/// error that stops a study; its words are what the cache stores and the report prints.
#[derive(Clone, Debug, PartialEq)]
pub enum CaseFailure {
    /// Over the run limits: not run and not stored (raising the limits runs it).
    OverLimit(String),
    /// Not run: the sweep stopped first.
    NotRun,
    /// The run failed, or the cache holds it as failed.
    Run(String),
}

impl CaseFailure {
    /// Its words, as the cache stores them and the report prints them.
    pub fn words(&self) -> &str {
        match self {
            CaseFailure::OverLimit(why) | CaseFailure::Run(why) => why,
            CaseFailure::NotRun => "not run",
        }
    }
}

impl std::fmt::Display for CaseFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(self.words())
    }
}

impl serde::Serialize for CaseFailure {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// One case's outcome, or why it has none.
pub type CaseEvaluation = Result<Outcome, CaseFailure>;

/// The result of one case; None when it was not run (the sweep was stopped first).
pub type CaseResult = Option<CaseEvaluation>;

/// What a sweep did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Summary {
    pub cases: usize,
    /// Cases answered by the cache (done or failed before).
    pub cached: usize,
    /// Cases computed now, and the simulations that computed them (θ_s variants share one).
    pub computed: usize,
    pub simulations: usize,
    /// Cases that failed (now or before), and cases not run because the sweep was stopped.
    pub failed: usize,
    pub not_run: usize,
    pub stopped: bool,
    pub wall_time_s: f64,
    /// Cases whose stored entry was damaged (label and what was wrong): never served,
    /// computed again unless the sweep is stopped.
    pub damaged: Vec<String>,
}

/// The θ_s-free part of a case: cases equal in it share one simulation.
fn shared_key(case: &CaseSpec, num: &Numerics) -> String {
    let c = CaseSpec {
        theta_s: 0.0,
        ..case.clone()
    };
    Key::of(&c, num).hash
}

/// Evaluates every job: from the cache where it has the answer, else by simulation
/// (stored at once). `stop` is polled before each simulation starts.
pub fn run(
    jobs: &[Job],
    cache: &Mutex<Cache>,
    opt: &Options,
    stop: &AtomicBool,
) -> Result<(Summary, Vec<CaseResult>), CacheError> {
    let start = Instant::now();
    let keys: Vec<Key> = jobs.iter().map(|j| Key::of(&j.case, &j.numerics)).collect();
    let mut summary = Summary {
        cases: jobs.len(),
        ..Summary::default()
    };
    let (mut results, groups) = look_up(jobs, &keys, cache, opt, &mut summary)?;
    let to_compute: usize = groups.iter().map(Vec::len).sum();

    let bar = Display::new(opt.progress, summary.cached, jobs.len(), to_compute);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opt.jobs.max(1))
        .build()
        .map_err(|e| CacheError::Io {
            path: "-".into(),
            why: format!("cannot start {} worker threads: {e}", opt.jobs),
        })?;
    let work = Work {
        jobs,
        keys: &keys,
        cache,
        stop,
        retry_failed: opt.retry_failed,
        bar: &bar,
        done: AtomicUsize::new(0),
        failed_now: AtomicUsize::new(0),
        simulations: AtomicUsize::new(0),
        cache_error: Mutex::new(None),
    };
    work.all(&pool, &groups, &mut results, &mut summary);
    bar.finish();
    if let Some(e) = work.cache_error.lock().expect("lock").take() {
        return Err(e);
    }
    let done = &work.done;
    summary.computed = done.load(Ordering::SeqCst);
    summary.simulations = work.simulations.load(Ordering::SeqCst);
    summary.failed = results.iter().filter(|r| matches!(r, Some(Err(_)))).count();
    summary.not_run = results.iter().filter(|r| r.is_none()).count();
    summary.stopped = summary.not_run > 0;
    summary.wall_time_s = start.elapsed().as_secs_f64();
    Ok((summary, results))
}

/// What the cache answers before anything runs: each job's result where the cache holds it
/// (or the run limits refuse the job), and the groups of jobs left to compute (one
/// simulation each). Counts the cached cases and notes the damaged entries in `summary`.
fn look_up(
    jobs: &[Job],
    keys: &[Key],
    cache: &Mutex<Cache>,
    opt: &Options,
    summary: &mut Summary,
) -> Result<(Vec<CaseResult>, Vec<Vec<usize>>), CacheError> {
    let mut results: Vec<CaseResult> = vec![None; jobs.len()];
    let mut missing: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    let mut over_limit = 0;
    let c = cache.lock().expect("cache lock");
    for (i, k) in keys.iter().enumerate() {
        if let Err(e) = limits::check(&jobs[i].case, &jobs[i].numerics, &opt.limits) {
            let raise = match e.waiver {
                Some(Waiver::MemoryLimit) => "; raise the memory limit to run it",
                _ => "; raise the step limit to run it",
            };
            over_limit += 1;
            results[i] = Some(Err(CaseFailure::OverLimit(format!(
                "case {}: not run: {} = {}: {}{raise}",
                jobs[i].case.label(),
                e.param,
                e.value,
                e.rule
            ))));
            continue;
        }
        match c.get(k)? {
            Some(Entry::Done(o)) if current(&jobs[i], &o) => results[i] = Some(Ok(o)),
            Some(Entry::Failed(r)) if !opt.retry_failed => {
                results[i] = Some(Err(CaseFailure::Run(r)))
            }
            other => {
                if let Some(Entry::Damaged(why)) = other {
                    let hash = &k.hash[..12];
                    summary
                        .damaged
                        .push(format!("{} (entry {hash}): {why}", jobs[i].case.label()));
                }
                missing
                    .entry(shared_key(&jobs[i].case, &jobs[i].numerics))
                    .or_default()
                    .push(i);
            }
        }
    }
    drop(c);
    summary.cached = results.iter().filter(|r| r.is_some()).count() - over_limit;
    Ok((results, missing.into_values().collect()))
}

/// How often a sweep looks again at cases another process is computing.
const LEASE_POLL: std::time::Duration = std::time::Duration::from_millis(500);

/// What became of a group of cases (one simulation) in one pass of a sweep.
enum Pass {
    /// Computed here, and stored.
    Computed(Vec<(usize, CaseEvaluation)>),
    /// Stored meanwhile by another process sharing the cache.
    Stored(Vec<(usize, CaseEvaluation)>),
    /// Being computed by another live process: looked at again later.
    Held,
    /// Not started: the sweep was stopped.
    Stopped,
}

/// A sweep's shared state while its groups are evaluated in parallel.
struct Work<'a> {
    jobs: &'a [Job],
    keys: &'a [Key],
    cache: &'a Mutex<Cache>,
    stop: &'a AtomicBool,
    retry_failed: bool,
    bar: &'a Display,
    done: AtomicUsize,
    failed_now: AtomicUsize,
    simulations: AtomicUsize,
    cache_error: Mutex<Option<CacheError>>,
}

impl Work<'_> {
    /// Evaluates the groups in parallel on `pool`, their results into `results`. Groups
    /// another process holds are looked at again until they are stored or free.
    fn all(
        &self,
        pool: &rayon::ThreadPool,
        groups: &[Vec<usize>],
        results: &mut [CaseResult],
        summary: &mut Summary,
    ) {
        let mut pending: Vec<&Vec<usize>> = groups.iter().collect();
        while !pending.is_empty() {
            let passes: Vec<(&Vec<usize>, Pass)> =
                pool.install(|| pending.par_iter().map(|g| (*g, self.group(g))).collect());
            let mut held = Vec::new();
            for (g, pass) in passes {
                match pass {
                    Pass::Computed(out) => out.into_iter().for_each(|(i, r)| results[i] = Some(r)),
                    Pass::Stored(out) => {
                        summary.cached += out.len();
                        out.into_iter().for_each(|(i, r)| results[i] = Some(r));
                    }
                    Pass::Held => held.push(g),
                    Pass::Stopped => {}
                }
            }
            if self.stop.load(Ordering::SeqCst) {
                break;
            }
            if !held.is_empty() {
                std::thread::sleep(LEASE_POLL);
            }
            pending = held;
        }
    }

    /// Evaluates one group unless another process holds it (its lease, [`Cache::claim`]) or
    /// has stored it meanwhile.
    fn group(&self, group: &[usize]) -> Pass {
        if self.stop.load(Ordering::SeqCst) {
            return Pass::Stopped;
        }
        let lease = shared_key(&self.jobs[group[0]].case, &self.jobs[group[0]].numerics);
        let c = self.cache.lock().expect("cache lock");
        match c.claim(&lease) {
            Ok(true) => {}
            Ok(false) => return Pass::Held,
            Err(e) => return self.fail(e),
        }
        // Stored meanwhile by a process whose lease has ended: read, not computed again (a
        // failure only when failures are not to be retried).
        let stored: Option<Vec<_>> = group
            .iter()
            .map(|&i| match c.get(&self.keys[i]) {
                Ok(Some(Entry::Done(o))) if current(&self.jobs[i], &o) => Some((i, Ok(o))),
                Ok(Some(Entry::Failed(r))) if !self.retry_failed => {
                    Some((i, Err(CaseFailure::Run(r))))
                }
                _ => None,
            })
            .collect();
        if let Some(out) = stored {
            if let Err(e) = c.release(&lease) {
                return self.fail(e);
            }
            return Pass::Stored(out);
        }
        drop(c);
        let out = evaluate_group(self.jobs, group);
        self.simulations.fetch_add(1, Ordering::SeqCst);
        let c = self.cache.lock().expect("cache lock");
        let stored = out.iter().try_for_each(|(i, r)| match r {
            Ok(o) => c.put_done(&self.keys[*i], o),
            Err(reason) => c.put_failed(&self.keys[*i], reason.words(), 0.0),
        });
        // The lease ends once every case of the group is stored.
        if let Err(e) = stored.and_then(|()| c.release(&lease)) {
            self.fail(e);
        }
        drop(c);
        let nf = out.iter().filter(|(_, r)| r.is_err()).count();
        self.failed_now.fetch_add(nf, Ordering::SeqCst);
        let d = self.done.fetch_add(out.len(), Ordering::SeqCst) + out.len();
        self.bar.tick(d, self.failed_now.load(Ordering::SeqCst));
        Pass::Computed(out)
    }

    /// A cache that cannot be read or written stops the sweep (the error is returned).
    fn fail(&self, e: CacheError) -> Pass {
        self.stop.store(true, Ordering::SeqCst);
        self.cache_error.lock().expect("lock").get_or_insert(e);
        Pass::Stopped
    }
}

/// One simulation for a group of cases differing only in θ_s. A run that ends outside the
/// periodic regime, errs or panics is a failure with its reason, never a result.
fn evaluate_group(jobs: &[Job], group: &[usize]) -> Vec<(usize, CaseEvaluation)> {
    let first = &jobs[group[0]];
    let extra: Vec<f64> = group[1..].iter().map(|&i| jobs[i].case.theta_s).collect();
    let t0 = Instant::now();
    let run = std::panic::catch_unwind(|| {
        let opts = RunOptions {
            extra_theta_s: extra,
            ..RunOptions::default()
        };
        simulate_with(&first.case, &first.numerics, &opts, &mut Watch::default())
    });
    let wall = t0.elapsed().as_secs_f64();
    let fail = |why: String| {
        group
            .iter()
            .map(|&i| (i, Err(CaseFailure::Run(why.clone()))))
            .collect()
    };
    match run {
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            fail(format!(
                "case {}: internal error (panic: {msg}); please report it",
                first.case.label()
            ))
        }
        Ok(Err(e)) => fail(e.to_string()),
        Ok(Ok(r)) if !r.outcome.converged => fail(format!(
            "case {}: periodic regime not reached by t = {} ms (estimated distance {:.1e} > periodic_tol {:.0e}); raise t_max",
            first.case.label(),
            first.numerics.t_max,
            r.outcome.periodic_error,
            first.numerics.periodic_tol
        )),
        Ok(Ok(r)) => {
            let mut out = vec![(group[0], Ok(with_wall(r.outcome, wall)))];
            for (&i, (_, o)) in group[1..].iter().zip(r.extra) {
                out.push((i, Ok(with_wall(o, wall))));
            }
            out
        }
    }
}

fn with_wall(mut o: Outcome, wall: f64) -> Outcome {
    o.wall_time_s = wall;
    o
}

/// Progress on stderr: an indicatif bar on a terminal, else a plain line every 10 s.
struct Display {
    bar: Option<ProgressBar>,
    plain: bool,
    cached: usize,
    total: usize,
    to_compute: usize,
    start: Instant,
    last_line: Mutex<Instant>,
}

impl Display {
    fn new(enabled: bool, cached: usize, total: usize, to_compute: usize) -> Display {
        let tty = std::io::stderr().is_terminal();
        let bar = (enabled && tty && to_compute > 0).then(|| {
            let b = ProgressBar::new(to_compute as u64);
            b.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} computed ({msg}) {elapsed_precise} ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b.set_message("0 failed");
            b.enable_steady_tick(Duration::from_millis(500));
            b
        });
        if enabled {
            eprintln!("{total} cases: {cached} in the cache, {to_compute} to compute");
        }
        Display {
            bar,
            plain: enabled && !tty,
            cached,
            total,
            to_compute,
            start: Instant::now(),
            last_line: Mutex::new(Instant::now()),
        }
    }

    fn tick(&self, done: usize, failed: usize) {
        if let Some(b) = &self.bar {
            b.set_position(done as u64);
            b.set_message(format!("{failed} failed"));
        } else if self.plain {
            let mut last = self.last_line.lock().expect("lock");
            if last.elapsed() >= Duration::from_secs(10) || done == self.to_compute {
                *last = Instant::now();
                let el = self.start.elapsed().as_secs_f64();
                let eta = el / done.max(1) as f64 * (self.to_compute - done) as f64;
                eprintln!(
                    "computed {done}/{} ({} cached, {} cases), {failed} failed, {el:.0} s elapsed, ETA {eta:.0} s",
                    self.to_compute, self.cached, self.total
                );
            }
        }
    }

    fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// Whether a stored outcome is one this version gives: a deep-pocket answer stored before its
/// mesh uncertainty was measured is computed again (as an entry of an older layout is).
fn current(job: &Job, o: &Outcome) -> bool {
    o.error(&job.case, (0.0, 0.0)).is_ok()
}
