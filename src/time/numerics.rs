//! The numerics of a run: mesh, time step, periodic tolerance, start and accelerators, with
//! their validity against the case checked up front.

use serde::{Deserialize, Serialize};

use crate::model::case::{bad, positive, CaseSpec, InputError};
use crate::solve::{Method, Tolerance};

/// Numerical fidelity and run control.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Numerics {
    /// Cells along x1 over the domain [0, 0.2].
    pub n1: usize,
    /// Cells along x2 over the simulated half texture cell.
    pub n2: usize,
    /// Largest time step (L/U units); the step used divides the texture period exactly.
    pub dt: f64,
    /// Periodic regime reached when the estimated relative distance of the window means of
    /// f and Z from their periodic limits is below this (docs/solver.md, "Periodic regime").
    pub periodic_tol: f64,
    /// Guard: give up (converged = false) after this much simulated time.
    pub t_max: f64,
    /// At least this many averaging windows are simulated.
    pub min_periods: usize,
    /// Film solver.
    #[serde(default)]
    pub solver: Method,
    /// Initial state of the transient.
    #[serde(default)]
    pub start: Start,
    /// Jump the state along a slow mode to its limit when the window means show one (the
    /// periodic regime is then verified on fresh windows).
    #[serde(default = "yes")]
    pub extrapolate: bool,
    /// Coarse approach: reach the periodic regime first on a mesh of this many x2 cells (same
    /// N1 and time step; raised where a pocket would span fewer than 2 cells), then carry the
    /// state over to this mesh and run on to its own periodic regime. The answer is this
    /// mesh's (the periodic regime does not depend on the start); the coarse mesh only takes
    /// the ring's transient, where a step costs a few band factorisations (∝ N2³). None, or
    /// not below n2: off. Off in `Numerics::default()` (the plain method, which the tests
    /// compare against); the `paper` and `fine` tiers set it. Not serialised when off, so
    /// cache keys of runs without it do not carry it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach_n2: Option<usize>,
}

fn yes() -> bool {
    true
}

/// Where a transient run starts (the periodic regime it reaches does not depend on it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Start {
    /// The paper's initial state (docs/model.md §4): Z = z0, Z' = v0, flooded upstream gap.
    Paper,
    /// The untextured force balance (steady 1D film at its Z, at rest): the texture only
    /// perturbs an already balanced ring, so the periodic regime comes sooner.
    #[default]
    Equilibrium,
}

impl Default for Numerics {
    /// The paper's fidelity: 512×32, dt = 4e-4 (docs/model.md §3).
    fn default() -> Self {
        Numerics {
            n1: 512,
            n2: 32,
            dt: 4e-4,
            periodic_tol: 1e-5,
            t_max: 30.0,
            min_periods: 3,
            solver: Method::default(),
            start: Start::default(),
            extrapolate: true,
            approach_n2: None,
        }
    }
}

/// x2 cells of the coarse approach of the tiers with more (`paper`, `fine`).
pub const APPROACH_N2: usize = 8;

/// Periodic tolerance at which a coarse approach hands over to the full mesh: about the
/// coarse mesh's own offset from the full one (512×8 against 512×32: 0.1–0.4 % in f̄ and Z̄),
/// which only the full mesh's periods remove; converging the coarse run much further buys
/// nothing, stopping it much earlier leaves the full mesh part of the transient. Measured
/// (`paper` tier, Case I / Case III / R = 51.2, wall s): from the paper's start 19.6 / 19.7 /
/// 23.0 at 1e-1, 15.9 / 23.2 / 25.6 at 1e-2, 14.7 / 19.1 / 25.2 at 1e-3.
pub const APPROACH_TOL: f64 = 1e-3;

impl Numerics {
    /// The film-solver settings these numerics ask for.
    pub fn film_tolerance(&self) -> Tolerance {
        Tolerance::default()
    }

    /// Raises N2 where the pocket would span fewer than `cells` cells across.
    pub fn resolve_pockets(&mut self, case: &CaseSpec, cells: f64) {
        if let Some(t) = &case.texture {
            let half = 0.5 * t.width;
            let need = (cells * half / (2.0 * t.l2) - 1e-9).ceil();
            if need.is_finite() && need > self.n2 as f64 {
                self.n2 = need as usize;
            }
        }
    }

    /// The numerics of the coarse approach to the periodic regime (`approach_n2`), if it
    /// applies to this case: N2 = approach_n2, raised where a pocket would span fewer than 2
    /// cells (as for `draft`), and still below this N2; periodic tolerance [`APPROACH_TOL`];
    /// no approach of its own; the direct solver.
    pub fn approach_numerics(&self, case: &CaseSpec) -> Option<Numerics> {
        case.texture.as_ref()?;
        let mut coarse = Numerics {
            n2: self.approach_n2?,
            periodic_tol: APPROACH_TOL.max(self.periodic_tol),
            approach_n2: None,
            solver: Method::Direct,
            ..self.clone()
        };
        coarse.resolve_pockets(case, 2.0);
        (coarse.n2 < self.n2).then_some(coarse)
    }

    /// Checks the numerics against the case (cells across pockets, time step, guards).
    /// Errors name the field (`mesh` for n1 and n2).
    pub fn validate(&self, case: &CaseSpec) -> Result<(), InputError> {
        if self.n1 < 16 {
            return Err(bad("mesh", self.n1, "needs at least 16 cells along x1"));
        }
        if self.n2 < 1 {
            return Err(bad("mesh", self.n2, "needs at least 1 cell along x2"));
        }
        if self.approach_n2 == Some(0) {
            return Err(bad(
                "approach_n2",
                0,
                "needs at least 1 cell along x2 (or none for no coarse approach)",
            ));
        }
        positive("dt", self.dt)?;
        positive("periodic_tol", self.periodic_tol)?;
        positive("t_max", self.t_max)?;
        if let Some(t) = &case.texture {
            // (axis, semiaxis, cell size, extent the cells divide, name of the count)
            let axes = [
                ("l1", t.l1, 0.2 / self.n1 as f64, 0.2, "N1"),
                (
                    "l2",
                    t.l2,
                    0.5 * t.width / self.n2 as f64,
                    0.5 * t.width,
                    "N2",
                ),
            ];
            for (axis, l, d, extent, count) in axes {
                if 2.0 * l < 2.0 * d * (1.0 - 1e-12) {
                    return Err(bad(
                        "mesh",
                        format!("{}x{}", self.n1, self.n2),
                        format!(
                            "puts {:.2} cells across the pocket axis 2·{axis} = {} cm (need ≥ 2); raise {count} to at least {}",
                            2.0 * l / d,
                            2.0 * l,
                            (extent / l).ceil()
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::case::Texture;
    use crate::time::Fidelity;

    #[test]
    fn the_coarse_approach_runs_on_the_direct_solver_at_n2_8() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        for solver in [Method::Direct, Method::Reference] {
            let num = Numerics {
                solver,
                ..Fidelity::Paper.numerics_for(&case)
            };
            let coarse = num
                .approach_numerics(&case)
                .expect("the paper tier approaches");
            assert_eq!(coarse.solver, Method::Direct);
            assert_eq!((coarse.n1, coarse.n2, coarse.dt), (num.n1, 8, num.dt));
            assert_eq!(coarse.approach_n2, None);
        }
    }
}
