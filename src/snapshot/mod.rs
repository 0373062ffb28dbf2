//! Fields of one run: the film under the ring at chosen instants of the last texture period
//! (pressure p, saturation θ, gap h), the ring's history over that period, and the files that
//! show them (maps, centre-line profiles, the history with the instants marked, an animation).
//!
//! The recorder is an observer of the run ([`crate::time::Observers::on_step`]): it keeps, for
//! each chosen phase of the texture period, the last step taken at that phase on the run's
//! own mesh. When the run stops at its periodic regime these are the instants of its last
//! period, so the pictures are of the state the outcomes describe, not of a rerun.

mod animate;
mod columns;
mod draw;
mod write;

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use crate::mesh::Grid;
use crate::model::case::CaseSpec;
use crate::model::operating::Scales;
use crate::output::OutputError;
use crate::time::{
    simulate_with, steps_per_period, texture_period, Numerics, Progress, RunOptions, RunResult,
    SeriesRow, SolveError, Transient, Watch,
};

pub use animate::animate;
pub use write::{write_all, SnapshotFiles};

/// Instants of the period drawn by default: the paper's ten (a–j, its Figs. 8–10).
pub const DEFAULT_FRAMES: usize = 10;

/// Most instants a recording draws: each is a CSV file and a panel of every picture, and
/// the pictures of the maps grow 135 pixels a frame (100 frames: 1300 × 13,600 pixels,
/// ≈ 53 MB to draw each).
pub const MAX_FRAMES: usize = 100;

/// Frames the animation keeps over a period unless a stride is given: enough for the pocket
/// to move smoothly, few enough for a GIF of a few hundred kB.
pub const ANIMATION_FRAMES: usize = 30;

/// Most frames an animation keeps: two minutes of GIF at its frame delay, each frame the
/// film's fields held in memory until the run ends.
pub const MAX_ANIMATION_FRAMES: usize = 1000;

/// Files [`write_all`] writes besides one CSV an instant: the history (CSV), the index
/// (JSON) and the pictures (three maps, the profiles, the history).
const OTHER_FILES: usize = 7;

/// Files [`write_all`] writes for `frames` instants.
pub fn files_written(frames: usize) -> usize {
    frames + OTHER_FILES
}

/// The film at one step.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Time of the step (units of L/U) and its phase within the texture period: the texture
    /// is placed at the phase (docs/model.md §2), so pocket centres sit at
    /// x1 = phase_cm + u·phase + k·per.
    pub t: f64,
    pub phase: f64,
    /// Ring position Z (µm), hydrodynamic load W_h (eq. 16) and friction coefficient f
    /// (eq. 11) at the step.
    pub z: f64,
    pub w_h: f64,
    pub f: f64,
    /// Per node (i·n2 + j): pressure (units of 6μUL/H²), saturation θ = φ/h and gap h (µm).
    pub p: Vec<f64>,
    pub theta: Vec<f64>,
    pub h: Vec<f64>,
}

impl Frame {
    fn of(t: &Transient) -> Self {
        let (g, gap, z) = (&t.scene().grid, &t.scene().gap, t.ring_state().z);
        let h: Vec<f64> = (0..g.nodes()).map(|k| gap.h(g, k, z)).collect();
        let theta = t
            .state()
            .phi
            .iter()
            .zip(&h)
            .map(|(phi, h)| phi / h)
            .collect();
        Frame {
            t: t.t(),
            phase: (t.steps() % t.steps_per_period()) as f64 * t.dt(),
            z,
            w_h: t.last().w_h,
            f: t.friction().total(),
            p: t.state().p.clone(),
            theta,
            h,
        }
    }
}

/// What the recorder asks for: `frames` instants of the period, and every `stride`-th step
/// of it for an animation (None: no animation).
#[derive(Clone, Copy, Debug)]
pub struct Request {
    pub frames: usize,
    pub animation_stride: Option<usize>,
}

/// Keeps the last period's frames, animation frames and history of a run (see the module
/// text). Feed it every step with [`Recorder::observe`]; read it with [`Recorder::finish`].
pub struct Recorder {
    request: Request,
    /// The mesh of the steps kept: a step on another (a coarse approach) starts afresh.
    grid: Option<Grid>,
    steps_per_period: usize,
    frames: Vec<Option<Frame>>,
    animation: Vec<Option<Frame>>,
    history: VecDeque<SeriesRow>,
}

