//! `texopt simulate`: one case to its periodic regime, as a summary, JSON or a time series.

use std::io::IsTerminal;

use super::{flag, input_message, CmdError, SimulateArgs};
use crate::api::{ContactInputs, SimulateInputs};
use crate::model::case::{short, CaseSpec, InputError};
use crate::model::operating::Outside;
use crate::model::operating::{regime, Operating, Physical, Validity};
use crate::snapshot::Recording;
use crate::time::limits::Kept;
use crate::time::{
    simulate_with, unresolved_depth, AnswerError, Approach, ErrorSource, Fidelity, Numerics,
    Outcome, RunOptions, RunResult, SeriesRow, TimeScheme, Watch, DEEP_POCKET_RATIO,
    RESOLVED_DEEP_RATIO, UNCERTAINTY_FLOOR,
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

/// The case the flags describe and its numerics, validated ([`SimulateInputs::case`]).
fn inputs(a: &SimulateArgs) -> Result<(CaseSpec, Numerics), InputError> {
    named_inputs(a).case()
}

/// The flags as the library names its inputs.
fn named_inputs(a: &SimulateArgs) -> SimulateInputs {
    let c = &a.contact;
    SimulateInputs {
        r: a.r,
        l1: a.l1,
        l2: a.l2,
        per: a.per,
        width: a.width,
        depth: a.depth,
        phase: a.phase,
        theta_s: a.theta_s,
        operating: a.operating.inputs(),
        contact: ContactInputs {
            off: c.no_contact,
            eta_beta_sigma: c.eta_beta_sigma,
            sigma_over_beta: c.sigma_over_beta,
            e_star: c.e_star,
            tau0: c.tau0,
            varsigma: c.varsigma,
        },
        fidelity: a.fidelity,
        mesh: a.mesh,
        dt: a.dt,
        time_scheme: a.time_scheme,
        periodic_tol: a.periodic_tol,
        t_max: a.t_max,
        start: a.start,
        accelerate: !a.no_accelerate,
        approach: a.approach.map(|x| x.0),
        allow_thick_pockets: a.allow_thick_pockets,
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
    let mut observe = crate::api::progress(show, a.progress_every, op.scales().time_ms());
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

/// The run's answer on stdout: one JSON object with --json ([`crate::api::answer`]), else
/// the summary and its physical values.
fn print_result(
    a: &SimulateArgs,
    case: &CaseSpec,
    num: &Numerics,
    op: &Operating,
    validity: &Validity,
    outcome: &Outcome,
) -> Result<(), CmdError> {
    let ans = crate::api::answer(case, num, (op, validity), a.fidelity, outcome)
        .map_err(|e| CmdError::Other(e.to_string()))?;
    if a.json {
        println!("{}", ans.json);
    } else {
        // Times are in units of L/U, U the run's speed: 1 ms at 10 m/s (docs/model.md §1).
        print_summary(case, num, outcome, op.scales().time_ms());
        print_error(&ans.error, a.fidelity);
        print_contact(case, validity, outcome);
        print_physical(op, &ans.physical, validity.outside(case, outcome.c_min));
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
