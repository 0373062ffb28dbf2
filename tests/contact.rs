//! Asperity contact in the ring's balance and the friction (docs/model.md §11): where the film
//! stays beyond 4σ it changes nothing, to the bit; where it is thinner the asperities carry
//! load, the steady and transient balances agree, and the implicit ring update stays cheap.

mod common;

use common::{rel, texopt};
use texopt::model::case::{CaseSpec, Texture};
use texopt::model::operating::Operating;
use texopt::time::{
    resolve, simulate, simulate_with, solve_untextured, Fidelity, Numerics, Outcome, Overrides,
    RunOptions, Start, Transient, Watch,
};

/// The outcome without its wall time (the one field that differs between equal runs).
fn timeless(o: &Outcome) -> Outcome {
    Outcome {
        wall_time_s: 0.0,
        ..o.clone()
    }
}

/// The paper's plain liner at ring radius `r` under `load` N/m (its other inputs the paper's).
fn loaded(r: f64, load: f64) -> CaseSpec {
    let mut c = CaseSpec::paper(r);
    Operating {
        load_n_per_m: load,
        ..Operating::paper()
    }
    .apply(&mut c);
    c
}

#[test]
fn a_film_beyond_four_sigma_is_the_same_with_and_without_contact_to_the_bit() {
    // Case I (C_min ≈ 6.3 µm = 21σ) as a transient, and the plain liner at R = 0.8 under
    // 400 N/m (C_min 1.45 µm = 4.8σ; its root find passes Z = 1.1 µm = 3.7σ on the way) as
    // the steady balance.
    let case_i = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let plain = loaded(0.8, 400.0);
    for case in [case_i, plain] {
        assert!(case.contact.is_some(), "contact is on by default");
        let num = resolve(Fidelity::Fast, &Overrides::default(), &case);
        let opts = RunOptions {
            series: case.texture.is_some(),
            ..RunOptions::default()
        };
        let on = simulate_with(&case, &num, &opts, &mut Watch::default()).unwrap();
        let off_case = CaseSpec {
            contact: None,
            ..case.clone()
        };
        let off = simulate_with(&off_case, &num, &opts, &mut Watch::default()).unwrap();
        assert_eq!(
            timeless(&on.outcome),
            timeless(&off.outcome),
            "{}",
            case.label()
        );
        assert_eq!(on.outcome.f_boundary, 0.0);
        assert_eq!(on.outcome.asperity_share, 0.0);
        assert_eq!(on.series, off.series);
        if let Some(rows) = &on.series {
            assert!(rows.iter().all(|r| r.w_a == 0.0 && r.f_boundary == 0.0));
        }
    }
}

#[test]
fn heavy_loads_rest_on_the_asperities_and_the_transient_settles_there() {
    let mut share = 0.0;
    for load in [1000.0, 2000.0, 4000.0] {
        let case = loaded(0.8, load);
        let s = solve_untextured(&case, 700).unwrap();
        // The steady balance W_h + W_a = W_ps to round-off of the root find.
        let imbalance = (s.w_h + s.w_a - case.w_ps).abs() / case.w_ps;
        assert!(imbalance < 1e-12, "W = {load}: imbalance {imbalance:e}");
        let now = s.w_a / case.w_ps;
        println!(
            "W = {load} N/m: Z = {:.4} µm, W_a/W_ps = {now:.4e}, f_b = {:.4e}",
            s.z, s.friction.boundary
        );
        assert!(
            now > share,
            "W = {load}: asperity share {now} after {share}"
        );
        assert!(s.friction.boundary > 0.0);
        share = now;
    }
    // The 2D transient of the heaviest, from the paper's start (Z = 2.5 µm, falling), to the
    // steady answer.
    let case = loaded(0.8, 4000.0);
    let steady = solve_untextured(&case, 700).unwrap();
    let num = Numerics {
        start: Start::Paper,
        ..resolve(Fidelity::Fast, &Overrides::default(), &case)
    };
    let opts = RunOptions {
        transient: true,
        ..RunOptions::default()
    };
    let o = simulate_with(&case, &num, &opts, &mut Watch::default())
        .unwrap()
        .outcome;
    println!(
        "transient: {o:?}\nsteady: Z = {}, {:?}",
        steady.z, steady.friction
    );
    assert!(o.converged && o.method == "transient-2d");
    // Within the 0.2 % tests/consistency.rs allows the 2D transient against the 1D balance.
    assert!(
        rel(o.z_mean, steady.z) < 2e-3,
        "Z {} vs {}",
        o.z_mean,
        steady.z
    );
    assert!(rel(o.f_mean, steady.friction.total()) < 2e-3);
    assert!(rel(o.asperity_share, steady.w_a / case.w_ps) < 2e-3);
    assert!(rel(o.f_boundary, steady.friction.boundary) < 2e-3);
}

