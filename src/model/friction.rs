//! Friction on the ring (paper eqs. 7–11 and 17, docs/model.md §5).
//!
//! F = (1/B)∫∫_ring ( u·g(θ)/h + 3·h·∂p/∂x1 + 6·p·∂h_L/∂x1 ) dx1 dx2  (eq. 17), the Couette,
//! Poiseuille and pressure terms, with g(θ) = θ·s(θ), s = 1 if θ > θ_s else 0 (eqs. 8, 9),
//! and the friction coefficient f = (H/6L)·F/W_ps (eq. 11). The quadrature over a mesh is
//! `mesh::integrals::friction`.

use serde::{Deserialize, Serialize};

/// The three friction terms as friction coefficients per eq. (11) (dimensionless).
/// The paper prints these divided by 10 (docs/model.md §5).
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
