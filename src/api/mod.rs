//! What every front end asks of the library: the command line (`cli`) and the Python package
//! (`python/`) read the same inputs into the same case, run it the same way and answer with
//! the same JSON, so that an answer does not depend on where it was asked. Inputs are named
//! as the model names them (`l1`, `depth`, `roughness`); each front end turns those names
//! into its own (`--l1`, a keyword argument).

pub mod simulate;

pub use simulate::{
    answer, progress, AnswerFailure, Answered, ContactInputs, OperatingInputs, SimulateInputs,
};
