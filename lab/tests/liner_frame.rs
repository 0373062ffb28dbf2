//! The film in the liner's frame (lab/src/liner_frame.rs) against the product's ring frame,
//! on Case III's shallow pockets (R = 3.2 cm, 0.03/0.06/10 µm) on 300 × 12 cells.

use texopt::mesh::RimModel;
use texopt::mesh::Scene;
use texopt::time::TimeScheme;
use texopt_lab::liner_frame::{LinerError, LinerFrame, LinerScheme};
use texopt_lab::studies::liner_frame::{
    case, liner_run, ring_run, ring_step_run, BDF2_1, BDF2_2, BE_2,
};

const MESH: (usize, usize) = (300, 12);

/// A liner-frame run's f̄, C_min (µm), periods and whether it reached its periodic regime.
type Answer = (f64, f64, usize, bool);

/// docs/validation.md's uncertainty of Case III's reference: f̄ ± 0.20 %, C_min ± 0.09 %.
const REFERENCE_UNCERTAINTY: (f64, f64) = (2.0e-3, 0.9e-3);

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// On 600 × 24 cells, each frame one cell a step (the ring frame's characteristic scheme at
/// Courant number ½, the liner frame's BDF2), where both are within 0.1 % of their own step's
/// limit in C_min (results/liner_frame/): the two frames solve the same film.
#[test]
fn both_frames_agree_on_case_iii_within_the_reference_s_uncertainty() {
    let (c, mesh) = (case(0), (600, 24));
    let (f_ring, c_ring, z_ring, _) =
        ring_step_run(&c, mesh, (TimeScheme::Characteristic, 1)).unwrap();
    let (f, c_min, _, periodic) =
        liner_run(&c, mesh, (BDF2_1, RimModel::Nodal), Some(z_ring)).unwrap();
    assert!(periodic, "the liner frame reaches its periodic regime");
    let (df, dc) = (rel(f, f_ring), rel(c_min, c_ring));
    eprintln!(
        "f̄ {f:.6} against {f_ring:.6} ({df:.1e}), C_min {c_min:.5} against {c_ring:.5} ({dc:.1e})"
    );
    assert!(df < REFERENCE_UNCERTAINTY.0, "f̄ apart by {df:.2e}");
    assert!(dc < REFERENCE_UNCERTAINTY.1, "C_min apart by {dc:.2e}");
}

/// Halving the step (two cells a step to one) moves backward Euler's answer at first order;
/// BDF2 along the liner moves it far less.
#[test]
fn bdf2_along_the_liner_takes_most_of_the_step_s_error() {
    let c = case(0);
    let z0 = ring_run(&c, MESH, RimModel::Nodal).unwrap().2;
    let run = |s: LinerScheme| liner_run(&c, MESH, (s, RimModel::Nodal), Some(z0)).unwrap();
    let be = (run(BE_2), run(LinerScheme { k: 1, ..BE_2 }));
    let bdf2 = (run(BDF2_2), run(BDF2_1));
    let change = |(a, b): (Answer, Answer)| (rel(b.0, a.0), rel(b.1, a.1));
    let (be, bdf2) = (change(be), change(bdf2));
    eprintln!("changes in f̄, C_min: backward Euler {be:?}, BDF2 {bdf2:?}");
    assert!(
        bdf2.0 < 0.1 * be.0,
        "f̄: BDF2 {:.2e}, backward Euler {:.2e}",
        bdf2.0,
        be.0
    );
    assert!(
        bdf2.1 < 0.6 * be.1,
        "C_min: BDF2 {:.2e}, backward Euler {:.2e}",
        bdf2.1,
        be.1
    );
}

/// Every step balances: the film the interior control volumes gained over the relabelled old
/// level is what the stencil's fluxes brought through the two ends, to round-off (the excess
/// carried under the ring's face is handed on, not dropped), with backward Euler and BDF2, and
/// with the x1 faces fitted to the gap along x1 (their Couette content carried from node to
/// node as the stencil's own flux).
#[test]
fn each_step_conserves_the_film_it_relabels() {
    let c = case(2);
    for (bdf2, fitted) in [(false, false), (true, false), (true, true)] {
        let scheme = LinerScheme {
            k: 2,
            bdf2,
            x1_samples: if fitted { 8 } else { 1 },
            fitted,
            fitted_x2: false,
        };
        let mut run = LinerFrame::new(&c, Scene::new(&c, 300, 6), scheme, None).unwrap();
        let mut worst: f64 = 0.0;
        for _ in 0..2 * run.steps_per_period() {
            run.step().unwrap();
            worst = worst.max(run.mass_defect());
        }
        eprintln!("BDF2 {bdf2}, fitted {fitted}: largest relative mass defect {worst:.1e}");
        assert!(worst < 1e-9, "mass defect {worst:.2e}");
    }
}

#[test]
fn a_step_that_does_not_divide_the_texture_period_is_refused() {
    let c = case(0);
    let scene = Scene::new(&c, 301, 4);
    let scheme = LinerScheme {
        k: 1,
        bdf2: false,
        x1_samples: 1,
        fitted: false,
        fitted_x2: false,
    };
    match LinerFrame::new(&c, scene, scheme, None) {
        Err(e @ LinerError::Period { .. }) => assert!(e.to_string().contains("choose N1")),
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("301 cells were taken"),
    }
}
