//! When band LU factors at hand serve an iteration instead of a new factorisation
//! (docs/solver.md, "Reusing factors").
//!
//! Within a solve, and from the solve of the same texture phase one period earlier, the film
//! matrix of the same x1-range and active set differs from the factored one only through Z
//! (conductances ∝ h³): by 3|δZ|/h relative. Up to a bound on that drift the factors solve the
//! new system to that relative accuracy (a chord step); the iteration stays convergent and
//! ends where Newton's would, to [`CHORD_CONFIRM`].

use super::band::{BandLu, KeptLu};
use super::{FilmError, Stencil5};

/// Chord steps are taken while the matrix has changed by at most this much relative since
/// the factors (3|δZ|/h). Each chord step then cuts the error by at least this factor, and
/// the stopping rule accounts for it ([`CHORD_CONFIRM`]). With a narrow band a factorisation
/// is cheap against an iteration and a tight bound keeps the factors fresh, so that near the
/// periodic regime a step settles in one iteration; with a wide band ([`WIDE_BAND_N2`]) a
/// looser one trades iterations for factorisations. Measured (Case III, iterations and
/// factorisations a step): 512×8 at 1e-6 / 1e-5 / 1e-4: 2.90 / 3.05 / 3.06 and 2.18 / 1.94 /
/// 1.78 (an iteration costs ≈ 2.5 factorisations there); 512×32 at 1e-6 / 1e-4: 3.65 / 3.85
/// and 2.80 / 2.47 (a factorisation costs ≈ 1.5 iterations there).
pub(super) fn chord_drift(n2: usize) -> f64 {
    if n2 >= WIDE_BAND_N2 {
        1e-4
    } else {
        1e-6
    }
}

/// An iteration ends the solve only when the error it leaves, estimated as the relative
/// matrix error at the final Z (chord drift, or for a Newton step its own Z change) times
/// its relative correction, is at most this (relative, in p and φ). Near the periodic
/// regime a step's one chord solve through the period-old factors leaves ≈ 1e-9 (drift
/// ≈ 2e-5 times a correction ≈ 6e-5, Case III at 512×32): a bound at round-off would cost
/// every such step a second substitution that moves no outcome beyond 1e-10.
pub(super) const CHORD_CONFIRM: f64 = 1e-8;

/// Relative error of single-precision kept factors ([`KeptFactors`]), counted as a matrix
/// drift by the stopping rule: f32 rounding (6e-8) of factors whose elimination hardly grows
/// (M-matrices), with a margin.
pub(super) const ROUNDED_FACTORS: f64 = 1e-6;

/// Wide bands: period-old factors of the same range and active set serve chord steps up to
/// this drift (instead of [`chord_drift`]'s 1e-4) in one solve, and then only under the tight
/// bound: the first period to meet them stretched keeps them, the next one refreshes them.
/// While the ring still settles, Z moves by ≈ 1e-3 of the clearance a period; a chord step at
/// drift δ cuts the error by δ, so two such steps do what a factorisation and its confirming
/// step did. Kept stretched every period, factors grow old (settled windows then needed
/// 1.7–1.95 iterations a step instead of 1.0). Measured (Case III, 512×32, ten windows):
/// rows eliminated 41 731 → 28 166, iterations 17.27 → 17.03. At N2 = 8 it costs more
/// iterations than the factorisations it saves.
const STRETCH_DRIFT: f64 = 3e-3;

/// Fewest cells across (the band's half-width) from which a factorisation costs more than an
/// iteration, so that the solver saves factorisations rather than iterations: a looser chord
/// bound, the stretched bound, single-precision kept factors, and the Newton matrix frozen at
/// the factors' Z when only the active set changed (measured at 512×32: −6.4 % instructions
/// in the first period; at 512×8 +1.1 %, where a factorisation costs ≈ 2.5 substitutions and
/// the confirming chord step eats the gain).
pub(super) const WIDE_BAND_N2: usize = 16;

/// Band LU factors and what they were factored for.
#[derive(Debug, Default, Clone)]
struct Factors {
    lu: BandLu,
    of: Option<FactoredFor>,
}

