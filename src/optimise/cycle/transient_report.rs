//! The report of the transient `cycle` (docs/model.md §12): per liner the friction work, mean
//! power per ring and FMEP, the thinnest film and Λ, the asperities' share; per zone the work
//! of each liner and the texture kept; every step of the last cycle, the oil map and the
//! cycle-to-cycle convergence as CSV; the figures an engine engineer reads.

use super::cells::{change_pct, signed};
use super::liner::{Liner, Trio};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::angles::{CycleSettings, Designs};
use super::transient_liners::{LinerCycle, TransientLiners};
use crate::model::case::Texture;
use crate::model::engine::zone_label;
use crate::model::flow_factors::{film_label, FlowFactors};
use crate::optimise::design_report::{csv_bytes, json_and_md, Column};
use crate::optimise::error::OptimiseError;
use crate::plot::{self, Chart, Scale, Series, Style};
use crate::time::cycle::{CycleMetrics, CycleRow, CycleSummary, Drive, Regime, SETTLE_CYCLES};

/// The liners in the report's order.
const LINERS: [Liner; 3] = [Liner::Plain, Liner::Uniform, Liner::Zoned];

#[derive(Clone, Debug, Serialize)]
pub struct TransientZone {
    /// 1 at top dead centre.
    pub zone: usize,
    pub from_mm: f64,
    pub to_mm: f64,
    /// The texture kept (None: plain) and whose it is, and the zone's own search's best
    /// texture, which the zoned designs' run carried there.
    pub texture: Option<Texture>,
    pub kept: &'static str,
    pub searched: Option<Texture>,
    /// Friction work while the ring's centre is over the zone (J/m): plain, uniform, zoned.
    pub work_j_per_m: Trio<f64>,
    /// The zoned liner's against the plain liner's there (%).
    pub change_pct: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct TransientLinerRow {
    pub liner: &'static str,
    #[serde(flatten)]
    pub metrics: CycleMetrics,
    /// Against the plain liner (%).
    pub change_pct: Option<f64>,
    /// Cycles run, whether the last repeated the one before, and its changes.
    pub cycles: usize,
    pub cyclic: bool,
    /// The last cycle's changes (NaN without a cycle, written as null).
    #[serde(serialize_with = "crate::finite::absent")]
    pub work_change: f64,
    #[serde(serialize_with = "crate::finite::absent")]
    pub oil_change: f64,
    /// Largest relative oil defect of a cycle (film + liner − supply + scraped + thrown).
    pub oil_defect: f64,
    pub wall_s: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct TransientReport {
    pub name: String,
    pub rpm: f64,
    pub bore_mm: f64,
    pub stroke_mm: f64,
    pub fidelity: String,
    /// The mesh given in place of the tiers' (N1×N2), if any (absent from the JSON if none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<String>,
    /// How the zones were searched: the search's fidelity and swarm.
    pub search_fidelity: String,
    pub particles: usize,
    pub iterations: u64,
    /// Share of the cycle outside the model: none, the dead centres included.
    pub excluded_cycle_fraction: f64,
    /// The film's flow factors (docs/model.md §11), None for the film of smooth surfaces.
    pub flow_factors: Option<FlowFactors>,
    /// The uniform texture kept (None: it does not beat the plain liner) and the one judged.
    pub uniform: Option<Texture>,
    pub uniform_searched: Option<Texture>,
    pub zones: Vec<TransientZone>,
    pub liners: Vec<TransientLinerRow>,
    pub wall_time_s: f64,
    #[serde(skip)]
    runs: Trio<LinerCycle>,
}

fn liner_row(k: usize, r: &LinerCycle, plain: f64) -> TransientLinerRow {
    let last = r.outcome.cycles.last();
    TransientLinerRow {
        liner: LINERS[k].name(),
        metrics: r.metrics.clone(),
        change_pct: change_pct(r.metrics.work_j_per_m, plain),
        cycles: r.outcome.cycles.len(),
        cyclic: r.outcome.cyclic(),
        work_change: last.map_or(f64::NAN, |c| c.work_change),
        oil_change: last.map_or(f64::NAN, |c| c.oil_change),
        oil_defect: r
            .outcome
            .cycles
            .iter()
            .map(|c| c.oil.defect())
            .fold(0.0, f64::max),
        wall_s: r.wall_s,
    }
}

/// The report of the three liners.
pub fn assemble(s: &CycleSettings, d: &Designs, t: &TransientLiners, wall: f64) -> TransientReport {
    let runs = t.runs.clone();
    let plain = runs.plain.metrics.work_j_per_m;
    let b = s.zones.bounds_mm();
    let zones = (0..b.len() - 1)
        .map(|z| {
            let work = runs.as_ref().map(|r| r.metrics.zone_work_j_per_m[z]);
            TransientZone {
                zone: z + 1,
                from_mm: b[z],
                to_mm: b[z + 1],
                texture: d.zones[z].clone(),
                kept: t.kept[z].label(),
                searched: d.candidates.get(z).cloned().flatten(),
                change_pct: change_pct(work.designed, work.plain),
                work_j_per_m: work,
            }
        })
        .collect();
    let e = &s.engine.file.engine;
    TransientReport {
        name: e.name.clone(),
        rpm: e.rpm,
        bore_mm: e.bore_mm,
        stroke_mm: e.stroke_mm,
        fidelity: s.search.report_fidelity.name().into(),
        mesh: match (s.search.overrides.n1, s.search.overrides.n2) {
            (None, None) => None,
            (n1, n2) => Some(format!(
                "{}×{}",
                n1.map_or("the tier's".into(), |n| n.to_string()),
                n2.map_or("the tier's".into(), |n| n.to_string())
            )),
        },
        search_fidelity: s.search.search_fidelity.name().into(),
        particles: s.search.swarm.particles,
        iterations: s.search.swarm.iterations,
        excluded_cycle_fraction: 0.0,
        flow_factors: super::transient_liners::ring_case(s, &Drive::new(&s.engine)).flow,
        uniform: d.uniform.clone(),
        uniform_searched: d.uniform_candidate.clone(),
        zones,
        liners: (0..3)
            .map(|k| liner_row(k, runs.each()[k], plain))
            .collect(),
        wall_time_s: wall,
        runs,
    }
}

fn texture_label(t: &Option<Texture>) -> String {
    t.as_ref().map_or("plain".into(), |t| t.rounded_label())
}

/// The tables: liners, then zones.
pub fn table(r: &TransientReport) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "Engine `{}` at {} rpm, the cycle as one transient at {}{} (no crank angle excluded), on {}. Each zone's texture searched over the whole cycle at {} ({} particles × {} iterations, each candidate {} cycles from the plain liner's cyclic state).\n",
        r.name,
        r.rpm,
        r.fidelity,
        r.mesh
            .as_ref()
            .map_or(String::new(), |m| format!(" on the mesh given, {m} (the tiers' errors do not hold)")),
        film_label(r.flow_factors.as_ref()),
        r.search_fidelity,
        r.particles,
        r.iterations,
        SETTLE_CYCLES
    );
    let _ = writeln!(o, "| liner | friction work (J/m) | asperities' share | mean power per ring (W) | FMEP (kPa) | vs plain | h_min (µm) at | Λ_min | asperity load, max | time in mixed / boundary | cycles |");
    let _ = writeln!(o, "|---|---|---|---|---|---|---|---|---|---|---|");
    for l in &r.liners {
        let m = &l.metrics;
        let _ = writeln!(
            o,
            "| {} | {:.4} | {:.1} % | {:.2} | {:.3} | {} % | {:.3} at {:.1}° | {:.2} | {:.1} % | {:.1} % / {:.1} % | {}{} |",
            l.liner,
            m.work_j_per_m,
            100.0 * m.asperity_work_j_per_m / m.work_j_per_m.max(f64::MIN_POSITIVE),
            m.ring_power_w,
            m.fmep_kpa,
            signed(l.change_pct, 2),
            m.h_min_um,
            m.h_min_deg,
            m.lambda_min,
            100.0 * m.asperity_share_max,
            100.0 * m.regime_time_fraction[Regime::Mixed as usize],
            100.0 * m.regime_time_fraction[Regime::Boundary as usize],
            l.cycles,
            if l.cyclic { "" } else { " (not cyclic)" }
        );
    }
    let _ = writeln!(o, "\n| zone | mm from TDC | kept | texture | its search's best | work plain / uniform / zoned (J/m) | zoned vs plain |");
    let _ = writeln!(o, "|---|---|---|---|---|---|---|");
    let bounds: Vec<f64> = std::iter::once(r.zones.first().map_or(0.0, |z| z.from_mm))
        .chain(r.zones.iter().map(|z| z.to_mm))
        .collect();
    for z in &r.zones {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {:.4} / {:.4} / {:.4} | {} % |",
            z.zone,
            zone_label(&bounds, z.zone - 1),
            z.kept,
            texture_label(&z.texture),
            texture_label(&z.searched),
            z.work_j_per_m.plain,
            z.work_j_per_m.uniform,
            z.work_j_per_m.designed,
            signed(z.change_pct, 2)
        );
    }
    let _ = writeln!(
        o,
        "\nuniform texture judged: {} ({})",
        texture_label(&r.uniform_searched),
        if r.uniform.is_some() {
            "kept: it beats the plain liner over the cycle"
        } else {
            "not kept"
        }
    );
    o
}

