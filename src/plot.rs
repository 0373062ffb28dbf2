//! Charts (PNG via plotters): the few shapes the studies need, each a plain function of
//! named series, so a study file stays a short description of what it shows.

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

use crate::output::{Cause, OutputError};

/// Why plotters could not draw a chart.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The legend's text could not be measured.
    #[error("legend text: {0}")]
    Legend(Cause),
    #[error("{0}")]
    Draw(Cause),
}

/// plotters' error as a drawing failure.
pub fn drawing(e: impl std::error::Error + Send + Sync + 'static) -> PlotError {
    PlotError::Draw(Box::new(e))
}

/// One named series of (x, y) points.
pub struct Series<'a> {
    pub name: String,
    pub points: &'a [(f64, f64)],
    pub style: Style,
    /// Index into the palette.
    pub colour: usize,
}

impl<'a> Series<'a> {
    /// A family of faint curves in the first colour, the legend naming it once (`name`, on
    /// the first curve).
    pub fn faint_family(curves: &'a [Vec<(f64, f64)>], name: String) -> Vec<Series<'a>> {
        let mut name = Some(name);
        curves
            .iter()
            .map(|c| Series {
                name: name.take().unwrap_or_default(),
                points: c,
                style: Style::Faint,
                colour: 0,
            })
            .collect()
    }

    /// The points that are drawn (a failed case's NaN is left out, not plotted).
    fn drawn(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    }
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
    /// The points taken two by two, each pair a short line: error bars ((x, y − u) to
    /// (x, y + u), or along x).
    Segments,
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
        Scale::Log => {
            // plotters ticks a log axis from its first power of ten up: start the axis at
            // one when that would otherwise leave over half a decade unlabelled.
            let lo = lo / 1.5;
            let decade = 10f64.powf(lo.log10().ceil());
            // (Just below the power of ten, so that round-off cannot drop its tick.)
            let lo = if (decade / lo).log10() > 0.5 {
                decade / 10.0 * 0.999
            } else if decade / lo < 1.001 {
                decade * 0.999
            } else {
                lo
            };
            (lo, hi * 1.5)
        }
        Scale::Linear => {
            // A single value (every zone plain: depth 0) gets a unit around it, not ±1e-13.
            if hi - lo <= 1e-9 * hi.abs().max(lo.abs()) {
                let half = 0.5 * hi.abs().max(1.0);
                return (lo - half, hi + half);
            }
            let pad = 0.05 * (hi - lo);
            (lo - pad, hi + pad)
        }
    }
}

/// A tick label with at most 4 significant digits (log axes otherwise print round-off).
fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        trim(&format!("{v:.digits$}"))
    } else {
        // "2e-4", not "2.00e-4": crowded log axes need short labels.
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m)),
            None => s,
        }
    }
}

/// A tick label on a log axis spanning `decades`: over a decade or more only 1, 2 and 5
/// times a power of ten are labelled (plotters puts a tick at every digit, whose labels
/// then run into each other).
fn log_tick(v: f64, decades: f64) -> String {
    if decades >= 1.0 && v > 0.0 {
        let mantissa = v / 10f64.powf(v.log10().floor());
        if ![1.0, 2.0, 5.0, 10.0]
            .iter()
            .any(|m| (mantissa - m).abs() < 1e-6 * m)
        {
            return String::new();
        }
    }
    tick(v)
}

/// Font, inner margin and symbol width of plotters' series labels (its defaults, which
/// `xy` keeps), to know the legend's size before it is drawn.
const LEGEND_FONT: (&str, f64) = ("sans-serif", 12.0);
const LEGEND_MARGIN: i32 = 10;
const LEGEND_SYMBOL: i32 = 30;
/// Gap plotters leaves between the legend and the plotting area's edge.
const LEGEND_INSET: i32 = 5;

/// The legend's size in pixels for these labels, as plotters lays it out.
fn legend_size(names: &[&str]) -> Result<(i32, i32), PlotError> {
    let font: TextStyle = LEGEND_FONT.into_font().into();
    let mut text = MultiLineText::<_, &str>::new((0, 0), &font);
    for n in names {
        text.push_line(*n);
    }
    let (w, h) = text
        .estimate_dimension()
        .map_err(|e| PlotError::Legend(Box::new(e)))?;
    Ok((w + LEGEND_SYMBOL + 2 * LEGEND_MARGIN, h + 2 * LEGEND_MARGIN))
}

