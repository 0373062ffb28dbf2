//! What every part of a run shares: why a run fails, what it tells its observers while it
//! runs, and the clearance below which the lubrication model ends. A leaf of `time/`: it
//! names no other file of it.

use crate::solve::FilmError;

/// Contact: the ring is on the liner once Z (its apex's clearance above the plateau, µm) is at
/// or below this, 1 nm, a few oil molecules: no continuum film (docs/model.md §3's thin-film
/// model) is left to lubricate. Why not Z ≤ 0: the film iteration closes the gap by at most
/// half per iteration and each step's Z guess is at least half the last Z, so a ring pushed
/// into the liner approaches Z = 0 geometrically and never reaches it (a load 10⁴ times the
/// paper's: Z = 4e-250 µm and f̄ = 7e241 after 30 ms).
pub const CONTACT_Z: f64 = 1e-3;

/// Largest relative mass defect of a step (`Transient::mass_defect`) taken for a converged
/// solve: the Elrod–Adams scheme conserves mass to round-off (≤ 1.5e-12 over the stability
/// map, results/stability/).
pub const MASS_TOL: f64 = 1e-6;

/// Why a run failed: always names the case and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error("case {case}: film solve failed at t = {t:.5}: {source}")]
    Film {
        case: String,
        t: f64,
        source: FilmError,
    },
    #[error("case {case}: the ring reached the liner (Z = {z:.2e} µm, under the {floor} µm a lubricating film needs) at t = {t:.5}; neither the film nor the asperities (docs/model.md §11, where the case has them) could hold it off", floor = CONTACT_Z)]
    Contact { case: String, t: f64, z: f64 },
    #[error("case {case}: {quantity} = {value} at t = {t:.5}: the run is numerically unstable (try a smaller dt)")]
    Unstable {
        case: String,
        t: f64,
        quantity: String,
        value: f64,
    },
    #[error("case {case}: mass not conserved at t = {t:.5}: the step's film content changed by {defect:.2e} of its throughflow more than the boundary flows carried (tolerance {tol:.0e}); {hint}")]
    MassNotConserved {
        case: String,
        t: f64,
        defect: f64,
        tol: f64,
        hint: String,
    },
    #[error("case {case}: steady force balance failed: {source}")]
    Steady { case: String, source: SteadyError },
}

/// Why a steady solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SteadyError {
    #[error("{0}")]
    Film(#[from] FilmError),
    #[error("no force balance for Z in [{lo:.3e}, {hi:.3e}] µm (load there {w_lo:.3e} … {w_hi:.3e}, W_ps = {w_ps:.3e}); the film cannot carry the ring: {hint}")]
    NoBracket {
        lo: f64,
        hi: f64,
        w_lo: f64,
        w_hi: f64,
        w_ps: f64,
        /// The likely cause, for the user.
        hint: &'static str,
    },
    #[error("the ring reached the liner (Z = {z:.2e} µm at the force balance, under the {floor} µm a lubricating film needs) with the asperities carrying {w_a:.3e} of W_ps = {w_ps:.3e}: the load is beyond what film and asperities can bear (docs/model.md §11)", floor = CONTACT_Z)]
    Overloaded { z: f64, w_a: f64, w_ps: f64 },
}

/// Reported after each averaging window of a transient run.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub period: usize,
    pub t: f64,
    pub f_mean: f64,
    pub z_mean: f64,
    /// Estimated relative distance from the periodic regime (infinite until it can be told).
    pub periodic_error: f64,
}

/// Who watches a run: a closure called after every averaging window `W` (a transient's
/// [`Progress`]; a cycle run's cycle, `time::cycle::CycleWatch`), one after every step `S`
/// (the transient itself: `time::Watch`; a cycle's row). Observers sit outside the maths:
/// they read, never steer.
pub struct Observers<'a, S, W = Progress> {
    pub on_window: Option<&'a mut dyn FnMut(&W)>,
    pub on_step: Option<&'a mut dyn FnMut(&S)>,
}

impl<S, W> Default for Observers<'_, S, W> {
    fn default() -> Self {
        Observers {
            on_window: None,
            on_step: None,
        }
    }
}

impl<S, W> Observers<'_, S, W> {
    pub(super) fn window(&mut self, p: &W) {
        if let Some(f) = self.on_window.as_mut() {
            f(p);
        }
    }
    pub(super) fn step(&mut self, t: &S) {
        if let Some(f) = self.on_step.as_mut() {
            f(t);
        }
    }
}
