//! `#[chart_transition]`'s back end: the struct, its `FROM`/`TO` constants and
//! `impl ChartTransition` with straight-line `φ` and `Dφ`, through the table of
//! [`crate::back::impls`] (so the stubs after an error have the same signatures).

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Ident, ItemFn};

use crate::back::emit::straight_line;
use crate::back::impls::{self, Bodies};
use crate::back::items::camel_case;
use crate::front::transition::TransitionSpec;
use crate::ir::graph::Sym;
use crate::ir::transition::Transition;

/// The emitted type's name: `name = ..`, or the function's name in CamelCase.
pub fn type_name(spec: Option<&TransitionSpec>, func: &ItemFn) -> Ident {
    spec.and_then(|s| s.name.clone())
        .unwrap_or_else(|| camel_case(&func.sig.ident))
}

/// The coordinate names of both charts, shape then group.
fn chart_names(spec: &TransitionSpec) -> (Vec<String>, Vec<String>) {
    let names = |side: &crate::front::transition::Side| -> Vec<String> {
        side.shape
            .iter()
            .chain(&side.group)
            .map(Ident::to_string)
            .collect()
    };
    (names(&spec.from), names(&spec.to))
}

/// The struct, with the user's documentation and `note`.
fn item(func: &ItemFn, name: &Ident, note: &str) -> TokenStream {
    let vis = &func.vis;
    let docs = func.attrs.iter().filter(|a| a.path().is_ident("doc"));
    quote! {
        #( #docs )*
        #[doc = #note]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        #vis struct #name;
    }
}

/// Every item of a compiled transition.
pub fn generate(spec: &TransitionSpec, func: &ItemFn, t: &Transition) -> TokenStream {
    let (s, k) = (spec.from.shape.len(), spec.from.group.len());
    let n = s + k;
    let (graph, phi, columns) = (&t.graph, &t.phi, &t.columns);
    let na = quote!(::dirac::nalgebra);
    let name = type_name(Some(spec), func);
    let leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote! { q[#i] },
        other => unreachable!("a transition reads only its configuration, not {other:?}"),
    };
    let value = straight_line(graph, phi, &leaf);
    let (v_stmts, v_out) = (&value.stmts, &value.outputs);
    let mut roots = phi.to_vec();
    for col in columns {
        roots.extend(col.iter().copied());
    }
    let both = straight_line(graph, &roots, &leaf);
    let b_stmts = &both.stmts;
    let b_val = &both.outputs[..n];
    let mut sets = TokenStream::new();
    for (j, col) in both.outputs[n..].chunks(n).enumerate() {
        for (i, e) in col.iter().enumerate() {
            if graph.as_const(columns[j][i]) != Some(0.0) {
                sets.extend(quote! { d[(#i, #j)] = #e; });
            }
        }
    }
    let (from, to) = chart_names(spec);
    let note = format!(
        "\n\nA chart transition `({}) ↦ ({})`, emitted by `#[chart_transition]`: straight-line \
         code for `φ` and `Dφ` ({} operations together).",
        from.join(", "),
        to.join(", "),
        both.operations
    );
    let bodies = Bodies::Real(HashMap::from([
        (
            "map",
            quote! {
                #v_stmts
                #na::SVector::<f64, #n>::from([ #( #v_out ),* ])
            },
        ),
        (
            "map_jacobian",
            quote! {
                #b_stmts
                let mut d = #na::SMatrix::<f64, #n, #n>::zeros();
                #sets
                (#na::SVector::<f64, #n>::from([ #( #b_val ),* ]), d)
            },
        ),
    ]));
    let mut out = item(func, &name, &note);
    out.extend(impls::transition_inherent(&name, &from, &to).render(&bodies));
    out.extend(impls::chart_transition(&name, s, k).render(&bodies));
    out
}

/// After an error: the struct, and, when the attribute parsed, its constants and
/// `impl ChartTransition` with the real signatures and bodies never reached.
pub fn stubs(spec: Option<&TransitionSpec>, func: &ItemFn) -> TokenStream {
    let name = type_name(spec, func);
    let note = "\n\nA chart transition emitted by `#[chart_transition]`, which reported an error.";
    let mut out = item(func, &name, note);
    if let Some(spec) = spec {
        let (s, k) = (spec.from.shape.len(), spec.from.group.len());
        let (from, to) = chart_names(spec);
        let stub = Bodies::Stub("chart_transition");
        out.extend(impls::transition_inherent(&name, &from, &to).render(&stub));
        out.extend(impls::chart_transition(&name, s, k).render(&stub));
    }
    out
}
