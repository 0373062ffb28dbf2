//! The report of `cycle`: per zone and per liner (plain, uniform best, zoned) the friction
//! work over the cycle, the mean friction power and the least clearance; every crank angle
//! with its operating point, its exclusion or its forces; the tables, JSON, CSV and figures.

use crate::model::flow_factors::{film_label, FlowFactors};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::angles::{Confirmation, CycleSettings, Designs, Exclusion, LinerRuns, Runs};
use super::cells::{change_pct, or_dash};
use super::liner::{Liner, Trio};
use crate::model::case::Texture;
use crate::model::engine::zone_label;
use crate::optimise::design_report::{csv_bytes, json_and_md, Column};
use crate::optimise::error::OptimiseError;
use crate::plot::{self, Chart, Scale, Series, Style};

#[derive(Clone, Debug, Serialize)]
pub struct ZoneRow {
    /// 1 at top dead centre.
    pub zone: usize,
    pub from_mm: f64,
    pub to_mm: f64,
    /// None: the plain liner.
    pub texture: Option<Texture>,
    pub angles_inside: usize,
    pub angles_excluded: usize,
    /// Friction work per unit circumferential length over the cycle (J/m), plain and zoned;
    /// none where no angle of the zone is inside the model.
    pub work_plain_j_per_m: Option<f64>,
    pub work_zoned_j_per_m: Option<f64>,
    pub change_pct: Option<f64>,
    /// Least clearance of the zoned liner over the zone's angles (µm), if it has a run.
    pub c_min_um: Option<f64>,
    /// The zone's own searched design at the report's fidelity and step.
    pub searched: Confirmation,
}

