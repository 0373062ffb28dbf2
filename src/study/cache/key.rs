//! An evaluation's key: the canonical JSON of everything that determines its answer (the
//! model version, the case, the numerics) and its SHA-256.

use serde::Serialize;

use super::MODEL_VERSION;
use crate::mesh::RimModel;
use crate::model::case::CaseSpec;
use crate::solve::Method;
use crate::study::entry;
use crate::time::{Approach, Numerics, Start, TimeScheme};

/// The canonical key of an evaluation and its hash.
#[derive(Clone, Debug)]
pub struct Key {
    pub hash: String,
    pub json: String,
}

#[derive(Serialize)]
struct KeyInputs<'a> {
    model: &'a str,
    case: &'a CaseSpec,
    numerics: KeyNumerics,
}

/// The numerics as keys hold them: every field of [`Numerics`] in its order, and after
/// `solver` the film solve's tolerance and cycle count of the key format, constants
/// (changing the format would orphan every evaluation stored).
#[derive(Serialize)]
struct KeyNumerics {
    n1: usize,
    n2: usize,
    dt: f64,
    periodic_tol: f64,
    t_max: f64,
    min_periods: usize,
    solver: Method,
    solve_tol: f64,
    cycles: usize,
    start: Start,
    accelerate: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    approach: Option<Approach>,
    #[serde(skip_serializing_if = "TimeScheme::is_backward_euler")]
    scheme: TimeScheme,
    #[serde(skip_serializing_if = "Option::is_none")]
    deep: Option<Approach>,
    #[serde(skip_serializing_if = "RimModel::is_nodal")]
    rim: RimModel,
}

impl KeyNumerics {
    fn of(n: &Numerics) -> Self {
        let Numerics {
            n1,
            n2,
            dt,
            periodic_tol,
            t_max,
            min_periods,
            solver,
            start,
            accelerate,
            approach,
            scheme,
            deep,
            rim,
        } = n.clone();
        KeyNumerics {
            n1,
            n2,
            dt,
            periodic_tol,
            t_max,
            min_periods,
            solver,
            solve_tol: 1e-8,
            cycles: 8,
            start,
            accelerate,
            approach,
            scheme,
            deep,
            rim,
        }
    }
}

impl Key {
    pub fn of(case: &CaseSpec, numerics: &Numerics) -> Key {
        let json = serde_json::to_string(&KeyInputs {
            model: MODEL_VERSION,
            case,
            numerics: KeyNumerics::of(numerics),
        })
        .expect("plain data serialises");
        let hash = entry::hash_of(&json);
        Key { hash, json }
    }
}
