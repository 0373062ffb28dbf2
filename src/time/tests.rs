//! Unit tests of the time layer: the stopping rules, what a transient keeps from one period
//! to the next.

use super::fallback::stalled;
use super::memory::TextureShift;
use super::numerics::Numerics;
use super::periodic::{accelerated_error, periodic_error, slow_pair, SlowMode};
use super::transient::Transient;
use super::window::PeriodMeans;
use crate::mesh::integrals::{friction, friction_thresholds};
use crate::mesh::FilmState;
use crate::model::case::CaseSpec;
use crate::model::friction::FrictionModel;

/// Window means whose f̄ and Z̄ follow y_k = y* + A·ρ^k·cos(ωk + φ).
fn oscillation(n: usize, rho: f64, omega: f64) -> Vec<PeriodMeans> {
    (0..n)
        .map(|k| {
            let k = k as f64;
            let mut m = PeriodMeans::empty();
            m.z_mean = 3.0 + 0.05 * rho.powf(k) * (omega * k + 0.3).cos();
            m.friction.couette = 0.08 + 0.002 * rho.powf(k) * (omega * k + 1.1).cos();
            m
        })
        .collect()
}

#[test]
fn a_damped_oscillation_is_read_to_its_limit() {
    let h = oscillation(12, 0.75, 1.5);
    let mode = slow_pair(&h).expect("a clean damped oscillation fits");
    assert!((mode.radius() - 0.75).abs() < 1e-9, "{mode:?}");
    // Two real modes, 0.9 and 0.1: λ² = λ − 0.09.
    let real = SlowMode {
        alpha: 1.0,
        beta: -0.09,
    };
    assert!((real.radius() - 0.9).abs() < 1e-12);
    assert!((real.limit(1.0, 2.0, 2.5) - (2.5 - 2.0 + 0.09) / 0.09).abs() < 1e-9);
    // The estimate is the larger of the distance from the limit and the last change.
    let k = h.len() - 1;
    let rel = |y: &dyn Fn(&PeriodMeans) -> f64, limit: f64| {
        let (now, before) = (y(&h[k]), y(&h[k - 1]));
        ((now - limit).abs().max((now - before).abs())) / now.abs()
    };
    let expected = rel(&|m| m.z_mean, 3.0).max(rel(&|m| m.friction.total(), 0.08));
    let est = periodic_error(&h);
    assert!((est / expected - 1.0).abs() < 1e-6, "{est} vs {expected}");
}

#[test]
fn a_film_that_still_gains_or_loses_oil_is_not_periodic() {
    // The motion has settled (f̄ and Z̄ constant), but the film loses 1 % of the oil
    // through it every window: not periodic, whatever the motion says.
    let h: Vec<PeriodMeans> = (0..8)
        .map(|k| {
            let mut m = PeriodMeans::empty();
            m.z_mean = 3.0;
            m.friction.couette = 0.08;
            m.throughput = 0.5;
            m.start_content = 1.0 - 0.005 * k as f64;
            m.content = 1.0 - 0.005 * (k + 1) as f64;
            m
        })
        .collect();
    assert!((periodic_error(&h) - 0.01).abs() < 1e-12);
    // The same for an accelerated run, whatever its residual says.
    assert!((accelerated_error(&h, 0.0) - 0.01).abs() < 1e-12);
    let held: Vec<PeriodMeans> = h
        .into_iter()
        .map(|m| PeriodMeans {
            start_content: 1.0,
            content: 1.0,
            ..m
        })
        .collect();
    assert_eq!(periodic_error(&held), 0.0);
    assert_eq!(accelerated_error(&held, 0.0), 0.0);
}

#[test]
fn an_accelerated_run_is_as_far_as_its_last_change_or_residual() {
    let means = |f: f64, z: f64| {
        let mut m = PeriodMeans::empty();
        m.friction.couette = f;
        m.z_mean = z;
        m.throughput = 1.0;
        m
    };
    let h = vec![
        means(0.1, 3.0),
        means(0.09, 3.3),
        means(0.0801, 3.003),
        means(0.08, 3.0),
    ];
    // Two windows are too few to read a change from a window that started afresh.
    assert_eq!(accelerated_error(&h[..2], 0.0), f64::INFINITY);
    let change = (0.0001f64 / 0.08).max(0.003 / 3.0);
    assert!((accelerated_error(&h, 1e-6) - change).abs() < 1e-15);
    assert_eq!(accelerated_error(&h, 0.5), 0.5);
}

