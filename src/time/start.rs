//! Where a transient starts (docs/model.md §4): the paper's initial state, or the untextured
//! force balance laid on the textured gap.

use super::steady::Steady;
use crate::mesh::{FilmState, Scene};
use crate::model::case::CaseSpec;
use crate::model::ring::RingState;

/// The untextured force balance (docs/model.md §6) laid on the textured gap: its saturation
/// and pressure per column, Z at the balance, at rest, W_h + W_a = W_ps so Z''(0) = 0. The texture
/// then only perturbs a balanced ring, so the periodic regime comes sooner.
pub fn equilibrium_start(scene: &Scene, eq: &Steady) -> (FilmState, RingState) {
    let g = &scene.grid;
    let mut st = FilmState::cavitated(g, &scene.gap, eq.z, 0.0);
    for i in 0..=g.n1 {
        for j in 0..g.n2 {
            let k = g.idx(i, j);
            let h = scene.gap.h(g, k, eq.z);
            st.phi[k] = eq.theta[i].min(1.0) * h;
            if eq.pressurised[i] && i > 0 && i < g.n1 {
                st.p[k] = eq.p[i];
                st.pressurised[k] = true;
            }
        }
    }
    let rs = RingState {
        z: eq.z,
        v: 0.0,
        a: 0.0,
    };
    (st, rs)
}

/// The paper's initial state (docs/model.md §4): Z = z0, Z' = v0. The paper leaves the
/// initial film open; texopt floods the gap upstream of the ring (θ = 1 for x1 < a) and lays
/// a film of d_oil elsewhere (θ = min(1, d_oil/h)), nothing pressurised. Why: with a flooded
/// inlet the ring passes less oil than arrives, and the surplus banks up in front of the
/// ring, filling the wide gap e upstream; from a thin film that bank's front creeps to the
/// inlet at surplus/(e − d_oil) ≈ 0.005 cm/ms, so the periodic regime would come only after
/// ≈ 12 ms, with the bank's back-pressure lifting Z by up to 0.3 % on the way. The initial
/// acceleration is consistent with the unpressurised film: Z''(0) = −W_ps/m.
pub fn paper_start(scene: &Scene, case: &CaseSpec) -> (FilmState, RingState) {
    let g = &scene.grid;
    let mut st = FilmState::cavitated(g, &scene.gap, case.z0, case.d_oil);
    let (a, _) = scene.contact.ring_edges();
    for i in (0..=g.n1).filter(|&i| g.x(i) < a) {
        for j in 0..g.n2 {
            let k = g.idx(i, j);
            st.phi[k] = scene.gap.h(g, k, case.z0);
        }
    }
    let rs = RingState {
        z: case.z0,
        v: case.v0,
        a: -case.w_ps / case.mass,
    };
    (st, rs)
}
