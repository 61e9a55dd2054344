//! The attribute of `#[chart_transition(from(shape(..), group(..)), to(shape(..), group(..)),
//! name = Name)]`, a change of chart `φ : q_from ↦ q_to` between two charts of one system, and
//! its signature `fn f(q: Config) -> (f64, ..)`. The body is compiled like a Lagrangian
//! ([`crate::ir::transition`]) into straight-line `φ` and `Dφ`, which the atlas integrator needs
//! for the cotangent lift of the momenta (`p_to = Dφ^{-T} p_from`, §6 of the paper).

use proc_macro2::{Span, TokenStream};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{FnArg, Ident, ItemFn, Pat, Token};

use crate::ctxt::Ctxt;
use crate::symbol::{self, KeyArg, FROM, GROUP, NAME, SHAPE, TO};

const USAGE: &str = "accepted: `#[chart_transition(from(shape(..), group(..)), \
to(shape(..), group(..)), name = Name)]` (`name` optional)";

/// One side of the transition: its shape and group coordinate names.
pub struct Side {
    /// The shape coordinates.
    pub shape: Vec<Ident>,
    /// The group coordinates.
    pub group: Vec<Ident>,
}

/// The parsed attribute.
pub struct TransitionSpec {
    /// The old chart.
    pub from: Side,
    /// The new chart.
    pub to: Side,
    /// `name = ..`: the emitted type, if not the function's name in CamelCase.
    pub name: Option<Ident>,
}

/// `from(..)` or `to(..)` (a side), or `name = ..`.
type Arg = KeyArg<Side, Ident>;

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
            let slot = if key == SHAPE {
                &mut shape
            } else if key == GROUP {
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
        let unexpected =
            |key: &Ident| syn::Error::new(key.span(), format!("unexpected `{key}`; {USAGE}"));
        KeyArg::parse_with(
            input,
            |key, content| {
                if key == FROM || key == TO {
                    content.parse()
                } else {
                    Err(unexpected(key))
                }
            },
            |key, input| {
                if key == NAME {
                    input.parse()
                } else {
                    Err(unexpected(key))
                }
            },
            |key| unexpected(key).to_string(),
        )
    }
}

/// Parses the attribute, recording every mistake in `cx`.
pub fn parse_spec(cx: &Ctxt, args: TokenStream) -> Option<TransitionSpec> {
    let args = symbol::parse_args::<Arg>(cx, args)?;
    let (mut from, mut to, mut name) = (None, None, None);
    for arg in args {
        match arg {
            KeyArg::List(key, side) => {
                let slot = if key == FROM { &mut from } else { &mut to };
                if slot.is_some() {
                    cx.error_spanned_by(&key, format!("duplicate `{key}` argument"));
                }
                *slot = Some(side);
            }
            KeyArg::Value(key, n) => {
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
    for (what, a, b) in [
        (SHAPE, from.shape.len(), to.shape.len()),
        (GROUP, from.group.len(), to.group.len()),
    ] {
        if a != b {
            cx.error_at(
                Span::call_site(),
                format!(
                    "both charts must have the same number of {what} coordinates: `from` has {a}, `to` has {b}"
                ),
            );
        }
    }
    Some(TransitionSpec { from, to, name })
}

/// The single argument `q: Config`.
pub fn parse_signature(cx: &Ctxt, func: &ItemFn) -> Option<Ident> {
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
