//! Friction on the ring (paper eqs. 7–11 and 17, docs/model.md §5).
//!
//! F = (1/B)∫∫_ring ( u·g(θ)/h + 3·h·∂p/∂x1 + 6·p·∂h_L/∂x1 ) dx1 dx2  (eq. 17), the Couette,
//! Poiseuille and pressure terms, with g(θ) = θ·s(θ), s = 1 if θ > θ_s else 0 (eqs. 8, 9),
//! and the friction coefficient f = (H/6L)·F/W_ps (eq. 11); beside them the boundary
//! friction of the asperities, (1/B)∫∫_ring τ_b (docs/model.md §5, §11, eq. A4). The
//! quadrature over a mesh is `mesh::integrals::friction`.

use serde::{Deserialize, Serialize};

use super::asperity::ContactLaw;

/// The friction terms as friction coefficients per eq. (11) (dimensionless): the film's
/// Couette, Poiseuille and pressure terms and the asperities' boundary friction. The paper
/// prints the film's divided by 10 (docs/model.md §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Friction {
    pub couette: f64,
    pub poiseuille: f64,
    pub pressure: f64,
    /// Boundary friction on the asperities (docs/model.md §11, eq. A4); 0 where the film is
    /// thicker than 4σ everywhere under the ring.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub boundary: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl Friction {
    /// Total friction coefficient f: the sum of the terms (the boundary one added last, so
    /// that without contact the total is the film's to the bit).
    pub fn total(&self) -> f64 {
        self.couette + self.poiseuille + self.pressure + self.boundary
    }
    /// The film's part of [`Friction::total`]: Couette, Poiseuille and pressure terms.
    pub fn hydrodynamic(&self) -> f64 {
        self.couette + self.poiseuille + self.pressure
    }
    pub fn scaled(&self, s: f64) -> Self {
        Friction {
            couette: self.couette * s,
            poiseuille: self.poiseuille * s,
            pressure: self.pressure * s,
            boundary: self.boundary * s,
        }
    }
    pub fn add(&mut self, o: &Friction) {
        self.couette += o.couette;
        self.poiseuille += o.poiseuille;
        self.pressure += o.pressure;
        self.boundary += o.boundary;
    }
}

/// Inputs of the friction model that are not fields.
#[derive(Clone, Copy, Debug)]
pub struct FrictionModel {
    pub u: f64,
    /// Shear threshold θ_s of the switch function s(θ) (eq. 9).
    pub theta_s: f64,
    pub w_ps: f64,
    /// The asperity contact under the ring (docs/model.md §11; None: none).
    pub contact: Option<ContactLaw>,
}

/// Boundary friction stress of eq. (A4) in the direction of the film's Couette shear: τ_b
/// with the sign of the liner's speed u, 0 at u = 0 (no sliding, no sliding friction).
#[inline(always)]
pub fn boundary_term(u: f64, tau_b: f64) -> f64 {
    if u == 0.0 {
        0.0
    } else {
        tau_b.copysign(u)
    }
}

/// Couette shear u·θ/h of eq. (17) before the switch s(θ): it counts where θ > θ_s (eq. 9).
#[inline(always)]
pub fn couette_shear(u: f64, theta: f64, h: f64) -> f64 {
    u * theta / h
}

/// Poiseuille term 3·h·∂p/∂x1 of eq. (17).
#[inline(always)]
pub fn poiseuille_term(h: f64, dp_dx: f64) -> f64 {
    3.0 * h * dp_dx
}

/// Pressure term 6·p·∂h_L/∂x1 of eq. (17): the pocket walls' share of the load tilted along
/// the sliding direction.
#[inline(always)]
pub fn pressure_term(p: f64, dhl_dx: f64) -> f64 {
    6.0 * p * dhl_dx
}
