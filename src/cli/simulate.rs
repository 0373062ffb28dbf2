//! `texopt simulate`: one case to its periodic regime, as a summary, JSON or a time series.

use std::io::{IsTerminal, Write};

use super::{flag, input_message, CmdError, ContactArgs, SimulateArgs};
use crate::model::asperity::{self, Asperity};
use crate::model::case::{bad, short, CaseSpec, InputError, Texture};
use crate::model::operating::Outside;
use crate::model::operating::{regime, Operating, Physical, Validity};
use crate::model::units::H_M;
use crate::snapshot::Recording;
use crate::time::limits::Kept;
use crate::time::{
    simulate_with, unresolved_depth, AnswerError, Approach, ErrorSource, Fidelity, Numerics,
    Outcome, Overrides, Progress, RunOptions, RunResult, SeriesRow, TimeScheme, Watch,
    DEEP_POCKET_RATIO, RESOLVED_DEEP_RATIO, UNCERTAINTY_FLOOR,
};

/// The case and numerics named by the flags, validated (errors name the flags).
pub fn case_from_args(a: &SimulateArgs) -> Result<(CaseSpec, Numerics), String> {
    let (case, num) = inputs(a).map_err(|e| input_message(&e, flag))?;
    let limits = a.limits.limits().map_err(|e| match e {
        CmdError::Input(m) | CmdError::Other(m) => m,
    })?;
    crate::time::limits::check(&case, &num, &limits).map_err(|e| limit_message(a, e))?;
    Ok((case, num))
}

/// A run-limit error in flag names; a mesh the tier chose says so (no --mesh was given).
fn limit_message(a: &SimulateArgs, mut e: InputError) -> String {
    if e.param == "mesh" && a.mesh.is_none() {
        e.value = format!("{} (--fidelity {}'s mesh)", e.value, a.fidelity.name());
    }
    input_message(&e, flag)
}

/// The run with what it keeps beside it (the recording of --snapshots/--animate, the time
/// series of --series) within --max-memory, checked before it starts; a note of the files
/// many instants make.
fn check_kept(
    a: &SimulateArgs,
    case: &CaseSpec,
    num: &Numerics,
    wanted: Option<&super::snapshots::Wanted>,
) -> Result<(), CmdError> {
    let mut kept = Vec::new();
    if let Some(w) = wanted {
        let m = crate::snapshot::memory(&w.request, case, num);
        if w.dir.is_some() {
            kept.push(Kept {
                param: "frames",
                value: w.request.frames.to_string(),
                what: format!(
                    "{} instants of the film and their pictures",
                    w.request.frames
                ),
                fix: "ask for fewer".into(),
                bytes: m.frames,
            });
        }
        if let Some(stride) = w.request.animation_stride.filter(|_| m.animation > 0.0) {
            kept.push(Kept {
                param: "animate_stride",
                value: stride.to_string(),
                what: "the animation's frames".into(),
                fix: "give a longer stride".into(),
                bytes: m.animation,
            });
        }
    }
    if let Some(path) = &a.series {
        let steps = crate::time::limits::estimate(case, num).steps;
        kept.push(Kept {
            param: "series",
            value: path.display().to_string(),
            what: format!("the time series of up to {} steps", short(steps)),
            fix: "use a larger --dt or a shorter --t-max".into(),
            bytes: steps * std::mem::size_of::<SeriesRow>() as f64,
        });
    }
    let limits = a.limits.limits()?;
    crate::time::limits::check_with(case, num, &limits, &kept)
        .map_err(|e| CmdError::Input(limit_message(a, e)))?;
    // More instants than the paper's ten: how many files they make, before a long run.
    if let Some((w, dir)) = wanted.and_then(|w| w.dir.as_ref().map(|d| (w, d))) {
        if w.request.frames > crate::snapshot::DEFAULT_FRAMES {
            eprintln!(
                "note: --frames {} writes {} files into {} (a CSV an instant, the history, an index and five pictures)",
                w.request.frames,
                crate::snapshot::files_written(w.request.frames),
                dir.display()
            );
        }
    }
    Ok(())
}