/// The recorded last period of a run, ready to write.
pub struct Recording {
    pub grid: Grid,
    /// The texture period (units of L/U) and the time of the last step.
    pub period: f64,
    pub t_end: f64,
    /// Frames by increasing time, all within (t_end − period, t_end].
    pub frames: Vec<Frame>,
    pub animation: Vec<Frame>,
    /// Every step of the last period.
    pub history: Vec<SeriesRow>,
}

impl Recorder {
    pub fn new(request: Request) -> Self {
        Recorder {
            request,
            grid: None,
            steps_per_period: 0,
            frames: Vec::new(),
            animation: Vec::new(),
            history: VecDeque::new(),
        }
    }

    /// Takes one step of the run.
    pub fn observe(&mut self, t: &Transient) {
        if self.grid.as_ref() != Some(&t.scene().grid)
            || self.steps_per_period != t.steps_per_period()
        {
            self.restart(t);
        }
        let spp = self.steps_per_period;
        let slot = t.steps() % spp;
        if let Some(k) = frame_index(slot, spp, self.request.frames) {
            self.frames[k] = Some(Frame::of(t));
        }
        if let Some(stride) = self.request.animation_stride {
            if slot.is_multiple_of(stride) {
                self.animation[slot / stride] = Some(Frame::of(t));
            }
        }
        if self.history.len() == spp {
            self.history.pop_front();
        }
        self.history.push_back(t.row());
    }

    fn restart(&mut self, t: &Transient) {
        let spp = t.steps_per_period();
        self.grid = Some(t.scene().grid.clone());
        self.steps_per_period = spp;
        self.frames = vec![None; self.request.frames];
        let slots = self.request.animation_stride.map_or(0, |s| spp.div_ceil(s));
        self.animation = vec![None; slots];
        self.history.clear();
    }

    /// The last period recorded; an error if the run took less than a period on its mesh.
    pub fn finish(self, dt: f64) -> Result<Recording, SnapshotError> {
        let grid = self.grid.ok_or(SnapshotError::NoStep)?;
        let collect = |v: Vec<Option<Frame>>| -> Option<Vec<Frame>> {
            let mut f: Vec<Frame> = v.into_iter().collect::<Option<_>>()?;
            f.sort_by(|a, b| a.t.total_cmp(&b.t));
            Some(f)
        };
        let frames = collect(self.frames).ok_or(SnapshotError::Incomplete)?;
        let animation = collect(self.animation).ok_or(SnapshotError::Incomplete)?;
        let history: Vec<SeriesRow> = self.history.into();
        let t_end = history.last().map_or(0.0, |r| r.t);
        Ok(Recording {
            grid,
            period: self.steps_per_period as f64 * dt,
            t_end,
            frames,
            animation,
            history,
        })
    }
}

/// The frame a step at phase `slot` of `spp` fills, if any: frame k at the step nearest
/// to (k + 1)/n of the period, so that the n frames divide the period evenly and the last
/// is its end.
fn frame_index(slot: usize, spp: usize, n: usize) -> Option<usize> {
    (0..n).find(|&k| ((k + 1) * spp).div_ceil(n) % spp == slot)
}

/// The animation stride for `spp` steps a period: `requested`, or about
/// [`ANIMATION_FRAMES`] frames.
pub fn animation_stride(spp: usize, requested: Option<usize>) -> usize {
    requested.unwrap_or(spp.div_ceil(ANIMATION_FRAMES)).max(1)
}

/// The frame label of the k-th instant: a, b, c, … as in the paper's figures.
pub fn label(k: usize) -> String {
    if k < 26 {
        char::from(b'a' + k as u8).to_string()
    } else {
        format!("#{}", k + 1)
    }
}

/// Steps a texture period of `case` takes at `num`'s step: the most frames a period has.
pub fn steps_in_period(case: &CaseSpec, num: &Numerics) -> usize {
    steps_per_period(texture_period(case), num.dt) as usize
}

