//! The liner's frame in two dimensions against the ring's (results/liner_frame/):
//! `texopt-lab liner-frame [runs | report | probe …]`.
//!
//! Three cases: Case III (R = 3.2, 0.03/0.06/10 µm, shallow) and the paper's deep pockets
//! (0.03/0.06/20 µm) at R = 3.2 and 25.6, each on meshes refined along x1, across x2 and in
//! both, in the ring's frame (the product's transient with the `fast` tier's numerics on the
//! mesh given) and in the liner's (lab/src/liner_frame.rs: BDF2 along the liner, the ring two
//! cells a step; backward Euler and one cell a step beside it on one mesh; and with its x1
//! faces fitted to the gap along x1, `LinerScheme::fitted`). Each run's f̄,
//! C_min and wall time go to runs.csv as it ends; `report` writes the README from it.

use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;
use texopt::mesh::{RimModel, Scene};
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{resolve, simulate, Fidelity, Numerics, Overrides, TimeScheme};

use crate::liner_frame::{LinerFrame, LinerScheme};

const DIR: &str = "results/liner_frame";

/// (name, R in cm, l1, per, depth in µm).
const CASES: [(&str, f64, f64, f64, f64); 3] = [
    ("Case III", 3.2, 0.03, 0.06, 10.0),
    ("R = 3.2 (20 µm)", 3.2, 0.03, 0.06, 20.0),
    ("R = 25.6 (20 µm)", 25.6, 0.03, 0.06, 20.0),
];

/// The meshes (N1 × N2): the coarsest, then refined along x1, across x2 and in both.
const MESHES: [(usize, usize); 5] = [(300, 12), (600, 24), (1200, 24), (600, 48), (1200, 48)];

/// The liner frame's schemes: BDF2 two cells a step on every mesh; on 600 × 24 also one cell
/// a step (the step halved) and backward Euler.
pub const BDF2_2: LinerScheme = LinerScheme {
    k: 2,
    bdf2: true,
    x1_samples: 1,
    fitted: false,
    fitted_x2: false,
};
pub const BDF2_1: LinerScheme = LinerScheme { k: 1, ..BDF2_2 };
pub const BE_2: LinerScheme = LinerScheme {
    bdf2: false,
    ..BDF2_2
};

/// BDF2 two cells a step with each node's texture depth the mean over 8 points along its cell.
pub const CELL_MEAN: LinerScheme = LinerScheme {
    x1_samples: 8,
    fitted: false,
    fitted_x2: false,
    ..BDF2_2
};

/// BDF2 two cells a step with the x1 faces fitted to the gap along x1 (8 points a strip,
/// the cells' mean depth over 8 points as their storage).
pub const FITTED: LinerScheme = LinerScheme {
    x1_samples: 8,
    fitted: true,
    fitted_x2: false,
    ..BDF2_2
};

/// As [`FITTED`], the x2 faces fitted as well (8 strips along x1, 8 points between the rows).
pub const FITTED_X2: LinerScheme = LinerScheme {
    fitted_x2: true,
    ..FITTED
};

/// Relative tolerance of the liner frame's periodic regime, and its allowance in periods.
const PERIODIC_TOL: f64 = 2e-4;
const MAX_PERIODS: usize = 80;

/// How the film sees the gap across a cell: the nodal rows, or the strips of rim_rows.rs
/// (8 samples across each cell, x2 faces in series).
pub const STRIPS: RimModel = RimModel::Strips { samples: 8 };

#[derive(Clone, Copy, Debug)]
enum Frame {
    Ring(RimModel),
    /// The ring frame with BDF2 in place of the characteristic scheme, the ring k cells a
    /// step (dt = k·dx1/u), nodal rows.
    RingBdf2(usize),
    /// The ring frame's characteristic scheme with the ring k cells a step (dt = k·dx1/u, its
    /// Courant number k/2), nodal rows.
    RingChar(usize),
    Liner(LinerScheme, RimModel),
}

impl Frame {
    fn name(self) -> String {
        let rim = |r: RimModel| if r.is_nodal() { "" } else { "-strips" };
        match self {
            Frame::Ring(r) => format!("ring{}", rim(r)),
            Frame::RingBdf2(k) => format!("ring-bdf2-k{k}"),
            Frame::RingChar(k) => format!("ring-char-k{k}"),
            Frame::Liner(s, r) => format!(
                "liner-{}-k{}{}{}",
                if s.bdf2 { "bdf2" } else { "be" },
                s.k,
                match (s.fitted, s.x1_samples) {
                    (true, m) if s.fitted_x2 => format!("-fit{m}-x2"),
                    (true, m) => format!("-fit{m}"),
                    (false, 1) => String::new(),
                    (false, _) => "-mean".into(),
                },
                rim(r)
            ),
        }
    }
}

