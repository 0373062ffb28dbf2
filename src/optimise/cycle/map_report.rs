//! The report of `cycle --bands` (docs/model.md §13): the operating map; per liner (plain,
//! best uniform texture, banded) its time-weighted mean friction power and least film over
//! the map, and per point its friction work, least film and the asperities' share, with the
//! work in each band and between them; the search's front of friction against least film;
//! the figures (front, bands along the stroke, friction force per point).

use super::cells::{change_pct, fixed};
use super::liner::{Liner, Trio};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::angles::CycleSettings;
use super::bands::Banded;
use super::map_search::{MapDesigns, MapEval, MapLiners, OverMap};
use super::transient_report::thinned;
use super::transient_search::metrics_over;
use crate::model::case::Texture;
use crate::model::engine::MapPoint;
use crate::optimise::design_report::{csv_bytes, json_and_md, Column};
use crate::optimise::error::OptimiseError;
use crate::optimise::goal::{pareto, FAILED_COST};
use crate::plot::{self, Chart, Scale, Series, Style};
use crate::study::cycle_cache::CycleFailure;
use crate::time::cycle::{CycleMetrics, CycleRow};

/// The liners in the report's order.
const LINERS: [Liner; 3] = [Liner::Plain, Liner::Uniform, Liner::Banded];

/// One point of the map as it runs.
#[derive(Clone, Debug, Serialize)]
pub struct MapPointRow {
    pub name: String,
    pub share: f64,
    pub rpm: f64,
    pub peak_gas_bar: f64,
    pub viscosity_pa_s: f64,
}

