//! `texopt._texopt`: the Rust side of `import texopt` (python/texopt/__init__.py is the
//! Python side). No second implementation: `simulate` reads its inputs through
//! [`texopt::api::SimulateInputs`] and answers with [`texopt::api::answer`], as `texopt
//! simulate` does; `cli` runs a command of the `texopt` program in this process
//! ([`texopt::cli::run_embedded`]), so studies, the optimiser and the engine cycle share the
//! program's checks, cache and files.
//!
//! Every computation runs with the GIL released, on a thread of its own, while the calling
//! thread waits and looks for Python's signals: Ctrl-C stops a study as it stops the program
//! (no new case starts; those running finish and are stored), then raises
//! KeyboardInterrupt. A panic never crosses into Python: it becomes a `TexoptError`.

use std::sync::mpsc::RecvTimeoutError;
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use texopt::api::{answer, SimulateInputs};
use texopt::model::case::{CaseSpec, InputError, Waiver};
use texopt::snapshot::{Frame, Recording, Request};
use texopt::time::{
    limits, simulate_with, texture_period, Fidelity, Numerics, RunOptions, RunResult, SeriesRow,
    Start, TimeScheme, Watch,
};

pyo3::create_exception!(
    _texopt,
    TexoptError,
    PyRuntimeError,
    "A texopt run failed; the message says why."
);

/// How often the waiting thread looks for Python's signals.
const POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a thread of its own with the GIL released; the calling thread looks for
/// Python's signals meanwhile. On Ctrl-C `on_interrupt` runs (a study stops starting cases),
/// the work is waited for, and the interrupt is raised. A panic becomes a `TexoptError`.
fn detached<T: Send>(
    py: Python<'_>,
    on_interrupt: impl Fn(),
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::scope(|s| {
        s.spawn(move || {
            let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
            let _ = tx.send(out);
        });
        let mut interrupted = None;
        // The answer is taken the moment it is sent; between polls, Python's signals. (The
        // receiver goes into the GIL-free wait and comes back: it is Send, not Sync.)
        let mut rx = rx;
        let out = loop {
            let (got, back) = py.detach(move || (rx.recv_timeout(POLL), rx));
            rx = back;
            match got {
                Ok(out) => break out,
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    break Err(Box::new("the worker ended without an answer") as Panic)
                }
            }
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    on_interrupt();
                    interrupted = Some(e);
                }
            }
        };
        if let Some(e) = interrupted {
            return Err(e);
        }
        out.map_err(|panic| {
            TexoptError::new_err(format!(
                "internal error (please report it): {}",
                panic_words(&panic)
            ))
        })
    })
}

type Panic = Box<dyn std::any::Any + Send>;

fn panic_words(p: &Panic) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}

/// An input error in the words of Python: the keyword, the value, the rule, and the keyword
/// that waives a rule that may be waived.
fn value_error(e: &InputError) -> PyErr {
    let waiver = match e.waiver {
        Some(Waiver::ThickPockets) => "; pass allow_thick_pockets=True to run anyway",
        Some(Waiver::MemoryLimit) => {
            "; texopt.simulate keeps the program's limits (8 GiB); give a coarser mesh"
        }
        Some(Waiver::StepLimit) => {
            "; texopt.simulate keeps the program's limits (1e7 steps); give a larger dt or t_max"
        }
        Some(Waiver::NoContact) => "; contact=False runs without asperity contact",
        None => "",
    };
    PyValueError::new_err(format!("{} = {}: {}{waiver}", e.param, e.value, e.rule))
}

/// A keyword's number, None where absent or None; a value that is not a number is refused
/// by name.
fn number(kw: &Bound<'_, PyDict>, name: &str) -> PyResult<Option<f64>> {
    match kw.get_item(name)? {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => v
            .extract::<f64>()
            .map(Some)
            .map_err(|_| PyValueError::new_err(format!("{name} = {}: must be a number", repr(&v)))),
    }
}

