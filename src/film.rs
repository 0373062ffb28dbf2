//! The film: Elrod–Adams p–θ on conservative finite volumes (model.md §3; paper eqs. 4, 5, 14).
//!
//! Nondimensional film equation (model.md §3, with the factor 2 the scales imply):
//!
//! ```text
//!     ∇·(h³ ∇p) = u ∂(hθ)/∂x1 + 2 ∂(hθ)/∂t,   p ≥ 0, 0 ≤ θ ≤ 1, p·(1 − θ) = 0
//! ```
//!
//! i.e. ∂φ/∂t + ∇·q = 0 with φ = hθ and mass flux q = (u/2)·φ·e1 − (h³/2)·∇p.
//!
//! Discretisation: vertex-centred in x1 (nodes x_i = i·dx, i = 0..=n1, p Dirichlet at both
//! ends, inlet film φ_0 given), cell-centred in x2 (centres (j + ½)·dy, zero-flux walls).
//! Couette flux upwinded (u > 0 ⇒ (u/2)·φ_i at face i+½), Poiseuille flux centred with
//! h_face = mean of the two nodal gaps, backward Euler on φ with h at the new time level.
//!
//! Every node carries one unknown: p on the pressurised set (θ = 1, φ = h) or φ on the
//! cavitated set (p = 0). The complementarity problem is solved by a primal–dual active-set
//! (semi-smooth Newton) iteration: for a fixed active set the equations are linear in the
//! unknowns and their matrix is an M-matrix, solved exactly by a band LU over the x1-range
//! that holds the pressurised nodes; cavitated nodes outside it are exact upwind sweeps.
//! The ring position Z enters as one more unknown (bordered system, Schur complement), so
//! the Newmark coupling of model.md §4 is implicit and converged inside the same iteration.

use crate::banded::{BandLu, KeptLu};
use crate::multigrid::LineMultigrid;

/// The mesh: n1 cells along x1 over [0, length] (vertex-centred, n1 + 1 nodes) and n2 cells
/// along x2 over [0, half_width] (cell-centred). Node (i, j) is stored at i·n2 + j.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub n1: usize,
    pub n2: usize,
    /// Domain length along x1 (cm).
    pub length: f64,
    /// Simulated width B along x2 (cm): half a texture cell (model.md §2).
    pub width: f64,
    pub dx: f64,
    pub dy: f64,
}

impl Grid {
    pub fn new(n1: usize, n2: usize, length: f64, width: f64) -> Self {
        Grid {
            n1,
            n2,
            length,
            width,
            dx: length / n1 as f64,
            dy: width / n2 as f64,
        }
    }
    /// Number of nodes, boundary nodes included.
    pub fn nodes(&self) -> usize {
        (self.n1 + 1) * self.n2
    }
    #[inline]
    pub fn idx(&self, i: usize, j: usize) -> usize {
        i * self.n2 + j
    }
    /// x1 of node column i (cm).
    pub fn x(&self, i: usize) -> f64 {
        i as f64 * self.dx
    }
    /// x2 of node row j (cm).
    pub fn y(&self, j: usize) -> f64 {
        (j as f64 + 0.5) * self.dy
    }
}

/// The gap at the new time level as an affine function of the ring position:
/// h = base + Z on the node columns under the ring, h = base elsewhere (eq. 15).
#[derive(Clone, Debug, Default)]
pub struct Gap {
    /// Gap without Z (µm), per node.
    pub base: Vec<f64>,
    /// Per node column i: whether it lies under the ring (a < x_i < b), where ∂h/∂Z = 1.
    pub ring: Vec<bool>,
}

impl Gap {
    /// The gap at every node for ring position z into `out` (column by column: no index
    /// division in the hot loop).
    pub fn fill(&self, grid: &Grid, z: f64, out: &mut Vec<f64>) {
        out.clear();
        let n2 = grid.n2;
        for (i, &under) in self.ring.iter().enumerate() {
            let col = &self.base[i * n2..(i + 1) * n2];
            if under {
                out.extend(col.iter().map(|b| b + z));
            } else {
                out.extend_from_slice(col);
            }
        }
    }

    /// Refills `out`, which holds this gap at another ring position, for `z`: only the
    /// columns under the ring depend on Z (the same values as [`Gap::fill`]). `cols`:
    /// [`Gap::ring_columns`], computed once by the caller.
    pub fn refill_ring(&self, grid: &Grid, z: f64, cols: std::ops::Range<usize>, out: &mut [f64]) {
        let n2 = grid.n2;
        let span = cols.start * n2..cols.end * n2;
        for (i, (o, col)) in out[span.clone()]
            .chunks_exact_mut(n2)
            .zip(self.base[span].chunks_exact(n2))
            .enumerate()
        {
            if self.ring[cols.start + i] {
                for (o, b) in o.iter_mut().zip(col) {
                    *o = b + z;
                }
            }
        }
    }

    /// The node columns from the first under the ring to the last (empty without one).
    pub fn ring_columns(&self) -> std::ops::Range<usize> {
        match (
            self.ring.iter().position(|&r| r),
            self.ring.iter().rposition(|&r| r),
        ) {
            (Some(a), Some(b)) => a..b + 1,
            _ => 0..0,
        }
    }

    /// The smallest gap without Z under the ring (∞ when no column lies under it).
    pub fn ring_min_base(&self, grid: &Grid) -> f64 {
        let n2 = grid.n2;
        self.ring
            .iter()
            .enumerate()
            .filter(|(_, &under)| under)
            .flat_map(|(i, _)| self.base[i * n2..(i + 1) * n2].iter().copied())
            .fold(f64::INFINITY, f64::min)
    }

    #[inline]
    pub fn h(&self, grid: &Grid, k: usize, z: f64) -> f64 {
        if self.ring[k / grid.n2] {
            self.base[k] + z
        } else {
            self.base[k]
        }
    }
}

/// Boundary data along x1 (model.md §3).
#[derive(Clone, Copy, Debug)]
pub struct Boundary {
    /// Liner speed u (≥ 0; u = 1 in the paper).
    pub u: f64,
    /// Pressure at x1 = 0 and x1 = length (0 in the paper).
    pub p_left: f64,
    pub p_right: f64,
    /// Film φ = hθ carried in at x1 = 0 (µm); capped at the local gap (θ ≤ 1) per node.
    pub phi_inlet: f64,
}

/// Implicit ring dynamics in the film iteration: Z = z_pred + κ·(W_h − W_ps), the Newmark
/// average-acceleration update of m·Z'' = W_h − W_ps (eq. 13, model.md §4) with κ = dt²/(4m).
#[derive(Clone, Copy, Debug)]
pub struct RingLink {
    pub z_pred: f64,
    pub kappa: f64,
    pub w_ps: f64,
}

/// One film problem: a time step (inv_dt > 0) or a steady state (inv_dt = 0).
#[derive(Clone, Copy, Debug)]
pub struct Step<'a> {
    pub grid: &'a Grid,
    pub gap: &'a Gap,
    /// φ = hθ at the old time level (ignored when steady).
    pub phi_old: &'a [f64],
    /// 1/dt; 0 for a steady problem.
    pub inv_dt: f64,
    pub boundary: Boundary,
    /// None: Z is held fixed.
    pub ring: Option<RingLink>,
}

/// The film fields at one time level.
#[derive(Clone, Debug)]
pub struct FilmState {
    /// Pressure p (units of 6μUL/H²).
    pub p: Vec<f64>,
    /// Film content φ = hθ (µm).
    pub phi: Vec<f64>,
    /// Active set: node pressurised (θ = 1).
    pub pressurised: Vec<bool>,
}

impl FilmState {
    /// Takes `other`'s values (same grid), reusing the allocations.
    pub fn assign(&mut self, other: &FilmState) {
        self.p.copy_from_slice(&other.p);
        self.phi.copy_from_slice(&other.phi);
        self.pressurised.copy_from_slice(&other.pressurised);
    }

    /// Zero pressure and film φ_0 everywhere (capped at the local gap), nothing pressurised.
    pub fn cavitated(grid: &Grid, gap: &Gap, z: f64, phi0: f64) -> Self {
        let n = grid.nodes();
        let phi = (0..n).map(|k| phi0.min(gap.h(grid, k, z))).collect();
        FilmState {
            p: vec![0.0; n],
            phi,
            pressurised: vec![false; n],
        }
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

/// How the linear systems of the complementarity iteration are solved. Both use the same
/// matrix, assembled from the one stencil; they differ only in how it is inverted.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Exact band LU of the Newton system in every iteration (the default: at the paper's
    /// 512×32 it is the fastest measured, see results/speed.md).
    #[default]
    Direct,
    /// Experimental: inexact semi-smooth Newton, each linear system solved by GMRES with a
    /// line-multigrid V-cycle ([`crate::multigrid`]) as preconditioner. Its cost grows
    /// linearly with the mesh (the band LU's with N1·N2³), but on the flooded gap e the active
    /// set can flicker under inexact solves; it is not yet robust (results/speed.md).
    Multigrid,
    #[value(skip)]
    /// Test reference, the simplest sound solver: the band LU of the whole domain in every
    /// iteration (no restriction to the pressurised range, no upwind sweeps).
    Reference,
    /// Contrast only (stability study, issue 6): plain projected Gauss–Seidel on the p–θ
    /// unknowns, no acceleration, the ring by a secant iteration around it. Its error decays
    /// by 1 − O(1/N²) per sweep, so it stops within `Tolerance::sweeps` only on coarse
    /// meshes; beyond that it fails with an error, never a number.
    #[serde(rename = "gauss-seidel")]
    GaussSeidel,
    /// Experimental (issue 3): the p–θ multigrid of src/pt_multigrid.rs (Gauss–Seidel on
    /// p and θ, Galerkin coarse pressure corrections, the ring moved after every V-cycle),
    /// to the film tolerance by its residual. Slower than `direct` at the paper's 512×32
    /// (Case III: 21 V-cycles and ≈ 20 ms a step there, 37 s against 4–7 s), but its cost
    /// grows with the node count only: it is meant for fine meshes (2048×128: ≈ 20 V-cycles
    /// of 33 ms against the band LU's 1.4 s a step; docs/speed.md, "Measured in stop 28").
    #[serde(rename = "pt-multigrid")]
    PtMultigrid,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Multigrid => "multigrid",
            Method::Reference => "reference",
            Method::Direct => "direct",
            Method::GaussSeidel => "gauss-seidel",
            Method::PtMultigrid => "pt-multigrid",
        }
    }
}