/// A step of one liner's last cycle (a CSV row).
struct LinerStep {
    liner: &'static str,
    row: CycleRow,
}

const STEP_COLUMNS: [Column<LinerStep>; 17] = [
    ("liner", |x| x.liner.to_string()),
    ("crank_deg", |x| x.row.crank_deg.to_string()),
    ("position_mm", |x| x.row.position_mm.to_string()),
    ("speed_m_s", |x| x.row.u_ms.to_string()),
    ("load_n_m", |x| x.row.load_n_per_m.to_string()),
    ("p_above_bar", |x| x.row.p_above_bar.to_string()),
    ("p_below_bar", |x| x.row.p_below_bar.to_string()),
    ("z_um", |x| x.row.z_um.to_string()),
    ("h_min_um", |x| x.row.h_min_um.to_string()),
    ("lambda", |x| x.row.lambda.to_string()),
    ("regime", |x| {
        format!("{:?}", Regime::of(x.row.lambda)).to_lowercase()
    }),
    ("friction_n_m", |x| x.row.friction_n_per_m.to_string()),
    ("asperity_friction_n_m", |x| {
        x.row.asperity_friction_n_per_m.to_string()
    }),
    ("asperity_load_share", |x| x.row.asperity_share.to_string()),
    ("power_w_m", |x| x.row.power_w_per_m.to_string()),
    ("oil_met_um", |x| x.row.oil_met_um.to_string()),
    ("oil_left_um", |x| x.row.oil_left_um.to_string()),
];

