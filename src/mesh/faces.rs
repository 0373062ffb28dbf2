//! Face conductances of the Poiseuille flux over the mesh (docs/model.md §3): x1 faces
//! h_f³·dy/dx and x2 faces h_f³·dx/dy, h_f the mean of the two nodal gaps
//! ([`face_conductance`]), times the pressure flow factor φx(h_f) on a rough film
//! (docs/model.md §11, "Flow factors").

use super::Grid;
use crate::model::film::face_conductance;
use crate::model::flow_factors::FlowFactors;

/// Face conductances for the gap `h` into `cx`, `cy` (layout of [`crate::model::film::Faces`]),
/// of a smooth film or, with `flow`, a rough one.
/// With `only_ring`, only the faces of node columns under the ring (where h depends on Z) are
/// recomputed: the others must already hold this gap's (same texture position), which they
/// then keep, the same bits.
pub fn face_conductances(
    g: &Grid,
    h: &[f64],
    only_ring: Option<&[bool]>,
    flow: Option<&FlowFactors>,
    cx: &mut Vec<f64>,
    cy: &mut Vec<f64>,
) {
    let (n1, n2) = (g.n1, g.n2);
    let (sx, sy) = (g.dy / g.dx, g.dx / g.dy);
    let ny = n2.saturating_sub(1);
    let conductance = |a: f64, b: f64, s: f64| match flow {
        None => face_conductance(a, b, s),
        Some(f) => face_conductance(a, b, s) * f.pressure_flow(0.5 * (a + b)).0,
    };
    // x1 faces east of the nodes of columns `cols`, over slices of neighbouring nodes (no
    // index checked per face).
    let x_faces = |cols: std::ops::Range<usize>, out: &mut [f64]| {
        let (west, east) = (
            &h[cols.start * n2..cols.end * n2],
            &h[(cols.start + 1) * n2..],
        );
        for ((c, &a), &b) in out.iter_mut().zip(west).zip(east) {
            *c = conductance(a, b, sx);
        }
    };
    // x2 faces of column i.
    let y_faces = |i: usize, out: &mut [f64]| {
        let col = &h[i * n2..(i + 1) * n2];
        for ((c, &a), &b) in out.iter_mut().zip(col).zip(&col[1..]) {
            *c = conductance(a, b, sy);
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
