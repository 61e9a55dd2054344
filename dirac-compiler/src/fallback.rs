//! After an error, the items the user's other code refers to, so the real error is not buried
//! under follow-on ones (thiserror's `fallback.rs`): the same items as a successful expansion,
//! with the same signatures — the trait impls rendered from the one table of
//! [`crate::back::impls`] with bodies never reached, the rest from the same functions as the
//! real items.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ItemFn;

use crate::back::items::{config_struct, param_struct, type_name, user_function};
use crate::back::{adapted, system, transition};
use crate::front::signature::Signature;
use crate::front::transition::TransitionSpec;
use crate::front::Spec;

/// The fallback of `#[reduced_lagrangian]`: as much as the attribute and signature determine.
pub fn reduced_lagrangian(
    spec: Option<&Spec>,
    sig: Option<&Signature>,
    func: &ItemFn,
) -> TokenStream {
    let Some(spec) = spec else {
        return quote! { #func };
    };
    let ty = type_name(spec, func);
    let config = format_ident!("{}Config", ty);
    let mut out = config_struct(spec, func, &config, &ty);
    out.extend(adapted::adapted_impl(&spec.layout, &ty));
    out.extend(user_function(
        func,
        &config,
        true,
        &[],
        spec.layout.has_arrays(),
    ));
    if let Some(sig) = sig {
        out.extend(param_struct(sig, func, &ty));
        out.extend(system::stubs(spec, sig, &ty));
    }
    out
}

/// The fallback of `#[chart_transition]`: the struct, and its impls when the attribute parsed.
pub fn chart_transition(spec: Option<&TransitionSpec>, func: &ItemFn) -> TokenStream {
    transition::stubs(spec, func)
}