#[test]
fn a_run_stalls_when_its_distance_stops_halving() {
    // Settling at 0.75 a window (the slowest benchmark case): never stalled.
    let settling: Vec<f64> = (0..60).map(|k| 0.1 * 0.75f64.powi(k)).collect();
    assert!((1..=60).all(|n| !stalled(&settling[..n], 30)));
    // A spurious oscillation: the distance swings between the same bounds.
    let swinging: Vec<f64> = (0..30).map(|k| 0.02 + 0.01 * (k as f64).sin()).collect();
    assert!(!stalled(&swinging[..29], 30));
    assert!(stalled(&swinging, 30));
    // Before three windows the distance is unknown (infinite): not a stall on its own.
    let mut late = vec![f64::INFINITY; 3];
    late.extend((0..27).map(|k| 0.1 * 0.75f64.powi(k)));
    assert!(!stalled(&late, 30));
}

#[test]
fn the_slow_pair_is_refused_when_it_does_not_describe_the_changes() {
    // Five windows: too few to check a fit of two coefficients.
    assert!(slow_pair(&oscillation(5, 0.75, 1.5)).is_none());
    // A single geometric mode: the changes lie on one line (β undetermined); the
    // geometric tail reads it instead.
    let geometric: Vec<PeriodMeans> = (0..8)
        .map(|k| {
            let mut m = PeriodMeans::empty();
            m.z_mean = 3.0 + 0.05 * 0.9f64.powi(k);
            m
        })
        .collect();
    assert!(slow_pair(&geometric).is_none());
    // Growing, or changes that follow no recurrence.
    assert!(slow_pair(&oscillation(12, 1.05, 1.5)).is_none());
    let mut noisy = oscillation(12, 0.75, 1.5);
    for (i, m) in noisy.iter_mut().enumerate() {
        m.z_mean += 1e-3
            * [
                0.3, -1.0, 0.7, 0.2, -0.6, 1.0, -0.4, 0.9, -0.8, 0.1, 0.5, -0.2,
            ][i];
    }
    assert!(slow_pair(&noisy).is_none());
}

/// A transient of Case III's texture on a small mesh, `steps` steps in (two periods and
/// a bit: every phase slot has been placed once and served once).
fn case_iii_after(steps: usize) -> Transient {
    let case =
        CaseSpec::paper(3.2).with_texture(crate::model::case::Texture::circular(0.03, 0.06, 10.0));
    let num = Numerics {
        n1: 64,
        n2: 4,
        dt: 4e-3,
        ..Numerics::default()
    };
    let mut t = Transient::new(&case, &num);
    for _ in 0..steps {
        t.step().expect("a coarse Case III steps");
    }
    t
}

#[test]
fn the_texture_kept_from_a_period_ago_is_the_texture_placed_now() {
    let mut t = case_iii_after(0);
    let n = t.steps_per_period();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for _ in 0..2 * n + 3 {
        t.step().expect("a coarse Case III steps");
        // The scene as placing the texture afresh at this step's phase gives it.
        let mut fresh = t.scene().clone();
        fresh.place((t.steps() % n) as f64 * t.dt());
        assert_eq!(bits(&t.scene().hl), bits(&fresh.hl), "step {}", t.steps());
        assert_eq!(
            bits(&t.scene().gap.base),
            bits(&fresh.gap.base),
            "step {}",
            t.steps()
        );
    }
    // The kept phases served: every slot is filled.
    assert!(t.memory.placed.slots.iter().all(Option::is_some));
}

