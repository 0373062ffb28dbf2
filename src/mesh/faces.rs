//! Face conductances of the Poiseuille flux over the mesh (docs/model.md §3): x1 faces
//! h_f³·dy/dx and x2 faces h_f³·dx/dy, h_f the mean of the two nodal gaps
//! ([`face_conductance`]), times the pressure flow factor φx(h_f) on a rough film
//! (docs/model.md §11, "Flow factors"); where a row's gap varies across its cell, the
//! strips across an x1 face in parallel and the gap between two rows in series
//! ([`super::Rows`]); a face fitted to the gap between its nodes (`Gap::fitted` along x1,
//! `Gap::fitted_x2` across) takes its strips' exact one-dimensional conductance
//! ([`super::FittedFaces`]).

use super::{Gap, Grid};
use crate::model::film::{face_conductance, strip_conductance};

/// Face conductances for the gap `h` into `cx`, `cy` (layout of [`crate::model::film::Faces`]),
/// of the gap's film (smooth, or rough with `gap.flow`) over its rows (`gap.rows`).
/// With `only_ring`, only the faces of node columns under the ring (where h depends on Z) are
/// recomputed: the others must already hold this gap's (same texture position), which they
/// then keep, the same bits.
pub fn face_conductances(
    g: &Grid,
    h: &[f64],
    only_ring: Option<&[bool]>,
    gap: &Gap,
    cx: &mut Vec<f64>,
    cy: &mut Vec<f64>,
) {
    let (n1, n2) = (g.n1, g.n2);
    let (sx, sy) = (g.dy / g.dx, g.dx / g.dy);
    let ny = n2.saturating_sub(1);
    let (flow, rows) = (gap.flow.as_ref(), &gap.rows);
    let conductance = |a: f64, b: f64, s: f64| match flow {
        None => face_conductance(a, b, s),
        Some(f) => face_conductance(a, b, s) * f.pressure_flow(0.5 * (a + b)).0,
    };
    let strip = |hf: f64| strip_conductance(hf, flow);
    let fitted = gap.fitted.as_ref().filter(|f| f.any());
    let fitted_x2 = gap.fitted_x2.as_ref().filter(|f| f.any());
    let z = match (fitted, fitted_x2) {
        (None, None) => 0.0,
        _ => gap.z_of(g, h),
    };
    // x1 faces east of the nodes of columns `cols`, over slices of neighbouring nodes (no
    // index checked per face); then the faces of rows sampled across their cells.
    let x_faces = |cols: std::ops::Range<usize>, out: &mut [f64]| {
        let first = cols.start * n2;
        let (west, east) = (&h[first..cols.end * n2], &h[first + n2..]);
        for ((c, &a), &b) in out.iter_mut().zip(west).zip(east) {
            *c = conductance(a, b, sx);
        }
        if rows.any() {
            for (k, c) in (first..).zip(out.iter_mut()) {
                if rows.of(k).is_some() || rows.of(k + n2).is_some() {
                    *c = rows.across_x1_face((k, h[k]), (k + n2, h[k + n2]), strip) * sx;
                }
            }
        }
        if let Some(f) = fitted {
            for (k, c) in (first..).zip(out.iter_mut()) {
                if let Some(fit) = f.face(k, z) {
                    *c = fit.conductance * sx;
                }
            }
        }
    };
    // x2 faces of column i.
    let y_faces = |i: usize, out: &mut [f64]| {
        let first = i * n2;
        let col = &h[first..first + n2];
        for ((c, &a), &b) in out.iter_mut().zip(col).zip(&col[1..]) {
            *c = conductance(a, b, sy);
        }
        if rows.any() {
            for (k, c) in (first..).zip(out.iter_mut()) {
                if rows.of(k).is_some() || rows.of(k + 1).is_some() {
                    *c = rows.along_x2_face((k, h[k]), h[k + 1], strip) * sy;
                }
            }
        }
        if let Some(f) = fitted_x2 {
            for (face, c) in (i * ny..).zip(out.iter_mut()) {
                if let Some(fit) = f.face(face, z) {
                    *c = fit.conductance * sy;
                }
            }
        }
    };
    let Some(ring) = only_ring else {
        cx.resize(n1 * n2, 0.0);
        x_faces(0..n1, cx);
        cy.resize((n1 + 1) * ny, 0.0);
        for i in 0..=n1 {
            y_faces(i, &mut cy[i * ny..(i + 1) * ny]);
        }
        return;
    };
    for i in 0..=n1 {
        if i < n1 && (ring[i] || ring[i + 1]) {
            x_faces(i..i + 1, &mut cx[i * n2..(i + 1) * n2]);
        }
        if ring[i] {
            y_faces(i, &mut cy[i * ny..(i + 1) * ny]);
        }
    }
}
