//! A cycle run's numerics at a fidelity tier (docs/model.md §12, docs/solver.md "The engine
//! cycle"): the tier's mesh (through the one resolver, `time::resolve`), crank steps that
//! follow the motion, and the texture moved by at most a set number of cells a step.

use super::drive::StepRule;
use super::run::CycleNumerics;
use crate::model::case::{CaseSpec, Texture};
use crate::time::{resolve, Fidelity, Overrides};

/// Per tier: the crank step at the mean piston speed (degrees), the least fraction of it near
/// a dead centre, and the cells of x1 the texture may move in one step.
fn tier_steps(fidelity: Fidelity) -> (f64, f64, f64) {
    match fidelity {
        Fidelity::Draft => (1.0, 0.1, 2.0),
        Fidelity::Fast => (0.5, 0.1, 1.5),
        Fidelity::Paper => (0.25, 0.1, 1.0),
        Fidelity::Fine => (0.125, 0.1, 0.5),
    }
}

/// Largest change of the asperities' share of the load over one crank step, every tier
/// (docs/model.md §12, "Crank steps"; measured: results/cycle_contact/).
pub const CONTACT_SHARE: f64 = 0.05;

/// The numerics of a cycle run of a ring (`ring`: its case, width and contact) over liners
/// whose finest texture is `texture` (None: plain liners), at `fidelity` with the mesh
/// `given` (its N1 and N2; a cycle's time steps are its crank steps): the mesh the one
/// resolver gives the ring over that texture at the mean piston speed, N2 only where pockets
/// are under the ring.
pub fn cycle_numerics(
    fidelity: Fidelity,
    given: &Overrides,
    ring: &CaseSpec,
    texture: Option<&Texture>,
) -> CycleNumerics {
    let case = CaseSpec {
        u: 1.0,
        texture: texture.cloned(),
        ..ring.clone()
    };
    let mesh = Overrides {
        n1: given.n1,
        n2: given.n2,
        ..Overrides::default()
    };
    let n = resolve(fidelity, &mesh, &case);
    let (step_deg, refine, cells) = tier_steps(fidelity);
    let dx = case.contact().length_cm / n.n1 as f64;
    CycleNumerics {
        n1: n.n1,
        n2: n.n2,
        steps: StepRule {
            step_deg,
            refine,
            texture_step: if texture.is_some() {
                cells * dx
            } else {
                f64::INFINITY
            },
            contact_share: CONTACT_SHARE,
        },
        oil_cell_cm: dx,
        start_deg: 90.0,
        cyclic_tol: 1e-3,
        max_cycles: 20,
    }
}
