//! The pieces of the primal–dual active-set (semi-smooth Newton) iteration with Z bordered
//! (docs/solver.md, "Complementarity"): each is one step of an iteration, written once and
//! used by the product's solver ([`super::FilmSolver`]) and by the lab's inexact ones.
//!
//! For a fixed active set the film balance F (the stencil, [`Column::balance`]) is linear in
//! the unknowns x (p on the pressurised set, φ on the cavitated set) and nonlinear in Z only
//! through h(Z). A Newton iteration solves ∂F/∂x · y1 = −F and ∂F/∂x · y2 = ∂F/∂Z, then the
//! ring equation G = Z − z_pred − κ(W_h(p) + W_a(Z) − W_ps) = 0 for δZ (the Schur complement;
//! W_a the asperity load, docs/model.md §11), and moves x by y1 − y2·δZ; then nodes switch
//! sets: a pressure below its floor (the cavity pressure, docs/model.md §3) cavitates, an
//! over-full film pressurises.

use super::problem::limit_closing;
use super::{Stencil5, Step};
use crate::mesh::integrals::{contact_load, load};
use crate::mesh::{FilmState, FittedFaces, Gap, Grid, Rows};
use crate::model::film::strip_conductance;
use crate::model::film::{Column, Faces};
use crate::model::flow_factors::FlowFactors;
use crate::model::ring::RingLink;

/// Switching threshold of the active set, relative to the largest pressure: round-off.
const SWITCH_EPS: f64 = 1e-13;

/// θ = 1 on the pressurised set: φ = h there (interior nodes).
pub fn fill_pressurised(g: &Grid, state: &mut FilmState, h: &[f64]) {
    let interior = g.n2..g.n1 * g.n2;
    for ((phi, &pr), &h) in state.phi[interior.clone()]
        .iter_mut()
        .zip(&state.pressurised[interior.clone()])
        .zip(&h[interior])
    {
        if pr {
            *phi = h;
        }
    }
}

/// The x1-range [lo, hi] of node columns holding every pressurised node, with one column of
/// margin, within 1..=n1 − 1; None when nothing is pressurised.
pub fn pressurised_range(g: &Grid, pressurised: &[bool]) -> Option<(usize, usize)> {
    let (n1, n2) = (g.n1, g.n2);
    let (mut lo, mut hi) = (usize::MAX, 0);
    for i in 1..n1 {
        if pressurised[i * n2..(i + 1) * n2].contains(&true) {
            lo = lo.min(i);
            hi = i;
        }
    }
    (lo != usize::MAX).then(|| (lo.saturating_sub(1).max(1), (hi + 1).min(n1 - 1)))
}

/// Exact upwind sweep over node columns `cols`, all cavitated with p = p_c around them: the
/// stencil is affine in φ_ij with slope adv + at, and a node's balance reads φ of its own
/// node and the one upstream only, so each node is solved in order.
pub fn upwind_sweep(
    step: &Step,
    faces: &Faces,
    state: &mut FilmState,
    cols: std::ops::Range<usize>,
) {
    let n2 = step.grid.n2;
    let (adv, at) = step.coefficients();
    let phi_old = step.phi_old();
    for i in cols {
        let (done, rest) = state.phi.split_at_mut(i * n2);
        let col = Column::new(n2, faces, &state.p, done, phi_old, i);
        for (j, phi) in rest[..n2].iter_mut().enumerate() {
            let r = col.balance_with(adv, at, j, *phi);
            *phi -= r / (col.couette_slopes(adv, j).0 + at);
        }
    }
}

