//! Every solver variant solves the same discrete problem (one stencil, one assembly): the
//! default direct solver (band LU over the pressurised range, exact upwind sweeps outside),
//! the plain reference (band LU of the whole domain) and the multigrid/GMRES variant agree to
//! the solve tolerance, step by step, on a textured case with cavitation. And the periodic
//! answer does not depend on where the run starts.

use texopt::case::{CaseSpec, Fidelity, Numerics, Start, Texture};
use texopt::film::Method;
use texopt::run::{simulate, Transient};

fn case_three() -> CaseSpec {
    CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0))
}

/// Iterations per step of a conformal ring (R = 51.2) creeping from the untextured
/// balance, steps `from..` up to t = `t_end` (ms), with or without the period-old guess; and
/// the mean Z over those steps.
fn creeping_iterations(guess: bool, from: usize, t_end: f64) -> (f64, f64) {
    let case = CaseSpec::paper(51.2).with_texture(Texture::circular(0.01, 0.04, 2.0));
    let num = Numerics {
        n1: 256,
        n2: 8,
        dt: 8e-4,
        start: Start::Equilibrium,
        extrapolate: false,
        t_max: t_end,
        ..Numerics::default()
    };
    let mut tr = Transient::new(&case, &num);
    tr.set_period_guess(guess);
    let (mut its, mut z, mut n) = (0usize, 0.0, 0usize);
    let mut step = 0;
    tr.run_with(&num, false, &mut |_| {}, &mut |t| {
        step += 1;
        if step > from {
            its += t.last.iterations;
            z += t.ring_state.z;
            n += 1;
        }
    })
    .unwrap();
    (its as f64 / n as f64, z / n as f64)
}

#[test]
fn the_period_old_guess_serves_a_creeping_ring() {
    // While a conformal ring creeps to its textured clearance (0.5–1 % of Z a period) the
    // film a period ago still has nearly the right active set, while the previous step's is
    // off along every pocket edge; the guess is chosen by which set the last step's
    // solution was nearer to, so it serves here (the rule by the ring's drift did not:
    // there the period-old state was never "near" and both counts were equal). Steps after
    // the first three periods (the film's own transient) up to t = 0.8 ms.
    let (with, z_with) = creeping_iterations(true, 150, 0.8);
    let (without, z_without) = creeping_iterations(false, 150, 0.8);
    println!("iterations per step creeping: {with} with the guess, {without} without");
    assert!(with < 0.85 * without, "{with} vs {without}");
    // Only the start of each iteration changed: Z to the solve tolerance (film.rs
    // `CHORD_CONFIRM`, 1e-8 relative).
    assert!(((z_with - z_without) / z_without).abs() < 1e-8);
}

#[test]
fn solver_variants_agree_step_by_step_on_a_cavitating_textured_case() {
    let case = case_three();
    let base = Numerics {
        n1: 128,
        n2: 8,
        dt: 1.6e-3,
        ..Numerics::default()
    };
    let run = |m: Method| {
        let num = Numerics {
            solver: m,
            ..base.clone()
        };
        let mut tr = Transient::new(&case, &num);
        let mut z = Vec::new();
        for _ in 0..120 {
            tr.step().unwrap();
            z.push(tr.ring_state.z);
        }
        (z, tr)
    };
    let (z_ref, t_ref) = run(Method::Reference);
    // The state really cavitates under the ring, in and behind the pockets.
    let g = &t_ref.scene.grid;
    let cavitated_under_ring = (0..g.nodes())
        .filter(|&k| t_ref.scene.gap.ring[k / g.n2] && !t_ref.state.pressurised[k])
        .count();
    assert!(cavitated_under_ring > 50, "{cavitated_under_ring}");
    let pmax = t_ref.state.p.iter().fold(0.0f64, |m, &p| m.max(p));
    for m in [Method::Direct, Method::Multigrid, Method::PtMultigrid] {
        let (z, t) = run(m);
        let dz = z
            .iter()
            .zip(&z_ref)
            .map(|(a, b)| ((a - b) / b).abs())
            .fold(0.0, f64::max);
        let dp = t
            .state
            .p
            .iter()
            .zip(&t_ref.state.p)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / pmax;
        let same_set = t.state.pressurised == t_ref.state.pressurised;
        assert!(dz < 1e-9, "{}: Z differs by {dz:e} (relative)", m.name());
        assert!(dp < 1e-7, "{}: p differs by {dp:e} of p_max", m.name());
        assert!(same_set, "{}: different active sets", m.name());
    }
}

