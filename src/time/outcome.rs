//! What a run reports: its outcomes and its time series.

use serde::{Deserialize, Serialize};

use super::numerics::TimeScheme;
use super::uncertainty::{
    needs_uncertainty, AnswerError, ErrorSource, MeshUncertainty, MissingUncertainty,
};
use crate::model::case::CaseSpec;
use crate::model::friction::Friction;

/// Outcomes of one evaluation (docs/model.md §6). Friction coefficients per eq. (11); Z and
/// clearances in µm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// Period-mean friction coefficient f̄ and its Couette, Poiseuille and pressure terms.
    pub f_mean: f64,
    pub f_couette: f64,
    pub f_poiseuille: f64,
    pub f_pressure: f64,
    /// The asperities' boundary friction, part of f̄ (docs/model.md §11). Absent (0) where
    /// they carry nothing.
    #[serde(default, skip_serializing_if = "is_zero_f")]
    pub f_boundary: f64,
    /// Period-mean share of the load the asperities carry, W̄_a/W_ps (docs/model.md §11).
    /// Absent (0) where they carry nothing.
    #[serde(default, skip_serializing_if = "is_zero_f")]
    pub asperity_share: f64,
    /// Mean, minimum and maximum of Z over the last period (µm).
    pub z_mean: f64,
    pub z_min: f64,
    pub z_max: f64,
    /// Minimum clearance over the period: min over t and over the ring of h_U + Z (µm).
    pub c_min: f64,
    /// Texture periods simulated (0 for a steady solve).
    pub periods: usize,
    /// Time steps taken (0 for a steady solve).
    pub steps: usize,
    /// Whether the periodic regime (or the steady force balance) was reached.
    pub converged: bool,
    /// Estimated relative distance of f̄ and Z̄ from their periodic limits at the end: +∞
    /// where too few periods ran to tell (an answer, written as null).
    #[serde(serialize_with = "crate::finite::unbounded")]
    pub periodic_error: f64,
    /// "steady-1d" or "transient-2d".
    pub method: String,
    /// Time step used (divides the texture period exactly); 0 for steady.
    pub dt: f64,
    /// Simulated time at the end.
    pub t_end: f64,
    /// Mean complementarity/Newton iterations per step (per film solve when steady).
    pub iterations_per_step: f64,
    /// Largest relative nodal residual of the film equation over the run.
    pub max_residual: f64,
    pub wall_time_s: f64,
    /// Of `steps` (and `periods`), those taken on the coarse approach mesh
    /// (`Numerics::approach_n2`); 0 without one. Absent in records made before it existed.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub approach_steps: usize,
    /// The film's time scheme of the last window: the run's own, or backward Euler where a
    /// BDF2 run did not settle (`time::BDF2_PATIENCE`). Absent (backward Euler) in records
    /// made before BDF2 existed, and for steady solves.
    #[serde(default, skip_serializing_if = "TimeScheme::is_backward_euler")]
    pub scheme: TimeScheme,
    /// The mesh (N1, N2) and step the answer is on where it is not the numerics' own: a run
    /// whose pockets ended deeper than its mesh resolves and went on on the deep-pocket mesh
    /// ([`super::Numerics::deep`]). Absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deep_mesh: Option<(usize, usize)>,
    /// The run went on on the deep-pocket mesh, which did not reach its periodic regime within
    /// its allowance: the answer is the run's own mesh's. Absent otherwise.
    #[serde(default, skip_serializing_if = "is_false")]
    pub deep_unsettled: bool,
    /// The mesh uncertainty of an answer whose pockets end deeper than
    /// [`super::DEEP_POCKET_RATIO`]·C_min ([`MeshUncertainty`], on the mesh the answer is
    /// on). Absent on the others, which carry the tier's stated error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh_uncertainty: Option<Box<MeshUncertainty>>,
}

