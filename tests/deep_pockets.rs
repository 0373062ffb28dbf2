//! Pockets far deeper than the film (depth > 6·C_min): `fast` goes on from its periodic state
//! on the deep-pocket mesh (docs/solver.md, "Deep pockets"), and what it reports is that
//! mesh's own periodic regime, the same as a run on that mesh from the coarse approach.

mod common;

use common::rel;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, Coarse, Fidelity, MeshUncertainty, Numerics, Outcome};

/// The larger of a JSON number and `x`, as JSON.
trait MaxWith {
    fn max_with(&self, x: f64) -> serde_json::Value;
}

impl MaxWith for serde_json::Value {
    fn max_with(&self, x: f64) -> serde_json::Value {
        serde_json::json!(self.as_f64().unwrap().max(x))
    }
}

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
    // The answer says how well it is known: the deep-pocket rule on its mesh.
    let known = |v: &serde_json::Value| {
        assert_eq!(v["error"]["source"], "deep-mesh", "{v}");
        let u = &v["mesh_uncertainty"];
        assert_eq!(
            v["error"]["f_mean"],
            u["f_mean"].max_with(Fidelity::Fast.f_error())
        );
        u["f_mean"].as_f64().unwrap()
    };
    let fine = known(&v);
    // With --mesh the run stays on it, and the note says what that costs.
    let given = [&deep[..], &["--mesh", "700x8"]].concat();
    let (code, out, err) = common::texopt(&given);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["inputs"]["mesh"], "700x8");
    assert!(v.get("deep_mesh").is_none(), "{out}");
    assert!(err.contains("goes on on 600x24 by itself"), "{err}");
    // Fewer cells across: a larger uncertainty.
    assert!(known(&v) > fine, "{out}");
    // So does a step given.
    let (code, out, _) = common::texopt(&[&deep[..], &["--dt", "5e-4"]].concat());
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["inputs"]["mesh"], "700x8");
}

/// A study's report is not written where an answer with pockets deeper than 6·C_min carries no
/// mesh uncertainty; with the uncertainty its CSV says how well each row is known.
#[test]
fn a_deep_answer_without_an_uncertainty_cannot_be_written() {
    let dir = common::scratch("deep-uncertainty");
    let toml = format!(
        "[study]\nname = \"deep\"\nfidelity = \"draft\"\nuntextured = true\n\n[parameters]\nR = 3.2\nl1 = 0.03\nper = 0.06\ndepth = [5, 20]\n\n[report]\ndir = \"{}\"\n",
        dir.join("out").display()
    );
    let study = texopt::study::parse(&toml, "deep.toml").unwrap();
    // Outcomes as a run would give them, the least clearance 1.7 µm: the 20 µm pockets end
    // deeper than 6·C_min, the 5 µm ones do not.
    let plain = simulate(&study.jobs[0].case, &study.jobs[0].numerics)
        .unwrap()
        .outcome;
    let answer = |c_min: f64| Outcome {
        c_min,
        ..plain.clone()
    };
    let bare: Vec<_> = study
        .jobs
        .iter()
        .map(|j| {
            Some(Ok(answer(if j.case.texture.is_some() {
                1.7
            } else {
                plain.c_min
            })))
        })
        .collect();
    let Err(e) = texopt::study::report::write(&study, &bare, "") else {
        panic!("a deep answer without its uncertainty was written");
    };
    assert!(e.to_string().contains("carries no mesh uncertainty"), "{e}");
    assert!(!dir.join("out/deep.csv").exists());
    // Given one (as every run measures on such an answer), the report is written: a coarser
    // mesh's answer 5 % off in f̄ makes it 10 %.
    let given: Vec<_> = bare
        .iter()
        .map(|r| {
            let o = r.clone().unwrap().unwrap();
            let coarse = Coarse {
                n1: 32,
                n2: 2,
                f_mean: 1.05 * o.f_mean,
                c_min: o.c_min,
            };
            let mesh_uncertainty = (o.c_min == 1.7)
                .then(|| Box::new(MeshUncertainty::of((o.f_mean, o.c_min), Some(coarse))));
            Some(Ok(Outcome {
                mesh_uncertainty,
                ..o
            }))
        })
        .collect();
    texopt::study::report::write(&study, &given, "").unwrap();
    let csv = std::fs::read_to_string(dir.join("out/deep.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(csv.as_bytes());
    let head = rows.headers().unwrap().clone();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let sources: Vec<(String, String, f64)> = rows
        .records()
        .map(|r| {
            let r = r.unwrap();
            (
                r[col("depth")].to_string(),
                r[col("error_source")].to_string(),
                r[col("f_error")].parse().unwrap(),
            )
        })
        .collect();
    let tier = Fidelity::Draft.f_error();
    for (depth, source, f_error) in &sources {
        match depth.as_str() {
            "20" => assert!(
                source == "deep-mesh" && rel(*f_error, 0.10) < 1e-9,
                "{sources:?}"
            ),
            _ => assert!(source == "tier" && *f_error == tier, "{sources:?}"),
        }
    }
}
