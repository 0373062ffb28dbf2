//! Which numerics a run gets: its fidelity tier, what was given explicitly, and the case. Every
//! command resolves its numerics here (`simulate`, `bench`, study files, `optimise` and
//! `cycle`), so one case gets the same numerics from each.

use super::fidelity::Fidelity;
use super::numerics::{Approach, Numerics, Start, TimeScheme};
use crate::model::case::CaseSpec;
use crate::solve::Method;

/// Numerics given explicitly beside a tier (a flag, a study's `[numerics]`); `None`: the
/// tier's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Cells along x1.
    pub n1: Option<usize>,
    /// Cells along x2: a floor, raised where a pocket would span fewer than the tier's
    /// [`Fidelity::pocket_cells`] across.
    pub n2: Option<usize>,
    /// The time step, taken as given (validated, not fitted).
    pub dt: Option<f64>,
    pub scheme: Option<TimeScheme>,
    pub periodic_tol: Option<f64>,
    pub t_max: Option<f64>,
    pub solver: Option<Method>,
    pub start: Option<Start>,
    pub accelerate: Option<bool>,
    /// The coarse approach; `Some(None)`: none.
    pub approach: Option<Option<Approach>>,
}

impl Overrides {
    /// Whether the mesh, step or scheme is given: the answer is then on them, with no
    /// deep-pocket mesh after it.
    pub fn fixes_the_mesh(&self) -> bool {
        self.n1.is_some() || self.n2.is_some() || self.dt.is_some() || self.scheme.is_some()
    }
}

/// The numerics of `case` at `fidelity` with `given` applied. One precedence:
///
/// 1. The tier's numerics, N1 (and the coarse approach's) scaled with the ring's width
///    ([`Numerics::fit_mesh_to_ring`]).
/// 2. A given N1, N2 or scheme replaces the tier's.
/// 3. A given step is taken as it is. Otherwise the step follows the mesh and scheme: a
///    ring-frame scheme given to a characteristic tier takes the texture one cell a step
///    (dx1/u, Courant number 1); the characteristic scheme steps at 2·dx1/u; then the step is
///    shortened to take at least [`super::MIN_STEPS_PER_PERIOD`] steps a texture period.
/// 4. The other settings given (tolerance, t_max, solver, start, acceleration, approach)
///    replace the tier's.
/// 5. A given mesh, step or scheme is what the answer is on: no deep-pocket mesh after it
///    ([`Overrides::fixes_the_mesh`]).
/// 6. Last, N2 — the tier's or the one given — is raised where a pocket would span fewer than
///    [`Fidelity::pocket_cells`] cells across, so that every texture is resolved alike.
pub fn resolve(fidelity: Fidelity, given: &Overrides, case: &CaseSpec) -> Numerics {
    let mut n = fidelity.numerics();
    n.fit_mesh_to_ring(case);
    let tier_scheme = n.scheme;
    n.n1 = given.n1.unwrap_or(n.n1);
    n.n2 = given.n2.unwrap_or(n.n2);
    n.scheme = given.scheme.unwrap_or(n.scheme);
    match given.dt {
        Some(dt) => n.dt = dt,
        None => {
            if n.scheme != tier_scheme && tier_scheme == TimeScheme::Characteristic {
                n.dt = n.cell_crossing_dt(case);
            }
            n.fit_characteristic_step(case);
            n.fit_step_to_period(case);
        }
    }
    n.periodic_tol = given.periodic_tol.unwrap_or(n.periodic_tol);
    n.t_max = given.t_max.unwrap_or(n.t_max);
    n.solver = given.solver.unwrap_or(n.solver);
    n.start = given.start.unwrap_or(n.start);
    n.accelerate = given.accelerate.unwrap_or(n.accelerate);
    n.approach = given.approach.unwrap_or(n.approach);
    if given.fixes_the_mesh() {
        n.deep = None;
    }
    n.resolve_pockets(case, fidelity.pocket_cells());
    n
}