/// A liner at one point: its cycle's figures, work per zone of the banded liner.
#[derive(Clone, Debug, Serialize)]
pub struct PointFigures {
    pub point: String,
    pub work_j_per_m: f64,
    pub mean_power_w_per_m: f64,
    pub h_min_um: f64,
    /// +∞ without contact (written as null).
    #[serde(serialize_with = "crate::finite::unbounded")]
    pub lambda_min: f64,
    pub asperity_share_max: f64,
    pub asperity_work_j_per_m: f64,
    /// Per zone of the banded liner (top band, between, bottom band).
    pub zone_work_j_per_m: Vec<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct MapLinerRow {
    pub liner: &'static str,
    pub design: String,
    /// Per point its figures, or why its run failed.
    pub points: Vec<Result<PointFigures, CycleFailure>>,
    /// Time-weighted mean friction power over the map (W/m), and against the plain liner's
    /// (%), at the report's fidelity; the same change at the search's.
    pub mean_power_w_per_m: Option<f64>,
    pub change_pct: Option<f64>,
    pub searched_change_pct: Option<f64>,
    /// Least film over the map (µm).
    pub worst_film_um: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct MapReport {
    pub name: String,
    pub stroke_mm: f64,
    pub points: Vec<MapPointRow>,
    pub search_fidelity: String,
    pub report_fidelity: String,
    pub particles: usize,
    pub iterations: u64,
    pub min_clearance_um: f64,
    pub banded: Banded,
    pub uniform: Option<Texture>,
    /// Zone boundaries of the banded liner (mm).
    pub zones_mm: Vec<f64>,
    pub liners: Trio<MapLinerRow>,
    /// Banded liners the search judged, feasible ones, and those on its front.
    pub evaluations: usize,
    pub feasible: usize,
    pub front: Vec<MapEval>,
    pub wall_time_s: f64,
    #[serde(skip)]
    all: Vec<MapEval>,
}

fn figures(point: &MapPoint, m: &CycleMetrics) -> PointFigures {
    PointFigures {
        point: point.name.clone(),
        work_j_per_m: m.work_j_per_m,
        mean_power_w_per_m: m.mean_power_w_per_m,
        h_min_um: m.h_min_um,
        lambda_min: m.lambda_min,
        asperity_share_max: m.asperity_share_max,
        asperity_work_j_per_m: m.asperity_work_j_per_m,
        zone_work_j_per_m: m.zone_work_j_per_m.clone(),
    }
}

/// The plain liner's figures at point k, work per zone of the banded liner.
fn plain_figures(l: &MapLiners, k: usize) -> PointFigures {
    let m = metrics_over(&l.plain(k).rows, &l.map[k].engine, &l.zones_cm);
    figures(&l.map[k], &m)
}

fn liner_row(
    liner: Liner,
    design: String,
    over: &OverMap,
    l: &MapLiners,
    searched_ratio: Option<f64>,
) -> MapLinerRow {
    let points = (0..l.map.len())
        .map(|p| {
            over.points[p]
                .as_ref()
                .map(|j| figures(&l.map[p], &j.metrics))
                .map_err(Clone::clone)
        })
        .collect();
    let power = over.mean_power(&l.map);
    MapLinerRow {
        liner: liner.name(),
        design,
        points,
        mean_power_w_per_m: power,
        change_pct: power.and_then(|p| change_pct(p, over.plain_mean_power(&l.map))),
        searched_change_pct: searched_ratio
            .filter(|r| *r < FAILED_COST)
            .map(|r| 100.0 * (r - 1.0)),
        worst_film_um: over.worst_film(),
    }
}

/// The non-dominated liners of the search (least power ratio, largest film ratio), by power.
fn front(log: &[MapEval]) -> Vec<MapEval> {
    let ok: Vec<&MapEval> = log.iter().filter(|e| e.feasible).collect();
    let points: Vec<(f64, f64)> = ok.iter().map(|e| (e.power_ratio, e.film_ratio)).collect();
    let mut f: Vec<MapEval> = pareto(&points).into_iter().map(|i| ok[i].clone()).collect();
    f.sort_by(|a, b| a.power_ratio.total_cmp(&b.power_ratio));
    f.dedup_by(|a, b| a.banded == b.banded);
    f
}

pub fn assemble(s: &CycleSettings, d: &MapDesigns, l: &MapLiners, wall: f64) -> MapReport {
    let zones_mm: Vec<f64> = l.zones_cm.iter().map(|z| 10.0 * z).collect();
    let plain_points = (0..l.map.len()).map(|k| Ok(plain_figures(l, k))).collect();
    let plain_power = l.banded.plain_mean_power(&l.map);
    let plain = MapLinerRow {
        liner: Liner::Plain.name(),
        design: "plain".into(),
        points: plain_points,
        mean_power_w_per_m: Some(plain_power),
        change_pct: Some(0.0),
        searched_change_pct: Some(0.0),
        worst_film_um: Some(l.banded.plain_worst_film()),
    };
    let uniform = match (&l.uniform, &d.uniform) {
        (Some(u), Some((t, c))) => {
            liner_row(Liner::Uniform, t.rounded_label(), u, l, Some(*c))
        }
        _ => MapLinerRow {
            liner: Liner::Uniform.name(),
            design: "none: every band texture over the whole stroke failed or thinned the film too far at the search".into(),
            points: vec![Err(CycleFailure::NotRun); l.map.len()],
            mean_power_w_per_m: None,
            change_pct: None,
            searched_change_pct: None,
            worst_film_um: None,
        },
    };
    let label = match d.banded_cost < FAILED_COST {
        true => d.banded.label(),
        false => format!(
            "{} (the search's best, infeasible: every banded liner judged failed or thinned the film too far at some point)",
            d.banded.label()
        ),
    };
    let liners = Trio {
        plain,
        uniform,
        designed: liner_row(Liner::Banded, label, &l.banded, l, Some(d.banded_cost)),
    };
    let points = l
        .map
        .iter()
        .map(|p| MapPointRow {
            name: p.name.clone(),
            share: p.share,
            rpm: p.engine.file.engine.rpm,
            peak_gas_bar: p
                .engine
                .file
                .gas
                .pressure_bar
                .iter()
                .copied()
                .fold(0.0, f64::max),
            viscosity_pa_s: p.engine.file.oil.viscosity_pa_s,
        })
        .collect();
    MapReport {
        name: s.engine.file.engine.name.clone(),
        stroke_mm: s.engine.file.engine.stroke_mm,
        points,
        search_fidelity: d.fidelity.name().into(),
        report_fidelity: s.search.report_fidelity.name().into(),
        particles: s.search.swarm.particles,
        iterations: s.search.swarm.iterations,
        min_clearance_um: s.min_clearance_um,
        banded: d.banded.clone(),
        uniform: d.uniform.as_ref().map(|u| u.0.clone()),
        zones_mm,
        liners,
        evaluations: d.log.len(),
        feasible: d.log.iter().filter(|e| e.feasible).count(),
        front: front(&d.log),
        wall_time_s: wall,
        all: d.log.clone(),
    }
}

/// The report's tables.
pub fn table(r: &MapReport) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "Operating map of {} ({} point(s); shares of the running time):\n\n| point | share | rpm | peak gas (bar) | viscosity (Pa·s) |\n|---|---|---|---|---|",
        r.name,
        r.points.len()
    );
    for p in &r.points {
        let _ = writeln!(
            t,
            "| {} | {:.3} | {} | {:.1} | {} |",
            p.name, p.share, p.rpm, p.peak_gas_bar, p.viscosity_pa_s
        );
    }
    let _ = writeln!(
        t,
        "\nLiners at {} (searched at {}); mean power: time-weighted over the map; per point work (J/m) / least film (µm) / asperities' peak share (%):\n",
        r.report_fidelity, r.search_fidelity
    );
    let heads: Vec<String> = r.points.iter().map(|p| p.name.clone()).collect();
    let _ = writeln!(
        t,
        "| liner | design | mean power (W/m) | change (%) | change at {} (%) | least film (µm) | {} |\n|---|---|---|---|---|---|{}",
        r.search_fidelity,
        heads.join(" | "),
        "---|".repeat(heads.len())
    );
    for l in r.liners.each() {
        let cells: Vec<String> = l
            .points
            .iter()
            .map(|p| match p {
                Ok(f) => format!(
                    "{:.4} / {:.3} / {:.1}",
                    f.work_j_per_m,
                    f.h_min_um,
                    100.0 * f.asperity_share_max
                ),
                Err(_) => "failed".into(),
            })
            .collect();
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {} | {} |",
            l.liner,
            l.design,
            fixed(l.mean_power_w_per_m, 3),
            fixed(l.change_pct, 3),
            fixed(l.searched_change_pct, 3),
            fixed(l.worst_film_um, 3),
            cells.join(" | ")
        );
    }
    zone_table(&mut t, r);
    let _ = writeln!(
        t,
        "\nSearch: {} banded liners judged ({} feasible: least film at every point above {:.3} µm or the plain liner's), {} on the front; {:.0} s.",
        r.evaluations,
        r.feasible,
        r.min_clearance_um,
        r.front.len(),
        r.wall_time_s
    );
    t
}

