//! The film's time schemes on the conformal ring (R = 51.2, Case I's pocket), where the time
//! step sets most of the error: backward Euler converges at first order, BDF2 at second order
//! or better once the texture moves less than half a cell a step, and far closer to the limit
//! at every step tried; the characteristic scheme, whose step follows the mesh, at first order
//! in the mesh.

mod common;

use common::rel;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, Approach, Fidelity, Numerics, Outcome, TimeScheme};

fn run(scheme: TimeScheme, dt: f64) -> Outcome {
    let case = CaseSpec::paper(51.2).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let num = Numerics {
        n1: 256,
        n2: 8,
        dt,
        scheme,
        periodic_tol: 1e-8,
        ..Numerics::default()
    };
    let o = simulate(&case, &num).unwrap().outcome;
    assert!(o.converged, "{o:?}");
    o
}

/// Observed order from the errors at dt and dt/2 against a run at dt/8.
fn order(coarse: f64, fine: f64, limit: f64) -> f64 {
    (rel(coarse, limit) / rel(fine, limit)).log2()
}

#[test]
fn bdf2_converges_at_second_order_where_backward_euler_is_first() {
    // Courant numbers u·dt/Δx1 = 0.5, 0.26 and 0.064 on 256 cells along x1. Measured (f̄,
    // C_min): BDF2 orders 5.9 and 3.6 between 4e-4 and 2e-4 (the error in f̄ falls from
    // 0.6 % to 1e-5), backward Euler 1.25 and 1.27 (against its own run at 5e-5, itself
    // first-order off).
    let runs = |scheme| [run(scheme, 4e-4), run(scheme, 2e-4), run(scheme, 5e-5)];
    let (bdf2, be) = (runs(TimeScheme::Bdf2), runs(TimeScheme::BackwardEuler));
    for (scheme, [a, b, limit], lo, hi) in
        [("BDF2", &bdf2, 1.8, f64::INFINITY), ("BE", &be, 0.7, 1.5)]
    {
        for (what, x, y, l) in [
            ("f", a.f_mean, b.f_mean, limit.f_mean),
            ("C_min", a.c_min, b.c_min, limit.c_min),
        ] {
            let p = order(x, y, l);
            println!(
                "{scheme} {what}: observed order {p:.2} ({x} at 4e-4, {y} at 2e-4, {l} at 5e-5)"
            );
            assert!(p >= lo && p <= hi, "{scheme} {what}: order {p}");
        }
    }
    // At the tiers' step BDF2 is far the nearer to the limit.
    let limit = &bdf2[2];
    assert!(rel(bdf2[0].f_mean, limit.f_mean) * 3.0 < rel(be[0].f_mean, limit.f_mean));
    assert!(rel(bdf2[0].c_min, limit.c_min) * 3.0 < rel(be[0].c_min, limit.c_min));
}

#[test]
fn a_bdf2_run_that_does_not_settle_finishes_with_backward_euler() {
    // Small dense pockets at a Courant number near 1: BDF2 settles into a slow spurious
    // oscillation (time/fallback.rs, `BDF2_PATIENCE`); after that many windows the run goes on
    // with backward Euler and reaches the periodic regime backward Euler reaches alone.
    let case = CaseSpec::paper(1.6).with_texture(Texture::circular(0.005, 0.01, 10.0));
    let run = |scheme| {
        // The ring-frame numerics this was measured with: 384×8 at dt = 5.4e-4 (Courant
        // number 0.96), after 128×4 at 1.6e-3.
        let num = Numerics {
            n1: 384,
            dt: 5.4e-4,
            scheme,
            periodic_tol: 1e-5,
            approach: Some(Approach {
                n1: 128,
                n2: 4,
                dt: 1.6e-3,
            }),
            ..Fidelity::Draft.numerics_for(&case)
        };
        simulate(&case, &num).unwrap().outcome
    };
    let (bdf2, be) = (run(TimeScheme::Bdf2), run(TimeScheme::BackwardEuler));
    assert!(bdf2.converged && be.converged);
    assert_eq!(bdf2.scheme, TimeScheme::BackwardEuler, "no fall-back");
    assert!(bdf2.periods > be.periods);
    for (what, a, b) in [
        ("f", bdf2.f_mean, be.f_mean),
        ("C_min", bdf2.c_min, be.c_min),
    ] {
        assert!(rel(a, b) < 3e-5, "{what}: {a} after the fall-back vs {b}");
    }
}

#[test]
fn the_characteristic_scheme_converges_at_first_order_in_the_mesh() {
    // N1 = 256, 512, 1024 at the characteristic step 2·dx1/u each (the film content moves a
    // cell a step). Measured (f̄, C_min): successive changes in the ratio 2.62 and 2.58 (an
    // observed order ≈ 1.4; their extrapolation is within 0.2 % of the reference).
    let case = CaseSpec::paper(51.2).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let run = |n1: usize| {
        let mut num = Numerics {
            n1,
            n2: 8,
            scheme: TimeScheme::Characteristic,
            periodic_tol: 1e-8,
            ..Numerics::default()
        };
        num.fit_characteristic_step(&case);
        let o = simulate(&case, &num).unwrap().outcome;
        assert!(o.converged, "{o:?}");
        o
    };
    let [a, b, c] = [run(256), run(512), run(1024)];
    for (what, x, y, z) in [
        ("f", a.f_mean, b.f_mean, c.f_mean),
        ("C_min", a.c_min, b.c_min, c.c_min),
    ] {
        let ratio = (x - y) / (y - z);
        println!("characteristic {what}: {x}, {y}, {z} on 256, 512, 1024 cells: ratio {ratio:.2}");
        assert!((1.5..=3.0).contains(&ratio), "{what}: ratio {ratio}");
    }
}
