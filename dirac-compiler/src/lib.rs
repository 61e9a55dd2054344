//! The compiler behind dirac's attributes: a discrete Lagrangian written in Rust to the
//! straight-line residual and Jacobian of the reduced (+) and (−) discrete
//! Lagrange–Poincaré–Dirac equations (Rodríguez Abella & Leok, eqs. (4.6), (4.8)), and a change
//! of chart to its transition functions.
//!
//! A plain library on `proc_macro2` tokens: `dirac-macros` wraps it as `#[reduced_lagrangian]`
//! and `#[chart_transition]`, and a run-time front end parses the same text with `syn` and
//! reads the same intermediate representation.
//!
//! Stages, each a module that imports only the ones below it:
//!
//! * `expand` — the attribute's entry: one phase after another, each with its own error context;
//!   `fallback` — the items emitted after an error; [`text`] — the run-time entry: the same
//!   phases on a system given as text, ending in programs;
//! * `back` — the back end: graph → straight-line Rust, the backend choice, the one table of
//!   trait impls (rendered with real or stub bodies), the items around them; and [`program`] —
//!   graph → straight-line program as data, for a code generator at run time;
//! * `ir` — lowering (body → hash-consed graph), the invariance check, forward- and
//!   reverse-mode derivatives, the paper's constructions (reduction, discretization of a
//!   continuous `L`), the configuration groups (`ir::group`);
//! * `front` — the front end: the attribute grammar, the coordinate layout, the signature, the
//!   ranges;
//! * `ctxt` (every error with its span, one report per compilation), `symbol` (the
//!   attribute keys, spelled once) and `stack` (enough stack for deep expressions).

#![warn(missing_docs)]

mod back;
mod ctxt;
mod expand;
mod fallback;
mod front;
#[cfg(test)]
mod fuzz;
mod ir;
mod stack;
mod symbol;
pub mod text;

pub use back::program;

use proc_macro2::TokenStream;

/// `#[reduced_lagrangian(args)] item`: every item the attribute emits, or its errors (as
/// `compile_error!` invocations at their spans) followed by stand-in items with the same
/// signatures, so the caller's other code shows no follow-on errors.
pub fn reduced_lagrangian(args: TokenStream, item: TokenStream) -> TokenStream {
    stack::run(&args, &item, || expand::expand(args.clone(), item.clone()))
}

/// `#[chart_transition(args)] item`: the transition's items, or its errors and stand-in items.
pub fn chart_transition(args: TokenStream, item: TokenStream) -> TokenStream {
    stack::run(&args, &item, || {
        expand::expand_transition(args.clone(), item.clone())
    })
}
