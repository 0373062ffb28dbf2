//! The moving groove of rim_moving.rs solved in the liner's frame (results/rim_liner/):
//! `texopt-lab rim-liner`. In the ring's frame the groove's rim crosses the control volumes,
//! and each one's stored film jumps by the groove's depth as it passes; in the liner's frame
//! the groove stands still, the ring's smooth face moves over it, and a control volume's gap
//! changes only as smoothly as the face does.
//!
//! The same film (rim_moving.rs: one dimension, the parabolic ring face over a rectangular
//! groove 20 times deeper than the land, u = 1, flooded at the inlet, p = 0 at both ends,
//! backward Euler one cell a step, three periods), on nodes that follow the ring by one whole
//! cell a step (a relabelling, no interpolation): the film at node i after a step is the
//! liner's that was at node i − 1 before it, so the storage term reads that old content, and
//! the fluxes are the liner frame's, Couette content carried at −u/2 (the ring's half speed
//! against the liner). The inlet node is the flooded supply; the trailing node holds the film
//! the liner carries out. Two discretisations as in rim_moving.rs: nodal, and the exact
//! two-point flux with the cut cell's storage.
//!
//! Solved by rim_1d.rs's active set on the mirrored film (x → 1 − x), where the Couette
//! content runs towards +x as that solver has it, and the trailing edge is its inlet.
//!
//! Then the step apart from the cells: the nodes follow the ring by k whole cells a step
//! (dt = k·dx/u), so the cells can shrink at a held step and the step on held cells; and BDF2
//! along the liner, its older level relabelled by 2k cells as the last one is by k.

use std::fmt::Write as _;

use crate::liner_frame::bdf2_old_level;

use super::rim_1d::{active_set_from, error_cells, write_report, Storage};
use super::rim_moving::{run as ring_frame, Gap, Scheme, PERIODS, U};

const MESHES: [usize; 6] = [25, 50, 100, 200, 400, 800];
const REFERENCE: usize = 6400;
/// The step held while the cells shrink (units of L/U: 1/200 of the period) and the cells
/// held while the step shrinks.
const HELD_STEP_CELLS: usize = 200;
const SPACE_MESHES: [usize; 5] = [200, 400, 800, 1600, 3200];
const HELD_CELLS: usize = 3200;
const CELLS_A_STEP: [usize; 5] = [16, 8, 4, 2, 1];

/// One backward-Euler step in the liner's frame with the ring's face placed by `gap`, the
/// nodes following the ring by `k` whole cells: the content θ·s per node `content` (the last
/// step's, left as this one's) and the active set `full` (updated). Returns the nodal
/// pressures.
fn step(
    scheme: Scheme,
    gap: &Gap,
    (n, k): (usize, usize),
    dt: f64,
    (content, older): (&mut [f64], Option<&[f64]>),
    full: &mut [bool],
) -> Result<Vec<f64>, String> {
    let (faces, s) = scheme.discretise(gap, n);
    // Mirrored: node j is node n − j, face j face n − 1 − j.
    let m = |i: usize| n - i;
    let faces: Vec<(f64, f64)> = (0..n).map(|j| faces[n - 1 - j]).collect();
    let stored: Vec<f64> = (0..=n).map(|j| s[m(j)]).collect();
    // The liner moved k cells: node i holds what node i − k held, the flooded supply where
    // that was upstream of the domain.
    let moved = |level: &[f64], by: usize| -> Vec<f64> {
        (0..=n)
            .map(|j| if m(j) < by { s[m(j)] } else { level[m(j) - by] })
            .collect()
    };
    let last = moved(content, k);
    let theta_in = (last[0] / stored[0]).min(1.0);
    // BDF2 along the liner: (3φⁿ⁺¹ − 4φⁿ + φⁿ⁻¹)/(2dt), each older level moved with the
    // liner as the last one is; backward Euler where its combined old term would go negative.
    let (old, per_dt) = bdf2_old_level(last, older.map(|o| moved(o, 2 * k)));
    let per_dt = per_dt / dt;
    let mut mfull: Vec<bool> = (0..=n).map(|j| full[m(j)]).collect();
    let storage = Storage {
        s: &stored,
        old: &old,
        per_dt: (1.0 / n as f64) * per_dt,
    };
    let (p, x) =
        active_set_from(&faces, Some(storage), &mut mfull, 4 * n, theta_in).ok_or_else(|| {
            format!(
                "{}: the active set did not settle on {n} cells",
                scheme.name()
            )
        })?;
    for (r, &xr) in x.iter().enumerate() {
        let (j, i) = (r + 1, m(r + 1));
        full[i] = mfull[j];
        content[i] = if full[i] { s[i] } else { xr * s[i] };
    }
    content[0] = s[0];
    content[n] = theta_in * s[n];
    Ok((0..=n).map(|i| p[m(i)]).collect())
}

