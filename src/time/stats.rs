//! What a run has done so far, across its meshes: its film solves' tallies, its worst mass
//! defect, and the part a coarse approach took before it.

use super::outcome::Outcome;
use crate::solve::SolveStats;

/// The part of a run taken on a coarse approach mesh (zero without one).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ApproachDone {
    pub steps: usize,
    pub periods: usize,
    pub wall_time_s: f64,
}

impl ApproachDone {
    /// The whole of a finished run, as the part before a continuation on a finer mesh.
    pub fn of(o: &Outcome) -> Self {
        ApproachDone {
            steps: o.steps,
            periods: o.periods,
            wall_time_s: o.wall_time_s,
        }
    }
}

/// A run's tallies: they go on across a change of mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunStats {
    /// Film iterations over all steps.
    pub iterations: usize,
    /// Largest relative nodal residual of a film solve.
    pub max_residual: f64,
    /// Largest relative mass defect of a step.
    pub max_mass_defect: f64,
    /// What a coarse approach took before this run's mesh.
    pub approach: ApproachDone,
}

impl RunStats {
    /// Counts a step's film solve.
    pub fn record(&mut self, s: &SolveStats) {
        self.iterations += s.iterations;
        self.max_residual = self.max_residual.max(s.residual);
    }
}
