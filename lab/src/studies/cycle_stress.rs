//! Whether every liner runs wherever the engine does (results/cycle_stress/):
//! `texopt-lab cycle-stress [LINER …]`.
//!
//! The example map's five points (studies/engine_gasoline_map.toml) at each point's viscosity
//! and at 0.5× and 0.3× it (hotter, thinner oil: thinner films, more contact), each with the
//! plain liner, one texture over the whole stroke at depths 2, 5 and 10 µm (the design
//! space's middle lattice, the band search's start texture), and the eight banded liners the
//! band search once lost to the film solver (results/cycle_gasoline_bands/_front.csv, their
//! textures as that file rounds them). Each liner is judged as the band search judges it:
//! at `draft`, two cycles from the plain liner's cyclic state on the same cells. The table
//! counts the runs, the failures by kind (a solver's failure, or a physical one named as
//! such), and the cost. `LINER …` (optional) runs only those liners (and the plain one) and
//! writes nothing.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use texopt::model::case::Texture;
use texopt::model::engine::Engine;
use texopt::model::liner_layout::LinerLayout;
use texopt::solve::FilmError;
use texopt::study::engine_file::parse;
use texopt::time::cycle::CycleWatch;
use texopt::time::cycle::{
    cycle_numerics, metrics, whole_stroke, CycleMetrics, CycleNumerics, CycleRun, CycleState,
    Drive, SETTLE_CYCLES,
};
use texopt::time::{Fidelity, Overrides, SolveError};

/// Factors on each point's viscosity.
const VISCOSITY: [f64; 3] = [1.0, 0.5, 0.3];

/// A lattice l1, l2, per (= width), depth, as the front's CSV writes it (cm, µm).
fn tex(l1: f64, l2: f64, per: f64, depth: f64) -> Texture {
    Texture {
        l1,
        l2,
        per,
        width: per,
        depth,
        phase: 0.0,
    }
}

/// A band: its start and end along the stroke (mm) and its texture.
type Band = (f64, f64, Texture);

/// The eight banded liners the band search lost (results/cycle_gasoline_bands/_front.csv):
/// name, and per band its start and end along the stroke (mm) and its texture.
fn lost_liners() -> Vec<(&'static str, [Band; 2])> {
    vec![
        (
            "lost-1",
            [
                (
                    6.973364469584489,
                    24.210830124667147,
                    tex(0.0059, 0.0037, 0.0147, 5.7),
                ),
                (
                    45.35409183625753,
                    74.10089175119849,
                    tex(0.0053, 0.0054, 0.0126, 7.2),
                ),
            ],
        ),
        (
            "lost-2",
            [
                (
                    2.0133298884640034,
                    29.764610757179565,
                    tex(0.0025, 0.0025, 0.0061, 3.9),
                ),
                (
                    42.21920045546704,
                    46.22751971796932,
                    tex(0.0195, 0.0140, 0.0407, 3.5),
                ),
            ],
        ),
        (
            "lost-3",
            [
                (
                    24.264983004872974,
                    35.325933224944436,
                    tex(0.0241, 0.0050, 0.0498, 6.0),
                ),
                (
                    42.26945428963212,
                    50.65845567619837,
                    tex(0.0026, 0.0040, 0.0125, 4.6),
                ),
            ],
        ),
        (
            "lost-4",
            [
                (36.5, 40.5, tex(0.0025, 0.0025, 0.0060, 4.1)),
                (
                    56.964230813615956,
                    79.41049437432643,
                    tex(0.0033, 0.0025, 0.0600, 4.8),
                ),
            ],
        ),
        (
            "lost-5",
            [
                (
                    15.782352870760105,
                    19.782352870760107,
                    tex(0.0209, 0.0253, 0.0517, 30.0),
                ),
                (
                    68.11314605765565,
                    72.11314605765565,
                    tex(0.0025, 0.0185, 0.0600, 4.0),
                ),
            ],
        ),
        (
            "lost-6",
            [
                (
                    4.127319018002377,
                    24.49438403723735,
                    tex(0.0025, 0.0047, 0.0128, 4.2),
                ),
                (71.32477921558143, 81.0, tex(0.0025, 0.0165, 0.0392, 2.6)),
            ],
        ),
        (
            "lost-7",
            [
                (
                    23.573602350996893,
                    27.573602350996893,
                    tex(0.0109, 0.0103, 0.0247, 17.3),
                ),
                (
                    41.80494664081901,
                    76.69654368510987,
                    tex(0.0025, 0.0025, 0.0600, 5.0),
                ),
            ],
        ),
        (
            "start",
            [
                (0.0, 4.0, tex(0.0092, 0.0092, 0.0330, 10.2)),
                (77.0, 81.0, tex(0.0092, 0.0092, 0.0330, 10.2)),
            ],
        ),
    ]
}

