//! `#[chart_transition]`: a change of chart `φ : q_from ↦ q_to` between two charts of one system,
//! compiled like a Lagrangian — the same lowering, graph and forward-mode differentiation — into
//! straight-line code for `φ` and its Jacobian `Dφ`, which the atlas integrator needs for the
//! cotangent lift of the momenta (`p_to = Dφ^{-T} p_from`, §6 of the paper).
//!
//! Both charts must trivialize the same symmetry by translation, so `φ` must be equivariant:
//! `φ(x, g + a) = φ(x, g) + (0, a)`, i.e. `x_to = ψ(x_from)` and `g_to = g_from + c(x_from)`.
//! This is checked symbolically on the derivative graph: `∂x_to/∂g_from` must fold to 0 and
//! `∂g_to/∂g_from` to the identity. A transition that fails the check is a compile error.

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{FnArg, Ident, ItemFn, Pat, Token};

use crate::ctxt::Ctxt;
use crate::diff::derivatives;
use crate::emit::straight_line;
use crate::graph::{Graph, NodeId, Sym};
use crate::lints;
use crate::lower::{CoordName, Lowering, Names};

const USAGE: &str = "accepted: `#[chart_transition(from(shape(..), group(..)), \
to(shape(..), group(..)), name = Name)]` (`name` optional)";

/// One side of the transition: its shape and group coordinate names.
struct Side {
    shape: Vec<Ident>,
    group: Vec<Ident>,
}

struct Spec {
    from: Side,
    to: Side,
    name: Option<Ident>,
}

enum Arg {
    Side(Ident, Side),
    Name(Ident, Ident),
}

fn ident_list(input: ParseStream) -> syn::Result<Vec<Ident>> {
    let content;
    syn::parenthesized!(content in input);
    Ok(Punctuated::<Ident, Token![,]>::parse_terminated(&content)?
        .into_iter()
        .collect())
}

impl Parse for Side {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let mut shape = None;
        let mut group = None;
        while !input.is_empty() {
            let key: Ident = input.parse()?;
            let slot = if key == "shape" {
                &mut shape
            } else if key == "group" {
                &mut group
            } else {
                return Err(syn::Error::new(
                    key.span(),
                    format!("unknown key `{key}`; expected `shape(..)` and `group(..)`"),
                ));
            };
            if slot.is_some() {
                return Err(syn::Error::new(key.span(), format!("duplicate `{key}`")));
            }
            *slot = Some(ident_list(input)?);
            if !input.is_empty() {
                input.parse::<Token![,]>()?;
            }
        }
        match (shape, group) {
            (Some(shape), Some(group)) => Ok(Side { shape, group }),
            _ => Err(input.error("expected both `shape(..)` and `group(..)`")),
        }
    }
}

impl Parse for Arg {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let key: Ident = input.parse()?;
        if (key == "from" || key == "to") && input.peek(syn::token::Paren) {
            let content;
            syn::parenthesized!(content in input);
            Ok(Arg::Side(key, content.parse()?))
        } else if key == "name" && input.peek(Token![=]) {
            input.parse::<Token![=]>()?;
            Ok(Arg::Name(key, input.parse()?))
        } else {
            Err(syn::Error::new(
                key.span(),
                format!("unexpected `{key}`; {USAGE}"),
            ))
        }
    }
}