#[derive(Clone, Debug, Serialize)]
pub struct LinerRow {
    pub liner: String,
    pub work_j_per_m: f64,
    /// Mean friction power over the cycle, per unit length (W/m) and for the ring (W).
    pub mean_power_w_per_m: f64,
    pub ring_power_w: f64,
    /// Against the plain liner; none if the plain liner has no work to compare with.
    pub change_pct: Option<f64>,
    /// Least clearance over the angles with a run (µm), if any.
    pub c_min_um: Option<f64>,
    /// Angles inside the model where the liner's run failed (its work leaves them out).
    pub failed_angles: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct SampleRow {
    pub crank_deg: f64,
    pub position_mm: f64,
    pub zone: usize,
    pub speed_ms: f64,
    pub load_n_per_m: f64,
    pub stribeck: f64,
    pub d_oil_um: f64,
    /// Why the angle is outside the hydrodynamic model (then no number is reported).
    pub excluded: Option<Exclusion>,
    /// Friction force (N/m) and clearance (µm) of the plain, uniform and zoned liners.
    pub force_n_per_m: Trio<Option<f64>>,
    pub c_min_um: Trio<Option<f64>>,
}

#[derive(Clone, Debug, Serialize)]
pub struct CycleReport {
    pub name: String,
    pub rpm: f64,
    pub stroke_mm: f64,
    pub bore_mm: f64,
    pub step_deg: f64,
    pub design_step_deg: f64,
    pub search_fidelity: String,
    pub report_fidelity: String,
    pub min_clearance_um: f64,
    pub uniform: Option<Texture>,
    /// The uniform search's design at the report's fidelity and step.
    pub uniform_searched: Confirmation,
    pub zones: Vec<ZoneRow>,
    pub liners: Vec<LinerRow>,
    /// Share of the cycle's time, and of its sliding distance, outside the model.
    pub excluded_cycle_fraction: f64,
    pub excluded_sliding_fraction: f64,
    /// The evaluated angles' film (docs/model.md §11, "Flow factors"), None when smooth.
    pub flow_factors: Option<FlowFactors>,
    pub samples: Vec<SampleRow>,
    pub wall_time_s: f64,
}

/// Every crank angle: its operating point, its exclusion or the three liners' forces and
/// clearances.
fn samples(s: &CycleSettings, ev: &LinerRuns) -> Vec<SampleRow> {
    ev.points
        .iter()
        .enumerate()
        .map(|(k, p)| SampleRow {
            crank_deg: p.sample.crank_deg,
            position_mm: p.sample.position_mm,
            zone: p.sample.zone + 1,
            speed_ms: p.sample.speed_ms,
            load_n_per_m: p.sample.load_n_per_m,
            stribeck: s.engine.file.oil.viscosity_pa_s * p.sample.speed_ms / p.sample.load_n_per_m,
            d_oil_um: p.sample.d_oil_um,
            excluded: p.excluded.clone(),
            force_n_per_m: ev.liners.as_ref().map(|l| l[k].as_ref().map(|x| x.1)),
            c_min_um: ev.liners.as_ref().map(|l| l[k].as_ref().map(|x| x.0.c_min)),
        })
        .collect()
}

/// The report of the evaluated liners.
pub fn assemble(s: &CycleSettings, d: &Designs, ev: &LinerRuns, wall: f64) -> CycleReport {
    let e = &s.engine.file.engine;
    let pts = &ev.points;
    // (+ 0.0: an empty sum is -0.0, which would print as "-0.0".)
    let work = |runs: &Runs, zone: Option<usize>| -> f64 {
        pts.iter()
            .zip(runs)
            .filter(|(p, _)| zone.is_none_or(|z| p.sample.zone == z))
            .filter_map(|(p, r)| r.as_ref().map(|(_, f)| f * p.distance_m))
            .sum::<f64>()
            + 0.0
    };
    let least = |runs: &Runs, zone: Option<usize>| -> Option<f64> {
        pts.iter()
            .zip(runs)
            .filter(|(p, _)| zone.is_none_or(|z| p.sample.zone == z))
            .filter_map(|(_, r)| r.as_ref().map(|(o, _)| o.c_min))
            .min_by(f64::total_cmp)
    };
    let zones = (0..d.zones.len())
        .map(|z| {
            let inside = pts
                .iter()
                .filter(|p| p.sample.zone == z && p.excluded.is_none())
                .count();
            let all = pts.iter().filter(|p| p.sample.zone == z).count();
            let (wp, wz) = (
                work(&ev.liners.plain, Some(z)),
                work(&ev.liners.designed, Some(z)),
            );
            let weighed = inside > 0;
            ZoneRow {
                zone: z + 1,
                from_mm: s.zones.bounds_mm()[z],
                to_mm: s.zones.bounds_mm()[z + 1],
                texture: d.zones[z].clone(),
                angles_inside: inside,
                angles_excluded: all - inside,
                work_plain_j_per_m: weighed.then_some(wp),
                work_zoned_j_per_m: weighed.then_some(wz),
                change_pct: change_pct(wz, wp).filter(|_| weighed),
                c_min_um: least(&ev.liners.designed, Some(z)),
                searched: ev.confirmed[z].clone(),
            }
        })
        .collect();
    let cycle_s = 120.0 / e.rpm;
    let circumference = std::f64::consts::PI * e.bore_mm * 1e-3;
    let w0 = work(&ev.liners.plain, None);
    let liners = ev
        .liners
        .named(Liner::Zoned)
        .into_iter()
        .map(|(liner, runs)| {
            let w = work(runs, None);
            LinerRow {
                liner: liner.name().into(),
                work_j_per_m: w,
                mean_power_w_per_m: w / cycle_s,
                ring_power_w: w / cycle_s * circumference,
                change_pct: change_pct(w, w0),
                c_min_um: least(runs, None),
                failed_angles: pts
                    .iter()
                    .zip(runs)
                    .filter(|(p, r)| p.excluded.is_none() && r.is_none())
                    .count(),
            }
        })
        .collect();
    let out = pts.iter().filter(|p| p.excluded.is_some());
    let total: f64 = pts.iter().map(|p| p.distance_m).sum();
    let samples = samples(s, ev);
    CycleReport {
        name: e.name.clone(),
        rpm: e.rpm,
        stroke_mm: e.stroke_mm,
        bore_mm: e.bore_mm,
        step_deg: s.step_deg,
        design_step_deg: s.design_step_deg,
        search_fidelity: s.search.search_fidelity.name().into(),
        report_fidelity: s.search.report_fidelity.name().into(),
        min_clearance_um: s.min_clearance_um,
        uniform: d.uniform.clone(),
        uniform_searched: ev.confirmed[d.zones.len()].clone(),
        zones,
        liners,
        excluded_cycle_fraction: out.clone().count() as f64 / pts.len() as f64,
        excluded_sliding_fraction: out.map(|p| p.distance_m).sum::<f64>() / total,
        flow_factors: pts.iter().find_map(|p| p.base.flow),
        samples,
        wall_time_s: wall,
    }
}

fn texture_label(t: &Option<Texture>) -> String {
    t.as_ref()
        .map_or("plain liner".into(), Texture::rounded_label)
}

/// A searched design and what the report's fidelity and step made of it (`weighed`: its
/// zone has angles inside the model there).
fn searched(c: &Confirmation, weighed: bool) -> String {
    match (&c.searched, c.change_pct) {
        (None, _) => "none beat the plain liner".into(),
        (Some(t), _) if !weighed => format!(
            "{}: no angle inside the model here to weigh it on, not kept",
            texture_label(&Some(t.clone()))
        ),
        (Some(t), Some(x)) => format!(
            "{}: {x:+.1} %{}",
            texture_label(&Some(t.clone())),
            if c.kept { "" } else { ", not kept" }
        ),
        (Some(t), None) => format!(
            "{}: below the least clearance or failed at some angle, not kept",
            texture_label(&Some(t.clone()))
        ),
    }
}

/// Why angles are outside the model, counted by kind (the per-angle reasons are in the CSV),
/// e.g. "30 angles slow near a dead centre, 2 with the Stribeck number out of range".
pub fn exclusion_summary(samples: &[SampleRow]) -> String {
    // Counted by variant, in the order each is first met.
    let mut counts: Vec<(&Exclusion, usize)> = Vec::new();
    for why in samples.iter().filter_map(|x| x.excluded.as_ref()) {
        let same = |k: &&Exclusion| std::mem::discriminant(*k) == std::mem::discriminant(why);
        match counts.iter_mut().find(|(k, _)| same(k)) {
            Some((_, n)) => *n += 1,
            None => counts.push((why, 1)),
        }
    }
    if counts.is_empty() {
        return "no angle".into();
    }
    counts
        .iter()
        .map(|(k, n)| format!("{n} angle{} {}", if *n == 1 { "" } else { "s" }, k.kind()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The tables (terminal and Markdown).
pub fn table(r: &CycleReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "texopt cycle {}: {} rpm, stroke {} mm; designed at {} every {}°, reported at {} every {}°, on {}\n",
        r.name, r.rpm, r.stroke_mm, r.search_fidelity, r.design_step_deg, r.report_fidelity, r.step_deg,
        film_label(r.flow_factors.as_ref())
    );
    let _ = writeln!(
        s,
        "Outside the hydrodynamic model, and left out of every number below: {:.1} % of the cycle's time, {:.1} % of its sliding distance ({}).\n",
        100.0 * r.excluded_cycle_fraction,
        100.0 * r.excluded_sliding_fraction,
        exclusion_summary(&r.samples)
    );
    let _ = writeln!(s, "| zone | from–to (mm) | texture | angles in / out | work plain (J/m) | work zoned (J/m) | change | least C_min (µm) | its search's design: change here |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    let bounds: Vec<f64> = r
        .zones
        .iter()
        .map(|z| z.from_mm)
        .chain(r.zones.last().map(|z| z.to_mm))
        .collect();
    for (k, z) in r.zones.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} / {} | {} | {} | {} | {} | {} |",
            z.zone,
            zone_label(&bounds, k),
            texture_label(&z.texture),
            z.angles_inside,
            z.angles_excluded,
            or_dash(z.work_plain_j_per_m, |x| format!("{x:.4}")),
            or_dash(z.work_zoned_j_per_m, |x| format!("{x:.4}")),
            or_dash(z.change_pct, |x| format!("{x:+.1} %")),
            or_dash(z.c_min_um, |x| format!("{x:.3}")),
            searched(&z.searched, z.angles_inside > 0)
        );
    }
    let unweighed: Vec<String> = r
        .zones
        .iter()
        .filter(|z| z.angles_inside == 0)
        .map(|z| z.zone.to_string())
        .collect();
    if !unweighed.is_empty() {
        let (zone, has) = match unweighed.len() {
            1 => ("zone", "its"),
            _ => ("zones", "their"),
        };
        let _ = writeln!(
            s,
            "\nNo angle of {zone} {} lies inside the model at this step (the CSV says why): {has} liner stays plain and adds no work.",
            unweighed.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "\nuniform best: {} (its search's design: {})\n",
        texture_label(&r.uniform),
        searched(&r.uniform_searched, true)
    );
    let _ = writeln!(s, "| liner | work (J/m per cycle) | mean power (W/m) | ring (W) | change | least C_min (µm) | failed angles |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for l in &r.liners {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.2} | {:.2} | {} | {} | {} |",
            l.liner,
            l.work_j_per_m,
            l.mean_power_w_per_m,
            l.ring_power_w,
            or_dash(l.change_pct, |x| format!("{x:+.1} %")),
            or_dash(l.c_min_um, |x| format!("{x:.3}")),
            l.failed_angles
        );
    }
    let _ = writeln!(
        s,
        "\nLeast clearance kept by every design: {:.2} µm. {:.1} s for this run (evaluations found in the cache cost nothing).",
        r.min_clearance_um, r.wall_time_s
    );
    s
}

/// What to read from each figure, a line each.
fn captions(r: &CycleReport) -> String {
    format!(
        "\n## Figures\n\n\
         - `cycle_{0}_force.png`: the friction force per metre of circumference against crank angle for the plain, uniform and zoned liners, over the angles inside the model (the excluded ones marked on the axis); where the zoned liner's line runs under the plain liner's, its zone's texture saves friction at those angles.\n\
         - `cycle_{0}_liner.png`: the pocket depth each zone of the stroke gets (0: the plain liner) beside the uniform best: the liner to make, read along the stroke from top dead centre.\n",
        r.name
    )
}

/// JSON, CSV (one row per crank angle), the tables as Markdown, and the two figures.
pub fn write(dir: &Path, r: &CycleReport) -> Result<Vec<PathBuf>, OptimiseError> {
    let base = format!("cycle_{}", r.name);
    let md = format!("# Cycle `{}`\n\n{}{}", r.name, table(r), captions(r));
    let stem = json_and_md(dir, &base, r, md)?;
    crate::output::write(&stem(".csv"), csv_bytes(&COLUMNS, &r.samples)?)?;
    force_plot(&stem("_force.png"), r)?;
    liner_plot(&stem("_liner.png"), r)?;
    Ok(["json", "md", "csv"]
        .iter()
        .map(|x| stem(&format!(".{x}")))
        .chain([stem("_force.png"), stem("_liner.png")])
        .collect())
}

/// The CSV's columns, named once: each header with how its cell is written (a liner's force
/// and clearance empty where it has none).
const COLUMNS: [Column<SampleRow>; 14] = [
    ("crank_deg", |x| x.crank_deg.to_string()),
    ("position_mm", |x| x.position_mm.to_string()),
    ("zone", |x| x.zone.to_string()),
    ("speed_m_s", |x| x.speed_ms.to_string()),
    ("load_n_m", |x| x.load_n_per_m.to_string()),
    ("stribeck", |x| x.stribeck.to_string()),
    ("d_oil_um", |x| x.d_oil_um.to_string()),
    ("excluded", |x| {
        x.excluded
            .as_ref()
            .map(ToString::to_string)
            .unwrap_or_default()
    }),
    ("force_plain_n_m", |x| cell(x.force_n_per_m.plain)),
    ("force_uniform_n_m", |x| cell(x.force_n_per_m.uniform)),
    ("force_zoned_n_m", |x| cell(x.force_n_per_m.designed)),
    ("c_min_plain_um", |x| cell(x.c_min_um.plain)),
    ("c_min_uniform_um", |x| cell(x.c_min_um.uniform)),
    ("c_min_zoned_um", |x| cell(x.c_min_um.designed)),
];

fn cell(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| v.to_string())
}

