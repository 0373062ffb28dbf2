//! Explicit ring coupling (contrast only): the central-difference update Z⁺ = Z + dt·V +
//! dt²/2·A from the old acceleration, the film solved at that Z, then the new acceleration
//! from its load. The film's squeeze stiffness makes it unstable at the paper's time step
//! (docs/model.md §4), which is why texopt couples the ring implicitly.

use texopt::mesh::integrals::{contact_load, load};
use texopt::mesh::FilmState;
use texopt::solve::{FilmError, FilmMethod, SolveStats, Step};

/// Wraps a film solver: each step is solved at the explicitly predicted Z, the ring link
/// ignored.
pub struct Explicit {
    pub inner: Box<dyn FilmMethod>,
    /// The load of the last step (None before the first: read from the initial film).
    last_w_h: Option<f64>,
}

impl Explicit {
    pub fn new(inner: Box<dyn FilmMethod>) -> Self {
        Explicit {
            inner,
            last_w_h: None,
        }
    }
}

impl FilmMethod for Explicit {
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        let Some(link) = step.ring else {
            return self.inner.solve(step, state, z);
        };
        // The Newmark link carries Z + dt·V + dt²/4·A and κ = dt²/(4m): the explicit
        // prediction adds dt²/4·A = κ·(W_h − W_ps) at the old level.
        // The load is the film's and the asperities' (docs/model.md §11) at the old level.
        let w_h = self.last_w_h.unwrap_or_else(|| {
            load(step.grid, &step.gap.ring, &state.p)
                + link
                    .contact
                    .map_or(0.0, |l| contact_load(step.grid, step.gap, *z, &l).0)
        });
        *z = link.z_pred + link.kappa * (w_h - link.w_ps);
        let fixed = Step {
            ring: None,
            ..*step
        };
        let mut stats = self.inner.solve(&fixed, state, z)?;
        stats.w_a = link
            .contact
            .map_or(0.0, |l| contact_load(step.grid, step.gap, *z, &l).0);
        self.last_w_h = Some(stats.w_h + stats.w_a);
        Ok(stats)
    }

    fn carries_guess(&self) -> bool {
        self.inner.carries_guess()
    }
}
