//! `texopt study FILE`: a study file's cases through the cache, and its report.

use super::{directory_can_be_made, install_ctrl_c, open_cache, CmdError, StudyArgs, STOP};
use crate::study::sweep::CaseFailure;

pub(super) fn run(a: &StudyArgs) -> Result<i32, CmdError> {
    let mut study = crate::study::load(&a.file).map_err(|e| CmdError::Input(e.to_string()))?;
    if let Some(dir) = &a.slurm {
        return super::slurm::run(a, &study, dir);
    }
    if let Some(share) = a.shard {
        keep_share(&mut study, share);
    }
    let report = !a.no_report && a.shard.is_none();
    let limits = a.limits.limits()?;
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    announce(&study);
    if a.dry_run {
        for j in &study.jobs {
            println!(
                "{}  [{}x{}, dt {}]",
                j.case.label(),
                j.numerics.n1,
                j.numerics.n2,
                crate::model::case::short(j.numerics.dt)
            );
        }
        return Ok(0);
    }
    // A report directory that cannot be made stops the study now, not after its simulations.
    if report {
        report_dir_can_be_made(a, &study)?;
    }
    let cache = cache_of_run(a)?;
    install_ctrl_c();
    let cache = std::sync::Mutex::new(cache);
    let opt = crate::study::sweep::Options {
        jobs,
        retry_failed: a.retry_failed,
        progress: true,
        limits,
    };
    let stop_now = std::sync::atomic::AtomicBool::new(true);
    let stop = if a.cached_only { &stop_now } else { &STOP };
    let (sum, results) = crate::study::sweep::run(&study.jobs, &cache, &opt, stop)
        .map_err(|e| CmdError::Other(e.to_string()))?;
    let threads = if jobs == 1 { "thread" } else { "threads" };
    let note = format!(
        "{} cases: {} from the cache, {} computed in {} simulations, {} failed, {} not run; {:.1} s wall time with {jobs} worker {threads}",
        sum.cases, sum.cached, sum.computed, sum.simulations, sum.failed, sum.not_run, sum.wall_time_s
    );
    println!("{note}");
    tell_unserved(&sum, &results);
    if sum.stopped && !a.cached_only {
        println!("stopped before the end: run the same command again to compute the rest");
        return Ok(130);
    }
    if let Some((i, n)) = a.shard {
        // A share has no report of its own; its failed cases are results (stored), so the
        // task succeeds and the merge that waits for every task runs.
        eprintln!(
            "share {i}/{n} done; merge the shares' caches with `texopt cache merge … --into FILE`, then report with `texopt study {} --cache FILE --cached-only`",
            a.file.display()
        );
        return Ok(0);
    }
    if report {
        write_report(a, &study, &results, &note)?;
    }
    Ok(if sum.failed > 0 { 1 } else { 0 })
}

/// Keeps share `i` of `n` of the study's cases.
fn keep_share(study: &mut crate::study::Study, (i, n): (usize, usize)) {
    let all = study.jobs.len();
    let mine = crate::study::shard::shard(&study.jobs, i, n);
    study.jobs = mine.into_iter().map(|k| study.jobs[k].clone()).collect();
    eprintln!(
        "share {i}/{n}: {} of the study's {all} cases",
        study.jobs.len()
    );
}

/// What the study runs: its cases, its fidelity, and the combinations skipped.
fn announce(study: &crate::study::Study) {
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
}

fn report_dir_can_be_made(a: &StudyArgs, study: &crate::study::Study) -> Result<(), CmdError> {
    let dir = std::path::Path::new(&study.report.dir);
    directory_can_be_made(dir).map_err(|why| {
        CmdError::Input(format!(
            "{}: the report directory {} cannot be made: {why}; change [report] dir, or run with --no-report",
            a.file.display(),
            dir.display()
        ))
    })
}

/// The cache the run reads (--cached-only) or computes into; a share's with its leases
/// cleared.
fn cache_of_run(a: &StudyArgs) -> Result<crate::study::cache::Cache, CmdError> {
    let cache = if a.cached_only {
        read_cache(a.cache.as_deref())?
    } else {
        open_cache(a.cache.as_deref())?
    };
    eprintln!("cache {}", cache.path().display());
    if a.shard.is_some() {
        // A share's cache is its task's alone: a lease left by a cancelled run of this task
        // (on whatever host) would only hold its own case back.
        cache
            .clear_leases()
            .map_err(|e| CmdError::Other(e.to_string()))?;
    }
    Ok(cache)
}

/// The cases the sweep could not serve: damaged entries, and cases over the run limits
/// (not stored: said here, whatever the report).
fn tell_unserved(sum: &crate::study::sweep::Summary, results: &[crate::study::sweep::CaseResult]) {
    for d in &sum.damaged {
        eprintln!("  damaged in the cache, not served: {d}");
    }
    let unrun: Vec<&CaseFailure> = results
        .iter()
        .filter_map(|r| match r {
            Some(Err(why @ CaseFailure::OverLimit(_))) => Some(why),
            _ => None,
        })
        .collect();
    for why in unrun.iter().take(5) {
        eprintln!("  {why}");
    }
    if unrun.len() > 5 {
        eprintln!("  … and {} more cases over the limits", unrun.len() - 5);
    }
}

/// The study's report, unless the one in place holds more; its headline on stdout.
fn write_report(
    a: &StudyArgs,
    study: &crate::study::Study,
    results: &[crate::study::sweep::CaseResult],
    note: &str,
) -> Result<(), CmdError> {
    keep_fuller_report(a, study, results)?;
    let w = crate::study::report::write(study, results, note)
        .map_err(|e| CmdError::Other(e.to_string()))?;
    for l in &w.headline {
        println!("  {l}");
    }
    for f in &w.files {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}

/// The cache a report-only run reads: it must exist, and is opened read-only (a mistyped
/// path must not become an empty cache whose report replaces the real one).
fn read_cache(flag: Option<&std::path::Path>) -> Result<crate::study::cache::Cache, CmdError> {
    let path = crate::study::cache::path_from(flag).map_err(|e| CmdError::Input(e.to_string()))?;
    if !path.is_file() {
        return Err(CmdError::Input(format!(
            "--cached-only reads a cache, and there is none at {}; give the cache the study ran into with --cache FILE (or $TEXOPT_CACHE)",
            path.display()
        )));
    }
    crate::study::cache::Cache::open_read_only(&path).map_err(super::cache_error)
}

/// A report in place that holds more evaluated cases than this run's is kept, unless
/// --replace-report says otherwise.
fn keep_fuller_report(
    a: &crate::cli::StudyArgs,
    study: &crate::study::Study,
    results: &[crate::study::sweep::CaseResult],
) -> Result<(), CmdError> {
    if a.replace_report {
        return Ok(());
    }
    let Some(before) = crate::study::report::in_place(study) else {
        return Ok(());
    };
    let evaluated = results.iter().filter(|r| r.is_some()).count();
    let done = results.iter().filter(|r| matches!(r, Some(Ok(_)))).count();
    if before.holds_more_than(done, evaluated) {
        return Err(CmdError::Input(format!(
            "{} holds {} cases done ({} evaluated) and this run has {done} ({evaluated}): the report was kept as it was; run the missing cases (without --cached-only, or with the cache that holds them), or give --replace-report to replace it",
            before.path.display(),
            before.done,
            before.evaluated
        )));
    }
    Ok(())
}