/// Assembles over node columns lo..=hi the Newton matrix ∂F/∂x of the current active set
/// into `a` and −F into `rhs`. F is evaluated with the conductances `faces` (the current Z);
/// the matrix with `jfaces` (the same, or those of another Z when the matrix is frozen).
#[allow(clippy::too_many_arguments)]
pub fn assemble(
    step: &Step,
    state: &FilmState,
    faces: &Faces,
    jfaces: &Faces,
    (lo, hi): (usize, usize),
    a: &mut Stencil5,
    rhs: &mut Vec<f64>,
) {
    let n2 = step.grid.n2;
    let (adv, at) = step.coefficients();
    let phi_old = step.phi_old();
    // Every entry is written below.
    a.reshape(hi - lo + 1, n2);
    rhs.clear();
    for i in lo..=hi {
        let col = Column::new(n2, faces, &state.p, &state.phi, phi_old, i);
        // The matrix's conductances and the active set around column i, and its rows, as
        // slices of length n2 (no index checked per entry).
        let (cx_w, cx_e) = (&jfaces.cx[(i - 1) * n2..][..n2], &jfaces.cx[i * n2..][..n2]);
        let cy = &jfaces.cy[i * (n2 - 1)..][..n2 - 1];
        let pr_w = &state.pressurised[(i - 1) * n2..][..n2];
        let pr = &state.pressurised[i * n2..][..n2];
        let pr_e = &state.pressurised[(i + 1) * n2..][..n2];
        let r0 = (i - lo) * n2;
        let ac = &mut a.c[r0..][..n2];
        let aw = &mut a.w[r0..][..n2];
        let ae = &mut a.e[r0..][..n2];
        let a_s = &mut a.s[r0..][..n2];
        let an = &mut a.n[r0..][..n2];
        for j in 0..n2 {
            rhs.push(-col.balance(adv, at, j));
            let cw = cx_w[j];
            let ce = cx_e[j];
            let cs = if j > 0 { cy[j - 1] } else { 0.0 };
            let cn = if j + 1 < n2 { cy[j] } else { 0.0 };
            // Diagonal: ∂F/∂p_ij = Σc on the pressurised set, ∂F/∂φ_ij = adv (+ r) + at on
            // the cavitated set.
            let (slope, slope_w) = col.couette_slopes(adv, j);
            ac[j] = if pr[j] { cw + ce + cs + cn } else { slope + at };
            // Off-diagonals depend on the neighbour's unknown only: its pressure enters
            // through −c, the upstream φ through −adv, downstream φ not at all.
            aw[j] = if i == lo {
                0.0
            } else if pr_w[j] {
                -cw
            } else {
                -slope_w
            };
            let coupled = |on: bool, c: f64| if on { -c } else { 0.0 };
            ae[j] = coupled(i < hi && pr_e[j], ce);
            a_s[j] = coupled(j > 0 && pr[j - 1], cs);
            an[j] = coupled(j + 1 < n2 && pr[j + 1], cn);
        }
    }
}

/// Work arrays of the ring's sensitivity ∂F/∂Z.
#[derive(Debug, Default, Clone)]
pub struct RingWork {
    dcx: Vec<f64>,
    dcy: Vec<f64>,
    dphi: Vec<f64>,
}

/// d(h_f³)/dh_f = 3·h_f², on a rough film d(φx·h_f³)/dh_f (docs/model.md §11, "Flow
/// factors").
#[inline(always)]
fn conductance_slope(hf: f64, flow: Option<&FlowFactors>) -> f64 {
    match flow {
        None => 3.0 * hf * hf,
        Some(f) => {
            let (phi, slope) = f.pressure_flow(hf);
            3.0 * hf * hf * phi + hf * hf * hf * slope
        }
    }
}

/// ∂(face conductance)/∂Z = 3·h_f²·∂h_f/∂Z·(geometry factor), ∂h_f/∂Z the mean of the nodal
/// ∂h/∂Z (1 under the ring, 0 elsewhere), on a rough film with the flow factors; where a row's
/// gap varies across its cell, the derivative of the strips' mean (x1 faces) or of their
/// series (x2 faces) of [`crate::mesh::face_conductances`]; a fitted x1 face's own
/// ([`crate::mesh::FaceFit::slope`]).
pub fn face_conductance_derivatives(
    g: &Grid,
    h: &[f64],
    gap: &Gap,
    dcx: &mut Vec<f64>,
    dcy: &mut Vec<f64>,
) {
    let (n1, n2) = (g.n1, g.n2);
    let (ring, flow, rows) = (&gap.ring, gap.flow.as_ref(), &gap.rows);
    let (sx, sy) = (g.dy / g.dx, g.dx / g.dy);
    let dz = |i: usize| if ring[i] { 1.0 } else { 0.0 };
    let slope = |hf: f64| conductance_slope(hf, flow);
    // Zero away from the ring (the same +0.0 the product gives), computed under it only:
    // the ring columns are the same in every call, so the zeros stay once written.
    if dcx.len() != n1 * n2 || dcy.len() != (n1 + 1) * n2.saturating_sub(1) {
        dcx.clear();
        dcx.resize(n1 * n2, 0.0);
        dcy.clear();
        dcy.resize((n1 + 1) * n2.saturating_sub(1), 0.0);
    }
    for i in 0..=n1 {
        if i < n1 && (ring[i] || ring[i + 1]) {
            for k in i * n2..(i + 1) * n2 {
                let hf = 0.5 * (h[k] + h[k + n2]);
                dcx[k] = slope(hf) * 0.5 * (dz(i) + dz(i + 1)) * sx;
            }
        }
        if ring[i] {
            for j in 0..n2.saturating_sub(1) {
                let k = i * n2 + j;
                let hf = 0.5 * (h[k] + h[k + 1]);
                dcy[i * (n2 - 1) + j] = slope(hf) * dz(i) * sy;
            }
        }
    }
    if rows.any() {
        sampled_derivatives(g, h, gap, dcx, dcy);
    }
    if let Some(f) = gap.fitted.as_ref().filter(|f| f.any()) {
        let z = gap.z_of(g, h);
        for i in (0..n1).filter(|&i| ring[i] || ring[i + 1]) {
            fitted_slopes(f, z, sx, i * n2..(i + 1) * n2, dcx);
        }
    }
    if let Some(f) = gap.fitted_x2.as_ref().filter(|f| f.any()) {
        let (z, ny) = (gap.z_of(g, h), n2.saturating_sub(1));
        for i in (0..=n1).filter(|&i| ring[i]) {
            fitted_slopes(f, z, sy, i * ny..(i + 1) * ny, dcy);
        }
    }
}

