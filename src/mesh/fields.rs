//! The film fields on the mesh at one time level: pressure, film content and active set.

use super::{Gap, Grid};
use crate::model::film::Boundary;

/// The film fields at one time level.
#[derive(Debug)]
pub struct FilmState {
    /// Pressure p (units of 6μUL/H²).
    pub p: Vec<f64>,
    /// Film content φ = hθ (µm).
    pub phi: Vec<f64>,
    /// Active set: node pressurised (θ = 1).
    pub pressurised: Vec<bool>,
    /// With two gas pressures (docs/model.md §3), each node's cavity pressure for the solve
    /// at hand: fixed from the active set the solve starts with ([`cavity_pressures`]), so
    /// that a solve is a complementarity problem with a fixed floor at each node. Empty with
    /// one cavity pressure.
    pub cavity: Vec<f64>,
}

impl FilmState {
    /// Takes `other`'s values (same grid), reusing the allocations.
    pub fn assign(&mut self, other: &FilmState) {
        self.p.copy_from_slice(&other.p);
        self.phi.copy_from_slice(&other.phi);
        self.pressurised.copy_from_slice(&other.pressurised);
    }

    /// Zero pressure and film φ_0 everywhere (capped at the local gap), nothing pressurised.
    /// A film solve lays the cavity pressures of its boundary data on the cavitated nodes
    /// ([`FilmState::lay_cavity_pressure`]).
    pub fn cavitated(grid: &Grid, gap: &Gap, z: f64, phi0: f64) -> Self {
        let n = grid.nodes();
        let phi = (0..n).map(|k| phi0.min(gap.h(grid, k, z))).collect();
        FilmState {
            p: vec![0.0; n],
            phi,
            pressurised: vec![false; n],
            cavity: Vec::new(),
        }
    }
    /// Fixes the cavity pressures of a solve with boundary data `bc` (docs/model.md §3): with
    /// two gas pressures from the active set as it is ([`cavity_pressures`]), and lays them on
    /// every cavitated node of the interior columns 1..n1 − 1.
    pub fn lay_cavity_pressure(&mut self, grid: &Grid, bc: &Boundary) {
        if bc.split_cavity() {
            cavity_pressures(grid, bc, &self.pressurised, &mut self.cavity);
        } else {
            self.cavity.clear();
        }
        for i in 1..grid.n1 {
            let pc = bc.cavity_pressure(i, grid.n1);
            for k in i * grid.n2..(i + 1) * grid.n2 {
                if !self.pressurised[k] {
                    self.p[k] = self.cavity.get(k).copied().unwrap_or(pc);
                }
            }
        }
    }

    /// The cavity pressure of node k in column i for the solve at hand (see
    /// [`FilmState::cavity`]).
    #[inline(always)]
    pub fn cavity_at(&self, bc: &Boundary, i: usize, n1: usize, k: usize) -> f64 {
        self.cavity
            .get(k)
            .copied()
            .unwrap_or_else(|| bc.cavity_pressure(i, n1))
    }

    /// A full film (θ = 1, p = 0) everywhere.
    pub fn flooded(grid: &Grid, gap: &Gap, z: f64) -> Self {
        Self::cavitated(grid, gap, z, f64::INFINITY)
    }
    /// Saturation θ = φ/h at node k.
    pub fn theta(&self, grid: &Grid, gap: &Gap, z: f64, k: usize) -> f64 {
        self.phi[k] / gap.h(grid, k, z)
    }
}

/// The cavity pressure of every node into `out` (docs/model.md §3, "Gas pressures"): a cavity
/// open to the gas at x1 = 0 (connected through cavitated nodes to column 1) holds
/// `cavity_left`, one open to the other end `cavity_right`, one open to both the value of
/// its half ([`Boundary::cavity_pressure`]), an enclosed one the rupture pressure. A
/// pressurised node gets the pressure of the cavity it would join: the highest among its
/// cavitated interior neighbours' (a film never draws oil out of a cavity by pressure), else
/// the rupture pressure. With one cavity pressure on both sides every node gets it.
pub fn cavity_pressures(grid: &Grid, bc: &Boundary, pressurised: &[bool], out: &mut Vec<f64>) {
    let (n1, n2) = (grid.n1, grid.n2);
    out.clear();
    if !bc.split_cavity() {
        out.resize(grid.nodes(), bc.cavity_left);
        return;
    }
    let open = open_ends(n1, n2, pressurised);
    let of_cavity = |i: usize, k: usize| match open[k] {
        1 => bc.cavity_left,
        2 => bc.cavity_right,
        3 => bc.cavity_pressure(i, n1),
        _ => bc.rupture_pressure(),
    };
    out.resize(grid.nodes(), bc.rupture_pressure());
    for i in 1..n1 {
        for j in 0..n2 {
            let k = i * n2 + j;
            out[k] = if !pressurised[k] {
                of_cavity(i, k)
            } else {
                // The interior neighbours: columns 1..n1 − 1, no wrap across.
                let mut floor = bc.rupture_pressure();
                let mut see = |m: usize, i: usize| {
                    if !pressurised[m] {
                        floor = floor.max(of_cavity(i, m));
                    }
                };
                if i > 1 {
                    see(k - n2, i - 1);
                }
                if i + 1 < n1 {
                    see(k + n2, i + 1);
                }
                if j > 0 {
                    see(k - 1, i);
                }
                if j + 1 < n2 {
                    see(k + 1, i);
                }
                floor
            };
        }
    }
}

