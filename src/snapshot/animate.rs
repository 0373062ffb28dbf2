//! The animation: the pocket passing under the ring over the last period, one GIF frame a
//! recorded step — the pressure map above, the centre-line p and h below, on scales fixed
//! over the period.

use std::path::Path;

use plotters::prelude::*;

use super::columns::Units;
use super::draw::{
    case_line, colour_bar, fields, map_panel, profile_axes, profile_panel, Area, MAP_KEY,
};
use super::{Context, Recording, SnapshotError};
use crate::plot::drawing;
use crate::plot::PlotError;

/// Time each GIF frame shows (ms).
const FRAME_DELAY_MS: u32 = 120;

/// Writes the animation of `rec` to `path` (a .gif).
pub fn animate(path: &Path, rec: &Recording, cx: &Context) -> Result<(), SnapshotError> {
    if rec.animation.is_empty() {
        return Err(SnapshotError::NoAnimation);
    }
    crate::output::atomically(path, |tmp| {
        let root = BitMapBackend::gif(tmp, (820, 580), FRAME_DELAY_MS)
            .map_err(drawing)?
            .into_drawing_area();
        let [pressure, ..] = fields(rec, cx, &rec.animation);
        let axes = profile_axes(rec, cx, &rec.animation);
        let u = Units::of(cx);
        for f in &rec.animation {
            root.fill(&WHITE).map_err(drawing)?;
            let (title, rest) = root.split_vertically(40);
            title
                .draw(&Text::new(case_line(cx), (10, 4), ("sans-serif", 16)))
                .map_err(drawing)?;
            title
                .draw(&Text::new(MAP_KEY, (10, 23), ("sans-serif", 12)))
                .map_err(drawing)?;
            let (map, profile): (Area, Area) = rest.split_vertically(290);
            let (map, bar) = map.split_horizontally(730);
            let caption = format!(
                "pressure p (MPa) at t = {:.4} ms (Z = {:.3} µm, f = {:.4})",
                f.t * u.ms,
                f.z,
                f.f
            );
            map_panel(&map, rec, cx, f, &pressure, &caption)?;
            colour_bar(&bar.margin(30, 40, 5, 5), &pressure)?;
            profile_panel(
                &profile,
                rec,
                cx,
                f,
                axes,
                "centre line: p (blue, MPa), h (red, µm)",
            )?;
            root.present().map_err(drawing)?;
        }
        Ok::<(), PlotError>(())
    })?;
    Ok(())
}
