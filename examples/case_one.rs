//! The paper's Case I through the library API: ring R = 0.8 cm on a liner with circular
//! pockets l1 = l2 = 0.01 cm, period 0.06 cm, depth 5 µm, at the paper's fidelity.
//!
//!     cargo run --release --example case_one            # 512×32, about a minute
//!     cargo run --release --example case_one -- 128x8   # a coarse look in a second

use texopt::case::{CaseSpec, Numerics, Texture};
use texopt::run::simulate;

fn main() {
    let mut num = Numerics::default();
    if let Some(mesh) = std::env::args().nth(1) {
        let (a, b) = mesh.split_once('x').expect("mesh as N1xN2, e.g. 128x8");
        num.n1 = a.parse().expect("N1");
        num.n2 = b.parse().expect("N2");
    }
    let textured = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
    let smooth = CaseSpec::paper(0.8);
    for case in [&smooth, &textured] {
        case.validate(false).expect("a valid case");
        num.validate(case).expect("a valid mesh");
        match simulate(case, &num, false) {
            Ok(r) => {
                let o = r.outcome;
                println!(
                    "{:55}  f = {:.5} (paper units f/10 = {:.6})  Z̄ = {:.3} µm  C_min = {:.3} µm  [{}, {:.1} s]",
                    case.label(),
                    o.f_mean,
                    o.f_mean / 10.0,
                    o.z_mean,
                    o.c_min,
                    o.method,
                    o.wall_time_s
                );
            }
            Err(e) => eprintln!("{e}"),
        }
    }
    println!(
        "paper (§3.5): untextured f/10 = 0.00754, Z = 6.41; textured f/10 = 0.00763, Z ≈ 6.25"
    );
}
