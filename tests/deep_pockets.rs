//! Pockets far deeper than the film (depth > 6·C_min): `fast` goes on from its periodic state
//! on the deep-pocket mesh (docs/solver.md, "Deep pockets"), and what it reports is that
//! mesh's own periodic regime, the same as a run on that mesh from the coarse approach.

mod common;

use common::rel;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, Fidelity, Numerics};

#[test]
fn the_deep_pocket_answer_is_the_deep_mesh_s_periodic_regime() {
    let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 20.0));
    let num = Fidelity::Fast.numerics_for(&case);
    let via = simulate(&case, &num).unwrap().outcome;
    assert_eq!(via.deep_mesh, Some((600, 24)));
    assert!(rel(via.dt, 2.0 * 0.2 / 600.0) < 1e-12, "{}", via.dt);
    // The deep-pocket mesh on its own, after the same coarse approach.
    let deep = num
        .deep_numerics(&case)
        .expect("fast resolves deep pockets");
    let own = Numerics {
        approach: num.approach,
        ..deep
    };
    let direct = simulate(&case, &own).unwrap().outcome;
    assert_eq!(direct.deep_mesh, None);
    let tol = 2.0 * num.periodic_tol;
    for (what, a, b) in [
        ("f̄", via.f_mean, direct.f_mean),
        ("C_min", via.c_min, direct.c_min),
    ] {
        println!("{what}: after 700x8 {a:.6}, from the approach {b:.6}");
        assert!(rel(a, b) < tol, "{what}: {a} against {b}");
    }
    // The 700x8 part counts in the steps and periods, and in the steps before the mesh.
    assert!(via.approach_steps > 0 && via.steps > via.approach_steps);
}

#[test]
fn simulate_names_the_mesh_of_its_answer_and_a_mesh_given_stays() {
    let deep = [
        "simulate",
        "--R",
        "3.2",
        "--l1",
        "0.03",
        "--per",
        "0.06",
        "--depth",
        "20",
        "--allow-thick-pockets",
        "--json",
    ];
    let (code, out, _) = common::texopt(&deep);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["inputs"]["mesh"], "600x24");
    assert_eq!(v["deep_mesh"], serde_json::json!([600, 24]));
    // With --mesh the run stays on it, and the note says what that costs.
    let given = [&deep[..], &["--mesh", "700x8"]].concat();
    let (code, out, err) = common::texopt(&given);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["inputs"]["mesh"], "700x8");
    assert!(v.get("deep_mesh").is_none(), "{out}");
    assert!(err.contains("goes on on 600x24 by itself"), "{err}");
    // So does a step given.
    let (code, out, _) = common::texopt(&[&deep[..], &["--dt", "5e-4"]].concat());
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["inputs"]["mesh"], "700x8");
}
