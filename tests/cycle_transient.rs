//! The engine cycle as one transient (docs/model.md §12).

use texopt::model::liner_layout::LinerLayout;
use texopt::study::engine_file::parse;
use texopt::time::cycle::{CycleNumerics, CycleRun, Drive, StepRule};

fn example_engine() -> texopt::model::engine::Engine {
    let mut text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/engine_gasoline.toml"
    ))
    .unwrap();
    if std::env::var("NOGAS").is_ok() {
        text = text.replace("pressure_bar = [15, 30, 35, 28, 12, 6,  4,   2,   0.5, 0.2, 0,   0,   1.5, 4,   8,   12]", "pressure_bar = [0, 0, 0, 0, 0, 0,  0,   0,   0, 0, 0,   0,   0, 0,   0,   0]");
    }
    parse::<serde::de::IgnoredAny>(&text).unwrap().0
}

#[test]
#[ignore]
fn probe_plain_cycle() {
    let engine = example_engine();
    let drive = Drive::new(&engine);
    let stroke_cm = 0.1 * engine.file.engine.stroke_mm;
    let step: f64 = std::env::var("STEP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let n1: usize = std::env::var("N1")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let num = CycleNumerics {
        n1,
        n2: 1,
        steps: StepRule {
            step_deg: step,
            refine: 0.1,
            texture_step: f64::INFINITY,
        },
        oil_cell_cm: 0.001,
        start_deg: 90.0,
        cyclic_tol: 1e-3,
        max_cycles: 8,
    };
    let t0 = std::time::Instant::now();
    let run = CycleRun::new(
        &drive,
        drive.ring_case(),
        LinerLayout::uniform(stroke_cm, None),
        num,
    )
    .unwrap();
    let out = run
        .run(
            &mut |c| eprintln!("{c:?}  {:.2}s", t0.elapsed().as_secs_f64()),
            &mut |_| {},
        )
        .unwrap();
    for r in out.rows.iter().step_by(out.rows.len() / 60) {
        eprintln!(
            "{:7.2} u {:7.3} W {:8.1} Z {:7.3} F {:8.3} P {:8.2} met {:6.3} left {:6.3}",
            r.crank_deg,
            r.u_ms,
            r.load_n_per_m,
            r.z_um,
            r.friction_n_per_m,
            r.power_w_per_m,
            r.oil_met_um,
            r.oil_left_um
        );
    }
    eprintln!("{:.2}s", t0.elapsed().as_secs_f64());
}

