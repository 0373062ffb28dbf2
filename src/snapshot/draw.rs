//! The snapshot pictures: maps of p, θ and h over the contact at each instant, centre-line
//! profiles of p and h (as the paper's Figs. 8–10), and Z(t), f(t) over the period with the
//! instants marked. Colour scales and axes are fixed over the period so frames compare.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::columns::{shown_columns, Units};
use super::{label, Context, Frame, Recording};
use crate::output::OutputError;
use crate::plot::drawing;
use crate::plot::PlotError;

pub(super) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// A field drawn as maps: its name, unit, values per node and colour range.
pub(super) struct Field<'a> {
    pub name: &'a str,
    pub unit: &'a str,
    pub values: fn(&Frame) -> &[f64],
    pub scale: f64,
    pub range: (f64, f64),
    /// Drawn under the ring only (grey beyond it): the gap, whose value beyond the ring is
    /// the ring's far clearance e, off any useful colour scale.
    pub ring_only: bool,
}

impl Field<'_> {
    fn value(&self, f: &Frame, k: usize) -> f64 {
        (self.values)(f)[k] * self.scale
    }
}

/// The three fields over `frames`, each with its range over all of them (θ always 0–1).
pub(super) fn fields<'a>(rec: &Recording, cx: &Context, frames: &[Frame]) -> [Field<'a>; 3] {
    let u = Units::of(cx);
    let cols = shown_columns(rec, cx);
    let n2 = rec.grid.n2;
    let span = |v: fn(&Frame) -> &[f64], scale: f64, ring_only: bool| {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for f in frames {
            for i in cols.clone().filter(|&i| cx.ring[i] || !ring_only) {
                for &x in &v(f)[i * n2..(i + 1) * n2] {
                    lo = lo.min(x * scale);
                    hi = hi.max(x * scale);
                }
            }
        }
        if hi <= lo {
            hi = lo + 1.0;
        }
        (lo, hi)
    };
    [
        Field {
            name: "pressure p",
            unit: "MPa",
            values: |f| &f.p,
            scale: u.mpa,
            range: span(|f| &f.p, u.mpa, false),
            ring_only: false,
        },
        Field {
            name: "saturation θ (θ < 1: cavitated)",
            unit: "",
            values: |f| &f.theta,
            scale: 1.0,
            range: (0.0, 1.0),
            ring_only: false,
        },
        Field {
            name: "gap h under the ring (grey beyond it)",
            unit: "µm",
            values: |f| &f.h,
            scale: 1.0,
            range: span(|f| &f.h, 1.0, true),
            ring_only: true,
        },
    ]
}

/// Every picture of the recording, written into `dir`.
pub(super) fn pictures(
    dir: &Path,
    rec: &Recording,
    cx: &Context,
) -> Result<Vec<PathBuf>, OutputError> {
    let mut out = Vec::new();
    for (field, file) in fields(rec, cx, &rec.frames).iter().zip([
        "maps_pressure.png",
        "maps_saturation.png",
        "maps_gap.png",
    ]) {
        let path = dir.join(file);
        crate::output::atomically(&path, |tmp| maps(tmp, rec, cx, field))?;
        out.push(path);
    }
    let path = dir.join("profiles.png");
    crate::output::atomically(&path, |tmp| profiles(tmp, rec, cx))?;
    out.push(path);
    let path = dir.join("history.png");
    crate::output::atomically(&path, |tmp| history(tmp, rec, cx))?;
    out.push(path);
    Ok(out)
}

/// A line saying which run the picture is of.
pub(super) fn case_line(cx: &Context) -> String {
    let ring = if cx.case.r.is_infinite() {
        "flat ring".to_string()
    } else {
        format!("R = {} cm", cx.case.r)
    };
    match &cx.case.texture {
        None => format!("{ring}, plain liner"),
        Some(t) => format!(
            "{ring}; pockets {} × {} cm, {} µm deep, lattice {} × {} cm",
            t.l1, t.l2, t.depth, t.per, t.width
        ),
    }
}

/// Rows and columns of panels the pictures of `n` frames have.
pub(super) fn maps_grid(n: usize) -> (usize, usize) {
    let cols = if n > 1 { 2 } else { 1 };
    (n.div_ceil(cols), cols)
}

/// Width of the pictures of the maps (pixels), the largest pictures drawn.
pub(super) const MAPS_WIDTH: u32 = 1300;