/// Per point, the work in each zone of the banded liner for the three liners.
fn zone_table(t: &mut String, r: &MapReport) {
    let z = &r.zones_mm;
    let spans: Vec<String> = z
        .windows(2)
        .map(|w| format!("{:.1}–{:.1} mm", w[0], w[1]))
        .collect();
    let _ = writeln!(
        t,
        "\nFriction work (J/m) while the ring's centre is over each zone of the banded liner:\n\n| point | liner | {} |\n|---|---|{}",
        spans.join(" | "),
        "---|".repeat(spans.len())
    );
    for (k, p) in r.points.iter().enumerate() {
        for l in r.liners.each() {
            if let Ok(f) = &l.points[k] {
                let w: Vec<String> = f
                    .zone_work_j_per_m
                    .iter()
                    .map(|w| format!("{w:.4}"))
                    .collect();
                let _ = writeln!(t, "| {} | {} | {} |", p.name, l.liner, w.join(" | "));
            }
        }
    }
}

const FRONT_COLUMNS: [Column<MapEval>; 6] = [
    ("power_ratio", |e| e.power_ratio.to_string()),
    ("film_ratio", |e| e.film_ratio.to_string()),
    ("feasible", |e| e.feasible.to_string()),
    ("why_infeasible", |e| {
        e.why.as_ref().map(ToString::to_string).unwrap_or_default()
    }),
    ("bands", |e| e.banded.label()),
    ("band_mm", |e| {
        let b: Vec<String> = e
            .banded
            .bands
            .iter()
            .map(|b| format!("{}-{}", b.start_mm, b.end_mm))
            .collect();
        b.join(" ")
    }),
];