/// Factors kept from a solve for the film problem of the same texture phase one period later
/// (the transient keeps one per step of a period): there they serve chord steps and lend
/// their leading rows to a factorisation. Wide bands (N2 ≥ 16) keep them in single
/// precision: half the memory (at 512×32 ≈ 0.5 GB instead of 1 GB a period) and half the
/// bytes a substitution reads.
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
/// them and the ring position Z. With the same texture phase, range and active set, the
/// matrix differs from theirs only through Z.
#[derive(Debug, Clone)]
struct FactoredFor {
    lo: usize,
    hi: usize,
    z: f64,
    active: Vec<bool>,
    /// Whether these factors have served a solve under the stretched bound already.
    stretched: bool,
    /// Whether they are those of their matrix only to ≈ 1e-7 (single precision, whole or in
    /// part): the stopping rule then counts [`ROUNDED_FACTORS`] as a drift.
    rounded: bool,
}

impl FactoredFor {
    /// Whether these factors are of the matrix of range lo..=hi with active set `active`:
    /// then their Z.
    fn fit(&self, lo: usize, hi: usize, active: &[bool]) -> Option<f64> {
        (self.lo == lo && self.hi == hi && self.active == active).then_some(self.z)
    }
}

/// How one iteration's matrix is had.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan {
    /// Solve with the factors at hand (a chord step) instead of factoring.
    pub chord: bool,
    /// Assemble the matrix at this Z (the factors') instead of the current one: when only the
    /// active set changed since the factors (Z within the chord drift), the matrix then
    /// differs from theirs only in the rows around the switched nodes, and the LU reuses
    /// every row before the first of them.
    pub frozen: Option<f64>,
    /// The Z the iteration's matrix is of.
    pub z_matrix: f64,
}

/// The band LU of the film iteration and its factors: this solve's, and those lent for it.
#[derive(Debug, Default, Clone)]
pub(super) struct Reuse {
    /// No reuse at all: every iteration factors (the plain reference).
    reference: bool,
    /// The factors of the last factorisation: of this solve once it has factored, else of
    /// another problem, serving only through their bit-identical leading rows.
    factors: Factors,
    /// Factors handed in for this very film problem ([`Reuse::inherit`]): they serve chord
    /// steps until this solve factors. Else (`inherited` false) only their leading rows serve.
    kept: KeptFactors,
    inherited: bool,
    /// Factorisations in the current solve and the rows they eliminated.
    pub factorisations: usize,
    pub eliminated_rows: usize,
}

impl Reuse {
    pub fn new(reference: bool) -> Self {
        Reuse {
            reference,
            ..Default::default()
        }
    }

    /// Whether this is the plain reference (nothing reused, the whole domain every time).
    pub fn is_reference(&self) -> bool {
        self.reference
    }

    /// A new solve. Factors not handed in for it are of an earlier problem: they serve only
    /// through their identical rows.
    pub fn begin(&mut self) {
        self.factorisations = 0;
        self.eliminated_rows = 0;
        if !std::mem::take(&mut self.inherited) {
            self.factors.of = None;
            self.kept.of = None;
        }
    }

    /// The factors at hand for a chord step: this solve's own once it has factored, else the
    /// kept ones it was lent.
    fn at_hand(&self) -> Option<&FactoredFor> {
        self.factors.of.as_ref().or(self.kept.of.as_ref())
    }

    fn at_hand_mut(&mut self) -> Option<&mut FactoredFor> {
        self.factors.of.as_mut().or(self.kept.of.as_mut())
    }

    /// Whether period-old factors may serve this solve under the stretched bound (they have
    /// not yet, and the band is wide).
    pub fn may_stretch(&self, n2: usize) -> bool {
        !self.reference && n2 >= WIDE_BAND_N2 && self.at_hand().is_some_and(|f| !f.stretched)
    }

