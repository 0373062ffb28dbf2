//! Probe of the experimental p–θ multigrid ([`texopt::pt_multigrid`], issue 3): on the film
//! problems of a real run, how fast does it converge to the direct solver's solution, and
//! at what cost per V-cycle? The run is the benchmark's (Case III at `paper` from the
//! paper's start unless told otherwise). At three steps of its fine mesh (the first, one in
//! the fourth period and one in the eleventh, settled) the step's film problem is posed
//! again with the ring where the direct solver put it (fixed Z) and solved from the previous
//! step's solution and from the one a texture period before (the direct solver's two
//! guesses). A Markdown table on stdout, one row per start, coarse operator ("faces":
//! rediscretised; "Galerkin": Pᵀ·A·P, rebuilt every V-cycle, its time included) and smoothing:
//! the largest pressure error relative to the largest pressure at the start and after 1, 4
//! and 10 V-cycles, the V-cycles to 1e-8 (the film solver's tolerance, `CHORD_CONFIRM`),
//! the mean error reduction per V-cycle over the first ten, the relative nodal residual
//! after 20, and the wall time a V-cycle; and, for scale, 100 Gauss–Seidel sweeps alone.
//!
//!     cargo run --release --example pt_multigrid_probe               # Case III, paper
//!     cargo run --release --example pt_multigrid_probe -- case-I paper

use std::cell::RefCell;
use std::collections::VecDeque;
use std::time::Instant;
use texopt::bench::cases;
use texopt::case::{Fidelity, Numerics, Start};
use texopt::dynamics::RingState;
use texopt::film::{FilmState, Step};
use texopt::pt_multigrid::PtMultigrid;
use texopt::run::{run_transient_with, Transient};

/// Largest |p − p*| relative to max p*.
fn p_error(a: &FilmState, exact: &FilmState) -> f64 {
    let pmax = exact.p.iter().fold(0.0f64, |m, &p| m.max(p));
    let e =
        a.p.iter()
            .zip(&exact.p)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    e / pmax
}

/// Root-mean-square |p − p*| over the nodes relative to max p*: a smooth error shows in it
/// as much as in the largest, an error at a few nodes (a moving front) far less.
fn p_rms_error(a: &FilmState, exact: &FilmState) -> f64 {
    let pmax = exact.p.iter().fold(0.0f64, |m, &p| m.max(p));
    let sum: f64 = a.p.iter().zip(&exact.p).map(|(x, y)| (x - y).powi(2)).sum();
    (sum / a.p.len() as f64).sqrt() / pmax
}

fn probe(t: &Transient, guess: &FilmState, start: &str, window: usize) {
    let step = t.fixed_z_problem();
    let z = t.ring_state.z;
    let exact = &t.state;
    let e0 = p_error(guess, exact);
    let mut st = guess.clone();
    for (galerkin, pre, post) in [
        (false, 1, 1),
        (false, 2, 2),
        (false, 4, 4),
        (true, 1, 1),
        (true, 2, 2),
    ] {
        let mut mg = PtMultigrid::new(&step, z);
        mg.pre = pre;
        mg.post = post;
        mg.galerkin = galerkin;
        let coarse = if galerkin { "Galerkin" } else { "faces" };
        mg.load(guess);
        let (mut errors, mut ms) = (Vec::new(), 0.0);
        for _ in 0..20 {
            let t0 = Instant::now();
            mg.vcycle();
            ms += 1e3 * t0.elapsed().as_secs_f64();
            mg.store(&mut st);
            errors.push(p_error(&st, exact));
        }
        let to_tol = errors
            .iter()
            .position(|&e| e <= 1e-8)
            .map_or("> 20".to_string(), |c| (c + 1).to_string());
        let rate = (errors[9] / e0).powf(0.1);
        println!(
            "| {} ({window}) | {start} | V({pre},{post}), {coarse} | {e0:.1e} | {:.1e} | {:.1e} | {:.1e} | {to_tol} | {rate:.2} | {:.0e} | {:.2} |",
            t.steps,
            errors[0],
            errors[3],
            errors[9],
            mg.relative_residual(),
            ms / 20.0
        );
    }
    let mut gs = PtMultigrid::new(&step, z);
    gs.load(guess);
    let t0 = Instant::now();
    gs.smooth(100);
    let ms = 1e3 * t0.elapsed().as_secs_f64();
    gs.store(&mut st);
    println!(
        "| {} ({window}) | {start} | 100 Gauss–Seidel sweeps | {e0:.1e} | | | {:.1e} | | | {:.0e} | {:.3} a sweep |",
        t.steps,
        p_error(&st, exact),
        gs.relative_residual(),
        ms / 100.0
    );
}