fn parse_spec(cx: &Ctxt, args: TokenStream) -> Option<Spec> {
    let parser = Punctuated::<Arg, Token![,]>::parse_terminated;
    let args = match syn::parse::Parser::parse2(parser, args) {
        Ok(a) => a,
        Err(e) => {
            cx.syn_error(e);
            return None;
        }
    };
    let (mut from, mut to, mut name) = (None, None, None);
    for arg in args {
        match arg {
            Arg::Side(key, side) => {
                let slot = if key == "from" { &mut from } else { &mut to };
                if slot.is_some() {
                    cx.error_spanned_by(&key, format!("duplicate `{key}` argument"));
                }
                *slot = Some(side);
            }
            Arg::Name(key, n) => {
                if name.is_some() {
                    cx.error_spanned_by(&key, "duplicate `name` argument");
                }
                name = Some(n);
            }
        }
    }
    let (Some(from), Some(to)) = (from, to) else {
        cx.error_at(
            Span::call_site(),
            format!("`from(..)` and `to(..)` are both required; {USAGE}"),
        );
        return None;
    };
    for side in [&from, &to] {
        let all: Vec<&Ident> = side.shape.iter().chain(&side.group).collect();
        for (i, id) in all.iter().enumerate() {
            if all[..i].contains(id) {
                cx.error_spanned_by(id, format!("coordinate `{id}` declared twice"));
            }
        }
        if side.group.is_empty() {
            cx.error_at(
                Span::call_site(),
                "a chart transition needs at least one group coordinate",
            );
        }
    }
    if from.shape.len() != to.shape.len() {
        cx.error_at(
            Span::call_site(),
            format!(
                "both charts must have the same number of shape coordinates: `from` has {}, `to` has {}",
                from.shape.len(),
                to.shape.len()
            ),
        );
    }
    if from.group.len() != to.group.len() {
        cx.error_at(
            Span::call_site(),
            format!(
                "both charts must have the same number of group coordinates: `from` has {}, `to` has {}",
                from.group.len(),
                to.group.len()
            ),
        );
    }
    Some(Spec { from, to, name })
}

/// The single argument `q: Config`.
fn parse_signature(cx: &Ctxt, func: &ItemFn) -> Option<Ident> {
    let mut inputs = func.sig.inputs.iter();
    let first = match (inputs.next(), inputs.next()) {
        (Some(first), None) => first,
        (_, Some(extra)) => {
            cx.error_spanned_by(
                extra,
                "a chart transition takes exactly one argument, the configuration `q: Config`",
            );
            return None;
        }
        (None, None) => {
            cx.error_spanned_by(
                &func.sig,
                "a chart transition takes the configuration `q: Config`",
            );
            return None;
        }
    };
    match first {
        FnArg::Typed(pt) => match &*pt.pat {
            Pat::Ident(p) => Some(p.ident.clone()),
            other => {
                cx.error_spanned_by(other, "expected a plain argument name, `q: Config`");
                None
            }
        },
        FnArg::Receiver(r) => {
            cx.error_spanned_by(r, "expected `q: Config`, found `self`");
            None
        }
    }
}

pub fn expand(args: TokenStream, item: TokenStream) -> TokenStream {
    let func: ItemFn = match syn::parse2(item) {
        Ok(f) => f,
        Err(e) => return e.into_compile_error(),
    };
    let cx = Ctxt::default();
    let spec = parse_spec(&cx, args);
    let q = parse_signature(&cx, &func);
    let out = match (&spec, &q) {
        (Some(spec), Some(q)) if !cx.has_errors() => compile(&cx, spec, q, &func),
        _ => None,
    };
    match (cx.into_result(), out) {
        (Ok(()), Some(out)) => out,
        (Err(e), _) => {
            let mut ts = e.into_compile_error();
            // Still emit the type, so uses of it do not add follow-on errors.
            let vis = &func.vis;
            let name = spec
                .as_ref()
                .and_then(|s| s.name.clone())
                .unwrap_or_else(|| type_name(&func));
            ts.extend(quote! { #vis struct #name; });
            ts
        }
        (Ok(()), None) => unreachable!("every failed stage records an error"),
    }
}

fn compile(cx: &Ctxt, spec: &Spec, q: &Ident, func: &ItemFn) -> Option<TokenStream> {
    let (s, k) = (spec.from.shape.len(), spec.from.group.len());
    let n = s + k;
    // The body reads `q.name` as a coordinate of `q0`; the `q1` slot is a name no body can use.
    let unused = Ident::new("__dirac_no_second_configuration", Span::call_site());
    let names = Names {
        q0: q,
        q1: &unused,
        coords: CoordName::scalars(
            spec.from
                .shape
                .iter()
                .chain(&spec.from.group)
                .map(Ident::to_string),
        ),
        params: Vec::new(),
    };
    let mut graph = Graph::default();
    let phi = Lowering::new(&mut graph, cx, &names).body_tuple(&func.block, n)?;
    // Dφ by columns: one forward pass per coordinate of the old chart.
    let columns: Vec<Vec<NodeId>> = (0..n)
        .map(|j| derivatives(&mut graph, &phi, Sym::Q0(j)))
        .collect();
    check_equivariance(cx, &graph, spec, &columns, func);
    if cx.has_errors() {
        return None;
    }
    Some(generate(spec, func, &graph, &phi, &columns, s, k))
}

/// `∂x_to/∂g_from = 0` and `∂g_to/∂g_from = I`, structurally (after folding).
fn check_equivariance(
    cx: &Ctxt,
    graph: &Graph,
    spec: &Spec,
    columns: &[Vec<NodeId>],
    func: &ItemFn,
) {
    let s = spec.from.shape.len();
    let to: Vec<&Ident> = spec.to.shape.iter().chain(&spec.to.group).collect();
    for (jg, g_from) in spec.from.group.iter().enumerate() {
        for (i, to_name) in to.iter().enumerate() {
            let expected = if i == s + jg { 1.0 } else { 0.0 };
            if graph.as_const(columns[s + jg][i]) != Some(expected) {
                let what = if i < s {
                    format!("the shape coordinate `{to_name}` must not depend on `{g_from}`")
                } else if i == s + jg {
                    format!(
                        "`{to_name}` must be `{g_from}` plus a function of the shape coordinates"
                    )
                } else {
                    format!("`{to_name}` must not depend on `{g_from}`")
                };
                cx.error_spanned_by(
                    &func.sig.ident,
                    format!(
                        "the transition is not equivariant (the symmetry must act by translation \
                         of the group coordinates in both charts, so `x_to = ψ(x_from)` and \
                         `g_to = g_from + c(x_from)`): {what}"
                    ),
                );
            }
        }
    }
}

fn type_name(func: &ItemFn) -> Ident {
    let camel: String = func
        .sig
        .ident
        .to_string()
        .split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
        })
        .collect();
    Ident::new(&camel, func.sig.ident.span())
}