/// The case the flags describe and its numerics ([`crate::time::resolve`]), validated.
fn inputs(a: &SimulateArgs) -> Result<(CaseSpec, Numerics), InputError> {
    let mut case = CaseSpec::paper(a.r);
    case.theta_s = a.theta_s;
    let (op, validity) = a.operating.resolve()?;
    op.apply(&mut case);
    case.contact = contact(&a.contact, &validity)?;
    let depth = a.depth.unwrap_or(0.0);
    if !depth.is_finite() || depth < 0.0 {
        return Err(bad(
            "depth",
            depth,
            "must be a finite depth ≥ 0 µm (0 or absent: untextured)",
        ));
    }
    if depth > 0.0 {
        let need = |name: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                bad(
                    name,
                    "missing",
                    format!("a textured liner (--depth {depth}) needs --{name}"),
                )
            })
        };
        let l1 = need("l1", a.l1)?;
        let per = need("per", a.per)?;
        case.texture = Some(Texture {
            l1,
            l2: a.l2.unwrap_or(l1),
            per,
            width: a.width.unwrap_or(per),
            depth,
            phase: a.phase,
        });
    }
    let num = crate::time::resolve(a.fidelity, &given(a), &case);
    case.validate(a.allow_thick_pockets)?;
    num.validate(&case)?;
    Ok((case, num))
}

/// Each contact flag's field of [`Asperity`], its unit and that unit in SI (σ is
/// `--roughness`, in µm).
const CONTACT_UNITS: [(&str, &str, &str, f64); 6] = [
    ("sigma", "roughness", "µm", 1e-6),
    ("eta_beta_sigma", "eta_beta_sigma", "", 1.0),
    ("sigma_over_beta", "sigma_over_beta", "", 1.0),
    ("e_star", "e_star", "GPa", 1e9),
    ("tau0", "tau0", "MPa", 1e6),
    ("varsigma", "varsigma", "", 1.0),
];

/// The asperity contact the flags give (docs/model.md §11; σ the validity's roughness), None
/// with --no-contact; a constant out of its range is refused in the flag's own unit.
fn contact(c: &ContactArgs, validity: &Validity) -> Result<Option<Asperity>, InputError> {
    if c.no_contact {
        return Ok(None);
    }
    let d = Asperity::default();
    let a = Asperity {
        sigma: validity.roughness_um * H_M,
        eta_beta_sigma: c.eta_beta_sigma.unwrap_or(d.eta_beta_sigma),
        sigma_over_beta: c.sigma_over_beta.unwrap_or(d.sigma_over_beta),
        e_star: c.e_star.map_or(d.e_star, |gpa| gpa * 1e9),
        tau0: c.tau0.map_or(d.tau0, |mpa| mpa * 1e6),
        varsigma: c.varsigma.unwrap_or(d.varsigma),
    };
    let values = [
        a.sigma,
        a.eta_beta_sigma,
        a.sigma_over_beta,
        a.e_star,
        a.tau0,
        a.varsigma,
    ];
    for ((field, lo, hi), (v, (of, name, unit, si))) in asperity::RANGES
        .into_iter()
        .zip(values.into_iter().zip(CONTACT_UNITS))
    {
        debug_assert_eq!(field, of);
        if !(v.is_finite() && (lo..=hi).contains(&v)) {
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" {unit}")
            };
            return Err(bad(
                name,
                v / si,
                format!(
                    "must lie in {} to {}{unit} (docs/model.md §11); --no-contact runs without asperity contact",
                    short(lo / si),
                    short(hi / si),
                ),
            ));
        }
    }
    Ok(Some(a))
}

/// The numerics the flags give beside the tier.
fn given(a: &SimulateArgs) -> Overrides {
    Overrides {
        n1: a.mesh.map(|m| m.0),
        n2: a.mesh.map(|m| m.1),
        dt: a.dt,
        scheme: a.time_scheme,
        periodic_tol: a.periodic_tol,
        t_max: Some(a.t_max),
        solver: None,
        start: Some(a.start),
        accelerate: Some(!a.no_accelerate),
        approach: a.approach.map(|x| x.0),
    }
}

