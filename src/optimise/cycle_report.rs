//! The report of `cycle`: per zone and per liner (plain, uniform best, zoned) the friction
//! work over the cycle, the mean friction power and the least clearance; every crank angle
//! with its operating point, its exclusion or its forces; the tables, JSON, CSV and figures.

use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::cycle::{Confirmation, CycleSettings, Designs, Evaluated};
use crate::model::case::Texture;
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
    /// Friction work per unit circumferential length over the cycle (J/m), plain and zoned.
    pub work_plain_j_per_m: f64,
    pub work_zoned_j_per_m: f64,
    pub change_pct: f64,
    /// Least clearance of the zoned liner over the zone's angles (µm).
    pub c_min_um: f64,
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
    pub change_pct: f64,
    pub c_min_um: f64,
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
    pub excluded: Option<String>,
    /// Friction force (N/m) and clearance (µm) of the plain, uniform and zoned liners.
    pub force_n_per_m: [Option<f64>; 3],
    pub c_min_um: [Option<f64>; 3],
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
    pub samples: Vec<SampleRow>,
    pub wall_time_s: f64,
}

const LINERS: [&str; 3] = ["plain liner", "uniform best", "zoned"];

/// The report of the evaluated liners.
pub fn assemble(s: &CycleSettings, d: &Designs, ev: &Evaluated, wall: f64) -> CycleReport {
    let e = &s.engine.file.engine;
    let pts = &ev.points;
    let work = |i: usize, zone: Option<usize>| -> f64 {
        pts.iter()
            .zip(&ev.liners[i])
            .filter(|(p, _)| zone.is_none_or(|z| p.sample.zone == z))
            .filter_map(|(p, r)| r.as_ref().map(|(_, f)| f * p.distance_m))
            .sum()
    };
    let least = |i: usize, zone: Option<usize>| -> f64 {
        pts.iter()
            .zip(&ev.liners[i])
            .filter(|(p, _)| zone.is_none_or(|z| p.sample.zone == z))
            .filter_map(|(_, r)| r.as_ref().map(|(o, _)| o.c_min))
            .fold(f64::INFINITY, f64::min)
    };
    let zones = (0..d.zones.len())
        .map(|z| {
            let inside = pts
                .iter()
                .filter(|p| p.sample.zone == z && p.excluded.is_none())
                .count();
            let all = pts.iter().filter(|p| p.sample.zone == z).count();
            let (wp, wz) = (work(0, Some(z)), work(2, Some(z)));
            ZoneRow {
                zone: z + 1,
                from_mm: s.engine.bounds_mm[z],
                to_mm: s.engine.bounds_mm[z + 1],
                texture: d.zones[z].clone(),
                angles_inside: inside,
                angles_excluded: all - inside,
                work_plain_j_per_m: wp,
                work_zoned_j_per_m: wz,
                change_pct: 100.0 * (wz / wp - 1.0),
                c_min_um: least(2, Some(z)),
                searched: ev.confirmed[z].clone(),
            }
        })
        .collect();
    let cycle_s = 120.0 / e.rpm;
    let circumference = std::f64::consts::PI * e.bore_mm * 1e-3;
    let w0 = work(0, None);
    let liners = (0..3)
        .map(|i| {
            let w = work(i, None);
            LinerRow {
                liner: LINERS[i].into(),
                work_j_per_m: w,
                mean_power_w_per_m: w / cycle_s,
                ring_power_w: w / cycle_s * circumference,
                change_pct: 100.0 * (w / w0 - 1.0),
                c_min_um: least(i, None),
                failed_angles: pts
                    .iter()
                    .zip(&ev.liners[i])
                    .filter(|(p, r)| p.excluded.is_none() && r.is_none())
                    .count(),
            }
        })
        .collect();
    let out = pts.iter().filter(|p| p.excluded.is_some());
    let total: f64 = pts.iter().map(|p| p.distance_m).sum();
    let samples = pts
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
            force_n_per_m: [0, 1, 2].map(|i| ev.liners[i][k].as_ref().map(|x| x.1)),
            c_min_um: [0, 1, 2].map(|i| ev.liners[i][k].as_ref().map(|x| x.0.c_min)),
        })
        .collect();
    CycleReport {
        name: e.name.clone(),
        rpm: e.rpm,
        stroke_mm: e.stroke_mm,
        bore_mm: e.bore_mm,
        step_deg: s.step_deg,
        design_step_deg: s.design_step_deg,
        search_fidelity: s.search_fidelity.name().into(),
        report_fidelity: s.report_fidelity.name().into(),
        min_clearance_um: s.min_clearance_um,
        uniform: d.uniform.clone(),
        uniform_searched: ev.confirmed[d.zones.len()].clone(),
        zones,
        liners,
        excluded_cycle_fraction: out.clone().count() as f64 / pts.len() as f64,
        excluded_sliding_fraction: out.map(|p| p.distance_m).sum::<f64>() / total,
        samples,
        wall_time_s: wall,
    }
}

