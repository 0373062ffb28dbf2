//! The BDF2 fall-back (docs/solver.md, "Time scheme"): a BDF2 run whose distance from its
//! regime stops falling goes on with backward Euler.

use super::numerics::TimeScheme;

/// Averaging windows a BDF2 run may take on its mesh, without its distance from the periodic
/// regime halving over the last half of them, before it goes on with backward Euler.
/// Why: at a Courant number u·dt/Δx1 near 1, BDF2 can settle into a slow spurious oscillation
/// where backward Euler's damping finds the periodic regime (R = 1.6, pockets 0.005 / 0.01 /
/// 10 µm on 384×8 at dt = 5.4e-4: f̄ swinging between 0.181 and 0.209 with a period of 2.4 ms,
/// where backward Euler settles at 0.151 in 102 periods and both schemes at dt = 1e-4 agree on
/// 0.158; tests/time_scheme.rs). Every benchmark case settles within 12 windows, a
/// conformal ring's creep within 20; a run whose distance stalls after 30 (a spurious
/// oscillation, or a draining oil bank, which takes ≈ 220) finishes with backward Euler, at
/// its first-order accuracy, and says so (`Outcome::scheme`). A run still settling goes on:
/// the plain march to 1e-8 takes ≈ 40 windows.
pub const BDF2_PATIENCE: usize = 30;

/// Whether a run's estimated distance from the periodic regime has stopped falling: after
/// `patience` windows, the best of the last `patience / 2` is not half the best before them.
/// A settling run's distance falls geometrically (by 0.5–0.75 a window in the benchmark
/// cases), a spurious oscillation's or a steady drift's stays put.
pub(crate) fn stalled(errors: &[f64], patience: usize) -> bool {
    if errors.len() < patience {
        return false;
    }
    let (early, late) = errors.split_at(errors.len() - patience / 2);
    let best = |e: &[f64]| e.iter().copied().fold(f64::INFINITY, f64::min);
    best(late) > 0.5 * best(early)
}

/// The distances of a run's windows since its map last changed, watched for a stall.
#[derive(Default)]
pub(super) struct Bdf2Fallback {
    motion: Vec<f64>,
}

impl Bdf2Fallback {
    /// After a window at distance `motion` (of the motion alone) of a run of `scheme`:
    /// whether it goes on with backward Euler (then a new map, watched afresh).
    pub fn after_window(&mut self, motion: f64, scheme: TimeScheme) -> bool {
        self.motion.push(motion);
        let stall = scheme == TimeScheme::Bdf2 && stalled(&self.motion, BDF2_PATIENCE);
        if stall {
            self.motion.clear();
        }
        stall
    }
}
