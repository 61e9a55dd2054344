//! `#[reduced_lagrangian]`: a small compiler from a discrete Lagrangian written in Rust to the
//! straight-line residual and Jacobian of the reduced (+) discrete Lagrange–Poincaré–Dirac
//! equations (Rodríguez Abella & Leok, eq. (4.6)); and `#[chart_transition]`, the same compiler
//! for a change of chart.
//!
//! Stages, each a module that imports only the ones below it:
//!
//! * `expand` — the entry: one phase after another, each with its own error context;
//!   `fallback` — the items emitted after an error;
//! * `codegen` — graph → straight-line Rust, the backend choice, the one table of trait impls
//!   (rendered with real or stub bodies), the items around them;
//! * `ir` — lowering (body → hash-consed graph), the invariance check, forward- and
//!   reverse-mode derivatives, the paper's constructions (reduction, discretization of a continuous `L`);
//! * `ast` — the attribute grammar, the coordinate layout, the signature, the ranges;
//! * `ctxt` (every error with its span, one report per compilation), `symbol` (the
//!   attribute keys, spelled once) and `stack` (enough stack for deep expressions).
//!
//! The user guide is the `dirac` crate's documentation; the attributes' own documentation below
//! is the reference of their syntax.

#![warn(missing_docs)]

mod ast;
mod codegen;
mod ctxt;
mod expand;
mod fallback;
#[cfg(test)]
mod fuzz;
mod ir;
mod stack;
mod symbol;

use proc_macro::TokenStream;

#[doc = include_str!("../docs/reduced_lagrangian.md")]
#[proc_macro_attribute]
pub fn reduced_lagrangian(args: TokenStream, item: TokenStream) -> TokenStream {
    let (args, item) = (args.into(), item.into());
    stack::run(&args, &item, || expand::expand(args.clone(), item.clone())).into()
}

#[doc = include_str!("../docs/chart_transition.md")]
#[proc_macro_attribute]
pub fn chart_transition(args: TokenStream, item: TokenStream) -> TokenStream {
    let (args, item) = (args.into(), item.into());
    stack::run(&args, &item, || {
        expand::expand_transition(args.clone(), item.clone())
    })
    .into()
}
