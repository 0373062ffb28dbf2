//! Ring dynamics m·Z'' = W_h + W_a − W_ps (paper eqs. 3, 13 with the asperity load of
//! docs/model.md §11; §4), Newmark average acceleration (β = 1/4, γ = 1/2). The update is
//! implicit: the film solver receives Z = z_pred + κ·(W_h + W_a(Z) − W_ps) as one more
//! equation of its nonlinear iteration, because the film's squeeze stiffness (and the
//! asperities' contact stiffness) makes an explicit coupling unstable at the paper's time step.

use super::asperity::ContactLaw;

/// Implicit ring dynamics inside a film solve: Z = z_pred + κ·(W_h + W_a(Z) − W_ps), the
/// Newmark average-acceleration update of m·Z'' = W_h + W_a − W_ps (eq. 13, docs/model.md
/// §4, §11) with κ = dt²/(4m).
#[derive(Clone, Copy, Debug)]
pub struct RingLink {
    pub z_pred: f64,
    pub kappa: f64,
    pub w_ps: f64,
    /// The asperity contact under the ring (None: the film alone carries it).
    pub contact: Option<ContactLaw>,
}

/// Ring mass per unit width m, pre-stress load W_ps (units of docs/model.md §1) and the
/// asperity contact under it (docs/model.md §11; None: none).
#[derive(Clone, Copy, Debug)]
pub struct Ring {
    pub mass: f64,
    pub w_ps: f64,
    pub contact: Option<ContactLaw>,
}

/// Position Z (µm), velocity and acceleration of the ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingState {
    pub z: f64,
    pub v: f64,
    pub a: f64,
}

impl Ring {
    /// The implicit Newmark relation for a step dt from `s`:
    /// Z⁺ = Z + dt·V + dt²/4·(A + A⁺), A⁺ = (W_h⁺ + W_a⁺ − W_ps)/m.
    pub fn link(&self, s: &RingState, dt: f64) -> RingLink {
        RingLink {
            z_pred: s.z + dt * s.v + 0.25 * dt * dt * s.a,
            kappa: 0.25 * dt * dt / self.mass,
            w_ps: self.w_ps,
            contact: self.contact,
        }
    }

    /// The state after the step, given the converged Z⁺ and the load the ring carries there,
    /// film and asperities: `load` = W_h⁺ + W_a⁺.
    pub fn advance(&self, s: &RingState, dt: f64, z_new: f64, load: f64) -> RingState {
        let a = (load - self.w_ps) / self.mass;
        RingState {
            z: z_new,
            v: s.v + 0.5 * dt * (s.a + a),
            a,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newmark_is_exact_for_constant_force() {
        // W_h = 0: free fall under W_ps, Z = Z0 − W_ps t²/(2m).
        let ring = Ring {
            mass: 2.0,
            w_ps: 1.0,
            contact: None,
        };
        let mut s = RingState {
            z: 3.0,
            v: 0.0,
            a: -0.5,
        };
        let dt = 0.1;
        for _ in 0..10 {
            let l = ring.link(&s, dt);
            let z = l.z_pred + l.kappa * (0.0 - l.w_ps);
            s = ring.advance(&s, dt, z, 0.0);
        }
        assert!((s.z - (3.0 - 0.25)).abs() < 1e-12);
        assert!((s.v + 0.5).abs() < 1e-12);
    }
}