#[test]
fn the_period_old_guess_and_chord_steps_save_work_without_changing_the_answer() {
    // The film iteration of a step starts from the state one texture period earlier (same
    // texture position) once the ring is near where it was then, and the direct method
    // reuses its factors when the matrix has barely changed; the step's film problem has
    // one solution, so the outcomes may change only within the solve tolerance.
    for case in [
        case_three(),
        CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0)),
    ] {
        // The last period is counted deep in the periodic regime (a period-old factor serves
        // while the ring has moved by ≲ 1e-6 relative since).
        let num = Numerics {
            n1: 128,
            n2: 8,
            dt: 1.6e-3,
            start: Start::Paper,
            periodic_tol: 1e-7,
            ..Numerics::default()
        };
        let out = |guess: bool, solver: Method| {
            let num = Numerics {
                solver,
                ..num.clone()
            };
            let mut tr = Transient::new(&case, &num);
            tr.set_period_guess(guess);
            // Factorisations and iterations per step over the last period.
            let mut last: Vec<(usize, usize)> = Vec::new();
            let spp = tr.steps_per_period;
            let o = tr
                .run_with(&num, false, &mut |_| {}, &mut |t| {
                    last.push((t.last.factorisations, t.last.iterations));
                    if last.len() > spp {
                        last.remove(0);
                    }
                })
                .unwrap()
                .outcome;
            let per_step = |f: fn(&(usize, usize)) -> usize| {
                last.iter().map(f).sum::<usize>() as f64 / spp as f64
            };
            (o, per_step(|x| x.0), per_step(|x| x.1))
        };
        // The direct method also confirms steps by chord solves (reused factors), near the
        // periodic regime on the factors of the same texture phase a period earlier; the
        // reference method factors every iteration.
        let (plain, plain_lu, plain_it) = out(false, Method::Reference);
        let (guessed, guessed_lu, guessed_it) = out(true, Method::Direct);
        println!("factorisations per step in the last period: {guessed_lu} vs {plain_lu}");
        println!("iterations per step in the last period: {guessed_it} vs {plain_it}");
        // Without the period-old factors every step factors at least once.
        assert!(guessed_lu < 0.75, "{guessed_lu} factorisations per step");
        // With Z guessed from the ring's step a period ago, and a stop once what is left is
        // within the solve tolerance, most steps near the periodic regime settle in one iteration (the
        // older rules needed a confirming one: exactly 2).
        assert!(guessed_it < 1.75, "{guessed_it} iterations per step");
        assert!(plain.converged && guessed.converged);
        // The same periodic regime: at this tight periodic tolerance (1e-7) the solve
        // tolerance may move the window the test stops at by one.
        assert!(
            plain.periods.abs_diff(guessed.periods) <= 1,
            "{} vs {} periods",
            guessed.periods,
            plain.periods
        );
        let rel = |x: f64, y: f64| ((x - y) / y).abs();
        for (name, a, b) in [
            ("f_mean", guessed.f_mean, plain.f_mean),
            ("c_min", guessed.c_min, plain.c_min),
            ("z_mean", guessed.z_mean, plain.z_mean),
        ] {
            // To the solve tolerance (film.rs `CHORD_CONFIRM`, 1e-8 relative; measured
            // ≤ 5e-11), whichever of the two windows the runs stopped at.
            assert!(rel(a, b) < 1e-8, "{name}: {a} vs {b}");
        }
        assert!(
            guessed.iterations_per_step < 0.9 * plain.iterations_per_step,
            "{} vs {} iterations per step",
            guessed.iterations_per_step,
            plain.iterations_per_step
        );
    }
}

/// What a run of Case III at 256×16 (a wide band) from the paper's start did over `periods`
/// texture periods with its solver set by `setup`: Z after each step, rows eliminated,
/// iterations, the largest nodal residual, and the final transient.
struct WideRun {
    z: Vec<f64>,
    rows: usize,
    iterations: usize,
    residual: f64,
    tr: Transient,
}