impl Outcome {
    /// The mesh (N1, N2) the answer is on: the deep-pocket mesh where the run went on on it,
    /// else the numerics' `own`.
    pub fn mesh(&self, own: (usize, usize)) -> (usize, usize) {
        self.deep_mesh.unwrap_or(own)
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn is_zero_f(x: &f64) -> bool {
    *x == 0.0
}

/// One row of the time series: values at the end of each step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeriesRow {
    pub t: f64,
    pub z: f64,
    pub w_h: f64,
    /// Asperity load W_a (docs/model.md §11).
    pub w_a: f64,
    pub f: f64,
    pub f_couette: f64,
    pub f_poiseuille: f64,
    pub f_pressure: f64,
    /// Boundary friction of the asperities (docs/model.md §11), part of f.
    pub f_boundary: f64,
}

/// A run's outcomes and, on request, its time series.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub outcome: Outcome,
    pub series: Option<Vec<SeriesRow>>,
    /// The outcomes for further shear thresholds θ_s asked for (same film and ring).
    pub extra: Vec<(f64, Outcome)>,
}

impl Outcome {
    /// This outcome with other friction terms (another θ_s of the same run).
    pub fn with_friction(&self, f: &Friction) -> Outcome {
        Outcome {
            f_mean: f.total(),
            f_couette: f.couette,
            f_poiseuille: f.poiseuille,
            f_pressure: f.pressure,
            f_boundary: f.boundary,
            ..self.clone()
        }
    }
}

impl Outcome {
    /// The answer's errors: the tier's `tier` (f̄, C_min) where the pockets end within
    /// [`super::DEEP_POCKET_RATIO`]·C_min; else the larger of those and its mesh uncertainty (+∞
    /// where that could not be measured), which such an answer must carry.
    pub fn error(
        &self,
        case: &CaseSpec,
        tier: (f64, f64),
    ) -> Result<AnswerError, MissingUncertainty> {
        if !needs_uncertainty(case, self.c_min) {
            return Ok(AnswerError {
                f_mean: tier.0,
                c_min: tier.1,
                source: ErrorSource::Tier,
            });
        }
        let u = self
            .mesh_uncertainty
            .as_deref()
            .ok_or_else(|| MissingUncertainty { case: case.label() })?;
        let known = |x: Option<f64>, floor: f64| x.map_or(f64::INFINITY, |x| x.max(floor));
        Ok(AnswerError {
            f_mean: known(u.f_mean, tier.0),
            c_min: known(u.c_min, tier.1),
            source: ErrorSource::DeepMesh,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::case::Texture;

    fn deep_case() -> CaseSpec {
        CaseSpec::paper(25.6).with_texture(Texture::circular(0.03, 0.06, 20.0))
    }

    /// An outcome with least clearance `c_min` (µm); the rest does not matter here.
    fn outcome(c_min: f64) -> Outcome {
        let json = format!(
            r#"{{"f_mean":0.16,"f_couette":0.1,"f_poiseuille":0.03,"f_pressure":0.03,"z_mean":2.0,"z_min":1.9,"z_max":2.1,"c_min":{c_min},"periods":10,"steps":1000,"converged":true,"periodic_error":1e-5,"method":"transient-2d","dt":6.7e-4,"t_end":1.0,"iterations_per_step":2.0,"max_residual":1e-9,"wall_time_s":1.0}}"#
        );
        serde_json::from_str(&json).expect("an outcome")
    }

    #[test]
    fn only_pockets_deeper_than_six_c_min_need_a_mesh_uncertainty_and_must_carry_it() {
        let case = deep_case();
        let tier = (0.009, 0.0077);
        // 20 µm over 4 µm: resolved, the tier's error.
        let e = outcome(4.0).error(&case, tier).unwrap();
        assert_eq!(
            (e.f_mean, e.c_min, e.source),
            (0.009, 0.0077, ErrorSource::Tier)
        );
        // 20 µm over 1.5 µm: deep; without its uncertainty it is refused.
        let mut deep = outcome(1.5);
        assert!(deep.error(&case, tier).is_err());
        deep.mesh_uncertainty = Some(Box::new(MeshUncertainty {
            f_mean: Some(0.05),
            c_min: Some(0.005),
            coarse: None,
        }));
        let e = deep.error(&case, tier).unwrap();
        assert_eq!(
            (e.f_mean, e.c_min, e.source),
            (0.05, 0.0077, ErrorSource::DeepMesh)
        );
        // Not measured: unbounded.
        deep.mesh_uncertainty = Some(Box::new(MeshUncertainty::of((0.16, 1.5), None)));
        assert_eq!(deep.error(&case, tier).unwrap().f_mean, f64::INFINITY);
    }
}
