//! `cycle`'s liners judged over the engine cycle as one transient (docs/model.md §12): the
//! plain liner, the uniform texture and the zones' designs each run through the whole cycle,
//! dead centres included, until the cycle repeats itself; each zone then keeps whichever of
//! the three does least friction work while the ring is over it, and the liner so assembled
//! is run in its turn.

use super::liner::Trio;
use rayon::prelude::*;

use super::angles::{CycleSettings, Designs};
use crate::model::case::{CaseSpec, Texture};
use crate::model::liner_layout::LinerLayout;
use crate::optimise::error::OptimiseError;
use crate::time::cycle::CycleWatch;
use crate::time::cycle::{
    cycle_numerics, metrics, CycleMetrics, CycleOutcome, CycleRun, CycleSummary, Drive,
};
use crate::time::Fidelity;

/// One liner run through the cycle.
#[derive(Clone, Debug)]
pub struct LinerCycle {
    /// The texture of each zone (None: plain).
    pub textures: Vec<Option<Texture>>,
    pub outcome: CycleOutcome,
    pub metrics: CycleMetrics,
    /// Its wall time (s).
    pub wall_s: f64,
}

/// The three liners of the report (plain, uniform best, zoned) and the designs they carry.
pub struct TransientLiners {
    /// The plain, uniform and zoned liners' cycles.
    pub runs: Trio<LinerCycle>,
    /// Per zone, which liner's texture it keeps.
    pub kept: Vec<Kept>,
}

/// Which of the three liners' textures a zone of the zoned liner keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kept {
    Plain,
    Uniform,
    /// The zone's own design.
    Own,
}

impl Kept {
    /// The three, in the order the report lists the liners (a tie goes to the earlier).
    pub const ALL: [Kept; 3] = [Kept::Plain, Kept::Uniform, Kept::Own];

    /// Its words in the report.
    pub fn label(self) -> &'static str {
        match self {
            Kept::Plain => "plain",
            Kept::Uniform => "uniform",
            Kept::Own => "zone design",
        }
    }
}

/// The engine's ring with the engine file's contact and the settings' roughness
/// (docs/model.md §11).
pub fn ring_case(s: &CycleSettings, drive: &Drive) -> CaseSpec {
    drive.ring_case_at(s.search.validity.roughness_um)
}

/// Runs the liner of zone `textures` through the cycle at `fidelity` until it repeats
/// itself; `label` names it in the progress lines.
pub fn run_liner(
    s: &CycleSettings,
    textures: Vec<Option<Texture>>,
    fidelity: Fidelity,
    label: &str,
) -> Result<LinerCycle, OptimiseError> {
    let t0 = std::time::Instant::now();
    let drive = Drive::new(&s.engine);
    let ring = ring_case(s, &drive);
    let bounds_cm = s.zones.bounds_cm();
    let layout = LinerLayout::zoned(bounds_cm, textures.clone())?;
    let finest = textures
        .iter()
        .flatten()
        .min_by(|a, b| a.per.total_cmp(&b.per));
    let numerics = cycle_numerics(fidelity, &s.search.overrides, &ring, finest);
    let run =
        CycleRun::new(&drive, ring, layout, numerics).map_err(|source| OptimiseError::RunOf {
            label: label.to_string(),
            source,
        })?;
    let progress = s.search.progress;
    let mut on_cycle = |c: &CycleSummary| {
        if progress {
            eprintln!(
                "[{:6.1} s] {label}: cycle {} of {} steps, friction work {:.4} J/m (change {}), oil map change {}",
                t0.elapsed().as_secs_f64(),
                1 + c.index,
                c.steps,
                c.friction_work_j_per_m,
                percent(c.work_change),
                percent(c.oil_change),
            );
        }
    };
    let outcome = run
        .run(CycleWatch {
            on_window: Some(&mut on_cycle),
            on_step: None,
        })
        .map_err(|source| OptimiseError::RunOf {
            label: label.to_string(),
            source,
        })?;
    let metrics = metrics(&outcome.rows, &s.engine, s.zones.bounds_mm());
    Ok(LinerCycle {
        textures,
        outcome,
        metrics,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

fn percent(x: f64) -> String {
    if x.is_finite() {
        format!("{:.3} %", 100.0 * x)
    } else {
        "–".into()
    }
}

/// The plain liner, the uniform search's best texture and the zones' best textures of `d`
/// (their candidates: whether or not they beat the plain liner at the search's angles, which
/// leave out the dead centres) through the cycle at the report's fidelity, side by side; each
/// zone then keeps the least work of the three there.
pub fn evaluate_transient(
    s: &CycleSettings,
    d: &Designs,
) -> Result<(Designs, TransientLiners), OptimiseError> {
    let fidelity = s.search.report_fidelity;
    let zones = d.zones.len();
    let plain_t = vec![None; zones];
    let uniform_t = vec![d.uniform_candidate.clone(); zones];
    let own_t = d.candidates.clone();
    let layouts = [
        (plain_t.clone(), "plain liner"),
        (uniform_t.clone(), "uniform texture"),
        (own_t.clone(), "zones' designs"),
    ];
    // A liner equal to one before it is not run twice.
    let distinct: Vec<usize> = (0..3)
        .filter(|&k| (0..k).all(|j| layouts[j].0 != layouts[k].0))
        .collect();
    let runs: Vec<(usize, LinerCycle)> = distinct
        .par_iter()
        .map(|&k| {
            Ok((
                k,
                run_liner(s, layouts[k].0.clone(), fidelity, layouts[k].1)?,
            ))
        })
        .collect::<Result<_, OptimiseError>>()?;
    let find = |k: usize| -> LinerCycle {
        let src = (0..=k).find(|&j| layouts[j].0 == layouts[k].0).unwrap_or(k);
        runs.iter()
            .find(|(i, _)| *i == src)
            .map(|(_, r)| r.clone())
            .expect("every distinct liner was run")
    };
    let (plain, uniform, own) = (find(0), find(1), find(2));
    // Per zone the least work of the three (ties to the plainer liner).
    let liner = |k: Kept| match k {
        Kept::Plain => (&plain, &plain_t),
        Kept::Uniform => (&uniform, &uniform_t),
        Kept::Own => (&own, &own_t),
    };
    let kept: Vec<Kept> = (0..zones)
        .map(|z| {
            let w = |k: Kept| liner(k).0.metrics.zone_work_j_per_m[z];
            Kept::ALL
                .into_iter()
                .fold(Kept::Plain, |best, k| if w(k) < w(best) { k } else { best })
        })
        .collect();
    let chosen: Vec<Option<Texture>> = (0..zones).map(|z| liner(kept[z]).1[z].clone()).collect();
    let zoned = match layouts.iter().position(|l| l.0 == chosen) {
        Some(k) => find(k),
        None => run_liner(s, chosen.clone(), fidelity, "zoned liner")?,
    };
    let uniform_kept = (uniform.metrics.work_j_per_m < plain.metrics.work_j_per_m)
        .then(|| d.uniform_candidate.clone())
        .flatten();
    let designs = Designs {
        zones: chosen,
        uniform: uniform_kept,
        ..d.clone()
    };
    Ok((
        designs,
        TransientLiners {
            runs: Trio {
                plain,
                uniform,
                designed: zoned,
            },
            kept,
        },
    ))
}
