//! What the snapshot files and pictures share: their units and the node columns they show.

use super::{Context, Recording};

/// Units of the files: x1, x2 in mm, p in MPa, h and Z in µm, t in ms, W_h in N/m.
pub(super) struct Units {
    pub mm_per_cm: f64,
    pub mpa: f64,
    pub ms: f64,
    pub n_per_m: f64,
}

impl Units {
    pub fn of(cx: &Context) -> Self {
        Units {
            mm_per_cm: 10.0,
            mpa: cx.scales.pressure_pa() * 1e-6,
            ms: cx.scales.time_ms(),
            n_per_m: cx.scales.load_n_per_m(),
        }
    }
}

/// The node columns the maps and the CSV cover: the ring and a quarter of its width on each
/// side (the film beyond carries no load and changes only by transport).
pub(super) fn shown_columns(rec: &Recording, cx: &Context) -> std::ops::RangeInclusive<usize> {
    let g = &rec.grid;
    let (a, b) = cx.case.contact().ring_edges();
    let m = 0.25 * (b - a);
    let first = (0..=g.n1).find(|&i| g.x(i) >= a - m).unwrap_or(0);
    let last = (0..=g.n1).rev().find(|&i| g.x(i) <= b + m).unwrap_or(g.n1);
    first..=last
}
