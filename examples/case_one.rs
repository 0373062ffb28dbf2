//! The paper's Case I through the library: a ring of R = 0.8 cm on a liner with circular
//! pockets l1 = l2 = 0.01 cm every 0.06 cm, 5 µm deep, against the plain liner.
//!
//!     cargo run --release --example case_one

use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{simulate, Fidelity};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let plain = CaseSpec::paper(0.8);
    let textured = plain
        .clone()
        .with_texture(Texture::circular(0.01, 0.06, 5.0));
    for case in [&plain, &textured] {
        let o = simulate(case, &Fidelity::Paper.numerics_for(case))?.outcome;
        println!(
            "{:55}  f = {:.5} (paper: f/10 = {:.6})  Z̄ = {:.3} µm  C_min = {:.3} µm",
            case.label(),
            o.f_mean,
            o.f_mean / 10.0,
            o.z_mean,
            o.c_min
        );
    }
    println!(
        "paper (§3.5): plain f/10 = 0.00754, Z = 6.41 µm; textured f/10 = 0.00763, Z ≈ 6.25 µm"
    );
    Ok(())
}