/// A keyword's True or False, `default` where absent or None.
fn flag(kw: &Bound<'_, PyDict>, name: &str, default: bool) -> PyResult<bool> {
    match kw.get_item(name)?.filter(|v| !v.is_none()) {
        None => Ok(default),
        Some(v) => v.extract::<bool>().map_err(|_| {
            PyValueError::new_err(format!("{name} = {}: must be True or False", repr(&v)))
        }),
    }
}

fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr().map_or_else(|_| "?".into(), |r| r.to_string())
}

/// A keyword naming one of a few choices (`fidelity="fast"`), read as the program reads it.
fn choice<T: serde::de::DeserializeOwned>(
    kw: &Bound<'_, PyDict>,
    name: &str,
    choices: &str,
) -> PyResult<Option<T>> {
    let Some(v) = kw.get_item(name)?.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let refuse =
        || PyValueError::new_err(format!("{name} = {}: must be one of {choices}", repr(&v)));
    let s: String = v.extract().map_err(|_| refuse())?;
    serde_json::from_value(serde_json::Value::String(s)).map_err(|_| refuse())
}

/// `mesh=(N1, N2)`: two whole numbers of cells.
fn mesh(kw: &Bound<'_, PyDict>) -> PyResult<Option<(usize, usize)>> {
    let Some(v) = kw.get_item("mesh")?.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let m: (usize, usize) = v.extract().map_err(|_| {
        PyValueError::new_err(format!(
            "mesh = {}: must be two whole numbers of cells (N1, N2), e.g. (700, 8)",
            repr(&v)
        ))
    })?;
    Ok(Some(m))
}

/// The keywords `texopt.simulate` knows (python/texopt/__init__.py names the same).
const KEYWORDS: [&str; 31] = [
    "R",
    "l1",
    "l2",
    "per",
    "width",
    "depth",
    "phase",
    "theta_s",
    "speed",
    "load",
    "viscosity",
    "ring_width",
    "ring_mass",
    "d_oil",
    "roughness",
    "contact",
    "eta_beta_sigma",
    "sigma_over_beta",
    "e_star",
    "tau0",
    "varsigma",
    "fidelity",
    "mesh",
    "dt",
    "time_scheme",
    "periodic_tol",
    "t_max",
    "start",
    "accelerate",
    "allow_thick_pockets",
    "transient",
];

/// The inputs the keywords name, as `texopt simulate` names them in its flags.
fn inputs(kw: &Bound<'_, PyDict>) -> PyResult<SimulateInputs> {
    for key in kw.keys() {
        let k: String = key.extract()?;
        if !KEYWORDS.contains(&k.as_str()) {
            return Err(PyTypeError::new_err(format!(
                "simulate() got an unexpected keyword argument '{k}'"
            )));
        }
    }
    let r = number(kw, "R")?.ok_or_else(|| {
        PyValueError::new_err(
            "R = missing: the ring face radius in cm is needed (inf: a flat ring)",
        )
    })?;
    let mut s = SimulateInputs::new(r);
    s.l1 = number(kw, "l1")?;
    s.l2 = number(kw, "l2")?;
    s.per = number(kw, "per")?;
    s.width = number(kw, "width")?;
    s.depth = number(kw, "depth")?;
    s.phase = number(kw, "phase")?.unwrap_or(s.phase);
    s.theta_s = number(kw, "theta_s")?.unwrap_or(s.theta_s);
    let o = &mut s.operating;
    o.speed = number(kw, "speed")?;
    o.load = number(kw, "load")?;
    o.viscosity = number(kw, "viscosity")?;
    o.ring_width = number(kw, "ring_width")?;
    o.ring_mass = number(kw, "ring_mass")?;
    o.d_oil = number(kw, "d_oil")?;
    o.roughness = number(kw, "roughness")?;
    let c = &mut s.contact;
    c.off = !flag(kw, "contact", !c.off)?;
    c.eta_beta_sigma = number(kw, "eta_beta_sigma")?;
    c.sigma_over_beta = number(kw, "sigma_over_beta")?;
    c.e_star = number(kw, "e_star")?;
    c.tau0 = number(kw, "tau0")?;
    c.varsigma = number(kw, "varsigma")?;
    s.fidelity =
        choice::<Fidelity>(kw, "fidelity", "draft, fast, paper, fine")?.unwrap_or(s.fidelity);
    s.mesh = mesh(kw)?;
    s.dt = number(kw, "dt")?;
    s.time_scheme =
        choice::<TimeScheme>(kw, "time_scheme", "characteristic, bdf2, backward-euler")?;
    s.periodic_tol = number(kw, "periodic_tol")?;
    s.t_max = number(kw, "t_max")?.unwrap_or(s.t_max);
    s.start = choice::<Start>(kw, "start", "equilibrium, paper")?.unwrap_or(s.start);
    s.accelerate = flag(kw, "accelerate", s.accelerate)?;
    s.allow_thick_pockets = flag(kw, "allow_thick_pockets", s.allow_thick_pockets)?;
    Ok(s)
}