/// Which ends each cavitated interior node (columns 1..n1 − 1) is connected to through
/// cavitated interior nodes: bit 1 the x1 = 0 end (through column 1), bit 2 the other
/// (through column n1 − 1). Sweeps along x1 one way and back, each column both ways across,
/// until a round changes nothing: the connected components as a flood fill finds them, in
/// a few passes over plain arrays (this runs once or twice a film solve, over every node).
fn open_ends(n1: usize, n2: usize, pressurised: &[bool]) -> Vec<u8> {
    let mut open = vec![0u8; (n1 + 1) * n2];
    if n1 < 2 {
        return open;
    }
    // Node k in column i takes the ends of its cavitated neighbours; true if it changed.
    let visit = |open: &mut [u8], i: usize, j: usize| -> bool {
        let k = i * n2 + j;
        if pressurised[k] {
            return false;
        }
        let mut b = open[k];
        if i == 1 {
            b |= 1;
        }
        if i + 1 == n1 {
            b |= 2;
        }
        if i > 1 {
            b |= open[k - n2];
        }
        if i + 1 < n1 {
            b |= open[k + n2];
        }
        if j > 0 {
            b |= open[k - 1];
        }
        if j + 1 < n2 {
            b |= open[k + 1];
        }
        let changed = b != open[k];
        open[k] = b;
        changed
    };
    let column = |open: &mut [u8], i: usize| {
        let mut changed = false;
        for j in 0..n2 {
            changed |= visit(open, i, j);
        }
        for j in (0..n2).rev() {
            changed |= visit(open, i, j);
        }
        changed
    };
    loop {
        let mut changed = false;
        for i in 1..n1 {
            changed |= column(&mut open, i);
        }
        for i in (1..n1).rev() {
            changed |= column(&mut open, i);
        }
        if !changed {
            return open;
        }
    }
}

/// Field by field; `clone_from` keeps the arrays' allocations.
impl Clone for FilmState {
    fn clone(&self) -> Self {
        FilmState {
            p: self.p.clone(),
            phi: self.phi.clone(),
            pressurised: self.pressurised.clone(),
            cavity: self.cavity.clone(),
        }
    }

    fn clone_from(&mut self, s: &Self) {
        self.p.clone_from(&s.p);
        self.phi.clone_from(&s.phi);
        self.pressurised.clone_from(&s.pressurised);
        self.cavity.clone_from(&s.cavity);
    }
}

#[cfg(test)]
mod tests {
    use super::open_ends;

    /// The connected components by a plain flood fill from each end's column.
    fn flood(n1: usize, n2: usize, pressurised: &[bool]) -> Vec<u8> {
        let mut open = vec![0u8; (n1 + 1) * n2];
        let cav = |i: usize, j: usize| (1..n1).contains(&i) && !pressurised[i * n2 + j];
        for (bit, col) in [(1u8, 1), (2u8, n1 - 1)] {
            let mut stack: Vec<(usize, usize)> = (0..n2).map(|j| (col, j)).collect();
            while let Some((i, j)) = stack.pop() {
                if !cav(i, j) || open[i * n2 + j] & bit != 0 {
                    continue;
                }
                open[i * n2 + j] |= bit;
                stack.extend([(i - 1, j), (i + 1, j)]);
                if j > 0 {
                    stack.push((i, j - 1));
                }
                if j + 1 < n2 {
                    stack.push((i, j + 1));
                }
            }
        }
        open
    }

    #[test]
    fn the_sweeps_find_the_flood_fills_components() {
        // Random patterns at several densities, and a serpentine cavity that turns back
        // along x1 many times (the sweeps' worst case).
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as f64 / (1u64 << 31) as f64
        };
        for (n1, n2) in [(2, 1), (3, 1), (40, 1), (37, 6), (64, 8)] {
            for density in [0.2, 0.45, 0.6, 0.8] {
                let p: Vec<bool> = (0..(n1 + 1) * n2).map(|_| next() < density).collect();
                assert_eq!(
                    open_ends(n1, n2, &p),
                    flood(n1, n2, &p),
                    "{n1}x{n2} {density}"
                );
            }
        }
        let (n1, n2) = (41, 9);
        let mut p = vec![true; (n1 + 1) * n2];
        for i in 1..n1 {
            for j in 0..n2 {
                // Rows 0, 2, 4, … open; the rows between joined at alternate ends.
                let joint = (j / 2) % 2 == 0 && i == n1 - 1 || (j / 2) % 2 == 1 && i == 1;
                p[i * n2 + j] = !(j % 2 == 0 || joint);
            }
        }
        p[n2..n2 + n2].fill(true);
        p[n2] = false;
        assert_eq!(open_ends(n1, n2, &p), flood(n1, n2, &p));
    }
}