/// Tally of one window of `every`: steps, V-cycles summed to each tolerance, the most.
#[derive(Default)]
struct Window {
    steps: usize,
    to_1e6: usize,
    to_1e8: usize,
    most: usize,
    failed: usize,
    /// Steps right after a jump (not probed: the ring state seen before it is not theirs).
    skipped: usize,
    /// Steps with the drift-corrected guess (a period and a step of history) and, summed
    /// over them: the p error (largest and root-mean-square) of the period-old guess and of the
    /// drift-corrected one, the
    /// relative Z error of the ring's velocity and of the drift-corrected Z, the V-cycles
    /// to 1e-8 from the drift-corrected guess, and Gauss–Seidel sweeps to 1e-8 from it with
    /// Z fixed at the direct solver's (at most `SWEEPS`).
    drift: usize,
    e_old: f64,
    e_drift: f64,
    rms_old: f64,
    rms_drift: f64,
    ez_velocity: f64,
    ez_drift: f64,
    cycles_drift: usize,
    sweeps_drift: usize,
}

/// Most Gauss–Seidel sweeps tried from the drift-corrected guess.
const SWEEPS: usize = 60;

/// The drift-corrected period-old guess x_{n−P} + (x_{n−1} − x_{n−1−P}), projected on
/// p ≥ 0, φ ≥ 0: the period-old solution moved by how much the last step drifted from its
/// own period-old solution (same texture phase, so the difference is the slow transient).
fn drift_corrected(period_old: &FilmState, last: &FilmState, last_old: &FilmState) -> FilmState {
    let mut g = period_old.clone();
    for k in 0..g.p.len() {
        g.p[k] = (period_old.p[k] + last.p[k] - last_old.p[k]).max(0.0);
        g.phi[k] = (period_old.phi[k] + last.phi[k] - last_old.phi[k]).max(0.0);
        g.pressurised[k] = g.p[k] > 0.0;
    }
    g
}

