//! The oscillatory squeeze film with rupture and reformation (Ausas, Jai & Buscaglia,
//! J. Tribol. 131 (2009) 031702, §3) against its exact solution: the product film solver
//! stepped by backward Euler through rupture, an expanding and a receding cavity, and
//! reformation (docs/validation.md, "The oscillatory squeeze film").
//!
//! `cargo test --release --test squeeze -- --nocapture` prints the table of errors against
//! the mesh that docs/validation.md shows.

use std::sync::OnceLock;

use texopt::mesh::integrals::boundary_flows;
use texopt::mesh::{FilmState, Gap, Grid};
use texopt::model::film::Boundary;
use texopt::solve::{Method, Step};

/// The exact solution (docs/validation.md, "The oscillatory squeeze film"): 1-D on [0, 1],
/// u = 0, uniform gap h(t), p = p0 and θ = 1 at both ends, full film at t = 0, in texopt's
/// nondimensional film equation ∂x(h³∂x p) = 2∂t(hθ) (docs/model.md §3). Symmetric about
/// x = ½; L is the width of the full film at each end, the cavity is (L, 1 − L), Σ = 1 − L.
mod exact {
    use std::f64::consts::PI;
    use std::sync::OnceLock;

    /// The pressure at both ends.
    pub const P0: f64 = 0.025;
    const W: f64 = 4.0 * PI;

    /// h(t) = 0.125·cos(4πt) + 0.375 and its derivatives.
    pub fn h(t: f64) -> f64 {
        0.125 * (W * t).cos() + 0.375
    }
    pub fn dh(t: f64) -> f64 {
        -0.125 * W * (W * t).sin()
    }
    pub fn ddh(t: f64) -> f64 {
        -0.125 * W * W * (W * t).cos()
    }
    /// |ḧ| ≤ this.
    pub const DDH_MAX: f64 = 0.125 * W * W;

    /// The root of f on (a, b), f(a) and f(b) of opposite signs, by bisection to round-off.
    fn root(f: impl Fn(f64) -> f64, (mut a, mut b): (f64, f64)) -> f64 {
        let fa = f(a);
        assert!(fa * f(b) < 0.0, "no sign change on ({a}, {b})");
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if (f(m) < 0.0) == (fa < 0.0) {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    }

    /// Full film: p = p0 − (ḣ/h³)·x(1 − x) (∂x(h³∂x p) = 2ḣ with p(0) = p(1) = p0).
    pub fn p_full(x: f64, t: f64) -> f64 {
        P0 - dh(t) / h(t).powi(3) * x * (1.0 - x)
    }

    /// Rupture: the full film's minimum p(½) = p0 − ḣ/(4h³) reaches 0, ḣ = 4·p0·h³.
    pub fn t_rupture() -> f64 {
        root(|t| dh(t) - 4.0 * P0 * h(t).powi(3), (0.25, 0.26))
    }

    /// Expanding cavity: the front runs into full film, so JFO's mass balance leaves
    /// p = ∂x p = 0 there (Swift–Stieber) and L² = p0·h³/ḣ.
    pub fn l_expanding(t: f64) -> f64 {
        (P0 * h(t).powi(3) / dh(t)).sqrt()
    }

    /// The front stops where d(h³/ḣ)/dt = 0, i.e. 3ḣ² = h·ḧ.
    pub fn t_star() -> f64 {
        root(|t| 3.0 * dh(t).powi(2) - h(t) * ddh(t), (0.26, 0.374))
    }

    /// The time the expanding front passed L (the inverse of [`l_expanding`] on
    /// [t_rup, t*], where it falls from ½ to L*); the cavity keeps the content h(τ) it
    /// had there (no flux where p = 0 and u = 0).
    fn tau(l: f64, ts: &Times) -> f64 {
        if l <= ts.l_star {
            return ts.t_star;
        }
        if l >= 0.5 {
            return ts.t_rup;
        }
        root(|t| l_expanding(t) - l, (ts.t_rup, ts.t_star))
    }

    /// ∂x p at the front's full-film side, p = A(x − Σ) + (ḣ/h³)(x − Σ)² on [Σ, 1] with
    /// p(1) = p0: A = p0/L − ḣL/h³.
    pub fn slope(l: f64, t: f64) -> f64 {
        P0 / l - dh(t) * l / h(t).powi(3)
    }

    /// Receding front (JFO mass balance on the moving boundary, the content behind it
    /// h(τ(Σ)) < h): Σ̇·(h − h(τ)) = −(h³/2)·A, i.e.
    /// dL/dt = (p0·h³/L − ḣ·L) / (2·(h(t) − h(τ(L)))).
    fn dl_dt(t: f64, l: f64, ts: &Times) -> f64 {
        (P0 * h(t).powi(3) / l - dh(t) * l) / (2.0 * (h(t) - h(tau(l, ts))))
    }

    struct Times {
        t_rup: f64,
        t_star: f64,
        l_star: f64,
    }

    /// The solution's instants and the receding front L(t) on a uniform grid of times.
    pub struct Solution {
        pub t_rup: f64,
        pub t_star: f64,
        pub t_ref: f64,
        t0: f64,
        step: f64,
        l: Vec<f64>,
    }

    /// RK4 step of the receding front.
    const RK_STEP: f64 = 1e-5;

    /// The solution, computed once.
    pub fn solution() -> &'static Solution {
        static S: OnceLock<Solution> = OnceLock::new();
        S.get_or_init(receding_front)
    }

