//! A·X ≈ B for the band LU: factors, reuse of shared rows, kept factors.

use super::*;

/// A 5-point M-matrix on an nx×ny grid (node (i, j) at i·ny + j) whose diagonal from row
/// `from` on is raised by `bump` (a Z change under the ring, seen by the trailing rows
/// only). Some couplings are zero, as for cavitated neighbours in the film.
fn laplacian(nx: usize, ny: usize, from: usize, bump: f64) -> Stencil5 {
    let mut s = Stencil5::default();
    s.reset(nx, ny);
    for i in 0..nx {
        for j in 0..ny {
            let r = i * ny + j;
            s.c[r] = 4.5 + 0.1 * (r as f64).sin() + if r >= from { bump } else { 0.0 };
            if i > 0 {
                s.w[r] = -1.0 - 0.05 * (r as f64).cos();
            }
            if i + 1 < nx && r % 5 != 3 {
                s.e[r] = -1.2;
            }
            if j > 0 {
                s.s[r] = -0.9;
            }
            if j + 1 < ny && r % 7 != 2 {
                s.n[r] = -1.0;
            }
        }
    }
    s
}

/// The plain band elimination, one pivot at a time (the order the factors must match).
fn reference_factors(s: &Stencil5) -> Vec<f64> {
    let (n, w) = (s.len(), s.n2);
    let stride = 2 * w + 1;
    let mut a = vec![0.0; n * stride];
    for r in 0..n {
        a[r * stride + w] += s.c[r];
        if r >= w {
            a[r * stride] += s.w[r];
        }
        if r + w < n {
            a[r * stride + 2 * w] += s.e[r];
        }
        if r % w > 0 {
            a[r * stride + w - 1] += s.s[r];
        }
        if r % w + 1 < w {
            a[r * stride + w + 1] += s.n[r];
        }
    }
    for k in 0..n {
        let inv = 1.0 / a[k * stride + w];
        let last = (k + w).min(n - 1);
        for i in k + 1..=last {
            let l = a[i * stride + k + w - i] * inv;
            if l == 0.0 {
                continue;
            }
            a[i * stride + k + w - i] = l;
            for c in k + 1..=last {
                a[i * stride + c + w - i] -= l * a[k * stride + c + w - k];
            }
        }
    }
    a
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn two_pivots_at_a_time_give_the_plain_factors_bit_for_bit() {
    // Odd and even row counts (the pair loop's end), bands 1..7, zero couplings.
    // Widths 8, 16, 24 and 32 take the fixed-length path in the band's interior.
    for (nx, ny) in [
        (1, 1),
        (5, 1),
        (6, 2),
        (7, 3),
        (9, 4),
        (8, 7),
        (3, 7),
        (7, 8),
        (2, 8),
        (6, 16),
        (5, 24),
        (4, 32),
    ] {
        let s = laplacian(nx, ny, 0, 0.0);
        let mut lu = BandLu::default();
        lu.factor(&s).unwrap();
        assert_eq!(bits(&lu.a), bits(&reference_factors(&s)), "{nx}x{ny}");
    }
}

#[test]
fn solves_a_2d_laplacian_band() {
    // Width 4 takes the general path, 8, 16 and 32 the fixed-length one inside the band
    // (none of it with one node column, n = W).
    for (nx, ny) in [(6, 4), (7, 8), (1, 8), (5, 16), (4, 32), (2, 32)] {
        let s = laplacian(nx, ny, 0, 0.0);
        let n = s.len();
        let x: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; n];
        s.apply(&x, &mut b);
        let mut lu = BandLu::default();
        lu.factor(&s).unwrap();
        let (mut b1, mut b2) = (b.clone(), b.iter().map(|v| 2.0 * v).collect::<Vec<_>>());
        lu.solve(&mut b);
        lu.solve2(&mut b1, &mut b2, &mut Vec::new());
        assert_eq!(bits(&b), bits(&b1), "{nx}x{ny}");
        for (x2, x) in b2.iter().zip(&b) {
            assert_eq!(*x2, 2.0 * x);
        }
        for k in 0..n {
            assert!((b[k] - x[k]).abs() < 1e-12, "{k}: {} vs {}", b[k], x[k]);
        }
    }
}