/// The deep case at R = 3.2 with other gaps ahead of and behind the ring than the paper's
/// e = 1000 µm: (name, e in µm).
const EDGES: [(&str, f64); 2] = [
    ("R = 3.2 (20 µm) e = 300 µm", 300.0),
    ("R = 3.2 (20 µm) e = 5000 µm", 5000.0),
];

/// Case `c`: one of `CASES`, then one of `EDGES`.
pub fn case(c: usize) -> CaseSpec {
    let (e, c) = match c.checked_sub(CASES.len()) {
        Some(k) => (Some(EDGES[k].1), 1),
        None => (None, c),
    };
    let (_, r, l1, per, depth) = CASES[c];
    let mut case = CaseSpec::paper(r).with_texture(Texture::circular(l1, per, depth));
    if let Some(e) = e {
        case.e = e;
    }
    case
}

fn case_name(c: usize) -> &'static str {
    match c.checked_sub(CASES.len()) {
        Some(k) => EDGES[k].0,
        None => CASES[c].0,
    }
}

/// The `fast` tier's numerics with `mesh` given and the gap across a cell seen as `rim` sees
/// it.
fn numerics(case: &CaseSpec, (n1, n2): (usize, usize), rim: RimModel) -> Numerics {
    let given = Overrides {
        n1: Some(n1),
        n2: Some(n2),
        ..Overrides::default()
    };
    Numerics {
        rim,
        ..resolve(Fidelity::Fast, &given, case)
    }
}

/// The case's ring-frame run on `mesh` with the `fast` tier's numerics: f̄, C_min, Z̄, periods.
pub fn ring_run(
    case: &CaseSpec,
    mesh: (usize, usize),
    rim: RimModel,
) -> Result<(f64, f64, f64, usize), String> {
    outcome(case, &numerics(case, mesh, rim))
}

/// The same with `scheme` and the ring `k` cells a step, nodal rows.
pub fn ring_step_run(
    case: &CaseSpec,
    mesh: (usize, usize),
    (scheme, k): (TimeScheme, usize),
) -> Result<(f64, f64, f64, usize), String> {
    let num = numerics(case, mesh, RimModel::Nodal);
    let dx = case.contact().length_cm / num.n1 as f64;
    let num = Numerics {
        scheme,
        dt: k as f64 * dx / case.u,
        ..num
    };
    outcome(case, &num)
}

fn outcome(case: &CaseSpec, num: &Numerics) -> Result<(f64, f64, f64, usize), String> {
    let o = simulate(case, num).map_err(|e| e.to_string())?.outcome;
    Ok((o.f_mean, o.c_min, o.z_mean, o.periods))
}

/// One liner-frame run from the paper's start with the ring at `z0`: f̄, C_min, periods,
/// whether periodic.
pub fn liner_run(
    case: &CaseSpec,
    (n1, n2): (usize, usize),
    (scheme, rim): (LinerScheme, RimModel),
    z0: Option<f64>,
) -> Result<(f64, f64, usize, bool), String> {
    let scene = Scene::new(case, n1, n2).with_rim(rim);
    let mut run = LinerFrame::new(case, scene, scheme, z0).map_err(|e| e.to_string())?;
    let (last, periodic, periods) = run
        .run_to_periodic(PERIODIC_TOL, MAX_PERIODS)
        .map_err(|e| e.to_string())?;
    Ok((last.f_mean, run.clearance(last.z_min), periods, periodic))
}

