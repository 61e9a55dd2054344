//! The run: the one run loop over any stepper ([`driver`]: steps or an end time, step sizes,
//! controls, stop conditions, observers and the policies applied after every step) and parallel
//! members of an ensemble ([`ensemble`]). Each is re-exported at the crate root under its own
//! name.

pub mod driver;
pub mod ensemble;
