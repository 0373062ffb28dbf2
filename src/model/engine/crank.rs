//! The slider-crank (docs/model.md §10): where the ring is along the stroke at a crank
//! angle, how fast it moves, and the angle at which it passes a place.

use super::Engine;

impl Engine {
    /// The crank's angular speed ω = π·rpm/30 (rad/s).
    pub fn omega_rad_s(&self) -> f64 {
        self.file.engine.rpm * std::f64::consts::PI / 30.0
    }

    /// Crank radius and rod length (mm), and the crank's angular speed (rad/s).
    fn crank(&self) -> (f64, f64, f64) {
        let e = &self.file.engine;
        (0.5 * e.stroke_mm, e.rod_mm, self.omega_rad_s())
    }

    /// The piston's (and ring's) distance from top dead centre (mm) at crank angle θ:
    /// x = r(1 − cos θ) + l − √(l² − r² sin² θ) (docs/model.md §10).
    pub fn position_mm(&self, crank_deg: f64) -> f64 {
        let (r, l, _) = self.crank();
        let t = crank_deg.to_radians();
        r * (1.0 - t.cos()) + l - (l * l - (r * t.sin()).powi(2)).sqrt()
    }

    /// Its velocity (m/s, positive away from top dead centre): dx/dt = ω·r·sin θ·(1 +
    /// r·cos θ / √(l² − r² sin² θ)).
    pub fn velocity_ms(&self, crank_deg: f64) -> f64 {
        let (r, l, w) = self.crank();
        let t = crank_deg.to_radians();
        let root = (l * l - (r * t.sin()).powi(2)).sqrt();
        1e-3 * w * r * t.sin() * (1.0 + r * t.cos() / root)
    }

    /// The crank angle of the down stroke (0–180°) at which the ring is `x` mm from top dead
    /// centre (the position increases over it).
    pub(super) fn crank_at(&self, x: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, 180.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.position_mm(mid) < x {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}
