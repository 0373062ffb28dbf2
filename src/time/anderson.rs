//! Anderson acceleration of the period map (docs/solver.md, "Periodic regime"): the state at
//! a window's end is a function of the state at its start, G(x); the periodic regime is its
//! fixed point. From the last few pairs (x_j, G(x_j)) the next start is the combination that
//! makes the residual G(x) − x smallest (type II, Walker & Ni, SIAM J. Numer. Anal. 49,
//! 2011), so the slow modes of the approach (the ring's damped oscillation, a conformal
//! ring's creep, the oil bank) are removed together instead of decaying window by window.

use nalgebra::{DMatrix, DVector};

use super::transient::Transient;
use crate::model::ring::RingState;

/// Windows marched plainly on a mesh before the first acceleration: the start's large,
/// nonlinear transient (the ring lifting from the paper's Z = 2.5 µm, the film flushed
/// through the contact) first. Measured (`fast`, four reference cases from the paper's
/// start, windows to the periodic tolerance): 1, 2 or 3 windows ask the same ±1 window.
const PLAIN_WINDOWS: usize = 2;

/// Pairs kept (the same scan: 3, 5 and 8 within ±1 window; 5 was never the slowest).
const MEMORY: usize = 5;

/// Largest residual, and largest oil imbalance of the window (its change of the film's oil
/// against the oil through the domain), at which the acceleration combines. Above them the
/// film is still being flushed and the ring still lifting or sinking by µm (residuals 0.2–1
/// in the first windows from the paper's start), or the film drains at a steady rate (a
/// flooded bank emptying through deep pockets: 25 % of the throughflow a window for 17 ms
/// at R = 0.2, 0.02 / 0.04 / 30 µm): no fixed point of a linear model of the period map
/// describes either. A combination taken there sent that ring into the liner, and, taken
/// during the drain, kept refilling the bank. Measured on the benchmark cases, the residual
/// falls below 0.05 within 4–6 windows of the paper's start and starts below it after a
/// coarse approach.
const ACCELERATE_BELOW: f64 = 0.1;

/// A residual this many times the smallest one so far drops the history: the combination
/// is not converging (a nonlinear stretch, an active set moving), and the next windows are
/// marched plainly from where the last one ended.
const RESTART_GROWTH: f64 = 10.0;

/// The state of a transient as the acceleration sees it: the saturation θ = φ/h at every
/// node, then Z, Z'·T and Z''·T² relative to `z_ref` (T the window's length), the ring's
/// entries weighted as √N film entries so that the ring counts as much as the whole film.
fn pack(t: &Transient, window: f64, z_ref: f64) -> DVector<f64> {
    let (scene, phi) = (t.scene(), &t.state().phi);
    let g = &scene.grid;
    let s = t.ring_state();
    let n = g.nodes();
    let w = (n as f64).sqrt() / z_ref;
    DVector::from_iterator(
        n + 3,
        (0..n).map(|k| phi[k] / scene.gap.h(g, k, s.z)).chain([
            w * s.z,
            w * s.v * window,
            w * s.a * window * window,
        ]),
    )
}

/// The accelerator's memory: the pairs (x_j, G(x_j)) of the last windows, oldest first, and
/// the smallest residual since they were last dropped.
struct Pairs {
    xs: Vec<DVector<f64>>,
    gs: Vec<DVector<f64>>,
    smallest: f64,
}

impl Pairs {
    /// Keeps the pair (x, g) of residual `residual`, dropping the older ones when it grew
    /// by [`RESTART_GROWTH`], and all but the last [`MEMORY`] + 1.
    fn push(&mut self, x: DVector<f64>, g: DVector<f64>, residual: f64) {
        if residual > RESTART_GROWTH * self.smallest {
            self.xs.clear();
            self.gs.clear();
            self.smallest = residual;
        }
        self.smallest = self.smallest.min(residual);
        self.xs.push(x);
        self.gs.push(g);
        if self.xs.len() > MEMORY + 1 {
            self.xs.remove(0);
            self.gs.remove(0);
        }
    }

