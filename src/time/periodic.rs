//! The periodic regime (docs/model.md §6; docs/solver.md, "Periodic regime"): the estimated
//! distance of the last averaging windows' means from their periodic limits, the slow modes
//! that distance is read from, and the stopping rule it makes.

use super::numerics::Numerics;
use super::stop::{Distance, StopRule};
use super::window::PeriodMeans;

/// The periodic regime as a run's stopping rule: the window means since the run's map last
/// changed, and the tolerance.
pub(crate) struct PeriodicRegime {
    history: Vec<PeriodMeans>,
    /// Windows run before the map last changed (they count in the periods).
    earlier: usize,
    /// At least this many windows (and 4) on one map.
    min_windows: usize,
    tol: f64,
    /// The load the film carries on average in the periodic regime.
    w_ps: f64,
}

impl PeriodicRegime {
    /// The periodic regime to `num`'s tolerance of a ring under load `w_ps`.
    pub fn new(num: &Numerics, w_ps: f64) -> Self {
        PeriodicRegime {
            history: Vec::new(),
            earlier: 0,
            min_windows: num.min_periods,
            tol: num.periodic_tol,
            w_ps,
        }
    }

    /// The estimated distance of the plain march from the periodic regime: it must hold at
    /// two consecutive window ends, so that one lucky cancellation between a decaying
    /// oscillation and a drift does not stop the run.
    fn error(&self) -> f64 {
        let fresh = &self.history;
        periodic_error(fresh).max(if fresh.len() > 3 {
            periodic_error(&fresh[..fresh.len() - 1])
        } else {
            f64::INFINITY
        })
    }
}

impl StopRule for PeriodicRegime {
    fn push(&mut self, m: PeriodMeans) {
        self.history.push(m);
    }

    fn last(&self) -> &PeriodMeans {
        self.history.last().expect("at least one window")
    }

    /// The plain march's estimate, or, accelerated, the accelerator's (see
    /// [`accelerated_error`]); in all, raised to the force imbalance (see
    /// [`with_force_balance`]).
    fn distance(&self, residual: Option<f64>) -> Distance {
        let motion = match residual {
            Some(r) => accelerated_error(&self.history, r),
            None => self.error(),
        };
        Distance {
            motion,
            total: with_force_balance(motion, self.last(), self.w_ps),
        }
    }

    /// At least `min_periods` (and 4) windows, and the distance within the tolerance.
    fn reached(&self, total: f64) -> bool {
        self.history.len() >= self.min_windows.max(4) && total <= self.tol
    }

    fn windows(&self) -> usize {
        self.earlier + self.history.len()
    }

    fn restart(&mut self) {
        self.earlier += self.history.len();
        self.history.clear();
    }
}

/// Largest mean force imbalance |W̄_h + W̄_a − W_ps| / W_ps a window may end with in the periodic
/// regime. Why: over a period the ring's momentum returns, so the film carries the load on
/// average (the ring equation, eq. 3, summed over the period); a ring too heavy to move
/// (a mass 10¹⁹ times the paper's) repeats the same window while the film carries 0.91 of the
/// load, and would be taken for periodic. Measured at the stop of the benchmark cases at
/// `fast`: 5e-8 to 5e-6; 1e-3 leaves those runs unchanged to the bit.
pub const FORCE_TOL: f64 = 1e-3;

/// The estimated distance `err` from the periodic regime, raised to the mean force imbalance
/// of the window `last` when that is above [`FORCE_TOL`] (so that the run goes on, and a run
/// that never balances reports how far it is).
pub(crate) fn with_force_balance(err: f64, last: &PeriodMeans, w_ps: f64) -> f64 {
    let imbalance = ((last.w_h + last.w_a - w_ps) / w_ps).abs();
    if imbalance > FORCE_TOL {
        err.max(imbalance)
    } else {
        err
    }
}

/// A slow mode of the approach to the periodic regime, as the recurrence its window-to-window
/// changes obey: d_{i+1} = α·d_i + β·d_{i−1} (β = 0: one geometric mode of ratio α; β ≠ 0:
/// a damped oscillation or two modes). Any sequence y_i that obeys it tends to
/// y* = (y_k − α·y_{k−1} − β·y_{k−2}) / (1 − α − β).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SlowMode {
    pub alpha: f64,
    pub beta: f64,
}

