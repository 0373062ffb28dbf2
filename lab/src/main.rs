//! `texopt-lab`: the studies beside the product (results/<study>/ each).
//!
//!     texopt-lab speed run CASE N1xN2 DT [KEY=VALUE …] | report
//!     texopt-lab convergence run N1xN2 DT [--solver NAME] [--approach N1xN2@DT] | report
//!     texopt-lab stability [runs | contrasts | report]
//!     texopt-lab where-time-goes [CASE [TIER]]
//!     texopt-lab references run CASE N1xN2 DT | report
//!     texopt-lab deep-pockets
//!     texopt-lab shear-threshold
//!     texopt-lab cycle-steps
//!     texopt-lab cycle-contact
//!     texopt-lab cycle-stress [LINER …]
//!     texopt-lab deep-mesh
//!     texopt-lab deep-rule
//!     texopt-lab rim-1d
//!     texopt-lab rim-2d
//!     texopt-lab rim-moving
//!     texopt-lab rim-liner
//!     texopt-lab liner-frame [runs | report | probe …]
//!     texopt-lab rim-rows

use texopt_lab::studies;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rest = args.get(1..).unwrap_or(&[]);
    let result = match args.first().map(String::as_str) {
        Some("speed") => studies::speed::main(rest),
        Some("convergence") => studies::convergence::main(rest),
        Some("stability") => studies::stability::main(rest),
        Some("where-time-goes") => studies::where_time_goes::main(rest),
        Some("references") => studies::references::main(rest),
        Some("deep-pockets") => studies::deep_pockets::main(rest),
        Some("shear-threshold") => studies::shear_threshold::main(rest),
        Some("cycle-steps") => studies::cycle_steps::main(rest),
        Some("cycle-contact") => studies::cycle_contact::main(rest),
        Some("cycle-stress") => studies::cycle_stress::main(rest),
        Some("deep-mesh") => studies::deep_mesh::main(rest),
        Some("deep-rule") => studies::deep_mesh::rule_main(rest),
        Some("liner-frame") => studies::liner_frame::main(rest),
        Some("rim-1d") => studies::rim_1d::main(rest),
        Some("rim-2d") => studies::rim_2d::main(rest),
        Some("rim-moving") => studies::rim_moving::main(rest),
        Some("rim-liner") => studies::rim_liner::main(rest),
        Some("rim-rows") => studies::rim_rows::main(rest),
        _ => Err(
            "usage: texopt-lab speed … | references … | deep-pockets | deep-mesh | deep-rule | shear-threshold | cycle-steps | cycle-contact | cycle-stress [LINER …] | rim-1d | rim-2d | rim-moving | rim-liner | liner-frame [runs | report | probe …] | rim-rows | convergence … | stability … | where-time-goes … (see lab/src/main.rs)"
                .into(),
        ),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}
