//! The lab's studies, run by `texopt-lab STUDY …`: each writes under `results/<study>/`.

pub mod convergence;
pub mod cycle_contact;
pub mod cycle_steps;
pub mod cycle_stress;
pub mod deep_mesh;
pub mod deep_pockets;
pub mod liner_frame;
pub mod references;
pub mod rim_1d;
pub mod rim_2d;
pub mod rim_liner;
pub mod rim_moving;
pub mod rim_rows;
pub mod shear_threshold;
pub mod speed;
pub mod stability;
pub mod where_time_goes;

use std::fs;

use texopt::model::case::CaseSpec;
use texopt::time::{
    simulate_with, Numerics, Outcome, Progress, RunOptions, RunResult, Transient, Watch,
};

use crate::solvers::Solver;

/// One run of a study: the case's name, its numerics, the film solver of its own mesh and
/// its outcome (one JSON object, or a line of a JSON-lines file).
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunRecord {
    pub case: String,
    pub numerics: Numerics,
    pub solver: Solver,
    pub outcome: Outcome,
}

impl RunRecord {
    /// A record from its JSON. The solver is a field of its own; in older records it sat in
    /// the numerics (then any solver, now the product's only).
    pub fn parse(mut v: serde_json::Value) -> Result<RunRecord, String> {
        let in_numerics = v["numerics"]["solver"].as_str().map(str::to_string);
        let solver = match (v["solver"].as_str(), in_numerics.as_deref()) {
            (Some(s), _) | (None, Some(s)) => Solver::parse(s)?,
            (None, None) => Solver::Direct,
        };
        if let Some(n) = v["numerics"].as_object_mut() {
            n.insert("solver".into(), "direct".into());
            // Older records name their coarse approach by its cells across alone (on the
            // run's own N1 and time step).
            if let Some(n2) = n.remove("approach_n2") {
                let approach = serde_json::json!({"n1": n["n1"], "n2": n2, "dt": n["dt"]});
                n.entry("approach").or_insert(approach);
            }
        }
        Ok(RunRecord {
            case: v["case"].as_str().unwrap_or("case-I").to_string(),
            numerics: serde_json::from_value(v["numerics"].clone()).map_err(|e| e.to_string())?,
            solver,
            outcome: serde_json::from_value(v["outcome"].clone()).map_err(|e| e.to_string())?,
        })
    }

    /// The records of a JSON-lines file (a setting run again replaces its earlier line).
    pub fn load(path: &str) -> Result<Vec<RunRecord>, String> {
        let text = fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
        let mut runs: Vec<RunRecord> = text
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| RunRecord::parse(serde_json::from_str(l).map_err(|e| e.to_string())?))
            .collect::<Result<_, _>>()?;
        let mut i = 0;
        while i < runs.len() {
            let same = |r: &RunRecord| {
                r.case == runs[i].case
                    && r.numerics == runs[i].numerics
                    && r.solver == runs[i].solver
            };
            if runs[i + 1..].iter().any(same) {
                runs.remove(i);
            } else {
                i += 1;
            }
        }
        Ok(runs)
    }

    /// Appends this record as one line of the JSON-lines file `path` (its folder made if
    /// missing). One write per line: runs on both cores append to the same file.
    pub fn append(&self, path: &str) -> Result<(), String> {
        if let Some(dir) = std::path::Path::new(path).parent() {
            fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let line = serde_json::to_string(self).map_err(|e| e.to_string())?;
        let mut f = fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| format!("{path}: {e}"))?;
        std::io::Write::write_all(&mut f, format!("{line}\n").as_bytes())
            .map_err(|e| format!("{path}: {e}"))
    }
}

/// The convergence study's runs (results/convergence/run_*.json, Case I).
pub fn convergence_runs() -> Result<Vec<RunRecord>, String> {
    let mut runs = Vec::new();
    let Ok(dir) = fs::read_dir("results/convergence") else {
        return Ok(runs);
    };
    for e in dir.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        if name.starts_with("run_") && name.ends_with(".json") {
            let v: serde_json::Value = fs::read_to_string(e.path())
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok())
                .ok_or(format!("unreadable {name}"))?;
            runs.push(RunRecord::parse(v)?);
        }
    }
    Ok(runs)
}

/// The solver's constructor as the product's run options take it.
fn maker(s: Solver) -> fn() -> Box<dyn texopt::solve::FilmMethod> {
    match s {
        Solver::Direct => || Solver::Direct.build(),
        Solver::Reference => || Solver::Reference.build(),
        Solver::Multigrid => || Solver::Multigrid.build(),
        Solver::PtMultigrid => || Solver::PtMultigrid.build(),
        Solver::GaussSeidel => || Solver::GaussSeidel.build(),
    }
}

/// `case` to its periodic regime on `num` (a coarse approach on the direct solver, when the
/// numerics ask for one), `solver` on the numerics' own mesh; the observers see every window
/// and step.
pub fn run_case(
    case: &CaseSpec,
    num: &Numerics,
    solver: Solver,
    on_window: &mut dyn FnMut(&Progress),
    on_step: &mut dyn FnMut(&Transient),
) -> Result<RunResult, String> {
    let opts = RunOptions {
        solver: Some(maker(solver)),
        ..RunOptions::default()
    };
    let mut watch = Watch {
        on_window: Some(on_window),
        on_step: Some(on_step),
    };
    simulate_with(case, num, &opts, &mut watch).map_err(|e| e.to_string())
}

/// A coarse approach written N1xN2@DT (as texopt's `--approach`).
pub fn parse_approach(s: &str) -> Result<texopt::time::Approach, String> {
    let bad = || format!("an approach is N1xN2@DT (e.g. 128x4@1.6e-3), not {s:?}");
    let (mesh, dt) = s.split_once('@').ok_or_else(bad)?;
    let (a, b) = mesh.split_once('x').ok_or_else(bad)?;
    Ok(texopt::time::Approach {
        n1: a.parse().map_err(|_| bad())?,
        n2: b.parse().map_err(|_| bad())?,
        dt: dt.parse().map_err(|_| bad())?,
    })
}

/// An approach as tables name it.
pub fn approach_name(a: &texopt::time::Approach) -> String {
    // A step given as a fraction (1/300) prints in four digits, not seventeen.
    let dt = match a.dt.to_string() {
        s if s.len() <= 8 => s,
        _ => format!("{:.3e}", a.dt),
    };
    format!("{}×{}@{dt}", a.n1, a.n2)
}

#[cfg(test)]
mod tests {
    use super::{approach_name, parse_approach};

    #[test]
    fn an_approach_reads_back_as_given_and_a_fraction_in_four_digits() {
        let given = parse_approach("128x4@1.6e-3").unwrap();
        assert_eq!(approach_name(&given), "128×4@0.0016");
        let third = parse_approach("120x4@3.3333333333333e-3").unwrap();
        assert_eq!(approach_name(&third), "120×4@3.333e-3");
        assert!(parse_approach("128x4").is_err());
    }
}
