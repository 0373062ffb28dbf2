//! Against the published study (docs/model.md §8): the untextured force balance for all ten ring
//! radii, and the paper's Case I at its own fidelity.

use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, solve_untextured, Numerics};

const RADII: [f64; 10] = [0.2, 0.4, 0.8, 1.6, 3.2, 6.4, 12.8, 25.6, 51.2, 102.4];

#[test]
fn untextured_force_balance_matches_reference_table() {
    // docs/model.md §8, rows "N = 512" and "N = 2048" (an independent implementation).
    let z512 = [
        4.031, 5.620, 6.396, 6.301, 5.689, 4.882, 4.065, 3.323, 2.687, 2.157,
    ];
    let f512 = [
        0.0803, 0.0744, 0.0758, 0.0847, 0.1019, 0.1287, 0.1669, 0.2220, 0.2924, 0.3673,
    ];
    let z2048 = [
        3.950, 5.559, 6.355, 6.274, 5.672, 4.870, 4.056, 3.317, 2.682, 2.153,
    ];
    let f2048 = [
        0.0809, 0.0749, 0.0760, 0.0850, 0.1022, 0.1287, 0.1671, 0.2224, 0.2926, 0.3675,
    ];
    for (k, &r) in RADII.iter().enumerate() {
        for (n, z_ref, f_ref) in [(512, z512[k], f512[k]), (2048, z2048[k], f2048[k])] {
            let s = solve_untextured(&CaseSpec::paper(r), n).unwrap();
            let (dz, df) = (s.z / z_ref - 1.0, s.friction.total() / f_ref - 1.0);
            println!(
                "R = {r:6}, N = {n}: Z {:.4} ({:+.3} %), f {:.5} ({:+.3} %)",
                s.z,
                100.0 * dz,
                s.friction.total(),
                100.0 * df
            );
            assert!(dz.abs() < 0.005, "Z at R = {r}, N = {n}");
            assert!(df.abs() < 0.01, "f at R = {r}, N = {n}");
        }
    }
}

#[test]
fn case_one_matches_the_paper() {
    // Paper §3.5, Case I: l1 = l2 = 0.01, per = 0.06, depth 5, R = 0.8 at 512×32, dt = 4e-4,
    // from Z = 2.5, Z' = 0. The paper prints f/10 = 0.00763 (docs/model.md §5) and Z ≈ 6.25.
    let case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let out = simulate(&case, &Numerics::default()).unwrap().outcome;
    println!("{out:#?}");
    assert!(out.converged);
    assert!(
        (out.f_mean / 0.0763 - 1.0).abs() < 0.02,
        "f = {}",
        out.f_mean
    );
    assert!((out.z_mean / 6.25 - 1.0).abs() < 0.02, "Z = {}", out.z_mean);
    // The paper's finding for Case I: the texture raises friction over the untextured ring.
    let smooth = solve_untextured(&CaseSpec::paper(0.8), 512).unwrap();
    assert!(out.f_mean > smooth.friction.total());
    assert!(out.c_min < smooth.z);
}