/// A request the run cannot fill, or that would keep too much.
#[derive(Clone, Debug, PartialEq)]
pub enum RequestError {
    /// Frames outside 1..=most (the period's steps, at most [`MAX_FRAMES`]).
    Frames {
        asked: usize,
        most: usize,
        steps: usize,
    },
    /// A stride of 0, or one that gives more than [`MAX_ANIMATION_FRAMES`] frames.
    Stride {
        stride: usize,
        frames: usize,
        steps: usize,
    },
}

impl std::fmt::Display for RequestError {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match *self {
            RequestError::Frames { most, steps, .. } => write!(
                f,
                "a texture period here takes {steps} steps, and at most {MAX_FRAMES} instants are drawn: ask for 1 to {most} frames"
            ),
            RequestError::Stride { stride: 0, .. } => {
                write!(f, "an animation stride of 0 steps: give 1 (every step) or more")
            }
            RequestError::Stride { frames, steps, .. } => write!(
                f,
                "gives {frames} animation frames over the {steps}-step period, more than an animation keeps ({MAX_ANIMATION_FRAMES}): give a stride of at least {} steps",
                steps.div_ceil(MAX_ANIMATION_FRAMES)
            ),
        }
    }
}

/// Checks `request` against the run before it starts: 1 to [`MAX_FRAMES`] frames, no more
/// than the period has steps; an animation stride of at least 1 step giving at most
/// [`MAX_ANIMATION_FRAMES`] frames.
pub fn check_request(
    request: &Request,
    case: &CaseSpec,
    num: &Numerics,
) -> Result<(), RequestError> {
    let steps = steps_in_period(case, num);
    let most = steps.min(MAX_FRAMES);
    if request.frames == 0 || request.frames > most {
        return Err(RequestError::Frames {
            asked: request.frames,
            most,
            steps,
        });
    }
    if let Some(stride) = request.animation_stride {
        let frames = if stride == 0 {
            0
        } else {
            steps.div_ceil(stride)
        };
        if stride == 0 || frames > MAX_ANIMATION_FRAMES {
            return Err(RequestError::Stride {
                stride,
                frames,
                steps,
            });
        }
    }
    Ok(())
}

/// Memory a recording of `request` holds (bytes), estimated before the run as
/// [`crate::time::limits::estimate`] estimates the run's: the drawn instants with the
/// largest picture of them (the maps), and the animation's frames. Each frame keeps three
/// numbers a node (p, θ, h) of the largest mesh the run may end on (a deep-pocket mesh), and
/// the history one row a step of its longest period.
pub fn memory(request: &Request, case: &CaseSpec, num: &Numerics) -> Memory {
    let meshes =
        std::iter::once((num.n1, num.n2, num.dt)).chain(num.deep.map(|d| (d.n1, d.n2, d.dt)));
    let (nodes, steps) = meshes.fold((0.0f64, 0.0f64), |(nodes, steps), (n1, n2, dt)| {
        let spp = steps_per_period(texture_period(case), dt);
        (nodes.max((n1 as f64 + 1.0) * n2 as f64), steps.max(spp))
    });
    let frame = std::mem::size_of::<Frame>() as f64 + 3.0 * 8.0 * nodes;
    let (rows, _) = draw::maps_grid(request.frames);
    let picture = 3.0 * draw::MAPS_WIDTH as f64 * draw::maps_height(rows) as f64;
    let history = steps * std::mem::size_of::<SeriesRow>() as f64;
    let animation = request
        .animation_stride
        .map_or(0.0, |s| (steps / s.max(1) as f64).ceil() * frame);
    Memory {
        frames: request.frames as f64 * frame + picture + history,
        animation,
    }
}

/// What [`memory`] estimates (bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Memory {
    /// The drawn instants, the largest picture of them and the period's history.
    pub frames: f64,
    /// The animation's frames.
    pub animation: f64,
}

/// Runs `case` to its periodic regime as [`simulate_with`] does with `opts` (as a 2D
/// transient, whatever the liner), recording its last period; `on_window` sees the progress.
pub fn run_recorded(
    case: &CaseSpec,
    num: &Numerics,
    opts: &RunOptions,
    request: Request,
    mut on_window: Option<&mut dyn FnMut(&Progress)>,
) -> Result<(RunResult, Recording), SnapshotError> {
    let mut recorder = Recorder::new(request);
    let mut on_step = |t: &Transient| recorder.observe(t);
    let mut progress = |p: &Progress| {
        if let Some(f) = on_window.as_mut() {
            f(p)
        }
    };
    let mut watch = Watch {
        on_window: Some(&mut progress),
        on_step: Some(&mut on_step),
    };
    let opts = RunOptions {
        transient: true,
        ..opts.clone()
    };
    let result = simulate_with(case, num, &opts, &mut watch)?;
    let recording = recorder.finish(result.outcome.dt)?;
    Ok((result, recording))
}

