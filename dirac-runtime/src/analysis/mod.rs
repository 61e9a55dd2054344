//! What is read off a trajectory or a step: the paper's Dirac structures, energies and action
//! ([`diagnostics`]) and the step map's derivatives ([`sensitivity`]). Each is re-exported at
//! the crate root under its own name.

pub mod diagnostics;
pub mod sensitivity;
