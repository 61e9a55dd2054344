//! The lint allowances every emitted item carries, each with its reason, so that a user crate
//! under `#![deny(warnings, clippy::all, clippy::pedantic)]` builds.
//!
//! Most lints skip code whose spans come from a procedural macro, but not all: `approx_constant`
//! fires on the folded `2.0 * PI` = `6.283185307179586` the graph emits. The list is explicit so
//! that the generated code never depends on which lints happen to look through macro spans.

use proc_macro2::TokenStream;
use quote::quote;

/// `#[allow(..)]` attributes for items whose bodies are generated straight-line code.
pub fn generated() -> TokenStream {
    quote! {
        #[allow(
            clippy::approx_constant,
            reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
        )]
        #[allow(
            clippy::excessive_precision,
            clippy::unreadable_literal,
            reason = "folded constants are printed with every digit f64 round-trips, without separators"
        )]
        #[allow(
            clippy::many_single_char_names,
            clippy::similar_names,
            reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
        )]
        #[allow(
            clippy::too_many_lines,
            clippy::let_and_return,
            clippy::neg_multiply,
            clippy::double_parens,
            clippy::unnecessary_cast,
            clippy::float_cmp,
            clippy::suboptimal_flops,
            clippy::imprecise_flops,
            reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
        )]
        #[allow(
            clippy::must_use_candidate,
            clippy::missing_const_for_fn,
            clippy::return_self_not_must_use,
            reason = "accessors of the emitted types; their results are plain values"
        )]
    }
}

/// `#[allow(..)]` attributes for the user's function, re-emitted with `Config` replaced.
pub fn user_function() -> TokenStream {
    quote! {
        #[allow(
            clippy::too_many_arguments,
            reason = "the attribute takes the Lagrangian's parameters as `f64` arguments"
        )]
        #[allow(
            clippy::many_single_char_names,
            reason = "parameters keep the physical symbols (h, m, g, l)"
        )]
    }
}

/// The extra allowance for a user's function that reads array coordinates (`q.x[i]`): the body
/// language unrolls `for` loops over constant ranges and accepts no iterators, so clippy's
/// advice to iterate instead of indexing cannot be followed.
pub fn user_function_indexed() -> TokenStream {
    quote! {
        #[allow(
            clippy::needless_range_loop,
            reason = "`#[reduced_lagrangian]` bodies index array coordinates in unrolled `for` loops; iterators are not accepted"
        )]
    }
}
