//! Closed-form checks of the film solver: the inclined-plane slider (no cavitation) and the
//! oscillating squeeze film with rupture (Ausas, Jai, Buscaglia, J. Tribol. 2009), and a flat
//! slider over a groove with the faces fitted to the gap along x1.

use texopt::mesh::integrals::boundary_flows;
use texopt::mesh::{sample_across, FilmState, FittedFaces, Gap, Grid, RimModel, Rows};
use texopt::model::film::Boundary;
use texopt::solve::{FilmMethod, FilmSolver, Method, Step};

/// Steady 1D slider on [0, 1] with h falling linearly from h1 to h2, flooded inlet, p = 0 at
/// both ends. With θ = 1 everywhere (∇·(h³∇p) = u ∂h/∂x1):
/// p(x) = u/(h1 − h2)·[(1/h − 1/h1) − (h_m/2)(1/h² − 1/h1²)], h_m = 2·h1·h2/(h1 + h2).
fn slider_error(n: usize) -> f64 {
    let (h1, h2, u) = (2.0, 1.0, 1.0);
    let g = Grid::new(n, 1, 1.0, 1.0);
    let gap = Gap {
        base: (0..=n).map(|i| h1 - (h1 - h2) * g.x(i)).collect(),
        ring: vec![false; n + 1],
        flow: None,
        rows: Default::default(),
        fitted: None,
        fitted_x2: None,
    };
    let phi_old = vec![0.0; g.nodes()];
    let step = Step::steady(
        &g,
        &gap,
        &phi_old,
        Boundary::with_ends(u, (0.0, 0.0), 100.0),
    );
    let mut state = FilmState::cavitated(&g, &gap, 0.0, 100.0);
    let mut z = 0.0;
    FilmSolver::new(Method::Direct)
        .solve(&step, &mut state, &mut z)
        .unwrap();
    let hm = 2.0 * h1 * h2 / (h1 + h2);
    let exact = |x: f64| {
        let h = h1 - (h1 - h2) * x;
        u / (h1 - h2) * ((1.0 / h - 1.0 / h1) - 0.5 * hm * (1.0 / (h * h) - 1.0 / (h1 * h1)))
    };
    let pmax = (0..=n).map(|i| exact(g.x(i))).fold(0.0, f64::max);
    assert!(
        state.pressurised[1..n].iter().all(|&a| a),
        "the slider must not cavitate"
    );
    (0..=n)
        .map(|i| (state.p[i] - exact(g.x(i))).abs())
        .fold(0.0, f64::max)
        / pmax
}

#[test]
fn inclined_slider_matches_analytic_pressure_with_second_order() {
    let ns = [64, 128, 256, 512];
    let errs: Vec<f64> = ns.iter().map(|&n| slider_error(n)).collect();
    println!("slider max error / p_max: {errs:?}");
    assert!(errs[3] < 0.005, "error at 512 cells {} ≥ 0.5 %", errs[3]);
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.9, "observed order {order} (errors {errs:?})");
    }
}

/// h(t) = 0.125·cos(4πt) + 0.375 between parallel plates on [0, 1], u = 0, p = p0 at both
/// ends, θ = 1 initially. In our scaling ∇·(h³∇p) = 2·∂(hθ)/∂t, so k = 2.
mod squeeze {
    use std::f64::consts::PI;

    pub const P0: f64 = 0.025;
    pub const K: f64 = 2.0;

    pub fn h(t: f64) -> f64 {
        0.125 * (4.0 * PI * t).cos() + 0.375
    }
    pub fn dh(t: f64) -> f64 {
        -0.5 * PI * (4.0 * PI * t).sin()
    }

    /// Full film while separating: p = p0 + (k·h'/(2h³))·x·(x − 1); its minimum at x = ½
    /// reaches 0 when h'/h³ = 8·p0/k: the rupture time (bisection on (0.25, 0.3)).
    pub fn rupture_time() -> f64 {
        let g = |t: f64| dh(t) / h(t).powi(3) - 8.0 * P0 / K;
        let (mut a, mut b) = (0.25 + 1e-9, 0.3);
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if g(m) > 0.0 {
                b = m
            } else {
                a = m
            }
        }
        0.5 * (a + b)
    }

    /// After rupture the pressurised zone next to x = 0 satisfies p'' = k·h'/h³ with
    /// p = p' = 0 at the front: p0 = (k·h'/(2h³))·x_f², so x_f = √(2·p0·h³/(k·h')).
    pub fn front(t: f64) -> f64 {
        (2.0 * P0 * h(t).powi(3) / (K * dh(t))).sqrt()
    }
}