    /// How the iteration's matrix over range lo..=hi with active set `active` is had, the
    /// ring at `z`. `stretch`: [`Reuse::may_stretch`] at the solve's start.
    pub fn plan(
        &mut self,
        (lo, hi): (usize, usize),
        active: &[bool],
        z: f64,
        ring_min_base: f64,
        n2: usize,
        stretch: bool,
    ) -> Plan {
        if self.reference {
            return Plan {
                chord: false,
                frozen: None,
                z_matrix: z,
            };
        }
        // Relative matrix change 3|δZ|/h since factors at zf (conductances ∝ h³).
        let drift = |zf: f64| 3.0 * (z - zf).abs() / (z + ring_min_base);
        let drift_ok = |zf: f64| drift(zf) <= chord_drift(n2);
        let bound = if stretch {
            STRETCH_DRIFT
        } else {
            chord_drift(n2)
        };
        let fit_z = self.at_hand().and_then(|f| f.fit(lo, hi, active));
        let chord = fit_z.is_some_and(|zf| drift(zf) <= bound);
        if chord && fit_z.is_some_and(|zf| !drift_ok(zf)) {
            if let Some(f) = self.at_hand_mut() {
                f.stretched = true;
            }
        }
        let frozen = match self.at_hand() {
            Some(f)
                if !chord
                    && n2 >= WIDE_BAND_N2
                    && f.lo == lo
                    && f.hi == hi
                    && f.z != z
                    && drift_ok(f.z) =>
            {
                Some(f.z)
            }
            _ => None,
        };
        let z_matrix = if chord {
            self.at_hand().map_or(z, |f| f.z)
        } else {
            frozen.unwrap_or(z)
        };
        Plan {
            chord,
            frozen,
            z_matrix,
        }
    }

    /// Factors `a` (taken, not copied: the next assembly writes every entry), the matrix of
    /// range lo..=hi and active set `active` at ring position `z_of`. Kept factors lent for
    /// this problem share the rows the texture alone sets.
    pub fn factor(
        &mut self,
        a: &mut Stencil5,
        (lo, hi): (usize, usize),
        active: &[bool],
        z_of: f64,
    ) -> Result<(), FilmError> {
        self.factorisations += 1;
        self.factors.of = None;
        let kept = self.kept.of.is_some().then_some(&self.kept.lu);
        let rows = self
            .factors
            .lu
            .factor_taking_reusing(a, kept)
            .map_err(|e| FilmError::Singular {
                row: e.row,
                pivot: e.value,
            })?;
        self.eliminated_rows += rows;
        self.factors.of = Some(FactoredFor {
            lo,
            hi,
            z: z_of,
            active: active.to_vec(),
            stretched: false,
            rounded: self.factors.lu.rounded(),
        });
        Ok(())
    }

    /// Whether the factors at hand are rounded (single precision).
    pub fn rounded(&self) -> bool {
        self.at_hand().is_some_and(|f| f.rounded)
    }

    /// Solves for two right-hand sides in place with the factors at hand.
    pub fn solve2(&self, y1: &mut [f64], y2: &mut [f64], pairs: &mut Vec<[f64; 2]>) {
        if self.factors.of.is_some() {
            self.factors.lu.solve2(y1, y2, pairs);
        } else {
            self.kept.lu.solve2(y1, y2, pairs);
        }
    }

    /// Solves for one right-hand side in place with the factors at hand.
    pub fn solve(&self, y: &mut [f64]) {
        if self.factors.of.is_some() {
            self.factors.lu.solve(y);
        } else {
            self.kept.lu.solve(y);
        }
    }

    /// Exchanges the kept factors with `other`, which must be of the film problem the next
    /// solve is given up to Z (same grid, texture phase, time step and boundary data).
    pub fn inherit(&mut self, other: &mut KeptFactors) {
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

    /// Puts the factors of the last solve's last iteration into `slot` (reusing its memory):
    /// the solve's own if it factored, else those it was lent (exchanged back). Wide bands
    /// keep single precision.
    pub fn keep(&mut self, slot: &mut KeptFactors) {
        let single = self.factors.lu.half_band() >= WIDE_BAND_N2;
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
}