    /// The type II combination: γ minimising |f_k − ΔF·γ| (least squares by SVD, dropping
    /// directions below 1e-10 of the largest), x⁺ = g_k − ΔG·γ.
    fn combine(&self) -> Option<DVector<f64>> {
        let k = self.xs.len() - 1;
        let f = |j: usize| &self.gs[j] - &self.xs[j];
        let df: Vec<DVector<f64>> = (0..k).map(|j| f(j + 1) - f(j)).collect();
        let dg: Vec<DVector<f64>> = (0..k).map(|j| &self.gs[j + 1] - &self.gs[j]).collect();
        let df = DMatrix::from_columns(&df);
        let svd = df.svd(true, true);
        let cut = 1e-10 * svd.singular_values.max();
        let gamma = svd.solve(&f(k), cut).ok()?;
        let next = &self.gs[k] - DMatrix::from_columns(&dg) * gamma;
        next.iter().all(|v| v.is_finite()).then_some(next)
    }
}

/// The accelerator of a run's windows: its memory and the residual of the latest.
pub(crate) struct Anderson {
    window: f64,
    pairs: Pairs,
    /// The scale of the ring's entries: Z at the first window's start.
    z_ref: Option<f64>,
    /// The packed state at the current window's start.
    start: Option<DVector<f64>>,
    /// Windows seen.
    windows: usize,
    /// RMS of the last residual G(x) − x over its entries (θ, and the ring's relative
    /// change counted as much as the whole film): a window's change of the state.
    residual: f64,
}

impl Anderson {
    /// For windows of `window` (ms).
    pub fn new(window: f64) -> Self {
        Anderson {
            window,
            pairs: Pairs {
                xs: Vec::new(),
                gs: Vec::new(),
                smallest: f64::INFINITY,
            },
            z_ref: None,
            start: None,
            windows: 0,
            residual: f64::INFINITY,
        }
    }

    /// Notes the state a window starts from.
    pub fn before_window(&mut self, t: &Transient) {
        let z_ref = *self.z_ref.get_or_insert(t.ring_state().z);
        self.start = Some(pack(t, self.window, z_ref));
    }

    /// After a window whose oil imbalance was `imbalance`: the pair (x, G(x)) recorded, its
    /// residual, and the next start set by the acceleration (after [`PLAIN_WINDOWS`], with two
    /// pairs at hand, both measures below [`ACCELERATE_BELOW`]). Returns the latest residual.
    pub fn after_window(&mut self, t: &mut Transient, imbalance: f64) -> f64 {
        self.windows += 1;
        let (Some(x), Some(z_ref)) = (self.start.take(), self.z_ref) else {
            return self.residual;
        };
        let g = pack(t, self.window, z_ref);
        let f = &g - &x;
        self.residual = f.norm() / (2.0 * f.len() as f64).sqrt();
        self.pairs.push(x, g, self.residual);
        let settling = self.residual.max(imbalance) <= ACCELERATE_BELOW;
        if self.windows <= PLAIN_WINDOWS || self.pairs.xs.len() < 2 || !settling {
            return self.residual;
        }
        if let Some(next) = self.pairs.combine() {
            unpack(t, &next, z_ref, self.window);
        }
        self.residual
    }
}

/// Sets the transient's state from a packed vector ([`pack`]): Z and its rates, θ clipped
/// into [0, 1] and φ = θ·h on the new gap (h on the pressurised set), the time scheme's
/// previous level moved with it. Refused when Z would leave [½, 2]× its present value.
fn unpack(t: &mut Transient, v: &DVector<f64>, z_ref: f64, window: f64) {
    let n = v.len();
    let w = ((n - 3) as f64).sqrt() / z_ref;
    let z = v[n - 3] / w;
    let now = t.ring_state().z;
    if !(z.is_finite() && z >= 0.5 * now && z <= 2.0 * now) {
        return;
    }
    let (scene, state) = (t.scene(), t.state());
    let g = &scene.grid;
    let phi = (0..g.nodes())
        .map(|k| {
            let h = scene.gap.h(g, k, z);
            if state.pressurised[k] {
                h
            } else {
                v[k].clamp(0.0, 1.0) * h
            }
        })
        .collect();
    let ring = RingState {
        z,
        v: v[n - 2] / w / window,
        a: v[n - 1] / w / (window * window),
    };
    t.jump(phi, ring);
}