/// `every`: the benchmark's Case III at `paper` from the paper's start; at every step of both
/// meshes the step's problem with its ring link is solved again by Galerkin V(2,2) cycles
/// from the guess the direct solver's rule would start from when it has one (the period-old
/// solution, else the previous step's) and Z by the ring's velocity, with ∂W_h/∂Z measured
/// at each mesh's first step and kept. A row per window: the mean V-cycles until p and Z are
/// within 1e-6 and 1e-8 of the direct solution (at most 40; steps that need more are counted
/// as failed). Steps right after a jump along a slow mode are not probed (the jump moves the
/// state and the ring between two steps this observer sees). Then, from a period and a step
/// of history on, the same from the drift-corrected guess ([`drift_corrected`], Z likewise),
/// and Gauss–Seidel sweeps alone from it: does a better guess leave a step to a few sweeps?
fn every_step() {
    let bench = cases()
        .into_iter()
        .find(|c| c.name == "case-III")
        .expect("Case III");
    let mut num = Fidelity::Paper.numerics_for(&bench.case);
    num.start = Start::Paper;
    println!(
        "# p–θ multigrid at every step of Case III at `paper` (Galerkin V(2,2), ring coupled)\n"
    );
    println!("| mesh | window | steps probed | mean V-cycles to 1e-6 | mean V-cycles to 1e-8 | most to 1e-8 | steps over 40 | largest p error: period-old / drift-corrected | rms p error: period-old / drift-corrected | Z error: velocity / drift-corrected | V-cycles to 1e-8 from drift-corrected | Gauss–Seidel sweeps to 1e-8 from it (at most {SWEEPS}, Z fixed) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    struct Seen {
        mesh: (usize, usize),
        /// The last period and one step of solutions with their Z, oldest first.
        history: VecDeque<(FilmState, f64)>,
        ring: Option<RingState>,
        slope: Option<f64>,
        window: Window,
        windows: usize,
        total: Window,
    }
    let seen = RefCell::new(Seen {
        mesh: (0, 0),
        history: VecDeque::new(),
        ring: None,
        slope: None,
        window: Window::default(),
        windows: 0,
        total: Window::default(),
    });
    let flush = |s: &mut Seen| {
        let w = std::mem::take(&mut s.window);
        s.total.skipped += w.skipped;
        if w.steps == 0 {
            return;
        }
        s.windows += 1;
        let n = w.steps as f64;
        let d = w.drift.max(1) as f64;
        let drift = if w.drift == 0 {
            "| | | | |".to_string()
        } else {
            format!(
                "{:.1e} / {:.1e} | {:.1e} / {:.1e} | {:.1e} / {:.1e} | {:.2} | {:.1} |",
                w.e_old / d,
                w.e_drift / d,
                w.rms_old / d,
                w.rms_drift / d,
                w.ez_velocity / d,
                w.ez_drift / d,
                w.cycles_drift as f64 / d,
                w.sweeps_drift as f64 / d
            )
        };
        println!(
            "| {}×{} | {} | {} | {:.2} | {:.2} | {} | {} | {drift}",
            s.mesh.0,
            s.mesh.1,
            s.windows,
            w.steps,
            w.to_1e6 as f64 / n,
            w.to_1e8 as f64 / n,
            w.most,
            w.failed
        );
        s.total.steps += w.steps;
        s.total.to_1e6 += w.to_1e6;
        s.total.to_1e8 += w.to_1e8;
        s.total.most = s.total.most.max(w.most);
        s.total.failed += w.failed;
    };
    let t0 = Instant::now();
    let result = run_transient_with(
        &bench.case,
        &num,
        false,
        &[],
        &mut |_| flush(&mut seen.borrow_mut()),
        &mut |t: &Transient| {
            let mut guard = seen.borrow_mut();
            let s = &mut *guard;
            let before = s.ring.replace(t.ring_state);
            let mesh = (t.scene.grid.n1, t.scene.grid.n2);
            if mesh != s.mesh {
                s.mesh = mesh;
                s.history.clear();
                s.slope = None;
                s.windows = 0;
            }
            let n = t.steps_per_period;
            // A jump along a slow mode (between windows) moves the state and the ring after
            // the last step seen: that step's link and guesses are then not this one's.
            if s.history
                .back()
                .is_some_and(|(prev, _)| prev.phi != t.phi_old)
            {
                s.history.clear();
                s.window.skipped += 1;
            }
            if let (Some(before), Some((prev, _))) = (before, s.history.back()) {
                let len = s.history.len();
                let guess = if len >= n {
                    &s.history[len - n].0
                } else {
                    prev
                };
                let step = Step {
                    ring: Some(t.ring.link(&before, t.dt)),
                    ..t.fixed_z_problem()
                };
                let (exact, z) = (&t.state, t.ring_state.z);
                let slope = *s
                    .slope
                    .get_or_insert_with(|| PtMultigrid::load_slope(&step, exact, z));
                // V-cycles from `guess` and Z = `z0` until p and Z are within each tolerance.
                let cycles = |guess: &FilmState, z0: f64| {
                    let mut mg = PtMultigrid::new(&step, z0);
                    mg.galerkin = true;
                    mg.dw_dz = slope;
                    mg.load(guess);
                    let mut st = guess.clone();
                    let (mut to6, mut to8) = (None, None);
                    for c in 1..=40 {
                        mg.vcycle();
                        mg.store(&mut st);
                        let e = p_error(&st, exact).max((mg.z() - z).abs() / z);
                        if e <= 1e-6 && to6.is_none() {
                            to6 = Some(c);
                        }
                        if e <= 1e-8 {
                            to8 = Some(c);
                            break;
                        }
                    }
                    (to6, to8)
                };
                let z_velocity = before.z + t.dt * before.v;
                let (to6, to8) = cycles(guess, z_velocity);
                let w = &mut s.window;
                w.steps += 1;
                w.to_1e6 += to6.unwrap_or(40);
                w.to_1e8 += to8.unwrap_or(40);
                w.most = w.most.max(to8.unwrap_or(40));
                w.failed += usize::from(to8.is_none());
                if len == n + 1 {
                    let ((last_old, z_last_old), (period_old, z_period_old), (last, z_last)) =
                        (&s.history[0], &s.history[1], &s.history[n]);
                    let g = drift_corrected(period_old, last, last_old);
                    let z_drift = z_period_old + z_last - z_last_old;
                    let fixed = t.fixed_z_problem();
                    let mut gs = PtMultigrid::new(&fixed, z);
                    gs.load(&g);
                    let mut st = g.clone();
                    let sweeps = (1..=SWEEPS)
                        .find(|_| {
                            gs.smooth(1);
                            gs.store(&mut st);
                            p_error(&st, exact) <= 1e-8
                        })
                        .unwrap_or(SWEEPS);
                    w.drift += 1;
                    w.e_old += p_error(period_old, exact);
                    w.e_drift += p_error(&g, exact);
                    w.rms_old += p_rms_error(period_old, exact);
                    w.rms_drift += p_rms_error(&g, exact);
                    w.ez_velocity += (z_velocity - z).abs() / z;
                    w.ez_drift += (z_drift - z).abs() / z;
                    w.cycles_drift += cycles(&g, z_drift).1.unwrap_or(40);
                    w.sweeps_drift += sweeps;
                }
            }
            if s.history.len() == n + 1 {
                s.history.pop_front();
            }
            s.history.push_back((t.state.clone(), t.ring_state.z));
        },
    );
    if let Err(e) = result {
        eprintln!("run failed: {e}");
        std::process::exit(1);
    }
    let s = seen.into_inner();
    let n = s.total.steps as f64;
    println!(
        "\nAll {} steps probed ({} right after a jump and each mesh's first were not): {:.2} V-cycles to 1e-6 and {:.2} to 1e-8 a step on average, at most {}; {} steps over 40. Wall time with the probe: {:.0} s.",
        s.total.steps,
        s.total.skipped,
        s.total.to_1e6 as f64 / n,
        s.total.to_1e8 as f64 / n,
        s.total.most,
        s.total.failed,
        t0.elapsed().as_secs_f64()
    );
}