/// What each series puts on the plotting area, in its pixels: (x, y, weight), the points
/// and samples every few pixels along drawn lines. The family's faint lines weigh less
/// than the series a chart is about.
fn ink(series: &[Series], to_px: impl Fn((f64, f64)) -> (i32, i32)) -> Vec<(i32, i32, u32)> {
    let mut out = Vec::new();
    for s in series {
        let weight = if s.style == Style::Faint { 1 } else { 4 };
        let px: Vec<(i32, i32)> = s.drawn().map(&to_px).collect();
        out.extend(px.iter().map(|&(x, y)| (x, y, weight)));
        if matches!(s.style, Style::Line | Style::Thick | Style::Faint) {
            for seg in px.windows(2) {
                let (a, b) = (seg[0], seg[1]);
                let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 3).max(1);
                for k in 1..n {
                    let t = k as f64 / n as f64;
                    let x = a.0 as f64 + t * (b.0 - a.0) as f64;
                    let y = a.1 as f64 + t * (b.1 - a.1) as f64;
                    out.push((x.round() as i32, y.round() as i32, weight));
                }
            }
        }
    }
    out
}

/// The legend position, among plotters' nine, whose box covers the least ink (`ink`) on a
/// plotting area of `area` pixels; ties go to the first in reading preference (corners,
/// right before left, top before bottom).
fn least_covered(
    ink: &[(i32, i32, u32)],
    legend: (i32, i32),
    area: (i32, i32),
) -> SeriesLabelPosition {
    use SeriesLabelPosition::*;
    let (lw, lh) = legend;
    let (aw, ah) = area;
    let candidates = [
        UpperRight,
        UpperLeft,
        LowerRight,
        LowerLeft,
        MiddleRight,
        MiddleLeft,
        UpperMiddle,
        LowerMiddle,
        MiddleMiddle,
    ];
    // The same layout as plotters' `SeriesLabelPosition` (private there).
    let corner = |p: &SeriesLabelPosition| -> (i32, i32) {
        let x = match p {
            UpperLeft | MiddleLeft | LowerLeft => LEGEND_INSET,
            UpperMiddle | MiddleMiddle | LowerMiddle => (aw - lw) / 2,
            _ => aw - lw - LEGEND_INSET,
        };
        let y = match p {
            UpperLeft | UpperMiddle | UpperRight => LEGEND_INSET,
            MiddleLeft | MiddleMiddle | MiddleRight => (ah - lh) / 2,
            _ => ah - lh - LEGEND_INSET,
        };
        (x, y)
    };
    // A marker reaches a few pixels beyond its point.
    let pad = 4;
    let covered = |p: &SeriesLabelPosition| -> u64 {
        let (x0, y0) = corner(p);
        ink.iter()
            .filter(|&&(x, y, _)| {
                x >= x0 - pad && x <= x0 + lw + pad && y >= y0 - pad && y <= y0 + lh + pad
            })
            .map(|&(_, _, w)| w as u64)
            .sum()
    };
    // `min_by_key` keeps the first of equal minima, i.e. the preferred one.
    candidates
        .into_iter()
        .min_by_key(covered)
        .unwrap_or(UpperRight)
}

/// Where a note of `chars` characters goes beside the point `at` (pixels): centred on it, a
/// line clear of its marker, above or below it, a line further out when the nearer places
/// would run into a note already `placed` (rectangles left, top, right, bottom).
fn note_place(placed: &[(i32, i32, i32, i32)], at: (i32, i32), chars: i32) -> (i32, i32) {
    let (w, h) = (6 * chars, 12);
    let left = at.0 - w / 2;
    let free = |top: i32| {
        placed
            .iter()
            .all(|&(l, t, r, b)| left + w <= l || left >= r || top + h <= t || top >= b)
    };
    [-22, 10, -36, 24, -50, 38]
        .iter()
        .map(|dy| at.1 + dy)
        .find(|&top| free(top))
        .map_or((left, at.1 - 22), |top| (left, top))
}

/// A short text at a point of the chart (e.g. what a point of an envelope is).
pub struct Note {
    pub at: (f64, f64),
    pub text: String,
}

/// Writes an x–y chart of the series to `path` (PNG, 900×600).
pub fn xy(path: &Path, chart: &Chart, series: &[Series]) -> Result<(), OutputError> {
    xy_noted(path, chart, series, &[])
}

/// As `xy`, with notes written beside their points, above or below them, wherever they do
/// not run into the notes written before.
pub fn xy_noted(
    path: &Path,
    chart: &Chart,
    series: &[Series],
    notes: &[Note],
) -> Result<(), OutputError> {
    crate::output::atomically(path, |tmp| draw(tmp, chart, series, notes))
}

fn draw(path: &Path, chart: &Chart, series: &[Series], notes: &[Note]) -> Result<(), PlotError> {
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(drawing)?;
    let all = || series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(all().map(|p| p.0), chart.x_scale);
    let (y0, y1) = range(all().map(|p| p.1), chart.y_scale);
    let decades = ((x1 / x0).log10(), (y1 / y0).log10());
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(chart.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70);
    let parts = Parts {
        root: &root,
        chart,
        series,
        notes,
        decades,
    };
    match (chart.x_scale, chart.y_scale) {
        (Scale::Linear, Scale::Linear) => parts.fill(
            builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(drawing)?,
        )?,
        (Scale::Log, Scale::Linear) => parts.fill(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(drawing)?,
        )?,
        (Scale::Linear, Scale::Log) => parts.fill(
            builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(drawing)?,
        )?,
        (Scale::Log, Scale::Log) => parts.fill(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(drawing)?,
        )?,
    }
    root.present().map_err(drawing)?;
    Ok(())
}