    /// Integrates the receding front from t* to reformation (L = ½). At t* the ODE is 0/0;
    /// a local analysis gives L − L* = γ·a·s²/2 with 2γ + √γ − 1 = 0, γ = ¼, a = L_e''(t*),
    /// s = t − t*: the integration starts from that at s = 1e-4.
    fn receding_front() -> Solution {
        let (t_rup, t_star) = (t_rupture(), t_star());
        let ts = Times {
            t_rup,
            t_star,
            l_star: l_expanding(t_star),
        };
        let e = 1e-4;
        let a = (l_expanding(t_star + e) - 2.0 * ts.l_star + l_expanding(t_star - e)) / (e * e);
        let s0 = 1e-4;
        let (t0, mut l) = (t_star + s0, ts.l_star + a * s0 * s0 / 8.0);
        let mut ls = vec![l];
        let dt = RK_STEP;
        while l < 0.5 {
            let t = t0 + (ls.len() - 1) as f64 * dt;
            let k1 = dl_dt(t, l, &ts);
            let k2 = dl_dt(t + 0.5 * dt, l + 0.5 * dt * k1, &ts);
            let k3 = dl_dt(t + 0.5 * dt, l + 0.5 * dt * k2, &ts);
            let k4 = dl_dt(t + dt, l + dt * k3, &ts);
            l += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            ls.push(l);
        }
        // Reformation where L crosses ½ (linear within the last RK step).
        let k = ls.len() - 1;
        let frac = (0.5 - ls[k - 1]) / (ls[k] - ls[k - 1]);
        let t_ref = t0 + (k as f64 - 1.0 + frac) * dt;
        Solution {
            t_rup,
            t_star,
            t_ref,
            t0,
            step: dt,
            l: ls,
        }
    }

    impl Solution {
        /// L(t), None while the film is full (t < t_rup, or t_ref ≤ t < t_rup + ½: the
        /// full film has no memory, so the solution is periodic with period ½).
        pub fn l(&self, t: f64) -> Option<f64> {
            if t < self.t_rup || t >= self.t_ref {
                None
            } else if t <= self.t_star {
                Some(l_expanding(t))
            } else if t < self.t0 {
                // Within s0 of t*: L − L* ≤ a·s0²/8 ≈ 1e-8.
                Some(self.l[0])
            } else {
                let r = (t - self.t0) / self.step;
                let k = (r.floor() as usize).min(self.l.len() - 2);
                let f = r - k as f64;
                Some(self.l[k] + f * (self.l[k + 1] - self.l[k]))
            }
        }

