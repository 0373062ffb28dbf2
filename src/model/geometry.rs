//! Geometry of ring and liner, and the gap between them (docs/model.md §2, paper eqs. 1 and 15).
//!
//! Ring profiles and pocket shapes are small traits: a new shape (flat-bottomed pocket,
//! asymmetric ring) is a new type implementing the trait, not an edit of the solver.

use std::sync::Arc;

use super::units::UM_PER_CM;

/// The face of the ring: its gap above the apex plane as a function of the axial position.
pub trait RingProfile: Send + Sync + std::fmt::Debug {
    /// Gap h_U (µm) between the ring face and the plane through its lowest point, at axial
    /// offset `s` (cm) from the ring centre; defined for |s| < half width.
    fn sag_um(&self, s_cm: f64) -> f64;
    /// Minimum of `sag_um` over the ring face (µm): 0 for profiles touching the apex plane.
    fn min_sag_um(&self) -> f64 {
        0.0
    }
}

/// A barrel-shaped ring: circular arc of radius R (cm); R = ∞ is a flat ring (docs/model.md §2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularArc {
    /// Face radius R in cm (f64::INFINITY for a flat ring).
    pub radius_cm: f64,
}

impl RingProfile for CircularArc {
    /// h_U = (R − √(R² − s²))·10⁴ µm (docs/model.md §2), written as s²/(R + √(R² − s²)) to avoid
    /// cancellation at large R.
    fn sag_um(&self, s_cm: f64) -> f64 {
        if self.radius_cm.is_infinite() {
            return 0.0;
        }
        let r = self.radius_cm;
        s_cm * s_cm / (r + (r * r - s_cm * s_cm).sqrt()) * UM_PER_CM
    }
}

/// A pocket's depth below the liner plateau as a function of the offsets from its centre.
pub trait PocketShape: Send + Sync + std::fmt::Debug {
    /// Depth h_L (µm, ≥ 0) at offsets ξ (along x1) and η (along x2) in cm from the centre.
    fn depth_um(&self, xi_cm: f64, eta_cm: f64) -> f64;
    /// Half extents of the pocket's footprint along x1 and x2 (cm).
    fn half_extent_cm(&self) -> (f64, f64);
    /// Deepest point (µm).
    fn max_depth_um(&self) -> f64;
    /// Footprint area (cm²).
    fn area_cm2(&self) -> f64;
}

/// Half an ellipsoid: h_L = depth·√(1 − (ξ/l1)² − (η/l2)²) inside the ellipse (docs/model.md §2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfEllipsoid {
    /// Semiaxis along the sliding direction x1 (cm).
    pub l1_cm: f64,
    /// Semiaxis across the sliding direction x2 (cm).
    pub l2_cm: f64,
    /// Depth (µm).
    pub depth_um: f64,
}

impl PocketShape for HalfEllipsoid {
    fn depth_um(&self, xi_cm: f64, eta_cm: f64) -> f64 {
        let a = xi_cm / self.l1_cm;
        let b = eta_cm / self.l2_cm;
        let q = 1.0 - a * a - b * b;
        if q > 0.0 {
            self.depth_um * q.sqrt()
        } else {
            0.0
        }
    }
    fn half_extent_cm(&self) -> (f64, f64) {
        (self.l1_cm, self.l2_cm)
    }
    fn max_depth_um(&self) -> f64 {
        self.depth_um
    }
    fn area_cm2(&self) -> f64 {
        std::f64::consts::PI * self.l1_cm * self.l2_cm
    }
}

/// The liner: a plateau at x3 = 0 with a rectangular lattice of identical pockets, period `per`
/// along x1 and `width` along x2, translating with the liner at speed u (docs/model.md §2).
/// Pocket centres sit on x2 = width/2 (and images), so the field is symmetric about x2 = 0
/// and x2 = width/2.
#[derive(Clone, Debug)]
pub struct Liner {
    /// None: untextured (smooth) liner.
    pub pocket: Option<Arc<dyn PocketShape>>,
    /// Lattice period along x1 (cm).
    pub per_cm: f64,
    /// Lattice period along x2 (cm).
    pub width_cm: f64,
    /// x1 position (cm) of one pocket centre at t = 0 (the texture's initial phase).
    pub phase_cm: f64,
}

impl Liner {
    pub fn smooth() -> Self {
        Liner {
            pocket: None,
            per_cm: f64::INFINITY,
            width_cm: f64::INFINITY,
            phase_cm: 0.0,
        }
    }

    /// Texture depth h_L(x1 − u t, x2) in µm (eq. 15) at liner-frame position `x_liner`.
    pub fn depth_um(&self, x_liner_cm: f64, x2_cm: f64) -> f64 {
        match &self.pocket {
            None => 0.0,
            Some(shape) => {
                let xi = wrap(x_liner_cm - self.phase_cm, self.per_cm);
                let eta = wrap(x2_cm - 0.5 * self.width_cm, self.width_cm);
                shape.depth_um(xi, eta)
            }
        }
    }