/// Every liner of the set: name and layout along a stroke of `stroke_mm`.
fn liners(stroke_mm: f64) -> Vec<(String, LinerLayout)> {
    let stroke_cm = 0.1 * stroke_mm;
    let mut out = vec![("plain".to_string(), LinerLayout::uniform(stroke_cm, None))];
    for depth in [2.0, 5.0, 10.0] {
        out.push((
            format!("uniform-{depth}um"),
            LinerLayout::uniform(stroke_cm, Some(tex(0.0092, 0.0092, 0.0330, depth))),
        ));
    }
    for (name, bands) in lost_liners() {
        let b: Vec<(f64, f64, Texture)> = bands
            .iter()
            .map(|(s, e, t)| (0.1 * s, 0.1 * e, t.clone()))
            .collect();
        out.push((name.to_string(), LinerLayout::banded(stroke_cm, &b)));
    }
    out
}

/// Where along the film a failure sits: the ring's edges and the film's centre column
/// (cm), and the half width of a bucket (1.5 cells).
#[derive(Clone, Copy)]
struct Places {
    edges: (f64, f64),
    centre: f64,
    near: f64,
}

impl Places {
    /// The example ring's, on `n1` cells along the film.
    fn of(drive: &Drive, n1: usize) -> Places {
        let contact = drive.ring_case().contact();
        Places {
            edges: contact.ring_edges(),
            centre: contact.x_center_cm,
            near: 1.5 * contact.length_cm / n1 as f64,
        }
    }

    fn name(&self, x1: f64) -> &'static str {
        let near = |x: f64| (x1 - x).abs() <= self.near;
        if near(self.centre) {
            "at the centre column (a cavity open to both gases)"
        } else if near(self.edges.0) || near(self.edges.1) {
            "at a ring edge, beside the free gap"
        } else {
            "under the ring"
        }
    }
}

/// What a run's failure was: its kind and, for a saturation out of range, where.
fn kind(e: &SolveError, places: Places) -> String {
    match e {
        SolveError::Film { source, .. } => match source {
            FilmError::SaturationOutOfRange { theta, x1, .. } if *theta < 0.0 => {
                format!("film solve: θ < 0 {}", places.name(*x1))
            }
            FilmError::SaturationOutOfRange { .. } => "film solve: θ > 1".into(),
            FilmError::NotConverged { .. } => "film solve: not converged".into(),
            FilmError::GapClosed { .. } => "film solve: gap closed".into(),
            FilmError::Singular { .. } => "film solve: singular matrix".into(),
            FilmError::NonFinite { .. } => "film solve: not finite".into(),
            FilmError::Other(_) => "film solve: other".into(),
        },
        SolveError::Contact { .. } => "the ring reached the liner".into(),
        SolveError::MassNotConserved { .. } => "mass not conserved".into(),
        SolveError::Steady { .. } => "steady start".into(),
        SolveError::Unstable { .. } => "unstable".into(),
    }
}

/// One point of the set: a map point's engine at a factor on its viscosity.
struct Point {
    name: String,
    engine: Engine,
}