/// Height of the pictures of the maps with `rows` rows of panels (pixels).
pub(super) fn maps_height(rows: usize) -> u32 {
    100 + 270 * rows as u32
}

fn maps(path: &Path, rec: &Recording, cx: &Context, field: &Field) -> Result<(), PlotError> {
    let (rows, cols) = maps_grid(rec.frames.len());
    let size = (MAPS_WIDTH, maps_height(rows));
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(drawing)?;
    let title = format!(
        "{} over the last period ({}), {}",
        field.name,
        if field.unit.is_empty() {
            "-"
        } else {
            field.unit
        },
        case_line(cx)
    );
    let (top, rest) = root.split_vertically(70);
    top.draw(&Text::new(title, (20, 10), ("sans-serif", 22)))
        .map_err(drawing)?;
    top.draw(&Text::new(MAP_KEY, (20, 40), ("sans-serif", 15)))
        .map_err(drawing)?;
    let (panels, bar) = rest.split_horizontally(1180);
    colour_bar(&bar.margin(20, 40, 10, 10), field)?;
    let u = Units::of(cx);
    for (k, (area, f)) in panels
        .split_evenly((rows, cols))
        .iter()
        .zip(&rec.frames)
        .enumerate()
    {
        let caption = format!("({}) t = {:.4} ms", label(k), f.t * u.ms);
        map_panel(area, rec, cx, f, field, &caption)?;
    }
    root.present().map_err(drawing)
}

/// What the marks on a map are, under its title.
pub(super) const MAP_KEY: &str = "dashed white: the ring's edges; white outlines: the pockets; x2 spans a whole texture cell (the simulated half, mirrored about the pockets' centre line)";

/// One map: the field over the shown columns, mirrored about the pocket's centre line so that
/// a whole texture cell shows (the simulated half cell is its lower half), the ring's edges
/// dashed and the pocket outlines drawn.
pub(super) fn map_panel(
    area: &Area,
    rec: &Recording,
    cx: &Context,
    f: &Frame,
    field: &Field,
    caption: &str,
) -> Result<(), PlotError> {
    let (g, u) = (&rec.grid, Units::of(cx));
    let cols = shown_columns(rec, cx);
    let mm = u.mm_per_cm;
    let (x0, x1) = (g.x(*cols.start()) * mm, g.x(*cols.end()) * mm);
    let top = 2.0 * g.width * mm;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 16))
        .margin(6)
        .x_label_area_size(32)
        .y_label_area_size(48)
        .build_cartesian_2d(x0..x1, 0.0..top)
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x1 (mm), the liner slides →")
        .y_desc("x2 (mm)")
        .x_labels(6)
        .y_labels(4)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(drawing)?;
    let (lo, hi) = field.range;
    let cells = cols.clone().flat_map(|i| (0..g.n2).map(move |j| (i, j)));
    let rect = |i: usize, j: usize| {
        let xa = (g.x(i) - 0.5 * g.dx).max(g.x(*cols.start())) * mm;
        let xb = (g.x(i) + 0.5 * g.dx).min(g.x(*cols.end())) * mm;
        let (ya, yb) = (j as f64 * g.dy * mm, (j + 1) as f64 * g.dy * mm);
        let c = if field.ring_only && !cx.ring[i] {
            RGBColor(200, 200, 200)
        } else {
            ViridisRGB.get_color_normalized(field.value(f, g.idx(i, j)), lo, hi)
        };
        let lower = Rectangle::new([(xa, ya), (xb, yb)], c.filled());
        let upper = Rectangle::new([(xa, top - yb), (xb, top - ya)], c.filled());
        [lower, upper]
    };
    chart
        .draw_series(cells.flat_map(|(i, j)| rect(i, j)))
        .map_err(drawing)?;
    let (a, b) = cx.case.contact().ring_edges();
    for x in [a * mm, b * mm] {
        chart
            .draw_series(DashedLineSeries::new(
                [(x, 0.0), (x, top)],
                6,
                4,
                WHITE.stroke_width(2),
            ))
            .map_err(drawing)?;
    }
    for outline in pocket_outlines(cx, f, (x0, x1), mm) {
        chart
            .draw_series(LineSeries::new(outline, WHITE.stroke_width(1)))
            .map_err(drawing)?;
    }
    Ok(())
}

