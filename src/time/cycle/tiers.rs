//! A cycle run's numerics at a fidelity tier (docs/model.md §12, docs/solver.md "The engine
//! cycle"): the tier's mesh (through the one resolver, `time::resolve`), crank steps that
//! follow the motion, and the texture moved by at most a set number of cells a step.

use super::drive::{crank_steps, Drive, StepRule};
use super::record::CycleSummary;
use crate::model::case::{CaseSpec, InputError, Texture};
use crate::solve::{FilmSolver, Method};
use crate::time::limits::check_cycle;
use crate::time::{resolve, Fidelity, Limits, Overrides, TimeScheme};

/// How a cycle run is discretised and when it stops.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CycleNumerics {
    /// Cells along x1 over the film's domain (2.5 ring widths) and across half a lattice
    /// width (1 for a plain liner, whose film does not vary across).
    pub n1: usize,
    pub n2: usize,
    pub steps: StepRule,
    /// The film's storage term: backward Euler, or along the Couette characteristics on the
    /// steps whose Courant number u·dt/(2·dx1) is at most 1 (backward Euler on the others).
    pub scheme: TimeScheme,
    /// Length of the oil map's cells along the liner (cm).
    pub oil_cell_cm: f64,
    /// Crank angle the first cycle starts from (degrees): mid-stroke, where the untextured
    /// force balance is a sound start.
    pub start_deg: f64,
    /// Cycles stop repeating when the friction work and the oil map change by less than
    /// this from one cycle to the next (relative).
    pub cyclic_tol: f64,
    /// Most cycles run; a run that has not repeated itself by then says so.
    pub max_cycles: usize,
    /// Cycles after which a run resumed from another liner's cyclic state is settled
    /// ([`super::SETTLE_CYCLES`]); None: it runs until it repeats itself. Not serialised: a
    /// cache key names the settle rule beside the numerics ([`CycleNumerics::keyed`]).
    #[serde(skip)]
    pub settle: Option<usize>,
}

/// Why a cycle run stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleEnd {
    /// The last cycle repeated the one before: friction work and oil map within the
    /// tolerance.
    Repeated,
    /// The settle rule's cycles were run (a run resumed from another liner's cyclic state).
    Settled(usize),
    /// The most cycles were run without the last repeating the one before.
    OutOfCycles,
}

impl CycleNumerics {
    /// The stop rule after `cycles`: None to run another.
    pub fn stop(&self, cycles: &[CycleSummary]) -> Option<CycleEnd> {
        let tol = self.cyclic_tol;
        if cycles
            .last()
            .is_some_and(|c| c.work_change < tol && c.oil_change < tol)
        {
            Some(CycleEnd::Repeated)
        } else if let Some(n) = self.settle.filter(|&n| cycles.len() >= n) {
            Some(CycleEnd::Settled(n))
        } else if cycles.len() >= self.max_cycles {
            Some(CycleEnd::OutOfCycles)
        } else {
            None
        }
    }

    /// A run of these numerics under `drive` against `limits`, before it runs: its film's
    /// memory, and its crank steps with pockets under the ring all the way over its most
    /// cycles (a bound: a liner textured in part, or one that repeats sooner, takes fewer).
    pub fn check(&self, drive: &Drive, limits: &Limits) -> Result<(), InputError> {
        let per_cycle = crank_steps(drive, self.start_deg, &self.steps, &|_| true).len() - 1;
        check_cycle((self.n1, self.n2), per_cycle, self.most_cycles(), limits)
    }

    /// The most cycles a run of these numerics takes: the settle rule's where it is the
    /// fewer.
    pub fn most_cycles(&self) -> usize {
        self.settle
            .map_or(self.max_cycles, |n| n.min(self.max_cycles))
    }

    /// The numerics as a cache key holds them: the most cycles the run takes in
    /// `max_cycles` (the key names the settle rule itself beside them).
    pub fn keyed(&self) -> CycleNumerics {
        CycleNumerics {
            max_cycles: self.most_cycles(),
            ..self.clone()
        }
    }

    /// The film solver of a cycle run: the direct active-set solver (docs/solver.md, "One
    /// film problem"), whose exact band-LU solves the crank steps' changing loads need.
    pub fn solver(&self) -> FilmSolver {
        FilmSolver::new(Method::Direct)
    }
}

/// A cycle tier's steps and cells.
struct Tier {
    /// Crank step where the piston runs at the mean piston speed or faster (degrees), and
    /// the least fraction of it taken near a dead centre.
    step_deg: f64,
    refine: f64,
    /// Cells along x1 as a share of `draft`'s film mesh for the ring (the one resolver's).
    cells: f64,
}

