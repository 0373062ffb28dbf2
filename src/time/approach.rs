//! The coarse approach (docs/solver.md, "Coarse approach"): the ring's transient on a mesh
//! with fewer cells across, then the film carried over to the full mesh (time/interpolate.rs),
//! which runs to its own periodic regime.

use std::time::Instant;

use super::common::SolveError;
use super::numerics::Numerics;
use super::outcome::SeriesRow;
use super::stats::ApproachDone;
use super::transient::{Transient, Watch};
use crate::model::case::CaseSpec;
use crate::solve::FilmMethod;

/// The transient of a case ready to run on `num`'s mesh: from the start of `num.start`, or,
/// with a coarse approach (`num.approach_n2` below N2), from where a run on the coarse mesh
/// reached its periodic regime to [`super::numerics::APPROACH_TOL`] (`watch` sees that run;
/// its time series, when asked for, goes to `series`).
pub(super) fn start_transient(
    case: &CaseSpec,
    num: &Numerics,
    solver: Option<fn() -> Box<dyn FilmMethod>>,
    series: Option<&mut Vec<SeriesRow>>,
    watch: &mut Watch,
) -> Result<Transient, SolveError> {
    let make = || solver.map_or_else(|| num.solver.solver(), |f| f());
    let Some(mut coarse) = num.approach_numerics(case) else {
        return Ok(Transient::with_solver(case, num, make()));
    };
    // The full mesh keeps at least half of the time allowed.
    coarse.t_max = 0.5 * num.t_max;
    let began = Instant::now();
    let mut t = Transient::new(case, &coarse);
    let r = match t.run_to_periodic(&coarse, series.is_some(), watch) {
        Ok(r) => r,
        // A coarse mesh may fail where the full one would not (a pocket it resolves poorly
        // closing the gap): then the full mesh runs from the start alone (the time spent
        // still counts).
        Err(_) => {
            let mut full = Transient::with_solver(case, num, make());
            full.set_approach(ApproachDone {
                wall_time_s: began.elapsed().as_secs_f64(),
                ..ApproachDone::default()
            });
            return Ok(full);
        }
    };
    if let (Some(all), Some(rows)) = (series, r.series) {
        all.extend(rows);
    }
    Ok(t.refined(num, ApproachDone::of(&r.outcome), make()))
}