#[test]
fn refactoring_reuses_shared_leading_rows_bit_for_bit() {
    let (nx, ny) = (12, 4);
    let rhs: Vec<f64> = (0..nx * ny).map(|k| (k as f64 * 0.61).cos()).collect();
    let solve = |lu: &BandLu| {
        let mut b = rhs.clone();
        lu.solve(&mut b);
        b
    };
    let fresh = |s: &Stencil5| {
        let mut f = BandLu::default();
        f.factor(s).unwrap();
        f
    };
    // A reused factorisation: first the old matrix, then one differing from row 25 on
    // (odd: the first re-eliminated pivot pair straddles the reused rows).
    let mut reused = BandLu::default();
    reused.factor(&laplacian(nx, ny, 25, 0.0)).unwrap();
    let s = laplacian(nx, ny, 25, 0.37);
    reused.factor(&s).unwrap();
    assert_eq!(bits(&reused.a), bits(&fresh(&s).a), "factors differ");
    assert_eq!(bits(&reused.a), bits(&reference_factors(&s)));
    assert_eq!(solve(&reused), solve(&fresh(&s)));
    // A change in the first row, a smaller matrix, and back: always the fresh factors.
    for (n_x, from, bump) in [(12, 0, 0.1), (9, 5, 0.2), (12, 30, 0.3), (12, 31, 0.4)] {
        let s = laplacian(n_x, ny, from, bump);
        reused.factor(&s).unwrap();
        assert_eq!(
            bits(&reused.a),
            bits(&fresh(&s).a),
            "factors differ for {n_x} columns, change from {from}"
        );
    }
    // A change in one coupling of one row (each of the five in turn) is seen.
    for q in 0..5 {
        let base = laplacian(nx, ny, 0, 0.0);
        reused.factor(&base).unwrap();
        let mut s = base.clone();
        let r = 3 * ny + 2;
        let [c, w, e, so, no] = [&mut s.c, &mut s.w, &mut s.e, &mut s.s, &mut s.n];
        let v = [c, w, e, so, no].into_iter().nth(q).unwrap();
        v[r] *= 1.1;
        assert_ne!(v[r], 0.0);
        reused.factor(&s).unwrap();
        assert_eq!(bits(&reused.a), bits(&fresh(&s).a), "coupling {q} changed");
    }
    // A failed factorisation is never reused.
    assert!(reused.factor(&laplacian(nx, ny, 40, f64::NAN)).is_err());
    let s = laplacian(nx, ny, 40, 0.5);
    reused.factor(&s).unwrap();
    assert_eq!(bits(&reused.a), bits(&fresh(&s).a));
}

#[test]
fn taking_the_operator_gives_the_copied_ones_factors_and_reuse() {
    // The film solver's use: each operator assembled into the buffer the last one left.
    let (copying, taking) = (&mut BandLu::default(), &mut BandLu::default());
    let mut buffer = Stencil5::default();
    let sequence = [
        (12, 25, 0.0),
        (12, 25, 0.37),
        (12, 0, 0.1),
        (9, 5, 0.2),
        (12, 30, 0.3),
    ];
    for (n_x, from, bump) in sequence {
        let s = laplacian(n_x, 4, from, bump);
        buffer.reshape(s.m1, s.n2);
        for (b, v) in buffer.coefficients_mut().into_iter().zip(s.coefficients()) {
            b.copy_from_slice(v);
        }
        let kept = copying.factor(&s).unwrap();
        assert_eq!(
            taking.factor_taking(&mut buffer).unwrap(),
            kept,
            "rows eliminated"
        );
        assert_eq!(
            bits(&taking.a),
            bits(&copying.a),
            "{n_x} columns, from {from}"
        );
    }
}

