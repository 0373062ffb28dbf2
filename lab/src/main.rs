//! `texopt-lab`: the studies beside the product (results/<study>/ each).
//!
//!     texopt-lab speed run CASE N1xN2 DT [PERIODIC_TOL] [SOLVER] [APPROACH_N2] | report | finer
//!     texopt-lab convergence run N1xN2 DT [--solver NAME] [--approach N2] | report
//!     texopt-lab stability [runs | contrasts | report]
//!     texopt-lab where-time-goes [CASE [TIER]]

use texopt_lab::studies;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rest = args.get(1..).unwrap_or(&[]);
    let result = match args.first().map(String::as_str) {
        Some("speed") => studies::speed::main(rest),
        Some("convergence") => studies::convergence::main(rest),
        Some("stability") => studies::stability::main(rest),
        Some("where-time-goes") => studies::where_time_goes::main(rest),
        _ => Err(
            "usage: texopt-lab speed … | convergence … | stability … | where-time-goes … (see lab/src/main.rs)"
                .into(),
        ),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}
