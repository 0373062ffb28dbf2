//! Inexact semi-smooth Newton: the product's active-set iteration ([`texopt::solve::newton`])
//! with each linear system solved by GMRES preconditioned with a line-multigrid V-cycle
//! ([`crate::line_multigrid`]). Its cost grows linearly with the mesh (the band LU's with
//! N1·N2³), but an inexact iterate can flip nodes where p ≈ 0 and θ ≈ 1 back and forth, and
//! at the paper's 512×32 it is slower than the band LU (results/speed/).

use texopt::mesh::FilmState;
use texopt::model::film::Column;
use texopt::solve::newton::{
    apply_correction, assemble, fill_pressurised, pressurised_range, ring_sensitivity, ring_update,
    update_active_set, upwind_sweep, RingWork,
};
use texopt::solve::{
    check_finite, finish, impose_boundary, FilmError, FilmMethod, GapCache, SolveStats, Step,
    Tolerance,
};

use crate::line_multigrid::LineMultigrid;

/// Settings of the inexact solves.
#[derive(Clone, Copy, Debug)]
pub struct MgTolerance {
    /// Converged when the largest nodal residual, relative to the node's flux terms, is
    /// below this (and the set and Z settled).
    pub residual: f64,
    /// Most V-cycles (GMRES iterations) per linear solve.
    pub cycles: usize,
    /// A linear solve stops once its residual has dropped by this factor (inexact Newton).
    pub inner: f64,
}

impl Default for MgTolerance {
    fn default() -> Self {
        MgTolerance {
            residual: 1e-8,
            cycles: 8,
            inner: 1e-2,
        }
    }
}

/// The inexact Newton film solver.
#[derive(Default)]
pub struct NewtonMultigrid {
    pub tol: MgTolerance,
    newton: Tolerance,
    gap: GapCache,
    mg: LineMultigrid,
    rhs: Vec<f64>,
    y1: Vec<f64>,
    y2: Vec<f64>,
    rhs2: Vec<f64>,
    ring: RingWork,
}

impl NewtonMultigrid {
    pub fn new(tol: MgTolerance) -> Self {
        NewtonMultigrid {
            tol,
            ..Default::default()
        }
    }

    /// Largest |F| over columns lo..=hi relative to the node's Poiseuille and Couette terms.
    fn residual(&self, step: &Step, state: &FilmState, (lo, hi): (usize, usize)) -> f64 {
        let n2 = step.grid.n2;
        let (adv, at) = step.coefficients();
        let faces = self.gap.faces();
        let mut fmax: f64 = 0.0;
        for i in lo..=hi {
            let col = Column::new(n2, &faces, &state.p, &state.phi, step.phi_old(), i);
            for j in 0..n2 {
                let f = self.rhs[(i - lo) * n2 + j];
                let scale = col.conductance_sum(j) * col.p[j].abs() + (adv + at) * col.phi[j].abs();
                if scale > 0.0 {
                    fmax = fmax.max(f.abs() / scale);
                }
            }
        }
        fmax
    }

    fn iterate(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<(usize, usize), FilmError> {
        let g = step.grid;
        let n2 = g.n2;
        let ring_min_base = step.gap.ring_min_base(g);
        let (mut iterations, mut cycles) = (0, 0);
        let (mut last_changes, mut last_dz) = (usize::MAX, f64::INFINITY);
        let mut y2_range = None;
        loop {
            iterations += 1;
            self.gap.set_gap(step, *z)?;
            fill_pressurised(g, state, self.gap.h());
            let range = pressurised_range(g, &state.pressurised);
            let (lo, hi) = range.unwrap_or((g.n1, g.n1 - 1));
            upwind_sweep(step, &self.gap.faces(), state, 1..lo);
            let mut dz = 0.0;
            if let Some(r) = range {
                let faces = self.gap.faces();
                assemble(
                    step,
                    state,
                    &faces,
                    &faces,
                    r,
                    self.mg.fine_mut(),
                    &mut self.rhs,
                );
                // Converged when the last update settled the set and Z and the residual is at
                // tolerance.
                if last_changes == 0
                    && last_dz <= self.newton.z_abs
                    && self.residual(step, state, r) <= self.tol.residual
                {
                    break;
                }
                let active = self.mg.fine_active_mut();
                active.clear();
                active.extend_from_slice(&state.pressurised[lo * n2..(hi + 1) * n2]);
                self.mg.setup().map_err(|e| FilmError::Singular {
                    row: e.node,
                    pivot: e.value,
                })?;
                // Inexact Newton (each solve cuts the residual by tol.inner); if the set keeps
                // flickering, solve accurately.
                let (rel, max_cycles) = if iterations > 8 {
                    (self.tol.residual, 4 * self.tol.cycles)
                } else {
                    (self.tol.inner, self.tol.cycles)
                };
                self.y1.clear();
                self.y1.resize(self.rhs.len(), 0.0);
                cycles += self.mg.gmres(&mut self.y1, &self.rhs, rel, max_cycles);
                if let Some(link) = step.ring {
                    // The sensitivity sets only the rate of the Z iteration, not its limit:
                    // kept while the range holds, refreshed (warm) after the second iteration.
                    if y2_range != Some(r) || iterations > 2 {
                        ring_sensitivity(
                            step,
                            state,
                            self.gap.h(),
                            self.gap.faces().rough,
                            r,
                            &mut self.ring,
                            &mut self.rhs2,
                        );
                        if !(self.y2.len() == self.rhs2.len() && y2_range == Some(r)) {
                            self.y2.clear();
                            self.y2.resize(self.rhs2.len(), 0.0);
                        }
                        cycles += self.mg.gmres(
                            &mut self.y2,
                            &self.rhs2,
                            self.tol.inner,
                            self.tol.cycles,
                        );
                        y2_range = Some(r);
                    }
                    dz = ring_update(
                        step,
                        link,
                        state,
                        r,
                        &mut self.y1,
                        &self.y2,
                        *z,
                        ring_min_base,
                    );
                }
                apply_correction(step, state, self.gap.h(), &self.y1, r);
            } else if let Some(link) = step.ring {
                dz = link.z_pred - link.kappa * link.w_ps - *z;
            }
            *z += dz;
            upwind_sweep(step, &self.gap.faces(), state, hi + 1..g.n1);
            self.gap.fill_h(step, *z);
            let changes = update_active_set(step, state, self.gap.h());
            check_finite(g, state, *z)?;
            // Nothing pressurised: the sweeps are exact.
            if range.is_none() && changes == 0 && dz.abs() <= self.newton.z_abs {
                break;
            }
            (last_changes, last_dz) = (changes, dz.abs());
            if iterations >= g.n1 + self.newton.extra_iterations {
                return Err(FilmError::NotConverged {
                    iterations,
                    changes,
                    dz: dz.abs(),
                    z: *z,
                });
            }
        }
        Ok((iterations, cycles))
    }
}

impl FilmMethod for NewtonMultigrid {
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        self.gap.begin(step);
        impose_boundary(step, state, *z);
        let (iterations, cycles) = self.iterate(step, state, z)?;
        finish(&mut self.gap, step, state, *z, iterations, cycles)
    }

    /// Its solves stop on the nodal residual, so where they start moves their answer (by
    /// the tolerance): from the guess carried with the texture they left a step's mass defect
    /// of 7e-6, above the run's guard, at 256×16.
    fn carries_guess(&self) -> bool {
        false
    }
}
