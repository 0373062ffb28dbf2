//! What the optimiser reports of its designs: each design's row against the plain liner, the
//! roles a row plays on the front, the report itself and the designs merged away. Data, and the order the table lists them in;
//! the table and the files are written by the design report.

use crate::time::ErrorSource;
use serde::Serialize;

use super::space::Space;
use crate::model::case::Texture;
use crate::model::operating::Outside;

/// What a reported design is on the front, in the order a label names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    BestFriction,
    BestClearance,
    Balanced,
    PlainLiner,
}

impl Role {
    pub fn name(self) -> &'static str {
        match self {
            Role::BestFriction => "best friction",
            Role::BestClearance => "best clearance",
            Role::Balanced => "balanced",
            Role::PlainLiner => "plain liner",
        }
    }
}

/// A reported design's label: its roles (none before the front is labelled), named joined by
/// " + " (a kept design carries the roles of the designs merged into it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Label(Vec<Role>);

impl Label {
    pub fn of(role: Role) -> Label {
        Label(vec![role])
    }

    pub fn has(&self, role: Role) -> bool {
        self.0.contains(&role)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The label of a kept row carrying `labels`: each role once, the best designs first;
    /// "balanced" says nothing once a row is a best design.
    pub fn joined<'a>(labels: impl IntoIterator<Item = &'a Label>) -> Label {
        let mut roles: Vec<Role> = Vec::new();
        for &r in labels.into_iter().flat_map(|l| &l.0) {
            if !roles.contains(&r) {
                roles.push(r);
            }
        }
        roles.sort_by_key(|r| match r {
            Role::BestClearance => 1,
            Role::Balanced => 2,
            Role::BestFriction | Role::PlainLiner => 0,
        });
        if roles.len() > 1 {
            roles.retain(|r| *r != Role::Balanced);
        }
        Label(roles)
    }
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, r) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(" + ")?;
            }
            f.write_str(r.name())?;
        }
        Ok(())
    }
}

impl Serialize for Label {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// One reported design.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub label: Label,
    /// None: the plain liner.
    pub texture: Option<Texture>,
    pub f_mean: f64,
    pub c_min: f64,
    pub z_mean: f64,
    pub f_change_pct: f64,
    pub c_min_change_pct: f64,
    pub area_fraction: f64,
    /// The pockets' walls (NaN for the plain liner, written as null).
    #[serde(serialize_with = "crate::finite::absent")]
    pub wall_x1_cm: f64,
    #[serde(serialize_with = "crate::finite::absent")]
    pub wall_x2_cm: f64,
    pub depth_ratio: f64,
    pub active_constraints: Vec<String>,
    pub on_front: bool,
    /// Period-mean friction force and power per unit circumferential length (N/m, W/m).
    pub friction_n_per_m: f64,
    pub power_w_per_m: f64,
    /// Why the design is outside the hydrodynamic model (docs/model.md §9), if it is.
    pub outside_model: Option<Outside>,
    /// How well f̄ and C_min are known (relative): the reported tier's stated error, or the
    /// mesh uncertainty of pockets deeper than the tiers resolve (docs/validation.md).
    pub f_error: f64,
    pub c_min_error: f64,
    pub error_source: ErrorSource,
}

/// The result of `optimise`.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub r: f64,
    /// The operating point: its Stribeck number (eq. 19) and the composite roughness of the
    /// clearance limit (µm).
    pub stribeck: f64,
    pub roughness_um: f64,
    pub space: Space,
    pub search_fidelity: String,
    pub report_fidelity: String,
    /// Relative error of f̄ of the reported fidelity (`Fidelity::f_error`).
    pub fidelity_error: f64,
    /// Relative error of C_min of the reported fidelity (`Fidelity::c_error`).
    pub fidelity_c_error: f64,
    pub plain: Row,
    /// The plain liner's f̄ and C_min at the search fidelity (the searched designs' changes).
    pub plain_search_f_mean: f64,
    pub plain_search_c_min: f64,
    pub best_friction: Row,
    pub best_clearance: Row,
    /// The confirmed Pareto front (plain liner included when on it), by increasing f̄.
    pub front: Vec<Row>,
    /// Front designs left out because a thicker-walled one on the front has the same f̄ and
    /// C_min within the reported tier's errors (the front's merge rule), and how many.
    pub merged_count: usize,
    pub merged: Vec<Merged>,
    /// Whether a texture beats the plain liner's friction by more than the fidelity error.
    pub texture_beats_plain: bool,
    pub verdict: String,
    pub evaluations_search: usize,
    pub evaluations_confirm: usize,
    pub simulations: usize,
    pub wall_time_s: f64,
    /// Every evaluated design: (fidelity, texture, f̄, C_min, feasible) for the plot and audit.
    pub evaluated: Vec<EvaluatedDesign>,
}

#[derive(Clone, Debug, Serialize)]
pub struct EvaluatedDesign {
    pub fidelity: String,
    pub texture: Texture,
    pub f_mean: Option<f64>,
    pub c_min: Option<f64>,
    pub failure: Option<String>,
    pub active_constraints: Vec<String>,
}

/// A design left out of the table because a thicker-walled one gives the same f̄ and C_min.
#[derive(Clone, Debug, Serialize)]
pub struct Merged {
    /// Its label before merging.
    pub label: Label,
    pub texture: Texture,
    pub f_mean: f64,
    pub c_min: f64,
    /// The kept design it was merged into.
    pub into: Texture,
}

/// The table's rows with their labels: the best designs, the other front designs by f̄,
/// the plain liner.
pub fn table_rows(r: &Report) -> Vec<(String, &Row)> {
    let mut rows: Vec<(String, &Row)> = Vec::new();
    for (x, role) in [
        (&r.best_friction, Role::BestFriction),
        (&r.best_clearance, Role::BestClearance),
    ] {
        if x.texture.is_some() && !rows.iter().any(|(_, y)| y.texture == x.texture) {
            rows.push((labelled(x, role), x));
        }
    }
    for x in &r.front {
        if x.texture.is_some() && !rows.iter().any(|(_, y)| y.texture == x.texture) {
            rows.push((x.label.to_string(), x));
        }
    }
    rows.push((Role::PlainLiner.name().into(), &r.plain));
    rows
}

/// A best design's label: its own, or its role where it has none (a best design off the
/// front after merging).
pub(super) fn labelled(x: &Row, role: Role) -> String {
    if x.label.is_empty() {
        role.name().into()
    } else {
        x.label.to_string()
    }
}

impl Report {
    /// What the merge rule adds where a front design's pockets end deeper than the tiers
    /// resolve: its own mesh uncertainty (nothing where none does).
    pub fn deep_clause(&self) -> &'static str {
        if self
            .front
            .iter()
            .any(|x| x.error_source == ErrorSource::DeepMesh)
        {
            ", or the larger mesh uncertainty of a design with deep pockets"
        } else {
            ""
        }
    }
}