/// One step of a liner's last cycle at a point.
struct PointStep {
    point: String,
    liner: &'static str,
    row: CycleRow,
}

/// A value to 6 significant digits (the steps' CSV stays small).
fn sig6(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let decimals = (5 - x.abs().log10().floor() as i32).clamp(0, 17) as usize;
    format!("{x:.decimals$}")
}

const STEP_COLUMNS: [Column<PointStep>; 8] = [
    ("point", |x| x.point.to_string()),
    ("liner", |x| x.liner.to_string()),
    ("crank_deg", |x| sig6(x.row.crank_deg)),
    ("position_mm", |x| sig6(x.row.position_mm)),
    ("h_min_um", |x| sig6(x.row.h_min_um)),
    ("friction_n_m", |x| sig6(x.row.friction_n_per_m)),
    ("asperity_friction_n_m", |x| {
        sig6(x.row.asperity_friction_n_per_m)
    }),
    ("asperity_share", |x| sig6(x.row.asperity_share)),
];

/// Per point, each liner's last cycle (None where it failed or is not reported).
fn runs<'a>(l: &'a MapLiners, k: usize) -> Trio<Option<&'a [CycleRow]>> {
    let of = |o: &'a OverMap| o.points[k].as_ref().ok().map(|j| j.rows.as_slice());
    Trio {
        plain: Some(l.plain(k).rows.as_slice()),
        uniform: l.uniform.as_ref().and_then(of),
        designed: of(&l.banded),
    }
}

/// Writes the report's files into `dir`: `cycle_NAME_bands` .md, .json, _front.csv,
/// _steps.csv, _front.png, _bands.png and _force_POINT.png per point.
pub fn write(dir: &Path, r: &MapReport, l: &MapLiners) -> Result<Vec<PathBuf>, OptimiseError> {
    let base = format!("cycle_{}_bands", r.name);
    let md = format!(
        "# Where to texture `{}`: bands over its operating map\n\n{}",
        r.name,
        table(r)
    );
    let stem = json_and_md(dir, &base, r, md)?;
    crate::output::write(&stem("_front.csv"), csv_bytes(&FRONT_COLUMNS, &r.all)?)?;
    let mut steps: Vec<PointStep> = Vec::new();
    for k in 0..l.map.len() {
        for (liner, rows) in runs(l, k).named(Liner::Banded) {
            let rows = rows.unwrap_or_default();
            steps.extend(thinned(rows).map(|row| PointStep {
                point: l.map[k].name.clone(),
                liner: liner.name(),
                row: *row,
            }));
        }
    }
    crate::output::write(&stem("_steps.csv"), csv_bytes(&STEP_COLUMNS, &steps)?)?;
    let mut out: Vec<PathBuf> = [".json", ".md", "_front.csv", "_steps.csv"]
        .iter()
        .map(|x| stem(x))
        .collect();
    front_plot(&stem("_front.png"), r)?;
    bands_plot(&stem("_bands.png"), r)?;
    out.extend([stem("_front.png"), stem("_bands.png")]);
    for k in 0..l.map.len() {
        let path = stem(&format!("_force_{}.png", l.map[k].name));
        force_plot(&path, r, l, k)?;
        out.push(path);
    }
    Ok(out)
}

fn chart<'a>(title: &'a str, x: &'a str, y: &'a str) -> Chart<'a> {
    Chart {
        title,
        x_label: x,
        y_label: y,
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
    }
}

