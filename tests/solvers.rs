//! The direct solver (band LU over the pressurised range, exact upwind sweeps outside, factors
//! reused) and the plain reference (band LU of the whole domain, nothing reused) solve the same
//! discrete problem: they agree to the solve tolerance, step by step, on a textured case with
//! cavitation. The accelerators (period-old guesses, Anderson acceleration of the period
//! map, the coarse approach) save work without changing the answer, and the periodic answer
//! does not depend on where the run starts.

mod common;

use common::{case_one, case_three, rel};
use texopt::model::case::{CaseSpec, Texture};
use texopt::solve::Method;
use texopt::time::{
    simulate, simulate_with, Approach, Fidelity, Numerics, Outcome, RunOptions, Start, TimeScheme,
    Transient, Watch, APPROACH,
};

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
        accelerate: false,
        t_max: t_end,
        ..Numerics::default()
    };
    let mut tr = Transient::new(&case, &num);
    tr.set_period_guess(guess);
    let (mut its, mut z, mut n) = (0usize, 0.0, 0usize);
    let mut step = 0;
    let mut count = |t: &Transient| {
        step += 1;
        if step > from {
            its += t.last().iterations;
            z += t.ring_state().z;
            n += 1;
        }
    };
    let mut watch = Watch {
        on_step: Some(&mut count),
        ..Watch::default()
    };
    tr.run_to_periodic(&num, false, &mut watch).unwrap();
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
    // Only the start of each iteration changed: Z to the solve tolerance (solve/reuse.rs
    // `CHORD_CONFIRM`, 1e-8 relative).
    assert!(((z_with - z_without) / z_without).abs() < 1e-8);
}

#[test]
fn the_direct_solver_agrees_with_the_reference_step_by_step_on_a_cavitating_case() {
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
            z.push(tr.ring_state().z);
        }
        (z, tr)
    };
    let (z_ref, t_ref) = run(Method::Reference);
    // The state really cavitates under the ring, in and behind the pockets.
    let g = &t_ref.scene().grid;
    let cavitated_under_ring = (0..g.nodes())
        .filter(|&k| t_ref.scene().gap.ring[k / g.n2] && !t_ref.state().pressurised[k])
        .count();
    assert!(cavitated_under_ring > 50, "{cavitated_under_ring}");
    let pmax = t_ref.state().p.iter().fold(0.0f64, |m, &p| m.max(p));
    let (z, t) = run(Method::Direct);
    let dz = z
        .iter()
        .zip(&z_ref)
        .map(|(a, b)| rel(*a, *b))
        .fold(0.0, f64::max);
    let dp = t
        .state()
        .p
        .iter()
        .zip(&t_ref.state().p)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / pmax;
    assert!(dz < 1e-9, "Z differs by {dz:e} (relative)");
    assert!(dp < 1e-7, "p differs by {dp:e} of p_max");
    assert_eq!(t.state().pressurised, t_ref.state().pressurised);
}

