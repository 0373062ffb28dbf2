//! The Reynolds cut-off (contrast only): p ≥ 0 with the Reynolds equation for a full film
//! (θ ≡ 1), the equation dropped where p = 0. It does not conserve mass (the paper's ref.
//! [7]): a run detects that and fails, and with the guard lifted its answer is far from
//! Elrod–Adams's (results/stability/). Solved by the active-set Newton iteration with the
//! ring bordered, every linear system by a band LU over the pressurised range.

use texopt::mesh::FilmState;
use texopt::model::film::{Column, Faces};
use texopt::solve::band::BandLu;
use texopt::solve::newton::{face_conductance_derivatives, pressurised_range, ring_update};
use texopt::solve::{
    check_finite, finish, impose_boundary, FilmError, FilmMethod, GapCache, SolveStats, Stencil5,
    Step, Tolerance,
};

/// The cut-off film solver.
#[derive(Default)]
pub struct Cutoff {
    tol: Tolerance,
    gap: GapCache,
    lu: BandLu,
    a: Stencil5,
    y1: Vec<f64>,
    y2: Vec<f64>,
    pairs: Vec<[f64; 2]>,
    dcx: Vec<f64>,
    dcy: Vec<f64>,
    dphi: Vec<f64>,
}

/// Sets the film full (φ = h) at every interior node.
fn full_film(step: &Step, state: &mut FilmState, h: &[f64]) {
    let g = step.grid;
    state.phi[g.n2..g.n1 * g.n2].copy_from_slice(&h[g.n2..g.n1 * g.n2]);
}

impl Cutoff {
    /// The Newton matrix and −F over columns lo..=hi: the Elrod–Adams rows on the pressurised
    /// set with θ ≡ 1 (no upstream φ unknown), identity rows elsewhere (p = 0 held).
    fn assemble(&mut self, step: &Step, state: &FilmState, (lo, hi): (usize, usize)) {
        let n2 = step.grid.n2;
        let (adv, at) = step.coefficients();
        let faces = self.gap.faces();
        self.a.reset(hi - lo + 1, n2);
        self.y1.clear();
        for i in lo..=hi {
            let col = Column::new(n2, &faces, &state.p, &state.phi, step.phi_old(), i);
            for j in 0..n2 {
                let (k, r) = (i * n2 + j, (i - lo) * n2 + j);
                if !state.pressurised[k] {
                    self.y1.push(0.0);
                    self.a.c[r] = 1.0;
                    continue;
                }
                self.y1.push(-col.balance(adv, at, j));
                self.a.c[r] = col.conductance_sum(j);
                let on = |m: usize| state.pressurised[m];
                if i > lo && on(k - n2) {
                    self.a.w[r] = -col.cx_w[j];
                }
                if i < hi && on(k + n2) {
                    self.a.e[r] = -col.cx_e[j];
                }
                if j > 0 && on(k - 1) {
                    self.a.s[r] = -col.cy[j - 1];
                }
                if j + 1 < n2 && on(k + 1) {
                    self.a.n[r] = -col.cy[j];
                }
            }
        }
    }

    /// ∂F/∂Z over columns lo..=hi on the pressurised rows (φ = h everywhere, so φ' = 1 under
    /// the ring), into y2.
    fn ring_sensitivity(&mut self, step: &Step, state: &FilmState, (lo, hi): (usize, usize)) {
        let (g, ring) = (step.grid, &step.gap.ring);
        let n2 = g.n2;
        let (adv, at) = step.coefficients();
        face_conductance_derivatives(g, self.gap.h(), step.gap, &mut self.dcx, &mut self.dcy);
        self.dphi.clear();
        self.dphi
            .extend((0..g.nodes()).map(|k| if ring[k / n2] { 1.0 } else { 0.0 }));
        let dfaces = Faces::new(&self.dcx, &self.dcy);
        self.y2.clear();
        self.y2.resize((hi - lo + 1) * n2, 0.0);
        for i in lo..=hi {
            let col = Column::new(n2, &dfaces, &state.p, &self.dphi, None, i);
            for j in 0..n2 {
                if state.pressurised[i * n2 + j] {
                    self.y2[(i - lo) * n2 + j] = col.balance(adv, at, j);
                }
            }
        }
    }

    /// Active-set update: a negative pressure drops its node (p = 0); a dropped node comes
    /// back when p = 0 leaves it a net inflow (the Reynolds equation would raise its
    /// pressure). Returns the switches.
    fn update_active_set(&self, step: &Step, state: &mut FilmState, h_new: &[f64]) -> usize {
        let g = step.grid;
        let n2 = g.n2;
        let (adv, at) = step.coefficients();
        let interior = n2..g.n1 * n2;
        let pmax = interior
            .clone()
            .filter(|&k| state.pressurised[k])
            .fold(0.0f64, |m, k| m.max(state.p[k]));
        let mut changes = 0;
        for k in interior {
            if state.pressurised[k] {
                if state.p[k] < -1e-13 * pmax {
                    state.pressurised[k] = false;
                    state.p[k] = 0.0;
                    changes += 1;
                }
            } else {
                let col = Column::new(
                    n2,
                    &self.gap.faces(),
                    &state.p,
                    &state.phi,
                    step.phi_old(),
                    k / n2,
                );
                let f = col.balance(adv, at, k % n2);
                let scale = (adv + at) * h_new[k] + adv * state.phi[k - n2];
                if f < -1e-12 * scale {
                    state.pressurised[k] = true;
                    changes += 1;
                }
            }
        }
        changes
    }
}

impl FilmMethod for Cutoff {
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        super::refuse_cavity_pressure(step, "cut-off")?;
        let g = step.grid;
        let ring_min_base = step.gap.ring_min_base(g);
        self.gap.begin(step);
        impose_boundary(step, state, *z);
        let mut iterations = 0;
        loop {
            iterations += 1;
            self.gap.set_gap(step, *z)?;
            full_film(step, state, self.gap.h());
            let mut dz = 0.0;
            if let Some(r) = pressurised_range(g, &state.pressurised) {
                self.assemble(step, state, r);
                self.lu.factor(&self.a).map_err(|e| FilmError::Singular {
                    row: e.row,
                    pivot: e.value,
                })?;
                match step.ring {
                    Some(link) => {
                        self.ring_sensitivity(step, state, r);
                        self.lu.solve2(&mut self.y1, &mut self.y2, &mut self.pairs);
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
                    None => self.lu.solve(&mut self.y1),
                }
                for (m, d) in (r.0 * g.n2..(r.1 + 1) * g.n2).zip(&self.y1) {
                    if state.pressurised[m] {
                        state.p[m] += d;
                    }
                }
            } else if let Some(link) = step.ring {
                dz = link.z_pred - link.kappa * link.w_ps - *z;
            }
            *z += dz;
            let h_new = {
                let mut h = Vec::new();
                step.gap.fill(g, *z, &mut h);
                h
            };
            let changes = self.update_active_set(step, state, &h_new);
            check_finite(g, state, *z)?;
            if changes == 0 && dz.abs() <= self.tol.z_abs {
                break;
            }
            if iterations >= g.n1 + self.tol.extra_iterations {
                return Err(FilmError::NotConverged {
                    iterations,
                    changes,
                    dz: dz.abs(),
                    z: *z,
                });
            }
        }
        self.gap.fill_h(step, *z);
        full_film(step, state, self.gap.h());
        finish(&mut self.gap, step, state, *z, iterations, 0)
    }
}
