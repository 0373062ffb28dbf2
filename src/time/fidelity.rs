//! Named fidelity tiers: the numerics the product's commands ask for, and the errors they
//! carry.

use serde::{Deserialize, Serialize};

use super::numerics::{Approach, Numerics, TimeScheme};

/// Named fidelity tiers the rest of the product asks for, chosen from the Pareto front of the
/// speed-against-accuracy study (results/speed/; errors against the converged references of
/// results/references/): the cell count along the sliding direction and the time scheme carry
/// most of the error, the cells across (N2) less, so the tiers are anisotropic. `draft` and
/// `fast` step the film along the Couette characteristics at dt = 2·dx1/u, where the
/// cavitated film's transport is exact (docs/solver.md, "Time scheme"); `fine` by BDF2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Fidelity {
    /// The optimiser's search ([`Fidelity::summary`] gives each tier's numerics and errors).
    Draft,
    /// Studies, the optimiser's reports and `simulate`.
    Fast,
    /// The paper's numerics.
    Paper,
    /// Checks, by a scheme independent of the characteristic tiers'.
    Fine,
}

impl Fidelity {
    /// What the tier is: its mesh, step and scheme, what it is for, its measured errors and
    /// cost (the command line's help shows it).
    pub fn summary(self) -> &'static str {
        match self {
            Fidelity::Draft => {
                "400×8, characteristic, dt = 1e-3: the optimiser's search (errors ≤ 1.5 % in f̄ \
                and 0.63 % in C_min, ≈ 0.1–0.2 s a case; a pocket needs only 2 cells across)"
            }
            Fidelity::Fast => {
                "700×8, characteristic, dt = 5.7e-4, going on on 600×24 where pockets end \
                deeper than 6·C_min (the deep-pocket mesh): studies, the optimiser and \
                `simulate` (errors ≤ 0.9 % in f̄ and 0.77 % in C_min on Case I, Case III, \
                R = 51.2 and the deep close-packed array; ≈ 0.4–0.7 s a case, ≈ 2 s with deep \
                pockets)"
            }
            Fidelity::Paper => {
                "512×32, dt = 4e-4, backward Euler: the paper's numerics (docs/model.md §3), \
                for reproducing it (4 % off on the conformal R = 51.2, its time step's error)"
            }
            Fidelity::Fine => {
                "1024×16, dt = 2e-4, BDF2: checks (errors ≤ 0.7 %), by a scheme independent of \
                the characteristic tiers'"
            }
        }
    }

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

    /// The measured relative error of f̄ at this tier: the largest of Case I, Case III, the
    /// conformal R = 51.2 and, at `fast` (which resolves them on its deep-pocket mesh), the
    /// deep close-packed pockets, against their converged references (results/references/,
    /// rounded up; tests/fidelity.rs checks it). Differences below it are not resolved.
    /// (`paper` keeps the paper's backward Euler, whose time-step error is the 4 % of
    /// R = 51.2; pockets much deeper than the film carry more at the other tiers, and beyond
    /// [`RESOLVED_DEEP_RATIO`] at `fast` too: [`DEEP_POCKET_RATIO`].)
    pub fn f_error(self) -> f64 {
        match self {
            Fidelity::Draft => 0.0146,
            Fidelity::Fast => 0.0090,
            Fidelity::Paper => 0.0410,
            Fidelity::Fine => 0.0068,
        }
    }

    /// The measured relative error of C_min at this tier (as `f_error`).
    pub fn c_error(self) -> f64 {
        match self {
            Fidelity::Draft => 0.0063,
            Fidelity::Fast => 0.0077,
            Fidelity::Paper => 0.0423,
            Fidelity::Fine => 0.0013,
        }
    }

    /// The numerics of this tier (other settings at their defaults). The screening tiers
    /// stop early: `fast` at a periodic tolerance of 1e-4 (the speed study: against 1e-5 it
    /// moves f̄ by < 5e-5 relative, far under its mesh error, and saves 1–2 periods),
    /// `draft` at 1e-3 (its errors stay under 2 %, tests/fidelity.rs).
    pub fn numerics(self) -> Numerics {
        let (n1, n2, dt, periodic_tol, scheme, approach) = match self {
            Fidelity::Draft => (
                400,
                8,
                characteristic_dt(400),
                1e-3,
                TimeScheme::Characteristic,
                CHARACTERISTIC_APPROACH,
            ),
            Fidelity::Fast => (
                700,
                8,
                characteristic_dt(700),
                1e-4,
                TimeScheme::Characteristic,
                CHARACTERISTIC_APPROACH,
            ),
            // The paper's own scheme (docs/model.md §3). Its approach is 512×8 at its own
            // step: the 512×32 windows dominate, and they start nearer their regime from
            // 512×8 (Case III from the paper's start: 4.3 s, against 7.0 s after 128×4).
            Fidelity::Paper => (
                512,
                32,
                4e-4,
                1e-5,
                TimeScheme::BackwardEuler,
                PAPER_APPROACH,
            ),
            Fidelity::Fine => (1024, 16, 2e-4, 1e-5, TimeScheme::Bdf2, APPROACH),
        };
        let deep = (self == Fidelity::Fast).then_some(DEEP_MESH);
        Numerics {
            n1,
            n2,
            dt,
            periodic_tol,
            scheme,
            approach: Some(approach),
            deep,
            ..Numerics::default()
        }
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

/// The coarse approach of the `fine` tier: the ring's transient from its start (the
/// nonlinear part: the ring lifting or sinking by µm, the film flushed through the contact)
/// on 128×4 cells at dt = 1.6e-3, ≈ 250 times fewer cell-steps a period than its mesh.
pub const APPROACH: Approach = Approach {
    n1: 128,
    n2: 4,
    dt: 1.6e-3,
};

/// The coarse approach of the characteristic tiers: the ring's transient on 120×4 cells at
/// their own characteristic step, 2·dx1/u = 3.3e-3 at u = 1 (a slower liner takes the same
/// step, below its own characteristic one). Measured on Case I, Case III and R = 51.2 at
/// `fast` from the paper's start (results/speed/): 0.37–0.67 s, against 0.40–0.69 s after
/// 128×4 at 1.6e-3, whose step interpolates the characteristics' feet, and 0.65–0.92 s
/// without an approach (R = 51.2, whose creep the coarse mesh does not shorten, alone is as
/// quick without: 0.65 s against 0.67 s).
pub const CHARACTERISTIC_APPROACH: Approach = Approach {
    n1: 120,
    n2: 4,
    dt: 2.0 * PAPER_LENGTH / 120.0,
};

/// The length of the paper's domain along x1 (cm): 2.5 widths of its 0.08 cm ring.
const PAPER_LENGTH: f64 = 0.2;

/// The characteristic step 2·dx1/u on `n1` cells of the paper's domain at u = 1: the step
/// at which the film content moves exactly one cell ([`TimeScheme::Characteristic`]).
const fn characteristic_dt(n1: usize) -> f64 {
    2.0 * PAPER_LENGTH / n1 as f64
}

/// The coarse approach of the `paper` tier: its own N1 and step on 8 cells across.
pub const PAPER_APPROACH: Approach = Approach {
    n1: 512,
    n2: 8,
    dt: 4e-4,
};

/// Fewest cells across a pocket (along x2) the tiers above `draft` accept before raising N2.
pub const POCKET_CELLS: f64 = 4.0;

/// Pockets deeper than this many times the least clearance are not resolved to the tiers'
/// errors: the rim of a half-ellipsoid pocket falls with a vertical tangent, and the band
/// where it is shallower than the film, ≈ l·(C_min/depth)²/2 wide, is then narrower than a
/// quarter of a cell. Measured on Case III's ring and lattice (results/deep_pockets/): at
/// depth/C_min ≈ 2.6 (10 µm) doubling the cells across or halving dt moves f̄ and C_min by
/// < 0.4 %; at ≈ 12 (20 µm) by 0.5–6.3 %, at ≈ 20 (30 µm) by up to 14 %, with walls between the
/// pockets or without.
pub const DEEP_POCKET_RATIO: f64 = 6.0;

/// Where `fast` goes on when a run ends with pockets deeper than [`DEEP_POCKET_RATIO`]·C_min:
/// 600×24 at its characteristic step, three times the rows across. Measured on the deep
/// close-packed case (R = 3.2, 0.03 / 0.06 / 20 µm, results/speed/ and results/bench/): 700×8
/// is +2.8 % / −6.3 % off in f̄ / C_min; 600×24 −0.30 % / −0.77 %, as 700×24 (−0.28 % /
/// −0.81 %): along x1 600 cells suffice, across 24 rows are what it takes (16: +0.7 % /
/// −2.3 %). Rows graded towards the pockets' rims do no better than uniform ones at the same
/// count (docs/solver.md, "Deep pockets").
pub const DEEP_MESH: Approach = Approach {
    n1: 600,
    n2: 24,
    dt: characteristic_dt(600),
};

/// The deepest pockets, as a multiple of C_min, at which the deep-pocket mesh is shown within
/// 1 % of the converged answer: the deep close-packed benchmark case, 20 µm against
/// C_min = 1.74 µm (11.5). Deeper still its answer is nearer than 700×8's but not within 1 %:
/// on R = 3.2 with 0.02 / 0.04 / 20 µm (depth/C_min ≈ 18), 8, 16 and 32 rows across give
/// f̄ 0.1573, 0.1491, 0.1454 and C_min 0.971, 1.068, 1.126 µm, first order, the 32 rows still
/// ≈ 2–5 % from their limit (docs/validation.md).
pub const RESOLVED_DEEP_RATIO: f64 = 12.0;

/// Whether pockets `depth_um` deep on a film whose least clearance is `c_min_um` are deeper
/// than the tiers resolve ([`DEEP_POCKET_RATIO`]).
pub fn unresolved_depth(depth_um: f64, c_min_um: f64) -> bool {
    depth_um > DEEP_POCKET_RATIO * c_min_um
}
