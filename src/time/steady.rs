//! Untextured liner: the problem is 1D and steady (docs/model.md §6), solved as such — a
//! steady Elrod–Adams film on one line of nodes (the same stencil and solver as the transient,
//! without the time term) and a scalar root find on Z for the force balance
//! W_h(Z) + W_a(Z) = W_ps (W_a the asperity load, docs/model.md §11).

use std::time::Instant;

use super::common::CONTACT_Z;
use super::common::{SolveError, SteadyError};
use super::numerics::TimeScheme;
use super::outcome::{Outcome, RunResult};
use crate::mesh::integrals::{contact_load, friction};
use crate::mesh::{FilmState, Grid, Scene};
use crate::model::asperity::ContactLaw;
use crate::model::case::CaseSpec;
use crate::model::friction::{Friction, FrictionModel};
use crate::solve::{FilmError, FilmMethod, FilmSolver, Method, Step};

/// Force-balanced steady state of an untextured contact.
#[derive(Clone, Debug)]
pub struct Steady {
    /// Ring position Z (µm) at which W_h + W_a = W_ps.
    pub z: f64,
    /// The film's and the asperities' loads there (docs/model.md §11).
    pub w_h: f64,
    pub w_a: f64,
    pub friction: Friction,
    /// Film solves used by the root find.
    pub film_solves: usize,
    /// Pressure and film content along x1 at the balance.
    pub x: Vec<f64>,
    pub p: Vec<f64>,
    pub theta: Vec<f64>,
    /// Nodes of the full film held above their cavity pressure (docs/model.md §3).
    pub pressurised: Vec<bool>,
}

/// Solves the untextured steady contact on `n1` cells along x1.
pub fn solve_untextured(case: &CaseSpec, n1: usize) -> Result<Steady, SteadyError> {
    let mut c = case.clone();
    c.texture = None;
    let contact = c.contact();
    let length = contact.length_cm;
    let scene = Scene::with_grid(contact, Grid::new(n1, 1, length, 1.0), case.u, case.flow);
    let g = &scene.grid;
    let phi_old = vec![0.0; g.nodes()];
    let step = Step {
        grid: g,
        gap: &scene.gap,
        phi_old: &phi_old,
        inv_dt: 0.0,
        boundary: case.film_boundary(),
        ring: None,
    };
    let mut solver = FilmSolver::new(Method::Direct);
    let mut state = FilmState::cavitated(g, &scene.gap, case.z0, case.d_oil);
    let mut solves = 0;
    let (mut w_h, mut w_a) = (0.0, 0.0);
    // Residual of the force balance at Z with the contact `law` (warm-started film solves).
    let mut excess = |z: f64, law: Option<&ContactLaw>| -> Result<f64, FilmError> {
        let mut zz = z;
        solves += 1;
        w_h = solver.solve(&step, &mut state, &mut zz)?.w_h;
        w_a = law.map_or(0.0, |l| contact_load(g, &scene.gap, z, l).0);
        Ok(w_h + w_a - case.w_ps)
    };
    // The film's balance first: where it leaves every gap under the ring beyond the
    // asperities' reach, W_a = 0 there and it is the balance with them too, found by the
    // same steps as without contact (the same bits). Else, or where the film alone cannot
    // carry the load, the balance with the asperities.
    let law = case.contact_law();
    let film_only = root(case, case.z0, &mut |z| excess(z, None));
    let min_base = scene.gap.ring_min_base(g);
    let z = match (film_only, law) {
        (Ok(z), Some(l)) if l.touches(min_base + z) => root(case, z, &mut |z| excess(z, Some(&l)))?,
        (Err(SteadyError::NoBracket { .. }), Some(l)) => {
            root(case, case.z0, &mut |z| excess(z, Some(&l)))?
        }
        (z, _) => z?,
    };
    // Final state exactly at the returned Z.
    excess(z, law.as_ref())?;
    if law.is_some() && z <= CONTACT_Z {
        return Err(SteadyError::Overloaded {
            z,
            w_a,
            w_ps: case.w_ps,
        });
    }
    let model = FrictionModel {
        u: case.u,
        theta_s: case.theta_s,
        w_ps: case.w_ps,
        contact: case.contact_law(),
    };
    let friction = friction(g, &scene.gap, z, &scene.hl, &state, &model);
    let theta = (0..g.nodes())
        .map(|k| state.theta(g, &scene.gap, z, k))
        .collect();
    let pressurised = (0..g.nodes())
        .map(|k| state.pressurised[k] && state.p[k] > step.boundary.cavity_pressure(k, g.n1))
        .collect();
    Ok(Steady {
        z,
        w_h,
        w_a,
        friction,
        film_solves: solves,
        x: (0..=g.n1).map(|i| g.x(i)).collect(),
        p: state.p.clone(),
        theta,
        pressurised,
    })
}

/// Z at the force balance whose excess load is `excess`, bracketed from `z_start`.
fn root(
    case: &CaseSpec,
    z_start: f64,
    excess: &mut dyn FnMut(f64) -> Result<f64, FilmError>,
) -> Result<f64, SteadyError> {
    let bracket = bracket(case, z_start, excess)?;
    Ok(balance(case.w_ps, bracket, excess)?)
}