/// The plotting area of a chart, whatever the scales of its axes.
type Plot<'a, 'p, X, Y> = ChartContext<'a, BitMapBackend<'p>, Cartesian2d<X, Y>>;

/// What a chart is drawn from: the image, the chart's texts and scales, its series and notes,
/// and the decades its axes span (`log_tick`).
struct Parts<'a, 'p> {
    root: &'a DrawingArea<BitMapBackend<'p>, Shift>,
    chart: &'a Chart<'a>,
    series: &'a [Series<'a>],
    notes: &'a [Note],
    decades: (f64, f64),
}

impl<'a, 'p> Parts<'a, 'p> {
    /// Draws onto the plotting area, in this order: axes, series, notes, legend (each drawn
    /// over the ones before).
    fn fill<X, Y>(&self, mut plot: Plot<'a, 'p, X, Y>) -> Result<(), PlotError>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        self.axes(&mut plot)?;
        for s in self.series {
            draw_series(&mut plot, s)?;
        }
        self.write_notes(&plot)?;
        self.legend(&mut plot)
    }

    fn axes<X, Y>(&self, plot: &mut Plot<'a, 'p, X, Y>) -> Result<(), PlotError>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let label = |v: f64, scale: Scale, decades: f64| match scale {
            Scale::Linear => tick(v),
            Scale::Log => log_tick(v, decades),
        };
        let (chart, (x_decades, y_decades)) = (self.chart, self.decades);
        plot.configure_mesh()
            .x_desc(chart.x_label)
            .y_desc(chart.y_label)
            .x_label_formatter(&|v| label(*v, chart.x_scale, x_decades))
            .y_label_formatter(&|v| label(*v, chart.y_scale, y_decades))
            .draw()
            .map_err(drawing)
    }

    /// The notes, each beside its point where it runs into no note written before it.
    fn write_notes<X, Y>(&self, plot: &Plot<'a, 'p, X, Y>) -> Result<(), PlotError>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let font = ("sans-serif", 11).into_font().color(&BLACK);
        let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
        for n in self.notes {
            let (x, y) = plot.backend_coord(&n.at);
            let (left, top) = note_place(&placed, (x, y), n.text.chars().count() as i32);
            placed.push((
                left,
                top,
                left + 6 * n.text.chars().count() as i32,
                top + 12,
            ));
            self.root
                .draw(&Text::new(n.text.clone(), (left, top), font.clone()))
                .map_err(drawing)?;
        }
        Ok(())
    }

    /// The legend, where it hides the least of what was drawn (a fixed corner covered the
    /// untextured line in Fig. 6).
    fn legend<X, Y>(&self, plot: &mut Plot<'a, 'p, X, Y>) -> Result<(), PlotError>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let base = plot.plotting_area().get_base_pixel();
        let (w, h) = plot.plotting_area().dim_in_pixel();
        let ink = ink(self.series, |p| {
            let b = plot.backend_coord(&p);
            (b.0 - base.0, b.1 - base.1)
        });
        let names: Vec<&str> = self
            .series
            .iter()
            .filter(|s| !s.name.is_empty())
            .map(|s| s.name.as_str())
            .collect();
        let position = least_covered(&ink, legend_size(&names)?, (w as i32, h as i32));
        plot.configure_series_labels()
            .position(position)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(drawing)
    }
}

/// Colours of the series, by their `colour` index.
const PALETTE: [&RGBColor; 7] = [&BLUE, &RED, &GREEN, &MAGENTA, &CYAN, &BLACK, &YELLOW];

