//! Integrals of the film over the mesh: the hydrodynamic load (eq. 16), the asperity load
//! (docs/model.md §11), the friction terms (eq. 17 and the boundary friction, eq. A4) and the
//! mass flows through the ends of the domain (docs/model.md §3–5), by nodal quadrature over
//! the node columns under the ring.

use super::{FilmState, Gap, Grid};
use crate::model::asperity::ContactLaw;
use crate::model::film::{strip_conductance, x1_flux};
use crate::model::flow_factors::FlowFactors;
use crate::model::friction::{
    boundary_term, couette_shear, poiseuille_term, pressure_term, Friction, FrictionModel,
};
use crate::model::units::friction_coefficient;

/// Hydrodynamic load per unit width W_h = (1/B)∫∫_ring p dx1 dx2 (eq. 16), as the nodal sum
/// over the node columns under the ring.
pub fn load(g: &Grid, ring: &[bool], p: &[f64]) -> f64 {
    let mut s = 0.0;
    for (i, &r) in ring.iter().enumerate() {
        if r {
            s += p[i * g.n2..(i + 1) * g.n2].iter().sum::<f64>();
        }
    }
    s * g.dx * g.dy / g.width
}

/// Asperity load per unit width W_a = (1/B)∫∫_ring p_a(h) dx1 dx2 (docs/model.md §11) and
/// its derivative dW_a/dZ = (1/B)∫∫_ring dp_a/dh (∂h/∂Z = 1 under the ring), by the nodal
/// quadrature of [`load`], at ring position `z`. Both exactly 0 where every gap under the
/// ring is at least 4σ ([`ContactLaw::reach_um`]).
pub fn contact_load(g: &Grid, gap: &Gap, z: f64, law: &ContactLaw) -> (f64, f64) {
    let (mut w, mut dw) = (0.0, 0.0);
    let n2 = g.n2;
    for (i, &r) in gap.ring.iter().enumerate() {
        if r {
            for k in i * n2..(i + 1) * n2 {
                let h = gap.base[k] + z;
                match gap.rows.of(k) {
                    None if law.touches(h) => {
                        let (p, dp) = law.pressure_and_dh(h);
                        w += p;
                        dw += dp;
                    }
                    None => {}
                    // A row that varies across its cell: its samples' mean.
                    Some(_) => {
                        let part = |f: fn(&ContactLaw, f64) -> f64| {
                            gap.rows
                                .mean_of(k, h, |x| if law.touches(x) { f(law, x) } else { 0.0 })
                        };
                        w += part(|l, x| l.pressure_and_dh(x).0);
                        dw += part(|l, x| l.pressure_and_dh(x).1);
                    }
                }
            }
        }
    }
    let weight = g.dx * g.dy / g.width;
    (w * weight, dw * weight)
}

/// Mass flow rates of φ = hθ through the x1 boundaries of the interior control volumes,
/// summed over the simulated width: (inflow through the face at x1 = dx/2, outflow through
/// the face at x1 = length − dx/2), with the flux of [`x1_flux`] at liner speed `u` and, on
/// a rough film, its φx and its share (u_rough/2)·(κ − 1)·φ of the Couette flux
/// (docs/model.md §11, "Flow factors"). Over a step,
/// Σ(φ^{n+1} − φ^n)·dx·dy = dt·(inflow − outflow) at the new level.
pub fn boundary_flows(
    g: &Grid,
    gap: &Gap,
    z: f64,
    (u, u_rough): (f64, f64),
    state: &FilmState,
) -> (f64, f64) {
    let n1 = g.n1;
    let flux = |i: usize, j: usize| {
        let (k, kn) = (g.idx(i, j), g.idx(i + 1, j));
        let (a, b) = (gap.h(g, k, z), gap.h(g, kn, z));
        let hf = 0.5 * (a + b);
        let dp = state.p[kn] - state.p[k];
        let rough = |f: &FlowFactors| 0.5 * u_rough * gap.couette_excess(f, k, a) * state.phi[k];
        if gap.rows.of(k).is_some() || gap.rows.of(kn).is_some() {
            // The strips' conductance of `face_conductances`.
            let flow = gap.flow.as_ref();
            let c = gap
                .rows
                .across_x1_face((k, a), (kn, b), |h| strip_conductance(h, flow));
            return 0.5 * u * state.phi[k] - 0.5 * c * dp / g.dx + flow.map_or(0.0, rough);
        }
        match &gap.flow {
            None => x1_flux(u, state.phi[k], hf, dp, g.dx),
            Some(f) => x1_flux(u, state.phi[k], hf, dp * f.pressure_flow(hf).0, g.dx) + rough(f),
        }
    };
    let inflow = (0..g.n2).map(|j| flux(0, j) * g.dy).sum();
    let outflow = (0..g.n2).map(|j| flux(n1 - 1, j) * g.dy).sum();
    (inflow, outflow)
}

