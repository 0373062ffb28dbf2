//! A study from code: three depths of one pocket lattice on two rings, in parallel through
//! the evaluation cache, then each texture's friction and clearance against its plain liner.
//!
//!     cargo run --release --example custom_study

use std::sync::atomic::AtomicBool;
use std::sync::Mutex;

use texopt::model::case::{CaseSpec, Texture};
use texopt::model::operating::Scales;
use texopt::study::cache::Cache;
use texopt::study::sweep::{self, Options};
use texopt::study::Job;
use texopt::time::Fidelity;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let tier = Fidelity::Draft;
    let mut jobs = Vec::new();
    for r in [0.8, 6.4] {
        let plain = CaseSpec::paper(r);
        jobs.push(Job {
            numerics: tier.numerics_for(&plain),
            case: plain.clone(),
            scales: Scales::PAPER,
        });
        for depth in [2.0, 5.0, 10.0] {
            let case = plain
                .clone()
                .with_texture(Texture::circular(0.03, 0.06, depth));
            jobs.push(Job {
                numerics: tier.numerics_for(&case),
                case,
                scales: Scales::PAPER,
            });
        }
    }
    let cache = Mutex::new(Cache::open(std::path::Path::new(".texopt/example.sqlite"))?);
    let options = Options {
        jobs: 2,
        retry_failed: false,
        progress: false,
        limits: Default::default(),
    };
    let (_, results) = sweep::run(&jobs, &cache, &options, &AtomicBool::new(false))?;
    // Each ring's plain liner comes first among its jobs.
    let (mut f0, mut c0) = (f64::NAN, f64::NAN);
    for (job, result) in jobs.iter().zip(results) {
        let o = result.expect("not stopped").map_err(|e| e.to_string())?;
        if job.case.texture.is_none() {
            (f0, c0) = (o.f_mean, o.c_min);
        }
        println!(
            "{:55} f = {:.5} ({:+.1} %)  C_min = {:.3} µm ({:+.1} %)",
            job.case.label(),
            o.f_mean,
            100.0 * (o.f_mean / f0 - 1.0),
            o.c_min,
            100.0 * (o.c_min / c0 - 1.0)
        );
    }
    Ok(())
}
