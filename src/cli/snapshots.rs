//! `--snapshots DIR`, `--frames N` and `--animate FILE.gif`: the film of a run's last period,
//! checked before the run and written after it.

use std::path::{Path, PathBuf};

use super::CmdError;
use crate::model::case::CaseSpec;
use crate::model::operating::Scales;
use crate::snapshot::{self, Context, Recording, Request};
use crate::time::Numerics;

/// What a run is asked to record and where it goes.
pub(super) struct Wanted {
    pub request: Request,
    pub dir: Option<PathBuf>,
    pub gif: Option<PathBuf>,
}

/// The recording asked for by `--snapshots`, `--frames`, `--animate` and `--animate-stride`,
/// checked against the run and the file system before any simulation (exit 2 when not).
pub(super) fn wanted(
    dir: Option<&Path>,
    frames: usize,
    gif: Option<&Path>,
    stride: Option<usize>,
    case: &CaseSpec,
    num: &Numerics,
) -> Result<Option<Wanted>, CmdError> {
    if dir.is_none() && gif.is_none() {
        return Ok(None);
    }
    if stride == Some(0) {
        return Err(CmdError::Input(
            "--animate-stride = 0: must be at least 1 (time steps between frames)".into(),
        ));
    }
    let spp = snapshot::steps_in_period(case, num);
    let request = Request {
        frames,
        animation_stride: gif.map(|_| snapshot::animation_stride(spp, stride)),
    };
    snapshot::check_request(&request, case, num).map_err(|e| {
        CmdError::Input(match e {
            snapshot::RequestError::Frames { asked, .. } => format!("--frames = {asked}: {e}"),
            snapshot::RequestError::Stride { stride, .. } => {
                format!("--animate-stride = {stride}: {e}")
            }
        })
    })?;
    if let Some(d) = dir {
        snapshot::prepare_dir(d)
            .map_err(|e| CmdError::Input(format!("--snapshots {}: {e}", d.display())))?;
    }
    if let Some(g) = gif {
        snapshot::check_gif_path(g)
            .map_err(|e| CmdError::Input(format!("--animate {}: {e}", g.display())))?;
    }
    Ok(Some(Wanted {
        request,
        dir: dir.map(Path::to_path_buf),
        gif: gif.map(Path::to_path_buf),
    }))
}

/// Writes what `w` asked for from the recording of `case`; says where on stderr.
pub(super) fn write(
    w: &Wanted,
    case: &CaseSpec,
    scales: Scales,
    rec: &Recording,
) -> Result<(), String> {
    let cx = Context::new(case, scales, rec);
    if let Some(dir) = &w.dir {
        let written = snapshot::write_all(dir, rec, &cx).map_err(|e| e.to_string())?;
        eprintln!(
            "snapshots: {} instants of the last period, {} files in {}",
            rec.frames.len(),
            written.files.len(),
            written.dir.display()
        );
    }
    if let Some(gif) = &w.gif {
        snapshot::animate(gif, rec, &cx).map_err(|e| e.to_string())?;
        eprintln!(
            "animation: {} frames of the last period in {}",
            rec.animation.len(),
            gif.display()
        );
    }
    Ok(())
}