/// Rings at least this flat (cm) get a note when they run backward Euler (the `paper` tier, or
/// `--time-scheme backward-euler`) at a step above [`CONFORMAL_DT`]: its first-order
/// time-step error grows with R (Case I's pocket at 512×8, dt = 4e-4: 3 % at R = 51.2, against
/// 1 % with BDF2; docs/validation.md).
const CONFORMAL_R_CM: f64 = 10.0;
/// The backward-Euler step that keeps R = 51.2 within ≈ 0.7 % of its dt-converged answer.
const CONFORMAL_DT: f64 = 1e-4;

/// What a user should know of pockets far deeper than the film (docs/validation.md): the run
/// did not go on on the deep-pocket mesh (another tier, or `--mesh`), or did, but deeper
/// than that mesh is shown to resolve.
fn deep_pocket_note(depth: f64, o: &Outcome) {
    let ratio = depth / o.c_min;
    if o.deep_unsettled {
        eprintln!(
            "note: pockets {depth} µm deep against a least clearance of {:.2} µm (more than {DEEP_POCKET_RATIO}×): the run went on on the deep-pocket mesh, which did not reach its periodic regime within its allowance, so the answer is the run's own mesh's, whose error with pockets this deep is several % (docs/solver.md, \"Deep pockets\"); --mesh 600x24 with a larger --t-max runs that mesh alone",
            o.c_min
        );
    } else if o.deep_mesh.is_none() && unresolved_depth(depth, o.c_min) {
        eprintln!(
            "note: pockets {depth} µm deep against a least clearance of {:.2} µm (more than {DEEP_POCKET_RATIO}×): their rims are narrower than the cells, and the error grows to several % (20 µm on R = 3.2 on 700x8: f̄ +2.8 %, C_min −6.3 % against the converged answer; on 600x24 within 1 %; docs/validation.md); --fidelity fast without --mesh goes on on 600x24 by itself",
            o.c_min
        );
    } else if o.deep_mesh.is_some() && ratio > RESOLVED_DEEP_RATIO {
        eprintln!(
            "note: pockets {depth} µm deep against a least clearance of {:.2} µm ({ratio:.0}×): the deep-pocket mesh is shown within 1 % up to {RESOLVED_DEEP_RATIO}×; deeper, its answer is nearer than 8 cells across give but can still be several % off, more with small pockets: the uncertainty measured on this answer (\"known to\" below, docs/validation.md) says how far",
            o.c_min
        );
    }
}

/// Cells across from which `simulate` says that N2 was raised for the pockets: the tiers
/// have 8–32, and a band that wide makes every step dear.
const HEAVY_N2: usize = 64;

/// What became of the coarse approach asked for, when the run does not take it as given: it
/// is dropped where it would be no cheaper than the run itself (or cannot run the case), and
/// taken with N2 raised to resolve the pockets, the step capped at the characteristic one or
/// nothing finer than the run's own.
fn approach_note(asked: Approach, used: Option<&Numerics>) -> Option<String> {
    let name = format!("{}x{}@{}", asked.n1, asked.n2, short(asked.dt));
    match used {
        None => Some(format!(
            "--approach {name} is not used: it would be no cheaper than the run's own mesh and step, or cannot run this case; the run starts on its own mesh"
        )),
        Some(c) if (c.n1, c.n2, c.dt) != (asked.n1, asked.n2, asked.dt) => Some(format!(
            "--approach {name} runs as {}x{}@{} (N2 raised to put 2 cells across a pocket, the step at most the characteristic one, nothing finer than the run's own)",
            c.n1,
            c.n2,
            short(c.dt)
        )),
        Some(_) => None,
    }
}

