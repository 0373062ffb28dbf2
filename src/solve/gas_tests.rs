//! Gas pressures on the two sides of the ring (docs/model.md §3, "Gas pressures"): the
//! product's film solver on problems built here.

use super::{FilmMethod, FilmSolver, Method, Step};
use crate::mesh::integrals::{boundary_flows, load};
use crate::mesh::{FilmState, Scene};
use crate::model::case::{CaseSpec, Texture};
use crate::model::film::Boundary;
use crate::model::ring::RingLink;

/// Boundary data with gas pressure `left` at x1 = 0 and `right` at x1 = length, each also
/// the cavity pressure of its half.
fn gas(u: f64, phi_inlet: f64, left: f64, right: f64) -> Boundary {
    Boundary {
        u,
        u_rough: u,
        p_left: left,
        p_right: right,
        phi_inlet,
        cavity_left: left,
        cavity_right: right,
    }
}

fn steady<'a>(scene: &'a Scene, phi_old: &'a [f64], boundary: Boundary) -> Step<'a> {
    Step {
        grid: &scene.grid,
        gap: &scene.gap,
        phi_old,
        inv_dt: 0.0,
        boundary,
        ring: None,
    }
}

/// Largest |p_P − P − p_0| relative to max p_0, and largest |φ_P − φ_0|/h, over all nodes;
/// panics unless the two active sets agree.
fn shift_error(scene: &Scene, z: f64, a: &FilmState, b: &FilmState, shift: f64) -> (f64, f64) {
    let g = &scene.grid;
    assert_eq!(a.pressurised, b.pressurised, "the active sets differ");
    let pmax = a.p.iter().fold(0.0f64, |m, &p| m.max(p));
    let (mut ep, mut ephi) = (0.0f64, 0.0f64);
    for k in 0..g.nodes() {
        ep = ep.max((b.p[k] - shift - a.p[k]).abs() / pmax);
        ephi = ephi.max((b.phi[k] - a.phi[k]).abs() / scene.gap.h(g, k, z));
    }
    (ep, ephi)
}

#[test]
fn a_common_gas_pressure_shifts_the_steady_ring_film_and_nothing_else() {
    // The untextured R = 0.8 ring at Z = 5 µm, flooded, sliding: the film ruptures in the
    // divergent half. With P on both ends and as the cavity pressure everywhere the solution
    // is the ambient one plus P, with the same saturation (P: about the film's peak, and the
    // cylinder pressure of a firing stroke, 2.5e-3 ≈ 60 bar).
    let scene = Scene::new(&CaseSpec::paper(0.8), 256, 1);
    let z = 5.0;
    let phi_old = vec![0.0; scene.grid.nodes()];
    let solve = |p: f64| {
        let mut st = FilmState::cavitated(&scene.grid, &scene.gap, z, 20.0);
        let step = steady(&scene, &phi_old, gas(1.0, 20.0, p, p));
        FilmSolver::new(Method::Direct)
            .solve(&step, &mut st, &mut z.clone())
            .unwrap();
        st
    };
    let base = solve(0.0);
    let cavitated = (1..scene.grid.n1).filter(|&i| !base.pressurised[i]).count();
    assert!(cavitated > 10, "no cavity formed ({cavitated} nodes)");
    let pmax = base.p.iter().fold(0.0f64, |m, &p| m.max(p));
    for shift in [pmax, 2.5e-3] {
        let (ep, ephi) = shift_error(&scene, z, &base, &solve(shift), shift);
        // Round-off of p is relative to P + p_max.
        assert!(
            ep <= 1e-11 * (1.0 + shift / pmax),
            "P = {shift:e}: p off by {ep:e}"
        );
        assert!(ephi <= 1e-12, "P = {shift:e}: φ off by {ephi:e}");
    }
}