#[test]
fn oscillating_squeeze_film_rupture_time_and_front() {
    use squeeze::*;
    let (n, dt): (usize, f64) = (2000, 1e-5);
    let g = Grid::new(n, 1, 1.0, 1.0);
    let mut gap = Gap {
        base: vec![h(0.0); n + 1],
        ring: vec![false; n + 1],
        flow: None,
        rows: Default::default(),
        fitted: None,
        fitted_x2: None,
    };
    let mut state = FilmState::flooded(&g, &gap, 0.0);
    let mut solver = FilmSolver::new(Method::Direct);
    let checks = [0.255, 0.26, 0.27, 0.28, 0.29, 0.30];
    let mut next = 0;
    let mut t_rupture = None;
    let mut z = 0.0;
    let steps = (0.30 / dt).round() as usize;
    for s in 1..=steps {
        let t = s as f64 * dt;
        let phi_old = state.phi.clone();
        gap.base.iter_mut().for_each(|v| *v = h(t));
        let step = Step {
            grid: &g,
            gap: &gap,
            phi_old: &phi_old,
            inv_dt: 1.0 / dt,
            boundary: Boundary {
                u: 0.0,
                u_rough: 0.0,
                p_left: P0,
                p_right: P0,
                phi_inlet: 0.0,
                cavity_left: 0.0,
                cavity_right: 0.0,
            },
            ring: None,
        };
        solver.solve(&step, &mut state, &mut z).unwrap();
        let cavitated = (1..n).any(|i| !state.pressurised[i]);
        if t_rupture.is_none() && t > 0.1 && cavitated {
            t_rupture = Some(t);
        }
        if next < checks.len() && (t - checks[next]).abs() < 0.5 * dt {
            // Front: midway between the last pressurised node from the left and the next.
            let last = (1..n).take_while(|&i| state.pressurised[i]).last().unwrap();
            let x_num = g.x(last) + 0.5 * g.dx;
            let last_r = (1..n)
                .rev()
                .take_while(|&i| state.pressurised[i])
                .last()
                .unwrap();
            let x_num_r = 1.0 - (g.x(last_r) - 0.5 * g.dx);
            let x_exact = front(t);
            println!("t = {t}: front {x_num:.5} / {x_num_r:.5} (right), exact {x_exact:.5}");
            assert!(
                (x_num - x_exact).abs() <= 2.0 * g.dx,
                "front at t = {t}: {x_num} vs {x_exact} (dx = {})",
                g.dx
            );
            assert!((x_num_r - x_exact).abs() <= 2.0 * g.dx);
            next += 1;
        }
    }
    assert_eq!(next, checks.len());
    let t_num = t_rupture.expect("the film must rupture");
    let t_exact = rupture_time();
    println!("rupture at t = {t_num}, closed form {t_exact}");
    assert!((t_num - t_exact).abs() <= 0.01 * t_exact);
    // Sharper than 1 %: within two steps (the k = 1 scaling would rupture 8e-5 later).
    assert!((t_num - t_exact).abs() <= 2.0 * dt);
}

/// A film between parallel surfaces whose gap varies only across the sliding direction (a
/// groove 20 times deeper than the land over half of each cell's width), driven by a pressure
/// drop along x1 with the liner sliding: p is linear in x1 and the flow through the width is
/// exactly Σ over the strips of (u/2)·h − (h³/2)·∂p/∂x1. Sampled across its one row of cells
/// ([`RimModel::Strips`]) the mesh carries that flow to round-off; at its nodes it sees one
/// gap, the centre line's, and carries another.
fn strip_film_inflow(rim: RimModel, n2: usize) -> (f64, f64) {
    let (n, u, dp) = (32, 1.0, 1.0);
    let g = Grid::new(n, n2, 1.0, 1.0);
    // Deep (20) on the lower half of the width, the land (1) on the upper half.
    let depth = |y: f64| if y < 0.5 { 19.0 } else { 0.0 };
    let mut rows = Rows::nodal();
    rows.reset(g.nodes(), rim);
    let mut base = vec![0.0; g.nodes()];
    let mut samples = Vec::new();
    for i in 0..=n {
        for j in 0..n2 {
            let k = g.idx(i, j);
            let d = match rim {
                RimModel::Nodal => depth(g.y(j)),
                _ => {
                    sample_across(g.y(j), g.dy, rim.samples(), depth, &mut samples);
                    rows.set(k, &samples)
                }
            };
            base[k] = 1.0 + d;
        }
    }
    let gap = Gap {
        base,
        ring: vec![false; n + 1],
        flow: None,
        rows,
        fitted: None,
        fitted_x2: None,
    };
    let phi_old = vec![0.0; g.nodes()];
    let step = Step::steady(&g, &gap, &phi_old, Boundary::with_ends(u, (dp, 0.0), 100.0));
    let mut state = FilmState::flooded(&g, &gap, 0.0);
    let mut z = 0.0;
    FilmSolver::new(Method::Direct)
        .solve(&step, &mut state, &mut z)
        .unwrap();
    let (inflow, _) = boundary_flows(&g, &gap, 0.0, (u, u), &state);
    // Half the width at h = 20, half at h = 1 (the simulated width is 1).
    let exact =
        0.5 * (0.5 * u * 20.0 + 0.5 * 20f64.powi(3) * dp) + 0.5 * (0.5 * u * 1.0 + 0.5 * dp);
    (inflow, exact)
}

