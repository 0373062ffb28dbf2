//! Helpers shared by the integration tests: the paper's cases, the binary, scratch space.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

use std::sync::atomic::AtomicBool;
use std::sync::Mutex;
use texopt::model::case::{CaseSpec, Texture};
use texopt::model::operating::Scales;
use texopt::optimise::search::Evaluator;
use texopt::study::cache::Cache;
use texopt::study::sweep;
use texopt::time::cycle::CycleWatch;
use texopt::time::Overrides;
use texopt::time::{Fidelity, Limits};

/// The paper's Case I: R = 0.8, pockets 0.01 / 0.06 / 5 µm.
pub fn case_one() -> CaseSpec {
    CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0))
}

/// The paper's Case III: R = 3.2, pockets 0.03 / 0.06 / 10 µm.
pub fn case_three() -> CaseSpec {
    CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0))
}

/// The conformal ring of the benchmark: R = 51.2 with Case I's pockets.
pub fn conformal() -> CaseSpec {
    CaseSpec::paper(51.2).with_texture(Texture::circular(0.01, 0.06, 5.0))
}

/// `simulate` of Case I at `draft`: the quick run the command-line tests start from.
pub fn case_one_draft() -> [&'static str; 11] {
    [
        "simulate",
        "--R",
        "0.8",
        "--l1",
        "0.01",
        "--per",
        "0.06",
        "--depth",
        "5",
        "--fidelity",
        "draft",
    ]
}

/// |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// Runs the texopt binary: exit code, stdout, stderr.
pub fn texopt(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_texopt"))
        .args(args)
        .output()
        .expect("run texopt");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh scratch directory for one test (removed first if a previous run left it).
pub fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("texopt-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small engine file of the cycle tests, its `[zones]` given as `zones`.
/// The plain liner of the engine file `text` run straight through its cycle, as `texopt
/// cycle` runs it: the ring with the default roughness, at draft on `mesh` (N1, N2) cells, until
/// it repeats itself. Its friction work (J/m).
#[allow(dead_code)]
pub fn plain_cycle_work(text: &str, (n1, n2): (usize, usize)) -> f64 {
    use texopt::model::engine::{Engine, LinerZones};
    use texopt::model::liner_layout::LinerLayout;
    use texopt::model::operating::Validity;
    use texopt::time::cycle::{cycle_numerics, metrics, CycleRun, Drive};
    let (engine, zones, _): (Engine, LinerZones, serde::de::IgnoredAny) =
        texopt::study::engine_file::parse(text).unwrap();
    let drive = Drive::new(&engine);
    let ring = drive.ring_case_at(Validity::default().roughness_um);
    let mesh = Overrides {
        n1: Some(n1),
        n2: Some(n2),
        ..Overrides::default()
    };
    let num = cycle_numerics(Fidelity::Draft, &mesh, &ring, None);
    let layout = LinerLayout::uniform(0.1 * engine.file.engine.stroke_mm, None);
    let plain = CycleRun::new(&drive, ring, layout, num)
        .unwrap()
        .run(CycleWatch::default())
        .unwrap();
    metrics(&plain.rows, &engine, zones.bounds_mm()).work_j_per_m
}

/// The report `out/base` + each suffix must exist; its JSON, `out/base.json`, read.
#[allow(dead_code)]
pub fn report_files(out: &std::path::Path, base: &str, suffixes: &[&str]) -> serde_json::Value {
    for suffix in suffixes {
        let f = out.join(format!("{base}{suffix}"));
        assert!(f.is_file(), "{} missing", f.display());
    }
    let json = std::fs::read_to_string(out.join(format!("{base}.json"))).unwrap();
    serde_json::from_str(&json).unwrap()
}

/// A report's JSON (`DIR/BASE.json`) without its wall time, the one field that differs
/// between equal runs.
pub fn report_without_wall_time(out: &std::path::Path, base: &str) -> serde_json::Value {
    let mut r = report_files(out, base, &[".json"]);
    r.as_object_mut().unwrap().remove("wall_time_s");
    r
}

/// The test engine with a map: idle (slow, half the gas load, a thicker oil) and cruise (the
/// engine's own point), the second three times as long.
pub fn mapped_engine() -> String {
    engine("count = 2").replace(
        "[zones]",
        "[[operating]]\nname = \"idle\"\nweight = 1\nrpm = 800\ngas_scale = 0.5\nviscosity_pa_s = 0.02\n\n\
         [[operating]]\nname = \"cruise\"\nweight = 3\n\n[zones]",
    )
}

/// The least search a command takes: 2 particles, 1 iteration, at draft.
#[allow(dead_code)]
pub const QUICK_SEARCH: [&str; 6] = [
    "--particles",
    "2",
    "--iterations",
    "1",
    "--fidelity",
    "draft",
];

pub fn engine(zones: &str) -> String {
    format!(
        r#"
[engine]
name = "t"
bore_mm = 79
stroke_mm = 81
rod_mm = 130
rpm = 3000
[ring]
R_cm = 5
width_mm = 1.2
mass_kg_per_m = 0.03
elastic_load_n_per_m = 150
[gas]
crank_deg = [0, 15, 60, 180, 360, 540, 690]
pressure_bar = [15, 35, 12, 2, 0.2, 0, 8]
[oil]
viscosity_pa_s = 0.007
d_oil_um = 20
[zones]
{zones}
[design]
per = [0.0128, 0.06]
l1 = [0.005, 0.03]
l2 = [0.005, 0.03]
"#
    )
}

/// The optimiser's evaluation service over `cache`, quiet, on `jobs` threads, within the
/// default run limits.
pub fn evaluator<'a>(
    base: CaseSpec,
    scales: Scales,
    fidelity: Fidelity,
    overrides: Overrides,
    (cache, stop): (&'a Mutex<Cache>, &'a AtomicBool),
    jobs: usize,
) -> Evaluator<'a> {
    Evaluator {
        base,
        scales,
        fidelity,
        overrides,
        cache,
        options: sweep::Options {
            jobs,
            retry_failed: false,
            progress: false,
            limits: Limits::default(),
        },
        stop,
        log: Mutex::new(Vec::new()),
        simulations: Mutex::new(0),
        progress: false,
        name: String::new(),
    }
}

/// `texopt cycle FILE extra…` with a scratch output and cache: exit code, stdout, stderr, and
/// whether anything was written.
pub fn cycle(
    dir: &std::path::Path,
    file: &std::path::Path,
    extra: &[&str],
) -> (i32, String, String, bool) {
    let out = dir.join("out");
    let cache = dir.join("c.sqlite");
    let mut args = vec![
        "cycle",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = texopt(&args);
    (code, stdout, stderr, out.exists() || cache.exists())
}
