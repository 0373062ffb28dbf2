//! The errors the reports weigh gains against (`Fidelity::f_error`, `c_error`: "no texture
//! beats the plain liner by more than the tier's error") are each tier's measured errors:
//! the larger of Case I and Case III against their converged references, rounded up by less
//! than 1e-4. The tiers are run here; the references are embedded with their source.
//! Changing a tier's mesh, step or tolerance fails this test until the constants follow.

mod common;

use common::{case_one, case_three, rel};
use texopt::model::case::CaseSpec;
use texopt::time::{simulate, Fidelity};

/// The 2048×128, dt = 1e-4 references (periodic tolerance 1e-5, from the untextured
/// balance): f̄ and C_min (µm). Case I: results/convergence/run_2048x128.json; Case III:
/// results/speed/finer.jsonl (both `texopt-lab` runs, docs/validation.md).
const REFERENCES: [(&str, f64, f64); 2] = [
    ("case-I", 0.07746503114315603, 6.130009850477485),
    ("case-III", 0.08667616001054197, 3.8606887479404635),
];

fn case(name: &str) -> CaseSpec {
    match name {
        "case-I" => case_one(),
        _ => case_three(),
    }
}

#[test]
fn tier_errors_are_the_measured_ones() {
    for tier in Fidelity::ALL {
        let (mut worst_f, mut worst_c) = (0.0f64, 0.0f64);
        for (name, f_ref, c_ref) in REFERENCES {
            let c = case(name);
            let o = simulate(&c, &tier.numerics_for(&c)).unwrap().outcome;
            worst_f = worst_f.max(rel(o.f_mean, f_ref));
            worst_c = worst_c.max(rel(o.c_min, c_ref));
        }
        for (what, measured, constant) in [
            ("f̄", worst_f, tier.f_error()),
            ("C_min", worst_c, tier.c_error()),
        ] {
            println!(
                "{}: {what} error measured {measured:.5}, used {constant:.4}",
                tier.name()
            );
            assert!(
                constant >= measured && constant < measured + 1e-4,
                "{}: the {what} error used ({constant}) is not the measured {measured} rounded up",
                tier.name()
            );
        }
    }
}
