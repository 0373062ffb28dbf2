//! One case given to `simulate`, to a study file and to the optimiser's evaluation path gets
//! the same numerics and the same outcome, to the bit: a cheap case, small pockets whose N2 is
//! raised above a mesh given, and deep pockets that go on on the deep-pocket mesh.

mod common;

use common::{scratch, texopt};
use serde_json::{Map, Value};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;
use texopt::model::case::{CaseSpec, Texture};
use texopt::model::operating::Operating;
use texopt::study::cache::Cache;
use texopt::time::Fidelity;
use texopt::time::Overrides;

/// A case as each path is told it: ring, pockets, tier and a mesh given beside it.
struct Given {
    r: f64,
    l1: f64,
    per: f64,
    depth: f64,
    fidelity: Fidelity,
    mesh: Option<(usize, usize)>,
}

/// `simulate --json`: the inputs it ran and its outcome.
fn by_simulate(g: &Given) -> Map<String, Value> {
    let num = |x: f64| x.to_string();
    let (r, l1, per, depth) = (num(g.r), num(g.l1), num(g.per), num(g.depth));
    let mesh = g.mesh.map(|(a, b)| format!("{a}x{b}"));
    let mut args = vec![
        "simulate",
        "--R",
        &r,
        "--l1",
        &l1,
        "--per",
        &per,
        "--depth",
        &depth,
        "--fidelity",
        g.fidelity.name(),
        "--json",
    ];
    if let Some(m) = &mesh {
        args.extend(["--mesh", m]);
    }
    let (code, out, err) = texopt(&args);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(out.trim()).expect("one JSON object")
}

/// A one-case study file through `texopt study`: its cache entry (key, hash, outcome).
fn by_study(g: &Given, dir: &Path) -> Map<String, Value> {
    let numerics = g
        .mesh
        .map_or(String::new(), |(n1, n2)| format!("n1 = {n1}\nn2 = {n2}\n"));
    let file = dir.join("one.toml");
    std::fs::write(
        &file,
        format!(
            "[study]\nname = \"one\"\nfidelity = \"{}\"\n\n[parameters]\nR = {}\nl1 = {}\n\
             l2 = \"l1\"\nper = {}\nwidth = \"per\"\ndepth = {}\n\n[numerics]\n{numerics}",
            g.fidelity.name(),
            g.r,
            g.l1,
            g.per,
            g.depth
        ),
    )
    .unwrap();
    let cache = dir.join("study.sqlite");
    let (code, _, err) = texopt(&[
        "study",
        file.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
        "--no-report",
    ]);
    assert_eq!(code, 0, "{err}");
    only_entry(&cache)
}

/// The design evaluated as the optimiser evaluates its designs (its `Evaluator`, the base
/// case of `optimise --R`, the overrides of `--mesh`): its cache entry.
fn by_optimiser(g: &Given, dir: &Path) -> Map<String, Value> {
    let op = Operating::paper();
    let mut base = CaseSpec::paper(g.r);
    op.apply(&mut base);
    let path = dir.join("optimiser.sqlite");
    let cache = Mutex::new(Cache::open(&path).unwrap());
    let stop = AtomicBool::new(false);
    let eval = common::evaluator(
        base,
        op.scales(),
        g.fidelity,
        Overrides {
            n1: g.mesh.map(|m| m.0),
            n2: g.mesh.map(|m| m.1),
            ..Overrides::default()
        },
        (&cache, &stop),
        1,
    );
    let design = Texture::circular(g.l1, g.per, g.depth);
    let out = eval.evaluate(&[Some(design)]).unwrap();
    assert!(out[0].is_ok(), "{:?}", out[0]);
    drop(eval);
    drop(cache);
    only_entry(&path)
}

/// The one entry of a cache, as `texopt cache export` writes it.
fn only_entry(cache: &Path) -> Map<String, Value> {
    let (code, out, err) = texopt(&["cache", "export", "--cache", cache.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "{out}");
    serde_json::from_str(lines[0]).unwrap()
}

/// An outcome without its wall time (the one field that may differ between runs).
fn outcome(o: &Map<String, Value>) -> Map<String, Value> {
    let mut o = o.clone();
    o.remove("wall_time_s");
    o
}

/// The three paths agree on `g`; returns the numerics they ran and `simulate`'s answer.
fn same_on_every_path(test: &str, g: &Given) -> (Map<String, Value>, Map<String, Value>) {
    let dir = scratch(test);
    let sim = by_simulate(g);
    let study = by_study(g, &dir);
    let opt = by_optimiser(g, &dir);
    // The study and the optimiser store the same evaluation under the same key.
    assert_eq!(study["key"], opt["key"]);
    assert_eq!(study["hash"], opt["hash"]);
    let study_outcome = outcome(study["outcome"].as_object().unwrap());
    assert_eq!(study_outcome, outcome(opt["outcome"].as_object().unwrap()));
    // `simulate` runs that key's case and numerics (the cache adds its own settings beside
    // them), to the same outcome.
    let key = study["key"].as_object().unwrap();
    let inputs = sim["inputs"].as_object().unwrap();
    assert_eq!(inputs["case"], key["case"]);
    let numerics = key["numerics"].as_object().unwrap();
    for (k, v) in inputs["numerics"].as_object().unwrap() {
        assert_eq!(Some(v), numerics.get(k), "numerics.{k}");
    }
    for (k, v) in &study_outcome {
        assert_eq!(Some(v), sim.get(k), "outcome.{k}");
    }
    let numerics = numerics.clone();
    let _ = std::fs::remove_dir_all(dir);
    (numerics, sim)
}

#[test]
fn a_draft_case_is_the_same_on_every_path() {
    let g = Given {
        r: 0.8,
        l1: 0.01,
        per: 0.06,
        depth: 5.0,
        fidelity: Fidelity::Draft,
        mesh: None,
    };
    let (n, _) = same_on_every_path("paths-draft", &g);
    assert_eq!((n["n1"].as_u64(), n["n2"].as_u64()), (Some(400), Some(8)));
}

#[test]
fn a_mesh_given_gets_n2_raised_for_small_pockets_on_every_path() {
    // l2 = 0.005 in a 0.05 cm cell: 4 cells across a pocket take N2 = 10 at `fast`.
    let g = Given {
        r: 3.2,
        l1: 0.005,
        per: 0.05,
        depth: 10.0,
        fidelity: Fidelity::Fast,
        mesh: Some((512, 8)),
    };
    let (n, _) = same_on_every_path("paths-small", &g);
    assert_eq!((n["n1"].as_u64(), n["n2"].as_u64()), (Some(512), Some(10)));
    assert!(n.get("deep").is_none(), "a mesh given keeps the run on it");
}

#[test]
fn deep_pockets_go_on_on_the_deep_pocket_mesh_on_every_path() {
    let g = Given {
        r: 3.2,
        l1: 0.03,
        per: 0.06,
        depth: 20.0,
        fidelity: Fidelity::Fast,
        mesh: None,
    };
    let (n, sim) = same_on_every_path("paths-deep", &g);
    assert_eq!((n["n1"].as_u64(), n["n2"].as_u64()), (Some(700), Some(8)));
    assert_eq!(n["deep"]["n2"].as_u64(), Some(24));
    assert_eq!(sim["deep_mesh"], serde_json::json!([600, 24]));
}