/// The cavitation model of the film (model.md §3).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Cavitation {
    /// Elrod–Adams p–θ: mass-conserving (paper eqs. 4, 5; the model texopt is built on).
    #[default]
    ElrodAdams,
    /// Contrast only (stability study, issue 6): Reynolds' cut-off, p ≥ 0 with the Reynolds
    /// equation for a full film (θ ≡ 1) and dropped where p = 0. It does not conserve mass
    /// (the paper's ref. [7]): runs detect that and fail (`SolveError::MassNotConserved`).
    ReynoldsCutoff,
}

impl Cavitation {
    pub fn is_elrod_adams(&self) -> bool {
        *self == Cavitation::ElrodAdams
    }
}

/// Tolerances of the complementarity/ring iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Converged when the active set no longer changes and the last ring update |δZ| is
    /// below this (µm). With the direct method the relative error left is then at most
    /// `CHORD_CONFIRM`.
    pub z_abs: f64,
    /// Multigrid: also the largest nodal mass residual, relative to that node's flux terms
    /// (Σc·|p| + (adv + at)·φ), must be below this.
    pub residual: f64,
    /// Multigrid: at most this many V-cycles (GMRES iterations) per linear solve.
    pub cycles: usize,
    /// Multigrid: a linear solve stops once its residual has dropped by this factor
    /// (inexact Newton forcing term).
    pub inner: f64,
    /// Iteration cap beyond n1 (a cold start moves a cavitation front by about one node per
    /// iteration, and the iteration is monotone for M-matrices, so n1 + this bounds a sound
    /// solve): more means a failed solve (an error, never a number).
    pub extra_iterations: usize,
    /// Gauss–Seidel (contrast): most sweeps per film solve before it is declared failed.
    pub sweeps: usize,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            z_abs: 1e-10,
            residual: 1e-8,
            cycles: 8,
            inner: 1e-2,
            extra_iterations: 60,
            sweeps: 20_000,
        }
    }
}

/// Gauss–Seidel stops at this largest relative nodal residual at most: the nodes of the
/// flooded gap upstream hold φ ≈ 1000 µm, so 1e-8 relative there still leaves a summed
/// mass defect of ~1e-4 of the throughflow; 1e-12 keeps it under `run::MASS_TOL`.
const GS_RESIDUAL: f64 = 1e-12;

/// p–θ multigrid: most V-cycles of one solve, and the count past which its ring slope is
/// measured again (every step of Case III at `paper` converges in ≤ 25 to 1e-8 of the
/// direct solution, results/speed/pt_multigrid_every.md).
const PT_MAX_CYCLES: usize = 80;
const PT_SLOW: usize = 40;

/// Largest excursion of θ outside [0, 1] taken for round-off.
const THETA_ROUND_OFF: f64 = 1e-9;

/// Direct method: the factors at hand are reused (a chord step) when the matrix has changed
/// by at most this much relative since they were computed (3|δZ|/h: conductances ∝ h³).
/// Each chord step then cuts the error by at least this factor, and the stopping rule
/// accounts for it (`CHORD_CONFIRM`), so the converged state is Newton's to that bound.
/// With a narrow band a factorisation is cheap against an iteration, and a tight bound keeps
/// the factors fresh, so that near the periodic regime a step settles in one iteration; with
/// a wide band ([`WIDE_BAND_N2`]) a looser one trades iterations for factorisations.
/// Measured (Case III from the paper start, per step): 512×8 at 1e-6 / 1e-5 / 1e-4: 2.90 /
/// 3.05 / 3.06 iterations, 2.18 / 1.94 / 1.78 factorisations (there an iteration costs
/// ≈ 2.5 factorisations); 512×32 at 1e-6 / 1e-4: 3.65 / 3.85 iterations, 2.80 / 2.47
/// factorisations (there a factorisation costs ≈ 1.5 iterations).
fn chord_drift(n2: usize) -> f64 {
    if n2 >= WIDE_BAND_N2 {
        1e-4
    } else {
        1e-6
    }
}

/// An iteration ends the solve only when the error it leaves, estimated as the relative
/// matrix error at the final Z (chord drift, or for a Newton step its own Z change) times
/// its relative correction, is at most this (relative, in p and φ; the multigrid path's
/// default `solve_tol` is the same 1e-8). Why not round-off (1e-12, until stop 18): near the
/// periodic regime a step's one chord solve through the period-old factors leaves ≈ 1e-9
/// (drift ≈ 2e-5 times a correction ≈ 6e-5, Case III at 512×32), so a bound at round-off
/// cost every such step a second substitution, whose correction (≈ 6e-11) moved no outcome
/// beyond 1e-10. Measured: Case III at 512×32 from the paper's start, the last four
/// windows 1.9–2.0 → 1.0–1.4 iterations a step (f̄ and C_min within 1.4e-11); at `fast` 3.21 →
/// 2.46 iterations a step and 14 % fewer instructions (valgrind), f̄ within 4.5e-13; 30
/// sampled study cases at `fast` 2.65 → 2.12 iterations a step, outcomes within 1.6e-10.
const CHORD_CONFIRM: f64 = 1e-8;

/// Relative error of single-precision kept factors ([`KeptFactors`]), counted as a matrix
/// drift by the stopping rule: f32 rounding (6e-8) of factors whose elimination hardly grows
/// (M-matrices), with a margin. Beside the chord drifts of 1e-5–1e-4 the rule meets anyway it
/// changes few decisions, and it keeps the solve's stated accuracy honest.
const ROUNDED_FACTORS: f64 = 1e-6;

/// Wide bands ([`WIDE_BAND_N2`]): period-old factors of the same range and active set serve
/// chord steps up to this drift (instead of `chord_drift`'s 1e-4) in one solve, and then
/// only under the tight bound: the first period to meet them stretched keeps them, the next
/// one refreshes them. Why: while the ring still settles (at 512×32 after the hand-off from
/// the coarse mesh), Z moves by ≈ 1e-3 of the clearance a period, and 712 of the 1762
/// factorisations of Case III's 512×32 stage came at a step's first iteration only because
/// of that drift, with the period-old factors of the very active set at hand. A chord step
/// at drift δ cuts the error by δ, so two such steps do what a factorisation and its
/// confirming step did. Kept stretched every period (a plain looser bound), factors grow
/// old: the settled windows then needed 1.7–1.95 iterations a step instead of 1.0.
/// Measured (Case III from the paper's start, windows 14–23 of its 512×32 stage, summed
/// per-step means): rows eliminated 41 731 → 28 166, iterations 17.27 → 17.03; 1e-3: 33 435
/// and 16.55; 1e-2: as 3e-3. At N2 = 8 (`fast`) it costs more iterations than the
/// factorisations it saves (Case III 34.3 → 36.0 iterations, R = 51.2 30.7 → 33.0).
const STRETCH_DRIFT: f64 = 3e-3;

/// Fewest cells across (the band's half-width) from which a factorisation costs more than
/// an iteration, so that the solver saves factorisations rather than iterations: a looser
/// chord bound, and the Newton matrix frozen at the factors' Z when only the active set
/// changed. Measured for the latter (valgrind instruction counts, Case III from the paper
/// start): 512×32 first period −6.4 %; 512×8 whole run +1.1 % (there a factorisation costs
/// ≈ 2.5 substitutions, and the confirming chord step eats the gain).
const WIDE_BAND_N2: usize = 16;

/// Why a film solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilmError {
    #[error("complementarity iteration did not converge in {iterations} iterations ({changes} active-set changes in the last one, last |δZ| = {dz:.3e} µm, Z = {z:.4e} µm)")]
    NotConverged {
        iterations: usize,
        changes: usize,
        dz: f64,
        z: f64,
    },
    #[error("non-finite {quantity} at x1 = {x1:.5} cm, x2 = {x2:.5} cm")]
    NonFinite {
        quantity: &'static str,
        x1: f64,
        x2: f64,
    },
    #[error("the gap closed (h = {h:.3e} µm at x1 = {x1:.5} cm, x2 = {x2:.5} cm): solid contact is outside the lubrication model")]
    GapClosed { h: f64, x1: f64, x2: f64 },
    #[error("saturation θ = {theta:.6e} outside [0, 1] beyond round-off at x1 = {x1:.5} cm, x2 = {x2:.5} cm")]
    SaturationOutOfRange { theta: f64, x1: f64, x2: f64 },
    #[error("plain Gauss–Seidel did not converge in {sweeps} sweeps (relative residual {residual:.2e} > {tol:.0e}); its error decays by 1 − O(1/N²) per sweep, so fine meshes are out of its reach: use --solver direct or multigrid")]
    SweepsExhausted {
        sweeps: usize,
        residual: f64,
        tol: f64,
    },
    #[error("singular film matrix at unknown {row} (pivot {pivot:e})")]
    Singular { row: usize, pivot: f64 },
}