impl SlowMode {
    /// The limit y* from three consecutive values, oldest first.
    pub fn limit(&self, y0: f64, y1: f64, y2: f64) -> f64 {
        (y2 - self.alpha * y1 - self.beta * y0) / (1.0 - self.alpha - self.beta)
    }

    /// |λ| of the two roots of λ² = αλ + β, larger first (equal for a complex pair).
    fn radii(&self) -> (f64, f64) {
        let (a, b) = (self.alpha, self.beta);
        let disc = a * a + 4.0 * b;
        if disc < 0.0 {
            ((-b).sqrt(), (-b).sqrt())
        } else {
            (
                0.5 * (a.abs() + disc.sqrt()),
                0.5 * (a.abs() - disc.sqrt()).abs(),
            )
        }
    }

    /// Largest |λ|: the decay per window.
    pub fn radius(&self) -> f64 {
        self.radii().0
    }
}

/// The ring's slow mode as a damped oscillation: coefficients (α, β) of the recurrence
/// d_{i+1} = α·d_i + β·d_{i−1} fitted by least squares to the last three changes of the
/// period-mean Z̄ (six period means), when it fits them (RMS residual ≤ [`PAIR_FIT`] of the
/// changes) and decays (both roots of λ² = αλ + β inside |λ| < [`PAIR_RADIUS`]); None
/// otherwise, and for one monotone mode (the changes then lie on one line and β is
/// undetermined: the geometric tail reads it).
///
/// Why: near its periodic regime a textured ring settles by a complex pair of slow modes
/// (Case III: |λ| ≈ 0.49 a period, a pseudo-period of ≈ 5 periods; Case I: 0.65, 7.5). Its
/// cycle-to-cycle changes swing in size with the phase of the oscillation, so a ratio of two
/// changes says nothing about the tail and the geometric estimate stayed infinite for a third
/// of the periods: Case III at `fast` ran 24 periods at any tolerance from 1e-3 to 1e-5,
/// to 3e-8 of its limit.
pub(crate) fn slow_pair(h: &[PeriodMeans]) -> Option<SlowMode> {
    if h.len() < 6 {
        return None;
    }
    let d: Vec<f64> = h.windows(2).map(|w| w[1].z_mean - w[0].z_mean).collect();
    let d = &d[d.len() - 5..];
    // Normal equations of the 3×2 least-squares fit d[i] ≈ α d[i−1] + β d[i−2], i = 2..5.
    let (mut s11, mut s12, mut s22, mut t1, mut t2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 2..5 {
        let (u, v, y) = (d[i - 1], d[i - 2], d[i]);
        s11 += u * u;
        s12 += u * v;
        s22 += v * v;
        t1 += u * y;
        t2 += v * y;
    }
    let det = s11 * s22 - s12 * s12;
    if !det.is_finite() || det <= 1e-6 * s11 * s22 {
        return None;
    }
    let mode = SlowMode {
        alpha: (t1 * s22 - t2 * s12) / det,
        beta: (s11 * t2 - s12 * t1) / det,
    };
    let residual: f64 = (2..5)
        .map(|i| (d[i] - mode.alpha * d[i - 1] - mode.beta * d[i - 2]).powi(2))
        .sum();
    let size: f64 = (2..5).map(|i| d[i].powi(2)).sum();
    (residual <= PAIR_FIT * PAIR_FIT * size && mode.radius() < PAIR_RADIUS).then_some(mode)
}

/// Largest RMS residual of the slow pair's fit, relative to the changes it fits.
const PAIR_FIT: f64 = 0.1;

/// Slowest decay per period the slow pair may have: closer to 1, 1/(1 − α − β) amplifies
/// the fit's error too much for the limit to be read from six periods.
const PAIR_RADIUS: f64 = 0.95;

/// Estimated relative distance of the last window means (f̄ and Z̄) from their periodic
/// limits (docs/model.md §6), and never less than the film's oil imbalance over the last window
/// ([`oil_imbalance`]). For the motion:
/// - when the changes of Z̄ follow a damped oscillation ([`slow_pair`]: α, β), the limit of
///   a sequence y_i obeying that recurrence, y* = (y_k − α y_{k−1} − β y_{k−2})/(1 − α − β),
///   gives the distance |y_k − y*| (for f̄ with Z̄'s α, β: one mode moves both); never less
///   than the last change |y_k − y_{k−1}|;
/// - otherwise the cycle-to-cycle change d_k, extended by its geometric tail d_k/(1 − r)
///   when the changes shrink monotonically at ratio r = d_k/d_{k−1} ∈ (0, 1) (a slow creep);
///   infinite while fewer than three periods exist or while the changes grow.
pub(crate) fn periodic_error(h: &[PeriodMeans]) -> f64 {
    if h.len() < 3 {
        return f64::INFINITY;
    }
    let k = h.len() - 1;
    oil_imbalance(&h[k]).max(motion_error(h))
}

/// Estimated relative distance from the periodic regime of an accelerated run (each window
/// starts where the acceleration put it, not where the last one ended), never less than the
/// film's oil imbalance over the last window ([`oil_imbalance`]):
/// - the acceleration's residual `residual`, the state's change over the last window
///   (G(x) − x: θ at every node, and the ring's relative change counted as the whole film);
/// - the change of the window means f̄ and Z̄ from the window before, relative. Why this
///   measures the distance: the acceleration moves each start far closer to the fixed point
///   than the last, so the change is nearly the previous window's whole distance, and the
///   last window is nearer still.
///
/// Infinite before three windows.
pub(crate) fn accelerated_error(h: &[PeriodMeans], residual: f64) -> f64 {
    if h.len() < 3 {
        return f64::INFINITY;
    }
    let (a, b) = (&h[h.len() - 2], &h[h.len() - 1]);
    let change = |x: f64, y: f64| (y - x).abs() / y.abs().max(f64::MIN_POSITIVE);
    change(a.friction.total(), b.friction.total())
        .max(change(a.z_mean, b.z_mean))
        .max(residual)
        .max(oil_imbalance(b))
}

/// The change of the oil the film holds over a window, relative to the oil through the
/// domain in it: zero in the periodic regime (the film holds the same oil at every window
/// end). Why: a ring that passes more oil than arrives (deep pockets carry it) drains the
/// flooded bank in front of it at a steady rate, and with it Z and f̄ creep by less than the
/// tolerance per window for as long as the bank lasts, then settle elsewhere (R = 0.2,
/// pockets 0.02 / 0.04 / 30 µm at `fast`: 43 % more oil out than in, Z̄ creeping by 4e-6 a
/// window for ≈ 190 windows, after which f̄ is 17 % lower; the motion alone had passed for
/// periodic at window 36).
pub(crate) fn oil_imbalance(w: &PeriodMeans) -> f64 {
    (w.content - w.start_content).abs() / w.throughput.max(f64::MIN_POSITIVE)
}

/// The periodic error of the motion: f̄ and Z̄ (see [`periodic_error`]).
fn motion_error(h: &[PeriodMeans]) -> f64 {
    let k = h.len() - 1;
    if let Some(mode) = slow_pair(h) {
        let est = |y: &dyn Fn(&PeriodMeans) -> f64| {
            let (y0, y1, y2) = (y(&h[k - 2]), y(&h[k - 1]), y(&h[k]));
            let limit = mode.limit(y0, y1, y2);
            (y2 - limit).abs().max((y2 - y1).abs()) / y2.abs().max(f64::MIN_POSITIVE)
        };
        return est(&|p| p.friction.total()).max(est(&|p| p.z_mean));
    }
    let est = |y: &dyn Fn(&PeriodMeans) -> f64| {
        let (y0, y1, y2) = (y(&h[k - 2]), y(&h[k - 1]), y(&h[k]));
        let (d1, d2) = (y1 - y0, y2 - y1);
        let scale = y2.abs().max(f64::MIN_POSITIVE);
        if d2.abs() <= 1e-13 * scale {
            return d2.abs() / scale;
        }
        let r = if d1 != 0.0 { d2 / d1 } else { f64::INFINITY };
        let tail = if r > 0.0 && r < 1.0 {
            d2.abs() / (1.0 - r)
        } else if r <= 0.0 {
            d2.abs()
        } else {
            // Growing changes say nothing of the tail, however small they are. (Reading them
            // as 10× to 100× the change instead saved nothing at `fast`: 30 sampled study
            // cases at 1e-4 took 1033–1035 periods against 1037.)
            f64::INFINITY
        };
        tail / scale
    };
    est(&|p| p.friction.total()).max(est(&|p| p.z_mean))
}