        /// The cavity's right edge Σ = 1 − L.
        pub fn sigma(&self, t: f64) -> Option<f64> {
            self.l(t).map(|l| 1.0 - l)
        }

        /// dΣ/dt by a central difference (for the time step's share of a tolerance).
        pub fn sigma_rate(&self, t: f64) -> f64 {
            let e = 1e-4;
            match (self.sigma(t - e), self.sigma(t + e)) {
                (Some(a), Some(b)) => (b - a) / (2.0 * e),
                _ => f64::INFINITY,
            }
        }

        /// The load W = ∫₀¹ p dx: p0 − ḣ/(6h³) in full film, 2·(A·L²/2 + ḣL³/(3h³)) with a
        /// cavity (A = 0 while it expands).
        pub fn load(&self, t: f64) -> f64 {
            let (h3, hd) = (h(t).powi(3), dh(t));
            match self.l(t) {
                None => P0 - hd / (6.0 * h3),
                Some(l) => {
                    let a = if t <= self.t_star { 0.0 } else { slope(l, t) };
                    2.0 * (a * l * l / 2.0 + hd * l.powi(3) / (3.0 * h3))
                }
            }
        }

        /// Total content ∫₀¹ φ dx: h on the full film, h(τ(x)) in the cavity.
        pub fn content(&self, t: f64) -> f64 {
            let Some(l) = self.l(t) else {
                return h(t);
            };
            let ts = Times {
                t_rup: self.t_rup,
                t_star: self.t_star,
                l_star: l_expanding(self.t_star),
            };
            // Cavity content over (L, ½) by the midpoint rule in L' (mirror on the right).
            let n = 4000;
            let d = (0.5 - l) / n as f64;
            let cavity: f64 = (0..n)
                .map(|k| h(tau(l + (k as f64 + 0.5) * d, &ts)).min(h(t)))
                .sum::<f64>()
                * d;
            2.0 * (l * h(t) + cavity)
        }
    }
}

use exact::{h, P0};

/// The run ends after reformation and the full film that follows it.
const T_END: f64 = 0.745;
/// Where the cavity's edge is compared: on (0.26, 0.72), clear of rupture (infinite front
/// speed) and of the last instants before reformation (front speed 10–30).
const SIGMA_TIMES: [f64; 8] = [0.27, 0.30, 0.35, 0.40, 0.50, 0.60, 0.65, 0.70];
/// Where the full film's pressure is compared: closing, opening, and after reformation.
const FULL_TIMES: [f64; 3] = [0.1, 0.2, 0.74];
/// The meshes refined together with the step (dt = dx/5).
const MESHES: [usize; 5] = [100, 200, 400, 800, 1600];

/// What a run measured.
#[derive(Debug)]
struct Run {
    n: usize,
    dt: f64,
    dx: f64,
    /// First step with a cavitated node, and the first step after it with none.
    t_rupture: f64,
    t_reform: f64,
    /// Rupture between steps: the pressure at x = ½, where the film ruptures (N even), in
    /// full film p0 − ḣ/(4h³), extrapolated to zero from the last two steps before rupture.
    t_rupture_p: f64,
    /// The pressure at x = ½ of the last two steps before rupture (the later first).
    p_mins: [f64; 2],
    /// Reformation between steps: the cavity's void ∫(h − φ) dx, which falls linearly to
    /// zero as the cavity closes, extrapolated to zero from its last two steps.
    t_reform_void: f64,
    /// The void of the last two steps with a cavity (the later first).
    voids: [f64; 2],
    /// (t, Σ from the right edge, Σ mirrored from the left edge) at [`SIGMA_TIMES`].
    sigma: Vec<(f64, f64, f64)>,
    /// (t, max |p − p_exact| / max |p_exact − p0|, numerical load) at [`FULL_TIMES`].
    full: Vec<(f64, f64, f64)>,
    /// Largest |Δ∫φ − dt·(inflow − outflow)| of a step relative to the content ∫φ. (Relative
    /// to the step's flows it is round-off too, but that ratio grows without bound where the
    /// flows through the ends reverse, ≈ 0.558.)
    mass: f64,
}