    /// Textured area fraction π·l1·l2/(per·width) for the half-ellipsoid (docs/model.md §2).
    pub fn area_fraction(&self) -> f64 {
        match &self.pocket {
            None => 0.0,
            Some(shape) => shape.area_cm2() / (self.per_cm * self.width_cm),
        }
    }
}

/// Offset of `x` from the nearest multiple of `period`, in [−period/2, period/2).
fn wrap(x: f64, period: f64) -> f64 {
    x - period * (x / period + 0.5).floor()
}

/// The contact: ring of width `ring_width` centred at `x_center` in the domain [0, length],
/// gap `e` outside the ring (docs/model.md §2).
#[derive(Clone, Debug)]
pub struct Contact {
    pub ring: Arc<dyn RingProfile>,
    pub liner: Liner,
    /// Domain length along x1 (cm).
    pub length_cm: f64,
    /// Ring centre x_c (cm).
    pub x_center_cm: f64,
    /// Ring width b − a (cm).
    pub ring_width_cm: f64,
    /// Gap outside the ring (µm).
    pub e_um: f64,
}

impl Contact {
    /// The paper's contact (docs/model.md §2): domain 0.2, ring 0.08 centred at 0.1, e = 1000.
    pub fn paper(ring: Arc<dyn RingProfile>, liner: Liner) -> Self {
        Contact {
            ring,
            liner,
            length_cm: 0.2,
            x_center_cm: 0.1,
            ring_width_cm: 0.08,
            e_um: 1000.0,
        }
    }

    /// The same layout for a ring `w` cm wide (docs/model.md §2): the domain stays 2.5 ring
    /// widths long with the ring at its centre, so the film has as far to come and go as in
    /// the paper's layout. The paper's width gives the paper's numbers exactly.
    pub fn with_ring_width(mut self, w: f64) -> Self {
        if w != self.ring_width_cm {
            let scale = w / self.ring_width_cm;
            self.length_cm *= scale;
            self.x_center_cm *= scale;
            self.ring_width_cm = w;
        }
        self
    }

    /// Ring edges (a, b) in cm.
    pub fn ring_edges(&self) -> (f64, f64) {
        let hw = 0.5 * self.ring_width_cm;
        (self.x_center_cm - hw, self.x_center_cm + hw)
    }

    /// Whether x1 lies under the ring, a < x1 < b.
    pub fn under_ring(&self, x1_cm: f64) -> bool {
        let (a, b) = self.ring_edges();
        a < x1_cm && x1_cm < b
    }

    /// The ring's part of the gap without Z at x1 (µm), eq. (15): h_U under the ring, e
    /// elsewhere. The gap without Z is h_L plus this (`mesh::Scene::place`); the full gap
    /// adds Z under the ring.
    pub fn ring_part_um(&self, x1_cm: f64) -> f64 {
        if self.under_ring(x1_cm) {
            self.ring.sag_um(x1_cm - self.x_center_cm)
        } else {
            self.e_um
        }
    }

    /// Smallest surface separation for a ring at Z (µm): min over the ring of h_U + Z (docs/model.md §6).
    pub fn clearance_um(&self, z_um: f64) -> f64 {
        z_um + self.ring.min_sag_um()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_sag_matches_formula() {
        let r = CircularArc { radius_cm: 0.8 };
        let s: f64 = 0.04;
        let direct = (0.8 - (0.64 - s * s).sqrt()) * 1e4;
        assert!((r.sag_um(s) - direct).abs() < 1e-9);
        assert_eq!(
            CircularArc {
                radius_cm: f64::INFINITY
            }
            .sag_um(0.03),
            0.0
        );
    }

    #[test]
    fn lattice_wraps_and_is_symmetric() {
        let liner = Liner {
            pocket: Some(Arc::new(HalfEllipsoid {
                l1_cm: 0.01,
                l2_cm: 0.01,
                depth_um: 5.0,
            })),
            per_cm: 0.06,
            width_cm: 0.06,
            phase_cm: 0.0,
        };
        // Centre at (0, width/2) and its images.
        assert!((liner.depth_um(0.0, 0.03) - 5.0).abs() < 1e-12);
        assert!((liner.depth_um(0.12, 0.09) - 5.0).abs() < 1e-12);
        assert_eq!(liner.depth_um(0.03, 0.03), 0.0);
        assert!((liner.depth_um(0.004, 0.03) - liner.depth_um(-0.004, 0.03)).abs() < 1e-12);
        assert!((liner.area_fraction() - 0.0873).abs() < 1e-4);
    }
}