/// Runs the jobs runs.csv does not hold yet (a run that stopped goes on where it was), each
/// line appended as its run ends.
fn runs() -> Result<(), String> {
    fs::create_dir_all(DIR).map_err(|e| e.to_string())?;
    let path = format!("{DIR}/runs.csv");
    let done = if fs::metadata(&path).is_ok() {
        load()?
    } else {
        fs::write(
            &path,
            "case,frame,n1,n2,f_mean,c_min,periods,periodic,wall_s\n",
        )
        .map_err(|e| e.to_string())?;
        Vec::new()
    };
    let out = fs::OpenOptions::new()
        .append(true)
        .open(&path)
        .map_err(|e| e.to_string())?;
    // The ring's mean position on the coarsest mesh starts every liner-frame run of a case.
    let z0: Vec<f64> = (0..CASES.len() + EDGES.len())
        .map(|c| ring_run(&case(c), MESHES[0], RimModel::Nodal).map(|r| r.2))
        .collect::<Result<_, _>>()?;
    let mut jobs: Vec<(usize, Frame, (usize, usize))> = Vec::new();
    for c in 0..CASES.len() {
        for rim in [RimModel::Nodal, STRIPS] {
            for &m in &MESHES {
                jobs.push((c, Frame::Ring(rim), m));
                // The liner frame with strips on 1200 × 48 would take about 10 min a case.
                if rim.is_nodal() || m != MESHES[4] {
                    jobs.push((c, Frame::Liner(BDF2_2, rim), m));
                }
            }
            jobs.push((c, Frame::Liner(BDF2_1, rim), MESHES[1]));
            jobs.push((c, Frame::Liner(BE_2, rim), MESHES[1]));
        }
        jobs.push((c, Frame::Liner(CELL_MEAN, RimModel::Nodal), MESHES[1]));
        for &m in &MESHES[..4] {
            jobs.push((c, Frame::Liner(FITTED, STRIPS), m));
        }
        for &m in &MESHES[..3] {
            jobs.push((c, Frame::Liner(FITTED, RimModel::Nodal), m));
        }
        let fit16 = LinerScheme {
            x1_samples: 16,
            ..FITTED
        };
        jobs.push((c, Frame::Liner(fit16, STRIPS), MESHES[1]));
        jobs.push((
            c,
            Frame::Liner(LinerScheme { k: 1, ..FITTED }, STRIPS),
            MESHES[1],
        ));
        // Both refinements at once, where the deep pockets were furthest from converged.
        if c == 2 {
            jobs.push((c, Frame::Liner(FITTED, STRIPS), MESHES[4]));
        }
        if c > 0 {
            for m in [MESHES[0], MESHES[1], MESHES[3]] {
                jobs.push((c, Frame::Liner(FITTED_X2, STRIPS), m));
            }
        }
        jobs.push((
            c,
            Frame::Liner(LinerScheme { k: 1, ..BE_2 }, RimModel::Nodal),
            MESHES[1],
        ));
        jobs.push((
            c,
            Frame::Liner(LinerScheme { k: 4, ..BE_2 }, RimModel::Nodal),
            MESHES[1],
        ));
        jobs.push((
            c,
            Frame::Liner(LinerScheme { k: 4, ..BDF2_2 }, RimModel::Nodal),
            MESHES[1],
        ));
        jobs.push((c, Frame::Liner(BE_2, RimModel::Nodal), MESHES[2]));
        jobs.push((c, Frame::RingBdf2(2), MESHES[1]));
        jobs.push((c, Frame::RingBdf2(1), MESHES[1]));
        jobs.push((c, Frame::RingChar(1), MESHES[1]));
    }
    for c in CASES.len()..CASES.len() + EDGES.len() {
        for m in &MESHES[..2] {
            jobs.push((c, Frame::Ring(RimModel::Nodal), *m));
            jobs.push((c, Frame::Liner(BDF2_2, RimModel::Nodal), *m));
        }
    }
    jobs.retain(|&(c, frame, mesh)| {
        !done
            .iter()
            .any(|r| r.case == case_name(c) && r.frame == frame.name() && r.mesh == mesh)
    });
    // The costliest first, so that two cores end together.
    jobs.sort_by_key(|j| std::cmp::Reverse(j.2 .0 * j.2 .1));
    let out = Mutex::new(out);
    jobs.par_iter().try_for_each(|&(c, frame, mesh)| {
        let began = Instant::now();
        let (f, cm, periods, periodic) = match frame {
            Frame::Ring(rim) => ring_run(&case(c), mesh, rim).map(|r| (r.0, r.1, r.3, true))?,
            Frame::RingBdf2(k) => ring_step_run(&case(c), mesh, (TimeScheme::Bdf2, k))
                .map(|r| (r.0, r.1, r.3, true))?,
            Frame::RingChar(k) => ring_step_run(&case(c), mesh, (TimeScheme::Characteristic, k))
                .map(|r| (r.0, r.1, r.3, true))?,
            Frame::Liner(s, rim) => liner_run(&case(c), mesh, (s, rim), Some(z0[c]))?,
        };
        let line = format!(
            "{},{},{},{},{f},{cm},{periods},{periodic},{:.1}",
            case_name(c),
            frame.name(),
            mesh.0,
            mesh.1,
            began.elapsed().as_secs_f64()
        );
        eprintln!("{line}");
        let mut o = out.lock().expect("the CSV writer");
        writeln!(o, "{line}").map_err(|e| e.to_string())
    })
}