/// The fitted faces' d(conductance)/dZ times their geometry factor `scale` over the faces
/// `span` of `out` (the others left as they are).
fn fitted_slopes(
    f: &FittedFaces,
    z: f64,
    scale: f64,
    span: std::ops::Range<usize>,
    out: &mut [f64],
) {
    for (face, d) in span.clone().zip(&mut out[span]) {
        if let Some(fit) = f.face(face, z) {
            *d = fit.slope * scale;
        }
    }
}

/// The faces of [`face_conductance_derivatives`] whose rows are sampled across their cells,
/// overwritten: an x1 face's strips' mean of the slope, an x2 face's [`series_slope`].
fn sampled_derivatives(g: &Grid, h: &[f64], gap: &Gap, dcx: &mut [f64], dcy: &mut [f64]) {
    let (n1, n2) = (g.n1, g.n2);
    let (ring, flow, rows) = (&gap.ring, gap.flow.as_ref(), &gap.rows);
    let (sx, sy) = (g.dy / g.dx, g.dx / g.dy);
    let dz = |i: usize| if ring[i] { 1.0 } else { 0.0 };
    let slope = |hf: f64| conductance_slope(hf, flow);
    for i in 0..=n1 {
        if i < n1 && (ring[i] || ring[i + 1]) {
            for k in i * n2..(i + 1) * n2 {
                if rows.of(k).is_some() || rows.of(k + n2).is_some() {
                    let s = rows.across_x1_face((k, h[k]), (k + n2, h[k + n2]), slope);
                    dcx[k] = s * 0.5 * (dz(i) + dz(i + 1)) * sx;
                }
            }
        }
        if ring[i] {
            for j in 0..n2.saturating_sub(1) {
                let k = i * n2 + j;
                let (da, db) = (rows.of(k), rows.of(k + 1));
                if da.is_some() || db.is_some() {
                    let s = series_slope(rows, (da, h[k]), (db, h[k + 1]), flow);
                    dcy[i * (n2 - 1) + j] = s * dz(i) * sy;
                }
            }
        }
    }
}

/// d/dh of an x2 face's conductance over sampled rows, 1/mean(1/c(h)) over the samples
/// between them ([`crate::mesh::Rows::along_x2_face`]): mean(c′/c²)/mean(1/c)²; the nodal
/// face's where the rows do not take the series.
fn series_slope(
    rows: &Rows,
    (da, a): (Option<&[f64]>, f64),
    (db, b): (Option<&[f64]>, f64),
    flow: Option<&FlowFactors>,
) -> f64 {
    if !rows.series() {
        return conductance_slope(0.5 * (a + b), flow);
    }
    let c = |h: f64| strip_conductance(h, flow);
    let r = rows.between_rows((da, a), (db, b), |h| 1.0 / c(h));
    let d = rows.between_rows((da, a), (db, b), |h| {
        conductance_slope(h, flow) / (c(h) * c(h))
    });
    d / (r * r)
}