/// One series in its style, with its legend entry when it is named.
fn draw_series<X, Y>(plot: &mut Plot<'_, '_, X, Y>, s: &Series) -> Result<(), PlotError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let c = PALETTE[s.colour % PALETTE.len()];
    let pts = s.drawn();
    let named = !s.name.is_empty();
    match s.style {
        Style::Markers => {
            let a = plot
                .draw_series(pts.map(|p| Circle::new(p, 4, c.filled())))
                .map_err(drawing)?;
            if named {
                a.label(s.name.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled()));
            }
        }
        Style::Rings => {
            let a = plot
                .draw_series(pts.map(|p| Circle::new(p, 8, c.stroke_width(2))))
                .map_err(drawing)?;
            if named {
                a.label(s.name.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 7, c.stroke_width(2)));
            }
        }
        Style::Line | Style::Thick => {
            let w = if s.style == Style::Thick { 4 } else { 2 };
            let pts: Vec<_> = pts.collect();
            let a = plot
                .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(w)))
                .map_err(drawing)?;
            if named {
                a.label(s.name.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(w))
                });
            }
            if s.style == Style::Thick {
                plot.draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 6, c.filled())))
                    .map_err(drawing)?;
            }
        }
        Style::Segments => {
            let pts: Vec<_> = pts.collect();
            let w = 2;
            let a = plot
                .draw_series(
                    pts.chunks_exact(2)
                        .map(|ab| PathElement::new(vec![ab[0], ab[1]], c.stroke_width(w))),
                )
                .map_err(drawing)?;
            if named {
                a.label(s.name.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x + 10, y - 6), (x + 10, y + 6)], c.stroke_width(w))
                });
            }
        }
        Style::Faint => {
            let grey = RGBColor(150, 150, 150);
            let pts: Vec<_> = pts.collect();
            let a = plot
                .draw_series(LineSeries::new(pts.iter().copied(), grey.stroke_width(1)))
                .map_err(drawing)?;
            if named {
                a.label(s.name.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(1))
                });
            }
            plot.draw_series(pts.iter().map(|&p| Cross::new(p, 3, grey.stroke_width(1))))
                .map_err(drawing)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(p: SeriesLabelPosition) -> String {
        format!("{p:?}")
    }

    #[test]
    fn the_legend_goes_to_the_emptiest_place() {
        let (area, legend) = ((800, 500), (200, 80));
        // Nothing drawn: the first preference.
        assert_eq!(at(least_covered(&[], legend, area)), "UpperRight");
        // A rising line fills the upper right and lower left: upper left is free.
        let rising: Vec<_> = (0..800).map(|x| (x, 500 - x * 500 / 800, 4)).collect();
        assert_eq!(at(least_covered(&rising, legend, area)), "UpperLeft");
        // Faint family everywhere but the lower right, key series crossing the upper left:
        // the box goes over nothing rather than over a few faint marks or the key series.
        let mut ink: Vec<_> = (0..800)
            .flat_map(|x| (0..500).step_by(10).map(move |y| (x, y, 1)))
            .filter(|&(x, y, _)| !(x > 550 && y > 380))
            .collect();
        ink.extend((0..800).map(|x| (x, 40, 4)));
        assert_eq!(at(least_covered(&ink, legend, area)), "LowerRight");
    }

    #[test]
    fn tick_labels_are_short() {
        let got: Vec<String> = [0.0, 2e-4, 2.5e-4, 0.001, 0.0015, 1.0, 12.5, 3e5]
            .into_iter()
            .map(tick)
            .collect();
        assert_eq!(
            got,
            ["0", "2e-4", "2.5e-4", "0.001", "0.0015", "1", "12.5", "3e5"]
        );
    }

    #[test]
    fn log_axes_over_a_decade_label_one_two_five() {
        let labels: Vec<String> = [1e-4, 2e-4, 3e-4, 5e-4, 9.99999e-4, 1e-3, 4e-3]
            .into_iter()
            .map(|v| log_tick(v, 1.5))
            .collect();
        assert_eq!(labels, ["1e-4", "2e-4", "", "5e-4", "", "0.001", ""]);
        // Within a decade every tick keeps its label.
        assert_eq!(log_tick(3e-4, 0.5), "3e-4");
    }

    #[test]
    fn a_log_axis_starts_where_its_ticks_can_label_it() {
        // 0.35 / 1.5 = 0.23 would leave 0.23–1 without a tick: the axis starts just below 0.1.
        let (lo, hi) = range([0.35, 9.0].into_iter(), Scale::Log);
        assert!(
            (lo - 0.0999).abs() < 1e-12 && (hi - 13.5).abs() < 1e-12,
            "{lo} {hi}"
        );
        // 0.15 / 1.5 = 0.1 to round-off, which plotters may take for 1's decade.
        let (lo, _) = range([0.15, 9.0].into_iter(), Scale::Log);
        assert!((lo - 0.0999).abs() < 1e-12, "{lo}");
        // 0.07 / 1.5 = 0.047 is within half a decade of 0.1: kept.
        let (lo, _) = range([0.07, 0.5].into_iter(), Scale::Log);
        assert!((lo - 0.07 / 1.5).abs() < 1e-12, "{lo}");
    }

    #[test]
    fn the_legend_size_grows_with_its_labels() {
        let one = legend_size(&["a"]).unwrap();
        let two = legend_size(&["a", "a much longer label"]).unwrap();
        assert!(two.0 > one.0 && two.1 > one.1, "{one:?} {two:?}");
        assert!(one.0 >= LEGEND_SYMBOL + 2 * LEGEND_MARGIN);
    }
}
