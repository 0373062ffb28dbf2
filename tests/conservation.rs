//! Discrete mass conservation of the film scheme in a textured 2D run with cavitation:
//! over a step, Σ(hθ)·cell area changes by exactly dt × (inflow − outflow) at the x1 ends
//! (BDF2: its storage term's change, 1.5·(φⁿ⁺¹ − (4φⁿ − φⁿ⁻¹)/3), does; the characteristic
//! scheme: the change from the old level moved along the characteristics, against the
//! Poiseuille flows, the Couette ones being that move, whose own balance
//! time/characteristic.rs tests).

use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{Numerics, TimeScheme, Transient, Watch};

#[test]
fn textured_step_conserves_mass_to_round_off() {
    conserves_mass(TimeScheme::BackwardEuler, 4e-4);
}

#[test]
fn textured_bdf2_step_conserves_mass_to_round_off() {
    conserves_mass(TimeScheme::Bdf2, 4e-4);
}

/// At the characteristic step 2·dx1/u (the foot on a node) and below it (interpolated).
#[test]
fn textured_characteristic_step_conserves_mass_to_round_off() {
    conserves_mass(TimeScheme::Characteristic, 2.0 * 0.2 / 256.0);
    conserves_mass(TimeScheme::Characteristic, 4e-4);
}

fn conserves_mass(scheme: TimeScheme, dt: f64) {
    let case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let num = Numerics {
        n1: 256,
        n2: 16,
        dt,
        scheme,
        ..Numerics::default()
    };
    let mut sim = Transient::new(&case, &num);
    for _ in 0..400 {
        sim.step().unwrap();
    }
    let mut worst: f64 = 0.0;
    for _ in 0..30 {
        sim.step().unwrap();
        worst = worst.max(sim.mass_defect());
        let g = &sim.scene().grid;

        // The step really has both regions under the ring: pressurised and cavitated (θ < 1).
        let ring_nodes: Vec<usize> = (0..g.nodes())
            .filter(|&k| sim.scene().gap.ring[k / g.n2])
            .collect();
        assert!(ring_nodes.iter().any(|&k| sim.state().pressurised[k]));
        assert!(ring_nodes.iter().any(|&k| {
            sim.state()
                .theta(g, &sim.scene().gap, sim.ring_state().z, k)
                < 0.9
        }));
    }
    println!("worst relative mass defect per step: {worst:e}");
    assert!(worst <= 1e-10, "mass defect {worst:e}");
}

/// Every step's film solve ends within the solve tolerance (relative error 1e-8, solve/reuse.rs
/// `CHORD_CONFIRM`) in every node's balance, including the node past a flat ring's
/// trailing edge, whose west face spans the ring film and the gap e (h_f ≈ 500 µm, a
/// conductance ≈ 10⁸): there the clipping of a round-off negative pressure (≈ 1e-17) once
/// showed as a residual of 1.4e-7 because it was measured after the clip.
#[test]
fn film_residual_stays_within_the_solve_tolerance_past_a_flat_ring_edge() {
    let case = CaseSpec::paper(f64::INFINITY).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let num = Numerics {
        n1: 256,
        n2: 8,
        dt: 8e-4,
        periodic_tol: 1e-4,
        t_max: 3.0,
        ..Numerics::default()
    };
    let out = Transient::new(&case, &num)
        .run_to_periodic(&num, false, &mut Watch::default())
        .unwrap()
        .outcome;
    assert!(out.converged);
    assert!(
        out.max_residual <= 1e-8,
        "largest relative film residual {:e}",
        out.max_residual
    );
}
