//! `#[reduced_lagrangian]`: a small compiler from a discrete Lagrangian written in Rust to the
//! straight-line residual and Jacobian of the reduced (+) discrete Lagrange–Poincaré–Dirac
//! equations (Rodríguez Abella & Leok, eq. (4.6)).
//!
//! Stages, one file each: `spec` (the attribute and signature) → `lower` (body → graph) →
//! `graph` (hash-consed, simplifying) → `check` (G-invariance of the body, sampled) →
//! `diff` (forward-mode derivatives) → `reduce` (the paper's construction) → `emit`
//! (straight-line Rust); `expand` ties them together and `ctxt` collects every error with its
//! span. See the `dirac` crate for the user guide.

mod adapted;
mod check;
mod continuous;
mod ctxt;
mod diff;
mod emit;
mod expand;
#[cfg(test)]
mod fuzz;
mod graph;
mod lints;
mod lower;
mod reduce;
mod spec;
mod transition;

use proc_macro::TokenStream;

/// Derives a reduced variational integrator from a discrete Lagrangian at compile time.
///
/// See the `dirac` crate's documentation for the attribute syntax and the emitted items.
#[proc_macro_attribute]
pub fn reduced_lagrangian(args: TokenStream, item: TokenStream) -> TokenStream {
    expand::expand(args.into(), item.into()).into()
}

/// Compiles a change of chart `φ : q_from ↦ q_to` between two charts of one system into
/// straight-line code for `φ` and its Jacobian `Dφ` (an implementation of
/// `dirac::runtime::atlas::ChartTransition`), checking at compile time that it is equivariant
/// (`x_to = ψ(x_from)`, `g_to = g_from + c(x_from)`).
///
/// See the `dirac` crate's documentation for the attribute syntax.
#[proc_macro_attribute]
pub fn chart_transition(args: TokenStream, item: TokenStream) -> TokenStream {
    transition::expand(args.into(), item.into()).into()
}