/// The last period's mean load in the liner's frame, and its change from the period before,
/// one cell a step.
fn run(scheme: Scheme, n: usize) -> Result<(f64, f64), String> {
    run_steps(scheme, n, 1, false)
}

/// The same with the nodes following the ring by `k` cells a step (dt = k·dx/u): the step
/// apart from the cells; by BDF2 along the liner when `bdf2`.
fn run_steps(scheme: Scheme, n: usize, k: usize, bdf2: bool) -> Result<(f64, f64), String> {
    assert_eq!(
        n % k,
        0,
        "{k} cells a step must divide the {n} cells of a period"
    );
    let steps = n / k;
    let dt = k as f64 / (n as f64 * U);
    let (_, s) = scheme.discretise(&Gap { shift: 0.0 }, n);
    let mut content = s;
    let mut older: Option<Vec<f64>> = None;
    let mut full = vec![true; n + 1];
    let mut loads = Vec::new();
    for period in 0..PERIODS {
        let mut w = 0.0;
        for step_no in 1..=steps {
            let gap = Gap {
                shift: U * (period * steps + step_no) as f64 * dt,
            };
            let before = bdf2.then(|| content.clone());
            let levels = (&mut content[..], older.as_deref());
            let p = step(scheme, &gap, (n, k), dt, levels, &mut full)?;
            older = before;
            w += p.iter().sum::<f64>() / n as f64;
        }
        loads.push(w / steps as f64);
    }
    let w = loads[PERIODS - 1];
    Ok((w, w / loads[PERIODS - 2] - 1.0))
}

pub fn main(_args: &[String]) -> Result<(), String> {
    // References: each frame's cut cell on REFERENCE and REFERENCE/2 cells, extrapolated at
    // first order, 2·X(N) − X(N/2).
    let ring_w = {
        let (_, w1, _) = ring_frame(Scheme::CutCell, REFERENCE)?;
        let (_, w2, _) = ring_frame(Scheme::CutCell, REFERENCE / 2)?;
        2.0 * w1 - w2
    };
    let (l1, change) = run(Scheme::CutCell, REFERENCE)?;
    let (l2, _) = run(Scheme::CutCell, REFERENCE / 2)?;
    let liner_w = 2.0 * l1 - l2;
    let (ln, _) = run(Scheme::Nodal, REFERENCE)?;
    let mut md = format!(
        "# The moving groove in the liner's frame\n\n\
         `texopt-lab rim-liner` (a minute): rim_moving's film (a rectangular groove 20 times \
         deeper than the land moving under a parabolic ring face, cavitating, backward Euler \
         one cell a step) solved on nodes that follow the ring by a whole cell a step, the \
         storage term reading the liner's own film (lab/src/studies/rim_liner.rs says how). \
         References, each frame's cut cell on {REFERENCE} and {} cells extrapolated at first \
         order: the last period's mean load {ring_w:.6} in the ring's frame, {liner_w:.6} in \
         the liner's ({:+.1e} apart; on {REFERENCE} cells the liner frame's load changes by \
         {change:+.1e} from the period before, its nodal stencil is {:+.1e} from its cut \
         cell's limit). Relative errors in the load against the ring frame's reference \
         (observed order):\n\n\
         | N | ring frame, nodal | ring frame, cut cell | liner frame, nodal | liner frame, cut cell |\n|---|---|---|---|---|\n",
        REFERENCE / 2,
        liner_w / ring_w - 1.0,
        ln / liner_w - 1.0,
    );
    let mut last = [None; 2];
    for n in MESHES {
        let err = |w: f64| (w / ring_w - 1.0).abs();
        let (_, rn, _) = ring_frame(Scheme::Nodal, n)?;
        let (_, rc, _) = ring_frame(Scheme::CutCell, n)?;
        let (ln, _) = run(Scheme::Nodal, n)?;
        let (lc, _) = run(Scheme::CutCell, n)?;
        let _ = write!(md, "| {n} |");
        error_cells(&mut md, (err(rn), err(rc)), &mut last[0]);
        error_cells(&mut md, (err(ln), err(lc)), &mut last[1]);
        let _ = writeln!(md);
    }
    md.push_str(
        "\nWhat it says. The two frames solve the same film: their references meet within the \
         extrapolations' own error. In the liner's frame the cut cell (the exact two-point flux, \
         the control volume's film volume as storage) converges at first order, monotonically \
         and with a constant an order of magnitude below the ring frame's: no rim crosses a \
         control volume, so a step's storage change is the ring face's smooth one. Being \
         monotone, its error is told by the change from one mesh to the next (Richardson), \
         which neither ring-frame stencil allows. The nodal stencil is about as erratic in \
         either frame (its error depends on where the rim falls between nodes) and on these \
         meshes smaller; the cut cell still carries its cavitated film at the content \
         θ·∫h⁻²/∫h⁻³ where its storage is θ·(mean gap), the first-order error left in the \
         cells that hold a rim (the second measurement below says how little that weighs). \
         Not measured here: two dimensions.\n",
    );
    md.push_str(&step_tables(liner_w)?);
    write_report("rim_liner", &md)
}