/// What one film solve did.
#[derive(Clone, Copy, Debug, Default)]
pub struct SolveStats {
    /// Active-set/Newton iterations.
    pub iterations: usize,
    /// Multigrid V-cycles (0 for the direct method).
    pub cycles: usize,
    /// Band LU factorisations (direct and reference methods): iterations without one were
    /// chord steps on factors at hand.
    pub factorisations: usize,
    /// Matrix rows those factorisations eliminated (rows they shared with the factors at
    /// hand were kept).
    pub eliminated_rows: usize,
    /// Largest nodal mass-balance residual after the solve, relative to the largest flux
    /// term at that node (round-off level when converged).
    pub residual: f64,
    /// Hydrodynamic load W_h = (1/B)∫∫_ring p (eq. 16).
    pub w_h: f64,
}

/// Band LU factors of a film matrix and what they were factored for, so that they can serve
/// later solves: chord steps inside the iteration, and their leading rows the next
/// factorisation.
#[derive(Debug, Default, Clone)]
struct Factors {
    lu: BandLu,
    of: Option<FactoredFor>,
}

/// Factors kept from a solve for the film problem of the same texture phase one period later
/// (the transient keeps one per step of a period, run.rs): there they serve chord steps and
/// lend their leading rows to a factorisation. Wide bands ([`WIDE_BAND_N2`]) keep them in
/// single precision: half the memory (at 512×32 ≈ 0.5 GB instead of 1 GB a period, which this
/// VM's kernel takes ≈ 2 s a GB to hand out) and half the bytes a substitution reads.
#[derive(Debug, Default, Clone)]
pub struct KeptFactors {
    lu: KeptLu,
    of: Option<FactoredFor>,
}

impl KeptFactors {
    /// Memory held (bytes).
    pub fn bytes(&self) -> usize {
        self.lu.bytes() + self.of.as_ref().map_or(0, |f| f.active.len())
    }
}

/// The film problem factors were computed for: node columns lo..=hi, the active set over
/// them and the ring position Z. With the same texture phase, the same range and active set,
/// the matrix differs from theirs only through Z (conductances ∝ h³).
#[derive(Debug, Clone)]
struct FactoredFor {
    lo: usize,
    hi: usize,
    z: f64,
    active: Vec<bool>,
    /// Whether these factors have served a solve under the stretched bound already.
    stretched: bool,
    /// Whether they are those of their matrix only to ≈ 1e-7 (single precision, whole or in
    /// part): the stopping rule then counts `ROUNDED_FACTORS` as a drift.
    rounded: bool,
}

impl FactoredFor {
    /// Whether these factors are of the matrix of range lo..=hi with active set `active`:
    /// then their Z.
    fn fit(&self, lo: usize, hi: usize, active: &[bool]) -> Option<f64> {
        (self.lo == lo && self.hi == hi && self.active == active).then_some(self.z)
    }
}

/// Reusable work arrays of the film solver.
#[derive(Debug, Default, Clone)]
pub struct FilmSolver {
    pub tol: Tolerance,
    pub method: Method,
    pub cavitation: Cavitation,
    /// The factors of the solver's last factorisation: of this solve once it has factored,
    /// else of another problem, serving only through their bit-identical leading rows.
    factors: Factors,
    /// Factors handed in for this very film problem's geometry (the same texture phase one
    /// period earlier, [`FilmSolver::inherit_factors`]): they serve chord steps until this
    /// solve factors. Else (`inherited` false) only their leading rows can serve.
    kept: KeptFactors,
    inherited: bool,
    /// Factorisations in the current solve and the rows they eliminated.
    factorisations: usize,
    eliminated_rows: usize,
    /// Freeze the Newton matrix at the factors' Z when only the active set changed (wide
    /// bands, `WIDE_BAND_N2`); on by default, off to show what it saves.
    pub freeze_z: bool,
    /// Let period-old factors serve once under the stretched chord bound (`STRETCH_DRIFT`;
    /// wide bands). On by default; off for tests comparing the two.
    pub stretch_chord: bool,
    /// Keep factors for later solves in single precision at wide bands ([`KeptFactors`]).
    /// On by default; off for tests comparing the two.
    pub single_kept: bool,
    mg: LineMultigrid,
    /// The Z at which `h` holds this solve's gap (None: not yet filled in this solve).
    h_at: Option<f64>,
    /// This solve's node columns from the first under the ring to the last.
    ring_span: std::ops::Range<usize>,
    /// Whether `cx`, `cy` hold this solve's conductances away from the ring.
    faces_fresh: bool,
    rhs1: Vec<f64>,
    rhs2: Vec<f64>,
    h: Vec<f64>,
    cx: Vec<f64>,
    cy: Vec<f64>,
    /// The gap and face conductances at the Z of the factors at hand, when the Newton
    /// matrix is frozen there (see `active_set`).
    jh: Vec<f64>,
    jcx: Vec<f64>,
    jcy: Vec<f64>,
    dcx: Vec<f64>,
    dcy: Vec<f64>,
    dphi: Vec<f64>,
    y1: Vec<f64>,
    y2: Vec<f64>,
    /// y1 and y2 interleaved during their substitutions (`BandLu::solve2`).
    pairs: Vec<[f64; 2]>,
    /// p–θ multigrid: the ∂W_h/∂Z its ring updates assume, measured at the first coupled
    /// solve and again whenever a solve needs more than `PT_SLOW` V-cycles.
    pt_slope: Option<f64>,
}

/// Face conductances of the Poiseuille flux for the gap `h`: x1 faces h_f³·dy/dx and x2
/// faces h_f³·dx/dy with h_f the mean of the two nodal gaps (model.md §3), and their
/// derivatives with respect to Z (∂h_f/∂Z is the mean of the nodal ∂h/∂Z).
pub(crate) struct Faces<'a> {
    pub(crate) cx: &'a [f64],
    pub(crate) cy: &'a [f64],
}

/// The one stencil: −(discrete film equation) at interior node (i, j), i.e. the mass balance
/// Σ_faces c·(p_ij − p_nb) + adv·(φ_ij − φ_{i−1,j}) + at·(φ_ij − φ_old,ij), with adv = u·dy
/// and at = 2·dx·dy/dt. It is (−2)× [net outflow + cell-area·∂φ/∂t] of the cell. Every solver
/// path (residual, Z-derivative, upwind sweeps, mass checks) evaluates it, through
/// [`Column::balance`]; this is the same for one node.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn balance(
    g: &Grid,
    f: &Faces,
    adv: f64,
    at: f64,
    p: &[f64],
    phi: &[f64],
    phi_old: Option<&[f64]>,
    i: usize,
    j: usize,
) -> f64 {
    Column::new(g, f, p, phi, phi_old, i).balance(adv, at, j)
}

/// What the stencil reads around node column i (x1 position), sliced once for the column:
/// a pass over a column then indexes slices of length N2 instead of the whole field (no
/// bounds check per term), with the same arithmetic in the same order as node by node.
pub(crate) struct Column<'a> {
    /// Pressures of columns i − 1, i, i + 1.
    p_w: &'a [f64],
    p: &'a [f64],
    p_e: &'a [f64],
    /// Film content φ = hθ of columns i − 1 (upstream) and i, and φ at the old time level.
    phi_w: &'a [f64],
    phi: &'a [f64],
    old: Option<&'a [f64]>,
    /// Conductances of the x1 faces west and east of the column, and of its N2 − 1 x2 faces.
    pub(crate) cx_w: &'a [f64],
    pub(crate) cx_e: &'a [f64],
    pub(crate) cy: &'a [f64],
}

impl<'a> Column<'a> {
    #[inline(always)]
    pub(crate) fn new(
        g: &Grid,
        f: &Faces<'a>,
        p: &'a [f64],
        phi: &'a [f64],
        phi_old: Option<&'a [f64]>,
        i: usize,
    ) -> Self {
        let n2 = g.n2;
        let (w, c, e) = ((i - 1) * n2, i * n2, (i + 1) * n2);
        Column {
            p_w: &p[w..c],
            p: &p[c..e],
            p_e: &p[e..e + n2],
            phi_w: &phi[w..c],
            // Absent when the caller holds column i apart (`balance_with`).
            phi: phi.get(c..e).unwrap_or(&[]),
            old: phi_old.map(|o| &o[c..e]),
            cx_w: &f.cx[w..c],
            cx_e: &f.cx[c..e],
            cy: &f.cy[i * (n2 - 1)..(i + 1) * (n2 - 1)],
        }
    }

    /// The stencil at node (i, j) of this column (see [`balance`]).
    #[inline(always)]
    pub(crate) fn balance(&self, adv: f64, at: f64, j: usize) -> f64 {
        self.balance_with(adv, at, j, self.phi[j])
    }

    /// The stencil at node (i, j) with φ_ij given (the column's own φ held apart).
    #[inline(always)]
    fn balance_with(&self, adv: f64, at: f64, j: usize, phi_j: f64) -> f64 {
        let n2 = self.p.len();
        let pk = self.p[j];
        let mut r = self.cx_w[j] * (pk - self.p_w[j]) + self.cx_e[j] * (pk - self.p_e[j]);
        if j > 0 {
            r += self.cy[j - 1] * (pk - self.p[j - 1]);
        }
        if j + 1 < n2 {
            r += self.cy[j] * (pk - self.p[j + 1]);
        }
        r += adv * (phi_j - self.phi_w[j]);
        r += at * phi_j;
        if let Some(old) = self.old {
            r -= at * old[j];
        }
        r
    }
}