/// What the pictures need beyond the fields: the case (ring, texture), the scales to
/// physical units, and the mesh's ring columns.
pub struct Context<'a> {
    pub case: &'a CaseSpec,
    pub scales: Scales,
    pub ring: Vec<bool>,
}

impl<'a> Context<'a> {
    /// The context of a recording of `case` at `scales`.
    pub fn new(case: &'a CaseSpec, scales: Scales, rec: &Recording) -> Self {
        let contact = case.contact();
        let ring = (0..=rec.grid.n1)
            .map(|i| contact.under_ring(rec.grid.x(i)))
            .collect();
        Context { case, scales, ring }
    }
}

/// The directory for the snapshot files: created if missing, and a file must be creatable in
/// it, checked before any simulation so that a long run does not end unable to write.
pub fn prepare_dir(dir: &Path) -> Result<(), SnapshotError> {
    if dir.exists() && !dir.is_dir() {
        return Err(SnapshotError::NotADirectory(dir.to_path_buf()));
    }
    std::fs::create_dir_all(dir).map_err(|source| SnapshotError::CreateDir {
        dir: dir.to_path_buf(),
        source,
    })?;
    Ok(crate::output::check_writable(&dir.join("snapshots.json"))?)
}

/// Whether `path` can take the animation (its directory exists and is writable, the name
/// ends in .gif).
pub fn check_gif_path(path: &Path) -> Result<(), SnapshotError> {
    let gif = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gif"));
    if !gif {
        return Err(SnapshotError::NotGif);
    }
    Ok(crate::output::check_writable(path)?)
}

/// Why snapshots were not recorded or written.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    #[error("the run took no step to record")]
    NoStep,
    #[error("the run took less than a texture period on its own mesh")]
    Incomplete,
    #[error("no animation frames were recorded")]
    NoAnimation,
    #[error(transparent)]
    Run(#[from] SolveError),
    #[error("{} exists and is not a directory", .0.display())]
    NotADirectory(PathBuf),
    #[error("cannot create {}: {source}", dir.display())]
    CreateDir {
        dir: PathBuf,
        source: std::io::Error,
    },
    #[error("the animation is a GIF: give a file name ending in .gif")]
    NotGif,
    #[error(transparent)]
    Output(#[from] OutputError),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_animation_is_a_gif_whatever_the_case_of_its_extension() {
        let dir = std::env::temp_dir();
        for ok in ["a.gif", "A.GIF", "b.Gif"] {
            assert!(check_gif_path(&dir.join(ok)).is_ok(), "{ok}");
        }
        for bad in ["a.png", "gif", "a.gif.txt"] {
            assert!(check_gif_path(&dir.join(bad)).is_err(), "{bad}");
        }
    }

    #[test]
    fn frames_divide_the_period_evenly_and_end_at_its_end() {
        let slots: Vec<usize> = (0..150).filter_map(|s| frame_index(s, 150, 10)).collect();
        assert_eq!(slots.len(), 10);
        let at: Vec<usize> = (0..150)
            .filter(|&s| frame_index(s, 150, 10).is_some())
            .collect();
        assert_eq!(at, vec![0, 15, 30, 45, 60, 75, 90, 105, 120, 135]);
        assert_eq!(
            frame_index(0, 150, 10),
            Some(9),
            "the last frame ends the period"
        );
        // Uneven: 7 steps, 3 frames, at phases 3, 5 and 0 (= 7).
        let at: Vec<usize> = (0..7).filter(|&s| frame_index(s, 7, 3).is_some()).collect();
        assert_eq!(at, vec![0, 3, 5]);
    }

    #[test]
    fn the_animation_stride_keeps_about_thirty_frames() {
        assert_eq!(animation_stride(150, None), 5);
        assert_eq!(animation_stride(20, None), 1);
        assert_eq!(animation_stride(150, Some(1)), 1);
    }
}
