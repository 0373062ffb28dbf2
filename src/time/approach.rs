//! The coarse approach (docs/solver.md, "Coarse approach"): the ring's transient on a mesh
//! with fewer cells across, then the film carried over to the full mesh, which runs to its own
//! periodic regime.

use std::time::Instant;

use super::numerics::Numerics;
use super::outcome::{SeriesRow, SolveError};
use super::run::Watch;
use super::transient::{ApproachDone, Transient};
use crate::mesh::{FilmState, Scene};
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
            full.approach.wall_time_s = began.elapsed().as_secs_f64();
            return Ok(full);
        }
    };
    if let (Some(all), Some(rows)) = (series, r.series) {
        all.extend(rows);
    }
    let done = ApproachDone {
        steps: r.outcome.steps,
        periods: r.outcome.periods,
        wall_time_s: r.outcome.wall_time_s,
    };
    Ok(t.refined(num, done, make()))
}

/// The film state of scene `from` (ring at z) on the mesh of scene `to`: same N1, other N2,
/// both placed at the same texture phase. Saturation θ and pressure are interpolated
/// linearly in x2 between node centres (held constant beyond the outermost ones, the
/// symmetry lines), φ = θ·h on the new gap (h on the pressurised set, θ = 1), the active set
/// that of the nearer node. Why θ rather than φ: the pockets' depth differs node by node
/// between the meshes, the saturation far less.
pub(super) fn interpolate_x2(from: &Scene, state: &FilmState, z: f64, to: &Scene) -> FilmState {
    let (gc, gf) = (&from.grid, &to.grid);
    let mut out = FilmState::cavitated(gf, &to.gap, z, 0.0);
    let last = (gc.n2 - 1) as f64;
    for j in 0..gf.n2 {
        // The fine node's x2 in coarse node units, and its two neighbours there.
        let s = (gf.y(j) / gc.dy - 0.5).clamp(0.0, last);
        let j0 = s.floor() as usize;
        let j1 = (j0 + 1).min(gc.n2 - 1);
        let w = s - j0 as f64;
        for i in 0..=gf.n1 {
            let (k0, k1) = (gc.idx(i, j0), gc.idx(i, j1));
            let theta_at = |k: usize| state.theta(gc, &from.gap, z, k).clamp(0.0, 1.0);
            let theta = (1.0 - w) * theta_at(k0) + w * theta_at(k1);
            let p = (1.0 - w) * state.p[k0] + w * state.p[k1];
            let k = gf.idx(i, j);
            let h = to.gap.h(gf, k, z);
            let pressurised = state.pressurised[if w < 0.5 { k0 } else { k1 }];
            out.pressurised[k] = pressurised;
            out.p[k] = if pressurised { p.max(0.0) } else { 0.0 };
            out.phi[k] = if pressurised { h } else { theta * h };
        }
    }
    out
}
