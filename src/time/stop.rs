//! What a run runs until: the stopping rule the run's loop asks after every averaging window
//! (the periodic regime, time/periodic.rs, for a run at a constant operating point).

use super::window::PeriodMeans;

/// A window's estimated distance from the regime a run seeks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Distance {
    /// Of the motion alone (what a stall is read from).
    pub motion: f64,
    /// In all: the run stops on it, and reports it.
    pub total: f64,
}

/// The stopping rule of a run, asked after every averaging window.
pub(crate) trait StopRule {
    /// Takes the means of the window just run.
    fn push(&mut self, means: PeriodMeans);
    /// The window just run.
    fn last(&self) -> &PeriodMeans;
    /// The estimated distance after the window just run, given the accelerator's residual
    /// when one runs.
    fn distance(&self, residual: Option<f64>) -> Distance;
    /// Whether the run is there at distance `total`.
    fn reached(&self, total: f64) -> bool;
    /// Windows run in all (across restarts).
    fn windows(&self) -> usize;
    /// The run goes on as another map (a change of time scheme): its windows start afresh.
    fn restart(&mut self);
}