/// The outlines of the pockets at the frame's phase (mm), each cut to x1 within `shown`:
/// centres at x1 = phase + u·t_phase + k·per on the cell's centre line (docs/model.md §2).
fn pocket_outlines(cx: &Context, f: &Frame, shown: (f64, f64), mm: f64) -> Vec<Vec<(f64, f64)>> {
    let Some(t) = &cx.case.texture else {
        return Vec::new();
    };
    let first = t.phase.rem_euclid(t.per) + cx.case.u * f.phase;
    let y_c = 0.5 * t.width * mm;
    let mut out = Vec::new();
    let k0 = ((shown.0 / mm - first - t.l1) / t.per).floor() as i64;
    let k1 = ((shown.1 / mm - first + t.l1) / t.per).ceil() as i64;
    for k in k0..=k1 {
        let x_c = (first + k as f64 * t.per) * mm;
        let mut run = Vec::new();
        for s in 0..=96 {
            let a = std::f64::consts::TAU * s as f64 / 96.0;
            let p = (x_c + t.l1 * mm * a.cos(), y_c + t.l2 * mm * a.sin());
            if p.0 >= shown.0 && p.0 <= shown.1 {
                run.push(p);
            } else if !run.is_empty() {
                out.push(std::mem::take(&mut run));
            }
        }
        if !run.is_empty() {
            out.push(run);
        }
    }
    out
}

/// A vertical colour bar for `field`'s range with five labelled ticks.
pub(super) fn colour_bar(area: &Area, field: &Field) -> Result<(), PlotError> {
    let (lo, hi) = field.range;
    let mut chart = ChartBuilder::on(area)
        .y_label_area_size(0)
        .right_y_label_area_size(55)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(drawing)?
        .set_secondary_coord(0.0..1.0, lo..hi);
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .disable_y_axis()
        .draw()
        .map_err(drawing)?;
    chart
        .configure_secondary_axes()
        .y_desc(field.unit)
        .y_labels(6)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(drawing)?;
    let n = 120;
    chart
        .draw_series((0..n).map(|s| {
            let (ya, yb) = (
                lo + (hi - lo) * s as f64 / n as f64,
                lo + (hi - lo) * (s + 1) as f64 / n as f64,
            );
            let c = ViridisRGB.get_color_normalized(0.5 * (ya + yb), lo, hi);
            Rectangle::new([(0.0, ya), (1.0, yb)], c.filled())
        }))
        .map_err(drawing)?;
    Ok(())
}

/// The centre line's node row: nearest the pockets' centres (the simulated half cell's upper
/// edge), at half a cell's height below it.
pub(super) fn centre_row(rec: &Recording) -> usize {
    rec.grid.n2 - 1
}

/// p and h along x1 under the ring on the centre line, at one frame: (x1 mm, p MPa, h µm).
pub(super) fn centre_profile(rec: &Recording, cx: &Context, f: &Frame) -> Vec<(f64, f64, f64)> {
    let (g, u) = (&rec.grid, Units::of(cx));
    let j = centre_row(rec);
    (0..=g.n1)
        .filter(|&i| cx.ring[i])
        .map(|i| {
            let k = g.idx(i, j);
            (g.x(i) * u.mm_per_cm, f.p[k] * u.mpa, f.h[k])
        })
        .collect()
}

/// The axes the profiles share over a set of frames: x1 under the ring, p and h up to their
/// largest (5 % headroom).
pub(super) fn profile_axes(
    rec: &Recording,
    cx: &Context,
    frames: &[Frame],
) -> ((f64, f64), f64, f64) {
    let all: Vec<_> = frames
        .iter()
        .flat_map(|f| centre_profile(rec, cx, f))
        .collect();
    let x0 = all.iter().map(|q| q.0).fold(f64::INFINITY, f64::min);
    let x1 = all.iter().map(|q| q.0).fold(f64::NEG_INFINITY, f64::max);
    let p = all.iter().map(|q| q.1).fold(0.0, f64::max).max(1e-9) * 1.05;
    let h = all.iter().map(|q| q.2).fold(0.0, f64::max).max(1e-9) * 1.05;
    ((x0, x1), p, h)
}

