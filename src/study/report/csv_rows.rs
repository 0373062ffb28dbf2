//! The study's CSV: one row per case, its inputs, outcome, physical values and ratios to the
//! plain liner.

use std::path::Path;

use super::Row;
use crate::model::case::{CaseSpec, Texture};
use crate::model::operating::Physical;
use crate::output::OutputError;
use crate::study::file::Study;
use crate::time::Outcome;

pub(super) fn write_csv(path: &Path, study: &Study, rows: &[Row]) -> Result<(), OutputError> {
    crate::output::atomically(path, |tmp| csv_rows(tmp, study, rows))
}

fn csv_rows(path: &Path, study: &Study, rows: &[Row]) -> Result<(), csv::Error> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record(CSV_COLUMNS.iter().map(|(name, _)| name))?;
    for row in rows {
        let (c, o) = (&row.job.case, row.out);
        let line = Line {
            fidelity: study.fidelity.name(),
            row,
            physical: row.job.scales.physical(
                c,
                o.map_or(f64::NAN, |o| o.f_mean),
                o.map_or(f64::NAN, |o| o.c_min),
            ),
        };
        w.write_record(CSV_COLUMNS.iter().map(|(_, cell)| cell(&line)))?;
    }
    Ok(w.flush()?)
}

/// What one row of the study's CSV is written from.
struct Line<'a> {
    fidelity: &'a str,
    row: &'a Row<'a>,
    physical: Physical,
}

impl Line<'_> {
    fn case(&self) -> &CaseSpec {
        &self.row.job.case
    }
    fn texture(&self, value: fn(&Texture) -> f64) -> String {
        num(self.case().texture.as_ref().map(value))
    }
    fn outcome(&self, value: fn(&Outcome) -> f64) -> String {
        num(self.row.out.map(value))
    }
    /// The mesh of the answer (the deep-pocket mesh where the run went on).
    fn mesh(&self) -> (usize, usize) {
        let n = &self.row.job.numerics;
        self.row.out.map_or((n.n1, n.n2), |o| o.mesh((n.n1, n.n2)))
    }
}

/// A number, or an empty cell.
fn num(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| format!("{v}"))
}

/// How a cell of the study's CSV is written.
type Cell = fn(&Line) -> String;

/// The study CSV's columns: each header with how its cell is written.
const CSV_COLUMNS: [(&str, Cell); 43] = [
    ("R", |l| format!("{}", l.case().r)),
    ("textured", |l| format!("{}", l.case().texture.is_some())),
    ("l1", |l| l.texture(|t| t.l1)),
    ("l2", |l| l.texture(|t| t.l2)),
    ("per", |l| l.texture(|t| t.per)),
    ("width", |l| l.texture(|t| t.width)),
    ("depth", |l| l.texture(|t| t.depth)),
    ("area_fraction", |l| {
        num(Some(
            l.case()
                .texture
                .as_ref()
                .map_or(0.0, Texture::area_fraction),
        ))
    }),
    ("theta_s", |l| format!("{}", l.case().theta_s)),
    ("d_oil", |l| format!("{}", l.case().d_oil)),
    ("u", |l| format!("{}", l.case().u)),
    ("w_ps", |l| format!("{}", l.case().w_ps)),
    ("mass", |l| format!("{}", l.case().mass)),
    ("e", |l| format!("{}", l.case().e)),
    ("fidelity", |l| l.fidelity.to_string()),
    ("n1", |l| format!("{}", l.mesh().0)),
    ("n2", |l| format!("{}", l.mesh().1)),
    // The step of the answer (the deep-pocket mesh's where the run went on).
    ("dt", |l| {
        let o = l.row.out.filter(|o| o.deep_mesh.is_some());
        format!("{}", o.map_or(l.row.job.numerics.dt, |o| o.dt))
    }),
    ("status", |l| {
        match (l.row.out, l.row.reason) {
            (Some(_), _) => "done",
            (None, Some(_)) => "failed",
            _ => "not run",
        }
        .into()
    }),
    ("f_mean", |l| l.outcome(|o| o.f_mean)),
    ("f_couette", |l| l.outcome(|o| o.f_couette)),
    ("f_poiseuille", |l| l.outcome(|o| o.f_poiseuille)),
    ("f_pressure", |l| l.outcome(|o| o.f_pressure)),
    ("z_mean", |l| l.outcome(|o| o.z_mean)),
    ("z_min", |l| l.outcome(|o| o.z_min)),
    ("z_max", |l| l.outcome(|o| o.z_max)),
    ("c_min", |l| l.outcome(|o| o.c_min)),
    ("f_over_plain", |l| num(l.row.f_ratio())),
    ("c_min_over_plain", |l| num(l.row.c_ratio())),
    ("periods", |l| l.outcome(|o| o.periods as f64)),
    ("steps", |l| l.outcome(|o| o.steps as f64)),
    ("wall_time_s", |l| l.outcome(|o| o.wall_time_s)),
    ("reason", |l| l.row.reason.unwrap_or_default().to_string()),
    ("ring_width", |l| format!("{}", l.case().ring_width)),
    ("stribeck", |l| format!("{}", l.physical.stribeck)),
    ("speed_m_s", |l| format!("{}", l.physical.speed_ms)),
    ("load_n_m", |l| format!("{}", l.physical.load_n_per_m)),
    ("friction_n_m", |l| {
        num(l.row.out.map(|_| l.physical.friction_n_per_m))
    }),
    ("power_w_m", |l| {
        num(l.row.out.map(|_| l.physical.power_w_per_m))
    }),
    ("outside_model", |l| {
        l.row.outside.map(|o| o.to_string()).unwrap_or_default()
    }),
    // How well f̄ and C_min are known (relative): the tier's stated error, or the mesh
    // uncertainty of pockets deeper than the tiers resolve (docs/validation.md).
    ("f_error", |l| num(l.row.error.map(|e| e.f_mean))),
    ("c_min_error", |l| num(l.row.error.map(|e| e.c_min))),
    ("error_source", |l| {
        l.row
            .error
            .map_or(String::new(), |e| e.source.name().into())
    }),
];
