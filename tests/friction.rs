//! Friction bookkeeping (docs/model.md §5): the three terms add up to f̄; θ_s acts on the Couette
//! term only (it enters no equation of the film or the ring).

use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{Numerics, Transient, Watch};

#[test]
fn terms_sum_and_theta_s_changes_only_couette() {
    let num = Numerics {
        n1: 128,
        n2: 8,
        ..Numerics::default()
    };
    let run = |theta_s: f64| {
        let mut case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        case.theta_s = theta_s;
        Transient::new(&case, &num)
            .run_to_periodic(&num, true, &mut Watch::default())
            .unwrap()
    };
    let a = run(0.95);
    let b = run(0.25);
    println!("θs 0.95: {:?}\nθs 0.25: {:?}", a.outcome, b.outcome);
    for r in [&a, &b] {
        let o = &r.outcome;
        assert!(o.converged);
        let sum = o.f_couette + o.f_poiseuille + o.f_pressure;
        assert!((sum - o.f_mean).abs() <= 1e-12 * o.f_mean);
        // f̄ is the mean of the per-step totals over the last period.
        let series = r.series.as_ref().unwrap();
        let n = (0.06 / o.dt).round() as usize;
        let mean: f64 = series[series.len() - n..].iter().map(|s| s.f).sum::<f64>() / n as f64;
        assert!((mean - o.f_mean).abs() <= 1e-12 * o.f_mean);
        for s in series {
            let t = s.f_couette + s.f_poiseuille + s.f_pressure;
            assert!((t - s.f).abs() <= 1e-12 * s.f.abs());
        }
    }
    // Step by step (the runs may stop at different periods, as f̄ differs): same ring
    // motion, same Poiseuille and pressure terms, different Couette term.
    let (sa, sb) = (a.series.unwrap(), b.series.unwrap());
    let mut couette_differs = 0;
    for (ra, rb) in sa.iter().zip(&sb) {
        assert_eq!(ra.z, rb.z);
        assert_eq!(ra.w_h, rb.w_h);
        assert_eq!(ra.f_poiseuille, rb.f_poiseuille);
        assert_eq!(ra.f_pressure, rb.f_pressure);
        if rb.f_couette > ra.f_couette * 1.001 {
            couette_differs += 1;
        }
        // A lower threshold only ever counts more shear (θ > 0.25 ⊇ θ > 0.95).
        assert!(rb.f_couette >= ra.f_couette);
    }
    // Case III cavitates deeply in its pockets, so the threshold matters at most steps.
    assert!(couette_differs > sa.len().min(sb.len()) / 2);
}