struct CycleLine {
    liner: &'static str,
    c: CycleSummary,
}

const CYCLE_COLUMNS: [Column<CycleLine>; 6] = [
    ("liner", |x| x.liner.to_string()),
    ("cycle", |x| (x.c.index + 1).to_string()),
    ("friction_work_j_m", |x| {
        x.c.friction_work_j_per_m.to_string()
    }),
    ("work_change", |x| x.c.work_change.to_string()),
    ("oil_map_change", |x| x.c.oil_change.to_string()),
    ("oil_defect", |x| x.c.oil.defect().to_string()),
];

/// JSON, Markdown, CSVs (steps, oil map, convergence) and figures.
pub fn write(dir: &Path, r: &TransientReport) -> Result<Vec<PathBuf>, OptimiseError> {
    let base = format!("cycle_{}", r.name);
    let md = format!("# Cycle `{}`\n\n{}", r.name, table(r));
    let stem = json_and_md(dir, &base, r, md)?;
    let steps: Vec<LinerStep> = (0..3)
        .flat_map(|k| {
            thinned(&r.runs.each()[k].outcome.rows).map(move |row| LinerStep {
                liner: LINERS[k].name(),
                row: *row,
            })
        })
        .collect();
    crate::output::write(&stem("_steps.csv"), csv_bytes(&STEP_COLUMNS, &steps)?)?;
    let cycles: Vec<CycleLine> = (0..3)
        .flat_map(|k| {
            r.runs.each()[k]
                .outcome
                .cycles
                .iter()
                .map(move |c| CycleLine {
                    liner: LINERS[k].name(),
                    c: c.clone(),
                })
        })
        .collect();
    crate::output::write(&stem("_cycles.csv"), csv_bytes(&CYCLE_COLUMNS, &cycles)?)?;
    crate::output::write(&stem("_oil.csv"), oil_csv(r)?)?;
    let figures = [
        ("_force.png", force_plot as Figure),
        ("_film.png", film_plot),
        ("_asperity.png", asperity_plot),
        ("_oil.png", oil_plot),
        ("_convergence.png", convergence_plot),
    ];
    let mut out: Vec<PathBuf> = [".json", ".md", "_steps.csv", "_cycles.csv", "_oil.csv"]
        .iter()
        .map(|x| stem(x))
        .collect();
    for (suffix, draw) in figures {
        draw(&stem(suffix), r)?;
        out.push(stem(suffix));
    }
    Ok(out)
}

