//! Methods that fail on purpose: each failure must be detected and reported as an
//! error naming the case, the time and the quantity — never returned as a number.
//!
//! - Plain Gauss–Seidel on the p–θ unknowns solves the same discrete problem as the direct
//!   solver (it agrees on a coarse mesh) but its sweeps per step grow as N², so on a fine mesh
//!   it exhausts its sweep budget: a film-solve error.
//! - The Reynolds cut-off (p ≥ 0, full film, equation dropped where p = 0) does not conserve
//!   mass; the run's mass guard refuses it, and with the guard off its answer is far from
//!   the Elrod–Adams one (the paper's ref. [7]).

use texopt::model::case::{CaseSpec, Texture};
use texopt::solve::FilmError;
use texopt::time::{Numerics, SolveError, Transient, Watch, MASS_TOL};
use texopt_lab::solvers::{cutoff_transient, Solver};

fn case_one() -> CaseSpec {
    CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0))
}

fn mesh(n1: usize, n2: usize) -> Numerics {
    Numerics {
        n1,
        n2,
        dt: 4e-4,
        periodic_tol: 1e-4,
        t_max: 3.0,
        ..Numerics::default()
    }
}

#[test]
fn gauss_seidel_agrees_on_a_coarse_mesh_and_fails_loudly_on_a_fine_one() {
    let case = case_one();
    // Coarse: the same discrete problem, so the same answer step by step.
    let steps = |m: Solver| {
        let mut tr = m.transient(&case, &mesh(64, 4));
        let mut zs = Vec::new();
        for _ in 0..8 {
            tr.step().unwrap();
            zs.push(tr.ring_state().z);
        }
        (
            zs,
            tr.friction().total(),
            tr.last().iterations,
            tr.stats().max_mass_defect,
        )
    };
    let (z_direct, f_direct, it_direct, _) = steps(Solver::Direct);
    let (z_gs, f_gs, sweeps, defect_gs) = steps(Solver::GaussSeidel);
    for (a, b) in z_direct.iter().zip(&z_gs) {
        assert!(
            (a - b).abs() <= 1e-7 * a,
            "Z: direct {a} vs Gauss–Seidel {b}"
        );
    }
    assert!((f_direct - f_gs).abs() <= 1e-7 * f_direct);
    assert!(defect_gs <= MASS_TOL);
    // ... at a price: thousands of sweeps where the direct solver takes a few iterations.
    assert!(sweeps > 100 * it_direct, "{sweeps} sweeps vs {it_direct}");

    // Fine: the sweep budget runs out on the first step, an error naming case, time, cause.
    let mut tr = Solver::GaussSeidel.transient(&case, &mesh(256, 16));
    let err = tr.step().unwrap_err();
    match &err {
        SolveError::Film {
            case: label,
            t,
            source: FilmError::Other(why),
        } => {
            assert!(label.contains("R=0.8") && label.contains("depth=5"));
            assert!(*t > 0.0);
            assert!(why.contains("did not converge in 20000 sweeps"), "{why}");
        }
        other => panic!("expected exhausted sweeps, got {other:?}"),
    }
}

#[test]
fn the_reynolds_cutoff_is_refused_for_losing_mass_and_is_far_off_when_allowed() {
    let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
    let ea = mesh(128, 8);
    // Guarded (the default): an error within the first steps, naming the cause.
    let mut tr = cutoff_transient(&case, &ea);
    let err = (0..10).try_for_each(|_| tr.step()).unwrap_err();
    match &err {
        SolveError::MassNotConserved { defect, tol, t, .. } => {
            assert!(*defect > 0.1 && defect > tol, "defect {defect}");
            assert!(*t < 10.0 * 4e-4 + 1e-12);
        }
        other => panic!("expected a mass-conservation error, got {other:?}"),
    }
    assert!(err.to_string().contains("mass not conserved"));

    // Elrod–Adams conserves mass to round-off on the same case.
    let mut good = Transient::new(&case, &ea);
    let elrod = good
        .run_to_periodic(&ea, false, &mut Watch::default())
        .unwrap()
        .outcome;
    assert!(
        good.stats().max_mass_defect < 1e-10,
        "{}",
        good.stats().max_mass_defect
    );

    // Guard off: the cut-off runs, loses (here: creates) about the whole throughflow per
    // step, and its clearance is far from the mass-conserving one.
    let mut off = cutoff_transient(&case, &ea);
    off.set_mass_tolerance(f64::INFINITY);
    let wrong = off
        .run_to_periodic(&ea, false, &mut Watch::default())
        .unwrap()
        .outcome;
    assert!(off.stats().max_mass_defect > 0.5);
    let dc = (wrong.c_min - elrod.c_min) / elrod.c_min;
    assert!(dc.abs() > 0.1, "C_min {} vs {}", wrong.c_min, elrod.c_min);
}