/// The cavity's edges: the first and last cavitated interior node (the front lies in the
/// control volume of the last node that is not full); as Σ (the right edge) and the left
/// edge mirrored. None without a cavity. The cavity is one interval (the exact solution's):
/// a split one fails the run.
fn cavity_edges(g: &Grid, state: &FilmState) -> Option<(f64, f64)> {
    let cav: Vec<usize> = (1..g.n1).filter(|&i| !state.pressurised[i]).collect();
    let (&first, &last) = (cav.first()?, cav.last()?);
    assert_eq!(cav.len(), last - first + 1, "the cavity split: {cav:?}");
    Some((g.x(last), 1.0 - g.x(first)))
}

/// The change of content over the interior control volumes (width dx each), summed node
/// by node (no cancellation between two large sums).
fn content_change(g: &Grid, phi: &[f64], old: &[f64]) -> f64 {
    (1..g.n1).map(|i| phi[i] - old[i]).sum::<f64>() * g.dx
}

/// The load ∫₀¹ p dx by the trapezoidal rule over the nodes.
fn load(g: &Grid, p: &[f64]) -> f64 {
    (p[1..g.n1].iter().sum::<f64>() + 0.5 * (p[0] + p[g.n1])) * g.dx
}

/// Max |p − p_full(x, t)| / max |p_full − p0| over the nodes.
fn full_film_error(g: &Grid, p: &[f64], t: f64) -> f64 {
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    for (i, &pi) in p.iter().enumerate() {
        let pe = exact::p_full(g.x(i), t);
        err = err.max((pi - pe).abs());
        scale = scale.max((pe - P0).abs());
    }
    err / scale
}

impl Run {
    fn new(g: &Grid, dt: f64) -> Self {
        Run {
            n: g.n1,
            dt,
            dx: g.dx,
            t_rupture: f64::NAN,
            t_reform: f64::NAN,
            t_rupture_p: f64::NAN,
            p_mins: [0.0; 2],
            t_reform_void: f64::NAN,
            voids: [0.0; 2],
            sigma: Vec::new(),
            full: Vec::new(),
            mass: 0.0,
        }
    }

    /// Measures the state solved at step s (t = s·dt) from `phi_old`.
    fn record(&mut self, s: usize, g: &Grid, gap: &Gap, state: &FilmState, phi_old: &[f64]) {
        let (dt, t) = (self.dt, s as f64 * self.dt);
        let change = content_change(g, &state.phi, phi_old);
        let (inflow, outflow) = boundary_flows(g, gap, 0.0, (0.0, 0.0), state);
        let defect = change - dt * (inflow - outflow);
        let held = state.phi[1..g.n1].iter().sum::<f64>() * g.dx;
        self.mass = self.mass.max(defect.abs() / held);
        let edges = cavity_edges(g, state);
        match edges {
            Some(_) => {
                if self.t_rupture.is_nan() {
                    self.t_rupture = t;
                    let [p1, p2] = self.p_mins;
                    self.t_rupture_p = t - dt + dt * p1 / (p2 - p1);
                }
                let void = (1..g.n1)
                    .filter(|&i| !state.pressurised[i])
                    .map(|i| gap.base[i] - state.phi[i])
                    .sum::<f64>()
                    * g.dx;
                self.voids = [void, self.voids[0]];
            }
            None if !self.t_rupture.is_nan() && self.t_reform.is_nan() => {
                self.t_reform = t;
                let [v1, v2] = self.voids;
                self.t_reform_void = t - dt + dt * v1 / (v2 - v1);
            }
            None if self.t_rupture.is_nan() => {
                self.p_mins = [state.p[g.n1 / 2], self.p_mins[0]];
            }
            None => {}
        }
        let at = |times: &[f64]| times.iter().any(|&c| s == (c / dt).round() as usize);
        if at(&SIGMA_TIMES) {
            let (right, left) = edges.unwrap_or_else(|| panic!("no cavity at t = {t}"));
            self.sigma.push((t, right, left));
        }
        if at(&FULL_TIMES) {
            assert!(edges.is_none(), "N = {}: a cavity at t = {t}", g.n1);
            let err = full_film_error(g, &state.p, t);
            self.full.push((t, err, load(g, &state.p)));
        }
    }
}