fn wide_run(periods: usize, setup: impl Fn(&mut Transient)) -> WideRun {
    let num = Numerics {
        n1: 256,
        n2: 16,
        dt: 8e-4,
        start: Start::Paper,
        ..Numerics::default()
    };
    let mut tr = Transient::new(&case_three(), &num);
    setup(&mut tr);
    let (mut z, mut rows, mut iterations, mut residual) = (Vec::new(), 0, 0, 0.0f64);
    for _ in 0..periods * tr.steps_per_period {
        tr.step().unwrap();
        z.push(tr.ring_state.z);
        rows += tr.last.eliminated_rows;
        iterations += tr.last.iterations;
        residual = residual.max(tr.last.residual);
    }
    WideRun {
        z,
        rows,
        iterations,
        residual,
        tr,
    }
}

/// `on` eliminated fewer rows than `off` (by 5 % at least), with the same answer
/// ([`same_answer`]).
fn saves_elimination_with_the_same_answer(on: &WideRun, off: &WideRun) {
    println!(
        "rows eliminated {} vs {}; iterations {} vs {}; residual {:e} vs {:e}",
        on.rows, off.rows, on.iterations, off.iterations, on.residual, off.residual
    );
    assert!(
        (on.rows as f64) < 0.95 * off.rows as f64,
        "{} vs {} rows eliminated",
        on.rows,
        off.rows
    );
    same_answer(on, off);
}

/// Z at every step, the final p and the final active set the same to the solve tolerance
/// (film.rs `CHORD_CONFIRM`, 1e-8 relative).
fn same_answer(on: &WideRun, off: &WideRun) {
    let dz =
        on.z.iter()
            .zip(&off.z)
            .map(|(a, b)| ((a - b) / b).abs())
            .fold(0.0, f64::max);
    println!("largest Z difference {dz:e} (relative)");
    assert!(dz < 1e-8, "Z differs by {dz:e} (relative)");
    let (p_on, p_off) = (&on.tr.state.p, &off.tr.state.p);
    let pmax = p_off.iter().fold(0.0f64, |m, &p| m.max(p));
    let dp = p_on
        .iter()
        .zip(p_off)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(dp <= 1e-8 * pmax, "p differs by {dp:e} (p_max {pmax:e})");
    assert_eq!(on.tr.state.pressurised, off.tr.state.pressurised);
}

#[test]
fn a_matrix_frozen_at_the_factors_z_saves_elimination_without_changing_the_answer() {
    // With a wide band (N2 ≥ 16) an iteration that only switched nodes, Z having moved by
    // less than the chord drift, assembles its matrix at the factors' Z: the LU then keeps
    // every row before the first switched node. The step's solution is the same to
    // the solve tolerance (film.rs `CHORD_CONFIRM`, 1e-8 relative), as is the residual.
    let on = wide_run(3, |tr| tr.solver.freeze_z = true);
    let off = wide_run(3, |tr| tr.solver.freeze_z = false);
    saves_elimination_with_the_same_answer(&on, &off);
    // The stop rule bounds the error in p and φ (CHORD_CONFIRM, 1e-8 relative); the nodal
    // residual relative to the node's own largest term may exceed it by the ratio of the
    // stencil's other terms to that one (seen: 9.5e-9, and 1.6e-8 once the previous state
    // was carried with the texture, a different path to the same solution); the Z and p
    // checks hold the answer to 1e-8.
    assert!(on.residual <= 1e-7, "largest residual {:e}", on.residual);
}

#[test]
fn period_old_factors_stretched_once_save_elimination_without_changing_the_answer() {
    // With a wide band, the factors of the same phase a period earlier serve one solve's
    // chord steps up to a drift of 3e-3 (film.rs `STRETCH_DRIFT`) instead of 1e-4, while the
    // ring still settles. The steps' solutions are the same to the solve tolerance. Seen:
    // 4 080 474 against 4 345 420 rows eliminated (−6 %), 3095 against 3088 iterations.
    // 16 periods: the ring climbs from the paper's Z = 2.5 µm and then settles, moving by
    // less than 3e-3 of the clearance a period in the last ones.
    let on = wide_run(16, |tr| tr.solver.stretch_chord = true);
    let off = wide_run(16, |tr| tr.solver.stretch_chord = false);
    saves_elimination_with_the_same_answer(&on, &off);
}

