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
    /// A model of articulated rigid bodies whose system text cannot be written
    /// ([`crate::compile_model`]).
    #[error("{0}")]
    Model(#[from] dirac_multibody::ModelError),
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
    /// unknowns in a solve, sparse above).
    #[error(
        "the system `{name}` has {n} unknowns in each {} solve: instantiate it with `{}{}` (the dense backend takes at most {dense_max}, the sparse one more)",
        if *constrained { "constrained" } else { "step" },
        if *constrained { "instantiate_constrained" } else { "instantiate" },
        if *n > *dense_max { "_sparse" } else { "" }
    )]
    Backend {
        /// The system's type name.
        name: String,
        /// The unknowns of each solve: the coordinates `N`, or `Z = N + M` for the constrained
        /// solves.
        n: usize,
        /// The most unknowns of the dense backend.
        dense_max: usize,
        /// Whether the solves are the constrained ones.
        constrained: bool,
    },
    /// The constraints asked for are not the system's: another number of them, none declared,
    /// or `Z` not `N + M`.
    #[error(
        "the system `{name}` has {m} constraints; it was asked for with M = {want_m}, Z = {want_z} (Z is N + M = {n} + M)"
    )]
    Constraints {
        /// The system's type name.
        name: String,
        /// Its constraints (0 when it declares none).
        m: usize,
        /// Its coordinates.
        n: usize,
        /// The `M` asked for.
        want_m: usize,
        /// The `Z` asked for.
        want_z: usize,
    },
    /// The dimensions a program asked for a system on rotation groups are not the system's.
    #[error(
        "the system `{name}` has points of {p} entries and {n} chart coordinates; it was asked for as P = {want_p}, N = {want_n}"
    )]
    LieDimensions {
        /// The system's type name.
        name: String,
        /// The entries of its stored point.
        p: usize,
        /// Its chart coordinates, the dimension of its configuration space.
        n: usize,
        /// The `P` asked for.
        want_p: usize,
        /// The `N` asked for.
        want_n: usize,
    },
    /// A reduced system was asked for where the text declares no symmetry to reduce by, or
    /// where its reduced step cannot run on the backend asked for.
    #[error("the system `{name}` cannot be reduced: {reason}")]
    Symmetry {
        /// The system's type name.
        name: String,
        /// Why.
        reason: String,
    },
    /// A state the system cannot take: a wrong number of entries, a matrix that is not a
    /// rotation, a vector that is not a unit vector, a value that is not finite.
    #[error("a state of `{name}`: {reason}")]
    State {
        /// The system's type name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// An element-wise system that cannot be compiled or instantiated as asked: more sizes,
    /// stencil slots or nested loops than a system given at run time may have, a wrong number of
    /// sizes, or sizes at which a stencil's index arithmetic overflows.
    #[error("the element-wise system `{name}`: {reason}")]
    Element {
        /// The system's type name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// The runtime's typed error for what it refuses before any step: here
    /// [`StepError::OutOfMemory`](dirac_runtime::StepError::OutOfMemory) when the sizes of an
    /// element-wise system imply tables of elements that cannot be allocated (checked before
    /// allocating, as a run checks its workspace).
    #[error(transparent)]
    Step(#[from] dirac_runtime::StepError),
    /// A run request the system cannot run: an unknown word for its equations, an order other
    /// than 2, 4 or 6 (other than 2 with constraints), reduced equations of a system without
    /// them, a tolerance that is not a positive finite number ([`crate::RunRequest`]).
    #[error("{reason}")]
    Request {
        /// What is wrong, and what is accepted.
        reason: String,
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
