//! The film's time levels (docs/solver.md, "Time scheme"): the previous level φⁿ, the history
//! the scheme's storage term keeps beside it, and the old-level term each step's stencil reads.

use super::characteristic;
use super::numerics::TimeScheme;
use crate::mesh::Grid;

/// The storage term ∂(hθ)/∂t of the film, with the history it reads beyond φⁿ.
enum Storage {
    /// (φⁿ⁺¹ − φⁿ)/dt.
    BackwardEuler,
    /// (3φⁿ⁺¹ − 4φⁿ + φⁿ⁻¹)/(2dt) = 1.5·(φⁿ⁺¹ − (4φⁿ − φⁿ⁻¹)/3)/dt: φⁿ⁻¹ and the levels
    /// solved since the history last restarted (a start, a jump, a new mesh).
    Bdf2 { older: Vec<f64>, solved: usize },
    /// (φⁿ⁺¹ − φⁿ(x1 − u·dt/2))/dt: φⁿ moved along the Couette characteristics
    /// (time/characteristic.rs).
    Characteristic,
}

/// The old-level term a step's stencil reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Term {
    /// φⁿ at 1/dt (backward Euler, along the characteristics, or a BDF2 step without its
    /// history).
    Old,
    /// BDF2's (4φⁿ − φⁿ⁻¹)/3 at 1.5/dt.
    Combined,
}

/// The film's previous time level and its scheme's history, and the storage term the last
/// step took.
pub(super) struct TimeLevels {
    /// φⁿ: the film at the previous time level.
    old: Vec<f64>,
    storage: Storage,
    /// BDF2's old-level term (4φⁿ − φⁿ⁻¹)/3 of the last step that took it: kept beside the
    /// storage, so that the last step's term stays readable after a fall-back.
    combined: Vec<f64>,
    term: Term,
    /// 1/dt of the last step's storage term: 1/dt, or 1.5/dt for BDF2's.
    inv_dt: f64,
}

impl TimeLevels {
    /// The levels of a run of `scheme` with step `dt` starting from the film `phi`.
    pub fn new(scheme: TimeScheme, phi: &[f64], dt: f64) -> Self {
        let storage = match scheme {
            TimeScheme::BackwardEuler => Storage::BackwardEuler,
            TimeScheme::Bdf2 => Storage::Bdf2 {
                older: phi.to_vec(),
                solved: 0,
            },
            TimeScheme::Characteristic => Storage::Characteristic,
        };
        TimeLevels {
            old: phi.to_vec(),
            storage,
            combined: Vec::new(),
            term: Term::Old,
            inv_dt: 1.0 / dt,
        }
    }

    /// The scheme the levels are kept for.
    pub fn scheme(&self) -> TimeScheme {
        match self.storage {
            Storage::BackwardEuler => TimeScheme::BackwardEuler,
            Storage::Bdf2 { .. } => TimeScheme::Bdf2,
            Storage::Characteristic => TimeScheme::Characteristic,
        }
    }

    /// Before a step: the film just solved, `phi`, becomes the previous level (its buffer
    /// takes the one freed, for the step's guess to fill), moved along the characteristics
    /// at liner speed `u` with that scheme; then the step's storage term is chosen: BDF2's
    /// when the scheme asks for it, the previous two levels are at hand and its old-level
    /// term is nowhere negative; else backward Euler's.
    pub fn advance(&mut self, phi: &mut Vec<f64>, dt: f64, u: f64, g: &Grid) {
        if let Storage::Bdf2 { older, .. } = &mut self.storage {
            std::mem::swap(older, &mut self.old);
        }
        std::mem::swap(&mut self.old, phi);
        self.term = Term::Old;
        self.inv_dt = 1.0 / dt;
        match &mut self.storage {
            Storage::BackwardEuler => {}
            Storage::Characteristic => {
                let c = characteristic::courant(u, dt, g.dx);
                characteristic::shift(&mut self.old, g.n1, g.n2, c);
            }
            Storage::Bdf2 { older, solved } => {
                if *solved >= 1 {
                    let combined = &mut self.combined;
                    combined.clear();
                    combined.extend(
                        self.old
                            .iter()
                            .zip(older.iter())
                            .map(|(&now, &before)| (4.0 * now - before) / 3.0),
                    );
                    if combined.iter().all(|&p| p >= 0.0) {
                        self.term = Term::Combined;
                        self.inv_dt = 1.5 / dt;
                    }
                }
            }
        }
    }

    /// The step went through: one more level of history.
    pub fn solved(&mut self) {
        if let Storage::Bdf2 { solved, .. } = &mut self.storage {
            *solved += 1;
        }
    }

    /// The old-level term the last step's stencil read: φⁿ, or BDF2's (4φⁿ − φⁿ⁻¹)/3.
    pub fn read(&self) -> &[f64] {
        match self.term {
            Term::Combined => &self.combined,
            Term::Old => &self.old,
        }
    }

    /// φⁿ, the previous level (moved along the characteristics with that scheme).
    pub fn old(&self) -> &[f64] {
        &self.old
    }

    /// 1/dt of the last step's storage term.
    pub fn inv_dt(&self) -> f64 {
        self.inv_dt
    }

    /// The scale of the last step's content change against the flows: 1 for backward Euler,
    /// 1.5 (as (1.5/dt)·dt) for BDF2's term, or None where the change is not scaled.
    pub fn scale(&self, dt: f64) -> Option<f64> {
        (self.term == Term::Combined).then_some(self.inv_dt * dt)
    }

    /// Whether the last step took its scheme's own storage term (so that factors kept a
    /// period ago, of that term's coefficient, serve it): all but a BDF2 step that fell back
    /// on backward Euler.
    pub fn regular(&self) -> bool {
        !matches!(
            (&self.storage, self.term),
            (Storage::Bdf2 { .. }, Term::Old)
        )
    }

    /// Restarts the history: the next step is backward Euler (the state was moved: a jump,
    /// another mesh).
    pub fn restart(&mut self) {
        if let Storage::Bdf2 { solved, .. } = &mut self.storage {
            *solved = 0;
        }
    }

    /// Goes on with backward Euler (a BDF2 run that did not settle).
    pub fn fall_back_to_backward_euler(&mut self) {
        self.storage = Storage::BackwardEuler;
    }

    /// Sets the previous level (a film laid or carried over, not stepped to).
    pub fn set(&mut self, phi: &[f64]) {
        self.old.copy_from_slice(phi);
    }

    /// Keeps the history after the film moved from `before` to `now` on the same mesh (an
    /// extrapolation along slow modes): the previous level moves by the same change (kept
    /// ≥ 0), so BDF2 continues instead of restarting with a backward-Euler step, whose
    /// first-order error a periodic orbit would otherwise carry at every window.
    pub fn shift(&mut self, before: &[f64], now: &[f64]) {
        for ((old, &now), &b) in self.old.iter_mut().zip(now).zip(before) {
            *old = (*old + now - b).max(0.0);
        }
    }
}