#[test]
fn single_precision_kept_factors_halve_the_memory_without_changing_the_answer() {
    // With a wide band the factors kept for the same phase a period later are stored in
    // single precision: they solve their matrix to ≈ 1e-7, far inside the chord drifts the
    // stopping rule allows for anyway, which counts them (film.rs `ROUNDED_FACTORS`).
    // 6 periods: five of them with kept factors serving chord steps and lending their rows.
    let single = wide_run(6, |tr| tr.solver.single_kept = true);
    let double = wide_run(6, |tr| tr.solver.single_kept = false);
    let (bs, bd) = (single.tr.kept_factor_bytes(), double.tr.kept_factor_bytes());
    println!(
        "kept {bs} vs {bd} bytes; rows eliminated {} vs {}; iterations {} vs {}",
        single.rows, double.rows, single.iterations, double.iterations
    );
    // The band (2·N2 + 1 numbers a row) halves; the operator it is of (5 a row) stays.
    assert!(
        bd > 0 && (bs as f64) < 0.6 * bd as f64,
        "{bs} vs {bd} bytes"
    );
    same_answer(&single, &double);
    assert!(
        single.residual <= 1e-7,
        "largest residual {:e}",
        single.residual
    );
}

#[test]
fn periodic_outcome_does_not_depend_on_the_start() {
    for case in [
        case_three(),
        CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0)),
    ] {
        let out = |start: Start| {
            let num = Numerics {
                start,
                ..Fidelity::Draft.numerics()
            };
            simulate(&case, &num, false).unwrap().outcome
        };
        let (a, b) = (out(Start::Paper), out(Start::Equilibrium));
        assert!(a.converged && b.converged);
        let rel = |x: f64, y: f64| ((x - y) / y).abs();
        // Both stop within the periodic tolerance (1e-5) of the same periodic regime.
        assert!(
            rel(a.f_mean, b.f_mean) < 5e-5,
            "{} vs {}",
            a.f_mean,
            b.f_mean
        );
        assert!(rel(a.c_min, b.c_min) < 5e-5, "{} vs {}", a.c_min, b.c_min);
        assert!(
            rel(a.z_mean, b.z_mean) < 5e-5,
            "{} vs {}",
            a.z_mean,
            b.z_mean
        );
    }
}

#[test]
fn fidelity_tiers_refine_along_the_sliding_direction_and_in_time() {
    let n: Vec<Numerics> = Fidelity::ALL.iter().map(|f| f.numerics()).collect();
    for w in n.windows(2) {
        // Each tier resolves the sliding direction and time at least as finely as the one
        // before (the error carriers of results/speed.md).
        assert!(w[1].n1 >= w[0].n1 && w[1].dt <= w[0].dt);
        assert!(w[1].n1 > w[0].n1 || w[1].n2 > w[0].n2 || w[1].dt < w[0].dt);
    }
    // The paper's fidelity is a tier (model.md §3: 512×32, dt = 4e-4).
    let p = Fidelity::Paper.numerics();
    assert_eq!((p.n1, p.n2), (512, 32));
    assert!((p.dt - 4e-4).abs() < 1e-15);
}

#[test]
fn slow_mode_extrapolation_saves_periods_without_changing_the_answer() {
    // The conformal ring (R = 51.2) creeps to its periodic regime along one geometric mode.
    let case = CaseSpec::paper(51.2).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let out = |extrapolate: bool| {
        // The tolerance the bound below is stated against (the draft tier stops at 1e-4).
        let num = Numerics {
            extrapolate,
            periodic_tol: 1e-5,
            ..Fidelity::Draft.numerics()
        };
        simulate(&case, &num, false).unwrap().outcome
    };
    let (plain, fast) = (out(false), out(true));
    assert!(plain.converged && fast.converged);
    assert!(
        fast.periods * 3 < plain.periods,
        "{} vs {} periods",
        fast.periods,
        plain.periods
    );
    let rel = |x: f64, y: f64| ((x - y) / y).abs();
    assert!(
        rel(fast.f_mean, plain.f_mean) < 5e-5,
        "{} vs {}",
        fast.f_mean,
        plain.f_mean
    );
    assert!(
        rel(fast.c_min, plain.c_min) < 5e-5,
        "{} vs {}",
        fast.c_min,
        plain.c_min
    );
    assert!(
        rel(fast.z_mean, plain.z_mean) < 5e-5,
        "{} vs {}",
        fast.z_mean,
        plain.z_mean
    );
}

