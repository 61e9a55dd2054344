//! `#[reduced_lagrangian]` and `#[chart_transition]`: the procedural-macro entries to dirac's
//! compiler (the `dirac-compiler` crate), which does all the work on `proc_macro2` tokens; this
//! crate only converts the tokens rustc hands it.
//!
//! The user guide is the `dirac` crate's documentation; the attributes' own documentation below
//! is the reference of their syntax.

#![warn(missing_docs)]

use proc_macro::TokenStream;

#[doc = include_str!("../docs/reduced_lagrangian.md")]
#[proc_macro_attribute]
pub fn reduced_lagrangian(args: TokenStream, item: TokenStream) -> TokenStream {
    dirac_compiler::reduced_lagrangian(args.into(), item.into()).into()
}

#[doc = include_str!("../docs/chart_transition.md")]
#[proc_macro_attribute]
pub fn chart_transition(args: TokenStream, item: TokenStream) -> TokenStream {
    dirac_compiler::chart_transition(args.into(), item.into()).into()
}