/// Friction power against least film, both against the plain liner's (%): every feasible
/// liner the search judged, its front, the plain liner at the origin and the reported liners.
fn front_plot(path: &Path, r: &MapReport) -> Result<(), OptimiseError> {
    let pct = |e: &MapEval| (100.0 * (e.power_ratio - 1.0), 100.0 * (e.film_ratio - 1.0));
    let all: Vec<(f64, f64)> = r.all.iter().filter(|e| e.feasible).map(pct).collect();
    let front: Vec<(f64, f64)> = r.front.iter().map(pct).collect();
    let plain_film = r.liners.plain.worst_film_um.unwrap_or(f64::NAN);
    let reported: Vec<(f64, f64)> = [&r.liners.uniform, &r.liners.designed]
        .into_iter()
        .filter_map(|l| Some((l.change_pct?, 100.0 * (l.worst_film_um? / plain_film - 1.0))))
        .collect();
    let origin = [(0.0, 0.0)];
    let series = [
        Series {
            name: format!("banded liners judged at {}", r.search_fidelity),
            points: &all,
            style: Style::Markers,
            colour: 7,
        },
        Series {
            name: "their front".into(),
            points: &front,
            style: Style::Line,
            colour: 0,
        },
        Series {
            name: format!("uniform and banded best at {}", r.report_fidelity),
            points: &reported,
            style: Style::Rings,
            colour: 2,
        },
        Series {
            name: "plain liner".into(),
            points: &origin,
            style: Style::Thick,
            colour: 1,
        },
    ];
    let title = format!(
        "{}: friction against least film over the operating map",
        r.name
    );
    plot::xy(
        path,
        &chart(
            &title,
            "change in time-weighted friction power (%)",
            "change in least film over the map (%)",
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}

/// The front's liners' bands along the stroke, one line each (best power first at the top).
fn bands_plot(path: &Path, r: &MapReport) -> Result<(), OptimiseError> {
    let n = r.front.len();
    let segs: Vec<[(f64, f64); 2]> = r
        .front
        .iter()
        .enumerate()
        .flat_map(|(k, e)| {
            let y = (n - k) as f64;
            e.banded
                .bands
                .iter()
                .map(move |b| [(b.start_mm, y), (b.end_mm, y)])
        })
        .collect();
    let stroke = [(0.0, 0.0), (r.stroke_mm, 0.0)];
    let mut series = vec![Series {
        name: "stroke (plain)".into(),
        points: &stroke,
        style: Style::Line,
        colour: 7,
    }];
    for (k, s) in segs.iter().enumerate() {
        series.push(Series {
            name: if k == 0 {
                "bands of the front's liners (top: least friction)".into()
            } else {
                String::new()
            },
            points: s,
            style: Style::Thick,
            colour: 0,
        });
    }
    let title = format!("{}: where the front's liners are textured", r.name);
    plot::xy(
        path,
        &chart(
            &title,
            "distance from the ring's top-dead-centre position (mm)",
            "liner on the front",
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}

type Curve = Vec<(f64, f64)>;

/// Friction force against crank angle at point k: each liner's, and its asperities' part.
fn force_plot(path: &Path, r: &MapReport, l: &MapLiners, k: usize) -> Result<(), OptimiseError> {
    let curves: Vec<(usize, Curve, Curve)> = runs(l, k)
        .each()
        .into_iter()
        .enumerate()
        .filter_map(|(i, rows)| {
            let rows = (*rows)?;
            let f = thinned(rows)
                .map(|x| (x.crank_deg, x.friction_n_per_m))
                .collect();
            let a = thinned(rows)
                .map(|x| (x.crank_deg, x.asperity_friction_n_per_m))
                .collect();
            Some((i, f, a))
        })
        .collect();
    let mut series = Vec::new();
    for (i, f, a) in &curves {
        let colour = [1, 0, 2][*i];
        series.push(Series {
            name: LINERS[*i].name().into(),
            points: f,
            style: if *i == 0 { Style::Thick } else { Style::Line },
            colour,
        });
        series.push(Series {
            name: format!("{}: asperities' part", LINERS[*i].name()),
            points: a,
            style: Style::Faint,
            colour,
        });
    }
    let p = &r.points[k];
    let title = format!(
        "Friction force on the ring, {} at {} ({} rpm)",
        r.name, p.name, p.rpm
    );
    plot::xy(
        path,
        &chart(
            &title,
            "crank angle from firing top dead centre (°)",
            "friction force per unit length (N/m)",
        ),
        &series,
    )
    .map_err(OptimiseError::Output)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_keep_six_significant_digits() {
        assert_eq!(sig6(0.6332483694565367), "0.633248");
        assert_eq!(sig6(-2.9348739205225476), "-2.93487");
        assert_eq!(sig6(123.456789), "123.457");
        assert_eq!(sig6(0.0), "0");
        assert_eq!(sig6(1.2e-7), "0.000000120000");
    }
}