fn texture_label(t: &Option<Texture>) -> String {
    t.as_ref()
        .map_or("plain liner".into(), Texture::rounded_label)
}

/// A searched design and what the report's fidelity and step made of it.
fn searched(c: &Confirmation) -> String {
    match (&c.searched, c.change_pct) {
        (None, _) => "none beat the plain liner".into(),
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
    let kind = super::cycle::exclusion_kind;
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for why in samples.iter().filter_map(|x| x.excluded.as_deref()) {
        match counts.iter_mut().find(|(k, _)| *k == kind(why)) {
            Some((_, n)) => *n += 1,
            None => counts.push((kind(why), 1)),
        }
    }
    if counts.is_empty() {
        return "no angle".into();
    }
    counts
        .iter()
        .map(|(k, n)| format!("{n} angle{} {k}", if *n == 1 { "" } else { "s" }))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The tables (terminal and Markdown).
pub fn table(r: &CycleReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "texopt cycle {}: {} rpm, stroke {} mm; designed at {} every {}°, reported at {} every {}°\n",
        r.name, r.rpm, r.stroke_mm, r.search_fidelity, r.design_step_deg, r.report_fidelity, r.step_deg
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
    for z in &r.zones {
        let _ = writeln!(
            s,
            "| {} | {:.1}–{:.1} | {} | {} / {} | {:.4} | {:.4} | {:+.1} % | {:.3} | {} |",
            z.zone,
            z.from_mm,
            z.to_mm,
            texture_label(&z.texture),
            z.angles_inside,
            z.angles_excluded,
            z.work_plain_j_per_m,
            z.work_zoned_j_per_m,
            z.change_pct,
            z.c_min_um,
            searched(&z.searched)
        );
    }
    let _ = writeln!(
        s,
        "\nuniform best: {} (its search's design: {})\n",
        texture_label(&r.uniform),
        searched(&r.uniform_searched)
    );
    let _ = writeln!(s, "| liner | work (J/m per cycle) | mean power (W/m) | ring (W) | change | least C_min (µm) | failed angles |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for l in &r.liners {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.2} | {:.2} | {:+.1} % | {:.3} | {} |",
            l.liner,
            l.work_j_per_m,
            l.mean_power_w_per_m,
            l.ring_power_w,
            l.change_pct,
            l.c_min_um,
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
pub fn write(dir: &Path, r: &CycleReport) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let stem = |ext: &str| dir.join(format!("cycle_{}{ext}", r.name));
    let json = serde_json::to_string_pretty(r).map_err(|e| e.to_string())?;
    crate::output::write(&stem(".json"), json)?;
    crate::output::write(
        &stem(".md"),
        format!("# Cycle `{}`\n\n{}{}", r.name, table(r), captions(r)),
    )?;
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record([
        "crank_deg",
        "position_mm",
        "zone",
        "speed_m_s",
        "load_n_m",
        "stribeck",
        "d_oil_um",
        "excluded",
        "force_plain_n_m",
        "force_uniform_n_m",
        "force_zoned_n_m",
        "c_min_plain_um",
        "c_min_uniform_um",
        "c_min_zoned_um",
    ]);
    let num = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
    for x in &r.samples {
        let mut rec = vec![
            x.crank_deg.to_string(),
            x.position_mm.to_string(),
            x.zone.to_string(),
            x.speed_ms.to_string(),
            x.load_n_per_m.to_string(),
            x.stribeck.to_string(),
            x.d_oil_um.to_string(),
            x.excluded.clone().unwrap_or_default(),
        ];
        rec.extend(x.force_n_per_m.map(num));
        rec.extend(x.c_min_um.map(num));
        let _ = w.write_record(rec);
    }
    let bytes = w.into_inner().map_err(|e| e.error().to_string())?;
    crate::output::write(&stem(".csv"), bytes)?;
    force_plot(&stem("_force.png"), r)?;
    liner_plot(&stem("_liner.png"), r)?;
    Ok(["json", "md", "csv"]
        .iter()
        .map(|x| stem(&format!(".{x}")))
        .chain([stem("_force.png"), stem("_liner.png")])
        .collect())
}

/// Friction force against crank angle, each liner as lines over the angles inside the
/// model; the excluded angles marked on the axis.
fn force_plot(path: &Path, r: &CycleReport) -> Result<(), String> {
    let mut runs: Vec<(usize, Vec<(f64, f64)>)> = Vec::new();
    for i in 0..3 {
        let mut cur: Vec<(f64, f64)> = Vec::new();
        for x in &r.samples {
            match x.force_n_per_m[i] {
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
                LINERS[*i].to_string()
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
}

/// The liner along the stroke: each zone's pocket depth over its span (0: plain), named with
/// its texture; the uniform best as a faint line.
fn liner_plot(path: &Path, r: &CycleReport) -> Result<(), String> {
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
}