/// Whether the run is the 2D transient: a textured liner, or one asked for (an untextured
/// liner is otherwise its steady 1D balance, as `texopt simulate` solves it).
fn transient(kw: &Bound<'_, PyDict>, case: &CaseSpec, frames: Option<usize>) -> PyResult<bool> {
    Ok(case.texture.is_some() || frames.is_some() || flag(kw, "transient", false)?)
}

/// What one run gives back before it becomes Python objects.
struct Ran {
    json: String,
    last_period: Vec<SeriesRow>,
    recording: Option<Recording>,
}

/// The run of `case` on `num`: its answer, the last period's series and, when `frames` is
/// given, that many instants of the film over the last period.
fn run(
    s: &SimulateInputs,
    case: &CaseSpec,
    num: &Numerics,
    frames: Option<usize>,
    (transient, progress): (bool, bool),
) -> Result<Ran, String> {
    let (op, validity) = s.operating.resolve().map_err(|e| e.to_string())?;
    let opts = RunOptions {
        series: transient,
        transient,
        ..RunOptions::default()
    };
    let mut observe = texopt::api::progress(
        false,
        if progress { 10.0 } else { f64::INFINITY },
        op.scales().time_ms(),
    );
    let (result, recording): (RunResult, Option<Recording>) = match frames {
        Some(n) => {
            let request = Request {
                frames: n,
                animation_stride: None,
            };
            let (r, rec) =
                texopt::snapshot::run_recorded(case, num, &opts, request, Some(&mut observe))
                    .map_err(|e| e.to_string())?;
            (r, Some(rec))
        }
        None => {
            let mut watch = Watch {
                on_window: Some(&mut observe),
                on_step: None,
            };
            (
                simulate_with(case, num, &opts, &mut watch).map_err(|e| e.to_string())?,
                None,
            )
        }
    };
    let ans = answer(case, num, (&op, &validity), s.fidelity, &result.outcome)
        .map_err(|e| e.to_string())?;
    let series = result.series.unwrap_or_default();
    let from = result.outcome.t_end - texture_period(case);
    let last_period: Vec<SeriesRow> = series.into_iter().filter(|r| r.t > from + 1e-9).collect();
    texopt::finite::check(&last_period)
        .map_err(|bad| format!("the time series' {bad} is not a finite number"))?;
    Ok(Ran {
        json: ans.json.to_string(),
        last_period,
        recording,
    })
}

/// `texopt.simulate`'s Rust half: the keywords → (the answer's JSON text, the last period's
/// series as columns, the film's frames or None).
#[pyfunction]
#[pyo3(signature = (kw, frames=None, progress=true))]
fn simulate<'py>(
    py: Python<'py>,
    kw: &Bound<'py, PyDict>,
    frames: Option<usize>,
    progress: bool,
) -> PyResult<(String, Bound<'py, PyDict>, Option<Bound<'py, PyList>>)> {
    let s = inputs(kw)?;
    if let Some(n) = frames.filter(|n| !(1..=100).contains(n)) {
        return Err(PyValueError::new_err(format!(
            "frames = {n}: must be 1 to 100 instants of the last period"
        )));
    }
    let (case, num) = s.case().map_err(|e| value_error(&e))?;
    limits::check(&case, &num, &texopt::time::Limits::default()).map_err(|e| value_error(&e))?;
    let transient = transient(kw, &case, frames)?;
    let ran = detached(
        py,
        || {},
        || run(&s, &case, &num, frames, (transient, progress)),
    )?
    .map_err(TexoptError::new_err)?;
    let series = columns(py, &ran.last_period)?;
    let frames = match &ran.recording {
        Some(rec) => Some(frame_list(py, rec)?),
        None => None,
    };
    Ok((ran.json, series, frames))
}