pub fn main(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        None | Some("runs") => {
            runs()?;
            report()
        }
        Some("report") => report(),
        Some("probe") => probe(&args[1..]),
        _ => Err("usage: texopt-lab liner-frame [runs | report | probe R l1 per depth N1 N2 k bdf2 periods [e]]".into()),
    }
}

/// `probe R l1 per depth N1 N2 k bdf2 periods [e]`: one liner-frame run of so many periods from
/// the ring frame's mean Z on the same mesh, each period's f̄ and least clearance printed;
/// `e` the gap outside the ring (µm) in place of the case's.
fn probe(args: &[String]) -> Result<(), String> {
    let num = |i: usize| -> Result<f64, String> {
        let v = args
            .get(i)
            .ok_or("probe needs R l1 per depth N1 N2 k bdf2 periods")?;
        v.parse::<f64>().map_err(|e| format!("{v}: {e}"))
    };
    let mut case =
        CaseSpec::paper(num(0)?).with_texture(Texture::circular(num(1)?, num(2)?, num(3)?));
    if args.len() > 9 {
        case.e = num(9)?;
    }
    let mesh = (num(4)? as usize, num(5)? as usize);
    let fit = if args.len() > 10 {
        num(10)? as usize
    } else {
        0
    };
    let fit_x2 = args.len() > 12 && num(12)? > 0.0;
    let rim = match args.len() > 11 {
        true if num(11)? > 1.0 => RimModel::Strips {
            samples: num(11)? as usize,
        },
        _ => RimModel::Nodal,
    };
    let scheme = LinerScheme {
        k: num(6)? as usize,
        bdf2: num(7)? > 0.0,
        x1_samples: fit.max(1),
        fitted: fit > 0,
        fitted_x2: fit_x2,
    };
    let (f, c, z, _) = ring_run(&case, mesh, rim)?;
    eprintln!("ring frame: f̄ {f:.6}, C_min {c:.5}");
    let scene = Scene::new(&case, mesh.0, mesh.1).with_rim(rim);
    let mut run = LinerFrame::new(&case, scene, scheme, Some(z)).map_err(|e| e.to_string())?;
    for p in 1..=num(8)? as usize {
        let m = run.period().map_err(|e| e.to_string())?;
        eprintln!(
            "period {p}: f̄ {:.6}, C_min {:.5}, Z̄ {:.5}",
            m.f_mean,
            run.clearance(m.z_min),
            m.z_mean
        );
    }
    Ok(())
}

/// One row of runs.csv.
struct Row {
    case: String,
    frame: String,
    mesh: (usize, usize),
    f: f64,
    c: f64,
    periodic: bool,
    wall: f64,
}

fn load() -> Result<Vec<Row>, String> {
    let text = fs::read_to_string(format!("{DIR}/runs.csv")).map_err(|e| e.to_string())?;
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            let num = |i: usize| v[i].parse::<f64>().map_err(|e| format!("{l}: {e}"));
            Ok(Row {
                case: v[0].to_string(),
                frame: v[1].to_string(),
                mesh: (num(2)? as usize, num(3)? as usize),
                f: num(4)?,
                c: num(5)?,
                periodic: v[7] == "true",
                wall: num(8)?,
            })
        })
        .collect()
}

/// The columns of each case's table: (frame in runs.csv, heading).
const COLUMNS: [(&str, &str); 4] = [
    ("ring", "ring frame, nodal rows"),
    ("liner-bdf2-k2", "liner frame, nodal rows"),
    ("ring-strips", "ring frame, strips"),
    ("liner-bdf2-k2-strips", "liner frame, strips"),
];

/// The columns of each case's table of fitted faces.
const FITTED_COLUMNS: [(&str, &str); 5] = [
    ("liner-bdf2-k2", "nodal rows"),
    ("liner-bdf2-k2-fit8", "nodal rows, fitted faces"),
    ("liner-bdf2-k2-strips", "strips"),
    ("liner-bdf2-k2-fit8-strips", "strips, fitted faces"),
    (
        "liner-bdf2-k2-fit8-x2-strips",
        "strips, x1 and x2 faces fitted",
    ),
];

