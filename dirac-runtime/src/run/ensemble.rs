//! Ensembles: one system integrated from many initial states, or many parameter sets, in
//! parallel, each member with its own typed result.
//!
//! Members are independent integrations, so they are distributed over rayon's thread pool (one
//! workspace per member, nothing shared but the read-only stepper). A failed member is an `Err`
//! at its position, carrying its step index, residual and the trajectory it computed; the others
//! are unaffected. Results come back in input order, and each is bit-for-bit what a sequential
//! integration of that member gives (the arithmetic of a member does not depend on the thread it
//! runs on). To run on a given number of threads, configure the ensemble with `.threads(n)`.
//!
//! Ensembles over initial states are [`crate::Drive::ensemble`]; ensembles over parameter sets
//! are [`crate::driver::parameters`]. Both run on [`map`].

use rayon::prelude::*;

/// The thread pool the ensembles run on (e.g. `rayon::ThreadPoolBuilder` to fix the number of
/// threads).
pub use rayon;

/// `f` applied to every item in parallel, results in input order: any per-member computation.
///
/// ```
/// # use dirac_runtime::ensemble;
/// let squares = ensemble::map(&[1.0, 2.0, 3.0], |x| x * x);
/// assert_eq!(squares, vec![1.0, 4.0, 9.0]);
/// ```
pub fn map<T, R>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R>
where
    T: Sync,
    R: Send,
{
    items.par_iter().map(f).collect()
}
