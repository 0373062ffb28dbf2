//! How the film's face fluxes converge across a pocket's rim much deeper than the film
//! (results/rim_1d/): `texopt-lab rim-1d`.
//!
//! A steady one-dimensional full film, liner speed u = 1, p = 0 at both ends of [0, 1], over a
//! land of gap h_land(x) with one groove of depth 20 (the land's gap 1: depth/C = 20, the
//! deepest the issue of deep pockets asks for). Per unit width the flux through any section
//! is q = (u/2)·h − (h³/2)·dp/dx (docs/model.md §3, the scaled film), constant along x, so
//!
//! ```text
//! p(x) = ∫₀ˣ (u·h − 2q)/h³ dx,   q = u·∫h⁻² / (2·∫h⁻³)   (∫ over [0, 1]).
//! ```
//!
//! Two grooves: a rectangular one on a flat land (the integrals in closed form: the answer is
//! exact), and a half-ellipse one, the section of texopt's pocket, under a parabolic ring
//! face (the integrals by adaptive quadrature to 1e-13). Each on N cells, its edges at
//! 0.3137 and 0.5071 (on no node of these meshes), by four two-point fluxes through the face
//! between nodes i and i + 1, F = a − g·(p_{i+1} − p_i):
//!
//! - **nodal** (texopt's stencil today): g = h_f³/(2·dx) with h_f the mean of the two nodal
//!   gaps, a = (u/2)·h_i (upwind content);
//! - **face resistance**: g = 1/(2·∫h⁻³) over [x_i, x_{i+1}], the exact series resistance of
//!   the face's gap, a as nodal;
//! - **face resistance, cell content**: g as above, a = (u/2)·(mean gap of the upstream
//!   control volume [x_i − dx/2, x_i + dx/2]), the cut cell's film volume;
//! - **exact two-point**: g as above, a = (u/2)·∫h⁻²/∫h⁻³ over the face's interval, which
//!   makes the discrete flux the exact one for any gap (so its error is round-off): the
//!   limit a sub-cell model can reach where the film is full.
//!
//! Printed and written: the relative error of q and of the nodal pressures (max norm over
//! max |p|) against N, and the observed order between successive N.

use std::fmt::Write as _;
use std::fs;

const U: f64 = 1.0;
const LAND: f64 = 1.0;
const DEPTH: f64 = 20.0;
const EDGES: (f64, f64) = (0.3137, 0.5071);
/// The ring face's parabola: h_land = 1 + CROWN·(2x − 1)² in the curved case.
const CROWN: f64 = 2.0;
const MESHES: [usize; 7] = [25, 50, 100, 200, 400, 800, 1600];

/// The gap along x.
#[derive(Clone, Copy)]
enum Groove {
    /// Depth DEPTH on [EDGES], flat land of gap LAND.
    Rectangular,
    /// A half-ellipse DEPTH·√(1 − s²) across [EDGES] under the land LAND + CROWN·(2x − 1)².
    HalfEllipse,
}

impl Groove {
    fn name(self) -> &'static str {
        match self {
            Groove::Rectangular => "rectangular groove, flat land",
            Groove::HalfEllipse => "half-ellipse groove, parabolic ring face",
        }
    }

    fn h(self, x: f64) -> f64 {
        let (a, b) = EDGES;
        match self {
            Groove::Rectangular => LAND + if (a..b).contains(&x) { DEPTH } else { 0.0 },
            Groove::HalfEllipse => {
                let s = (2.0 * x - a - b) / (b - a);
                let pocket = if s.abs() < 1.0 {
                    DEPTH * (1.0 - s * s).sqrt()
                } else {
                    0.0
                };
                LAND + CROWN * (2.0 * x - 1.0).powi(2) + pocket
            }
        }
    }

    /// ∫ h^(−n) over [x0, x1] (n = 1 for the film's volume, −2 and −3 as written below).
    fn integral(self, x0: f64, x1: f64, power: i32) -> f64 {
        let f = |x: f64| self.h(x).powi(power);
        // Split at the edges: the integrand jumps (rectangular) or has an infinite slope
        // (half-ellipse) there.
        let mut cuts = vec![x0];
        for e in [EDGES.0, EDGES.1] {
            if x0 < e && e < x1 {
                cuts.push(e);
            }
        }
        cuts.push(x1);
        cuts.windows(2)
            .map(|w| match self {
                Groove::Rectangular => (w[1] - w[0]) * f(0.5 * (w[0] + w[1])),
                Groove::HalfEllipse => adaptive_simpson(&f, w[0], w[1], 1e-13, 40),
            })
            .sum()
    }
}

fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, depth: u32) -> f64 {
    let m = 0.5 * (a + b);
    let (fa, fm, fb) = (f(a), f(m), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_step(f, (a, fa), (m, fm), (b, fb), whole, tol, depth)
}

fn simpson_step(
    f: &dyn Fn(f64) -> f64,
    (a, fa): (f64, f64),
    (m, fm): (f64, f64),
    (b, fb): (f64, f64),
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol {
        return left + right + delta / 15.0;
    }
    simpson_step(f, (a, fa), (lm, flm), (m, fm), left, 0.5 * tol, depth - 1)
        + simpson_step(f, (m, fm), (rm, frm), (b, fb), right, 0.5 * tol, depth - 1)
}

/// The two-point fluxes compared.
#[derive(Clone, Copy)]
enum Flux {
    Nodal,
    FaceResistance,
    CellContent,
    ExactTwoPoint,
}

const FLUXES: [Flux; 4] = [
    Flux::Nodal,
    Flux::FaceResistance,
    Flux::CellContent,
    Flux::ExactTwoPoint,
];

impl Flux {
    fn name(self) -> &'static str {
        match self {
            Flux::Nodal => "nodal",
            Flux::FaceResistance => "face resistance",
            Flux::CellContent => "face resistance, cell content",
            Flux::ExactTwoPoint => "exact two-point",
        }
    }

    /// (a, g) of the face between nodes i and i + 1 on n cells.
    fn face(self, groove: Groove, n: usize, i: usize) -> (f64, f64) {
        let dx = 1.0 / n as f64;
        let (x0, x1) = (i as f64 * dx, (i + 1) as f64 * dx);
        let resistance = || groove.integral(x0, x1, -3);
        match self {
            Flux::Nodal => {
                let hf = 0.5 * (groove.h(x0) + groove.h(x1));
                (0.5 * U * groove.h(x0), hf * hf * hf / (2.0 * dx))
            }
            Flux::FaceResistance => (0.5 * U * groove.h(x0), 0.5 / resistance()),
            Flux::CellContent => {
                let (c0, c1) = ((x0 - 0.5 * dx).max(0.0), x0 + 0.5 * dx);
                let volume = groove.integral(c0, c1, 1) / (c1 - c0);
                (0.5 * U * volume, 0.5 / resistance())
            }
            Flux::ExactTwoPoint => {
                let r = resistance();
                (0.5 * U * groove.integral(x0, x1, -2) / r, 0.5 / r)
            }
        }
    }
}

/// The discrete film: nodal pressures (p_0 = p_n = 0) and the flux q through the first face.
fn solve(groove: Groove, flux: Flux, n: usize) -> (Vec<f64>, f64) {
    let faces: Vec<(f64, f64)> = (0..n).map(|i| flux.face(groove, n, i)).collect();
    // Node i (1..n−1): F_{i+1/2} = F_{i−1/2}, a tridiagonal system in p_1..p_{n−1}.
    let m = n - 1;
    let (mut lower, mut diag, mut upper, mut rhs) =
        (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    for k in 0..m {
        let (aw, gw) = faces[k];
        let (ae, ge) = faces[k + 1];
        diag[k] = gw + ge;
        lower[k] = -gw;
        upper[k] = -ge;
        rhs[k] = aw - ae;
    }
    let mut p = vec![0.0; n + 1];
    p[1..n].copy_from_slice(&thomas(lower, diag, upper, rhs));
    let (a0, g0) = faces[0];
    let q = a0 - g0 * (p[1] - p[0]);
    (p, q)
}

/// The exact film: q and p at the nodes of n cells.
fn exact(groove: Groove, n: usize) -> (Vec<f64>, f64) {
    let q = U * groove.integral(0.0, 1.0, -2) / (2.0 * groove.integral(0.0, 1.0, -3));
    let dx = 1.0 / n as f64;
    let mut p = vec![0.0; n + 1];
    for i in 0..n {
        let (x0, x1) = (i as f64 * dx, (i + 1) as f64 * dx);
        p[i + 1] = p[i] + U * groove.integral(x0, x1, -2) - 2.0 * q * groove.integral(x0, x1, -3);
    }
    (p, q)
}

/// The steady Elrod–Adams film on n cells (p_c = 0, flooded at x = 0): the nodal pressures,
/// the flux through the first face and the share of the nodes cavitated. The Couette content
/// through the face east of node i is θ_i·K_i: K_i = h_i (`Flux::Nodal`, with its nodal
/// conductance) or the face's ∫h⁻²/∫h⁻³ (`Flux::ExactTwoPoint`, with its resistance), both
/// equal to the full film's; in the cavitated film the content carried is then θ·K. Solved by
/// active sets: each a tridiagonal system in p (full nodes) and θ (cavitated ones).
fn solve_cavitating(groove: Groove, flux: Flux, n: usize) -> Result<(Vec<f64>, f64, f64), String> {
    // (K_i, g_i) with K_i = 2a_i/u: the face's full-film content.
    let faces: Vec<(f64, f64)> = (0..n)
        .map(|i| flux.face(groove, n, i))
        .map(|(a, g)| (2.0 * a / U, g))
        .collect();
    let mut full = vec![true; n + 1];
    let (p, _) = active_set(&faces, None, &mut full, 10 * n).ok_or_else(|| {
        format!(
            "{}: the active set did not settle on {n} cells",
            flux.name()
        )
    })?;
    let q = 0.5 * U * faces[0].0 - faces[0].1 * p[1];
    let cavitated = full[1..n].iter().filter(|&&f| !f).count() as f64 / (n - 1) as f64;
    Ok((p, q, cavitated))
}

/// The storage of a time step: per node its storage gap s_i and old content, and dx/dt.
pub(crate) struct Storage<'a> {
    pub s: &'a [f64],
    pub old: &'a [f64],
    pub per_dt: f64,
}