/// ∂F/∂Z over node columns lo..=hi into `rhs`: the same stencil with conductances ∂c/∂Z and
/// φ' = ∂h/∂Z on the pressurised set (φ = h there), without the old-time term. Only the
/// columns under the ring and their neighbours see Z; elsewhere ∂F/∂Z is exactly zero.
pub fn ring_sensitivity(
    step: &Step,
    state: &FilmState,
    h: &[f64],
    rough: &[f64],
    (lo, hi): (usize, usize),
    work: &mut RingWork,
    rhs: &mut Vec<f64>,
) {
    let (g, ring) = (step.grid, &step.gap.ring);
    let n2 = g.n2;
    let (adv, at) = step.coefficients();
    let cols = ring_columns(step);
    face_conductance_derivatives(g, h, step.gap, &mut work.dcx, &mut work.dcy);
    // φ' is read only in the columns that see Z and the one upstream of them.
    work.dphi.resize(ring.len() * n2, 0.0);
    let read = cols.start.saturating_sub(1)..cols.end.min(ring.len());
    for i in read {
        let col = &state.pressurised[i * n2..(i + 1) * n2];
        let out = &mut work.dphi[i * n2..(i + 1) * n2];
        for (d, &pr) in out.iter_mut().zip(col) {
            *d = if pr && ring[i] { 1.0 } else { 0.0 };
        }
    }
    // On a rough film d(κφ)/dZ is taken as κ·φ': its κ'(h)·φ is left out of this Jacobian
    // column (the iteration still converges to the same balance, only slower).
    let dfaces = Faces {
        cx: &work.dcx,
        cy: &work.dcy,
        rough,
    };
    rhs.clear();
    rhs.resize((hi - lo + 1) * n2, 0.0);
    for i in cols.start.max(lo)..cols.end.min(hi + 1) {
        let col = Column::new(n2, &dfaces, &state.p, &work.dphi, None, i);
        let out = &mut rhs[(i - lo) * n2..(i - lo + 1) * n2];
        for (j, r) in out.iter_mut().enumerate() {
            *r = col.balance(adv, at, j);
        }
    }
}

/// Node columns whose balance depends on Z: under the ring and one either side.
fn ring_columns(step: &Step) -> std::ops::Range<usize> {
    match step.gap.ring_columns() {
        c if c.is_empty() => 0..0,
        c => c.start.saturating_sub(1)..c.end + 1,
    }
}

/// The ring's Newton update δZ from the bordered system (y1 = −(∂F/∂x)⁻¹F, y2 =
/// (∂F/∂x)⁻¹∂F/∂Z over columns lo..=hi), limited so that no iterate closes the gap; y1 then
/// becomes the correction of x, y1 − y2·δZ.
#[allow(clippy::too_many_arguments)]
pub fn ring_update(
    step: &Step,
    link: RingLink,
    state: &FilmState,
    (lo, hi): (usize, usize),
    y1: &mut [f64],
    y2: &[f64],
    z: f64,
    ring_min_base: f64,
) -> f64 {
    let (g, ring) = (step.grid, &step.gap.ring);
    let n2 = g.n2;
    // G = Z − z_pred − κ(W_h(p) + W_a(Z) − W_ps) = 0, ∂G/∂p_k = −κ·w_k,
    // ∂G/∂Z gains −κ·dW_a/dZ ≥ 0 (the asperities stiffen the ring's balance).
    let w_h = load(g, ring, &state.p);
    let (w_a, dw_a) = asperity_load(step, link, z, ring_min_base);
    let gres = z - link.z_pred - link.kappa * (w_h + w_a - link.w_ps);
    let (mut gy1, mut gy2) = (0.0, 0.0);
    for i in (lo..=hi).filter(|&i| ring[i]) {
        for j in 0..n2 {
            if state.pressurised[i * n2 + j] {
                let r = (i - lo) * n2 + j;
                gy1 += y1[r];
                gy2 += y2[r];
            }
        }
    }
    let load_weight = g.dx * g.dy / g.width;
    let gx = -link.kappa * load_weight;
    let dz = -(gres + gx * gy1) / (1.0 - gx * gy2 - link.kappa * dw_a);
    let dz = limit_closing(dz, z, ring_min_base);
    for (a, b) in y1.iter_mut().zip(y2) {
        *a -= b * dz;
    }
    dz
}