#[test]
#[ignore]
fn probe_steady_textured() {
    use texopt::model::case::Texture;
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/engine_gasoline.toml"
    ))
    .unwrap()
    .replace(
        "d_oil_um =    [3, 6, 10, 20]",
        "d_oil_um =    [20, 20, 20, 20]",
    );
    let engine = parse::<serde::de::IgnoredAny>(&text).unwrap().0;
    let t = Texture::circular(0.01, 0.06, 5.0);
    let periods: f64 = std::env::var("PERIODS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3.0);
    let n2: usize = std::env::var("N2")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(32);
    let spp: f64 = std::env::var("SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(121.0);
    let drive = Drive::steady(&engine, 8.1, 150.0, periods * 0.06 / 1.0);
    let num = CycleNumerics {
        n1: 768,
        n2,
        steps: StepRule {
            step_deg: 90.0,
            refine: 1.0,
            texture_step: 0.06 / spp,
        },
        oil_cell_cm: 0.001,
        start_deg: 0.0,
        cyclic_tol: 1e-4,
        max_cycles: 40,
    };
    let t0 = std::time::Instant::now();
    let run = CycleRun::new(
        &drive,
        drive.ring_case(),
        LinerLayout::uniform(8.1, Some(t)),
        num,
    )
    .unwrap();
    let out = run
        .run(
            &mut |c| {
                eprintln!(
                    "W {:.6e} dW {:.2e} doil {:.2e} {:.2}s",
                    c.friction_work_j_per_m,
                    c.work_change,
                    c.oil_change,
                    t0.elapsed().as_secs_f64()
                )
            },
            &mut |_| {},
        )
        .unwrap();
    let n = out.rows.len() as f64;
    let f: f64 = out.rows.iter().map(|r| r.friction_n_per_m).sum::<f64>() / n;
    let zmin = out
        .rows
        .iter()
        .map(|r| r.z_um)
        .fold(f64::INFINITY, f64::min);
    let zmean: f64 = out.rows.iter().map(|r| r.z_um).sum::<f64>() / n;
    eprintln!(
        "F mean {f:.5} N/m, Z min {zmin:.4}, Z mean {zmean:.4}  {:.2}s",
        t0.elapsed().as_secs_f64()
    );
}

#[test]
#[ignore]
fn probe_uniform_cycle() {
    use texopt::model::case::Texture;
    use texopt::time::cycle::cycle_numerics;
    use texopt::time::Fidelity;
    let engine = example_engine();
    let drive = Drive::new(&engine);
    let stroke_cm = 0.1 * engine.file.engine.stroke_mm;
    let t = Texture::circular(0.01, 0.06, 5.0);
    let fid = match std::env::var("FID").as_deref() {
        Ok("fast") => Fidelity::Fast,
        Ok("paper") => Fidelity::Paper,
        _ => Fidelity::Draft,
    };
    let mut num = cycle_numerics(fid, &drive.ring_case(), Some(&t));
    num.max_cycles = std::env::var("CYC")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    eprintln!("{num:?}");
    let t0 = std::time::Instant::now();
    let run = CycleRun::new(
        &drive,
        drive.ring_case(),
        LinerLayout::uniform(stroke_cm, Some(t)),
        num,
    )
    .unwrap();
    let out = run
        .run(
            &mut |c| {
                eprintln!(
                    "W {:.6} dW {:.2e} doil {:.2e} steps {} {:.2}s",
                    c.friction_work_j_per_m,
                    c.work_change,
                    c.oil_change,
                    c.steps,
                    t0.elapsed().as_secs_f64()
                )
            },
            &mut |_| {},
        )
        .unwrap();
    let m = texopt::time::cycle::metrics(&out.rows, &engine);
    eprintln!("{m:?}");
}

/// The figures the flow-factor measurement compares (docs/model.md §11, "Flow factors"): the
/// plain liner (or, with TEX set, the uniform texture of `probe_uniform_cycle`) at the tier
/// FID (draft, fast, paper).
#[test]
#[ignore]
fn probe_cycle_figures() {
    use texopt::model::case::Texture;
    use texopt::time::cycle::cycle_numerics;
    use texopt::time::Fidelity;
    let engine = example_engine();
    let drive = Drive::new(&engine);
    let stroke_cm = 0.1 * engine.file.engine.stroke_mm;
    let t = std::env::var("TEX")
        .is_ok()
        .then(|| Texture::circular(0.01, 0.06, 5.0));
    let fid = match std::env::var("FID").as_deref() {
        Ok("fast") => Fidelity::Fast,
        Ok("paper") => Fidelity::Paper,
        _ => Fidelity::Draft,
    };
    let mut num = cycle_numerics(fid, &drive.ring_case(), t.as_ref());
    if let Some(c) = std::env::var("CYC").ok().and_then(|s| s.parse().ok()) {
        num.max_cycles = c;
    }
    eprintln!("{num:?}");
    let t0 = std::time::Instant::now();
    let run = CycleRun::new(
        &drive,
        drive.ring_case(),
        LinerLayout::uniform(stroke_cm, t),
        num,
    )
    .unwrap();
    let out = run
        .run(
            &mut |c| {
                eprintln!(
                    "W {:.6} dW {:.2e} doil {:.2e} steps {} {:.2}s",
                    c.friction_work_j_per_m,
                    c.work_change,
                    c.oil_change,
                    c.steps,
                    t0.elapsed().as_secs_f64()
                )
            },
            &mut |_| {},
        )
        .unwrap();
    let m = texopt::time::cycle::metrics(&out.rows, &engine);
    let peak = out
        .rows
        .iter()
        .max_by(|a, b| {
            a.friction_n_per_m
                .abs()
                .total_cmp(&b.friction_n_per_m.abs())
        })
        .unwrap();
    eprintln!(
        "FIGURES work {:.6e} asp_work {:.6e} h_min {:.6} at {:.2} lambda_min {:.6} \
         peak_F {:.6} at {:.2} asp_share_max {:.6e} contact_time {:.6} cyclic {}",
        m.work_j_per_m,
        m.asperity_work_j_per_m,
        m.h_min_um,
        m.h_min_deg,
        m.lambda_min,
        peak.friction_n_per_m.abs(),
        peak.crank_deg,
        m.asperity_share_max,
        m.contact_time_fraction,
        out.cyclic
    );
}