#[test]
fn switches_counted_over_slices_are_those_node_by_node() {
    // Two levels of a coarse Case III a few steps apart: sets that differ in and out of
    // the pockets.
    let mut t = case_iii_after(3);
    let before = t.state().pressurised.clone();
    for _ in 0..4 {
        t.step().expect("a coarse Case III steps");
    }
    let (g, hl, now) = (&t.scene().grid, &t.scene().hl, &t.state().pressurised);
    assert!(hl.iter().any(|&h| h > 0.0) && hl.iter().any(|&h| h <= 0.0));
    for columns in [0, 1, 3, g.n1, g.n1 + 1] {
        let shift = TextureShift { columns };
        let by_node = (0..now.len())
            .filter(|&m| before[shift.source(g, hl, m)] != now[m])
            .count();
        assert!(columns > 1 || by_node > 0, "the sets must differ somewhere");
        assert_eq!(
            shift.switches(g, hl, &before, now),
            by_node,
            "{columns} columns"
        );
    }
}

#[test]
fn the_previous_state_carried_with_the_texture_is_the_nearer_guess() {
    // Each step's guess from the previous level alone (no period-old states), with and
    // without carrying the pockets' film along with them.
    let mut carried = case_iii_after(0);
    carried.set_period_guess(false);
    assert_eq!(
        carried.memory.shift.columns, 1,
        "u·dt/dx = 1.28 at 64×4, dt = 4e-3"
    );
    let mut held = case_iii_after(0);
    held.set_period_guess(false);
    held.memory.shift = TextureShift::NONE;
    let n = carried.steps_per_period();
    let (mut switched_carried, mut switched_held) = (0, 0);
    let (mut it_carried, mut it_held) = (0, 0);
    for _ in 0..2 * n {
        let before = carried.state().clone();
        carried.step().expect("a coarse Case III steps");
        held.step().expect("a coarse Case III steps");
        it_carried += carried.last().iterations;
        it_held += held.last().iterations;
        let mut guess = before.clone();
        carried
            .memory
            .shift
            .carry(&carried.scene().grid, &carried.scene().hl, &mut guess);
        let differ = |g: &FilmState| {
            g.pressurised
                .iter()
                .zip(&carried.state().pressurised)
                .filter(|(a, b)| a != b)
                .count()
        };
        switched_carried += differ(&guess);
        switched_held += differ(&before);
    }
    // The pockets’ cavities move with them: the carried guess is the nearer active set
    // and needs fewer iterations (carrying the nodes outside the pockets instead, it
    // would not: 410 against 406 switches, 120 against 120 iterations).
    assert!(
        switched_carried < switched_held,
        "{switched_carried} {switched_held}"
    );
    assert!(it_carried < it_held, "{it_carried} {it_held}");
    // A guess only starts the iteration: the same film and ring to the solve tolerance.
    let dz = (carried.ring_state().z - held.ring_state().z).abs() / held.ring_state().z;
    assert!(dz < 1e-9, "{dz}");
    let pmax = held.state().p.iter().fold(0.0f64, |m, &p| m.max(p));
    for (a, b) in carried.state().p.iter().zip(&held.state().p) {
        assert!((a - b).abs() <= 1e-8 * pmax, "{a} {b}");
    }
}

#[test]
fn friction_for_several_thresholds_in_one_pass_is_each_ones_own() {
    let t = case_iii_after(20);
    let z = t.ring_state().z;
    let thresholds = [0.75, 0.5, 0.25, 0.05];
    let model = t.friction_model();
    let (own, extra) = friction_thresholds(
        &t.scene().grid,
        &t.scene().gap,
        z,
        &t.scene().hl,
        t.state(),
        &model,
        &thresholds,
    );
    let alone = |theta_s: f64| {
        friction(
            &t.scene().grid,
            &t.scene().gap,
            z,
            &t.scene().hl,
            t.state(),
            &FrictionModel { theta_s, ..model },
        )
    };
    assert_eq!(own, alone(model.theta_s));
    for (f, &theta_s) in extra.iter().zip(&thresholds) {
        assert_eq!(*f, alone(theta_s), "θs = {theta_s}");
    }
    // The thresholds do differ here (a cavitated film under the ring).
    assert_ne!(extra[0].couette, extra[3].couette);
}
