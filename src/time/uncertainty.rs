//! How well an answer is known: the tier's stated error where the mesh resolves the pockets;
//! where they end deeper than [`DEEP_POCKET_RATIO`]·C_min, a mesh uncertainty measured on the
//! answer itself (docs/validation.md, "Deep pockets: the measured uncertainty").

use serde::{Deserialize, Serialize};

use super::fidelity::{unresolved_depth, DEEP_POCKET_RATIO};
use crate::model::case::CaseSpec;

/// The least mesh uncertainty a deep answer is given (relative): where the uniform coarsening
/// changes the answer by less, its change does not follow a first-order error (its sign and
/// size do not match the refinement's), and one uniform refinement moves the answers measured
/// by at most 0.6 % (results/deep_mesh/, results/deep_rule/), whose first-order error is twice
/// that.
pub const UNCERTAINTY_FLOOR: f64 = 0.012;

/// The mesh uncertainty of a deep-pocket answer (docs/validation.md, "Deep pockets: the
/// measured uncertainty"): the answer's mesh coarsened uniformly (N1 and N2 halved, the step
/// doubled) and run on from the answer's periodic regime to its own. With Δ the relative
/// change it makes, a first-order scheme's error on the answer's mesh is |Δ|; the uncertainty
/// is 2·|Δ|, and at least [`UNCERTAINTY_FLOOR`]: over results/deep_rule/ and
/// results/deep_mesh/ it covers twice the change of one uniform refinement on every case.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshUncertainty {
    /// Relative uncertainties of f̄ and C_min (fractions); None: not measured (the coarser
    /// mesh is not valid for the case, or did not reach its periodic regime).
    pub f_mean: Option<f64>,
    pub c_min: Option<f64>,
    /// The coarser mesh's answer it was measured with.
    pub coarse: Option<Coarse>,
}

/// The coarser mesh's answer: its mesh and its f̄ and C_min.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Coarse {
    pub n1: usize,
    pub n2: usize,
    pub f_mean: f64,
    pub c_min: f64,
}

impl MeshUncertainty {
    /// The uncertainty of the answer (`f_mean`, `c_min`) from its coarser mesh's answer (see
    /// [`MeshUncertainty`]); not measured without one.
    pub fn of(answer: (f64, f64), coarse: Option<Coarse>) -> Self {
        let u = |x0: f64, x: f64| (2.0 * (x / x0 - 1.0).abs()).max(UNCERTAINTY_FLOOR);
        MeshUncertainty {
            f_mean: coarse.map(|c| u(answer.0, c.f_mean)),
            c_min: coarse.map(|c| u(answer.1, c.c_min)),
            coarse,
        }
    }
}

/// Whether an answer of `case` with least clearance `c_min` (µm) has pockets deeper than the
/// tiers resolve, and so must carry a [`MeshUncertainty`].
pub fn needs_uncertainty(case: &CaseSpec, c_min: f64) -> bool {
    case.texture
        .as_ref()
        .is_some_and(|t| unresolved_depth(t.depth, c_min))
}

/// What an answer is known to: its relative errors in f̄ and C_min, and where they come from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AnswerError {
    /// Relative errors (fractions); +∞ where a deep answer's could not be measured.
    #[serde(serialize_with = "crate::finite::unbounded")]
    pub f_mean: f64,
    #[serde(serialize_with = "crate::finite::unbounded")]
    pub c_min: f64,
    pub source: ErrorSource,
}

/// Where an answer's stated error comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ErrorSource {
    /// The tier's stated error: the mesh resolves the pockets.
    Tier,
    /// Measured on the answer's mesh ([`MeshUncertainty`]), or the tier's stated error where
    /// that is larger.
    DeepMesh,
}

impl ErrorSource {
    pub fn name(self) -> &'static str {
        match self {
            ErrorSource::Tier => "tier",
            ErrorSource::DeepMesh => "deep-mesh",
        }
    }
}

/// A deep-pocket answer without its mesh uncertainty: it is not written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("case {case}: its pockets end deeper than {DEEP_POCKET_RATIO}·C_min but its answer carries no mesh uncertainty; run it through `texopt` (which gives every such answer one) rather than writing an outcome made elsewhere")]
pub struct MissingUncertainty {
    pub case: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uncertainty_is_twice_the_coarsening_s_change_and_at_least_the_floor() {
        let coarse = |f_mean: f64, c_min: f64| {
            Some(Coarse {
                n1: 300,
                n2: 12,
                f_mean,
                c_min,
            })
        };
        // 5 % and 10 % changes: 10 % and 20 %.
        let u = MeshUncertainty::of((0.2, 1.0), coarse(0.19, 1.1));
        assert!(
            (u.f_mean.unwrap() - 0.10).abs() < 1e-12 && (u.c_min.unwrap() - 0.20).abs() < 1e-12
        );
        // A 0.1 % change: the floor.
        let u = MeshUncertainty::of((0.2, 1.0), coarse(0.2002, 1.0));
        assert_eq!(
            (u.f_mean, u.c_min),
            (Some(UNCERTAINTY_FLOOR), Some(UNCERTAINTY_FLOOR))
        );
        // No coarser answer: not measured.
        assert_eq!(MeshUncertainty::of((0.2, 1.0), None).f_mean, None);
    }
}