/// Face conductances for the gap `h` into cx, cy. With `only_ring`, only the faces of node
/// columns under the ring (where h depends on Z) are recomputed: the others must already
/// hold this gap's (same texture position), which they then keep, the same bits.
pub(crate) fn face_conductances(
    g: &Grid,
    h: &[f64],
    only_ring: Option<&[bool]>,
    cx: &mut Vec<f64>,
    cy: &mut Vec<f64>,
) {
    let (n1, n2) = (g.n1, g.n2);
    let (sx, sy) = (g.dy / g.dx, g.dx / g.dy);
    let ny = n2.saturating_sub(1);
    // A face between gaps a and b: h_f = (a + b)/2, conductance h_f³·s. Over slices of
    // neighbouring nodes (no index checked per face).
    let face = |a: f64, b: f64, s: f64| {
        let hf = 0.5 * (a + b);
        hf * hf * hf * s
    };
    // x1 faces east of the nodes of columns `cols`, and x2 faces of column i, into `out`.
    let x_faces = |cols: std::ops::Range<usize>, out: &mut [f64]| {
        let (west, east) = (
            &h[cols.start * n2..cols.end * n2],
            &h[(cols.start + 1) * n2..],
        );
        for ((c, &a), &b) in out.iter_mut().zip(west).zip(east) {
            *c = face(a, b, sx);
        }
    };
    let y_faces = |i: usize, out: &mut [f64]| {
        let col = &h[i * n2..(i + 1) * n2];
        for ((c, &a), &b) in out.iter_mut().zip(col).zip(&col[1..]) {
            *c = face(a, b, sy);
        }
    };
    let Some(ring) = only_ring else {
        cx.resize(n1 * n2, 0.0);
        x_faces(0..n1, cx);
        cy.resize((n1 + 1) * ny, 0.0);
        for i in 0..=n1 {
            y_faces(i, &mut cy[i * ny..(i + 1) * ny]);
        }
        return;
    };
    for i in 0..=n1 {
        if i < n1 && (ring[i] || ring[i + 1]) {
            x_faces(i..i + 1, &mut cx[i * n2..(i + 1) * n2]);
        }
        if ring[i] {
            y_faces(i, &mut cy[i * ny..(i + 1) * ny]);
        }
    }
}

/// ∂(face conductance)/∂Z = 3·h_f²·∂h_f/∂Z·(geometry factor).
fn face_conductance_derivatives(
    g: &Grid,
    h: &[f64],
    ring: &[bool],
    dcx: &mut Vec<f64>,
    dcy: &mut Vec<f64>,
) {
    let (n1, n2) = (g.n1, g.n2);
    let (sx, sy) = (g.dy / g.dx, g.dx / g.dy);
    let dz = |i: usize| if ring[i] { 1.0 } else { 0.0 };
    // Zero away from the ring (the same +0.0 the product gives), computed under it only:
    // the ring columns are the same in every call, so the zeros stay once written.
    if dcx.len() != n1 * n2 || dcy.len() != (n1 + 1) * n2.saturating_sub(1) {
        dcx.clear();
        dcx.resize(n1 * n2, 0.0);
        dcy.clear();
        dcy.resize((n1 + 1) * n2.saturating_sub(1), 0.0);
    }
    for i in 0..=n1 {
        if i < n1 && (ring[i] || ring[i + 1]) {
            for k in i * n2..(i + 1) * n2 {
                let hf = 0.5 * (h[k] + h[k + n2]);
                dcx[k] = 3.0 * hf * hf * 0.5 * (dz(i) + dz(i + 1)) * sx;
            }
        }
        if ring[i] {
            for j in 0..n2.saturating_sub(1) {
                let k = i * n2 + j;
                let hf = 0.5 * (h[k] + h[k + 1]);
                dcy[i * (n2 - 1) + j] = 3.0 * hf * hf * dz(i) * sy;
            }
        }
    }
}

impl FilmSolver {
    pub fn new(tol: Tolerance) -> Self {
        Self::with_method(tol, Method::default())
    }

    pub fn with_method(tol: Tolerance, method: Method) -> Self {
        FilmSolver {
            tol,
            method,
            freeze_z: true,
            stretch_chord: true,
            single_kept: true,
            ..Default::default()
        }
    }

    /// Assembles, over node columns lo..=hi, the Newton matrix ∂F/∂x of the current active
    /// set (into the multigrid's fine operator) and −F (into y1). Returns the largest nodal
    /// |F| relative to that node's flux terms.
    fn assemble(
        &mut self,
        step: &Step,
        state: &FilmState,
        (lo, hi): (usize, usize),
        adv: f64,
        at: f64,
        frozen: bool,
    ) -> f64 {
        let g = step.grid;
        let n2 = g.n2;
        let phi_old = (step.inv_dt > 0.0).then_some(step.phi_old);
        let faces = Faces {
            cx: &self.cx,
            cy: &self.cy,
        };
        // The matrix's conductances: at the current Z, or frozen at the factors' Z.
        let jfaces = if frozen {
            Faces {
                cx: &self.jcx,
                cy: &self.jcy,
            }
        } else {
            Faces {
                cx: &self.cx,
                cy: &self.cy,
            }
        };
        let inexact = self.method == Method::Multigrid;
        // The multigrid hierarchy reads the active set beside the operator; the band LU not.
        if inexact {
            let active = self.mg.fine_active_mut();
            active.clear();
            active.extend_from_slice(&state.pressurised[lo * n2..(hi + 1) * n2]);
        }
        let a = self.mg.fine_mut();
        // Every entry is written below.
        a.reshape(hi - lo + 1, n2);
        self.y1.clear();
        let mut fmax: f64 = 0.0;
        let cutoff = !self.cavitation.is_elrod_adams();
        for i in lo..=hi {
            let col = Column::new(g, &faces, &state.p, &state.phi, phi_old, i);
            // The matrix's conductances and the active set around column i, and its rows,
            // as slices of length N2 (no index checked per entry).
            let (cx_w, cx_e) = (&jfaces.cx[(i - 1) * n2..][..n2], &jfaces.cx[i * n2..][..n2]);
            let cy = &jfaces.cy[i * (n2 - 1)..][..n2 - 1];
            let pr_w = &state.pressurised[(i - 1) * n2..][..n2];
            let pr = &state.pressurised[i * n2..][..n2];
            let pr_e = &state.pressurised[(i + 1) * n2..][..n2];
            let r0 = (i - lo) * n2;
            let ac = &mut a.c[r0..][..n2];
            let aw = &mut a.w[r0..][..n2];
            let ae = &mut a.e[r0..][..n2];
            let a_s = &mut a.s[r0..][..n2];
            let an = &mut a.n[r0..][..n2];
            for j in 0..n2 {
                if cutoff && !pr[j] {
                    // Reynolds cut-off: p = 0 fixed, the equation dropped.
                    self.y1.push(0.0);
                    (ac[j], aw[j], ae[j], a_s[j], an[j]) = (1.0, 0.0, 0.0, 0.0, 0.0);
                    continue;
                }
                let f = col.balance(adv, at, j);
                self.y1.push(-f);
                let cw = cx_w[j];
                let ce = cx_e[j];
                let cs = if j > 0 { cy[j - 1] } else { 0.0 };
                let cn = if j + 1 < n2 { cy[j] } else { 0.0 };
                let csum = cw + ce + cs + cn;
                // Relative to the node's largest terms: its Poiseuille and Couette fluxes
                // (read by the multigrid path only).
                if inexact {
                    let scale = csum * col.p[j].abs() + (adv + at) * col.phi[j].abs();
                    if scale > 0.0 {
                        fmax = fmax.max(f.abs() / scale);
                    }
                }
                // Diagonal: ∂F/∂p_ij = Σc on the pressurised set, ∂F/∂φ_ij = adv + at on the
                // cavitated set.
                ac[j] = if pr[j] { csum } else { adv + at };
                // Off-diagonals depend on the neighbour's unknown only: its pressure enters
                // through −c, the upstream φ through −adv, downstream φ not at all.
                aw[j] = if i == lo {
                    0.0
                } else if pr_w[j] {
                    -cw
                } else if cutoff {
                    0.0
                } else {
                    -adv
                };
                let coupled = |on: bool, c: f64| if on { -c } else { 0.0 };
                ae[j] = coupled(i < hi && pr_e[j], ce);
                a_s[j] = coupled(j > 0 && pr[j - 1], cs);
                an[j] = coupled(j + 1 < n2 && pr[j + 1], cn);
            }
        }
        fmax
    }

    /// Prepares the assembled matrix for solves: band LU, or the multigrid hierarchy.
    fn factor(&mut self) -> Result<(), FilmError> {
        match self.method {
            Method::Direct | Method::Reference | Method::GaussSeidel | Method::PtMultigrid => {
                self.factors.of = None;
                // The operator is taken, not copied: the next assembly writes every entry.
                // Kept factors lent for this problem share the rows the texture alone sets.
                let kept = self.kept.of.is_some().then_some(&self.kept.lu);
                let rows = self
                    .factors
                    .lu
                    .factor_taking_reusing(self.mg.fine_mut(), kept)
                    .map_err(|e| FilmError::Singular {
                        row: e.row,
                        pivot: e.value,
                    })?;
                self.eliminated_rows += rows;
                Ok(())
            }
            Method::Multigrid => self.mg.setup().map_err(|e| FilmError::Singular {
                row: e.node,
                pivot: e.value,
            }),
        }
    }

