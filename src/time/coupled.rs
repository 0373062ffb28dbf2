//! The core of one coupled step, shared by the texture's transient (`time/transient.rs`) and
//! the engine cycle (`time/cycle/stepping.rs`): the ring's guess of Z, its implicit link into
//! the film solve, the contact floor, the Newmark advance (docs/model.md §4) and the mass
//! guard. What differs between the two (the film's old level, the texture's placement, the
//! oil the cycle exchanges with the liner) stays with each.

use super::common::{SolveError, CONTACT_Z};
use crate::model::ring::{Ring, RingLink, RingState};
use crate::solve::SolveStats;

/// The ring's part of one step of `dt` from `from`, under `ring`'s load at the step's end.
pub(super) struct RingStep {
    pub ring: Ring,
    pub from: RingState,
    pub dt: f64,
}

impl RingStep {
    /// Z extrapolated with the ring's velocity over the step.
    pub fn predicted(&self) -> f64 {
        self.from.z + self.dt * self.from.v
    }

    /// The film iteration's first Z from the caller's prediction `z`: never closer to the
    /// liner than half the present clearance (a guess must not put the ring on the liner by
    /// itself; the iteration then moves Z as far as the film demands). A guess that is not a
    /// number, or on the liner, fails the step at time `t` of the run `case` names.
    pub fn guess(&self, z: f64, case: impl Fn() -> String, t: f64) -> Result<f64, SolveError> {
        let z = z.max(0.5 * self.from.z);
        if !z.is_finite() {
            return Err(SolveError::Unstable {
                case: case(),
                t,
                quantity: "predicted ring position Z".into(),
                value: z,
            });
        }
        if z <= 0.0 {
            return Err(SolveError::Contact { case: case(), t, z });
        }
        Ok(z)
    }

    /// The implicit Newmark relation the film solve holds Z to (docs/model.md §4).
    pub fn link(&self) -> RingLink {
        self.ring.link(&self.from, self.dt)
    }

    /// The ring after the film solve put it at `z` carrying the film's and the asperities'
    /// load of `stats`; at or below [`CONTACT_Z`] the ring is on the liner and the step fails.
    pub fn close(
        &self,
        z: f64,
        stats: &SolveStats,
        case: impl Fn() -> String,
        t: f64,
    ) -> Result<RingState, SolveError> {
        if z <= CONTACT_Z {
            return Err(SolveError::Contact { case: case(), t, z });
        }
        Ok(self
            .ring
            .advance(&self.from, self.dt, z, stats.w_h + stats.w_a))
    }
}

/// The mass guard of every step: a relative mass defect above `tol` (or not a number) fails
/// the step at time `t` of the run `case` names. A wrong number that looks right is worse than
/// an error.
pub(super) fn guard_mass(
    defect: f64,
    tol: f64,
    case: impl Fn() -> String,
    t: f64,
) -> Result<(), SolveError> {
    if defect.is_nan() || defect > tol {
        return Err(SolveError::MassNotConserved {
            case: case(),
            t,
            defect,
            tol,
            hint: "the film solve did not conserve mass to round-off, which the Elrod–Adams \
                   scheme does when solved: the solve is not converged"
                .into(),
        });
    }
    Ok(())
}
