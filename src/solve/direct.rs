//! The product's film solver: the active-set Newton iteration ([`super::newton`]) with every
//! linear system solved exactly by the band LU over the pressurised range, factors reused per
//! [`super::reuse`].

use super::newton::{
    apply_correction, assemble, fill_pressurised, pressurised_range, ring_sensitivity, ring_update,
    unpressurised_ring_update, update_active_set, upwind_sweep, RingWork,
};
use super::problem::{check_finite, finish, impose_boundary, GapCache};
use super::reuse::{Plan, Reuse, CHORD_CONFIRM, ROUNDED_FACTORS};
use super::{FilmError, FilmMethod, KeptFactors, Method, SolveStats, Stencil5, Step, Tolerance};
use crate::mesh::{cavity_pressures, face_conductances, FilmState};
use crate::model::film::Faces;

/// The band-LU film solver and its work arrays.
#[derive(Debug, Default, Clone)]
pub struct FilmSolver {
    tol: Tolerance,
    gap: GapCache,
    reuse: Reuse,
    /// The Newton matrix of the current iteration (taken by the factorisation).
    a: Stencil5,
    /// −F, then the Newton correction; ∂F/∂Z, then the ring's sensitivity (y2).
    y1: Vec<f64>,
    y2: Vec<f64>,
    rhs2: Vec<f64>,
    /// y1 and y2 interleaved during their substitutions.
    pairs: Vec<[f64; 2]>,
    ring: RingWork,
    /// The gap and face conductances at the factors' Z, when the matrix is frozen there.
    jh: Vec<f64>,
    jcx: Vec<f64>,
    jcy: Vec<f64>,
    /// The cavity pressures of a settled active set, against the solve's (two gas pressures).
    cavity: Vec<f64>,
}

/// Most times a solve lays its cavities' pressures anew (two gas pressures): a front that
/// the gas and the film push back and forth between two nodes is left where the last
/// settled solve put it (its floors those of the cavities one refresh earlier).
const CAVITY_REFRESHES: usize = 8;

/// What one iteration did, for the stopping rule.
struct Iterate {
    dz: f64,
    /// The Z of the iteration's matrix (None when nothing was pressurised), whether it was a
    /// chord or frozen one, whether its factors were rounded, and its relative correction.
    z_matrix: Option<f64>,
    chorded: bool,
    rounded: bool,
    correction: f64,
}

impl Iterate {
    /// Nothing pressurised: W_h = 0, and the ring's update is explicit (a Newton step on the
    /// asperity load where the asperities touch).
    fn unpressurised(step: &Step, z: f64, ring_min_base: f64) -> Self {
        Iterate {
            dz: step.ring.map_or(0.0, |link| {
                unpressurised_ring_update(step, link, z, ring_min_base)
            }),
            z_matrix: None,
            chorded: false,
            rounded: false,
            correction: 0.0,
        }
    }

    /// Whether what a further iteration would change is negligible: a Newton step that
    /// moved Z by at most z_abs, or any step whose estimated leftover is. At a fixed set the
    /// problem is nonlinear only through h(Z), so what is left is about the matrix's relative
    /// error at the final Z (c: the drift of chord or frozen factors, or a Newton step's own
    /// Z change; rounded factors add theirs) times this iteration's change, in Z and in p, φ.
    fn settled(&self, z: f64, ring_min_base: f64, z_abs: f64) -> bool {
        (self.dz.abs() <= z_abs && !self.chorded && !self.rounded)
            || self.z_matrix.is_some_and(|zm| {
                let c = 3.0 * (z - zm).abs() / (z + ring_min_base)
                    + if self.rounded { ROUNDED_FACTORS } else { 0.0 };
                c * self.dz.abs() <= z_abs && c * self.correction <= CHORD_CONFIRM
            })
    }
}

impl FilmSolver {
    pub fn new(method: Method) -> Self {
        FilmSolver {
            reuse: Reuse::new(method == Method::Reference),
            ..Default::default()
        }
    }

