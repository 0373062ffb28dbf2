//! The friction of a liner-frame film whose x1 faces are fitted to the gap along x1
//! (lab/src/liner_frame.rs, `LinerScheme::fitted`): eq. (17)'s terms integrated between
//! the nodes along each strip of each face with the film's one-dimensional profile there,
//! the profile the fitted face's flux assumes, in place of the product's nodal quadrature,
//! which reads a rim only at the nodes.
//!
//! On a face whose two nodes are pressurised, each strip carries a constant flux
//! F = u·content − Δp/∫h⁻³ (docs/model.md §3 at a constant flux, the fitted face's), so
//! p′ = u/h² − F/h³ along it, and over the face (dx·mean over the strip's points):
//! Couette ∫u/h, Poiseuille ∫3h·p′ = 3(u∫h⁻¹ − F∫h⁻²), and the pressure term by parts,
//! ∫6p·h_L′ = 6[p·h_L] − 6∫h_L·p′, whose bracket telescopes over the faces to the ring span's
//! ends. On a face with a cavitated node the film is carried at the upstream cell's θ (the
//! stencil's content), its Couette shear u·θ/h where θ > θ_s, and p′ is the nodes' difference.
//! Half a cell at each end of the ring span takes the nodal terms. Everything is computed on
//! the mirrored film and turned back: x1 → L − x1 flips ∂/∂x1, so the Poiseuille and pressure
//! terms change sign.

use texopt::mesh::{FilmState, Scene};
use texopt::model::friction::{Friction, FrictionModel};
use texopt::model::units::friction_coefficient;

/// The means over a strip's points of 1/h, 1/h², 1/h³, h_L/h², h_L/h³ and h_L.
#[derive(Clone, Copy, Default)]
struct StripMeans {
    r1: f64,
    r2: f64,
    r3: f64,
    l2: f64,
    l3: f64,
    l: f64,
}

impl StripMeans {
    fn of(h: impl Iterator<Item = (f64, f64)>) -> Self {
        let (mut m, mut n) = (StripMeans::default(), 0.0);
        for (h, hl) in h {
            let r = 1.0 / h;
            m.r1 += r;
            m.r2 += r * r;
            m.r3 += r * r * r;
            m.l2 += hl * r * r;
            m.l3 += hl * r * r * r;
            m.l += hl;
            n += 1.0;
        }
        StripMeans {
            r1: m.r1 / n,
            r2: m.r2 / n,
            r3: m.r3 / n,
            l2: m.l2 / n,
            l3: m.l3 / n,
            l: m.l / n,
        }
    }
}

/// Sums of eq. (17)'s terms (each ∫ dx along x1, per unit width across x2).
#[derive(Default)]
struct Sums {
    couette: f64,
    poiseuille: f64,
    pressure: f64,
}

/// The friction of `state` on the `mirrored` scene (fitted faces in its gap) at ring position
/// `z`; `depth(i, j)` the texture depth at the points of the face east of mirrored node
/// (i, j), strip after strip (the points of the gap's fitted samples); `boundary` the
/// asperities' term, taken as given.
pub fn fitted_friction(
    mirrored: &Scene,
    state: &FilmState,
    z: f64,
    model: &FrictionModel,
    depth: impl Fn(usize, usize) -> Vec<f64>,
    boundary: f64,
) -> Friction {
    let (g, gap) = (&mirrored.grid, &mirrored.gap);
    let (n2, u) = (g.n2, model.u);
    let span = gap.ring_columns();
    let mut sums = Sums::default();
    if span.len() < 2 {
        return Friction::default();
    }
    let hn = |k: usize| gap.h(g, k, z);
    for i in span.start..span.end - 1 {
        for j in 0..n2 {
            face_terms(mirrored, state, z, model, (i, j), &depth, &mut sums);
        }
    }
    // Half a cell at each end of the span: the nodal terms.
    for i in [span.start, span.end - 1] {
        for j in 0..n2 {
            let k = i * n2 + j;
            let theta = state.phi[k] / hn(k);
            if theta > model.theta_s {
                sums.couette += 0.5 * g.dx * u * theta / hn(k);
            }
            let dp = 0.5 * (state.p[k + n2] - state.p[k - n2]);
            sums.poiseuille += 0.5 * 3.0 * hn(k) * dp;
        }
    }
    // The pressure term's bracket: 6·p·h_L at the span's ends (the nodes' cell means).
    let (a, b) = (span.start, span.end - 1);
    for j in 0..n2 {
        let (ka, kb) = (a * n2 + j, b * n2 + j);
        sums.pressure += 6.0 * (state.p[kb] * mirrored.hl[kb] - state.p[ka] * mirrored.hl[ka]);
    }
    let w = g.dy / g.width;
    Friction {
        couette: friction_coefficient(sums.couette * w, model.w_ps),
        poiseuille: friction_coefficient(-sums.poiseuille * w, model.w_ps),
        pressure: friction_coefficient(-sums.pressure * w, model.w_ps),
        boundary,
    }
}

/// Eq. (17)'s terms over the face east of mirrored node (i, j), added to `sums`.
fn face_terms(
    mirrored: &Scene,
    state: &FilmState,
    z: f64,
    model: &FrictionModel,
    (i, j): (usize, usize),
    depth: &impl Fn(usize, usize) -> Vec<f64>,
    sums: &mut Sums,
) {
    let (g, gap) = (&mirrored.grid, &mirrored.gap);
    let (n2, u, dx) = (g.n2, model.u, g.dx);
    let (k, e) = (i * n2 + j, (i + 1) * n2 + j);
    let (hk, he) = (gap.h(g, k, z), gap.h(g, e, z));
    let dp = state.p[e] - state.p[k];
    let full = state.pressurised[k] && state.pressurised[e];
    let theta = (state.phi[k] / hk).min(1.0);
    // The strips: fitted samples, or the two nodes' gaps (a plateau face).
    let strips: Vec<StripMeans> = match gap.fitted.as_ref().and_then(|f| f.samples_of(k)) {
        Some((base, under)) => {
            let m = gap.fitted.as_ref().map_or(1, |f| f.shape().1);
            let hl = depth(i, j);
            base.chunks_exact(m)
                .zip(under.chunks_exact(m))
                .zip(hl.chunks_exact(m))
                .map(|((b, un), l)| {
                    StripMeans::of(
                        b.iter()
                            .zip(un)
                            .zip(l)
                            .map(|((&b, &un), &l)| (if un { b + z } else { b }, l)),
                    )
                })
                .collect()
        }
        None => {
            let (lk, le) = (mirrored.hl[k], mirrored.hl[e]);
            vec![StripMeans::of([(hk, lk), (he, le)].into_iter())]
        }
    };
    let ns = strips.len() as f64;
    for s in &strips {
        if full {
            let f = u * s.r2 / s.r3 - dp / (dx * s.r3);
            sums.couette += dx * u * s.r1 / ns;
            sums.poiseuille += 3.0 * dx * (u * s.r1 - f * s.r2) / ns;
            sums.pressure -= 6.0 * dx * (u * s.l2 - f * s.l3) / ns;
        } else {
            if theta > model.theta_s {
                sums.couette += dx * u * theta * s.r1 / ns;
            }
            let h_mean = 0.5 * (hk + he);
            sums.poiseuille += 3.0 * h_mean * dp / ns;
            sums.pressure -= 6.0 * s.l * dp / ns;
        }
    }
}