/// Marches N cells with step dt from the full film at t = 0 to [`T_END`] by backward Euler
/// with the product's film solver, measuring as it goes.
fn simulate(n: usize, dt: f64) -> Run {
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
    state.p.fill(P0);
    let boundary = Boundary {
        u: 0.0,
        u_rough: 0.0,
        p_left: P0,
        p_right: P0,
        // Flooded ends: capped at the gap, θ = 1.
        phi_inlet: 10.0,
        // The film cavitates at 0, below the ambient p0 of its ends.
        cavity_left: 0.0,
        cavity_right: 0.0,
    };
    let mut solver = Method::Direct.solver();
    let mut run = Run::new(&g, dt);
    let mut phi_old = state.phi.clone();
    for s in 1..=(T_END / dt).round() as usize {
        let t = s as f64 * dt;
        phi_old.copy_from_slice(&state.phi);
        gap.base.fill(h(t));
        let step = Step {
            grid: &g,
            gap: &gap,
            phi_old: &phi_old,
            inv_dt: 1.0 / dt,
            boundary,
            ring: None,
        };
        let mut z = 0.0;
        if let Err(e) = solver.solve(&step, &mut state, &mut z) {
            panic!("N = {n}, dt = {dt}: the film solve at t = {t} failed: {e}");
        }
        run.record(s, &g, &gap, &state, &phi_old);
    }
    run
}

/// The run of mesh k of [`MESHES`] (dt = dx/5), computed once for every test.
fn run(k: usize) -> &'static Run {
    static RUNS: [OnceLock<Run>; MESHES.len()] = [const { OnceLock::new() }; MESHES.len()];
    RUNS[k].get_or_init(|| {
        let n = MESHES[k];
        simulate(n, 0.2 / n as f64)
    })
}