/// Per tier: the crank steps halve and the cells double from one tier to the next. The
/// texture moves at most [`TEXTURE_CELLS`] cells a step at every tier. Measured on the
/// example engine's uniformly textured liner (results/cycle_steps/): `draft` is within
/// 0.3 % of `fast` and `paper` in the cycle's friction work.
fn tier(fidelity: Fidelity) -> Tier {
    let (step_deg, cells) = match fidelity {
        Fidelity::Draft => (1.0, 0.5),
        Fidelity::Fast => (0.5, 1.0),
        Fidelity::Paper => (0.25, 2.0),
        Fidelity::Fine => (0.125, 4.0),
    };
    Tier {
        step_deg,
        refine: 0.1,
        cells,
    }
}

/// Cells of x1 the texture may move in one step where pockets pass under the ring: 2, the
/// characteristic scheme's Courant number 1 (u·dt/(2·dx1)), at which it carries the
/// cavitated film exactly (docs/solver.md, "Time scheme").
pub const TEXTURE_CELLS: f64 = 2.0;

/// Largest change of the asperities' share of the load over one crank step, every tier
/// (docs/model.md §12, "Crank steps"; measured: results/cycle_contact/).
pub const CONTACT_SHARE: f64 = 0.05;

/// The numerics of a cycle run of a ring (`ring`: its case, width and contact) over liners
/// whose finest texture is `texture` (None: plain liners), at `fidelity` with the mesh
/// `given` (its N1 and N2; a cycle's time steps are its crank steps): the mesh the one
/// resolver gives the ring over that texture at the mean piston speed, N2 only where pockets
/// are under the ring.
pub fn cycle_numerics(
    fidelity: Fidelity,
    given: &Overrides,
    ring: &CaseSpec,
    texture: Option<&Texture>,
) -> CycleNumerics {
    let case = CaseSpec {
        u: 1.0,
        texture: texture.cloned(),
        ..ring.clone()
    };
    let mesh = Overrides {
        n2: given.n2,
        ..Overrides::default()
    };
    let n = resolve(fidelity, &mesh, &case);
    let t = tier(fidelity);
    let n1 = given.n1.unwrap_or_else(|| {
        let draft = resolve(Fidelity::Draft, &mesh, &case).n1;
        ((draft as f64 * t.cells).round() as usize).max(16)
    });
    let dx = case.contact().length_cm / n1 as f64;
    CycleNumerics {
        n1,
        n2: n.n2,
        steps: StepRule {
            step_deg: t.step_deg,
            refine: t.refine,
            texture_step: if texture.is_some() {
                TEXTURE_CELLS * dx
            } else {
                f64::INFINITY
            },
            contact_share: CONTACT_SHARE,
        },
        scheme: TimeScheme::Characteristic,
        oil_cell_cm: dx,
        start_deg: 90.0,
        cyclic_tol: 1e-3,
        max_cycles: 20,
        settle: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::case::CaseSpec;

    /// Cycles whose work and oil change by `changes` from one to the next.
    fn cycles(changes: &[f64]) -> Vec<CycleSummary> {
        changes
            .iter()
            .enumerate()
            .map(|(index, &c)| CycleSummary {
                index,
                friction_work_j_per_m: 1.0,
                work_change: c,
                oil_change: c,
                oil: Default::default(),
                steps: 1,
            })
            .collect()
    }

    #[test]
    fn the_stop_rule_says_why_a_run_ended() {
        let n = cycle_numerics(
            Fidelity::Draft,
            &Overrides::default(),
            &CaseSpec::paper(5.0),
            None,
        );
        assert_eq!(n.stop(&cycles(&[])), None);
        assert_eq!(n.stop(&cycles(&[f64::INFINITY, 0.5])), None);
        assert_eq!(
            n.stop(&cycles(&[f64::INFINITY, 1e-4])),
            Some(CycleEnd::Repeated)
        );
        let never = vec![0.5; n.max_cycles];
        assert_eq!(n.stop(&cycles(&never)), Some(CycleEnd::OutOfCycles));
        let settling = CycleNumerics {
            settle: Some(2),
            ..n.clone()
        };
        assert_eq!(settling.stop(&cycles(&[f64::INFINITY])), None);
        assert_eq!(
            settling.stop(&cycles(&[f64::INFINITY, 0.5])),
            Some(CycleEnd::Settled(2))
        );
        // A cycle that repeats the one before is said to, settled or not.
        assert_eq!(
            settling.stop(&cycles(&[f64::INFINITY, 1e-4])),
            Some(CycleEnd::Repeated)
        );
        // The key holds the most cycles a run takes, as it did when settling cut them.
        assert_eq!(settling.most_cycles(), 2);
        assert_eq!(settling.keyed().max_cycles, 2);
        assert_eq!(n.keyed(), n);
    }
}