/// The Elrod–Adams film of one problem on the faces (K_i, g_i) east of each node (n faces,
/// p = 0 at both ends, θ_0 = 1: a flooded inlet), steady or with `storage`, from the active set `full`
/// (updated): node i's balance (u/2)(θ_i K_i − θ_{i−1} K_{i−1}) − g_i (p_{i+1} − p_i) +
/// g_{i−1} (p_i − p_{i−1}) (+ (θ_i s_i − old_i)·dx/dt) = 0, unknown p_i where full, θ_i
/// where cavitated, one tridiagonal system per active set, at most `tries` of them. Returns
/// the nodal pressures and the interior unknowns, None if the active set did not settle.
pub(crate) fn active_set(
    faces: &[(f64, f64)],
    storage: Option<Storage>,
    full: &mut [bool],
    tries: usize,
) -> Option<(Vec<f64>, Vec<f64>)> {
    active_set_from(faces, storage, full, tries, 1.0)
}

/// [`active_set`] with the inlet node's saturation θ_0 = `theta_in` (its pressure 0).
pub(crate) fn active_set_from(
    faces: &[(f64, f64)],
    storage: Option<Storage>,
    full: &mut [bool],
    tries: usize,
    theta_in: f64,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = faces.len();
    let m = n - 1;
    let store = storage.as_ref().map_or(0.0, |st| st.per_dt);
    let stored = |i: usize| {
        storage
            .as_ref()
            .map_or((0.0, 0.0), |st| (st.s[i], st.old[i]))
    };
    for _ in 0..tries {
        let (mut lower, mut diag, mut upper, mut rhs) =
            (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        for r in 0..m {
            let i = r + 1;
            let ((k, g), (kw, gw)) = (faces[i], faces[i - 1]);
            let (si, old) = stored(i);
            rhs[r] += old * store;
            // Own unknown: p_i (its constant θ_i K_i = K_i moved right) or θ_i.
            if full[i] {
                diag[r] = g + gw;
                rhs[r] -= 0.5 * U * k + si * store;
            } else {
                diag[r] = 0.5 * U * k + si * store;
            }
            // Upstream: the inlet (θ_0, p_0 = 0), a full node (θ = 1, its p) or a
            // cavitated one (its θ, p = 0).
            if i == 1 {
                rhs[r] += 0.5 * U * kw * theta_in;
            } else if full[i - 1] {
                rhs[r] += 0.5 * U * kw;
                lower[r] = -gw;
            } else {
                lower[r] = -0.5 * U * kw;
            }
            // Downstream: only a full node's pressure enters (p_n = 0).
            if i < m && full[i + 1] {
                upper[r] = -g;
            }
        }
        let x = thomas(lower, diag, upper, rhs);
        let mut p = vec![0.0; n + 1];
        let mut changes = 0;
        for (r, &xr) in x.iter().enumerate() {
            let i = r + 1;
            // A full node whose pressure fell below p_c, or a cavitated one whose θ rose
            // above 1, changes sides.
            let (value, leaves) = if full[i] {
                (xr, xr < 0.0)
            } else {
                (0.0, xr > 1.0)
            };
            p[i] = value;
            if leaves {
                full[i] = !full[i];
                changes += 1;
            }
        }
        if changes == 0 {
            return Some((p, x));
        }
    }
    None
}

/// " (order)" observed from the error `prev` on the previous mesh to `e` on this one, halved
/// cells, or nothing where either is round-off or absent.
pub(crate) fn observed_order(e: f64, prev: Option<f64>) -> String {
    match prev {
        Some(pr) if e > 1e-12 && pr > 1e-12 => format!(" ({:.2})", (pr / e).log2()),
        _ => String::new(),
    }
}

/// Two relative errors as a table's cells, each with the order observed from the previous
/// mesh's (`last`, then set to these).
pub(crate) fn error_cells(md: &mut String, (a, b): (f64, f64), last: &mut Option<(f64, f64)>) {
    let (la, lb) = last.map_or((None, None), |(x, y)| (Some(x), Some(y)));
    let _ = write!(
        md,
        " {a:.2e}{} | {b:.2e}{} |",
        observed_order(a, la),
        observed_order(b, lb)
    );
    *last = Some((a, b));
}

/// Writes a study's report to results/`study`/README.md and prints it.
pub(crate) fn write_report(study: &str, md: &str) -> Result<(), String> {
    let dir = format!("results/{study}");
    fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    fs::write(format!("{dir}/README.md"), md).map_err(|e| e.to_string())?;
    print!("{md}");
    eprintln!("wrote {dir}/README.md");
    Ok(())
}

/// Solves the tridiagonal system (lower, diag, upper)·x = rhs (Thomas algorithm).
pub(crate) fn thomas(
    lower: Vec<f64>,
    mut diag: Vec<f64>,
    upper: Vec<f64>,
    mut rhs: Vec<f64>,
) -> Vec<f64> {
    let m = diag.len();
    for k in 1..m {
        let w = lower[k] / diag[k - 1];
        diag[k] -= w * upper[k - 1];
        rhs[k] -= w * rhs[k - 1];
    }
    let mut x = vec![0.0; m];
    for k in (0..m).rev() {
        let next = if k + 1 < m { x[k + 1] } else { 0.0 };
        x[k] = (rhs[k] - upper[k] * next) / diag[k];
    }
    x
}

/// The cavitating film over the half-ellipse groove: nodal and exact two-point content
/// against the exact two-point film on REFERENCE_CELLS cells.
fn cavitating() -> Result<String, String> {
    const REFERENCE_CELLS: usize = 102_400;
    let groove = Groove::HalfEllipse;
    let load = |p: &[f64]| p.iter().sum::<f64>() / (p.len() - 1) as f64;
    let (pr, qr, cr) = solve_cavitating(groove, Flux::ExactTwoPoint, REFERENCE_CELLS)?;
    let (pn, qn, _) = solve_cavitating(groove, Flux::Nodal, REFERENCE_CELLS)?;
    let (wr, wn) = (load(&pr), load(&pn));
    let mut md = format!(
        "\n## Cavitating: half-ellipse groove, parabolic ring face, p_c = 0\n\n\
         The steady Elrod–Adams film (flooded inlet), the Couette content through a face θ·K \
         with K the nodal gap (nodal) or the face's ∫h⁻²/∫h⁻³ (exact two-point). Reference: \
         exact two-point on {REFERENCE_CELLS} cells, q = {qr:.8}, load ∫p = {wr:.8}, {:.1} % of \
         the nodes cavitated; nodal there is {:+.1e} in q and {:+.1e} in the load from it. \
         Relative errors (observed order):\n\n\
         | N | nodal: q | load | exact two-point: q | load |\n|---|---|---|---|---|\n",
        100.0 * cr,
        qn / qr - 1.0,
        wn / wr - 1.0
    );
    let mut last = [None; 2];
    for n in MESHES {
        let _ = write!(md, "| {n} |");
        for (k, f) in [Flux::Nodal, Flux::ExactTwoPoint].into_iter().enumerate() {
            let (p, q, _) = solve_cavitating(groove, f, n)?;
            let errors = ((q / qr - 1.0).abs(), (load(&p) / wr - 1.0).abs());
            error_cells(&mut md, errors, &mut last[k]);
        }
        let _ = writeln!(md);
    }
    Ok(md)
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let mut md = String::from(
        "# A pocket's rim on the film's mesh: four two-point fluxes against the exact film\n\n\
         `texopt-lab rim-1d` (seconds): a steady one-dimensional full film over one groove 20 \
         times deeper than the land's gap, on N cells, against the exact solution \
         (lab/src/studies/rim_1d.rs says how). Relative errors of the flux q and of the nodal \
         pressures (max norm over max |p|), and in brackets the observed order from the \
         previous N.\n",
    );
    for groove in [Groove::Rectangular, Groove::HalfEllipse] {
        let _ = writeln!(md, "\n## {}\n", groove.name());
        let _ = write!(md, "| N |");
        for f in FLUXES {
            let _ = write!(md, " {}: q | p |", f.name());
        }
        let _ = writeln!(md, "\n|---|{}", "---|---|".repeat(FLUXES.len()));
        let mut last: Vec<Option<(f64, f64)>> = vec![None; FLUXES.len()];
        for n in MESHES {
            let (pe, qe) = exact(groove, n);
            let pmax = pe.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let _ = write!(md, "| {n} |");
            for (k, f) in FLUXES.into_iter().enumerate() {
                let (p, q) = solve(groove, f, n);
                let eq = (q / qe - 1.0).abs();
                let ep = p
                    .iter()
                    .zip(&pe)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                    / pmax;
                error_cells(&mut md, (eq, ep), &mut last[k]);
            }
            let _ = writeln!(md);
        }
    }
    md.push_str(&cavitating()?);
    md.push_str(
        "\nWhat it says. The nodal flux, texopt's today, converges at about first order in the \
         pressures, erratically in q, as the rim's position against the nodes changes with N. \
         Taking the face's exact resistance alone makes it worse (by orders of magnitude on the \
         rectangular groove): the Couette content through the face must be the one the same \
         resistance implies. The exact two-point flux, whose content is ∫h⁻²/∫h⁻³ over the \
         face, is exact for the full film on every mesh, rim or not; carried as θ·∫h⁻²/∫h⁻³ \
         into the cavitated film it stays one to three orders of magnitude closer to the \
         converged film than the nodal flux on every mesh, and both meet in the limit. What \
         this steady film does not test: the storage of a moving texture (a cut cell's film \
         volume), and two dimensions.\n",
    );
    write_report("rim_1d", &md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exact_two_point_flux_reproduces_the_exact_film() {
        // By construction its discrete flux is the exact one: the solve returns the exact
        // film to round-off on any mesh, which checks the solve and the integrals together.
        for groove in [Groove::Rectangular, Groove::HalfEllipse] {
            let (pe, qe) = exact(groove, 50);
            let (p, q) = solve(groove, Flux::ExactTwoPoint, 50);
            assert!((q / qe - 1.0).abs() < 1e-11, "{q} {qe}");
            let pmax = pe.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in p.iter().zip(&pe) {
                assert!((a - b).abs() < 1e-10 * pmax, "{a} {b}");
            }
        }
    }

    #[test]
    fn both_contents_meet_in_the_cavitating_films_limit() {
        // Nodal and exact two-point content are two discretisations of one film: on fine
        // cells their flux and load agree, no pressure is below p_c, and part of the film
        // (the groove's entry, the ring face's divergent half) is cavitated.
        let g = Groove::HalfEllipse;
        let (pn, qn, _) = solve_cavitating(g, Flux::Nodal, 25_600).unwrap();
        let (pe, qe, cavitated) = solve_cavitating(g, Flux::ExactTwoPoint, 25_600).unwrap();
        assert!((qn / qe - 1.0).abs() < 1e-4, "{qn} {qe}");
        let load = |p: &[f64]| p.iter().sum::<f64>();
        assert!((load(&pn) / load(&pe) - 1.0).abs() < 1e-3);
        assert!(pn.iter().chain(&pe).all(|&p| p >= 0.0));
        assert!(cavitated > 0.1 && cavitated < 0.9, "{cavitated}");
    }

    #[test]
    fn the_rectangular_grooves_integrals_are_its_closed_form() {
        // ∫h⁻³ over [0, 1]: the land's length over 1, the groove's over 21³.
        let (a, b) = EDGES;
        let expect = (1.0 - (b - a)) + (b - a) / 21f64.powi(3);
        let got = Groove::Rectangular.integral(0.0, 1.0, -3);
        assert!((got - expect).abs() < 1e-15, "{got} {expect}");
    }
}