/// The asperity load W_a and dW_a/dZ of the link's contact at Z (docs/model.md §11): (0, 0)
/// without one, or where the smallest gap under the ring, `ring_min_base` + Z, is beyond the
/// contact's reach (no pass over the ring then).
pub fn asperity_load(step: &Step, link: RingLink, z: f64, ring_min_base: f64) -> (f64, f64) {
    match link.contact {
        Some(law) if law.touches(ring_min_base + z) => contact_load(step.grid, step.gap, z, &law),
        _ => (0.0, 0.0),
    }
}

/// The ring's update δZ when nothing is pressurised (W_h = 0): a Newton step on
/// Z − z_pred − κ(W_a(Z) − W_ps) = 0, limited so that it does not close the gap; without
/// contact the explicit Z = z_pred − κ·W_ps.
pub fn unpressurised_ring_update(step: &Step, link: RingLink, z: f64, ring_min_base: f64) -> f64 {
    let (w_a, dw_a) = asperity_load(step, link, z, ring_min_base);
    if w_a == 0.0 && dw_a == 0.0 {
        return link.z_pred - link.kappa * link.w_ps - z;
    }
    let gres = z - link.z_pred - link.kappa * (w_a - link.w_ps);
    limit_closing(-gres / (1.0 - link.kappa * dw_a), z, ring_min_base)
}

/// Moves the unknowns of columns lo..=hi by `y` (p on the pressurised set, φ elsewhere);
/// returns the correction's size relative to the solution: max(|δp|/p_max, |δφ|/h), p_max
/// the largest |p − p_r| over the pressurised set (p_r the rupture pressure: a gas pressure
/// common to the whole film moves no correction's size).
pub fn apply_correction(
    step: &Step,
    state: &mut FilmState,
    h: &[f64],
    y: &[f64],
    (lo, hi): (usize, usize),
) -> f64 {
    let n2 = step.grid.n2;
    let p_r = step.boundary.rupture_pressure();
    let (mut dp, mut dphi, mut pmax) = (0.0f64, 0.0f64, 0.0f64);
    let span = lo * n2..(hi + 1) * n2;
    for ((((&d, &pr), p), phi), &h) in y
        .iter()
        .zip(&state.pressurised[span.clone()])
        .zip(&mut state.p[span.clone()])
        .zip(&mut state.phi[span.clone()])
        .zip(&h[span])
    {
        if pr {
            *p += d;
            dp = dp.max(d.abs());
            pmax = pmax.max((*p - p_r).abs());
        } else {
            *phi += d;
            dphi = dphi.max(d.abs() / h);
        }
    }
    dphi.max(if pmax > 0.0 { dp / pmax } else { 0.0 })
}

/// Active-set update with the gap `h` at the new Z (docs/model.md §3): a pressure below its
/// floor by more than ε·p_scale cavitates its node (p = p_c, φ = h to start from), a film over
/// h·(1 + ε) pressurises it (p = p_c, φ = h); ε at round-off. The floor is the cavity
/// pressure p_c: with the two sides' p_c equal, that one; else the pressure of the cavity the
/// node would join as the solve started (`FilmState::cavity`). Returns the number of
/// switches.
pub fn update_active_set(step: &Step, state: &mut FilmState, h: &[f64]) -> usize {
    let (g, bc) = (step.grid, &step.boundary);
    let (n1, n2) = (g.n1, g.n2);
    let interior = n2..n1 * n2;
    let pmax = state.pressurised[interior.clone()]
        .iter()
        .zip(&state.p[interior])
        .filter(|(&pr, _)| pr)
        .fold(0.0f64, |m, (_, &p)| m.max(p));
    // Round-off of p is relative to |p|, the cavity pressures included.
    let p_eps = SWITCH_EPS * pmax.max(bc.cavity_left.abs()).max(bc.cavity_right.abs());
    let mut changes = 0;
    for i in 1..n1 {
        for j in 0..n2 {
            let k = i * n2 + j;
            // The node's floor, fixed for the solve (docs/model.md §3).
            let floor = state.cavity_at(bc, i, n1, k);
            if state.pressurised[k] {
                if state.p[k] < floor - p_eps {
                    state.pressurised[k] = false;
                    state.p[k] = floor;
                    state.phi[k] = h[k];
                    changes += 1;
                }
            } else if state.phi[k] > h[k] * (1.0 + SWITCH_EPS) {
                state.pressurised[k] = true;
                state.p[k] = floor;
                state.phi[k] = h[k];
                changes += 1;
            }
        }
    }
    changes
}
