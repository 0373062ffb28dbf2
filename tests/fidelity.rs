//! The errors the reports weigh gains against (`Fidelity::f_error`, `c_error`: "no texture
//! beats the plain liner by more than the tier's error") are the ones the committed speed
//! study measured: for each tier, the larger of Case I and Case III in results/speed.csv,
//! rounded up by less than 1e-4. Rerunning the study against another reference, or changing a
//! tier's mesh, step or tolerance, fails this test until the constants follow.

use texopt::case::Fidelity;

/// One row of results/speed.csv: a setting of one case and its errors against the reference.
#[derive(serde::Deserialize)]
struct Row {
    case: String,
    setting: String,
    n1: usize,
    n2: usize,
    dt: f64,
    periodic_tol: f64,
    solver: String,
    err_f: f64,
    err_c: f64,
}

#[test]
fn tier_errors_are_the_speed_studys() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/results/speed.csv");
    let rows: Vec<Row> = csv::Reader::from_path(path)
        .expect("results/speed.csv")
        .deserialize()
        .collect::<Result<_, _>>()
        .expect("rows of results/speed.csv");
    for tier in Fidelity::ALL {
        let t = tier.numerics();
        let approach = t
            .approach_n2
            .map_or(String::new(), |a| format!(" approach N2={a}"));
        let of_tier: Vec<&Row> = rows
            .iter()
            .filter(|r| {
                (r.n1, r.n2, r.solver.as_str()) == (t.n1, t.n2, t.solver.name())
                    && (r.dt / t.dt - 1.0).abs() < 1e-9
                    && (r.periodic_tol / t.periodic_tol - 1.0).abs() < 1e-9
                    && r.setting
                        .ends_with(&format!("{}{approach}", t.solver.name()))
            })
            .collect();
        let cases: Vec<&str> = of_tier.iter().map(|r| r.case.as_str()).collect();
        assert!(
            cases.contains(&"case-I") && cases.contains(&"case-III"),
            "{}: results/speed.csv has no row of the tier for both cases (found {cases:?})",
            tier.name()
        );
        let worst = |e: fn(&Row) -> f64| of_tier.iter().map(|r| e(r)).fold(0.0f64, f64::max);
        for (what, measured, constant) in [
            ("f̄", worst(|r| r.err_f), tier.f_error()),
            ("C_min", worst(|r| r.err_c), tier.c_error()),
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