/// Notes on what the run makes of the flags (before it starts): a large N2 raised for the
/// pockets, a coarse approach not taken as given, pocket flags of an untextured liner, a
/// conformal ring's time-step error.
fn input_notes(a: &SimulateArgs, case: &CaseSpec, num: &Numerics) {
    let width = case.texture.as_ref().map_or(0.0, |t| t.width);
    let cells = a.fidelity.pocket_cells();
    match a.mesh {
        None if num.n2 >= HEAVY_N2 => eprintln!(
            "note: {} cells across (N2 raised to put {cells} across each pocket of the {width} cm wide texture cell): a heavy run",
            num.n2
        ),
        Some((n1, n2)) if num.n2 > n2 => eprintln!(
            "note: --mesh {n1}x{n2} runs as {n1}x{} (N2 raised to put {cells} cells across each pocket of the {width} cm wide texture cell, as studies and the optimiser do)",
            num.n2
        ),
        _ => {}
    }
    if let (Some(super::args::ApproachArg(Some(asked))), Some(_)) = (a.approach, &case.texture) {
        if let Some(note) = approach_note(asked, num.approach_numerics(case).as_ref()) {
            eprintln!("note: {note}");
        }
    }
    let c = &a.contact;
    if c.no_contact
        && [
            c.eta_beta_sigma,
            c.sigma_over_beta,
            c.e_star,
            c.tau0,
            c.varsigma,
        ]
        .iter()
        .any(Option::is_some)
    {
        eprintln!("note: --no-contact: the asperity contact flags are not used");
    }
    if case.texture.is_none()
        && (a.l1.is_some() || a.per.is_some() || a.l2.is_some() || a.width.is_some())
    {
        eprintln!("note: --depth is 0 or absent, so the liner is untextured; the pocket flags are not used");
    }
    if case.texture.is_some()
        && case.r >= CONFORMAL_R_CM
        && num.dt > CONFORMAL_DT
        && num.scheme == TimeScheme::BackwardEuler
    {
        eprintln!(
            "note: R = {} cm is a conformal ring, where backward Euler's time step sets the error: dt = {:.0e} can be several % off in f and C_min; --time-scheme bdf2 (the default of every tier but paper) or --dt {CONFORMAL_DT:.0e} keeps it near 1 % (docs/validation.md)",
            case.r, num.dt
        );
    }
}

/// The flags a steady (untextured, not transient) run does not use, said.
fn steady_note(a: &SimulateArgs) {
    let unused: Vec<&str> = [
        (a.dt.is_some(), "--dt"),
        (a.time_scheme.is_some(), "--time-scheme"),
        (a.approach.is_some(), "--approach"),
        (a.mesh.is_some(), "--mesh's N2"),
        (a.phase != 0.0, "--phase"),
    ]
    .into_iter()
    .filter_map(|(given, name)| given.then_some(name))
    .collect();
    if !unused.is_empty() {
        eprintln!(
            "note: the untextured liner is solved as a steady 1D force balance on N1 cells: {} not used (--transient runs the 2D transient)",
            unused.join(", ")
        );
    }
}

fn mesh_name((n1, n2): (usize, usize)) -> String {
    format!("{n1}x{n2}")
}

pub(super) fn run(a: &SimulateArgs) -> Result<i32, CmdError> {
    let (case, num) = case_from_args(a).map_err(CmdError::Input)?;
    let (op, validity) = a.operating.resolve()?;
    input_notes(a, &case, &num);
    let wanted = super::snapshots::wanted(
        a.snapshots.as_deref(),
        a.frames,
        a.animate.as_deref(),
        a.animate_stride,
        &case,
        &num,
    )?;
    check_kept(a, &case, &num, wanted.as_ref())?;
    let transient = case.texture.is_some() || a.transient || wanted.is_some();
    if !transient {
        steady_note(a);
    }
    if let Some(path) = &a.series {
        check_series(path, transient)?;
    }

    let (result, recording) = solve(a, &case, &num, &op, transient, wanted.as_ref())?;
    let RunResult {
        outcome, series, ..
    } = result;
    print_result(a, &case, &num, &op, &validity, &outcome)?;
    if let Some(t) = case.texture.as_ref() {
        deep_pocket_note(t.depth, &outcome);
    }
    // The series is written after the result is printed: a full disk loses the file, not
    // the answer.
    if let (Some(path), Some(rows)) = (&a.series, &series) {
        if let Err(e) = write_series(path, rows, op.scales().time_ms()) {
            eprintln!("error: --series: {e}");
            return Ok(1);
        }
    }
    if let (Some(w), Some(rec)) = (&wanted, &recording) {
        if let Err(e) = super::snapshots::write(w, &case, op.scales(), rec) {
            eprintln!("error: --snapshots/--animate: {e}");
            return Ok(1);
        }
    }
    if !outcome.converged {
        eprintln!(
            "warning: the periodic regime was not reached by t = {} (the end of the first averaging window past --t-max {}; estimated error {:.1e} > tolerance {:.1e}); the numbers above are not final. Raise --t-max or loosen --periodic-tol.",
            short(outcome.t_end), short(num.t_max), outcome.periodic_error, num.periodic_tol
        );
        return Ok(1);
    }
    Ok(0)
}

