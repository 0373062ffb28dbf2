//! Consistency between solver paths: 2D transient vs 1D steady for an untextured liner,
//! independence of N2 for an untextured liner, independence of the texture's initial phase.

mod common;

use common::rel;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{solve_untextured, Numerics, SolveError, Transient, Watch, CONTACT_Z};

#[test]
fn untextured_transient_settles_to_the_steady_1d_balance_for_any_n2() {
    let case = CaseSpec::paper(0.8);
    let steady = solve_untextured(&case, 512).unwrap();
    let mut results = Vec::new();
    for n2 in [1, 3] {
        let num = Numerics {
            n1: 512,
            n2,
            periodic_tol: 1e-7,
            ..Numerics::default()
        };
        let out = Transient::new(&case, &num)
            .run_to_periodic(&num, false, &mut Watch::default())
            .unwrap()
            .outcome;
        assert!(out.converged);
        println!(
            "N2 = {n2}: Z {} f {} (steady {} {})",
            out.z_mean,
            out.f_mean,
            steady.z,
            steady.friction.total()
        );
        assert!(rel(out.z_mean, steady.z) < 0.002);
        assert!(rel(out.f_mean, steady.friction.total()) < 0.002);
        results.push(out);
    }
    assert!(rel(results[0].z_mean, results[1].z_mean) < 1e-9);
    assert!(rel(results[0].f_mean, results[1].f_mean) < 1e-9);
}

#[test]
fn periodic_outcomes_do_not_depend_on_the_initial_phase() {
    let num = Numerics {
        n1: 256,
        n2: 16,
        ..Numerics::default()
    };
    let run = |phase: f64| {
        let mut t = Texture::circular(0.01, 0.06, 5.0);
        t.phase = phase;
        let case = CaseSpec::paper(0.8).with_texture(t);
        let out = Transient::new(&case, &num)
            .run_to_periodic(&num, false, &mut Watch::default())
            .unwrap()
            .outcome;
        assert!(out.converged);
        out
    };
    let a = run(0.0);
    let b = run(0.06 / 3.0);
    let c = run(0.5 * 0.06 + 0.1);
    for o in [&b, &c] {
        println!(
            "f {} vs {}, c_min {} vs {}, Z {} vs {}",
            o.f_mean, a.f_mean, o.c_min, a.c_min, o.z_mean, a.z_mean
        );
        assert!(rel(o.f_mean, a.f_mean) < 0.005);
        assert!(rel(o.z_mean, a.z_mean) < 0.005);
        assert!(rel(o.c_min, a.c_min) < 0.005);
        assert!(rel(o.z_max, a.z_max) < 0.005);
    }
}

#[test]
fn a_ring_pushed_into_the_liner_fails_loudly_naming_the_case() {
    // A load 10⁴ times the paper's cannot be carried: the ring must reach the liner, and the
    // run must say so (never return outcomes).
    let mut case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
    case.w_ps *= 1e4;
    let num = Numerics {
        n1: 64,
        n2: 4,
        ..Numerics::default()
    };
    let err = Transient::new(&case, &num)
        .run_to_periodic(&num, false, &mut Watch::default())
        .unwrap_err();
    let msg = err.to_string();
    println!("{msg}");
    // Contact, found as the ring falls (Z ≤ 1 nm), not a run that creeps towards Z = 0 to
    // t_max (the film iteration at most halves the gap, so Z ≤ 0 is never reached).
    match err {
        SolveError::Contact { t, z, .. } => {
            assert!(z <= CONTACT_Z && t < 1.0, "Z = {z} at t = {t}")
        }
        other => panic!("not contact: {other}"),
    }
    assert!(msg.contains("R=0.8 l1=0.01"), "{msg}");
    assert!(msg.contains("t = "), "{msg}");
}