#[test]
fn a_common_gas_pressure_shifts_a_textured_transient_with_the_ring_free() {
    // Case I's texture, steps of the coupled film and ring from the paper's start: with P on
    // both sides and the pre-stress load raised by P's load on the ring face, Z and θ are the
    // ambient run's and p is its pressure plus P.
    let case = CaseSpec::paper(0.8).with_texture(Texture {
        l1: 0.01,
        l2: 0.01,
        per: 0.06,
        width: 0.06,
        depth: 5.0,
        phase: 0.0,
    });
    let mut scene = Scene::new(&case, 128, 8);
    let g = scene.grid.clone();
    let ring = scene.gap.ring.clone();
    let gas_load = |p: f64| load(&g, &ring, &vec![p; g.nodes()]);
    let run = |scene: &mut Scene, p: f64| {
        let (dt, kappa) = (2e-3, 2e-3 * 2e-3 / (4.0 * case.mass));
        scene.place(0.0);
        let mut st = FilmState::cavitated(&g, &scene.gap, case.z0, case.d_oil);
        let mut solver = FilmSolver::new(Method::Direct);
        let mut z = case.z0;
        for s in 1..=5 {
            scene.place(s as f64 * dt);
            let phi_old = st.phi.clone();
            let step = Step {
                grid: &g,
                gap: &scene.gap,
                phi_old: &phi_old,
                inv_dt: 1.0 / dt,
                boundary: gas(1.0, case.d_oil, p, p),
                ring: Some(RingLink {
                    z_pred: z,
                    kappa,
                    w_ps: case.w_ps + gas_load(p),
                    contact: None,
                }),
            };
            solver.solve(&step, &mut st, &mut z).unwrap();
        }
        (st, z)
    };
    let (base, z0) = run(&mut scene, 0.0);
    assert!(base.pressurised.iter().any(|&p| p) && base.pressurised.iter().any(|&p| !p));
    let pmax = base.p.iter().fold(0.0f64, |m, &p| m.max(p));
    let shift = 3.0 * pmax;
    let (shifted, z1) = run(&mut scene, shift);
    assert!((z1 - z0).abs() <= 1e-10 * z0, "Z: {z0} vs {z1}");
    let (ep, ephi) = shift_error(&scene, z0, &base, &shifted, shift);
    assert!(ep <= 1e-9, "p off by {ep:e}");
    assert!(ephi <= 1e-9, "φ off by {ephi:e}");
}

#[test]
fn a_gas_pressure_difference_drives_the_poiseuille_flow_through_a_flat_ring() {
    // A flat ring (uniform gap Z under it), flooded, no sliding, steady: the full film carries
    // the pressure linearly across the ring face from one gas pressure to the other, with the
    // flux q = h³Δp/(2·length) of docs/model.md §3 (the gap e outside adds no resistance worth
    // the name). Both ways round: the floor of a full film is the lower gas pressure.
    let scene = Scene::new(&CaseSpec::paper(f64::INFINITY), 250, 1);
    let (g, z) = (&scene.grid, 4.0);
    let ring: Vec<usize> = (0..=g.n1).filter(|&i| scene.gap.ring[i]).collect();
    let (first, last) = (ring[0], *ring.last().unwrap());
    let phi_old = vec![0.0; g.nodes()];
    for (pl, pr) in [(3e-4, 1e-4), (1e-4, 3e-4)] {
        let mut st = FilmState::flooded(g, &scene.gap, z);
        st.pressurised[1..g.n1].iter_mut().for_each(|p| *p = true);
        let step = steady(&scene, &phi_old, gas(0.0, 1000.0, pl, pr));
        FilmSolver::new(Method::Direct)
            .solve(&step, &mut st, &mut z.clone())
            .unwrap();
        assert!(
            st.pressurised[1..g.n1].iter().all(|&p| p),
            "a node cavitated"
        );
        let dp = pl - pr;
        // Linear over the ring's nodes, from one gas pressure to the other.
        assert!((st.p[first] - pl).abs() <= 1e-6 * dp.abs());
        assert!((st.p[last] - pr).abs() <= 1e-6 * dp.abs());
        let span = g.x(last) - g.x(first);
        for &i in &ring {
            let linear = st.p[first] + (st.p[last] - st.p[first]) * (g.x(i) - g.x(first)) / span;
            assert!((st.p[i] - linear).abs() <= 1e-9 * dp.abs(), "p at node {i}");
        }
        // The same flux through every face: Δp over the faces' resistances in series, within
        // 1e-5 of h³Δp/(2·span) (the gap e adds almost none); the ring's width is within
        // 2·dx of span.
        let face_h = |i: usize| 0.5 * (scene.gap.h(g, i, z) + scene.gap.h(g, i + 1, z));
        let resistance: f64 = (0..g.n1).map(|i| 2.0 * g.dx / face_h(i).powi(3)).sum();
        let series = dp / resistance;
        let expect = z * z * z * dp / (2.0 * span);
        assert!(
            (series / expect - 1.0).abs() <= 1e-5,
            "{series} vs {expect}"
        );
        for i in 0..g.n1 {
            let q = crate::model::film::x1_flux(0.0, 0.0, face_h(i), st.p[i + 1] - st.p[i], g.dx);
            // Across the gap e the pressure differences are ≈ 1e-13, a few hundred ulps of p.
            let tol = if face_h(i) < 2.0 * z { 1e-9 } else { 1e-5 };
            assert!(
                (q - series).abs() <= tol * series.abs(),
                "face {i}: {q} vs {series}"
            );
        }
        let width = scene.contact.ring_edges().1 - scene.contact.ring_edges().0;
        let continuum = z * z * z * dp / (2.0 * width);
        assert!((expect / continuum - 1.0).abs() <= 2.0 * g.dx / span);
    }
}

