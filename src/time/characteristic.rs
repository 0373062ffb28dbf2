//! The film's storage term along the Couette characteristics (docs/solver.md, "Time
//! scheme"): the film content φ = hθ travels at u/2 wherever the film is cavitated
//! (docs/model.md §3), so a step takes its old level at the foot of that characteristic,
//! x1 − (u/2)·dt, and the stencil keeps only the Poiseuille fluxes. At a Courant number
//! c = u·dt/(2·dx1) of exactly 1 the foot is the node upstream and the transport of the
//! cavitated film is exact; below 1 it is interpolated linearly between the two nodes
//! around the foot (a convex combination: positive, and mass-conserving up to the inlet's
//! inflow and the outlet's outflow). Above 1 the foot would skip a node, and content from
//! the wide gap ahead of the ring would land two cells deep under the ring face, where no
//! pressure gradient can return it: the numerics reject c > 1.

/// Largest Courant number u·dt/(2·dx1) of the characteristic scheme (round-off above 1
/// counts as 1).
pub const MAX_COURANT: f64 = 1.0 + 1e-9;

/// The Courant number of the film content, u·dt/(2·dx1), rounded to 1 where it is 1 to
/// round-off (a step chosen as 2·dx1/u and then fitted to divide the texture period).
pub fn courant(u: f64, dt: f64, dx: f64) -> f64 {
    let c = 0.5 * u * dt / dx;
    if (c - 1.0).abs() < 1e-9 {
        1.0
    } else {
        c
    }
}

/// Moves the film φ (node columns 0..=n1 of n2 nodes) by `c` cells downstream, in place:
/// column i takes the value at x_i − c·dx1, interpolated linearly between the columns
/// around it; columns upstream of column 0 read column 0 (the inlet's film).
pub fn shift(phi: &mut [f64], n1: usize, n2: usize, c: f64) {
    debug_assert!((0.0..=MAX_COURANT).contains(&c), "Courant number {c}");
    let whole = c.floor() as usize;
    let f = c - whole as f64;
    // Descending columns: each reads only columns at or upstream of itself, not yet written.
    for i in (1..=n1).rev() {
        let a = i.saturating_sub(whole);
        let b = a.saturating_sub(1);
        let (lo, hi) = phi.split_at_mut(i * n2);
        let dst = &mut hi[..n2];
        if a == i {
            // c < 1: between column i itself and the one upstream.
            let up = &lo[b * n2..(b + 1) * n2];
            for (d, &u) in dst.iter_mut().zip(up) {
                *d = (1.0 - f) * *d + f * u;
            }
        } else {
            let (pa, pb) = (&lo[a * n2..(a + 1) * n2], &lo[b * n2..(b + 1) * n2]);
            for ((d, &x), &y) in dst.iter_mut().zip(pa).zip(pb) {
                *d = (1.0 - f) * x + f * y;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(n1: usize, n2: usize) -> Vec<f64> {
        (0..(n1 + 1) * n2)
            .map(|k| 1.0 + ((k * 37) % 11) as f64)
            .collect()
    }

    #[test]
    fn a_unit_courant_number_moves_every_column_one_downstream() {
        let (n1, n2) = (9, 3);
        let before = field(n1, n2);
        let mut phi = before.clone();
        shift(&mut phi, n1, n2, 1.0);
        for i in 1..=n1 {
            assert_eq!(phi[i * n2..(i + 1) * n2], before[(i - 1) * n2..i * n2]);
        }
        assert_eq!(phi[..n2], before[..n2], "the inlet column stays");
    }

    /// Over the interior columns 1..n1 − 1 (column n1 is the outlet): Σφ after = Σφ before
    /// + c·(inlet column) − c·(last interior column), the film in and out through the ends.
    #[test]
    fn the_shift_conserves_the_film_but_the_boundary_flows() {
        let (n1, n2) = (12, 2);
        let col = |v: &[f64], i: usize| v[i * n2..(i + 1) * n2].iter().sum::<f64>();
        let interior = |v: &[f64]| (1..n1).map(|i| col(v, i)).sum::<f64>();
        for c in [0.0, 0.25, 0.5, 0.97, 1.0] {
            let before = field(n1, n2);
            let mut phi = before.clone();
            shift(&mut phi, n1, n2, c);
            let expected = interior(&before) + c * col(&before, 0) - c * col(&before, n1 - 1);
            assert!((interior(&phi) - expected).abs() < 1e-12, "c = {c}");
        }
    }

    #[test]
    fn between_nodes_the_foot_is_interpolated() {
        let (n1, n2) = (4, 1);
        let mut phi = vec![0.0, 10.0, 20.0, 30.0, 40.0];
        shift(&mut phi, n1, n2, 0.25);
        assert_eq!(phi, vec![0.0, 7.5, 17.5, 27.5, 37.5]);
    }

    #[test]
    fn round_off_above_one_counts_as_one() {
        let dx: f64 = 0.2 / 700.0;
        let dt = 0.06 / (0.06f64 / (2.0 * dx)).round();
        assert_eq!(courant(1.0, dt, dx), 1.0);
        assert!((courant(1.0, 0.5 * dt, dx) - 0.5).abs() < 1e-12);
    }
}