fn generate(
    spec: &Spec,
    func: &ItemFn,
    graph: &Graph,
    phi: &[NodeId],
    columns: &[Vec<NodeId>],
    s: usize,
    k: usize,
) -> TokenStream {
    let n = s + k;
    let na = quote!(::dirac::nalgebra);
    let name = spec.name.clone().unwrap_or_else(|| type_name(func));
    let vis = &func.vis;
    let docs = func.attrs.iter().filter(|a| a.path().is_ident("doc"));
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
    let from: Vec<String> = spec
        .from
        .shape
        .iter()
        .chain(&spec.from.group)
        .map(Ident::to_string)
        .collect();
    let to: Vec<String> = spec
        .to
        .shape
        .iter()
        .chain(&spec.to.group)
        .map(Ident::to_string)
        .collect();
    let note = format!(
        "\n\nA chart transition `({}) ↦ ({})`, emitted by `#[chart_transition]`: straight-line \
         code for `φ` and `Dφ` ({} operations together).",
        from.join(", "),
        to.join(", "),
        both.operations
    );
    let allow = lints::generated();
    quote! {
        #( #docs )*
        #[doc = #note]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        #vis struct #name;

        #allow
        impl #name {
            /// The coordinates of the old chart, shape then group.
            pub const FROM: [&'static str; #n] = [ #( #from ),* ];
            /// The coordinates of the new chart, shape then group.
            pub const TO: [&'static str; #n] = [ #( #to ),* ];
        }

        #allow
        impl ::dirac::runtime::atlas::ChartTransition<#s, #k, #n> for #name {
            #[allow(unused_variables)] // a coordinate the map does not need is still read
            fn map(&self, q: &#na::SVector<f64, #n>) -> #na::SVector<f64, #n> {
                #v_stmts
                #na::SVector::<f64, #n>::from([ #( #v_out ),* ])
            }

            #[allow(unused_variables)] // a coordinate the map does not need is still read
            fn map_jacobian(
                &self,
                q: &#na::SVector<f64, #n>,
            ) -> (#na::SVector<f64, #n>, #na::SMatrix<f64, #n, #n>) {
                #b_stmts
                let mut d = #na::SMatrix::<f64, #n, #n>::zeros();
                #sets
                (#na::SVector::<f64, #n>::from([ #( #b_val ),* ]), d)
            }
        }
    }
}