fn points() -> Result<Vec<Point>, String> {
    let text = fs::read_to_string("studies/engine_gasoline_map.toml").map_err(|e| {
        format!("studies/engine_gasoline_map.toml: {e} (run from the repository's root)")
    })?;
    let (engine, _, _) = parse::<serde::de::IgnoredAny>(&text).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for p in engine.operating_points() {
        for f in VISCOSITY {
            let mut e = p.engine.clone();
            e.file.oil.viscosity_pa_s *= f;
            out.push(Point {
                name: format!("{} ×{f}", p.name),
                engine: e,
            });
        }
    }
    Ok(out)
}

/// The numerics a liner is judged with at `draft` (the band search's): the tier's cells for
/// its finest lattice, cut to the settle rule's cycles.
fn numerics(drive: &Drive, layout: &LinerLayout) -> CycleNumerics {
    let finest = layout
        .textures()
        .iter()
        .flatten()
        .min_by(|a, b| a.per.total_cmp(&b.per));
    cycle_numerics(
        Fidelity::Draft,
        &Overrides::default(),
        &drive.ring_case(),
        finest,
    )
}

/// The plain liner's cyclic run at one point, per cells along the film: its figures and end
/// state.
type Plains = Mutex<BTreeMap<usize, Result<(CycleMetrics, CycleState), SolveError>>>;

/// The outcome of one run: its figures, or its failure and where along the film it sits.
type Answer = Result<CycleMetrics, (SolveError, Places)>;

/// The plain liner's cyclic run on `num`'s cells: its figures and end state.
fn plain(
    drive: &Drive,
    engine: &Engine,
    num: &CycleNumerics,
) -> Result<(CycleMetrics, CycleState), SolveError> {
    let layout = LinerLayout::uniform(0.1 * engine.file.engine.stroke_mm, None);
    let o =
        CycleRun::new(drive, drive.ring_case(), layout, num.clone())?.run(CycleWatch::default())?;
    Ok((metrics(&o.rows, engine, &whole_stroke(engine)), o.end))
}

/// `layout` judged at `point` from the plain liner's cyclic state on its cells.
fn judge(point: &Point, layout: &LinerLayout, plains: &Plains) -> Answer {
    let drive = Drive::new(&point.engine);
    let mut num = numerics(&drive, layout);
    let places = Places::of(&drive, num.n1);
    let start = {
        let mut m = plains.lock().unwrap_or_else(|e| e.into_inner());
        m.entry(num.n1)
            .or_insert_with(|| plain(&drive, &point.engine, &num))
            .clone()
    };
    let (plain_m, end) = start.map_err(|e| (e, places))?;
    if !layout.textured() {
        return Ok(plain_m);
    }
    num.settle = Some(SETTLE_CYCLES);
    CycleRun::resume(&drive, drive.ring_case(), layout.clone(), num, &end)
        .and_then(|r| r.run(CycleWatch::default()))
        .map(|o| metrics(&o.rows, &point.engine, &whole_stroke(&point.engine)))
        .map_err(|e| (e, places))
}

pub fn main(args: &[String]) -> Result<(), String> {
    let t0 = Instant::now();
    let points = points()?;
    let stroke = points[0].engine.file.engine.stroke_mm;
    let mut set = liners(stroke);
    if let Some(bad) = args.iter().find(|a| !set.iter().any(|(n, _)| n == *a)) {
        let names: Vec<&str> = set.iter().map(|(n, _)| n.as_str()).collect();
        return Err(format!("no liner {bad:?} in the set: {}", names.join(", ")));
    }
    if !args.is_empty() {
        set.retain(|(n, _)| n == "plain" || args.contains(n));
    }
    let plains: Vec<Plains> = points.iter().map(|_| Mutex::new(BTreeMap::new())).collect();
    let runs: Vec<(usize, usize)> = (0..points.len())
        .flat_map(|p| (0..set.len()).map(move |l| (p, l)))
        .collect();
    let done = Mutex::new(0usize);
    let answers: Vec<(Answer, f64)> = runs
        .par_iter()
        .map(|&(p, l)| {
            let t = Instant::now();
            let a = judge(&points[p], &set[l].1, &plains[p]);
            let s = t.elapsed().as_secs_f64();
            let mut d = done.lock().unwrap_or_else(|e| e.into_inner());
            *d += 1;
            eprintln!(
                "[{}/{}] {} {}: {} ({s:.1} s)",
                *d,
                runs.len(),
                points[p].name,
                set[l].0,
                match &a {
                    Ok(m) => format!("{:.4} J/m, h_min {:.3} µm", m.work_j_per_m, m.h_min_um),
                    Err((e, _)) => e.to_string(),
                }
            );
            (a, s)
        })
        .collect();
    let md = report(&points, &set, &runs, &answers, t0.elapsed().as_secs_f64());
    if !args.is_empty() {
        print!("{md}");
        return Ok(());
    }
    fs::create_dir_all("results/cycle_stress").map_err(|e| e.to_string())?;
    fs::write("results/cycle_stress/README.md", &md).map_err(|e| e.to_string())?;
    print!("{md}");
    eprintln!("wrote results/cycle_stress/README.md");
    Ok(())
}