/// Friction coefficients of the current state (eq. 17 by nodal quadrature over the ring,
/// ∂p/∂x1 and ∂h_L/∂x1 by centred differences of nodal values). `hl` is the texture depth h_L
/// per node (µm).
pub fn friction(
    g: &Grid,
    gap: &Gap,
    z: f64,
    hl: &[f64],
    state: &FilmState,
    model: &FrictionModel,
) -> Friction {
    friction_thresholds(g, gap, z, hl, state, model, &[]).0
}

/// The Couette shear and the Poiseuille term of node k, whose row's gap (mean `h`, film
/// content θ) varies across its cell: the means over its samples (eq. 17; a rough film's
/// shear factors, docs/model.md §11).
fn row_shear(gap: &Gap, k: usize, h: f64, theta: f64, dpdx: f64, u: f64) -> (f64, f64) {
    let rows = &gap.rows;
    match &gap.flow {
        None => (
            rows.mean_of(k, h, |x| couette_shear(u, theta, x)),
            poiseuille_term(h, dpdx),
        ),
        Some(f) => (
            rows.mean_of(k, h, |x| couette_shear(u, theta, x) * f.couette_shear(x)),
            rows.mean_of(k, h, |x| poiseuille_term(x, dpdx * f.poiseuille_shear(x))),
        ),
    }
}

/// As [`friction`], also for the further shear thresholds `extra_theta_s`, in one pass over
/// the ring: θ_s enters only the Couette term (eq. 9), so the Poiseuille and pressure terms
/// are shared, and each threshold's Couette sum adds the same terms in the same order as
/// its own pass would (the same bits).
pub fn friction_thresholds(
    g: &Grid,
    gap: &Gap,
    z: f64,
    hl: &[f64],
    state: &FilmState,
    model: &FrictionModel,
    extra_theta_s: &[f64],
) -> (Friction, Vec<Friction>) {
    let n2 = g.n2;
    let (mut fc, mut fp, mut fpr, mut fb) = (0.0, 0.0, 0.0, 0.0);
    let mut fc_extra = vec![0.0; extra_theta_s.len()];
    for i in 1..g.n1 {
        if !gap.ring[i] {
            continue;
        }
        for j in 0..n2 {
            let k = i * n2 + j;
            let h = gap.h(g, k, z);
            let theta = state.phi[k] / h;
            let dpdx = (state.p[k + n2] - state.p[k - n2]) / (2.0 * g.dx);
            let (shear, poiseuille) = match gap.rows.of(k) {
                None => {
                    let mut shear = couette_shear(model.u, theta, h);
                    let mut dpdx = dpdx;
                    if let Some(f) = &gap.flow {
                        shear *= f.couette_shear(h);
                        dpdx *= f.poiseuille_shear(h);
                    }
                    (shear, poiseuille_term(h, dpdx))
                }
                // A row that varies across its cell: each term's mean over its samples, θ
                // the cell's.
                Some(_) => row_shear(gap, k, h, theta, dpdx, model.u),
            };
            if theta > model.theta_s {
                fc += shear;
            }
            for (sum, &theta_s) in fc_extra.iter_mut().zip(extra_theta_s) {
                if theta > theta_s {
                    *sum += shear;
                }
            }
            fp += poiseuille;
            let dhl = (hl[k + n2] - hl[k - n2]) / (2.0 * g.dx);
            fpr += pressure_term(state.p[k], dhl);
            if let Some(law) = model.contact.as_ref() {
                fb += match gap.rows.of(k) {
                    None if law.touches(h) => boundary_term(model.u, law.shear(h)),
                    None => 0.0,
                    Some(_) => gap.rows.mean_of(k, h, |x| {
                        if law.touches(x) {
                            boundary_term(model.u, law.shear(x))
                        } else {
                            0.0
                        }
                    }),
                };
            }
        }
    }
    let w = g.dx * g.dy / g.width;
    let with_couette = |fc: f64| Friction {
        couette: friction_coefficient(fc * w, model.w_ps),
        poiseuille: friction_coefficient(fp * w, model.w_ps),
        pressure: friction_coefficient(fpr * w, model.w_ps),
        boundary: friction_coefficient(fb * w, model.w_ps),
    };
    (
        with_couette(fc),
        fc_extra.into_iter().map(with_couette).collect(),
    )
}
