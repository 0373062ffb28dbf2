//! What every solver of a film problem shares: the gap and face conductances at the current
//! Z, the boundary conditions, the final state and the guards a solution must pass.

use super::{FilmError, SolveStats, Step};
use crate::mesh::integrals::{contact_load, load};
use crate::mesh::{face_conductances, FilmState, FittedFaces, Grid};
use crate::model::film::{Column, Faces};
use crate::model::flow_factors::FlowFactors;

/// Largest excursion of θ outside [0, 1] taken for round-off.
const THETA_ROUND_OFF: f64 = 1e-9;

/// The gap of one film problem at the current Z and its face conductances, refreshed only
/// where Z changes them (the node columns under the ring).
#[derive(Debug, Default, Clone)]
pub struct GapCache {
    h: Vec<f64>,
    /// The Z at which `h` holds this problem's gap (None: not yet filled for it).
    h_at: Option<f64>,
    /// This problem's node columns from the first under the ring to the last.
    ring_span: std::ops::Range<usize>,
    /// Whether `cx`, `cy` hold this problem's conductances away from the ring.
    faces_fresh: bool,
    cx: Vec<f64>,
    cy: Vec<f64>,
    /// A rough film's Couette coefficients per node, empty for a smooth one
    /// ([`Faces::rough`]).
    rough: Vec<f64>,
}

impl GapCache {
    /// A new problem: the texture has moved since the gap and conductances were set.
    pub fn begin(&mut self, step: &Step) {
        self.h_at = None;
        self.faces_fresh = false;
        self.ring_span = step.gap.ring_columns();
    }

    /// The gap (after [`GapCache::fill_h`] or [`GapCache::set_gap`]).
    pub fn h(&self) -> &[f64] {
        &self.h
    }

    /// The face conductances (after [`GapCache::set_gap`] or [`GapCache::refresh_faces`]).
    pub fn faces(&self) -> Faces<'_> {
        Faces {
            cx: &self.cx,
            cy: &self.cy,
            rough: &self.rough,
        }
    }

    /// The node columns from the first under the ring to the last.
    pub fn ring_span(&self) -> std::ops::Range<usize> {
        self.ring_span.clone()
    }

    /// The gap at Z, unless it holds that already (an iteration fills it at the new Z to
    /// update the active set, and the next iteration starts there).
    pub fn fill_h(&mut self, step: &Step, z: f64) {
        match self.h_at {
            Some(at) if at.to_bits() == z.to_bits() => {}
            // This problem's gap at another Z: only the columns under the ring change.
            Some(_) => step
                .gap
                .refill_ring(step.grid, z, self.ring_span.clone(), &mut self.h),
            None => step.gap.fill(step.grid, z, &mut self.h),
        }
        self.h_at = Some(z);
    }

    /// The face conductances of the gap held (and a rough film's Couette coefficients): all
    /// of them at a problem's first call, afterwards only those under the ring (elsewhere h
    /// does not depend on Z).
    pub fn refresh_faces(&mut self, step: &Step) {
        let only_ring = self.faces_fresh.then_some(&step.gap.ring[..]);
        let flow = step.gap.flow.as_ref();
        face_conductances(
            step.grid,
            &self.h,
            only_ring,
            step.gap,
            &mut self.cx,
            &mut self.cy,
        );
        match (flow, step.gap.fitted.as_ref().filter(|f| f.any())) {
            (Some(f), _) => self.refresh_rough(step, f),
            (None, Some(fit)) => self.refresh_content(step, fit),
            (None, None) => self.rough.clear(),
        }
        self.faces_fresh = true;
    }

    /// The Couette flux of a fitted x1 face carries its full film's content, θ of the node
    /// upstream times the face's [`crate::mesh::FaceFit::content`]: the node's coefficient
    /// r = u·dy·(content/h − 1) (the stencil's adv·φ + r·φ, [`Faces::rough`]); 0 on nodal
    /// faces. Only under the ring once the problem's are set.
    fn refresh_content(&mut self, step: &Step, fit: &FittedFaces) {
        let (g, ring) = (step.grid, &step.gap.ring);
        let adv = step.boundary.u_rough * g.dy;
        let z = self.h_at.unwrap_or(0.0);
        let fresh = self.faces_fresh && self.rough.len() == self.h.len();
        self.rough.resize(self.h.len(), 0.0);
        for i in 0..g.n1 {
            if fresh && !(ring[i] || ring[i + 1]) {
                continue;
            }
            for k in i * g.n2..(i + 1) * g.n2 {
                self.rough[k] = fit
                    .face(k, z)
                    .map_or(0.0, |f| adv * (f.content / self.h[k] - 1.0));
            }
        }
    }

    /// r = u·dy·(κ − 1) per node (docs/model.md §11, "Flow factors"), at the liner's own
    /// speed whatever the scheme carries; only under the ring once the problem's are set.
    fn refresh_rough(&mut self, step: &Step, f: &FlowFactors) {
        let (g, ring) = (step.grid, &step.gap.ring);
        let adv = step.boundary.u_rough * g.dy;
        let fresh = self.faces_fresh && self.rough.len() == self.h.len();
        self.rough.resize(self.h.len(), 0.0);
        for (i, &under) in ring.iter().enumerate() {
            if under || !fresh {
                let first = i * g.n2;
                let span = first..first + g.n2;
                for (m, (r, &h)) in self.rough[span.clone()]
                    .iter_mut()
                    .zip(&self.h[span])
                    .enumerate()
                {
                    *r = adv * step.gap.couette_excess(f, first + m, h);
                }
            }
        }
    }

    /// The gap at Z and its face conductances; a closed gap is an error.
    pub fn set_gap(&mut self, step: &Step, z: f64) -> Result<(), FilmError> {
        let g = step.grid;
        // After this problem's first fill only the columns under the ring can change.
        let span = if self.h_at.is_some() {
            self.ring_span.start * g.n2..self.ring_span.end * g.n2
        } else {
            0..g.nodes()
        };
        self.fill_h(step, z);
        let closed = |h: &f64| *h <= 0.0 || h.is_nan();
        let rows = &step.gap.rows;
        let first = self.h[span.clone()].iter().position(closed);
        // A sampled row's least gap is its mean's plus its deepest deviation below it.
        let first = match rows.any() {
            false => first,
            true => span
                .clone()
                .position(|k| closed(&(self.h[k] + rows.min_dev(k)))),
        };
        if let Some(k) = first.map(|k| k + span.start) {
            return Err(FilmError::GapClosed {
                h: self.h[k],
                x1: g.x(k / g.n2),
                x2: g.y(k % g.n2),
            });
        }
        self.refresh_faces(step);
        Ok(())
    }

    /// Largest nodal residual of the state at Z ([`max_relative_residual`]).
    pub fn residual(&mut self, step: &Step, state: &FilmState, z: f64) -> f64 {
        self.fill_h(step, z);
        self.refresh_faces(step);
        let (adv, at) = step.coefficients();
        max_relative_residual(
            step.grid,
            &self.faces(),
            adv,
            at,
            &state.p,
            &state.phi,
            step.phi_old(),
        )
    }
}