/// The series as named columns.
fn columns<'py>(py: Python<'py>, rows: &[SeriesRow]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let col = |f: fn(&SeriesRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
    d.set_item("t", col(|r| r.t))?;
    d.set_item("z", col(|r| r.z))?;
    d.set_item("w_h", col(|r| r.w_h))?;
    d.set_item("w_a", col(|r| r.w_a))?;
    d.set_item("f", col(|r| r.f))?;
    d.set_item("f_couette", col(|r| r.f_couette))?;
    d.set_item("f_poiseuille", col(|r| r.f_poiseuille))?;
    d.set_item("f_pressure", col(|r| r.f_pressure))?;
    d.set_item("f_boundary", col(|r| r.f_boundary))?;
    Ok(d)
}

/// The film's instants: per frame its time, phase, Z, W_h, f and the node fields p, θ, h
/// with their shape (N1 + 1, N2) and the node coordinates x1, x2 (cm).
fn frame_list<'py>(py: Python<'py>, rec: &Recording) -> PyResult<Bound<'py, PyList>> {
    let g = &rec.grid;
    let x1: Vec<f64> = (0..=g.n1).map(|i| g.x(i)).collect();
    let x2: Vec<f64> = (0..g.n2).map(|j| g.y(j)).collect();
    let list = PyList::empty(py);
    for f in &rec.frames {
        list.append(frame(py, f, (g.n1 + 1, g.n2), (&x1, &x2))?)?;
    }
    Ok(list)
}

fn frame<'py>(
    py: Python<'py>,
    f: &Frame,
    shape: (usize, usize),
    (x1, x2): (&[f64], &[f64]),
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("t", f.t)?;
    d.set_item("phase", f.phase)?;
    d.set_item("z", f.z)?;
    d.set_item("w_h", f.w_h)?;
    d.set_item("f", f.f)?;
    d.set_item("p", &f.p)?;
    d.set_item("theta", &f.theta)?;
    d.set_item("h", &f.h)?;
    d.set_item("shape", shape)?;
    d.set_item("x1", x1)?;
    d.set_item("x2", x2)?;
    Ok(d)
}

/// Runs the `texopt` command line `argv` in this process (program name first): returns the
/// exit code and the files written. A command line that does not parse, or input the command
/// refuses, raises ValueError; a failed run, TexoptError.
#[pyfunction]
fn cli(py: Python<'_>, argv: Vec<String>) -> PyResult<(i32, Vec<String>)> {
    use texopt::cli::{CmdError, Embedded};
    let ran = detached(py, texopt::cli::stop_embedded, || {
        texopt::cli::run_embedded(&argv)
    })?;
    match ran {
        Ok((code, files)) => Ok((
            code,
            files.iter().map(|p| p.display().to_string()).collect(),
        )),
        Err(Embedded::Usage(m)) | Err(Embedded::Failed(CmdError::Input(m))) => {
            Err(PyValueError::new_err(m))
        }
        Err(Embedded::Failed(CmdError::Other(m))) => Err(TexoptError::new_err(m)),
    }
}

/// Where `texopt study FILE` writes the study's table.
#[pyfunction]
fn study_table(file: std::path::PathBuf) -> PyResult<String> {
    let study = texopt::study::load(&file).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(texopt::study::report::table_path(&study)
        .display()
        .to_string())
}

#[pymodule]
fn _texopt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(cli, m)?)?;
    m.add_function(wrap_pyfunction!(study_table, m)?)?;
    m.add("TexoptError", m.py().get_type::<TexoptError>())?;
    m.add("KEYWORDS", KEYWORDS.to_vec())?;
    Ok(())
}
