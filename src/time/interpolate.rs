//! A film carried from one mesh to another (the coarse approach's and the deep-pocket mesh's
//! handover, docs/solver.md, "Coarse approach").

use crate::mesh::{FilmState, Scene};

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
