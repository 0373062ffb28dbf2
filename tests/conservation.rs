//! Discrete mass conservation of the film scheme in a textured 2D run with cavitation:
//! over a step, Σ(hθ)·cell area changes by exactly dt × (inflow − outflow) at the x1 ends.

use texopt::case::{CaseSpec, Numerics, Texture};
use texopt::run::Transient;

#[test]
fn textured_step_conserves_mass_to_round_off() {
    let case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let num = Numerics {
        n1: 256,
        n2: 16,
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
        let g = &sim.scene.grid;

        // The step really has both regions under the ring: pressurised and cavitated (θ < 1).
        let ring_nodes: Vec<usize> = (0..g.nodes())
            .filter(|&k| sim.scene.gap.ring[k / g.n2])
            .collect();
        assert!(ring_nodes.iter().any(|&k| sim.state.pressurised[k]));
        assert!(ring_nodes
            .iter()
            .any(|&k| { sim.state.theta(g, &sim.scene.gap, sim.ring_state.z, k) < 0.9 }));
    }
    println!("worst relative mass defect per step: {worst:e}");
    assert!(worst <= 1e-10, "mass defect {worst:e}");
}
