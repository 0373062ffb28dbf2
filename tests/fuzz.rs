//! Property test over geometry and operating inputs: the solver never panics; it returns
//! finite outcomes or a typed error (input refused, film solve failed, contact, no periodic
//! regime within the time allowed).

use proptest::prelude::*;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, Numerics};

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
    #[test]
    fn never_panics_finite_or_typed_error(
        r in prop_oneof![0.05f64..200.0, Just(f64::INFINITY)],
        l1 in 0.002f64..0.05,
        l2 in 0.002f64..0.05,
        gap1 in 0.0f64..2.0,
        gap2 in 0.0f64..2.0,
        depth in 0.5f64..60.0,
        d_oil in 0.5f64..60.0,
        e in 5.0f64..2000.0,
        mass in 2e-10f64..2e-7,
        textured in any::<bool>(),
    ) {
        let mut case = CaseSpec::paper(r);
        case.d_oil = d_oil;
        case.e = e;
        case.mass = mass;
        if textured {
            let (per, width) = (2.0 * l1 * (1.0 + gap1), 2.0 * l2 * (1.0 + gap2));
            case.texture = Some(Texture { l1, l2, per, width, depth, phase: 0.0 });
        }
        // A coarse mesh that still resolves the pocket (≥ 2 cells along, 4 across).
        let n1 = (0.2 / l1.min(0.05)).ceil().max(48.0) as usize;
        let mut num = Numerics { n1, n2: 2, dt: 2e-3, t_max: 0.3, periodic_tol: 1e-3, ..Numerics::default() };
        num.resolve_pockets(&case, texopt::time::POCKET_CELLS);
        num.fit_step_to_period(&case);
        if let Err(e) = case.validate(true) {
            // Refused with a typed InputError before any simulation (a ring radius below
            // half the ring width).
            prop_assert!(e.param == "--R", "{e}");
            return Ok(());
        }
        prop_assert!(num.validate(&case).is_ok(), "{:?}", num.validate(&case));
        let res = simulate(&case, &num);
        match res {
            Ok(r) => {
                let o = r.outcome;
                for v in [o.f_mean, o.z_mean, o.z_min, o.z_max, o.c_min] {
                    prop_assert!(v.is_finite(), "{}: non-finite outcome {o:?}", case.label());
                }
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