/// Friction force against crank angle, each liner as lines over the angles inside the
/// model; the excluded angles marked on the axis.
fn force_plot(path: &Path, r: &CycleReport) -> Result<(), OptimiseError> {
    let mut runs: Vec<(usize, Vec<(f64, f64)>)> = Vec::new();
    for i in 0..3 {
        let mut cur: Vec<(f64, f64)> = Vec::new();
        for x in &r.samples {
            match *x.force_n_per_m.each()[i] {
                Some(f) => cur.push((x.crank_deg, f)),
                None if !cur.is_empty() => runs.push((i, std::mem::take(&mut cur))),
                None => {}
            }
        }
        if !cur.is_empty() {
            runs.push((i, cur));
        }
    }
    let excluded: Vec<(f64, f64)> = r
        .samples
        .iter()
        .filter(|x| x.excluded.is_some())
        .map(|x| (x.crank_deg, 0.0))
        .collect();
    let mut named = [false; 3];
    let mut series: Vec<Series> = runs
        .iter()
        .map(|(i, pts)| Series {
            name: if std::mem::replace(&mut named[*i], true) {
                String::new()
            } else {
                [Liner::Plain, Liner::Uniform, Liner::Zoned][*i]
                    .name()
                    .to_string()
            },
            points: pts,
            style: if *i == 0 { Style::Thick } else { Style::Line },
            colour: [1, 0, 2][*i],
        })
        .collect();
    series.push(Series {
        name: "excluded: outside the hydrodynamic model".into(),
        points: &excluded,
        style: Style::Markers,
        colour: 4,
    });
    plot::xy(
        path,
        &Chart {
            title: &format!("Friction force over the cycle, {} at {} rpm", r.name, r.rpm),
            x_label: "crank angle from firing top dead centre (°)",
            y_label: "friction force per unit length (N/m)",
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
        },
        &series,
    )
    .map_err(OptimiseError::Output)
}