/// One profile panel: p (blue, left axis) and h (red, right axis) along the centre line.
pub(super) fn profile_panel(
    area: &Area,
    rec: &Recording,
    cx: &Context,
    f: &Frame,
    axes: ((f64, f64), f64, f64),
    caption: &str,
) -> Result<(), PlotError> {
    let ((x0, x1), p_max, h_max) = axes;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 16))
        .margin(6)
        .x_label_area_size(32)
        .y_label_area_size(52)
        .right_y_label_area_size(46)
        .build_cartesian_2d(x0..x1, 0.0..p_max)
        .map_err(drawing)?
        .set_secondary_coord(x0..x1, 0.0..h_max);
    chart
        .configure_mesh()
        .x_desc("x1 (mm), the liner slides →")
        .y_desc("p (MPa), blue")
        .x_labels(6)
        .y_labels(5)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(drawing)?;
    chart
        .configure_secondary_axes()
        .y_desc("h (µm), red")
        .y_labels(5)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(drawing)?;
    let prof = centre_profile(rec, cx, f);
    chart
        .draw_series(LineSeries::new(
            prof.iter().map(|q| (q.0, q.1)),
            BLUE.stroke_width(2),
        ))
        .map_err(drawing)?;
    chart
        .draw_secondary_series(LineSeries::new(
            prof.iter().map(|q| (q.0, q.2)),
            RED.stroke_width(2),
        ))
        .map_err(drawing)?;
    Ok(())
}

fn profiles(path: &Path, rec: &Recording, cx: &Context) -> Result<(), PlotError> {
    let (rows, cols) = maps_grid(rec.frames.len());
    let root = BitMapBackend::new(path, (MAPS_WIDTH, 90 + 250 * rows as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(drawing)?;
    let g = &rec.grid;
    let title = format!(
        "p (blue) and h (red) along x1 through the pocket centres ({:.3} mm off), {}",
        0.5 * g.dy * 10.0,
        case_line(cx)
    );
    let (top, rest) = root.split_vertically(60);
    top.titled(&title, ("sans-serif", 17)).map_err(drawing)?;
    let axes = profile_axes(rec, cx, &rec.frames);
    let u = Units::of(cx);
    for (k, (area, f)) in rest
        .split_evenly((rows, cols))
        .iter()
        .zip(&rec.frames)
        .enumerate()
    {
        let caption = format!("({}) t = {:.4} ms, Z = {:.3} µm", label(k), f.t * u.ms, f.z);
        profile_panel(area, rec, cx, f, axes, &caption)?;
    }
    root.present().map_err(drawing)
}

fn history(path: &Path, rec: &Recording, cx: &Context) -> Result<(), PlotError> {
    let root = BitMapBackend::new(path, (1000, 760)).into_drawing_area();
    root.fill(&WHITE).map_err(drawing)?;
    let (top, rest) = root.split_vertically(50);
    top.titled(
        &format!(
            "The ring over the last period, the instants a–{} marked; {}",
            label(rec.frames.len().saturating_sub(1)),
            case_line(cx)
        ),
        ("sans-serif", 18),
    )
    .map_err(drawing)?;
    let u = Units::of(cx);
    let (z_area, f_area) = rest.split_vertically(355);
    let t: Vec<f64> = rec.history.iter().map(|r| r.t * u.ms).collect();
    let z: Vec<f64> = rec.history.iter().map(|r| r.z).collect();
    let fr: Vec<f64> = rec.history.iter().map(|r| r.f).collect();
    let marks = |v: fn(&Frame) -> f64| -> Vec<(f64, f64)> {
        rec.frames.iter().map(|f| (f.t * u.ms, v(f))).collect()
    };
    curve(&z_area, &t, &z, &marks(|f| f.z), "ring position Z (µm)")?;
    curve(
        &f_area,
        &t,
        &fr,
        &marks(|f| f.f),
        "friction coefficient f (eq. 11)",
    )?;
    root.present().map_err(drawing)
}

/// A curve against t (ms) with the frames' instants marked and lettered.
fn curve(
    area: &Area,
    t: &[f64],
    v: &[f64],
    marks: &[(f64, f64)],
    y: &str,
) -> Result<(), PlotError> {
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let pad = 0.12 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
    let (t0, t1) = (t[0], t[t.len() - 1]);
    let mut chart = ChartBuilder::on(area)
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .x_desc("t (ms)")
        .y_desc(y)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(drawing)?;
    chart
        .draw_series(LineSeries::new(
            t.iter().copied().zip(v.iter().copied()),
            BLUE.stroke_width(2),
        ))
        .map_err(drawing)?;
    chart
        .draw_series(marks.iter().enumerate().map(|(k, &p)| {
            EmptyElement::at(p)
                + Circle::new((0, 0), 5, RED.filled())
                + Text::new(label(k), (-4, -22), ("sans-serif", 16))
        }))
        .map_err(drawing)?;
    Ok(())
}
