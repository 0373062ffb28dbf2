//! The snapshot files: each frame's fields as CSV, the history of the period as CSV, an
//! index as JSON, and the pictures ([`super::draw`]).

use std::path::{Path, PathBuf};

use super::columns::{shown_columns, Units};
use super::{draw, label, Context, Recording, SnapshotError};
use crate::output::OutputError;

/// The files written.
pub struct SnapshotFiles {
    pub dir: PathBuf,
    pub files: Vec<PathBuf>,
}

/// Writes every snapshot file of `rec` into `dir` (which [`super::prepare_dir`] checked).
pub fn write_all(
    dir: &Path,
    rec: &Recording,
    cx: &Context,
) -> Result<SnapshotFiles, SnapshotError> {
    let u = Units::of(cx);
    let mut files = Vec::new();
    for (k, f) in rec.frames.iter().enumerate() {
        let path = dir.join(format!("fields_{}.csv", label(k)));
        frame_csv(&path, rec, cx, &u, f)?;
        files.push(path);
    }
    let path = dir.join("history.csv");
    history_csv(&path, rec, &u)?;
    files.push(path);
    let path = dir.join("snapshots.json");
    crate::output::write(&path, index_json(rec, cx, &u).to_string() + "\n")?;
    files.push(path);
    files.extend(draw::pictures(dir, rec, cx)?);
    Ok(SnapshotFiles {
        dir: dir.to_path_buf(),
        files,
    })
}

fn frame_csv(
    path: &Path,
    rec: &Recording,
    cx: &Context,
    u: &Units,
    f: &super::Frame,
) -> Result<(), OutputError> {
    let g = &rec.grid;
    crate::output::write_with(path, |w| {
        writeln!(w, "x1_mm,x2_mm,under_ring,p_mpa,theta,h_um")?;
        for i in shown_columns(rec, cx) {
            for j in 0..g.n2 {
                let k = g.idx(i, j);
                writeln!(
                    w,
                    "{:.8},{:.8},{},{:.6e},{:.6},{:.6}",
                    g.x(i) * u.mm_per_cm,
                    g.y(j) * u.mm_per_cm,
                    u8::from(cx.ring[i]),
                    f.p[k] * u.mpa,
                    f.theta[k],
                    f.h[k]
                )?;
            }
        }
        Ok(())
    })
}

fn history_csv(path: &Path, rec: &Recording, u: &Units) -> Result<(), OutputError> {
    let frame_at = |t: f64| rec.frames.iter().position(|f| f.t == t);
    crate::output::write_with(path, |w| {
        writeln!(w, "t_ms,z_um,f,w_h_n_per_m,frame")?;
        for r in &rec.history {
            writeln!(
                w,
                "{},{},{},{},{}",
                r.t * u.ms,
                r.z,
                r.f,
                r.w_h * u.n_per_m,
                frame_at(r.t).map_or(String::new(), label)
            )?;
        }
        Ok(())
    })
}

fn index_json(rec: &Recording, cx: &Context, u: &Units) -> serde_json::Value {
    let (a, b) = cx.case.contact().ring_edges();
    let min_sag = cx.case.contact().ring.min_sag_um();
    let frames: Vec<_> = rec
        .frames
        .iter()
        .enumerate()
        .map(|(k, f)| {
            serde_json::json!({
                "label": label(k),
                "file": format!("fields_{}.csv", label(k)),
                "t_ms": f.t * u.ms,
                "phase_ms": f.phase * u.ms,
                "z_um": f.z,
                "clearance_um": f.z + min_sag,
                "w_h_n_per_m": f.w_h * u.n_per_m,
                "f": f.f,
            })
        })
        .collect();
    serde_json::json!({
        "case": cx.case,
        "mesh": format!("{}x{}", rec.grid.n1, rec.grid.n2),
        "simulated_width_mm": rec.grid.width * u.mm_per_cm,
        "ring_edges_mm": [a * u.mm_per_cm, b * u.mm_per_cm],
        "period_ms": rec.period * u.ms,
        "t_end_ms": rec.t_end * u.ms,
        "units": {
            "x1, x2": "mm (x2 across the simulated half cell; the pocket's centre line is its upper edge)",
            "p": "MPa", "h, z, clearance": "µm", "t, phase": "ms", "w_h": "N/m of circumference",
            "f": "friction coefficient (eq. 11)",
        },
        "w_h_quadrature": "W_h = (1/B)·Σ p·dx1·dx2 over the nodes under the ring (eq. 16): the fields' nodal sum",
        "frames": frames,
    })
}
