//! The film fields on the mesh at one time level: pressure, film content and active set.

use super::{Gap, Grid};
use crate::model::film::Boundary;

/// The film fields at one time level.
#[derive(Clone, Debug)]
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
    // Which ends each cavitated node is connected to: bit 1 the x1 = 0 end, bit 2 the other.
    // Plain loops: this runs once or twice a film solve, over every node.
    let mut open = vec![0u8; grid.nodes()];
    let cavitated = |k: usize| k >= n2 && k < n1 * n2 && !pressurised[k];
    let mut stack: Vec<usize> = Vec::with_capacity(grid.nodes());
    for (bit, col) in [(1u8, 1), (2u8, n1 - 1)] {
        for k in col * n2..(col + 1) * n2 {
            if cavitated(k) {
                stack.push(k);
            }
        }
        while let Some(k) = stack.pop() {
            if open[k] & bit != 0 {
                continue;
            }
            open[k] |= bit;
            for m in grid.interior_neighbours(k) {
                if cavitated(m) && open[m] & bit == 0 {
                    stack.push(m);
                }
            }
        }
    }
    let of_cavity = |k: usize| match open[k] {
        1 => bc.cavity_left,
        2 => bc.cavity_right,
        3 => bc.cavity_pressure(k / n2, n1),
        _ => bc.rupture_pressure(),
    };
    out.resize(grid.nodes(), bc.rupture_pressure());
    for k in n2..n1 * n2 {
        out[k] = if !pressurised[k] {
            of_cavity(k)
        } else {
            grid.interior_neighbours(k)
                .filter(|&m| !pressurised[m])
                .fold(bc.rupture_pressure(), |floor, m| floor.max(of_cavity(m)))
        };
    }
}
