//! Friction on the ring (paper eqs. 7–11 and 17, model.md §5).
//!
//! F = (1/B)∫∫_ring ( u·g(θ)/h + 3·h·∂p/∂x1 + 6·p·∂h_L/∂x1 ) dx1 dx2  (eq. 17),
//! g(θ) = θ·s(θ), s = 1 if θ > θ_s else 0 (eqs. 8, 9), and f = (H/6L)·F/W_ps (eq. 11).
//! Nodal quadrature over the node columns under the ring; ∂p/∂x1 and ∂h_L/∂x1 by centred
//! differences of nodal values.

use serde::{Deserialize, Serialize};

use crate::film::{FilmState, Gap, Grid};
use crate::units::friction_coefficient;

/// The three friction terms as friction coefficients per eq. (11) (dimensionless).
/// The paper prints these divided by 10 (model.md §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Friction {
    pub couette: f64,
    pub poiseuille: f64,
    pub pressure: f64,
}

impl Friction {
    /// Total friction coefficient f: the sum of the three terms.
    pub fn total(&self) -> f64 {
        self.couette + self.poiseuille + self.pressure
    }
    pub fn scaled(&self, s: f64) -> Self {
        Friction {
            couette: self.couette * s,
            poiseuille: self.poiseuille * s,
            pressure: self.pressure * s,
        }
    }
    pub fn add(&mut self, o: &Friction) {
        self.couette += o.couette;
        self.poiseuille += o.poiseuille;
        self.pressure += o.pressure;
    }
}

/// Inputs of the friction model that are not fields.
#[derive(Clone, Copy, Debug)]
pub struct FrictionModel {
    pub u: f64,
    /// Shear threshold θ_s of the switch function s(θ) (eq. 9).
    pub theta_s: f64,
    pub w_ps: f64,
}

/// Friction coefficients of the current state. `hl` is the texture depth h_L per node (µm).
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
    let (mut fc, mut fp, mut fpr) = (0.0, 0.0, 0.0);
    let mut fc_extra = vec![0.0; extra_theta_s.len()];
    for i in 1..g.n1 {
        if !gap.ring[i] {
            continue;
        }
        for j in 0..n2 {
            let k = i * n2 + j;
            let h = gap.h(g, k, z);
            let theta = state.phi[k] / h;
            let shear = model.u * theta / h;
            if theta > model.theta_s {
                fc += shear;
            }
            for (sum, &theta_s) in fc_extra.iter_mut().zip(extra_theta_s) {
                if theta > theta_s {
                    *sum += shear;
                }
            }
            let dpdx = (state.p[k + n2] - state.p[k - n2]) / (2.0 * g.dx);
            fp += 3.0 * h * dpdx;
            let dhl = (hl[k + n2] - hl[k - n2]) / (2.0 * g.dx);
            fpr += 6.0 * state.p[k] * dhl;
        }
    }
    let w = g.dx * g.dy / g.width;
    let with_couette = |fc: f64| Friction {
        couette: friction_coefficient(fc * w, model.w_ps),
        poiseuille: friction_coefficient(fp * w, model.w_ps),
        pressure: friction_coefficient(fpr * w, model.w_ps),
    };
    (
        with_couette(fc),
        fc_extra.into_iter().map(with_couette).collect(),
    )
}
