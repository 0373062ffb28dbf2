//! texopt: surface-texture design for the piston-ring/cylinder-liner contact.
//!
//! Data flows one way: geometry → film solve → forces → ring dynamics → outcomes.
//! The physics is ../shared/model.md (the published study, with every convention fixed);
//! each module cites the section or equation it implements.
//!
//! ```no_run
//! use texopt::case::{CaseSpec, Numerics, Texture};
//! // Case I of the paper: R = 0.8, l1 = l2 = 0.01, per = 0.06, depth 5.
//! let case = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
//! let out = texopt::run::simulate(&case, &Numerics::default(), false).unwrap().outcome;
//! println!("f = {:.4}, Z = {:.3} µm", out.f_mean, out.z_mean);
//! ```

pub mod banded;
pub mod bench;
pub mod cache;
pub mod case;
pub mod cli;
pub mod dynamics;
pub mod film;
pub mod friction;
pub mod geometry;
pub mod multigrid;
pub mod optimise;
pub mod optimise_report;
pub mod plot;
pub mod pt_multigrid;
pub mod report;
pub mod run;
pub mod scene;
pub mod steady;
pub mod study;
pub mod sweep;
pub mod units;
