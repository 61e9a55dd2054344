//! What can go wrong between a system's text and its first step.

/// Why a system given at run time could not be compiled or instantiated.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The text has mistakes: the attribute's own messages, with lines and columns.
    #[error("{0}")]
    Text(#[from] dirac_compiler::text::Error),
    /// Cranelift could not generate the machine code (an unsupported machine, or a bug).
    #[error("code generation failed: {0}")]
    Codegen(String),
    /// The dimensions a program asked for are not the system's.
    #[error(
        "the system `{name}` has {s} shape and {k} group coordinates (N = {n}); it was asked for as S = {want_s}, K = {want_k}, N = {want_n}"
    )]
    Dimensions {
        /// The system's type name.
        name: String,
        /// Its shape coordinates.
        s: usize,
        /// Its group coordinates.
        k: usize,
        /// `S + K`.
        n: usize,
        /// The `S` asked for.
        want_s: usize,
        /// The `K` asked for.
        want_k: usize,
        /// The `N` asked for.
        want_n: usize,
    },
    /// The backend asked for is not the one of the system's size (dense up to `dense_max`
    /// coordinates, sparse above).
    #[error(
        "the system `{name}` has {n} coordinates: instantiate it with `{}` (the dense backend takes at most {dense_max} coordinates, the sparse one more)",
        if *n > *dense_max { "instantiate_sparse" } else { "instantiate" }
    )]
    Backend {
        /// The system's type name.
        name: String,
        /// Its coordinates.
        n: usize,
        /// The most coordinates of the dense backend.
        dense_max: usize,
    },
    /// The parameter values do not match the declared parameters.
    #[error("parameters of `{name}`: {reason}; declared: {declared}")]
    Parameters {
        /// The system's type name.
        name: String,
        /// What is wrong.
        reason: String,
        /// The declared parameters, in order.
        declared: String,
    },
}
