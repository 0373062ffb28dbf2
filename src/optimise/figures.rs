//! The optimiser's pictures: the confirmed front against the plain liner, and the texture
//! cell of each reported design. Drawn with plotters directly: they need labelled points,
//! error bars and shapes that the shared chart helper (`crate::plot`) does not draw.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

use super::design::{table_rows, Report, Row};
use super::error::OptimiseError;
use crate::model::case::Texture;
use crate::plot::{drawing, PlotError};

const FRONT: RGBColor = RGBColor(20, 70, 200);
const SEARCHED: RGBColor = RGBColor(185, 185, 185);
const OUTSIDE: RGBColor = RGBColor(200, 0, 160);

/// A tick label of a change in %: signed, zero plain.
fn signed(v: &f64) -> String {
    if v.abs() < 1e-9 {
        "0".into()
    } else {
        format!("{v:+.0}")
    }
}

/// An axis range holding `v` with a margin, and at least `least` wide.
fn span(v: &[f64], least: f64) -> (f64, f64) {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mid = 0.5 * (lo + hi);
    let half = (0.5 * (hi - lo)).max(0.5 * least) * 1.25;
    (mid - half, mid + half)
}

/// The front plot: changes of f̄ and C_min against the plain liner (%), the confirmed front
/// large and labelled with the tier's errors as bars, the searched designs faint behind.
pub fn front(path: &Path, r: &Report) -> Result<(), OptimiseError> {
    crate::output::atomically(path, |tmp| draw_front(tmp, r)).map_err(OptimiseError::Output)
}

