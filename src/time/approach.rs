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

/// The film state of scene `from` (ring at z) on the mesh of scene `to`, both placed at the
/// same texture phase: saturation θ and pressure interpolated bilinearly between the coarse
/// nodes (x1 nodes are vertices, x2 nodes cell centres, held constant beyond the outermost
/// ones, the symmetry lines), φ = θ·h on the new gap (h on the pressurised set, θ = 1), the
/// active set that of the nearest node. Why θ rather than φ: the pockets' depth differs node
/// by node between the meshes, the saturation far less.
pub(super) fn interpolate(from: &Scene, state: &FilmState, z: f64, to: &Scene) -> FilmState {
    let (gc, gf) = (&from.grid, &to.grid);
    let mut out = FilmState::cavitated(gf, &to.gap, z, 0.0);
    // A fine coordinate in coarse node units: the two neighbours and the weight of the second.
    let between = |s: f64, last: usize| {
        let s = s.clamp(0.0, last as f64);
        let a = (s.floor() as usize).min(last);
        (a, (a + 1).min(last), s - a as f64)
    };
    let theta_at = |k: usize| state.theta(gc, &from.gap, z, k).clamp(0.0, 1.0);
    for i in 0..=gf.n1 {
        let (i0, i1, u) = between(gf.x(i) / gc.dx, gc.n1);
        for j in 0..gf.n2 {
            let (j0, j1, w) = between(gf.y(j) / gc.dy - 0.5, gc.n2 - 1);
            let corners = [
                (gc.idx(i0, j0), (1.0 - u) * (1.0 - w)),
                (gc.idx(i1, j0), u * (1.0 - w)),
                (gc.idx(i0, j1), (1.0 - u) * w),
                (gc.idx(i1, j1), u * w),
            ];
            let theta: f64 = corners.iter().map(|&(k, c)| c * theta_at(k)).sum();
            let p: f64 = corners.iter().map(|&(k, c)| c * state.p[k]).sum();
            let nearest = gc.idx(if u < 0.5 { i0 } else { i1 }, if w < 0.5 { j0 } else { j1 });
            let pressurised = state.pressurised[nearest];
            let k = gf.idx(i, j);
            let h = to.gap.h(gf, k, z);
            out.pressurised[k] = pressurised;
            out.p[k] = if pressurised { p.max(0.0) } else { 0.0 };
            out.phi[k] = if pressurised { h } else { theta * h };
        }
    }
    out
}