/// The table: per point and liner its work ratio and least film, or its failure's kind;
/// then the counts by kind and the cost.
fn report(
    points: &[Point],
    set: &[(String, LinerLayout)],
    runs: &[(usize, usize)],
    answers: &[(Answer, f64)],
    wall_s: f64,
) -> String {
    let mut md = String::from("# Every liner through the cycle, wherever the engine runs\n\n");
    md.push_str(
        "`texopt-lab cycle-stress` (about 20 minutes on 2 cores): the example map's five points \
         (studies/engine_gasoline_map.toml) at each point's oil viscosity and at 0.5× and 0.3× it, \
         each with the plain liner, one texture over the whole stroke (l1 = l2 = 0.0092 cm, \
         per = 0.033 cm: the design space's middle lattice) at depths 2, 5 and 10 µm, and the \
         eight banded liners the band search once lost to the film solver (`start` is the \
         search's own start liner). Each judged as the band search judges it: `draft`, two \
         cycles from the plain liner's cyclic state on the same cells. A cell gives the \
         liner's friction work over the plain liner's at that point and its least film (µm), \
         or the kind of its failure.\n\n",
    );
    md.push_str("| point |");
    for (name, _) in set {
        let _ = write!(md, " {name} |");
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(set.len()));
    md.push('\n');
    let mut kinds: BTreeMap<String, usize> = BTreeMap::new();
    for (p, point) in points.iter().enumerate() {
        let _ = write!(md, "| {} |", point.name);
        let plain = runs
            .iter()
            .zip(answers)
            .find(|((q, l), _)| *q == p && *l == 0)
            .and_then(|(_, (a, _))| a.as_ref().ok());
        for (l, _) in set.iter().enumerate() {
            let i = p * set.len() + l;
            let cell = match &answers[i].0 {
                Ok(m) => match plain {
                    Some(pm) if l > 0 => format!(
                        "{:.4} / {:.3}",
                        m.work_j_per_m / pm.work_j_per_m,
                        m.h_min_um
                    ),
                    _ => format!("{:.4} J/m / {:.3}", m.work_j_per_m, m.h_min_um),
                },
                Err((e, places)) => {
                    let k = kind(e, *places);
                    *kinds.entry(k.clone()).or_default() += 1;
                    format!("**{k}**")
                }
            };
            let _ = write!(md, " {cell} |");
        }
        md.push('\n');
    }
    let failed: usize = kinds.values().sum();
    let cpu: f64 = answers.iter().map(|(_, s)| s).sum();
    let _ = writeln!(
        md,
        "\n{} runs, {} failed; {wall_s:.0} s wall ({cpu:.0} s of runs, the plain liner's \
         cyclic run at each point counted in the first run that needed it).\n",
        runs.len(),
        failed
    );
    if !kinds.is_empty() {
        md.push_str("| failure | runs |\n|---|---|\n");
        for (k, n) in &kinds {
            let _ = writeln!(md, "| {k} | {n} |");
        }
        md.push_str("\nThe failures, in full:\n\n");
        for ((p, l), (a, _)) in runs.iter().zip(answers) {
            if let Err((e, _)) = a {
                let _ = writeln!(md, "- {} {}: {e}", points[*p].name, set[*l].0);
            }
        }
    }
    md
}