    /// The iteration to a settled active set and ring. Returns the iterations taken.
    fn iterate(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<usize, FilmError> {
        let g = step.grid;
        let ring_min_base = step.gap.ring_min_base(g);
        let stretch = self.reuse.may_stretch(g.n2);
        let (mut iterations, mut refreshes) = (0, 0);
        loop {
            iterations += 1;
            self.gap.set_gap(step, *z)?;
            fill_pressurised(g, state, self.gap.h());
            let range = if self.reuse.is_reference() {
                Some((1, g.n1 - 1))
            } else {
                pressurised_range(g, &state.pressurised)
            };
            // Outside the range every node is cavitated with p = p_c around it: exact sweeps.
            let (lo, hi) = range.unwrap_or((g.n1, g.n1 - 1));
            upwind_sweep(step, &self.gap.faces(), state, 1..lo);
            let it = match range {
                Some(r) => self.newton_step(step, state, *z, r, ring_min_base, stretch)?,
                None => Iterate::unpressurised(step, *z, ring_min_base),
            };
            *z += it.dz;
            upwind_sweep(step, &self.gap.faces(), state, hi + 1..g.n1);
            self.gap.fill_h(step, *z);
            let changes = update_active_set(step, state, self.gap.h());
            check_finite(g, state, *z)?;
            if changes == 0 && it.settled(*z, ring_min_base, self.tol.z_abs) {
                // With two gas pressures, the cavities the solve has settled on may be open
                // to other ends than those it started with (docs/model.md §3): their
                // pressures are laid anew and the solve goes on from there.
                if !step.boundary.split_cavity()
                    || refreshes >= CAVITY_REFRESHES
                    || !self.cavities_moved(step, state)
                {
                    return Ok(iterations);
                }
                refreshes += 1;
            }
            // Each laying of the cavities' pressures starts a new iteration, with its own cap.
            if iterations >= (1 + refreshes) * (g.n1 + self.tol.extra_iterations) {
                return Err(FilmError::NotConverged {
                    iterations,
                    changes,
                    dz: it.dz.abs(),
                    z: *z,
                });
            }
        }
    }

    /// Whether the cavities of the settled active set differ from those the solve started
    /// with (two gas pressures, docs/model.md §3). A cavity open to a gas invades the film
    /// next to it wherever the film's pressure is below that gas's, as far as it goes; then
    /// every cavity's pressure is laid anew (`FilmState::lay_cavity_pressure`).
    fn cavities_moved(&mut self, step: &Step, state: &mut FilmState) -> bool {
        let (g, bc) = (step.grid, &step.boundary);
        cavity_pressures(g, bc, &state.pressurised, &mut self.cavity);
        let invaded = invade(g, state, &self.cavity, self.gap.h());
        if invaded == 0 && self.cavity == state.cavity {
            return false;
        }
        state.lay_cavity_pressure(g, bc);
        true
    }

    /// One Newton step over the columns lo..=hi: matrix (factored, or factors at hand),
    /// ring bordered, correction applied. Returns what it did.
    fn newton_step(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: f64,
        range: (usize, usize),
        ring_min_base: f64,
        stretch: bool,
    ) -> Result<Iterate, FilmError> {
        let n2 = step.grid.n2;
        let block = range.0 * n2..(range.1 + 1) * n2;
        let plan: Plan = self.reuse.plan(
            range,
            &state.pressurised[block.clone()],
            z,
            ring_min_base,
            n2,
            stretch,
        );
        if let Some(zf) = plan.frozen {
            step.gap.fill(step.grid, zf, &mut self.jh);
            face_conductances(
                step.grid,
                &self.jh,
                None,
                step.gap,
                &mut self.jcx,
                &mut self.jcy,
            );
        }
        let faces = self.gap.faces();
        let jfaces = match plan.frozen {
            Some(_) => Faces {
                cx: &self.jcx,
                cy: &self.jcy,
                rough: faces.rough,
            },
            None => faces,
        };
        assemble(
            step,
            state,
            &faces,
            &jfaces,
            range,
            &mut self.a,
            &mut self.y1,
        );
        if !plan.chord {
            let z_of = plan.frozen.unwrap_or(z);
            self.reuse
                .factor(&mut self.a, range, &state.pressurised[block], z_of)?;
        }
        let rounded = self.reuse.rounded();
        let dz = match step.ring {
            Some(link) => {
                ring_sensitivity(
                    step,
                    state,
                    self.gap.h(),
                    self.gap.faces().rough,
                    range,
                    &mut self.ring,
                    &mut self.rhs2,
                );
                // y2 takes ∂F/∂Z (rhs2 gets y2's old buffer, which the next one clears).
                std::mem::swap(&mut self.rhs2, &mut self.y2);
                self.reuse
                    .solve2(&mut self.y1, &mut self.y2, &mut self.pairs);
                ring_update(
                    step,
                    link,
                    state,
                    range,
                    &mut self.y1,
                    &self.y2,
                    z,
                    ring_min_base,
                )
            }
            None => {
                self.reuse.solve(&mut self.y1);
                0.0
            }
        };
        let correction = apply_correction(step, state, self.gap.h(), &self.y1, range);
        Ok(Iterate {
            dz,
            z_matrix: Some(plan.z_matrix),
            chorded: plan.chord || plan.frozen.is_some(),
            rounded,
            correction,
        })
    }
}

/// Cavitates every pressurised node reachable from a cavity through pressurised nodes whose
/// pressure is below that cavity's (`cavity`: each node's cavity pressure as the active set
/// stands): the gas open to the cavity pushes into the film as far as the film's pressure
/// is below its own. Returns the nodes cavitated.
fn invade(g: &crate::mesh::Grid, state: &mut FilmState, cavity: &[f64], h: &[f64]) -> usize {
    let (n1, n2) = (g.n1, g.n2);
    let pmax = state.p.iter().fold(0.0f64, |m, &p| m.max(p.abs()));
    let eps = 1e-13 * pmax;
    let mut stack: Vec<(usize, f64)> = (n2..n1 * n2)
        .filter(|&k| !state.pressurised[k])
        .map(|k| (k, cavity[k]))
        .collect();
    let mut invaded = 0;
    while let Some((k, pc)) = stack.pop() {
        for m in g.interior_neighbours(k) {
            if state.pressurised[m] && state.p[m] < pc - eps {
                state.pressurised[m] = false;
                state.p[m] = pc;
                state.phi[m] = h[m];
                invaded += 1;
                stack.push((m, pc));
            }
        }
    }
    invaded
}

impl FilmMethod for FilmSolver {
    fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        self.reuse.begin();
        self.gap.begin(step);
        impose_boundary(step, state, *z);
        let iterations = self.iterate(step, state, z)?;
        let stats = finish(&mut self.gap, step, state, *z, iterations, 0)?;
        Ok(SolveStats {
            factorisations: self.reuse.factorisations,
            eliminated_rows: self.reuse.eliminated_rows,
            ..stats
        })
    }