    /// Solves A x = rhs: exactly (direct; x's content ignored) or by `cycles` V-cycles from
    /// the guess in x. Returns the V-cycles used.
    fn solve_linear(&mut self, x: &mut Vec<f64>, rhs: &[f64], cycles: usize, rel: f64) -> usize {
        match self.method {
            Method::Direct | Method::Reference | Method::GaussSeidel | Method::PtMultigrid => {
                x.clear();
                x.extend_from_slice(rhs);
                self.factors.lu.solve(x);
                0
            }
            Method::Multigrid => self.mg.gmres(x, rhs, rel, cycles),
        }
    }

    /// Exchanges the solver's kept factors with `other`, which must be of the film problem
    /// the next [`Self::solve`] is given up to Z (same grid, texture phase, time step and
    /// boundary data): that solve may then use them for chord steps. (Factors of any other
    /// problem would still serve only through their bit-identical leading rows.)
    pub fn inherit_factors(&mut self, other: &mut KeptFactors) {
        if other.lu.is_single() {
            std::mem::swap(&mut self.kept, other);
            self.factors.of = None;
        } else {
            // Double factors become the solver's own, exchanged without a copy: their rows
            // then serve a refactorisation in place.
            other.lu.exchange(&mut self.factors.lu);
            std::mem::swap(&mut self.factors.of, &mut other.of);
            self.kept.of = None;
        }
        self.inherited = true;
    }

    /// Puts the factors of the last solve's last iteration into `slot` (reusing its memory),
    /// to keep them for a later solve ([`Self::inherit_factors`]): the solve's own if it
    /// factored, else those it was lent (exchanged back). Wide bands keep single precision.
    pub fn keep_factors(&mut self, slot: &mut KeptFactors) {
        let single = self.single_kept && self.factors.lu.half_band() >= WIDE_BAND_N2;
        match self.factors.of.take() {
            Some(of) if single => {
                slot.lu.keep_single(&self.factors.lu);
                slot.of = Some(FactoredFor {
                    rounded: true,
                    ..of
                });
            }
            // Double: exchanged, no copy (the solver takes the slot's old factors, which
            // serve only through their identical rows).
            Some(of) => {
                slot.lu.exchange(&mut self.factors.lu);
                slot.of = Some(of);
            }
            None => std::mem::swap(&mut self.kept, slot),
        }
        self.inherited = false;
    }

    /// The factors at hand for a chord step: this solve's own once it has factored, else
    /// the kept ones it was lent.
    fn at_hand(&self) -> Option<&FactoredFor> {
        self.factors.of.as_ref().or(self.kept.of.as_ref())
    }

    fn at_hand_mut(&mut self) -> Option<&mut FactoredFor> {
        self.factors.of.as_mut().or(self.kept.of.as_mut())
    }