/// The front plot's axes and marks, the searched designs' behind the front's.
fn draw_front(path: &Path, r: &Report) -> Result<(), PlotError> {
    let ((x0, x1), (y0, y1)) = front_axes(r);
    let searched = searched_changes(r);
    let inside = |p: &&(f64, f64)| (x0..=x1).contains(&p.0) && (y0..=y1).contains(&p.1);
    let shown: Vec<(f64, f64)> = searched.iter().filter(inside).copied().collect();

    let root = BitMapBackend::new(path, (1000, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(drawing)?;
    let title = format!(
        "Confirmed front against the plain liner, R = {} cm ({}; searched at {})",
        r.r, r.report_fidelity, r.search_fidelity
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .x_desc("change of the mean friction coefficient against the plain liner (%)")
        .y_desc("change of minimum clearance C_min against the plain liner (%)")
        .x_label_formatter(&signed)
        .y_label_formatter(&signed)
        .draw()
        .map_err(drawing)?;
    // The plain liner's lines: left of x = 0 less friction, above y = 0 more clearance.
    let grey = BLACK.mix(0.5);
    for line in [vec![(0.0, y0), (0.0, y1)], vec![(x0, 0.0), (x1, 0.0)]] {
        chart
            .draw_series(LineSeries::new(line, grey.stroke_width(1)))
            .map_err(drawing)?;
    }
    chart
        .draw_series(shown.iter().map(|&p| Circle::new(p, 3, SEARCHED.filled())))
        .map_err(drawing)?
        .label(format!(
            "{} designs searched at {} ({} beyond the axes)",
            searched.len(),
            r.search_fidelity,
            searched.len() - shown.len()
        ))
        .legend(|(x, y)| Circle::new((x + 10, y), 3, SEARCHED.filled()));
    draw_confirmed(&mut chart, r)?;
    draw_outside(&mut chart, r)?;
    labels(&root, &chart, r)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()
        .map_err(drawing)?;
    root.present().map_err(drawing)
}

/// A front design's error bars: its relative errors of f̄ and C_min (the report tier's, or
/// its deep-pocket mesh uncertainty), in % of the plain liner's values.
fn error_bar(r: &Report, x: &Row) -> (f64, f64) {
    let fe = 100.0 * x.f_error;
    let ce = 100.0 * x.c_min_error;
    (fe * x.f_mean / r.plain.f_mean, ce * x.c_min / r.plain.c_min)
}

/// The front plot's x and y ranges (%): the plain liner and every front design with its
/// error bars.
fn front_axes(r: &Report) -> ((f64, f64), (f64, f64)) {
    let mut xs = vec![0.0];
    let mut ys = vec![0.0];
    for x in &r.front {
        let (bx, by) = error_bar(r, x);
        xs.extend([x.f_change_pct - bx, x.f_change_pct + bx]);
        ys.extend([x.c_min_change_pct - by, x.c_min_change_pct + by]);
    }
    (span(&xs, 4.0), span(&ys, 4.0))
}

/// The designs evaluated at the search tier, as changes of f̄ and C_min (%) against the
/// plain liner at that tier.
fn searched_changes(r: &Report) -> Vec<(f64, f64)> {
    let pct = |v: f64, plain: f64| 100.0 * (v / plain - 1.0);
    r.evaluated
        .iter()
        .filter(|e| e.fidelity == r.search_fidelity)
        .filter_map(|e| {
            Some((
                pct(e.f_mean?, r.plain_search_f_mean),
                pct(e.c_min?, r.plain_search_c_min),
            ))
        })
        .collect()
}

/// The confirmed front: its line, each textured design's error bars and point, and the
/// plain liner at the origin.
fn draw_confirmed(chart: &mut Cell, r: &Report) -> Result<(), PlotError> {
    let pts: Vec<(f64, f64)> = r
        .front
        .iter()
        .map(|x| (x.f_change_pct, x.c_min_change_pct))
        .collect();
    chart
        .draw_series(LineSeries::new(pts.iter().copied(), FRONT.stroke_width(2)))
        .map_err(drawing)?;
    for x in r.front.iter().filter(|x| x.texture.is_some()) {
        let (bx, by) = error_bar(r, x);
        let (px, py) = (x.f_change_pct, x.c_min_change_pct);
        chart
            .draw_series([
                PathElement::new(vec![(px - bx, py), (px + bx, py)], FRONT.stroke_width(1)),
                PathElement::new(vec![(px, py - by), (px, py + by)], FRONT.stroke_width(1)),
            ])
            .map_err(drawing)?;
    }
    chart
        .draw_series(
            r.front
                .iter()
                .filter(|x| x.texture.is_some())
                .map(|x| Circle::new((x.f_change_pct, x.c_min_change_pct), 6, FRONT.filled())),
        )
        .map_err(drawing)?
        .label(format!(
            "confirmed front at {} (bars: its errors, ±{:.2} % friction, ±{:.2} % C_min{})",
            r.report_fidelity,
            100.0 * r.fidelity_error,
            100.0 * r.fidelity_c_error,
            if r.deep_clause().is_empty() {
                ""
            } else {
                "; more for deep pockets"
            }
        ))
        .legend(|(x, y)| Circle::new((x + 10, y), 6, FRONT.filled()));
    chart
        .draw_series([TriangleMarker::new((0.0, 0.0), 9, BLACK.filled())])
        .map_err(drawing)?
        .label("plain liner (the origin)")
        .legend(|(x, y)| TriangleMarker::new((x + 10, y), 7, BLACK.filled()));
    Ok(())
}

/// A ring around each front design whose least clearance is outside the hydrodynamic model.
fn draw_outside(chart: &mut Cell, r: &Report) -> Result<(), PlotError> {
    let outside: Vec<&Row> = r
        .front
        .iter()
        .filter(|x| x.outside_model.is_some())
        .collect();
    if outside.is_empty() {
        return Ok(());
    }
    chart
        .draw_series(outside.iter().map(|x| {
            Circle::new(
                (x.f_change_pct, x.c_min_change_pct),
                11,
                OUTSIDE.stroke_width(2),
            )
        }))
        .map_err(drawing)?
        .label(format!(
            "outside the hydrodynamic model (C_min < {:.2} µm)",
            crate::model::operating::FULL_FILM_LAMBDA * r.roughness_um
        ))
        .legend(|(x, y)| Circle::new((x + 10, y), 7, OUTSIDE.stroke_width(2)));
    Ok(())
}

/// Each reported design's name beside its point, and the plain liner's values.
fn labels(
    root: &DrawingArea<BitMapBackend, Shift>,
    chart: &Cell,
    r: &Report,
) -> Result<(), PlotError> {
    let font = ("sans-serif", 15).into_font();
    let mut taken: Vec<(i32, i32)> = Vec::new();
    for (label, x) in table_rows(r).iter().filter(|(_, x)| x.texture.is_some()) {
        let at = chart.backend_coord(&(x.f_change_pct, x.c_min_change_pct));
        // A label near an earlier one moves down a line.
        let mut pos = (at.0 + 12, at.1 - 20);
        while taken
            .iter()
            .any(|t| (t.0 - pos.0).abs() < 160 && (t.1 - pos.1).abs() < 17)
        {
            pos.1 += 17;
        }
        taken.push(pos);
        root.draw(&Text::new(label.clone(), pos, font.clone().color(&FRONT)))
            .map_err(drawing)?;
    }
    let at = chart.backend_coord(&(0.0, 0.0));
    root.draw(&Text::new(
        format!(
            "plain liner: mean f {:.5}, C_min {:.3} µm",
            r.plain.f_mean, r.plain.c_min
        ),
        (at.0 - 290, at.1 + 10),
        font.clone().color(&BLACK),
    ))
    .map_err(drawing)?;
    Ok(())
}

/// One panel per reported design (the plain liner has none): its lattice cell with the
/// pocket centred and the neighbours' edges, the walls dimensioned in µm, the depth.
pub fn cells(path: &Path, r: &Report) -> Result<(), OptimiseError> {
    let designs: Vec<(String, Texture)> = table_rows(r)
        .into_iter()
        .filter_map(|(l, x)| Some((l, x.texture.clone()?)))
        .collect();
    if designs.is_empty() {
        return Ok(());
    }
    crate::output::atomically(path, |tmp| draw_cells(tmp, r, &designs))
        .map_err(OptimiseError::Output)
}

fn draw_cells(path: &Path, r: &Report, designs: &[(String, Texture)]) -> Result<(), PlotError> {
    let cols = designs.len().min(3);
    let rows = designs.len().div_ceil(cols);
    let (pw, ph) = (380u32, 390u32);
    let root =
        BitMapBackend::new(path, (pw * cols as u32, ph * rows as u32 + 70)).into_drawing_area();
    root.fill(&WHITE).map_err(drawing)?;
    let (head, body) = root.split_vertically(70);
    head.draw(&Text::new(
        format!(
            "Texture cells of the reported designs, R = {} cm (µm; pockets half-ellipsoids)",
            r.r
        ),
        (14, 10),
        ("sans-serif", 20).into_font(),
    ))
    .map_err(drawing)?;
    head.draw(&Text::new(
        "sliding direction x1 →   (walls: between neighbouring pockets, along x1 and across x2)",
        (14, 40),
        ("sans-serif", 15).into_font(),
    ))
    .map_err(drawing)?;
    let panels = body.split_evenly((rows, cols));
    for ((label, t), area) in designs.iter().zip(&panels) {
        cell_panel(area, label, t)?;
    }
    root.present().map_err(drawing)
}

/// One design's cell: x1 along, x2 across, both in µm on equal scales.
fn cell_panel(
    area: &DrawingArea<BitMapBackend, Shift>,
    label: &str,
    t: &Texture,
) -> Result<(), PlotError> {
    let um = 1e4;
    let (per, width, l1, l2) = (t.per * um, t.width * um, t.l1 * um, t.l2 * um);
    let side = per.max(width);
    // The cell centred on its pocket, with room for the neighbours' edges and the labels.
    let m = 0.22 * side;
    let (cx, cy) = (0.5 * per, 0.5 * width);
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{label}: depth {:.1} µm", t.depth),
            ("sans-serif", 16),
        )
        .margin(8)
        .x_label_area_size(30)
        .y_label_area_size(45)
        .build_cartesian_2d(
            cx - 0.5 * side - m..cx + 0.5 * side + m,
            cy - 0.5 * side - m..cy + 0.5 * side + m,
        )
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(4)
        .y_labels(4)
        .x_desc("x1 (µm)")
        .y_desc("x2 (µm)")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0}"))
        .draw()
        .map_err(drawing)?;
    let ellipse = |ox: f64, oy: f64| -> Vec<(f64, f64)> {
        (0..=72)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 72.0;
                (ox + l1 * a.cos(), oy + l2 * a.sin())
            })
            .collect()
    };
    // The neighbours faint (clipped by the chart), the cell's pocket filled.
    for (i, j) in [
        (-1, 0),
        (1, 0),
        (0, -1),
        (0, 1),
        (-1, -1),
        (1, 1),
        (-1, 1),
        (1, -1),
    ] {
        let p = ellipse(cx + i as f64 * per, cy + j as f64 * width);
        chart
            .draw_series([Polygon::new(p, FRONT.mix(0.12).filled())])
            .map_err(drawing)?;
    }
    chart
        .draw_series([Polygon::new(ellipse(cx, cy), FRONT.mix(0.45).filled())])
        .map_err(drawing)?;
    chart
        .draw_series([Rectangle::new(
            [(0.0, 0.0), (per, width)],
            BLACK.stroke_width(1),
        )])
        .map_err(drawing)?;
    let red = RGBColor(200, 30, 30);
    let font = ("sans-serif", 14).into_font().color(&red);
    // Wall along x1: from this pocket's downstream tip to the next pocket's upstream tip.
    let (a, b) = (cx + l1, cx + per - l1);
    dimension(&mut chart, (a, cy), (b, cy), red)?;
    chart
        .draw_series([Text::new(
            format!("{:.1} µm", (per - 2.0 * l1)),
            (cx + 0.5 * per - 0.2 * side, cy + 0.09 * side),
            font.clone(),
        )])
        .map_err(drawing)?;
    // Wall across x2: from this pocket's side to the next row's.
    let (a, b) = (cy + l2, cy + width - l2);
    dimension(&mut chart, (cx, a), (cx, b), red)?;
    chart
        .draw_series([Text::new(
            format!("{:.1} µm", (width - 2.0 * l2)),
            (cx + 0.04 * side, cy + 0.5 * width + 0.13 * side),
            font,
        )])
        .map_err(drawing)?;
    chart
        .draw_series([Text::new(
            format!("2·l1 = {:.0}, 2·l2 = {:.0} µm", 2.0 * l1, 2.0 * l2),
            (cx - 0.5 * side, cy - 0.5 * side - 0.12 * side),
            ("sans-serif", 13).into_font(),
        )])
        .map_err(drawing)?;
    Ok(())
}