type Figure = fn(&Path, &TransientReport) -> Result<(), OptimiseError>;

/// Crank angle between the rows the steps' CSV keeps (degrees): a textured liner takes tens
/// of thousands of steps a cycle, and the file stays small.
const CSV_EVERY_DEG: f64 = 0.25;

/// The rows of a cycle, the first at or after each multiple of [`CSV_EVERY_DEG`] (every row of
/// a run whose steps are longer).
pub(super) fn thinned(rows: &[CycleRow]) -> impl Iterator<Item = &CycleRow> {
    let mut next = f64::NEG_INFINITY;
    rows.iter().filter(move |r| {
        let keep = r.crank_deg >= next;
        if keep {
            next = (r.crank_deg / CSV_EVERY_DEG).floor() * CSV_EVERY_DEG + CSV_EVERY_DEG;
        }
        keep
    })
}

fn oil_csv(r: &TransientReport) -> Result<Vec<u8>, OptimiseError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(["y_mm", "plain_um", "uniform_um", "zoned_um"]);
    let o = &r.runs.plain.outcome;
    for (k, y) in o.oil_y_cm.iter().enumerate() {
        let cell = |i: usize| {
            r.runs.each()[i]
                .outcome
                .oil_um
                .get(k)
                .map_or(String::new(), |v| v.to_string())
        };
        let _ = w.write_record([(10.0 * y).to_string(), cell(0), cell(1), cell(2)]);
    }
    w.into_inner()
        .map_err(|e| OptimiseError::Csv(e.into_error()))
}

fn chart<'a>(title: &'a str, x: &'a str, y: &'a str, y_scale: Scale) -> Chart<'a> {
    Chart {
        title,
        x_label: x,
        y_label: y,
        x_scale: Scale::Linear,
        y_scale,
    }
}

const CRANK: &str = "crank angle from firing top dead centre (°)";

/// One series per liner of `f(row)` against crank angle (the rows the CSV keeps).
fn per_liner(r: &TransientReport, f: impl Fn(&CycleRow) -> f64) -> Vec<Vec<(f64, f64)>> {
    r.runs
        .each()
        .into_iter()
        .map(|l| {
            thinned(&l.outcome.rows)
                .map(|x| (x.crank_deg, f(x)))
                .collect()
        })
        .collect()
}

fn liner_series<'a>(pts: &'a [Vec<(f64, f64)>], what: &str) -> Vec<Series<'a>> {
    pts.iter()
        .enumerate()
        .map(|(k, p)| Series {
            name: format!("{}{what}", LINERS[k].name()),
            points: p,
            style: if k == 0 { Style::Thick } else { Style::Line },
            colour: [1, 0, 2][k],
        })
        .collect()
}