    /// Solves one film problem in place. `state` holds the initial guess (normally the
    /// previous time level) and receives the solution; `z` the ring position, updated when
    /// the problem carries a `RingLink`.
    pub fn solve(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<SolveStats, FilmError> {
        let g = step.grid;
        let bc = step.boundary;
        self.factorisations = 0;
        self.eliminated_rows = 0;
        // A new problem: the texture has moved since `h` and the conductances were set.
        self.h_at = None;
        self.faces_fresh = false;
        self.ring_span = step.gap.ring_columns();
        // Factors not handed in for this problem (`inherit_factors`) are of an earlier one:
        // they serve only through their identical rows.
        if !std::mem::take(&mut self.inherited) {
            self.factors.of = None;
            self.kept.of = None;
        }
        for j in 0..g.n2 {
            let (k0, kn) = (g.idx(0, j), g.idx(g.n1, j));
            state.p[k0] = bc.p_left;
            state.phi[k0] = bc.phi_inlet.min(step.gap.h(g, k0, *z));
            state.pressurised[k0] = false;
            state.p[kn] = bc.p_right;
            state.pressurised[kn] = false;
        }
        let (iterations, cycles) = match self.method {
            Method::GaussSeidel => self.gauss_seidel(step, state, z)?,
            Method::PtMultigrid => self.pt_multigrid(step, state, z)?,
            _ => self.active_set(step, state, z)?,
        };
        self.finish(step, state, *z, iterations, cycles)
    }

    /// The gap at Z into `self.h`, unless it holds that already (the iteration fills it at
    /// the new Z to update the active set, and the next iteration starts there).
    fn fill_h(&mut self, step: &Step, z: f64) {
        match self.h_at {
            Some(at) if at.to_bits() == z.to_bits() => {}
            // This solve's gap at another Z: only the columns under the ring change.
            Some(_) => step
                .gap
                .refill_ring(step.grid, z, self.ring_span.clone(), &mut self.h),
            None => step.gap.fill(step.grid, z, &mut self.h),
        }
        self.h_at = Some(z);
    }

    /// The face conductances of `self.h`: all of them at a solve's first call, afterwards
    /// only those under the ring (elsewhere h does not depend on Z).
    fn refresh_faces(&mut self, step: &Step) {
        let only_ring = self.faces_fresh.then_some(&step.gap.ring[..]);
        face_conductances(step.grid, &self.h, only_ring, &mut self.cx, &mut self.cy);
        self.faces_fresh = true;
    }

    /// The gap at Z into `self.h` and its face conductances; a closed gap is an error.
    fn set_gap(&mut self, step: &Step, z: f64) -> Result<(), FilmError> {
        let g = step.grid;
        // After this solve's first fill only the columns under the ring can change.
        let span = if self.h_at.is_some() {
            self.ring_span.start * g.n2..self.ring_span.end * g.n2
        } else {
            0..g.nodes()
        };
        self.fill_h(step, z);
        let closed = |h: &f64| *h <= 0.0 || h.is_nan();
        if let Some(k) = self.h[span.clone()]
            .iter()
            .position(closed)
            .map(|k| k + span.start)
        {
            return Err(FilmError::GapClosed {
                h: self.h[k],
                x1: g.x(k / g.n2),
                x2: g.y(k % g.n2),
            });
        }
        self.refresh_faces(step);
        Ok(())
    }

    /// Primal–dual active-set (semi-smooth Newton) iteration with Z bordered (the direct,
    /// multigrid and reference methods). Returns (iterations, V-cycles).
    fn active_set(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<(usize, usize), FilmError> {
        let g = step.grid;
        let (n1, n2) = (g.n1, g.n2);
        let bc = step.boundary;
        let adv = bc.u * g.dy;
        let at = 2.0 * g.dx * g.dy * step.inv_dt;
        let load_weight = g.dx * g.dy / g.width;
        let ring = &step.gap.ring;
        let phi_old = (step.inv_dt > 0.0).then_some(step.phi_old);
        // Reynolds cut-off (contrast): θ ≡ 1, so φ = h is no unknown anywhere and the
        // cavitated nodes simply drop their equation (p = 0).
        let cutoff = !self.cavitation.is_elrod_adams();

        let interior = n2..n1 * n2;
        let ring_min_base = step.gap.ring_min_base(g);
        // Node columns whose balance depends on Z: under the ring and one either side.
        let ring_cols = match self.ring_span.clone() {
            c if c.is_empty() => 0..0,
            c => c.start.saturating_sub(1)..c.end + 1,
        };

        // Period-old factors that have not served under the stretched bound yet may, for
        // this whole solve (`STRETCH_DRIFT`).
        let stretch = self.stretch_chord
            && n2 >= WIDE_BAND_N2
            && self.at_hand().is_some_and(|f| !f.stretched);
        let mut iterations = 0;
        let mut cycles = 0;
        // What the last update did (multigrid: convergence is judged on the next residual).
        let (mut last_changes, mut last_dz) = (usize::MAX, f64::INFINITY);
        let mut y2_range = None;
        loop {
            iterations += 1;
            // Gap, conductances and their Z-derivatives at the current Z.
            self.set_gap(step, *z)?;
            for ((phi, &pr), &h) in state.phi[interior.clone()]
                .iter_mut()
                .zip(&state.pressurised[interior.clone()])
                .zip(&self.h[interior.clone()])
            {
                if pr || cutoff {
                    *phi = h;
                }
            }

            // x1-range [lo, hi] holding every pressurised node with one column of margin.
            let (mut lo, mut hi) = (usize::MAX, 0);
            for i in 1..n1 {
                if state.pressurised[i * n2..(i + 1) * n2].contains(&true) {
                    lo = lo.min(i);
                    hi = i;
                }
            }
            let empty = lo == usize::MAX && self.method != Method::Reference;
            let (lo, hi) = if self.method == Method::Reference {
                (1, n1 - 1)
            } else if empty {
                (n1, n1 - 1)
            } else {
                (lo.saturating_sub(1).max(1), (hi + 1).min(n1 - 1))
            };

            // Upstream of the range every node is cavitated with p = 0 around it: exact
            // upwind sweep (the stencil is affine in φ_ij with slope adv + at).
            if !cutoff {
                self.upwind_sweep(step, state, 1..lo, adv, at);
            }

            let mut dz = 0.0;
            // The Z the iteration's matrix is of (the current Z for a Newton step), whether
            // it was a chord or frozen one, and the relative size of its correction.
            let mut z_matrix: Option<f64> = None;
            let mut chorded = false;
            // Whether the factors this iteration solves with are rounded (single precision).
            let mut rounded = false;
            let mut correction: f64 = 0.0;
            if !empty {
                let m1 = hi - lo + 1;
                // Relative matrix change 3|δZ|/h since factors at zf (conductances ∝ h³).
                let drift = |zf: f64| 3.0 * (*z - zf).abs() / (*z + ring_min_base);
                let drift_ok = |zf: f64| drift(zf) <= chord_drift(n2);
                // Chord step: when the factors at hand are of this range and active set and
                // Z has moved since by so little that the matrix changed only by δc/c =
                // 3|δZ|/h ≤ chord_drift (conductances ∝ h³), they solve the new system to
                // that relative accuracy. The iteration stays convergent (error × the drift
                // per step) and ends where Newton would, to `CHORD_CONFIRM`; it saves a
                // factorisation: the confirming one of a step, and near the periodic regime
                // the first one too, with the factors of the same phase a period earlier.
                let active = &state.pressurised[lo * n2..(hi + 1) * n2];
                // The bound is `STRETCH_DRIFT` for factors that may be stretched this solve.
                let bound = if stretch {
                    STRETCH_DRIFT
                } else {
                    chord_drift(n2)
                };
                let fit_z = self.at_hand().and_then(|f| f.fit(lo, hi, active));
                let chord =
                    self.method == Method::Direct && fit_z.is_some_and(|zf| drift(zf) <= bound);
                if chord && fit_z.is_some_and(|zf| !drift_ok(zf)) {
                    if let Some(f) = self.at_hand_mut() {
                        f.stretched = true;
                    }
                }
                // Frozen Z: when only the active set changed since the factors (Z within the
                // chord drift), the matrix is assembled at their Z, so that it differs from
                // theirs only in the rows around the switched nodes and the LU reuses every
                // row before the first of them (at the current Z every row under the ring
                // would differ). Pays where a factorisation is dear against the confirming
                // chord step it may cost (wide bands).
                let frozen_z = match self.at_hand() {
                    Some(f)
                        if !chord
                            && self.freeze_z
                            && self.method == Method::Direct
                            && n2 >= WIDE_BAND_N2
                            && f.lo == lo
                            && f.hi == hi
                            && f.z != *z
                            && drift_ok(f.z) =>
                    {
                        Some(f.z)
                    }
                    _ => None,
                };
                chorded = chord || frozen_z.is_some();
                z_matrix = Some(if chord {
                    self.at_hand().map_or(*z, |f| f.z)
                } else {
                    frozen_z.unwrap_or(*z)
                });
                if let Some(zf) = frozen_z {
                    step.gap.fill(g, zf, &mut self.jh);
                    face_conductances(g, &self.jh, None, &mut self.jcx, &mut self.jcy);
                }
                // Residual F = balance(·) at the current iterate and the Newton matrix ∂F/∂x.
                let fmax = self.assemble(step, state, (lo, hi), adv, at, frozen_z.is_some());
                // Multigrid: converged when the last update settled the set and Z and the
                // residual is at tolerance (the direct path decides after its exact solve).
                if self.method == Method::Multigrid
                    && last_changes == 0
                    && last_dz <= self.tol.z_abs
                    && fmax <= self.tol.residual
                {
                    break;
                }
                if !chord {
                    self.factorisations += 1;
                    self.factor()?;
                    self.factors.of = Some(FactoredFor {
                        lo,
                        hi,
                        z: frozen_z.unwrap_or(*z),
                        active: active.to_vec(),
                        stretched: false,
                        rounded: self.factors.lu.rounded(),
                    });
                }
                rounded = self.at_hand().is_some_and(|f| f.rounded);
                // Newton correction: y1 holds −F, the right-hand side. Direct: solved in place,
                // once y2's right-hand side is there too, both substitutions together
                // (BandLu::solve2). Multigrid: from zero.
                let direct = self.method != Method::Multigrid;
                let mut y1_pending = direct;
                if !direct {
                    let rhs1 = std::mem::take(&mut self.y1);
                    let mut y1 = std::mem::take(&mut self.rhs1);
                    y1.clear();
                    y1.resize(rhs1.len(), 0.0);
                    // Inexact Newton (each solve cuts the residual by tol.inner); if the set
                    // keeps flickering, solve accurately (an inexact iterate can flip nodes
                    // where p ≈ 0 and θ ≈ 1 back and forth).
                    let (rel, max_cycles) = if iterations > 8 {
                        (self.tol.residual, 4 * self.tol.cycles)
                    } else {
                        (self.tol.inner, self.tol.cycles)
                    };
                    cycles += self.solve_linear(&mut y1, &rhs1, max_cycles, rel);
                    self.y1 = y1;
                    self.rhs1 = rhs1;
                }

                if let Some(link) = step.ring {
                    // Sensitivity y2 = (∂F/∂x)⁻¹ ∂F/∂Z. It sets only the rate of the Z
                    // iteration, not its limit, so the multigrid path keeps the one of the
                    // step's first iteration while the range holds, then refreshes it from
                    // the last one (warm start).
                    let refresh = self.method != Method::Multigrid
                        || y2_range != Some((lo, hi))
                        || iterations > 2;
                    if refresh {
                        // ∂F/∂Z: the same stencil with conductances ∂c/∂Z and φ' = ∂h/∂Z on
                        // the pressurised set (φ = h there; everywhere under the cut-off),
                        // without the old-time term.
                        face_conductance_derivatives(
                            g,
                            &self.h,
                            ring,
                            &mut self.dcx,
                            &mut self.dcy,
                        );
                        // φ' is read (below) only in the columns that see Z and the one
                        // upstream of them; only those are written.
                        self.dphi.resize(ring.len() * n2, 0.0);
                        let read = ring_cols.start.saturating_sub(1)..ring_cols.end.min(ring.len());
                        for i in read {
                            let col = &state.pressurised[i * n2..(i + 1) * n2];
                            let out = &mut self.dphi[i * n2..(i + 1) * n2];
                            for (d, &pr) in out.iter_mut().zip(col) {
                                *d = if (pr || cutoff) && ring[i] { 1.0 } else { 0.0 };
                            }
                        }
                        let dfaces = Faces {
                            cx: &self.dcx,
                            cy: &self.dcy,
                        };
                        // Only the columns under the ring and their neighbours see Z (the
                        // conductances of their faces, φ' there and upstream); elsewhere
                        // ∂F/∂Z is exactly zero.
                        self.rhs2.clear();
                        self.rhs2.resize(m1 * n2, 0.0);
                        for i in ring_cols.start.max(lo)..ring_cols.end.min(hi + 1) {
                            let col = Column::new(g, &dfaces, &state.p, &self.dphi, None, i);
                            let out = &mut self.rhs2[(i - lo) * n2..(i - lo + 1) * n2];
                            for (j, r) in out.iter_mut().enumerate() {
                                // Under the cut-off a cavitated node's equation is dropped.
                                if !cutoff || state.pressurised[i * n2 + j] {
                                    *r = col.balance(adv, at, j);
                                }
                            }
                        }
                        if y1_pending {
                            // Direct: solved in place (rhs2 gets y2's old buffer, which the
                            // next refresh clears).
                            std::mem::swap(&mut self.rhs2, &mut self.y2);
                            let (y1, y2, pairs) = (&mut self.y1, &mut self.y2, &mut self.pairs);
                            if self.factors.of.is_some() {
                                self.factors.lu.solve2(y1, y2, pairs);
                            } else {
                                self.kept.lu.solve2(y1, y2, pairs);
                            }
                            y1_pending = false;
                        } else {
                            let mut y2 = std::mem::take(&mut self.y2);
                            // Multigrid: start from the last sensitivity on the same range
                            // (the solver falls back to zero when that guess is worse).
                            let warm = y2.len() == self.rhs2.len() && y2_range == Some((lo, hi));
                            if !warm {
                                y2.clear();
                                y2.resize(self.rhs2.len(), 0.0);
                            }
                            let rhs2 = std::mem::take(&mut self.rhs2);
                            cycles +=
                                self.solve_linear(&mut y2, &rhs2, self.tol.cycles, self.tol.inner);
                            self.rhs2 = rhs2;
                            self.y2 = y2;
                        }
                        y2_range = Some((lo, hi));
                    }
                    debug_assert!(!y1_pending);
                    // Ring equation G = Z − z_pred − κ(W_h(p) − W_ps) = 0, ∂G/∂p_k = −κ·w_k.
                    let w_h = load(g, ring, &state.p);
                    let gres = *z - link.z_pred - link.kappa * (w_h - link.w_ps);
                    let (mut gy1, mut gy2) = (0.0, 0.0);
                    for i in (lo..=hi).filter(|&i| ring[i]) {
                        for j in 0..n2 {
                            if state.pressurised[i * n2 + j] {
                                let r = (i - lo) * n2 + j;
                                gy1 += self.y1[r];
                                gy2 += self.y2[r];
                            }
                        }
                    }
                    let gx = -link.kappa * load_weight;
                    dz = -(gres + gx * gy1) / (1.0 - gx * gy2);
                    dz = limit_closing(dz, *z, ring_min_base);
                    for (a, b) in self.y1.iter_mut().zip(&self.y2) {
                        *a -= b * dz;
                    }
                }
                if y1_pending {
                    // No ring: y1 alone.
                    if self.factors.of.is_some() {
                        self.factors.lu.solve(&mut self.y1);
                    } else {
                        self.kept.lu.solve(&mut self.y1);
                    }
                }
                debug_assert_eq!(self.y1.len(), m1 * n2);
                let (mut dp, mut dphi, mut pmax) = (0.0f64, 0.0f64, 0.0f64);
                // Nodes lo·n2.. in order, y1 indexed from 0.
                let span = lo * n2..(hi + 1) * n2;
                for ((((&d, &pr), p), phi), &h) in self
                    .y1
                    .iter()
                    .zip(&state.pressurised[span.clone()])
                    .zip(&mut state.p[span.clone()])
                    .zip(&mut state.phi[span.clone()])
                    .zip(&self.h[span])
                {
                    if pr {
                        *p += d;
                        dp = dp.max(d.abs());
                        pmax = pmax.max(p.abs());
                    } else if !cutoff {
                        *phi += d;
                        dphi = dphi.max(d.abs() / h);
                    }
                }
                correction = dphi.max(if pmax > 0.0 { dp / pmax } else { 0.0 });
            } else if let Some(link) = step.ring {
                // No pressure anywhere: W_h = 0 and the ring update is explicit.
                dz = link.z_pred - link.kappa * link.w_ps - *z;
            }
            *z += dz;

            // Downstream of the range: exact upwind sweep again.
            if !cutoff {
                self.upwind_sweep(step, state, hi + 1..n1, adv, at);
            }

            // Active-set update: negative pressure → cavitated; over-full film → pressurised.
            let pmax = state.pressurised[interior.clone()]
                .iter()
                .zip(&state.p[interior.clone()])
                .filter(|(&pr, _)| pr)
                .fold(0.0f64, |m, (_, &p)| m.max(p));
            // Switching thresholds at round-off.
            let eps = 1e-13;
            let p_eps = eps * pmax;
            let mut changes = 0;
            self.fill_h(step, *z);
            if !cutoff {
                // Elrod–Adams: each node by itself (slices, no index per node).
                let nodes = interior.clone();
                for (((pr, p), phi), &hk) in state.pressurised[nodes.clone()]
                    .iter_mut()
                    .zip(&mut state.p[nodes.clone()])
                    .zip(&mut state.phi[nodes.clone()])
                    .zip(&self.h[nodes])
                {
                    if *pr {
                        changes += usize::from(cavitate(pr, p, phi, hk, p_eps));
                    } else if *phi > hk * (1.0 + eps) {
                        *pr = true;
                        *p = 0.0;
                        *phi = hk;
                        changes += 1;
                    }
                }
            }
            // The cut-off's re-admission reads the neighbours (in node order, as above).
            for k in interior.clone().filter(|_| cutoff) {
                let hk = self.h[k];
                if state.pressurised[k] {
                    let (pr, p) = (&mut state.pressurised[k], &mut state.p[k]);
                    changes += usize::from(cavitate(pr, p, &mut state.phi[k], hk, p_eps));
                } else {
                    // Cut-off: a dropped node comes back when p = 0 leaves it a net inflow
                    // (the Reynolds equation would raise its pressure).
                    let faces = Faces {
                        cx: &self.cx,
                        cy: &self.cy,
                    };
                    let (i, j) = (k / n2, k % n2);
                    let f = balance(g, &faces, adv, at, &state.p, &state.phi, phi_old, i, j);
                    let scale = (adv + at) * hk + adv * state.phi[k - n2];
                    if f < -1e-12 * scale {
                        state.pressurised[k] = true;
                        changes += 1;
                    }
                }
            }
            check_finite(g, state, *z)?;
            // Exact linear solves (direct): stop once the set is settled and what the next
            // iteration would still change is negligible: a Newton step that moved Z by at
            // most z_abs, or any step whose estimated leftover is (`CHORD_CONFIRM`). At a fixed set the
            // problem is nonlinear only through h(Z), so what is left is about the matrix's
            // relative error at the final Z (c: the drift of chord or frozen factors, or a
            // Newton step's own Z change) times this iteration's change, in Z and in p, φ.
            let exact = empty || self.method != Method::Multigrid;
            // Rounded factors add their own relative error to c (`ROUNDED_FACTORS`).
            let settled = (dz.abs() <= self.tol.z_abs && !chorded && !rounded)
                || z_matrix.is_some_and(|zm| {
                    let c = 3.0 * (*z - zm).abs() / (*z + ring_min_base)
                        + if rounded { ROUNDED_FACTORS } else { 0.0 };
                    c * dz.abs() <= self.tol.z_abs && c * correction <= CHORD_CONFIRM
                });
            if exact && changes == 0 && settled {
                break;
            }
            (last_changes, last_dz) = (changes, dz.abs());
            if iterations >= n1 + self.tol.extra_iterations {
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

    /// Exact upwind sweep over node columns `cols`, all cavitated with p = 0 around them
    /// (the stencil is affine in φ_ij with slope adv + at).
    fn upwind_sweep(
        &self,
        step: &Step,
        state: &mut FilmState,
        cols: std::ops::Range<usize>,
        adv: f64,
        at: f64,
    ) {
        let g = step.grid;
        let phi_old = (step.inv_dt > 0.0).then_some(step.phi_old);
        let faces = Faces {
            cx: &self.cx,
            cy: &self.cy,
        };
        let n2 = g.n2;
        for i in cols {
            // A node's balance reads φ of its own node and the one upstream only, so the
            // column's updates can follow its residuals.
            let (done, rest) = state.phi.split_at_mut(i * n2);
            let col = Column::new(g, &faces, &state.p, done, phi_old, i);
            for (j, phi) in rest[..n2].iter_mut().enumerate() {
                let r = col.balance_with(adv, at, j, *phi);
                *phi -= r / (adv + at);
            }
        }
    }

    /// The p–θ multigrid ([`crate::pt_multigrid`], Galerkin V(2,2) cycles, Z moved after
    /// each) from `state` until the largest relative nodal residual is at most
    /// [`GS_RESIDUAL`] (as for Gauss–Seidel: the flooded gap's large φ needs it for the mass
    /// guard) and the last ring update at most `tol.z_abs`. Returns (V-cycles, V-cycles).
    fn pt_multigrid(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<(usize, usize), FilmError> {
        let tol = self.tol.residual.min(GS_RESIDUAL);
        let mut cycles = 0;
        // A ring slope that has gone stale (the ring moved far since it was measured) shows
        // as a slow solve: measured again, the solve starts over once.
        for attempt in 0..2 {
            let mut mg = crate::pt_multigrid::PtMultigrid::new(step, *z);
            mg.galerkin = true;
            if step.ring.is_some() {
                let slope = match self.pt_slope {
                    Some(s) if attempt == 0 => s,
                    _ => crate::pt_multigrid::PtMultigrid::load_slope(step, state, *z),
                };
                self.pt_slope = Some(slope);
                mg.dw_dz = slope;
            }
            mg.load(state);
            for c in 1..=PT_MAX_CYCLES {
                let z_before = mg.z();
                mg.vcycle();
                cycles += 1;
                let moved = (mg.z() - z_before).abs();
                if !mg.z().is_finite() {
                    break;
                }
                if moved <= self.tol.z_abs.max(1e-12 * mg.z()) && mg.relative_residual() <= tol {
                    mg.store(state);
                    *z = mg.z();
                    return Ok((cycles, cycles));
                }
                if c == PT_SLOW && attempt == 0 && step.ring.is_some() {
                    break;
                }
            }
            if step.ring.is_none() {
                break;
            }
        }
        Err(FilmError::NotConverged {
            iterations: cycles,
            changes: 0,
            dz: f64::NAN,
            z: *z,
        })
    }

    /// Plain Gauss–Seidel (contrast): at fixed Z when the problem has no ring, otherwise a
    /// secant iteration on the ring equation G(Z) = Z − z_pred − κ(W_h(Z) − W_ps) = 0 around
    /// film solves at fixed Z. Returns (sweeps, 0).
    fn gauss_seidel(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: &mut f64,
    ) -> Result<(usize, usize), FilmError> {
        let mut sweeps = 0;
        let Some(link) = step.ring else {
            self.gs_fixed_z(step, state, *z, &mut sweeps)?;
            return Ok((sweeps, 0));
        };
        let g = step.grid;
        let ring = &step.gap.ring;
        let ring_min_base = step.gap.ring_min_base(g);
        let ring_residual = |s: &mut Self, st: &mut FilmState, zz: f64, n: &mut usize| {
            s.gs_fixed_z(step, st, zz, n)?;
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
                return Ok((sweeps, 0));
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

    /// Plain projected Gauss–Seidel at fixed Z: each node in turn solves its own balance for
    /// its unknown (p if pressurised, φ if not), p < 0 → cavitated, φ > h → pressurised;
    /// until the largest relative residual is below `tol.residual`.
    fn gs_fixed_z(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: f64,
        sweeps: &mut usize,
    ) -> Result<(), FilmError> {
        let g = step.grid;
        let (n1, n2) = (g.n1, g.n2);
        let adv = step.boundary.u * g.dy;
        let at = 2.0 * g.dx * g.dy * step.inv_dt;
        let phi_old = (step.inv_dt > 0.0).then_some(step.phi_old);
        self.set_gap(step, z)?;
        for k in n2..n1 * n2 {
            if state.pressurised[k] {
                state.phi[k] = self.h[k];
            }
        }
        loop {
            let faces = Faces {
                cx: &self.cx,
                cy: &self.cy,
            };
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
                        if phi > self.h[k] {
                            state.phi[k] = self.h[k];
                            state.pressurised[k] = true;
                        } else {
                            state.phi[k] = phi;
                        }
                    }
                }
            }
            *sweeps += 1;
            if sweeps.is_multiple_of(4) || *sweeps >= self.tol.sweeps {
                check_finite(g, state, z)?;
                let residual = self.max_relative_residual(step, state, z);
                if residual <= self.tol.residual.min(GS_RESIDUAL) {
                    return Ok(());
                }
                if *sweeps >= self.tol.sweeps {
                    return Err(FilmError::SweepsExhausted {
                        sweeps: *sweeps,
                        residual,
                        tol: self.tol.residual.min(GS_RESIDUAL),
                    });
                }
            }
        }
    }

    /// Final state, guards and statistics of a converged solve.
    fn finish(
        &mut self,
        step: &Step,
        state: &mut FilmState,
        z: f64,
        iterations: usize,
        cycles: usize,
    ) -> Result<SolveStats, FilmError> {
        let g = step.grid;
        let (n1, n2) = (g.n1, g.n2);
        let interior = n2..n1 * n2;
        let cutoff = !self.cavitation.is_elrod_adams();
        // Final state: p = 0 on the cavitated set, θ = 1 on the pressurised set. φ on the
        // cavitated set is left as solved (θ ≤ 1 + 1e-13, the switching threshold): clipping
        // it would remove mass where φ ≈ h is large (the flooded gap e upstream of the ring)
        // and break the exact discrete balance.
        self.fill_h(step, z);
        for k in interior.clone() {
            if state.pressurised[k] || cutoff {
                state.phi[k] = self.h[k];
            } else {
                state.p[k] = 0.0;
            }
        }
        for j in 0..n2 {
            state.phi[g.idx(n1, j)] = state.phi[g.idx(n1 - 1, j)];
        }
        // The residual of the state as solved, before the round-off negative pressures the
        // switching threshold lets stand (|p| ≤ 1e-13·p_max) are clipped to 0 below. Why
        // before: next to the face between the ring's edge and the gap e (h_f ≈ e/2, so a
        // conductance ≈ 10⁸) such a clip of 1e-17 alone shows as a residual of ≈ 1e-7 of the
        // node's fluxes (seen at the trailing edge of a flat ring), which says nothing
        // about the solve.
        let residual = self.max_relative_residual(step, state, z);
        for k in interior.clone() {
            if state.pressurised[k] || cutoff {
                state.p[k] = state.p[k].max(0.0);
            }
        }
        // Guard: θ = φ/h must stay in [0, 1] up to round-off (a wrong number that looks
        // right is worse than an error).
        if let Some(k) = interior.clone().find(|&k| {
            let theta = state.phi[k] / self.h[k];
            !(-THETA_ROUND_OFF..=1.0 + THETA_ROUND_OFF).contains(&theta)
        }) {
            return Err(FilmError::SaturationOutOfRange {
                theta: state.phi[k] / step.gap.h(g, k, z),
                x1: g.x(k / n2),
                x2: g.y(k % n2),
            });
        }
        Ok(SolveStats {
            iterations,
            cycles,
            factorisations: self.factorisations,
            eliminated_rows: self.eliminated_rows,
            residual,
            w_h: load(g, &step.gap.ring, &state.p),
        })
    }

    /// Largest nodal residual of the discrete film equation relative to the largest term of
    /// that node's balance.
    fn max_relative_residual(&mut self, step: &Step, state: &FilmState, z: f64) -> f64 {
        let g = step.grid;
        self.fill_h(step, z);
        self.refresh_faces(step);
        let faces = Faces {
            cx: &self.cx,
            cy: &self.cy,
        };
        let adv = step.boundary.u * g.dy;
        let at = 2.0 * g.dx * g.dy * step.inv_dt;
        let phi_old = (step.inv_dt > 0.0).then_some(step.phi_old);
        max_relative_residual(g, &faces, adv, at, &state.p, &state.phi, phi_old)
    }
}

/// Largest nodal residual of the discrete film equation (the one stencil) relative to the
/// largest term of that node's balance: the measure every solver path is stopped and
/// reported by.
pub(crate) fn max_relative_residual(
    g: &Grid,
    faces: &Faces,
    adv: f64,
    at: f64,
    p: &[f64],
    phi: &[f64],
    phi_old: Option<&[f64]>,
) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 1..g.n1 {
        let col = Column::new(g, faces, p, phi, phi_old, i);
        for j in 0..g.n2 {
            let r = col.balance(adv, at, j);
            let pscale = col.cx_w[j].max(col.cx_e[j])
                * col.p[j].abs().max(col.p_w[j].abs().max(col.p_e[j].abs()));
            let scale = pscale + (adv + at) * col.phi[j].abs() + adv * col.phi_w[j];
            // Divides only where the ratio may exceed the worst so far: rounding is
            // monotone and |r| is a float, so |r|/scale > worst implies |r| ≥
            // fl(worst·scale). The same maximum, bit for bit, without a division per node.
            if scale > 0.0 && r.abs() >= worst * scale {
                worst = worst.max(r.abs() / scale);
            }
        }
    }
    worst
}

/// Active-set update of a pressurised node: a pressure below −p_eps releases it to the
/// cavitated set (p = 0, φ = h to start from). Returns whether it switched.
#[inline(always)]
fn cavitate(pressurised: &mut bool, p: &mut f64, phi: &mut f64, h: f64, p_eps: f64) -> bool {
    let switch = *p < -p_eps;
    if switch {
        *pressurised = false;
        *p = 0.0;
        *phi = h;
    }
    switch
}

/// Sum of the four face conductances of node (i, j): the diagonal ∂F/∂p_ij of the stencil.
#[inline]
pub(crate) fn conductance_sum(g: &Grid, f: &Faces, i: usize, j: usize) -> f64 {
    let (n2, k) = (g.n2, i * g.n2 + j);
    let mut c = f.cx[k - n2] + f.cx[k];
    if j > 0 {
        c += f.cy[i * (n2 - 1) + j - 1];
    }
    if j + 1 < n2 {
        c += f.cy[i * (n2 - 1) + j];
    }
    c
}

/// Damping of a ring update: it may at most halve the smallest gap under the ring, so no
/// iterate closes it (a ring truly pushed into the liner still fails).
fn limit_closing(dz: f64, z: f64, ring_min_base: f64) -> f64 {
    if ring_min_base + z + dz <= 0.5 * (ring_min_base + z) {
        -0.5 * (ring_min_base + z)
    } else {
        dz
    }
}

/// Guard: every interior p and φ and Z finite, else an error naming where.
fn check_finite(g: &Grid, state: &FilmState, z: f64) -> Result<(), FilmError> {
    if !z.is_finite() {
        return Err(FilmError::NonFinite {
            quantity: "ring position Z",
            x1: f64::NAN,
            x2: f64::NAN,
        });
    }
    // A value is not finite when its exponent bits are all set: one branch-free pass says
    // whether there is any; only then is it looked for.
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    let bad = |x: f64| x.to_bits() & EXPONENT == EXPONENT;
    let mut interior = g.n2..g.n1 * g.n2;
    let any = state.p[interior.clone()]
        .iter()
        .zip(&state.phi[interior.clone()])
        .fold(false, |a, (&p, &phi)| a | bad(p) | bad(phi));
    if !any {
        return Ok(());
    }
    if let Some(k) = interior.find(|&k| !(state.p[k].is_finite() && state.phi[k].is_finite())) {
        return Err(FilmError::NonFinite {
            quantity: if state.p[k].is_finite() {
                "film content hθ"
            } else {
                "pressure"
            },
            x1: g.x(k / g.n2),
            x2: g.y(k % g.n2),
        });
    }
    Ok(())
}

/// Hydrodynamic load per unit width W_h = (1/B)∫∫_ring p dx1 dx2 (eq. 16), as the nodal sum
/// over the node columns under the ring.
pub fn load(g: &Grid, ring: &[bool], p: &[f64]) -> f64 {
    let mut s = 0.0;
    for (i, &r) in ring.iter().enumerate() {
        if r {
            s += p[i * g.n2..(i + 1) * g.n2].iter().sum::<f64>();
        }
    }
    s * g.dx * g.dy / g.width
}

/// Mass flow rates of φ = hθ through the x1 boundaries of the interior control volumes,
/// summed over the simulated width: (inflow through the face at x1 = dx/2, outflow through
/// the face at x1 = length − dx/2), with the flux q = (u/2)·φ_upwind − (h_f³/2)·∂p/∂x1 of
/// model.md §3. Over a step, Σ(φ^{n+1} − φ^n)·dx·dy = dt·(inflow − outflow) at the new level.
pub fn boundary_flows(g: &Grid, gap: &Gap, z: f64, u: f64, state: &FilmState) -> (f64, f64) {
    let n1 = g.n1;
    let flux = |i: usize, j: usize| {
        let (k, kn) = (g.idx(i, j), g.idx(i + 1, j));
        let hf = 0.5 * (gap.h(g, k, z) + gap.h(g, kn, z));
        0.5 * u * state.phi[k] - 0.5 * hf * hf * hf * (state.p[kn] - state.p[k]) / g.dx
    };
    let inflow = (0..g.n2).map(|j| flux(0, j) * g.dy).sum();
    let outflow = (0..g.n2).map(|j| flux(n1 - 1, j) * g.dy).sum();
    (inflow, outflow)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_gap_is_an_error_not_a_number() {
        let g = Grid::new(16, 1, 1.0, 1.0);
        let mut base = vec![1.0; 17];
        base[8] = 0.0;
        let gap = Gap {
            base,
            ring: vec![false; 17],
        };
        let phi_old = vec![1.0; 17];
        let step = Step {
            grid: &g,
            gap: &gap,
            phi_old: &phi_old,
            inv_dt: 0.0,
            boundary: Boundary {
                u: 1.0,
                p_left: 0.0,
                p_right: 0.0,
                phi_inlet: 1.0,
            },
            ring: None,
        };
        let mut st = FilmState::flooded(&g, &gap, 0.0);
        let err = FilmSolver::new(Tolerance::default())
            .solve(&step, &mut st, &mut 0.0)
            .unwrap_err();
        assert!(matches!(err, FilmError::GapClosed { x1, .. } if (x1 - 0.5).abs() < 1e-12));
    }
}