type Cell<'a> = ChartContext<
    'a,
    BitMapBackend<'a>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A dimension line between two points with end ticks, drawn over the wall it measures.
fn dimension(chart: &mut Cell, a: (f64, f64), b: (f64, f64), c: RGBColor) -> Result<(), PlotError> {
    let (pa, pb) = (chart.backend_coord(&a), chart.backend_coord(&b));
    let vertical = pa.0 == pb.0;
    let tick = |p: (i32, i32)| {
        if vertical {
            vec![(p.0 - 6, p.1), (p.0 + 6, p.1)]
        } else {
            vec![(p.0, p.1 - 6), (p.0, p.1 + 6)]
        }
    };
    let area = chart.plotting_area().strip_coord_spec();
    let base = chart.plotting_area().get_base_pixel();
    let rel = |p: (i32, i32)| (p.0 - base.0, p.1 - base.1);
    let line = |v: Vec<(i32, i32)>| {
        PathElement::new(
            v.into_iter().map(rel).collect::<Vec<_>>(),
            c.stroke_width(2),
        )
    };
    area.draw(&line(vec![pa, pb])).map_err(drawing)?;
    area.draw(&line(tick(pa))).map_err(drawing)?;
    area.draw(&line(tick(pb))).map_err(drawing)?;
    Ok(())
}
