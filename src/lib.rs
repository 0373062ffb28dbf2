//! texopt: surface-texture design for the piston-ring/cylinder-liner contact.
//!
//! Layers, each using only those before it (docs/solver.md, "Layout"):
//! [`model`] (physics) → [`mesh`] (discretised contact) → [`solve`] (one film problem) →
//! [`time`] (the transient to its periodic regime) → [`study`] and [`optimise`] (many
//! evaluations, through a cache) → [`api`] (what every front end asks: the command line and
//! the Python package, python/) → [`plot`] → [`cli`] (the only layer that knows flags).
//! Every physical formula cites docs/model.md or the published study's equation.
//!
//! ```no_run
//! use texopt::model::case::{CaseSpec, Texture};
//! use texopt::time::{simulate, Fidelity};
//! // Case I of the paper: R = 0.8, l1 = l2 = 0.01, per = 0.06, depth 5.
//! let case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
//! let out = simulate(&case, &Fidelity::Fast.numerics_for(&case)).unwrap().outcome;
//! println!("f = {:.4}, Z = {:.3} µm", out.f_mean, out.z_mean);
//! ```

pub mod api;
pub mod cli;
pub mod finite;
pub mod mesh;
pub mod model;
pub mod optimise;
pub mod output;
pub mod plot;
pub mod snapshot;
pub mod solve;
pub mod study;
pub mod time;