/// The step apart from the cells: the cells shrinking at a held step, the step shrinking on
/// held cells; relative errors in the load against the liner frame's reference.
fn step_tables(reference: f64) -> Result<String, String> {
    let mut md = format!(
        "\n## The step apart from the cells\n\n\
         The nodes may follow the ring by k whole cells a step (dt = k·dx/u): the step is then \
         apart from the cells. Relative errors in the load against the liner frame's \
         reference (observed order), the step held at 1/{HELD_STEP_CELLS} of the period while \
         the cells shrink:\n\n\
         | N | k | nodal | cut cell |\n|---|---|---|---|\n"
    );
    let err = |w: f64| (w / reference - 1.0).abs();
    let mut last = None;
    for n in SPACE_MESHES {
        let k = n / HELD_STEP_CELLS;
        let (wn, _) = run_steps(Scheme::Nodal, n, k, false)?;
        let (wc, _) = run_steps(Scheme::CutCell, n, k, false)?;
        let _ = write!(md, "| {n} | {k} |");
        error_cells(&mut md, (err(wn), err(wc)), &mut last);
        let _ = writeln!(md);
    }
    let _ = write!(
        md,
        "\nand the cells held at N = {HELD_CELLS} while the step shrinks:\n\n\
         | k | dt | nodal | cut cell |\n|---|---|---|---|\n"
    );
    let mut last = None;
    for k in CELLS_A_STEP {
        let (wn, _) = run_steps(Scheme::Nodal, HELD_CELLS, k, false)?;
        let (wc, _) = run_steps(Scheme::CutCell, HELD_CELLS, k, false)?;
        let _ = write!(md, "| {k} | {:.2e} |", k as f64 / (HELD_CELLS as f64 * U));
        error_cells(&mut md, (err(wn), err(wc)), &mut last);
        let _ = writeln!(md);
    }
    md.push_str(&bdf2_table()?);
    md.push_str(
        "\nWhat it says. In the liner's frame the cut cell's error is the time step's: at a \
         held step its load does not move as the cells shrink, and on held cells its error \
         halves with the step, first order to two digits: backward Euler's error along the \
         liner, a constant times dt (about 8.7·dt, dt in periods of the groove), whatever the \
         cells. The first table's first order in N is this error, its step shrinking with its \
         cells. The nodal stencil's error instead grows as its cells shrink at a held step: \
         its error from where the rim falls between nodes and its step's error have opposite \
         signs and cancel on the coarse meshes. So in the liner's frame the rims no longer set \
         the error; the step does, smoothly, and BDF2 along the liner (its older level \
         relabelled as the last one is, backward Euler where the combined old term would go \
         negative) takes most of it away: its changes fall twenty-fold at the first halvings of \
         the step, then, below 3e-5 of the load, stop following one order (a cavitation \
         front moves by whole cells). At 1/800 of a period (k = 4) it is within 1e-4 of its \
         value at the finest step, where backward Euler is 1.1 % off its limit. With the \
         cells' error below 1e-4 of the load from 200 cells (the first table), a few hundred \
         cells and about 800 steps a period would then be within 0.1 %, in one dimension. \
         Still to measure: the same in two \
         dimensions (the strips across a pocket's curved rim in the cut cell's place) with the \
         ring's dynamics, at R = 3.2 and 25.6.\n",
    );
    Ok(md)
}

