//! The band LU's kernels on their own, at the film's sizes: a factorisation, and the
//! two-right-hand-side substitution with the factors in cache and cycling through 24 sets
//! (as a settled run reads a period-old set from memory each step). Beside them, the O(N)
//! building blocks an iterative film solver would spend per step instead: one application
//! of the operator (what a Gauss–Seidel-type sweep costs at least), and the line multigrid's
//! setup and one V-cycle (`multigrid::LineMultigrid`). Each figure is the best
//! of 20 rounds (this VM's neighbours steal up to half its time, so a mean would measure
//! them).
//!
//! `cargo run --release --example band_micro -- [N1 [N2]]` (default 360 × 32: the paper
//! tier's range in Case III; 360 8 for the `fast` tier).
use std::time::Instant;
use texopt::banded::BandLu;
use texopt::multigrid::{LineMultigrid, Stencil5};

/// A film-like operator: upwind Couette coupling (west), Poiseuille conductances varying
/// along and across, diagonally dominant (an M-matrix, as the film's Newton matrix).
fn operator(m1: usize, n2: usize, scale: f64) -> Stencil5 {
    let mut s = Stencil5::default();
    s.reset(m1, n2);
    for i in 0..m1 {
        for j in 0..n2 {
            let r = i * n2 + j;
            let c = scale * (1.0 + 0.5 * ((i as f64) * 0.05).sin() * ((j as f64) * 0.3).cos());
            s.w[r] = if i > 0 { -1.3 * c } else { 0.0 };
            s.e[r] = if i + 1 < m1 { -c } else { 0.0 };
            s.s[r] = if j > 0 { -0.7 * c } else { 0.0 };
            s.n[r] = if j + 1 < n2 { -0.7 * c } else { 0.0 };
            s.c[r] = 4.2 * c;
        }
    }
    s
}

/// ms per call of `f`, which makes `calls` calls.
fn time_ms(calls: usize, mut f: impl FnMut()) -> f64 {
    let t = Instant::now();
    f();
    t.elapsed().as_secs_f64() * 1e3 / calls as f64
}

fn main() {
    let mut args = std::env::args().skip(1).map(|a| a.parse::<usize>());
    let m1 = args.next().and_then(Result::ok).unwrap_or(360);
    let n2 = args.next().and_then(Result::ok).unwrap_or(32);
    let n = m1 * n2;
    // Operators differing from their first row on: each factorisation eliminates every row.
    let ops: Vec<Stencil5> = (0..24)
        .map(|k| operator(m1, n2, 1.0 + 1e-3 * k as f64))
        .collect();
    let sets: Vec<BandLu> = ops
        .iter()
        .map(|s| {
            let mut lu = BandLu::default();
            lu.factor(s).expect("an M-matrix");
            lu
        })
        .collect();
    let (mut b1, mut b2, mut work) = (vec![0.0; n], vec![0.0; n], Vec::new());
    let fill = |b1: &mut Vec<f64>, b2: &mut Vec<f64>| {
        b1.iter_mut()
            .enumerate()
            .for_each(|(k, v)| *v = (k as f64 * 0.37).sin());
        b2.iter_mut()
            .enumerate()
            .for_each(|(k, v)| *v = (k as f64 * 0.11).cos());
    };
    // Best of 20 rounds: [factor, solve2 in cache, solve2 cycling].
    let mut best = [f64::INFINITY; 3];
    let mut lu = BandLu::default();
    for _ in 0..20 {
        let t = [
            time_ms(4, || {
                for s in &ops[..4] {
                    lu.factor(s).expect("an M-matrix");
                }
            }),
            time_ms(10, || {
                for _ in 0..10 {
                    fill(&mut b1, &mut b2);
                    sets[0].solve2(&mut b1, &mut b2, &mut work);
                }
            }),
            time_ms(sets.len(), || {
                for lu in &sets {
                    fill(&mut b1, &mut b2);
                    lu.solve2(&mut b1, &mut b2, &mut work);
                }
            }),
        ];
        for (b, t) in best.iter_mut().zip(t) {
            *b = b.min(t);
        }
    }
    let [f, c, y] = best;
    println!(
        "{m1}x{n2} ({n} rows), ms per call, best of 20: factor {f:.3}, solve2 {c:.3} \
         (factors in cache), {y:.3} (cycling through {} sets)",
        sets.len()
    );

    // The O(N) blocks, best of 20: [apply, multigrid setup, V-cycle].
    let mut mg = LineMultigrid::default();
    *mg.fine_mut() = ops[0].clone();
    let mut best = [f64::INFINITY; 3];
    for _ in 0..20 {
        fill(&mut b1, &mut b2);
        let t = [
            time_ms(10, || {
                for _ in 0..10 {
                    ops[0].apply(&b1, &mut b2);
                }
            }),
            time_ms(1, || mg.setup().expect("an M-matrix")),
            time_ms(10, || {
                for _ in 0..10 {
                    mg.vcycle(&mut b2, &b1);
                }
            }),
        ];
        for (b, t) in best.iter_mut().zip(t) {
            *b = b.min(t);
        }
    }
    let [a, s, v] = best;
    println!(
        "{m1}x{n2}, ms per call, best of 20: operator applied once {a:.4}, line multigrid \
         setup {s:.3}, one V-cycle {v:.3}"
    );
}
