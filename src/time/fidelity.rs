//! Named fidelity tiers: the numerics the product's commands ask for, and the errors they
//! carry.

use serde::{Deserialize, Serialize};

use super::numerics::{Numerics, APPROACH_N2};
use crate::model::case::CaseSpec;

/// Named fidelity tiers the rest of the product asks for, chosen from the Pareto front of the
/// speed-against-accuracy study (results/speed/; errors against 2048×128 at dt = 1e-4 for
/// Case I and Case III): the cell count along the sliding direction and the time step carry
/// most of the error, the cells across (N2) less, so the fast tiers are anisotropic. The time
/// step's error grows with R (docs/validation.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Fidelity {
    /// 256×8, dt = 8e-4: screening (errors ≈ 1–2 %, ≈ 1 s a case).
    Draft,
    /// 512×8, dt = 4e-4: studies and optimisation (errors ≈ 1 %: ≤ 1.11 % against 2048×128
    /// on Case I and Case III; ≈ 1–2 s a case).
    Fast,
    /// 512×32, dt = 4e-4: the paper's fidelity (docs/model.md §3), for reproducing it.
    Paper,
    /// 1024×16, dt = 2e-4: checks.
    Fine,
}

impl Fidelity {
    pub const ALL: [Fidelity; 4] = [
        Fidelity::Draft,
        Fidelity::Fast,
        Fidelity::Paper,
        Fidelity::Fine,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Fidelity::Draft => "draft",
            Fidelity::Fast => "fast",
            Fidelity::Paper => "paper",
            Fidelity::Fine => "fine",
        }
    }

    /// The measured relative error of f̄ at this tier: the larger of Case I and Case III
    /// against their 2048×128, dt = 1e-4 references (results/speed/, rounded up;
    /// tests/fidelity.rs checks it against the references). Differences below it are not
    /// resolved.
    pub fn f_error(self) -> f64 {
        match self {
            Fidelity::Draft => 0.0183,
            Fidelity::Fast => 0.0112,
            Fidelity::Paper => 0.0074,
            Fidelity::Fine => 0.0047,
        }
    }

    /// The measured relative error of C_min at this tier (as `f_error`).
    pub fn c_error(self) -> f64 {
        match self {
            Fidelity::Draft => 0.0186,
            Fidelity::Fast => 0.0080,
            Fidelity::Paper => 0.0067,
            Fidelity::Fine => 0.0009,
        }
    }

    /// The numerics of this tier (other settings at their defaults). The screening tiers
    /// stop at a periodic tolerance of 1e-4 (the speed study: it moves f̄ by < 1e-5 relative
    /// on Case I, far under their mesh error, and saves ≈ 30 % of the periods).
    pub fn numerics(self) -> Numerics {
        let (n1, n2, dt, periodic_tol) = match self {
            Fidelity::Draft => (256, 8, 8e-4, 1e-4),
            Fidelity::Fast => (512, 8, 4e-4, 1e-4),
            Fidelity::Paper => (512, 32, 4e-4, 1e-5),
            Fidelity::Fine => (1024, 16, 2e-4, 1e-5),
        };
        Numerics {
            n1,
            n2,
            dt,
            periodic_tol,
            // The wide band of the paper tier makes the ring's transient its dearest part
            // (≈ 80 % of Case III from the paper's start); at N2 = 8 the band LU is ≈ 50×
            // cheaper.
            approach_n2: (n2 > APPROACH_N2).then_some(APPROACH_N2),
            ..Numerics::default()
        }
    }

    /// The numerics of this tier for one case: the tier's N2 is raised where the pocket
    /// would span fewer than `POCKET_CELLS` cells across (small pockets in a wide cell, e.g.
    /// l2 = 0.0025 in width 0.06 needs N2 = 24), so every texture is resolved alike.
    pub fn numerics_for(self, case: &CaseSpec) -> Numerics {
        let mut num = self.numerics();
        num.resolve_pockets(case, self.pocket_cells());
        num
    }

    /// Fewest cells across a pocket (along x2) the tier accepts before raising N2: 4, and 2
    /// for the screening tier `draft` (small pockets in wide cells would otherwise cost it
    /// N2 ≈ 24 and a band LU 20× dearer).
    pub fn pocket_cells(self) -> f64 {
        match self {
            Fidelity::Draft => 2.0,
            _ => POCKET_CELLS,
        }
    }
}

/// Fewest cells across a pocket (along x2) the tiers above `draft` accept before raising N2.
pub const POCKET_CELLS: f64 = 4.0;