/// The step and the scheme: (frame, mesh, what it is).
const VARIANTS: [(&str, (usize, usize), &str); 18] = [
    ("liner-be-k4", (600, 24), "liner, backward Euler, 4 cells a step, nodal rows"),
    ("liner-be-k2", (600, 24), "liner, backward Euler, 2 cells a step, nodal rows"),
    ("liner-be-k1", (600, 24), "liner, backward Euler, 1 cell a step, nodal rows"),
    ("liner-be-k2", (1200, 24), "liner, backward Euler, 2 cells a step, nodal rows"),
    ("liner-bdf2-k4", (600, 24), "liner, BDF2, 4 cells a step, nodal rows"),
    ("liner-bdf2-k2", (600, 24), "liner, BDF2, 2 cells a step, nodal rows"),
    ("liner-bdf2-k1", (600, 24), "liner, BDF2, 1 cell a step, nodal rows"),
    ("liner-bdf2-k2-mean", (600, 24), "liner, BDF2, 2 cells a step, nodal rows, each node's depth its cell's mean along x1 (8 points)"),
    ("liner-be-k2-strips", (600, 24), "liner, backward Euler, 2 cells a step, strips"),
    ("liner-bdf2-k2-strips", (600, 24), "liner, BDF2, 2 cells a step, strips"),
    ("liner-bdf2-k1-strips", (600, 24), "liner, BDF2, 1 cell a step, strips"),
    ("liner-bdf2-k2-strips", (1200, 24), "liner, BDF2, 2 cells a step, strips"),
    ("ring", (600, 24), "ring, characteristic, 2 cells a step (Courant number 1), nodal rows"),
    ("ring-char-k1", (600, 24), "ring, characteristic, 1 cell a step (Courant number ½), nodal rows"),
    ("ring-bdf2-k2", (600, 24), "ring, BDF2, 2 cells a step, nodal rows"),
    ("ring-bdf2-k1", (600, 24), "ring, BDF2, 1 cell a step, nodal rows"),
    ("liner-bdf2-k1-fit8-strips", (600, 24), "liner, BDF2, 1 cell a step, strips, fitted faces"),
    ("liner-bdf2-k2-fit16-strips", (600, 24), "liner, BDF2, 2 cells a step, strips, fitted faces at 16 points"),
];

fn report() -> Result<(), String> {
    let rows = load()?;
    let find = |case: &str, frame: &str, mesh: (usize, usize)| {
        rows.iter()
            .find(|r| r.case == case && r.frame == frame && r.mesh == mesh)
    };
    let cell = |r: Option<&Row>| {
        r.map_or("–".to_string(), |r| {
            let unsettled = if r.periodic { "" } else { " (not periodic)" };
            format!("{:.5} / {:.4} ({:.0} s){unsettled}", r.f, r.c, r.wall)
        })
    };
    let table =
        |md: &mut String, name: &str, columns: &[(&str, &str)], meshes: &[(usize, usize)]| {
            md.push_str("| N1 × N2 |");
            for (_, heading) in columns {
                let _ = write!(md, " {heading} |");
            }
            let _ = writeln!(md, "\n|---|{}", "---|".repeat(columns.len()));
            for &m in meshes {
                if columns.iter().all(|(f, _)| find(name, f, m).is_none()) {
                    continue;
                }
                let _ = write!(md, "| {}×{} |", m.0, m.1);
                for (frame, _) in columns {
                    let _ = write!(md, " {} |", cell(find(name, frame, m)));
                }
                md.push('\n');
            }
        };
    let mut md = String::from(include_str!("liner_frame_head.md"));
    for (name, ..) in CASES {
        let _ = writeln!(md, "\n### {name}\n\nf̄ / C_min (µm) (seconds):\n");
        table(&mut md, name, &COLUMNS, &MESHES);
        md.push_str("\nThe liner frame with its x1 faces fitted to the gap along x1 (8 points a strip), beside it without:\n\n");
        table(&mut md, name, &FITTED_COLUMNS, &MESHES);
        md.push_str("\nThe step and the scheme:\n\n| mesh | scheme | f̄ / C_min (µm) (seconds) |\n|---|---|---|\n");
        for (frame, m, what) in VARIANTS {
            let _ = writeln!(
                md,
                "| {}×{} | {what} | {} |",
                m.0,
                m.1,
                cell(find(name, frame, m))
            );
        }
    }
    md.push_str(include_str!("liner_frame_edge.md"));
    md.push_str("| e (µm) | N1 × N2 | ring frame | liner frame |\n|---|---|---|---|\n");
    let edges = [
        (CASES[1].0, 1000.0),
        (EDGES[0].0, EDGES[0].1),
        (EDGES[1].0, EDGES[1].1),
    ];
    for &m in &MESHES[..2] {
        for (name, e) in edges {
            let _ = writeln!(
                md,
                "| {e} | {}×{} | {} | {} |",
                m.0,
                m.1,
                cell(find(name, "ring", m)),
                cell(find(name, "liner-bdf2-k2", m))
            );
        }
    }
    md.push_str(include_str!("liner_frame_tail.md"));
    fs::write(format!("{DIR}/README.md"), md).map_err(|e| e.to_string())
}