impl Fidelity {
    /// The numerics of this tier for one case, nothing given beside it ([`resolve`]): N2
    /// raised where a pocket would span fewer than [`Self::pocket_cells`] cells across (small
    /// pockets in a wide cell, e.g. l2 = 0.0025 in width 0.06 needs N2 = 24), so every texture
    /// is resolved alike.
    pub fn numerics_for(self, case: &CaseSpec) -> Numerics {
        resolve(self, &Overrides::default(), case)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::case::Texture;

    fn given() -> Overrides {
        Overrides::default()
    }

    #[test]
    fn a_mesh_step_or_scheme_given_keeps_the_run_on_its_own_mesh() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 20.0));
        let deep = |o: Overrides| resolve(Fidelity::Fast, &o, &case).deep;
        assert!(deep(given()).is_some());
        let tol = Overrides {
            periodic_tol: Some(1e-5),
            start: Some(Start::Paper),
            approach: Some(None),
            ..given()
        };
        assert!(deep(tol).is_some());
        for o in [
            Overrides {
                n1: Some(512),
                ..given()
            },
            Overrides {
                n2: Some(12),
                ..given()
            },
            Overrides {
                dt: Some(5e-4),
                ..given()
            },
            Overrides {
                scheme: Some(TimeScheme::Characteristic),
                ..given()
            },
        ] {
            assert_eq!(deep(o), None, "{o:?}");
        }
    }

    #[test]
    fn a_given_n2_is_raised_to_resolve_small_pockets() {
        // l2 = 0.005 in a 0.05 cm cell: 4 cells across a pocket take N2 = 10, 2 take 5.
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.005, 0.05, 10.0));
        let n2 = |f: Fidelity, n2: Option<usize>| {
            let o = Overrides {
                n1: Some(512),
                n2,
                ..given()
            };
            resolve(f, &o, &case).n2
        };
        assert_eq!(n2(Fidelity::Fast, None), 10);
        assert_eq!(n2(Fidelity::Fast, Some(8)), 10);
        assert_eq!(n2(Fidelity::Fast, Some(2)), 10);
        assert_eq!(n2(Fidelity::Fast, Some(12)), 12);
        assert_eq!(n2(Fidelity::Draft, Some(4)), 5);
        assert_eq!(n2(Fidelity::Paper, None), 32);
    }

    #[test]
    fn the_step_follows_the_mesh_and_scheme_unless_given() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        let dt = |f: Fidelity, o: Overrides| resolve(f, &o, &case).dt;
        // The characteristic step 2·dx1/u of the mesh given (0.2 cm long, u = 1).
        let n1 = Overrides {
            n1: Some(400),
            ..given()
        };
        assert_eq!(dt(Fidelity::Fast, n1), 2.0 * 0.2 / 400.0);
        // A ring-frame scheme given to a characteristic tier: one cell a step, dx1/u.
        let bdf2 = Overrides {
            scheme: Some(TimeScheme::Bdf2),
            ..given()
        };
        assert_eq!(dt(Fidelity::Fast, bdf2), 0.2 / 700.0);
        // The characteristic scheme given to a ring-frame tier: its own step.
        let characteristic = Overrides {
            scheme: Some(TimeScheme::Characteristic),
            ..given()
        };
        assert_eq!(dt(Fidelity::Paper, characteristic), 2.0 * 0.2 / 512.0);
        // A step given is taken as it is, with any scheme.
        for scheme in [None, Some(TimeScheme::Bdf2)] {
            let o = Overrides {
                dt: Some(3e-4),
                scheme,
                ..given()
            };
            assert_eq!(dt(Fidelity::Fast, o), 3e-4);
        }
        // A short period shortens the tier's step to 8 steps a period, not a step given.
        let short = CaseSpec::paper(3.2).with_texture(Texture::circular(0.0025, 0.005, 5.0));
        assert_eq!(resolve(Fidelity::Draft, &given(), &short).dt, 0.005 / 8.0);
        let step = Overrides {
            dt: Some(1e-3),
            ..given()
        };
        assert_eq!(resolve(Fidelity::Draft, &step, &short).dt, 1e-3);
    }

    #[test]
    fn nothing_given_is_the_tier_for_the_case() {
        let case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.0025, 0.06, 5.0));
        for f in Fidelity::ALL {
            let n = resolve(f, &given(), &case);
            assert_eq!(n, f.numerics_for(&case));
            let tier = f.numerics();
            assert_eq!(
                (n.periodic_tol, n.scheme, n.approach, n.deep),
                (tier.periodic_tol, tier.scheme, tier.approach, tier.deep)
            );
            assert_eq!(
                n.n2,
                tier.n2.max(if f == Fidelity::Draft { 12 } else { 24 })
            );
        }
    }
}