/// The largest error of Σ over [`SIGMA_TIMES`] (both edges).
fn sigma_error(r: &Run) -> f64 {
    let sol = exact::solution();
    r.sigma
        .iter()
        .map(|&(t, right, left)| {
            let e = sol.sigma(t).unwrap();
            (right - e).abs().max((left - e).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_exact_solution_reproduces_the_derived_numbers() {
    let sol = exact::solution();
    assert!((sol.t_rup - 0.250079157).abs() < 1e-9, "{}", sol.t_rup);
    assert!((sol.t_star - 0.314825861).abs() < 1e-9, "{}", sol.t_star);
    assert!((sol.t_ref - 0.7323899).abs() < 2e-7, "{}", sol.t_ref);
    assert!((1.0 - exact::l_expanding(sol.t_star) - 0.976992294).abs() < 1e-9);
    // (t, Σ, W) of the table derived independently (pure Python, the same formulas).
    let table = [
        (0.2505, 0.801053, 0.003316),
        (0.26, 0.955193, 0.000747),
        (0.28, 0.972628, 0.000456),
        (0.30, 0.976416, 0.000393),
        (0.35, 0.976317, 0.000418),
        (0.40, 0.973219, 0.000534),
        (0.45, 0.967990, 0.000707),
        (0.50, 0.960913, 0.000977),
        (0.55, 0.951506, 0.001538),
        (0.60, 0.937223, 0.003310),
        (0.65, 0.909208, 0.012062),
        (0.70, 0.823062, 0.087415),
        (0.72, 0.706363, 0.288948),
        (0.73, 0.559769, 0.689540),
    ];
    for (t, sigma, w) in table {
        let s = sol.sigma(t).unwrap();
        assert!((s - sigma).abs() < 2e-6, "Σ({t}) = {s}, table {sigma}");
        let wl = sol.load(t);
        assert!((wl - w).abs() < 1e-6 + 1e-5 * w, "W({t}) = {wl}, table {w}");
    }
    for (t, w) in [(0.1, 3.543422), (0.2, 7.516008), (0.74, 2.100335)] {
        assert!(sol.sigma(t).is_none(), "a cavity at t = {t}");
        assert!((sol.load(t) - w).abs() < 1e-6, "W({t}) = {}", sol.load(t));
    }
}

/// An independent check of the receding front's ODE: the total content it implies changes
/// only by the flow out of both ends, d∫φ/dt = h³·∂x p(1), with ∂x p(1) = A + 2ḣL/h³.
#[test]
fn the_exact_solution_conserves_mass() {
    let sol = exact::solution();
    for t in [0.29, 0.40, 0.55, 0.70] {
        let e = 1e-4;
        let rate = (sol.content(t + e) - sol.content(t - e)) / (2.0 * e);
        let l = sol.l(t).unwrap();
        let a = if t <= sol.t_star {
            0.0
        } else {
            exact::slope(l, t)
        };
        let h3 = h(t).powi(3);
        let flow = h3 * (a + 2.0 * exact::dh(t) * l / h3);
        assert!(
            (rate - flow).abs() < 1e-4 * flow.abs().max(0.01),
            "t = {t}: d∫φ/dt = {rate}, end flows {flow}"
        );
    }
}

/// Backward Euler's discrete ḣ is the mean over the step, ḣ(t − dt/2) to O(dt²), and the
/// 3-point stencil holds the parabola exactly: the film ruptures dt/2 late, and shows it at
/// the first step at or after t_rup + dt/2.
#[test]
fn the_film_ruptures_half_a_step_late() {
    let sol = exact::solution();
    for k in 0..MESHES.len() {
        let r = run(k);
        let lag = r.t_rupture_p - sol.t_rup;
        assert!(
            (lag - 0.5 * r.dt).abs() <= 0.01 * r.dt,
            "N = {}: p(½) reaches 0 at {} (exact {}, dt {})",
            r.n,
            r.t_rupture_p,
            sol.t_rup,
            r.dt
        );
        let first = r.t_rupture - sol.t_rup;
        assert!(
            first >= 0.5 * r.dt - 1e-9 && first < 1.5 * r.dt,
            "N = {}: first cavitated step at {} (exact {}, dt {})",
            r.n,
            r.t_rupture,
            sol.t_rup,
            r.dt
        );
    }
}

/// Both edges of the cavity in the last cavitated node's control volume (±dx/2), widened by
/// a quarter cell and the distance the front moves in a step.
#[test]
fn the_cavity_edges_follow_the_exact_front() {
    let sol = exact::solution();
    for k in 0..MESHES.len() {
        let r = run(k);
        assert_eq!(r.sigma.len(), SIGMA_TIMES.len());
        for &(t, right, left) in &r.sigma {
            let e = sol.sigma(t).unwrap();
            let tol = 0.75 * r.dx + sol.sigma_rate(t).abs() * r.dt;
            assert!(
                (right - e).abs() <= tol && (left - e).abs() <= tol,
                "N = {}, t = {t}: Σ = {right} (right), {left} (left), exact {e}, tolerance {tol}",
                r.n
            );
        }
    }
}

/// The cavity closes within the step that holds t_ref: its void, extrapolated to zero,
/// within a tenth of a step of t_ref (seen: ≤ 0.04 dt), and the first step without a
/// cavity the one after.
#[test]
fn the_cavity_closes_at_the_exact_reformation_instant() {
    let sol = exact::solution();
    for k in 0..MESHES.len() {
        let r = run(k);
        assert!(
            (r.t_reform_void - sol.t_ref).abs() <= 0.1 * r.dt,
            "N = {}: the void vanishes at {} (exact {}, dt {})",
            r.n,
            r.t_reform_void,
            sol.t_ref,
            r.dt
        );
        let lag = r.t_reform - sol.t_ref;
        assert!(
            lag > 0.0 && lag <= r.dt,
            "N = {}: first step without a cavity {} (exact {}, dt {})",
            r.n,
            r.t_reform,
            sol.t_ref,
            r.dt
        );
    }
}

/// Every step's change of content equals the flows through the ends to round-off of the
/// content (seen: ≤ 1.2 ε at every mesh).
#[test]
fn mass_is_conserved_every_step() {
    for k in 0..MESHES.len() {
        let r = run(k);
        println!(
            "N = {}: largest mass defect of a step / ∫φ = {:.2e}",
            r.n, r.mass
        );
        assert!(
            r.mass <= 8.0 * f64::EPSILON,
            "N = {}: mass defect {:e} of the content",
            r.n,
            r.mass
        );
    }
}

/// In full film the discrete ḣ is ḣ(ξ) for some ξ in the step, and the stencil holds the
/// parabola exactly: the error relative to |p − p0| is at most dt·max|ḧ|/|ḣ(t)|. The load
/// adds the trapezoidal rule's error on the parabola, dx²·|W − p0| (with a tenth for
/// round-off). After reformation the film has no memory: the same parabola.
#[test]
fn the_full_film_pressure_is_the_exact_parabola() {
    let sol = exact::solution();
    for k in 0..MESHES.len() {
        let r = run(k);
        assert_eq!(r.full.len(), FULL_TIMES.len());
        for &(t, err, w) in &r.full {
            let tol = r.dt * exact::DDH_MAX / exact::dh(t).abs();
            assert!(err <= tol, "N = {}, t = {t}: error {err:e} > {tol:e}", r.n);
            let we = sol.load(t);
            assert!(
                (w - we).abs() <= (tol + 1.1 * r.dx * r.dx) * (we - P0).abs(),
                "N = {}, t = {t}: load {w}, exact {we}",
                r.n
            );
        }
    }
}

/// Mesh and step refined together (dt = dx/5): the errors of rupture, reformation and the
/// cavity's edge fall at first order or faster. Prints the table of docs/validation.md.
#[test]
fn the_errors_converge_with_mesh_and_step() {
    let sol = exact::solution();
    println!("| N | dt | rupture | reformation | Σ(0.30) | Σ(0.50) | Σ(0.70) | max Σ error / dx |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut errs = Vec::new();
    for k in 0..MESHES.len() {
        let r = run(k);
        let sig = |t: f64| {
            let &(_, right, _) = r.sigma.iter().find(|s| (s.0 - t).abs() < 1e-9).unwrap();
            format!("{right:.5} ({:+.1e})", right - sol.sigma(t).unwrap())
        };
        let e = [
            r.t_rupture_p - sol.t_rup,
            r.t_reform_void - sol.t_ref,
            sigma_error(r),
        ];
        println!(
            "| {} | {:.3e} | {:.7} ({:+.1e}) | {:.7} ({:+.1e}) | {} | {} | {} | {:.2e} ({:.2}) |",
            r.n,
            r.dt,
            r.t_rupture_p,
            e[0],
            r.t_reform_void,
            e[1],
            sig(0.30),
            sig(0.50),
            sig(0.70),
            e[2],
            e[2] / r.dx
        );
        errs.push(e);
    }
    println!(
        "| exact | | {:.7} | {:.7} | {:.5} | {:.5} | {:.5} | |",
        sol.t_rup,
        sol.t_ref,
        sol.sigma(0.30).unwrap(),
        sol.sigma(0.50).unwrap(),
        sol.sigma(0.70).unwrap()
    );
    let refinement = (MESHES[MESHES.len() - 1] / MESHES[0]) as f64;
    // First order divides each error by `refinement` (16): ask for at least a third of it,
    // and for every refinement to lower the error.
    for (c, name) in ["rupture", "reformation", "Σ"].iter().enumerate() {
        let seq: Vec<f64> = errs.iter().map(|e: &[f64; 3]| e[c].abs()).collect();
        assert!(
            seq[0] / seq[seq.len() - 1] >= refinement / 3.0 && seq.windows(2).all(|w| w[1] < w[0]),
            "{name}: errors {seq:?} on N = {MESHES:?}"
        );
    }
}