/// The run itself, its progress on stderr, and the recording that --snapshots/--animate
/// asked for.
fn solve(
    a: &SimulateArgs,
    case: &CaseSpec,
    num: &Numerics,
    op: &Operating,
    transient: bool,
    wanted: Option<&super::snapshots::Wanted>,
) -> Result<(RunResult, Option<Recording>), CmdError> {
    // On a terminal the line is redrawn every period; elsewhere (or beside --json output) a
    // plain line at most every `--progress-every` seconds, so that long runs in batch jobs
    // show that they advance without flooding the log.
    let show = std::io::stderr().is_terminal() && !a.json;
    let mut observe = progress(show, a.progress_every, op.scales().time_ms());
    let opts = RunOptions {
        series: a.series.is_some(),
        transient,
        ..RunOptions::default()
    };
    let ran = match wanted {
        Some(w) => {
            let (r, rec) =
                crate::snapshot::run_recorded(case, num, &opts, w.request, Some(&mut observe))
                    .map_err(|e| CmdError::Other(e.to_string()))?;
            (r, Some(rec))
        }
        None => {
            let mut watch = Watch {
                on_window: Some(&mut observe),
                on_step: None,
            };
            let r = simulate_with(case, num, &opts, &mut watch)
                .map_err(|e| CmdError::Other(e.to_string()))?;
            (r, None)
        }
    };
    if show && transient {
        eprintln!();
    }
    Ok(ran)
}

/// The progress line of each averaging window: redrawn in place when `redraw` (a terminal),
/// else printed at most every `every_s` seconds. `ms_per_t`: the time scale L/U in ms.
fn progress(redraw: bool, every_s: f64, ms_per_t: f64) -> impl FnMut(&Progress) {
    // Beyond what a Duration holds (1e300 s): never, as far as a run can tell.
    let every = std::time::Duration::try_from_secs_f64(every_s).unwrap_or(std::time::Duration::MAX);
    let began = std::time::Instant::now();
    let mut last_line = began;
    move |p: &Progress| {
        let line = format!(
            "  period {:4}  t = {:7.3} ms  f̄ = {:.5}  Z̄ = {:.4} µm  est. periodic error {:.1e}",
            p.period,
            p.t * ms_per_t,
            p.f_mean,
            p.z_mean,
            p.periodic_error
        );
        if redraw {
            eprint!("\r{line}   ");
            let _ = std::io::stderr().flush();
        } else if last_line.elapsed() >= every {
            last_line = std::time::Instant::now();
            eprintln!("{line}  ({:.0} s)", began.elapsed().as_secs_f64());
        }
    }
}

/// What `simulate` answers, as the guard over reports sees it.
#[derive(serde::Serialize)]
struct Answer<'a> {
    physical: &'a Physical,
    lambda_min: f64,
    #[serde(flatten)]
    outcome: &'a Outcome,
}