#[test]
fn the_implicit_ring_update_converges_where_the_asperities_carry_the_load() {
    // A flat ring has no wedge: at 1000 N/m the asperities carry all but 1e-4 of its load.
    // A ring a hundred times lighter than the paper's (0.48 g/m: little inertia against the
    // asperities' stiffness, κ·dW_a/dZ large), dropped at rest from Z = 0.25 µm (λ = 0.83,
    // pushed back up) onto its balance. Measured: 5.7 iterations a step, at most 13; with
    // dW_a/dZ left out of the ring's update the step does not converge.
    let case = CaseSpec {
        z0: 0.25,
        mass: 2e-11,
        ..loaded(f64::INFINITY, 1000.0)
    };
    let steady = solve_untextured(&case, 700).unwrap();
    assert!(steady.w_a > 0.99 * case.w_ps, "{}", steady.w_a / case.w_ps);
    let num = Numerics {
        start: Start::Paper,
        ..resolve(Fidelity::Fast, &Overrides::default(), &case)
    };
    let mut t = Transient::new(&case, &num);
    // The first step moves the laid film's cavitation fronts into place, about a node an
    // iteration (docs/solver.md), whatever the ring does: the steps after it are the ring's.
    t.step().unwrap();
    let (mut most, mut total, mut share) = (0, 0, 0.0);
    let steps = 400;
    for _ in 0..steps {
        t.step().unwrap();
        let it = t.last().iterations;
        most = most.max(it);
        total += it;
        share += t.last().w_a / case.w_ps / steps as f64;
        assert!(t.ring_state().z.is_finite() && t.ring_state().z > 0.0);
    }
    let mean = total as f64 / steps as f64;
    println!(
        "Z = {} (steady {}), mean W_a/W_ps = {share}, iterations: most {most}, mean {mean}",
        t.ring_state().z,
        steady.z,
    );
    assert!(share > 0.9, "the asperities carried {share} of the load");
    assert!(most <= 20, "{most} iterations in one step");
    assert!(mean < 8.0, "{mean} iterations a step");
}

#[test]
fn a_load_beyond_the_asperities_is_a_named_error() {
    // A flat ring under 20 kN/m: more than the asperities bear at contact (K·E*·F_{5/2}(0)
    // over the ring's 0.8 mm, ≈ 9.8 kN/m).
    let case = loaded(f64::INFINITY, 20000.0);
    let e = solve_untextured(&case, 256).unwrap_err().to_string();
    assert!(e.contains("asperities"), "{e}");
    let num = Numerics {
        start: Start::Paper,
        ..resolve(Fidelity::Draft, &Overrides::default(), &case)
    };
    let opts = RunOptions {
        transient: true,
        ..RunOptions::default()
    };
    let e = simulate_with(&case, &num, &opts, &mut Watch::default())
        .map(|r| r.outcome)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("reached the liner") && e.contains("asperities"),
        "{e}"
    );
    // And the steady run (`simulate`'s default for a plain liner) names it too.
    let e = simulate(&case, &num).unwrap_err().to_string();
    assert!(e.contains("asperities"), "{e}");
}

#[test]
fn absurd_contact_constants_are_refused_naming_the_flag() {
    for (flag, value) in [
        ("--e-star", "2e6"),
        ("--e-star", "0"),
        ("--eta-beta-sigma", "7"),
        ("--sigma-over-beta", "nan"),
        ("--tau0", "-1"),
        ("--varsigma", "3"),
    ] {
        let (code, out, err) = texopt(&["simulate", "--R", "0.8", flag, value]);
        assert_eq!(code, 2, "{flag} {value}: {out}{err}");
        assert!(out.is_empty(), "{out}");
        let line = err.trim();
        assert!(!line.contains('\n') && line.contains(flag), "{line}");
        assert!(!line.contains("panicked"), "{line}");
    }
    let (code, out, err) = texopt(&["simulate", "--R", "0.8", "--e-star", "2e6"]);
    assert_eq!(code, 2);
    assert!(err.contains("1 to 1000 GPa"), "{out}{err}");
    // The defaults and --no-contact run; the summary says the regime.
    let (code, out, _) = texopt(&["simulate", "--R", "0.8", "--load", "3000"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("boundary") && out.contains("asperities carry"),
        "{out}"
    );
    let (code, out, _) = texopt(&["simulate", "--R", "0.8", "--no-contact", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["contact"], false);
    assert_eq!(v["regime"], "hydrodynamic");
}