/// The boundary conditions (docs/model.md §3) on the end columns of `state`: p given at both
/// ends, the inlet film (capped at the gap) at x1 = 0, nothing pressurised there; and the
/// cavity pressures on the cavitated nodes (the state may hold another problem's).
pub fn impose_boundary(step: &Step, state: &mut FilmState, z: f64) {
    let (g, bc) = (step.grid, step.boundary);
    state.lay_cavity_pressure(g, &bc);
    for j in 0..g.n2 {
        let (k0, kn) = (g.idx(0, j), g.idx(g.n1, j));
        state.p[k0] = bc.p_left;
        state.phi[k0] = bc.phi_inlet.min(step.gap.h(g, k0, z));
        state.pressurised[k0] = false;
        state.p[kn] = bc.p_right;
        state.pressurised[kn] = false;
    }
}

/// Final state, guards and statistics of a converged solve: p = p_c on the cavitated set and
/// θ = 1 on the pressurised set, the outlet column's film copied from upstream, the residual
/// of the state as solved, then round-off pressures below the rupture pressure clipped and θ
/// checked.
pub fn finish(
    cache: &mut GapCache,
    step: &Step,
    state: &mut FilmState,
    z: f64,
    iterations: usize,
    cycles: usize,
) -> Result<SolveStats, FilmError> {
    let g = step.grid;
    let (n1, n2) = (g.n1, g.n2);
    let interior = n2..n1 * n2;
    // φ on the cavitated set is left as solved (θ ≤ 1 + 1e-13, the switching threshold):
    // clipping it would remove mass where φ ≈ h is large (the flooded gap e upstream of the
    // ring) and break the exact discrete balance.
    cache.fill_h(step, z);
    let bc = step.boundary;
    for i in 1..n1 {
        for k in i * n2..(i + 1) * n2 {
            if state.pressurised[k] {
                state.phi[k] = cache.h[k];
            } else {
                state.p[k] = state.cavity_at(&bc, i, n1, k);
            }
        }
    }
    for j in 0..n2 {
        state.phi[g.idx(n1, j)] = state.phi[g.idx(n1 - 1, j)];
    }
    // The residual before the round-off excursions below the rupture pressure p_r the
    // switching threshold lets stand (p_r − p ≤ 1e-13·p_max) are clipped: next to the face
    // between the ring's edge and the gap e (h_f ≈ e/2, a conductance ≈ 10⁸) such a clip of
    // 1e-17 alone shows as a residual of ≈ 1e-7 of the node's fluxes, which says nothing
    // about the solve.
    let residual = cache.residual(step, state, z);
    let p_r = bc.rupture_pressure();
    for k in interior.clone() {
        if state.pressurised[k] {
            state.p[k] = state.p[k].max(p_r);
        }
    }
    // θ = φ/h must stay in [0, 1] up to round-off (a wrong number that looks right is worse
    // than an error).
    if let Some(k) = interior.clone().find(|&k| {
        let theta = state.phi[k] / cache.h[k];
        !(-THETA_ROUND_OFF..=1.0 + THETA_ROUND_OFF).contains(&theta)
    }) {
        return Err(FilmError::SaturationOutOfRange {
            theta: state.phi[k] / step.gap.h(g, k, z),
            x1: g.x(k / n2),
            x2: g.y(k % n2),
        });
    }
    Ok(SolveStats {
        iterations,
        cycles,
        factorisations: 0,
        eliminated_rows: 0,
        residual,
        w_h: load(g, &step.gap.ring, &state.p),
        w_a: step
            .ring
            .and_then(|link| link.contact)
            .map_or(0.0, |law| contact_load(g, step.gap, z, &law).0),
    })
}

