//! Ready-made systems beside the paper's ([`crate::paper`]): test beds with known solutions that
//! the examples, the benchmarks and the guide use, each written with the attribute as a user
//! would write it.

pub mod kepler;
pub mod rotations;