fn force_plot(path: &Path, r: &TransientReport) -> Result<(), OptimiseError> {
    let total = per_liner(r, |x| x.friction_n_per_m);
    let asperity = per_liner(r, |x| x.asperity_friction_n_per_m);
    let mut series = liner_series(&total, "");
    for (k, p) in asperity.iter().enumerate() {
        series.push(Series {
            name: format!("{}: asperities' part", LINERS[k].name()),
            points: p,
            style: Style::Faint,
            colour: [1, 0, 2][k],
        });
    }
    let title = format!(
        "Friction force on the ring, {} at {} rpm (positive towards the crankcase)",
        r.name, r.rpm
    );
    plot::xy(
        path,
        &chart(
            &title,
            CRANK,
            "friction force per unit length (N/m)",
            Scale::Linear,
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}

fn film_plot(path: &Path, r: &TransientReport) -> Result<(), OptimiseError> {
    let lambda = per_liner(r, |x| x.lambda);
    let mut series = liner_series(&lambda, "");
    let bands = [
        vec![(0.0, 3.0), (720.0, 3.0)],
        vec![(0.0, 1.0), (720.0, 1.0)],
    ];
    series.push(Series {
        name: "Λ = 3: hydrodynamic above, mixed below".into(),
        points: &bands[0],
        style: Style::Faint,
        colour: 4,
    });
    series.push(Series {
        name: "Λ = 1: boundary below".into(),
        points: &bands[1],
        style: Style::Faint,
        colour: 3,
    });
    let title = format!("Film parameter Λ = h_min/σ over the cycle, {}", r.name);
    plot::xy(
        path,
        &chart(&title, CRANK, "Λ = h_min/σ (h_min in µm: Λ·σ)", Scale::Log),
        &series,
    )
    .map_err(OptimiseError::Output)
}

fn asperity_plot(path: &Path, r: &TransientReport) -> Result<(), OptimiseError> {
    let share = per_liner(r, |x| 100.0 * x.asperity_share);
    let series = liner_series(&share, "");
    let title = format!("Share of the ring's load on the asperities, {}", r.name);
    plot::xy(
        path,
        &chart(
            &title,
            CRANK,
            "asperity load / ring load (%)",
            Scale::Linear,
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}

fn oil_plot(path: &Path, r: &TransientReport) -> Result<(), OptimiseError> {
    let pts: Vec<Vec<(f64, f64)>> = r
        .runs
        .each()
        .into_iter()
        .map(|l| {
            l.outcome
                .oil_y_cm
                .iter()
                .zip(&l.outcome.oil_um)
                .map(|(y, d)| (10.0 * y, *d))
                .collect()
        })
        .collect();
    let series = liner_series(&pts, "");
    let title = format!("Oil left on the liner after the cycle, {}", r.name);
    plot::xy(
        path,
        &chart(
            &title,
            "distance along the liner from the ring's top-dead-centre position (mm)",
            "oil layer (µm)",
            Scale::Linear,
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}

fn convergence_plot(path: &Path, r: &TransientReport) -> Result<(), OptimiseError> {
    let per_cycle = |f: fn(&CycleSummary) -> f64| -> Vec<Vec<(f64, f64)>> {
        r.runs
            .each()
            .into_iter()
            .map(|l| {
                let c = &l.outcome.cycles;
                c.iter().map(|c| ((c.index + 1) as f64, f(c))).collect()
            })
            .collect()
    };
    let (work, oil) = (per_cycle(|c| c.work_change), per_cycle(|c| c.oil_change));
    let mut series = liner_series(&work, ": friction work");
    for (k, p) in oil.iter().enumerate() {
        series.push(Series {
            name: format!("{}: oil map", LINERS[k].name()),
            points: p,
            style: Style::Markers,
            colour: [1, 0, 2][k],
        });
    }
    let title = format!("Cycle-to-cycle change, {}", r.name);
    plot::xy(
        path,
        &chart(
            &title,
            "cycle",
            "relative change from the cycle before",
            Scale::Log,
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}