/// Largest nodal residual of the discrete film equation (the one stencil) relative to the
/// largest term of that node's balance: the measure every solver is stopped and reported by.
pub fn max_relative_residual(
    g: &Grid,
    faces: &Faces,
    adv: f64,
    at: f64,
    p: &[f64],
    phi: &[f64],
    phi_old: Option<&[f64]>,
) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 1..g.n1 {
        let col = Column::new(g.n2, faces, p, phi, phi_old, i);
        for j in 0..g.n2 {
            let r = col.balance(adv, at, j);
            let pscale = col.cx_w[j].max(col.cx_e[j])
                * col.p[j].abs().max(col.p_w[j].abs().max(col.p_e[j].abs()));
            let scale = pscale + (adv + at) * col.phi[j].abs() + adv * col.phi_w[j];
            // Divides only where the ratio may exceed the worst so far: rounding is monotone
            // and |r| is a float, so |r|/scale > worst implies |r| ≥ fl(worst·scale). The
            // same maximum, bit for bit, without a division per node.
            if scale > 0.0 && r.abs() >= worst * scale {
                worst = worst.max(r.abs() / scale);
            }
        }
    }
    worst
}

/// Damping of a ring update: it may at most halve the smallest gap under the ring, so no
/// iterate closes it (a ring truly pushed into the liner still fails).
pub fn limit_closing(dz: f64, z: f64, ring_min_base: f64) -> f64 {
    if ring_min_base + z + dz <= 0.5 * (ring_min_base + z) {
        -0.5 * (ring_min_base + z)
    } else {
        dz
    }
}

/// Every interior p and φ and Z finite, else an error naming where.
pub fn check_finite(g: &Grid, state: &FilmState, z: f64) -> Result<(), FilmError> {
    if !z.is_finite() {
        return Err(FilmError::NonFinite {
            quantity: "ring position Z",
            x1: f64::NAN,
            x2: f64::NAN,
        });
    }
    // A value is not finite when its exponent bits are all set: one branch-free pass says
    // whether there is any; only then is it looked for.
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    let bad = |x: f64| x.to_bits() & EXPONENT == EXPONENT;
    let mut interior = g.n2..g.n1 * g.n2;
    let any = state.p[interior.clone()]
        .iter()
        .zip(&state.phi[interior.clone()])
        .fold(false, |a, (&p, &phi)| a | bad(p) | bad(phi));
    if !any {
        return Ok(());
    }
    if let Some(k) = interior.find(|&k| !(state.p[k].is_finite() && state.phi[k].is_finite())) {
        return Err(FilmError::NonFinite {
            quantity: if state.p[k].is_finite() {
                "film content hθ"
            } else {
                "pressure"
            },
            x1: g.x(k / g.n2),
            x2: g.y(k % g.n2),
        });
    }
    Ok(())
}