/// BDF2 along the liner against backward Euler, the cut cell on held cells: each load and its
/// change from the step twice as long, with the ratio of successive changes (2: first order,
/// 4: second).
fn bdf2_table() -> Result<String, String> {
    let mut md = String::from(
        "\nand the same cells with BDF2 along the liner (the cut cell's load at each step, its \
         change from the step twice as long, and the ratio of successive changes: 2 is first \
         order, 4 second):\n\n\
         | k | dt | backward Euler | change (ratio) | BDF2 | change (ratio) |\n|---|---|---|---|---|---|\n"
    );
    let mut last: [Option<(f64, Option<f64>)>; 2] = [None, None];
    for k in CELLS_A_STEP {
        let _ = write!(md, "| {k} | {:.2e} |", k as f64 / (HELD_CELLS as f64 * U));
        for (col, bdf2) in [false, true].into_iter().enumerate() {
            let (w, _) = run_steps(Scheme::CutCell, HELD_CELLS, k, bdf2)?;
            let change = last[col].map(|(before, _)| w - before);
            let ratio = match (last[col].and_then(|(_, c)| c), change) {
                (Some(c0), Some(c1)) => format!(" ({:.1})", c0 / c1),
                _ => String::new(),
            };
            let shown = change.map_or("–".to_string(), |c| format!("{:+.2e}{ratio}", c / w));
            let _ = write!(md, " {w:.7} | {shown} |");
            last[col] = Some((w, change));
        }
        let _ = writeln!(md);
    }
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn in_the_liner_frame_the_cut_cell_s_error_is_the_step_s() {
        let w = |n, k| run_steps(Scheme::CutCell, n, k, false).unwrap().0;
        // The step halved on held cells: the change halves (first order in dt).
        let (c1, c2, c3) = (w(800, 4), w(800, 2), w(800, 1));
        let ratio = (c1 - c2) / (c2 - c3);
        assert!((1.8..2.2).contains(&ratio), "{c1} {c2} {c3}: ratio {ratio}");
        // The cells halved at a held step: the load moves by under 5 % of what halving the
        // step moves it (measured: 0.01 %).
        let cells = (w(400, 2) / c1 - 1.0).abs();
        assert!(cells < 0.05 * (c1 / c2 - 1.0).abs(), "{cells}");
        // BDF2 along the liner: the same halving moves the load by under a tenth of backward
        // Euler's change (measured at 3200 cells: a twentieth).
        let b = |k| run_steps(Scheme::CutCell, 800, k, true).unwrap().0;
        let bdf2 = (b(4) - b(2)).abs();
        assert!(bdf2 < 0.1 * (c1 - c2).abs(), "{bdf2} against {}", c1 - c2);
    }

    #[test]
    fn the_liner_frame_cut_cell_converges_at_first_order_to_the_ring_frame_film() {
        // Halving the cells halves the change (first order, one sign), and the extrapolated
        // load meets the ring frame's nodal stencil on 800 cells within 1 % (its error there
        // is 0.4 %, results/rim_moving/).
        let w = |n| run(Scheme::CutCell, n).unwrap().0;
        let (w1, w2, w3) = (w(100), w(200), w(400));
        let ratio = (w1 - w2) / (w2 - w3);
        assert!((1.7..2.3).contains(&ratio), "{w1} {w2} {w3}: ratio {ratio}");
        let extrapolated = 2.0 * w3 - w2;
        let (_, ring, _) = ring_frame(Scheme::Nodal, 800).unwrap();
        assert!(
            (extrapolated / ring - 1.0).abs() < 0.01,
            "{extrapolated} {ring}"
        );
    }
}