/// A bracket (lo, hi, excess at lo, excess at hi) of the force balance: the load carried
/// decreases with Z, so it is expanded geometrically from `z_start` until the excess changes
/// sign.
fn bracket(
    case: &CaseSpec,
    z_start: f64,
    excess: &mut dyn FnMut(f64) -> Result<f64, FilmError>,
) -> Result<(f64, f64, f64, f64), SteadyError> {
    let (mut lo, mut hi) = (z_start, z_start);
    let mut flo = excess(lo)?;
    let mut fhi = flo;
    let mut expansions = 0;
    while flo < 0.0 || fhi > 0.0 {
        expansions += 1;
        if expansions > 60 || lo < 1e-4 || hi > 1e5 {
            return Err(SteadyError::NoBracket {
                lo,
                hi,
                w_lo: flo + case.w_ps,
                w_hi: fhi + case.w_ps,
                w_ps: case.w_ps,
                hint: if case.contact.is_some() && flo < 0.0 {
                    "the asperities cannot carry it either: the load is beyond what ring face and liner can bear"
                } else if case.r.is_infinite() {
                    "a flat ring on a plain liner has no converging wedge to build pressure"
                } else if case.r > 1e4 {
                    "a ring this flat builds too little pressure to carry the load"
                } else {
                    "the inlet oil film (d_oil) may be too thin to carry the load"
                },
            });
        }
        if flo < 0.0 {
            hi = lo;
            fhi = flo;
            lo /= 1.5;
            flo = excess(lo)?;
        } else {
            lo = hi;
            flo = fhi;
            hi *= 1.5;
            fhi = excess(hi)?;
        }
    }
    Ok((lo, hi, flo, fhi))
}

/// Z at the force balance within `bracket` (see [`bracket`]), load `w_ps`: Illinois false
/// position in ln Z (W_h ≈ power law in Z, so this converges superlinearly).
fn balance(
    w_ps: f64,
    (lo, hi, flo, fhi): (f64, f64, f64, f64),
    excess: &mut dyn FnMut(f64) -> Result<f64, FilmError>,
) -> Result<f64, FilmError> {
    let (mut a, mut b) = (lo.ln(), hi.ln());
    let (mut fa, mut fb) = (flo, fhi);
    let mut side = 0;
    let mut z = lo;
    for _ in 0..200 {
        let c = if fa == fb {
            0.5 * (a + b)
        } else {
            b - fb * (b - a) / (fb - fa)
        };
        z = c.exp();
        let fc = excess(z)?;
        if fc == 0.0 || (b - a).abs() < 1e-13 || fc.abs() < 1e-13 * w_ps {
            break;
        }
        if (fc > 0.0) == (fa > 0.0) {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    Ok(z)
}

/// The steady untextured outcome in the common form.
pub fn steady_outcome(case: &CaseSpec, n1: usize) -> Result<RunResult, SolveError> {
    let start = Instant::now();
    let s = solve_untextured(case, n1).map_err(|source| SolveError::Steady {
        case: case.label(),
        source,
    })?;
    let c_min = case.contact().clearance_um(s.z);
    let outcome = Outcome {
        f_mean: s.friction.total(),
        f_couette: s.friction.couette,
        f_poiseuille: s.friction.poiseuille,
        f_pressure: s.friction.pressure,
        f_boundary: s.friction.boundary,
        asperity_share: s.w_a / case.w_ps,
        z_mean: s.z,
        z_min: s.z,
        z_max: s.z,
        c_min,
        periods: 0,
        steps: 0,
        converged: true,
        periodic_error: 0.0,
        method: "steady-1d".into(),
        dt: 0.0,
        t_end: 0.0,
        iterations_per_step: 0.0,
        max_residual: 0.0,
        wall_time_s: start.elapsed().as_secs_f64(),
        approach_steps: 0,
        scheme: TimeScheme::BackwardEuler,
        deep_mesh: None,
        deep_unsettled: false,
        mesh_uncertainty: None,
    };
    Ok(RunResult {
        outcome,
        series: None,
        extra: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_plain_ring_is_refused_with_its_reason() {
        // Parallel surfaces build no steady pressure: without asperity contact no Z balances
        // the load, and the error says why instead of guessing at the inlet.
        let film_only = CaseSpec {
            contact: None,
            ..CaseSpec::paper(f64::INFINITY)
        };
        match solve_untextured(&film_only, 128) {
            Err(SteadyError::NoBracket {
                hint, w_hi, w_ps, ..
            }) => {
                assert!(hint.contains("flat ring"), "{hint}");
                assert!(w_hi < 1e-2 * w_ps, "load {w_hi} against {w_ps}");
            }
            other => panic!("expected no force balance, got {other:?}"),
        }
        assert!(solve_untextured(&CaseSpec::paper(0.8), 128).is_ok());
        // With the asperities (docs/model.md §11) it rides on them: they carry the load.
        let s = solve_untextured(&CaseSpec::paper(f64::INFINITY), 128).unwrap();
        let w_ps = CaseSpec::paper(0.8).w_ps;
        assert!(s.w_h < 2e-3 * w_ps, "W_h = {}", s.w_h);
        assert!(
            (s.w_h + s.w_a - w_ps).abs() < 1e-12 * w_ps,
            "W_a = {}",
            s.w_a
        );
        assert!(s.z < 4.0 * 0.3 && s.friction.boundary > 0.0, "{s:?}");
    }
}