#[test]
fn the_period_old_guess_and_chord_steps_save_work_without_changing_the_answer() {
    // The film iteration of a step starts from the state one texture period earlier (same
    // texture position) once the ring is near where it was then, and the direct method
    // reuses its factors when the matrix has barely changed; the step's film problem has
    // one solution, so the outcomes may change only within the solve tolerance.
    for case in [case_three(), case_one()] {
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
            let spp = tr.steps_per_period();
            let mut tally = |t: &Transient| {
                last.push((t.last().factorisations, t.last().iterations));
                if last.len() > spp {
                    last.remove(0);
                }
            };
            let mut watch = Watch {
                on_step: Some(&mut tally),
                ..Watch::default()
            };
            let o = tr.run_to_periodic(&num, false, &mut watch).unwrap().outcome;
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
        for (name, a, b) in [
            ("f_mean", guessed.f_mean, plain.f_mean),
            ("c_min", guessed.c_min, plain.c_min),
            ("z_mean", guessed.z_mean, plain.z_mean),
        ] {
            // To the solve tolerance (solve/reuse.rs `CHORD_CONFIRM`, 1e-8 relative; measured
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
/// texture periods with `method`: Z after each step, the largest nodal residual, and the final
/// transient.
struct WideRun {
    z: Vec<f64>,
    residual: f64,
    tr: Transient,
}

fn wide_run(periods: usize, method: Method) -> WideRun {
    let num = Numerics {
        n1: 256,
        n2: 16,
        dt: 8e-4,
        start: Start::Paper,
        solver: method,
        ..Numerics::default()
    };
    let mut tr = Transient::new(&case_three(), &num);
    let (mut z, mut residual) = (Vec::new(), 0.0f64);
    for _ in 0..periods * tr.steps_per_period() {
        tr.step().unwrap();
        z.push(tr.ring_state().z);
        residual = residual.max(tr.last().residual);
    }
    WideRun { z, residual, tr }
}

#[test]
fn at_a_wide_band_reused_factors_give_the_reference_answer() {
    // With N2 ≥ 16 the direct solver freezes the Newton matrix at the factors' Z when only
    // the active set changed, lets period-old factors serve once under a stretched chord
    // bound while the ring settles, and keeps factors in single precision. Over 16 periods
    // (the ring climbs from the paper's Z = 2.5 µm and settles) every step's Z, and the final
    // pressure and active set, are the reference's to the solve tolerance (solve/reuse.rs
    // `CHORD_CONFIRM`, 1e-8 relative).
    let (on, off) = (
        wide_run(16, Method::Direct),
        wide_run(16, Method::Reference),
    );
    assert!(on.tr.kept_factor_bytes() > 0 && off.tr.kept_factor_bytes() == 0);
    let dz =
        on.z.iter()
            .zip(&off.z)
            .map(|(a, b)| rel(*a, *b))
            .fold(0.0, f64::max);
    println!("largest Z difference {dz:e} (relative)");
    assert!(dz < 1e-8, "Z differs by {dz:e} (relative)");
    let (p_on, p_off) = (&on.tr.state().p, &off.tr.state().p);
    let pmax = p_off.iter().fold(0.0f64, |m, &p| m.max(p));
    let dp = p_on
        .iter()
        .zip(p_off)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(dp <= 1e-8 * pmax, "p differs by {dp:e} (p_max {pmax:e})");
    assert_eq!(on.tr.state().pressurised, off.tr.state().pressurised);
    // The stop rule bounds the error in p and φ; the nodal residual relative to the node's
    // own largest term may exceed it by the ratio of the stencil's other terms to that one.
    assert!(on.residual <= 1e-7, "largest residual {:e}", on.residual);
}

#[test]
fn periodic_outcome_does_not_depend_on_the_start() {
    for case in [case_three(), case_one()] {
        let out = |start: Start| {
            let num = Numerics {
                start,
                ..Fidelity::Draft.numerics()
            };
            simulate(&case, &num).unwrap().outcome
        };
        let (a, b) = (out(Start::Paper), out(Start::Equilibrium));
        assert!(a.converged && b.converged);
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
    let ladder = [Fidelity::Draft, Fidelity::Fast, Fidelity::Fine];
    let n: Vec<Numerics> = ladder.iter().map(|f| f.numerics()).collect();
    for w in n.windows(2) {
        // Each tier of the ladder resolves the sliding direction and time at least as finely
        // as the one before (the error carriers of the speed study, results/speed/).
        assert!(w[1].n1 >= w[0].n1 && w[1].dt <= w[0].dt);
        assert!(w[1].n1 > w[0].n1 || w[1].n2 > w[0].n2 || w[1].dt < w[0].dt);
    }
    // The paper's fidelity is a tier (docs/model.md §3: 512×32, dt = 4e-4).
    let p = Fidelity::Paper.numerics();
    assert_eq!((p.n1, p.n2), (512, 32));
    assert!((p.dt - 4e-4).abs() < 1e-15);
}

/// Numerics of the acceleration tests: the draft tier's (400×8, the characteristic scheme),
/// plain or accelerated (with a coarse approach on 128×4 at 1.6e-3), from `start`, to `tol`.
fn draft_run(case: &CaseSpec, accelerate: bool, start: Start, tol: f64) -> Outcome {
    let num = Numerics {
        accelerate,
        approach: accelerate.then_some(APPROACH),
        start,
        periodic_tol: tol,
        ..Fidelity::Draft.numerics()
    };
    let o = simulate(case, &num).unwrap().outcome;
    assert!(o.converged, "{o:?}");
    o
}

#[test]
fn the_accelerated_periodic_regime_is_the_plain_one_from_either_start() {
    // Four ways of settling: Case I and Case III (a damped oscillation, |λ| ≈ 0.65 and 0.49
    // a period), a conformal ring creeping to its clearance (R = 51.2, Case I's pocket), a
    // sharp ring (R = 0.2) oscillating slowly (|λ| ≈ 0.75 a window). The plain march to 1e-8
    // is the limit; the accelerated run (coarse approach, then Anderson on the period map)
    // from the paper's start and from the untextured balance must stop within its tolerance
    // of it, on fewer periods of the full mesh.
    let cases = [
        ("Case I", case_one()),
        ("Case III", case_three()),
        (
            "R = 51.2",
            CaseSpec::paper(51.2).with_texture(Texture::circular(0.01, 0.06, 5.0)),
        ),
        (
            "R = 0.2",
            CaseSpec::paper(0.2).with_texture(Texture::circular(0.01, 0.05, 5.0)),
        ),
    ];
    let tol = 1e-5;
    for (name, case) in cases {
        let limit = draft_run(&case, false, Start::Paper, 1e-8);
        for start in [Start::Paper, Start::Equilibrium] {
            let fast = draft_run(&case, true, start, tol);
            let full_mesh = |o: &Outcome| o.steps - o.approach_steps;
            println!(
                "{name} from {start:?}: {} steps on the mesh ({} approach) vs {} plain to 1e-8",
                full_mesh(&fast),
                fast.approach_steps,
                limit.steps
            );
            assert!(full_mesh(&fast) < limit.steps, "{name}");
            for (what, a, b) in [
                ("f", fast.f_mean, limit.f_mean),
                ("C_min", fast.c_min, limit.c_min),
                ("Z", fast.z_mean, limit.z_mean),
            ] {
                assert!(
                    rel(a, b) < 2.0 * tol,
                    "{name} from {start:?}: {what} {a} accelerated vs {b} plain"
                );
            }
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
    // Backward Euler: BDF2 takes this sharp ring's first swing into the liner at draft.
    let case = CaseSpec::paper(0.2).with_texture(Texture::circular(0.02, 0.04, 30.0));
    let num = Numerics {
        scheme: TimeScheme::BackwardEuler,
        ..Fidelity::Draft.numerics()
    };
    let o = simulate(&case, &num).unwrap().outcome;
    assert!(o.converged, "{o:?}");
    assert!(o.t_end > 12.0, "stopped at t = {} ms", o.t_end);
}

#[test]
fn a_coarse_approach_takes_the_transient_without_changing_the_answer() {
    // From the paper's start the ring's transient runs on 128×4 cells at 4× the time step,
    // then the state moves to 256×16: the answer must be the 256×16 mesh's, reached in fewer
    // steps on it.
    for case in [case_three(), case_one()] {
        let run = |approach: Option<Approach>| {
            let num = Numerics {
                n2: 16,
                start: Start::Paper,
                periodic_tol: 1e-5,
                approach,
                ..Fidelity::Draft.numerics()
            };
            let opts = RunOptions {
                series: true,
                ..RunOptions::default()
            };
            simulate_with(&case, &num, &opts, &mut Watch::default()).unwrap()
        };
        let coarse = Approach {
            n1: 128,
            n2: 4,
            dt: 3.2e-3,
        };
        let (plain, approached) = (run(None), run(Some(coarse)));
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
        for (what, x, y) in [
            ("f", a.f_mean, b.f_mean),
            ("C_min", a.c_min, b.c_min),
            ("Z", a.z_mean, b.z_mean),
        ] {
            assert!(rel(x, y) < 5e-5, "{what}: {x} with the approach vs {y}");
        }
    }
}