#[test]
fn a_starved_inlet_at_gas_pressure_stays_starved() {
    // The R = 0.8 ring at Z = 5 µm with a 5.5 µm film on the liner (less than the ring
    // passes, ≈ 6.1 µm: starved) and gas pressure P on the inlet side only: the inlet's gap
    // stays cavitated at p = P with the film as it came (θ = d_oil/e), the film fills in the
    // converging half and starts there at p ≥ P, ruptures at the outlet side's pressure 0, and
    // what enters leaves.
    let scene = Scene::new(&CaseSpec::paper(0.8), 256, 1);
    let (g, z, d_oil) = (&scene.grid, 5.0, 5.5);
    let phi_old = vec![0.0; g.nodes()];
    let a = scene.contact.ring_edges().0;
    let solve = |cavity_left: f64, p: f64| {
        let mut st = FilmState::cavitated(g, &scene.gap, z, d_oil);
        let step = steady(
            &scene,
            &phi_old,
            Boundary {
                cavity_left,
                ..gas(1.0, d_oil, p, 0.0)
            },
        );
        let r = FilmSolver::new(Method::Direct).solve(&step, &mut st, &mut z.clone());
        (r, st)
    };
    let pmax = {
        let (r, st) = solve(0.0, 0.0);
        r.unwrap();
        st.p.iter().fold(0.0f64, |m, &p| m.max(p))
    };
    let p_gas = 0.5 * pmax;
    let (r, st) = solve(p_gas, p_gas);
    r.unwrap();
    let e = scene.gap.h(g, 1, z);
    for i in (1..g.n1).filter(|&i| g.x(i) < a) {
        assert!(!st.pressurised[i], "inlet node {i} pressurised");
        assert_eq!(st.p[i], p_gas);
        assert!(
            (st.phi[i] / e - d_oil / e).abs() <= 1e-12,
            "θ at {i}: {}",
            st.phi[i] / e
        );
    }
    let first = (1..g.n1).find(|&i| st.pressurised[i]).unwrap();
    let last = (1..g.n1).rev().find(|&i| st.pressurised[i]).unwrap();
    assert!(2 * first < g.n1 && 2 * last > g.n1);
    assert!(st.p[first] >= p_gas * (1.0 - 1e-12));
    assert!((last + 1..g.n1).all(|i| st.p[i] == 0.0 && !st.pressurised[i]));
    let (inflow, outflow) = boundary_flows(g, &scene.gap, z, (1.0, 1.0), &st);
    assert!((inflow - 0.5 * d_oil).abs() <= 1e-12 * d_oil);
    assert!(
        (inflow - outflow).abs() <= 1e-10 * inflow,
        "{inflow} in, {outflow} out"
    );
    // The same gas pressure held against a cavity at 0 floods the gap e instead (the
    // boundary's pressure pushes oil through its enormous conductance).
    let (r, st) = solve(0.0, p_gas);
    let flooded = r.is_err() || (1..g.n1).any(|i| g.x(i) < a && st.phi[i] > 2.0 * d_oil);
    assert!(flooded, "the contrast did not flood");
}

#[test]
fn a_starved_ring_against_a_large_gas_pressure_difference_is_an_error_not_a_number() {
    // The limit of docs/model.md §3: a 3 µm film never fills the ring at Z = 5 µm, so the
    // cavity spans the centre, where p_c steps from one side's gas pressure to the other's.
    // At 1 bar (4.2e-5) the Poiseuille flux of that step exceeds the oil arriving: the solve
    // fails with θ < 0. With no difference the same ring passes its film untouched.
    let scene = Scene::new(&CaseSpec::paper(0.8), 512, 1);
    let (g, z, d_oil) = (&scene.grid, 5.0, 3.0);
    let phi_old = vec![0.0; g.nodes()];
    let solve = |left: f64, right: f64| {
        let mut st = FilmState::cavitated(g, &scene.gap, z, d_oil);
        let step = steady(&scene, &phi_old, gas(1.0, d_oil, left, right));
        let r = FilmSolver::new(Method::Direct).solve(&step, &mut st, &mut z.clone());
        (r, st)
    };
    let (r, st) = solve(4.2e-5, 4.2e-5);
    r.unwrap();
    assert!(st.pressurised.iter().all(|&p| !p));
    assert!(st.phi[1..g.n1].iter().all(|&phi| phi == d_oil));
    let (r, _) = solve(4.2e-5, 0.0);
    assert!(
        matches!(r, Err(super::FilmError::SaturationOutOfRange { theta, .. }) if theta < 0.0),
        "{r:?}"
    );
}