/// `mesh N1 N2 DT STEPS`: the probe on one mesh without the coarse approach, at step STEPS
/// from the paper's start (previous-step start only), with the direct solver's time for
/// that step: how the cycle counts grow with the mesh.
fn mesh_probe(args: &[String]) {
    let parse = |i: usize| args.get(i).and_then(|s| s.parse::<f64>().ok());
    let (Some(n1), Some(n2), Some(dt), Some(steps)) = (parse(1), parse(2), parse(3), parse(4))
    else {
        eprintln!("usage: pt_multigrid_probe mesh N1 N2 DT STEPS, e.g. mesh 1024 64 2e-4 20");
        std::process::exit(2);
    };
    let bench = cases()
        .into_iter()
        .find(|c| c.name == "case-III")
        .expect("Case III");
    let num = Numerics {
        n1: n1 as usize,
        n2: n2 as usize,
        dt,
        ..Numerics::default()
    };
    let mut t = Transient::new(&bench.case, &num);
    let mut prev = t.state.clone();
    let mut ms = 0.0;
    for _ in 0..steps as usize {
        prev.assign(&t.state);
        let t0 = Instant::now();
        if let Err(e) = t.step() {
            eprintln!("run failed: {e}");
            std::process::exit(1);
        }
        ms = 1e3 * t0.elapsed().as_secs_f64();
    }
    println!(
        "# {}×{}, dt = {dt}, step {} of Case III from the paper's start: the direct solver took {ms:.0} ms ({} iterations)\n",
        num.n1, num.n2, t.steps, t.last.iterations
    );
    print_header();
    probe(&t, &prev, "previous step", 1);
}

