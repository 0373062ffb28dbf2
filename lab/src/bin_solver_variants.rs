//! Cost per time step of each film-solver variant on the same warmed-up state of Case III
//! (512×32): the state after WARM steps (direct solver), then STEPS steps with each variant.
//!
//!   cargo run --release --example solver_variants -- [WARM=600] [STEPS=100]
use std::time::Instant;
use texopt::case::{CaseSpec, Numerics, Texture};
use texopt::film::{FilmSolver, Method};
use texopt::run::Transient;

fn main() {
    let arg = |i: usize, d: usize| {
        std::env::args()
            .nth(i)
            .map_or(d, |s| s.parse().expect("a whole number"))
    };
    let (warm, steps) = (arg(1, 600), arg(2, 100));
    let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
    let num = Numerics::default();
    let mut base = Transient::new(&case, &num);
    for _ in 0..warm {
        base.step().expect("warm-up step");
    }
    for m in [Method::Direct, Method::Multigrid, Method::Reference] {
        let mut t = base.clone();
        t.solver = FilmSolver::with_method(num.film_tolerance(), m);
        let (mut it, mut cy, mut z) = (0, 0, 0.0);
        let t0 = Instant::now();
        for _ in 0..steps {
            t.step().expect("step");
            it += t.last.iterations;
            cy += t.last.cycles;
            z += t.ring_state.z;
        }
        let el = t0.elapsed().as_secs_f64();
        println!(
            "{:10} {:8.3} ms/step  {:5.2} Newton it/step  {:6.2} V-cycles/step  mean Z {:.10}",
            m.name(),
            1e3 * el / steps as f64,
            it as f64 / steps as f64,
            cy as f64 / steps as f64,
            z / steps as f64
        );
    }
}
