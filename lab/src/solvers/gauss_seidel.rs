//! Plain projected Gauss–Seidel on the p–θ unknowns (contrast only): no acceleration, the ring
//! by a secant iteration around film solves at fixed Z. Its error decays by 1 − O(1/N²) a
//! sweep, so it stops within its budget only on coarse meshes; beyond that it fails with an
//! error, never a number.

use texopt::mesh::integrals::load;
use texopt::mesh::FilmState;
use texopt::solve::{
    check_finite, finish, impose_boundary, limit_closing, FilmError, FilmMethod, GapCache,
    SolveStats, Step, Tolerance,
};

use crate::stencil::{balance, conductance_sum};

/// Gauss–Seidel stops at this largest relative nodal residual: the nodes of the flooded gap
/// upstream hold φ ≈ 1000 µm, so 1e-8 relative there would still leave a summed mass defect
/// of ~1e-4 of the throughflow; 1e-12 keeps it under the run's mass guard.
pub const GS_RESIDUAL: f64 = 1e-12;

/// The plain Gauss–Seidel film solver.
#[derive(Default)]
pub struct GaussSeidel {
    gap: GapCache,
    tol: Tolerance,
    /// Most sweeps per film solve before it is declared failed.
    pub sweeps: usize,
}

impl GaussSeidel {
    pub fn new() -> Self {
        GaussSeidel {
            sweeps: 20_000,
            ..Default::default()
        }
    }

    /// A secant iteration on the ring equation G(Z) = Z − z_pred − κ(W_h(Z) − W_ps) = 0
    /// around film solves at fixed Z. Returns the sweeps.
    fn with_ring(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<usize, FilmError> {
        let mut sweeps = 0;
        let Some(link) = step.ring else {
            self.fixed_z(step, state, *z, &mut sweeps)?;
            return Ok(sweeps);
        };
        let g = step.grid;
        let ring = &step.gap.ring;
        let ring_min_base = step.gap.ring_min_base(g);
        let ring_residual = |s: &mut Self, st: &mut FilmState, zz: f64, n: &mut usize| {
            s.fixed_z(step, st, zz, n)?;
            Ok::<f64, FilmError>(zz - link.z_pred - link.kappa * (load(g, ring, &st.p) - link.w_ps))
        };
        let (mut z0, mut g0) = (*z, ring_residual(self, state, *z, &mut sweeps)?);
        // First step as if W_h did not depend on Z, then secant steps.
        let mut z1 = z0 + limit_closing(-g0, z0, ring_min_base);
        for _ in 0..60 {
            let g1 = ring_residual(self, state, z1, &mut sweeps)?;
            let dz = if g1 == g0 {
                0.0
            } else {
                limit_closing(-g1 * (z1 - z0) / (g1 - g0), z1, ring_min_base)
            };
            (z0, g0) = (z1, g1);
            z1 += dz;
            if dz.abs() <= self.tol.z_abs.max(1e-9 * z1.abs()) {
                *z = z0;
                return Ok(sweeps);
            }
            if !z1.is_finite() {
                break;
            }
        }
        Err(FilmError::NotConverged {
            iterations: sweeps,
            changes: 0,
            dz: (z1 - z0).abs(),
            z: z1,
        })
    }

    /// Projected sweeps at fixed Z: each node in turn solves its own balance for its unknown
    /// (p if pressurised, φ if not), p < 0 → cavitated, φ > h → pressurised; until the
    /// largest relative residual is below [`GS_RESIDUAL`].
    fn fixed_z(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: f64,
        sweeps: &mut usize,
    ) -> Result<(), FilmError> {
        let g = step.grid;
        let (n1, n2) = (g.n1, g.n2);
        self.gap.set_gap(step, z)?;
        for k in n2..n1 * n2 {
            if state.pressurised[k] {
                state.phi[k] = self.gap.h()[k];
            }
        }
        loop {
            self.sweep(step, state);
            *sweeps += 1;
            if sweeps.is_multiple_of(4) || *sweeps >= self.sweeps {
                check_finite(g, state, z)?;
                let residual = self.gap.residual(step, state, z);
                if residual <= GS_RESIDUAL {
                    return Ok(());
                }
                if *sweeps >= self.sweeps {
                    return Err(FilmError::Other(format!(
                        "plain Gauss–Seidel did not converge in {sweeps} sweeps (relative residual {residual:.2e} > {GS_RESIDUAL:.0e}); its error decays by 1 − O(1/N²) per sweep, so fine meshes are out of its reach"
                    )));
                }
            }
        }
    }

    /// One lexicographic sweep.
    fn sweep(&self, step: &Step, state: &mut FilmState) {
        let g = step.grid;
        let (n1, n2) = (g.n1, g.n2);
        let (adv, at) = step.coefficients();
        let phi_old = step.phi_old();
        let faces = self.gap.faces();
        let h = self.gap.h();
        {
            for i in 1..n1 {
                for j in 0..n2 {
                    let k = i * n2 + j;
                    let f = balance(g, &faces, adv, at, &state.p, &state.phi, phi_old, i, j);
                    if state.pressurised[k] {
                        let p = state.p[k] - f / conductance_sum(g, &faces, i, j);
                        if p < 0.0 {
                            state.p[k] = 0.0;
                            state.pressurised[k] = false;
                        } else {
                            state.p[k] = p;
                        }
                    } else {
                        let phi = state.phi[k] - f / (adv + at);
                        if phi > h[k] {
                            state.phi[k] = h[k];
                            state.pressurised[k] = true;
                        } else {
                            state.phi[k] = phi;
                        }
                    }
                }
            }
        }
    }
}

impl FilmMethod for GaussSeidel {
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        super::refuse_cavity_pressure(step, "Gauss–Seidel")?;
        self.gap.begin(step);
        impose_boundary(step, state, *z);
        let sweeps = self.with_ring(step, state, z)?;
        finish(&mut self.gap, step, state, *z, sweeps, 0)
    }
}