/// The run's answer on stdout: one JSON object with --json, else the summary and its
/// physical values.
fn print_result(
    a: &SimulateArgs,
    case: &CaseSpec,
    num: &Numerics,
    op: &Operating,
    validity: &Validity,
    outcome: &Outcome,
) -> Result<(), CmdError> {
    let physical = op.scales().physical(case, outcome.f_mean, outcome.c_min);
    let outside = validity.outside(case, outcome.c_min);
    let lambda = outcome.c_min / validity.roughness_um;
    let tier = (a.fidelity.f_error(), a.fidelity.c_error());
    let error = outcome
        .error(case, tier)
        .map_err(|e| CmdError::Other(e.to_string()))?;
    super::checked(&Answer {
        physical: &physical,
        lambda_min: lambda,
        outcome,
    })?;
    if a.json {
        let report = serde_json::json!({
            "inputs": { "case": case, "numerics": num, "mesh": mesh_name(outcome.mesh((num.n1, num.n2))),
                        "operating": op, "roughness_um": validity.roughness_um },
            "physical": physical,
            "outside_model": outside,
            "contact": case.contact.is_some(),
            "lambda_min": lambda,
            "regime": regime(lambda),
            "asperity_share": outcome.asperity_share,
            "f_boundary": outcome.f_boundary,
            "error": error,
        });
        let mut obj = report.as_object().cloned().unwrap_or_default();
        if let serde_json::Value::Object(o) = serde_json::to_value(outcome).unwrap_or_default() {
            obj.extend(o);
        }
        println!("{}", serde_json::Value::Object(obj));
    } else {
        // Times are in units of L/U, U the run's speed: 1 ms at 10 m/s (docs/model.md §1).
        print_summary(case, num, outcome, op.scales().time_ms());
        print_error(&error, a.fidelity);
        print_contact(case, validity, outcome);
        print_physical(op, &physical, outside);
    }
    Ok(())
}

/// How well the answer is known: the tier's stated error, or a deep-pocket answer's mesh
/// uncertainty (docs/validation.md, "Deep pockets: the measured uncertainty").
fn print_error(e: &AnswerError, fidelity: Fidelity) {
    let why = match e.source {
        ErrorSource::Tier => format!("the {} tier's stated error", fidelity.name()),
        ErrorSource::DeepMesh => format!(
            "pockets deeper than {DEEP_POCKET_RATIO}× C_min: twice the change on the mesh coarsened in both directions, at least {:.1} %; docs/validation.md",
            100.0 * UNCERTAINTY_FLOOR
        ),
    };
    println!(
        "  known to: f ± {:.2} %, C_min ± {:.2} % ({why})",
        100.0 * e.f_mean,
        100.0 * e.c_min
    );
}

/// The film parameter Λ = C_min/σ and its regime (docs/model.md §9), and what the asperities
/// carry (docs/model.md §11).
fn print_contact(case: &CaseSpec, validity: &Validity, o: &Outcome) {
    let lambda = o.c_min / validity.roughness_um;
    let film = format!(
        "film parameter Λ = C_min/σ = {lambda:.2} (σ = {} µm): {}",
        short(validity.roughness_um),
        regime(lambda)
    );
    match case.contact {
        Some(_) => println!(
            "  {film}; the asperities carry {:.2} % of the load, boundary friction {:.5} of f",
            100.0 * o.asperity_share,
            o.f_boundary
        ),
        None => println!("  {film}; no asperity contact (--no-contact)"),
    }
}

/// Whether `--series PATH` can be written: a transient run, an existing and writable
/// directory.
fn check_series(path: &std::path::Path, transient: bool) -> Result<(), CmdError> {
    if !transient {
        return Err(CmdError::Input(format!(
            "--series {}: an untextured liner is solved as a steady 1D problem with no time series; add --transient to run it as a 2D transient",
            path.display()
        )));
    }
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    if !dir.is_dir() {
        return Err(CmdError::Input(format!(
            "--series {}: the directory {} does not exist; create it or choose another path",
            path.display(),
            dir.display()
        )));
    }
    crate::output::check_writable(path)
        .map_err(|why| CmdError::Input(format!("--series {}: {why}", path.display())))
}

/// The series, with the time also in ms (`ms_per_t`: the time scale L/U, 1 ms at 10 m/s);
/// the asperity load and boundary friction (docs/model.md §11) as two more columns where the
/// asperities carried load at any step.
fn write_series(path: &std::path::Path, rows: &[SeriesRow], ms_per_t: f64) -> Result<(), String> {
    let contact = rows.iter().any(|r| r.w_a != 0.0 || r.f_boundary != 0.0);
    crate::output::write_with(path, |w| {
        write!(w, "t,t_ms,Z,W_h,f,f_couette,f_poiseuille,f_pressure")?;
        writeln!(w, "{}", if contact { ",W_a,f_boundary" } else { "" })?;
        for r in rows {
            write!(
                w,
                "{},{},{},{},{},{},{},{}",
                r.t,
                r.t * ms_per_t,
                r.z,
                r.w_h,
                r.f,
                r.f_couette,
                r.f_poiseuille,
                r.f_pressure
            )?;
            if contact {
                write!(w, ",{},{}", r.w_a, r.f_boundary)?;
            }
            writeln!(w)?;
        }
        Ok(())
    })
    .map_err(|e| e.to_string())
}