/// The liner along the stroke: each zone's pocket depth over its span (0: plain), named with
/// its texture; the uniform best as a faint line.
fn liner_plot(path: &Path, r: &CycleReport) -> Result<(), OptimiseError> {
    let depth = |t: &Option<Texture>| t.as_ref().map_or(0.0, |t| t.depth);
    let spans: Vec<Vec<(f64, f64)>> = r
        .zones
        .iter()
        .map(|z| vec![(z.from_mm, depth(&z.texture)), (z.to_mm, depth(&z.texture))])
        .collect();
    let uniform = vec![(0.0, depth(&r.uniform)), (r.stroke_mm, depth(&r.uniform))];
    let mut series: Vec<Series> = spans
        .iter()
        .zip(&r.zones)
        .map(|(pts, z)| Series {
            name: format!("zone {}: {}", z.zone, texture_label(&z.texture)),
            points: pts,
            style: Style::Thick,
            colour: 2 + z.zone,
        })
        .collect();
    series.push(Series {
        name: format!("uniform best: {}", texture_label(&r.uniform)),
        points: &uniform,
        style: Style::Faint,
        colour: 0,
    });
    plot::xy(
        path,
        &Chart {
            title: &format!("The zoned liner of {} along the stroke", r.name),
            x_label: "distance from top dead centre (mm)",
            y_label: "pocket depth (µm; 0: plain liner)",
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
        },
        &series,
    )
    .map_err(OptimiseError::Output)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::finite::first_non_finite;

    #[test]
    fn a_number_that_is_not_finite_is_named_before_anything_is_printed() {
        let none = Confirmation {
            searched: None,
            change_pct: None,
            kept: false,
        };
        let mut r = CycleReport {
            name: "t".into(),
            rpm: 3000.0,
            stroke_mm: 81.0,
            bore_mm: 79.0,
            step_deg: 5.0,
            design_step_deg: 20.0,
            search_fidelity: "draft".into(),
            report_fidelity: "fast".into(),
            min_clearance_um: 0.9,
            uniform: None,
            uniform_searched: none.clone(),
            zones: vec![ZoneRow {
                zone: 1,
                from_mm: 0.0,
                to_mm: 81.0,
                texture: None,
                angles_inside: 0,
                angles_excluded: 1,
                work_plain_j_per_m: None,
                work_zoned_j_per_m: None,
                change_pct: None,
                c_min_um: None,
                searched: none,
            }],
            liners: vec![],
            excluded_cycle_fraction: 1.0,
            excluded_sliding_fraction: 1.0,
            flow_factors: None,
            samples: vec![],
            wall_time_s: 1.0,
        };
        assert_eq!(first_non_finite(&r), None);
        let t = table(&r);
        assert!(!t.contains("NaN") && !t.contains("inf"), "{t}");
        r.zones[0].change_pct = Some(f64::NAN);
        assert_eq!(
            first_non_finite(&r).unwrap().to_string(),
            "zones[0].change_pct = NaN"
        );
        r.zones[0].change_pct = None;
        r.zones[0].c_min_um = Some(f64::INFINITY);
        assert_eq!(
            first_non_finite(&r).unwrap().to_string(),
            "zones[0].c_min_um = inf"
        );
    }
}