fn print_header() {
    println!("| step (fine window) | start | cycle | p error at start | after 1 | after 4 | after 10 | V-cycles to 1e-8 | reduction a V-cycle | relative residual after 20 | ms a V-cycle |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("mesh") => return mesh_probe(&args),
        Some("every") => return every_step(),
        _ => {}
    }
    let name = args.first().cloned().unwrap_or_else(|| "case-III".into());
    let tier = args.get(1).cloned().unwrap_or_else(|| "paper".into());
    let all = cases();
    let Some(bench) = all
        .iter()
        .find(|c| c.name == name && c.case.texture.is_some())
    else {
        let names: Vec<_> = all
            .iter()
            .filter(|c| c.case.texture.is_some())
            .map(|c| c.name)
            .collect();
        eprintln!(
            "no textured benchmark case {name}; choose from {}",
            names.join(", ")
        );
        std::process::exit(2);
    };
    let fidelity = match tier.as_str() {
        "draft" => Fidelity::Draft,
        "fast" => Fidelity::Fast,
        "paper" => Fidelity::Paper,
        _ => {
            eprintln!("no fidelity tier {tier} for this probe; choose from draft, fast, paper");
            std::process::exit(2);
        }
    };
    let mut num = fidelity.numerics_for(&bench.case);
    num.start = Start::Paper;
    let fine_n2 = num.n2;
    println!(
        "# p–θ multigrid probe: {name} ({}) at `{tier}`, fixed Z, against the direct solver\n",
        bench.case.label()
    );
    print_header();
    // Fine-mesh steps seen so far and the solutions of the last texture period.
    let seen = RefCell::new((0usize, Vec::<FilmState>::new()));
    let coupled_rows = RefCell::new(Vec::new());
    // The ring state before the step being observed (the link of its Newmark update).
    let ring_before = RefCell::new(None::<RingState>);
    let result = run_transient_with(
        &bench.case,
        &num,
        false,
        &[],
        &mut |_| {},
        &mut |t: &Transient| {
            let before = ring_before.replace(Some(t.ring_state));
            if t.scene.grid.n2 != fine_n2 {
                return;
            }
            let mut s = seen.borrow_mut();
            s.0 += 1;
            let (k, n) = (s.0, t.steps_per_period);
            if [2, 3 * n + 7, 10 * n + 7].contains(&k) {
                let window = (k - 1) / n + 1;
                if let Some(prev) = s.1.last() {
                    probe(t, prev, "previous step", window);
                }
                if s.1.len() == n {
                    probe(t, &s.1[0], "a period before", window);
                    if let Some(before) = before {
                        coupled_rows
                            .borrow_mut()
                            .extend(coupled(t, &s.1[0], &before, window));
                    }
                }
            }
            if s.1.len() == n {
                s.1.remove(0);
            }
            s.1.push(t.state.clone());
        },
    );
    if let Err(e) = result {
        eprintln!("run failed: {e}");
        std::process::exit(1);
    }
    println!(
        "\n## With the ring: Z moved after every V-cycle (chord step on the Newmark equation)\n"
    );
    println!("Start: the period-old solution, Z by the ring's velocity (the link of the step). The slope ∂W_h/∂Z of the chord step is measured once by two fixed-Z solves at the direct solver's Z and 1e-4 above it (not timed).\n");
    println!("| step (fine window) | cycle | p error at start | Z error at start | p error after 4 | Z error after 4 | after 10: p / Z | V-cycles until both ≤ 1e-8 | ms a V-cycle |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for row in coupled_rows.into_inner() {
        println!("{row}");
    }
}

/// The step's problem with its ring link, solved from the period-old solution with Z moved
/// every V-cycle; one table row per coarse operator.
fn coupled(t: &Transient, guess: &FilmState, before: &RingState, window: usize) -> Vec<String> {
    let exact = &t.state;
    let z_exact = t.ring_state.z;
    let link = t.ring.link(before, t.dt);
    let step = Step {
        ring: Some(link),
        ..t.fixed_z_problem()
    };
    let dw_dz = PtMultigrid::load_slope(&step, exact, z_exact);
    let z0 = before.z + t.dt * before.v;
    let mut rows = Vec::new();
    for galerkin in [false, true] {
        let mut mg = PtMultigrid::new(&step, z0);
        mg.galerkin = galerkin;
        mg.dw_dz = dw_dz;
        mg.load(guess);
        let mut st = guess.clone();
        let (e0, ez0) = (p_error(guess, exact), (z0 - z_exact).abs() / z_exact);
        let (mut errs, mut ms, mut both) = (Vec::new(), 0.0, None);
        for c in 0..20 {
            let t0 = Instant::now();
            mg.vcycle();
            ms += 1e3 * t0.elapsed().as_secs_f64();
            mg.store(&mut st);
            let e = (p_error(&st, exact), (mg.z() - z_exact).abs() / z_exact);
            if both.is_none() && e.0 <= 1e-8 && e.1 <= 1e-8 {
                both = Some(c + 1);
            }
            errs.push(e);
        }
        let name = if galerkin { "Galerkin" } else { "faces" };
        rows.push(format!(
            "| {} ({window}) | V(2,2), {name} | {e0:.1e} | {ez0:.1e} | {:.1e} | {:.1e} | {:.1e} / {:.1e} | {} | {:.2} |",
            t.steps,
            errs[3].0,
            errs[3].1,
            errs[9].0,
            errs[9].1,
            both.map_or("> 20".into(), |c| c.to_string()),
            ms / 20.0
        ));
    }
    rows
}
