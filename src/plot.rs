//! Charts (PNG via plotters): the few shapes the studies need, each a plain function of
//! named series, so a study file stays a short description of what it shows.

use plotters::prelude::*;
use std::path::Path;

/// One named series of (x, y) points.
pub struct Series<'a> {
    pub name: String,
    pub points: &'a [(f64, f64)],
    pub style: Style,
    /// Index into the palette.
    pub colour: usize,
}

/// How a series is drawn.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Style {
    /// Points only.
    Markers,
    /// A line.
    Line,
    /// A thin grey line with small crosses at the points: one of many members of a family
    /// (legend entry only when named).
    Faint,
    /// A thick line with triangles at the points: the reference, or the result.
    Thick,
    /// Open rings around points: marks chosen members of a set drawn before them (the
    /// point underneath stays visible).
    Rings,
}

/// Axis scaling.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

pub struct Chart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub x_scale: Scale,
    pub y_scale: Scale,
}

fn range(v: impl Iterator<Item = f64>, scale: Scale) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v.filter(|x| x.is_finite() && (scale == Scale::Linear || *x > 0.0)) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    match scale {
        Scale::Log => (lo / 1.5, hi * 1.5),
        Scale::Linear => {
            let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
            (lo - pad, hi + pad)
        }
    }
}

/// A tick label with at most 4 significant digits (log axes otherwise print round-off).
fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

/// Writes an x–y chart of the series to `path` (PNG, 900×600).
pub fn xy(path: &Path, chart: &Chart, series: &[Series]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("plot {}: {e}", path.display());
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let all = || series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(all().map(|p| p.0), chart.x_scale);
    let (y0, y1) = range(all().map(|p| p.1), chart.y_scale);
    let palette = [&BLUE, &RED, &GREEN, &MAGENTA, &CYAN, &BLACK, &YELLOW];
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(chart.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70);
    macro_rules! draw {
        ($ctx:expr) => {{
            let mut ctx = $ctx;
            ctx.configure_mesh()
                .x_desc(chart.x_label)
                .y_desc(chart.y_label)
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v))
                .draw()
                .map_err(|e| err(&e))?;
            for s in series {
                let c = palette[s.colour % palette.len()];
                let pts = s
                    .points
                    .iter()
                    .copied()
                    .filter(|p| p.0.is_finite() && p.1.is_finite());
                let named = !s.name.is_empty();
                match s.style {
                    Style::Markers => {
                        let a = ctx
                            .draw_series(pts.map(|p| Circle::new(p, 4, c.filled())))
                            .map_err(|e| err(&e))?;
                        if named {
                            a.label(s.name.clone())
                                .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled()));
                        }
                    }
                    Style::Rings => {
                        let a = ctx
                            .draw_series(pts.map(|p| Circle::new(p, 8, c.stroke_width(2))))
                            .map_err(|e| err(&e))?;
                        if named {
                            a.label(s.name.clone()).legend(move |(x, y)| {
                                Circle::new((x + 10, y), 7, c.stroke_width(2))
                            });
                        }
                    }
                    Style::Line | Style::Thick => {
                        let w = if s.style == Style::Thick { 4 } else { 2 };
                        let pts: Vec<_> = pts.collect();
                        let a = ctx
                            .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(w)))
                            .map_err(|e| err(&e))?;
                        if named {
                            a.label(s.name.clone()).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(w))
                            });
                        }
                        if s.style == Style::Thick {
                            ctx.draw_series(
                                pts.iter().map(|&p| TriangleMarker::new(p, 6, c.filled())),
                            )
                            .map_err(|e| err(&e))?;
                        }
                    }
                    Style::Faint => {
                        let grey = RGBColor(150, 150, 150);
                        let pts: Vec<_> = pts.collect();
                        let a = ctx
                            .draw_series(LineSeries::new(pts.iter().copied(), grey.stroke_width(1)))
                            .map_err(|e| err(&e))?;
                        if named {
                            a.label(s.name.clone()).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(1))
                            });
                        }
                        ctx.draw_series(
                            pts.iter().map(|&p| Cross::new(p, 3, grey.stroke_width(1))),
                        )
                        .map_err(|e| err(&e))?;
                    }
                }
            }
            ctx.configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| err(&e))?;
        }};
    }
    match (chart.x_scale, chart.y_scale) {
        (Scale::Linear, Scale::Linear) => draw!(builder
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(&e))?),
        (Scale::Log, Scale::Linear) => draw!(builder
            .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
            .map_err(|e| err(&e))?),
        (Scale::Linear, Scale::Log) => draw!(builder
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(|e| err(&e))?),
        (Scale::Log, Scale::Log) => draw!(builder
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| err(&e))?),
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
