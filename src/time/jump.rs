//! Slow-mode extrapolation (docs/solver.md, "Slow-mode extrapolation"): when the window
//! means show a slow mode of the approach to the periodic regime, the state is moved to that
//! mode's limit; the periodic test then starts afresh on simulated windows.

use super::numerics::Numerics;
use super::periodic::{slow_mode_ratio, slow_pair, PeriodMeans, SlowMode, Windows};
use super::transient::Transient;
use crate::model::ring::RingState;

/// The jump rule weighs a mode against this tolerance when the run's is looser. Why: the
/// periodic test passes only once its estimate of the distance, read from the changes of
/// the window means, is below the tolerance at two window ends in a row, which for a damped
/// oscillation comes well after the mode itself has decayed to the tolerance; weighed
/// against 1e-4 the jump was refused where it would have paid (Case I at `fast`: 18 windows
/// without it, 14 with it), and a run could stop short of its tolerance (R = 0.8, 0.01 /
/// 0.02 / 20 µm at `fast`: 1.2e-4 from its limit, 6.1e-6 with this rule). Measured on 30
/// sampled study cases at `fast` (1e-4): periods 1037 → 982, the worst outcome 1.2e-4 →
/// 4.5e-5 from runs to 1e-6; the 730-case paper + θs study: periods −1.7 %, wall time 22.1
/// → 21.0 min, every status the same.
const JUMP_TOL: f64 = 1e-5;

/// Smallest |λ| the second mode of a pair must have for the pair to jump.
const PAIR_SECOND: f64 = 0.2;

/// Windows a slow mode must still need before a jump along it pays (see
/// [`SlowMode::worth_a_jump`]).
const JUMP_WINDOWS: usize = 6;

/// Most state extrapolations per run.
const MAX_JUMPS: usize = 3;

/// The state at the end of a texture period (same texture phase at every period end).
pub(crate) struct PeriodEnd {
    phi: Vec<f64>,
    ring: RingState,
}

impl PeriodEnd {
    pub fn of(t: &Transient) -> Self {
        PeriodEnd {
            phi: t.state.phi.clone(),
            ring: t.ring_state,
        }
    }
}

/// The jumps of one run and the window ends they read.
#[derive(Default)]
pub(crate) struct Extrapolator {
    jumps: usize,
    /// The last three window ends (oldest first).
    ends: Vec<PeriodEnd>,
}

impl Extrapolator {
    /// After a window of `t`: when the fresh windows show a slow mode and three window ends
    /// are at hand, jumps the state to the mode's limit and restarts the windows. A pair jumps
    /// only when both of its modes are slow (a damped oscillation, or two slow real modes);
    /// one slow real mode beside a fast one is the geometric jump's, a window or two later,
    /// once the fast one has gone (the pair fitted over it lands less close).
    pub fn after_window(&mut self, t: &mut Transient, windows: &mut Windows, num: &Numerics) {
        if !num.extrapolate || self.jumps >= MAX_JUMPS {
            return;
        }
        self.ends.push(PeriodEnd::of(t));
        if self.ends.len() > 3 {
            self.ends.remove(0);
        }
        let fresh = windows.fresh();
        let mode = slow_mode_ratio(fresh).or_else(|| {
            slow_pair(fresh)
                .filter(|m| m.second_radius() >= PAIR_SECOND && worth_a_jump(m, fresh, num))
        });
        if let (Some(mode), [a, b, c]) = (mode, &self.ends[..]) {
            if t.jump_to_limit([a, b, c], mode) {
                self.jumps += 1;
                windows.restart();
                self.ends.clear();
            }
        }
    }
}

/// Whether jumping along `mode` saves windows: only when, decaying at its own rate,
/// the mode would still need more than [`JUMP_WINDOWS`] windows to fall to the periodic
/// tolerance, or to [`JUMP_TOL`] if that is tighter (the run after a jump needs at least
/// four fresh windows, and a mode decaying fast, Case III's 0.49 a period, gains little:
/// the jump only resets the history).
pub(super) fn worth_a_jump(mode: &SlowMode, h: &[PeriodMeans], num: &Numerics) -> bool {
    let k = h.len() - 1;
    let z = |i: usize| h[i].z_mean;
    let distance = ((z(k) - mode.limit(z(k - 2), z(k - 1), z(k))) / z(k)).abs();
    let tol = num.periodic_tol.min(JUMP_TOL);
    distance > tol * mode.radius().powi(-(JUMP_WINDOWS as i32))
}

impl Transient {
    /// Moves the state to the limit of `mode` read from three consecutive window ends
    /// (oldest first), keeping θ in [0, 1]. The film content and the ring move together, as
    /// the slow mode couples them (the oil held in the contact and the clearance it
    /// carries). Refused (false, state unchanged) when the jump would take the ring to less
    /// than half or more than twice its clearance: then the mode is not the clean decay the
    /// extrapolation assumes.
    pub(crate) fn jump_to_limit(&mut self, ends: [&PeriodEnd; 3], mode: SlowMode) -> bool {
        let g = &self.scene.grid;
        let [a, b, c] = ends;
        let z = mode.limit(a.ring.z, b.ring.z, c.ring.z);
        if !(z.is_finite() && z >= 0.5 * c.ring.z && z <= 2.0 * c.ring.z) {
            return false;
        }
        for k in 0..g.nodes() {
            let h = self.scene.gap.h(g, k, z);
            let phi = mode.limit(a.phi[k], b.phi[k], c.phi[k]);
            self.state.phi[k] = phi.max(0.0).min(h);
            if self.state.pressurised[k] {
                self.state.phi[k] = h;
            }
        }
        // The states kept from the last period stay the guesses of the next one: the jump
        // moves the film and Z by the mode's remainder only, so their active sets are still
        // far nearer than the previous step's, and a guess changes no solution. Measured
        // (iterations a step): R = 51.2 at `paper`, the window after the fine mesh's jump
        // 6.18 → 2.41 (23 → 9 ms a step); at `fast` Case I / III / R = 51.2 1.97 / 2.74 /
        // 2.88 → 1.92 / 2.68 / 2.66, outcomes within 7e-12, against dropping them (the
        // period after a jump then starts from the previous step's state).
        self.ring_state = RingState {
            z,
            v: mode.limit(a.ring.v, b.ring.v, c.ring.v),
            a: mode.limit(a.ring.a, b.ring.a, c.ring.a),
        };
        true
    }
}