#[test]
fn a_damped_oscillation_is_read_and_jumped_without_changing_the_answer() {
    // A sharp ring (R = 0.2) settles by a slowly damped oscillation (|λ| ≈ 0.75 a window of
    // two periods, a pseudo-period of ≈ 4 windows): the state jumps to the limit read from
    // the window means, so the run stops sooner, within its tolerance of the limit (as does
    // the run without jumps).
    let case = CaseSpec::paper(0.2).with_texture(Texture::circular(0.01, 0.05, 5.0));
    let out = |extrapolate: bool, periodic_tol: f64| {
        let num = Numerics {
            extrapolate,
            periodic_tol,
            ..Fidelity::Draft.numerics()
        };
        simulate(&case, &num, false).unwrap().outcome
    };
    let limit = out(false, 1e-10);
    let read = out(false, 1e-5);
    let jumped = out(true, 1e-5);
    // (Without the fitted pair there is no jump: 68 periods for both.)
    assert!(limit.converged && read.converged && jumped.converged);
    // Measured: 152, 68 and 42 periods.
    assert!(
        jumped.periods * 5 < read.periods * 4 && read.periods * 2 < limit.periods,
        "{} / {} / {} periods",
        jumped.periods,
        read.periods,
        limit.periods
    );
    let rel = |x: f64, y: f64| ((x - y) / y).abs();
    for o in [&read, &jumped] {
        for (name, a, b) in [
            ("f_mean", o.f_mean, limit.f_mean),
            ("c_min", o.c_min, limit.c_min),
            ("z_mean", o.z_mean, limit.z_mean),
        ] {
            assert!(
                rel(a, b) < 1e-5,
                "{name}: {a} vs {b} ({} periods)",
                o.periods
            );
        }
    }
}

#[test]
fn a_draining_oil_bank_is_not_taken_for_the_periodic_regime() {
    // Deep pockets on a sharp ring carry more oil through the contact than arrives: the
    // flooded bank in front of the ring drains at a steady rate for ≈ 15 ms while Z̄ and f̄
    // creep by less than the tolerance per window, and only then does the film settle
    // (f̄ ≈ 17 % lower at `fast`). The run must go on until the film holds the same oil at
    // every window end. (Measured at draft: 456 periods, t = 18.2 ms; on the motion alone it
    // stopped near t = 2.5 ms.)
    let case = CaseSpec::paper(0.2).with_texture(Texture::circular(0.02, 0.04, 30.0));
    let o = simulate(&case, &Fidelity::Draft.numerics(), false)
        .unwrap()
        .outcome;
    assert!(o.converged, "{o:?}");
    assert!(o.t_end > 12.0, "stopped at t = {} ms", o.t_end);
}

#[test]
fn a_coarse_approach_takes_the_transient_without_changing_the_answer() {
    // From the paper's start the ring's transient runs on 8 cells along x2, then the state
    // moves to 16: the answer must be the 16-cell mesh's, reached in fewer steps on it.
    for case in [
        case_three(),
        CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0)),
    ] {
        let run = |approach_n2: Option<usize>| {
            let num = Numerics {
                n2: 16,
                start: Start::Paper,
                periodic_tol: 1e-5,
                approach_n2,
                ..Fidelity::Draft.numerics()
            };
            simulate(&case, &num, true).unwrap()
        };
        let (plain, approached) = (run(None), run(Some(8)));
        let (a, b) = (&approached.outcome, &plain.outcome);
        assert!(a.converged && b.converged);
        assert_eq!(b.approach_steps, 0);
        assert!(a.approach_steps > 0, "no coarse approach ran");
        // The time series holds every step, the coarse ones included.
        assert_eq!(approached.series.as_ref().map(Vec::len), Some(a.steps));
        assert!(
            a.steps - a.approach_steps < b.steps,
            "{} of {} steps on the full mesh vs {} without the approach",
            a.steps - a.approach_steps,
            a.steps,
            b.steps
        );
        let rel = |x: f64, y: f64| ((x - y) / y).abs();
        for (what, x, y) in [
            ("f", a.f_mean, b.f_mean),
            ("C_min", a.c_min, b.c_min),
            ("Z", a.z_mean, b.z_mean),
        ] {
            assert!(rel(x, y) < 5e-5, "{what}: {x} with the approach vs {y}");
        }
    }
}