#[test]
fn strips_across_a_cell_carry_the_exact_flow_of_a_grooved_film() {
    let (strips, exact) = strip_film_inflow(RimModel::Strips { samples: 8 }, 1);
    println!("strips on one row: {strips} against {exact}");
    assert!(((strips - exact) / exact).abs() < 1e-12);
    // The nodal row sees its centre line only (y = 0.5, on the land): the land's gap over the
    // whole width, and a two-thousandth of the flow.
    let (nodal, _) = strip_film_inflow(RimModel::Nodal, 1);
    println!("nodal on one row: {nodal}");
    assert!((nodal / exact) < 0.01);
    // Two nodal rows resolve the groove exactly: the two agree there.
    let (two, _) = strip_film_inflow(RimModel::Nodal, 2);
    assert!(((two - exact) / exact).abs() < 1e-12);
}

/// The steady full film of a flat slider over a groove on [0, 1] (one row), p = `ends`
/// at both ends, every face fitted at `m` points (or none): the nodal pressures.
fn groove(n1: usize, m: usize, fit: bool, h: impl Fn(f64) -> f64, ends: f64) -> Vec<f64> {
    let g = Grid::new(n1, 1, 1.0, 1.0);
    let base: Vec<f64> = (0..=n1).map(|i| h(g.x(i))).collect();
    let mut fitted = FittedFaces::new(n1, 1, m);
    for i in 0..n1 {
        let at: Vec<f64> = (0..m)
            .map(|q| h(g.x(i) + (q as f64 + 0.5) * g.dx / m as f64))
            .collect();
        fitted.set(i, &at, &vec![false; m]);
    }
    let gap = Gap {
        base,
        ring: vec![false; n1 + 1],
        fitted: fit.then_some(fitted),
        ..Gap::default()
    };
    let phi_old = gap.base.clone();
    let step = Step::steady(
        &g,
        &gap,
        &phi_old,
        Boundary::with_ends(1.0, (ends, ends), 1e3),
    );
    let mut st = FilmState::flooded(&g, &gap, 0.0);
    FilmSolver::new(Method::Direct)
        .solve(&step, &mut st, &mut 0.0)
        .expect("a full film");
    assert!(st.pressurised[1..n1].iter().all(|&p| p), "cavitated");
    st.p
}

#[test]
fn a_groove_under_a_flat_slider_is_exact_at_the_nodes_wherever_its_rims_fall() {
    // Gap 1 with a groove 20 deep on [0.325, 0.575]: both rims inside cells of 0.1 and on
    // the faces' quadrature points' boundaries (m = 4), so each face's integrals are exact.
    let h = |x: f64| {
        if (0.325..0.575).contains(&x) {
            21.0
        } else {
            1.0
        }
    };
    // The exact film (docs/model.md §3 at a constant flux F, u = 1): p' = 1/h² − F/h³.
    let integral = |x: f64, n: i32| {
        let inside = (x.min(0.575) - 0.325).max(0.0);
        (x - inside) + inside * 21f64.powi(-n)
    };
    let f = integral(1.0, 2) / integral(1.0, 3);
    let exact = |x: f64| 1.0 + integral(x, 2) - f * integral(x, 3);
    let fitted = groove(10, 4, true, h, 1.0);
    let nodal = groove(10, 4, false, h, 1.0);
    let error = |p: &[f64]| {
        (0..=10)
            .map(|i| (p[i] - exact(0.1 * i as f64)).abs())
            .fold(0.0, f64::max)
    };
    let swing = (0..=100)
        .map(|i| (exact(0.01 * i as f64) - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(
        error(&fitted) < 1e-12 * swing.max(1.0),
        "{} of {swing}",
        error(&fitted)
    );
    // The nodal stencil on the same cells is not: its rims fall where its nodes say.
    assert!(error(&nodal) > 1e-2 * swing, "{} of {swing}", error(&nodal));
}