/// The operating point and the outcomes in physical units; a run outside the hydrodynamic
/// model says so beside them.
fn print_physical(op: &Operating, p: &Physical, outside: Option<Outside>) {
    println!(
        "  operating point: {} m/s, load {} N/m, {} Pa·s, ring {} mm wide of {} kg/m, oil supply {} µm: Stribeck number {:.3e}",
        op.speed_ms, op.load_n_per_m, op.viscosity_pas, op.ring_width_mm, op.ring_mass_kg_per_m, op.d_oil_um, p.stribeck
    );
    println!(
        "  friction force {:.4} N/m, friction power {:.3} W/m (per unit circumferential length)",
        p.friction_n_per_m, p.power_w_per_m
    );
    if let Some(why) = outside {
        println!("  OUTSIDE THE HYDRODYNAMIC MODEL: {why}; the figures above are not a prediction");
    }
}

fn print_summary(case: &CaseSpec, num: &Numerics, o: &Outcome, ms_per_t: f64) {
    let ring = if case.r.is_infinite() {
        "flat ring".to_string()
    } else {
        format!("ring face radius R = {} cm", short(case.r))
    };
    match &case.texture {
        None => println!("texopt simulate: {ring}, untextured liner"),
        Some(t) => println!(
            "texopt simulate: {ring}; pockets l1 = {} cm, l2 = {} cm, depth = {} µm on a {} × {} cm lattice (textured area {:.1} %)",
            short(t.l1),
            short(t.l2),
            short(t.depth),
            short(t.per),
            short(t.width),
            100.0 * t.area_fraction()
        ),
    }
    if o.method == "steady-1d" {
        println!("  steady 1D force balance on {} cells", num.n1);
    } else {
        let (n1, n2) = o.mesh((num.n1, num.n2));
        println!(
            "  transient on {}x{} cells, dt = {:.4e} ms: {} periods, {} steps, t = {:.3} ms; periodic regime {} (est. error {:.1e})",
            n1,
            n2,
            o.dt * ms_per_t,
            o.periods,
            o.steps,
            o.t_end * ms_per_t,
            if o.converged { "reached" } else { "NOT reached" },
            o.periodic_error
        );
        if o.deep_mesh.is_some() {
            println!(
                "  (the pockets ended deeper than {DEEP_POCKET_RATIO}× C_min on {}x{} cells, which do not resolve their rims: the run went on on {n1}x{n2}, the deep-pocket mesh, from there; the first {} steps were on the coarser meshes)",
                num.n1, num.n2, o.approach_steps
            );
        } else if let (true, Some(coarse)) = (o.approach_steps > 0, num.approach_numerics(case)) {
            println!(
                "  (the first {} steps on {}x{} cells at dt = {:.4e}, the coarse approach: the outcomes are those of the full mesh; --approach off to run every step on it)",
                o.approach_steps, coarse.n1, coarse.n2, coarse.dt * ms_per_t
            );
        }
    }
    println!(
        "  mean friction coefficient  f = {:.5}   (eq. 11; the paper prints f/10 = {:.6})",
        o.f_mean,
        o.f_mean / 10.0
    );
    println!(
        "    Couette {:.5}, Poiseuille {:.5}, pressure {:.5}",
        o.f_couette, o.f_poiseuille, o.f_pressure
    );
    println!(
        "  ring position Z: mean {:.4} µm, min {:.4} µm, max {:.4} µm",
        o.z_mean, o.z_min, o.z_max
    );
    println!("  minimum clearance C_min = {:.4} µm", o.c_min);
    if o.method == "steady-1d" {
        println!("  wall time {:.3} s", o.wall_time_s);
    } else {
        println!(
            "  wall time {:.2} s ({:.2} ms/step, {:.2} active-set iterations per step)",
            o.wall_time_s,
            1e3 * o.wall_time_s / o.steps.max(1) as f64,
            o.iterations_per_step
        );
    }
}
