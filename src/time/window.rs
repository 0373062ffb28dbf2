//! Averaging windows (docs/solver.md, "Periodic regime"): whole texture periods, and the means
//! of a run over one, which its stopping rule reads.

use super::outcome::SeriesRow;
use crate::model::friction::Friction;

/// Shortest averaging window (ms = L/U): as long as the pseudo-period of an untextured run.
/// For short texture periods (per = 0.005 is 13 steps) the window-to-window change of a slow
/// creep is tiny against its tail (ratio ≈ 0.993 a period at R = 102.4), so neither the
/// periodicity estimate nor the slow-mode jump could read it period by period. Means over
/// whole periods are the same in the periodic regime.
pub const MIN_WINDOW: f64 = 0.06;

/// Texture periods per averaging window for a texture period `period` (ms): the fewest
/// whole periods spanning at least [`MIN_WINDOW`].
pub fn window_periods(period: f64) -> usize {
    ((MIN_WINDOW / period) - 1e-9).ceil().max(1.0) as usize
}

/// Means over one averaging window (whole texture periods).
#[derive(Clone, Debug)]
pub(crate) struct PeriodMeans {
    pub friction: Friction,
    pub extra: Vec<Friction>,
    pub z_mean: f64,
    pub z_min: f64,
    pub z_max: f64,
    /// Mean film force over the window (the load the film carries, in W_ps's units).
    pub w_h: f64,
    /// Mean asperity load over the window (docs/model.md §11, in W_ps's units).
    pub w_a: f64,
    /// Oil the film holds at the window's start and end (∫ h·θ dx1 dx2 over the domain,
    /// nondimensional).
    pub start_content: f64,
    pub content: f64,
    /// Oil through the domain over the window at the end's boundary flow rates (the larger
    /// of inflow and outflow, times the window's length): the scale of a content change.
    pub throughput: f64,
}

impl PeriodMeans {
    pub fn empty() -> Self {
        PeriodMeans {
            friction: Friction::default(),
            extra: Vec::new(),
            z_mean: 0.0,
            z_min: f64::INFINITY,
            z_max: f64::NEG_INFINITY,
            w_h: 0.0,
            w_a: 0.0,
            start_content: 0.0,
            content: 0.0,
            throughput: 0.0,
        }
    }
    pub fn add(&mut self, row: &SeriesRow, f: &Friction, extra: &[Friction]) {
        self.friction.add(f);
        self.extra.resize(extra.len(), Friction::default());
        for (a, e) in self.extra.iter_mut().zip(extra) {
            a.add(e);
        }
        self.z_mean += row.z;
        self.z_min = self.z_min.min(row.z);
        self.z_max = self.z_max.max(row.z);
        self.w_h += row.w_h;
        self.w_a += row.w_a;
    }
    /// The samples at the n step ends of a period: their plain mean is the trapezoidal mean
    /// of the periodic signal over the period.
    pub fn finish(mut self, n: usize) -> Self {
        self.friction = self.friction.scaled(1.0 / n as f64);
        for e in &mut self.extra {
            *e = e.scaled(1.0 / n as f64);
        }
        self.z_mean /= n as f64;
        self.w_h /= n as f64;
        self.w_a /= n as f64;
        self
    }
}