#[test]
fn kept_factors_solve_as_the_band_lu_double_to_the_bit_single_to_1e_7() {
    for (nx, ny) in [(7, 8), (5, 16), (4, 32), (6, 4)] {
        let s = laplacian(nx, ny, 0, 0.0);
        let n = s.len();
        let x: Vec<f64> = (0..n)
            .map(|k| 1.0 + 0.5 * (k as f64 * 0.37).sin())
            .collect();
        let mut b = vec![0.0; n];
        s.apply(&x, &mut b);
        let mut lu = BandLu::default();
        lu.factor(&s).unwrap();
        let (mut e1, mut e2) = (b.clone(), b.iter().map(|v| -v).collect::<Vec<_>>());
        lu.solve2(&mut e1, &mut e2, &mut Vec::new());
        for single in [false, true] {
            let mut kept = KeptLu::default();
            if single {
                kept.keep_single(&lu);
            } else {
                // Exchanged: the band LU takes what the kept set held (nothing here).
                let mut own = lu.clone();
                kept.exchange(&mut own);
                assert!(!own.valid && own.a.is_empty());
            }
            assert_eq!(kept.rounded(), single);
            let (mut k1, mut k2) = (b.clone(), b.iter().map(|v| -v).collect::<Vec<_>>());
            kept.solve2(&mut k1, &mut k2, &mut Vec::new());
            let mut k = b.clone();
            kept.solve(&mut k);
            assert_eq!(bits(&k), bits(&k1), "{nx}x{ny} single {single}");
            if single {
                for (i, (a, e)) in k1.iter().zip(&x).enumerate() {
                    assert!(
                        (a - e).abs() < 1e-6 * e.abs(),
                        "{nx}x{ny} row {i}: {a} vs {e}"
                    );
                }
                assert!(bits(&k1) != bits(&e1), "single factors solved to the bit?");
            } else {
                assert_eq!(bits(&k1), bits(&e1), "{nx}x{ny}");
                assert_eq!(bits(&k2), bits(&e2), "{nx}x{ny}");
            }
        }
    }
}

#[test]
fn refactoring_takes_the_rows_it_shares_with_kept_factors() {
    let (nx, ny) = (12, 8);
    let old = laplacian(nx, ny, 41, 0.0);
    let new = laplacian(nx, ny, 41, 0.37);
    let mut lu = BandLu::default();
    lu.factor(&old).unwrap();
    let mut fresh = BandLu::default();
    fresh.factor(&new).unwrap();
    for single in [false, true] {
        let mut kept = KeptLu::default();
        if single {
            kept.keep_single(&lu);
        } else {
            kept.exchange(&mut lu.clone());
        }
        // Factors at hand of another matrix (nothing shared), the kept ones lent.
        let mut other = BandLu::default();
        other.factor(&laplacian(nx, ny, 0, 0.2)).unwrap();
        let mut op = new.clone();
        let rows = other.factor_taking_reusing(&mut op, Some(&kept)).unwrap();
        assert_eq!(rows, nx * ny - 41, "single {single}: rows eliminated");
        assert_eq!(other.rounded(), single);
        if single {
            // The widened rows are the single-precision ones, the rest re-eliminated.
            let x: Vec<f64> = (0..nx * ny).map(|k| 1.5 + (k as f64 * 0.3).cos()).collect();
            let mut b = vec![0.0; nx * ny];
            new.apply(&x, &mut b);
            other.solve(&mut b);
            for (a, e) in b.iter().zip(&x) {
                assert!((a - e).abs() < 1e-6 * e.abs(), "{a} vs {e}");
            }
            // A full refactorisation (nothing shared) is exact again.
            other.factor(&laplacian(nx, ny, 0, 0.5)).unwrap();
            assert!(!other.rounded());
        } else {
            assert_eq!(bits(&other.a), bits(&fresh.a), "double: the fresh factors");
        }
    }
}

#[test]
fn exchanging_kept_factors_moves_them_whole_both_ways() {
    let (a, b) = (laplacian(6, 8, 0, 0.0), laplacian(6, 8, 20, 0.3));
    let (mut fa, mut fb) = (BandLu::default(), BandLu::default());
    fa.factor(&a).unwrap();
    fb.factor(&b).unwrap();
    let (bits_a, bits_b) = (bits(&fa.a), bits(&fb.a));
    let mut kept = KeptLu::default();
    kept.exchange(&mut fa); // kept: a's factors; fa: none
    assert!(!fa.valid);
    kept.exchange(&mut fb); // kept: b's; fb: a's
    assert!(fb.valid && !fb.rounded());
    assert_eq!(bits(&fb.a), bits_a);
    assert_eq!(
        fb.shared_rows(&a),
        a.len() - a.n2 - 1,
        "a's operator came along"
    );
    kept.exchange(&mut fa); // kept: none; fa: b's
    assert!(fa.valid && kept.n == 0);
    assert_eq!(bits(&fa.a), bits_b);
    // Single factors are not exchanged: the band LU is left with none.
    kept.keep_single(&fb);
    let mut fc = fb.clone();
    kept.exchange(&mut fc);
    assert!(!fc.valid);
}