    fn keeps_factors(&self) -> bool {
        !self.reuse.is_reference()
    }

    fn inherit_factors(&mut self, kept: &mut KeptFactors) {
        self.reuse.inherit(kept);
    }

    fn keep_factors(&mut self, slot: &mut KeptFactors) {
        self.reuse.keep(slot);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Gap, Grid};
    use crate::model::film::Boundary;

    #[test]
    fn a_closed_gap_is_an_error_not_a_number() {
        let g = Grid::new(16, 1, 1.0, 1.0);
        let mut base = vec![1.0; 17];
        base[8] = 0.0;
        let gap = Gap {
            base,
            ring: vec![false; 17],
            flow: None,
            rows: Default::default(),
            fitted: None,
            fitted_x2: None,
        };
        let phi_old = vec![1.0; 17];
        let step = Step::steady(
            &g,
            &gap,
            &phi_old,
            Boundary::with_ends(1.0, (0.0, 0.0), 1.0),
        );
        let mut st = FilmState::flooded(&g, &gap, 0.0);
        let err = FilmSolver::new(Method::Direct)
            .solve(&step, &mut st, &mut 0.0)
            .unwrap_err();
        assert!(matches!(err, FilmError::GapClosed { x1, .. } if (x1 - 0.5).abs() < 1e-12));
    }
}
