//! `ranges(name = (lo, hi), ...)`: where the compile-time invariance check samples a parameter
//! or a coordinate.

use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Expr, Ident, Token};

use crate::ctxt::Ctxt;
use crate::front::signature::Signature;
use crate::front::Spec;

/// What `ranges(...)` accepts, for error messages.
pub const RANGES: &str = "`ranges(name = (lo, hi), ...)` with a parameter or coordinate name and finite f64 literals lo < hi, e.g. `ranges(h = (0.001, 0.1))`";

/// One entry of `ranges(name = (lo, hi), ...)`: where the invariance check samples `name`.
pub struct Range {
    pub name: Ident,
    pub lo: f64,
    pub hi: f64,
}

/// The declared sampling ranges resolved against the signature; `None` where the default applies.
pub struct Ranges {
    /// One per user coordinate (an array coordinate's range applies to all its components), in
    /// the order of [`Layout::coords`].
    pub coords: Vec<Option<(f64, f64)>>,
    /// One per parameter, in declaration order.
    pub params: Vec<Option<(f64, f64)>>,
}

/// `name = (lo, hi)` inside `ranges(...)`; the value is checked later, with a span per mistake.
pub struct RangeArg {
    name: Ident,
    value: Expr,
}

impl Parse for RangeArg {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), format!("expected {RANGES}")))?;
        if !input.peek(Token![=]) {
            return Err(syn::Error::new(
                name.span(),
                format!("expected `{name} = (lo, hi)`; accepted: {RANGES}"),
            ));
        }
        input.parse::<Token![=]>()?;
        Ok(RangeArg {
            name,
            value: input.parse()?,
        })
    }
}

/// The entries of `ranges(...)`, each checked (a pair of finite literals, `lo < hi`, no
/// duplicate name).
pub fn parse_ranges(cx: &Ctxt, list: Punctuated<RangeArg, Token![,]>) -> Vec<Range> {
    let mut out: Vec<Range> = Vec::new();
    for RangeArg { name, value } in list {
        if out.iter().any(|r| r.name == name) {
            cx.error_spanned_by(&name, format!("duplicate range for `{name}`"));
            continue;
        }
        let bounds = match &value {
            Expr::Tuple(t) if t.elems.len() == 2 => {
                let lo = range_bound(cx, &t.elems[0]);
                let hi = range_bound(cx, &t.elems[1]);
                lo.zip(hi)
            }
            other => {
                cx.error_spanned_by(
                    other,
                    format!(
                        "expected a pair `(lo, hi)` for `{name}`, found `{}`; accepted: {RANGES}",
                        crate::ctxt::show(&other)
                    ),
                );
                None
            }
        };
        let Some((lo, hi)) = bounds else { continue };
        if lo >= hi {
            cx.error_spanned_by(
                &value,
                format!(
                    "empty range for `{name}`: the lower bound {lo:?} is not below the upper bound {hi:?}; accepted: {RANGES}"
                ),
            );
            continue;
        }
        out.push(Range { name, lo, hi });
    }
    out
}

/// A bound of `ranges(...)`: an f64 or integer literal, optionally negated.
fn range_bound(cx: &Ctxt, e: &Expr) -> Option<f64> {
    let (negated, lit) = match e {
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => (true, &*u.expr),
        other => (false, other),
    };
    let value = match lit {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Float(f),
            ..
        }) => f.base10_parse::<f64>().ok(),
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(i),
            ..
        }) => i.base10_parse::<f64>().ok(),
        _ => None,
    };
    let Some(value) = value else {
        cx.error_spanned_by(
            e,
            format!(
                "range bounds must be f64 literals, found `{}`; accepted: {RANGES}",
                crate::ctxt::show(&e)
            ),
        );
        return None;
    };
    if !value.is_finite() {
        cx.error_spanned_by(
            e,
            format!(
                "range bound `{}` is not a finite f64; accepted: {RANGES}",
                crate::ctxt::show(&e)
            ),
        );
        return None;
    }
    Some(if negated { -value } else { value })
}

/// Resolves the names in `ranges(...)` against the parameters and coordinates.
pub fn resolve_ranges(cx: &Ctxt, spec: &Spec, sig: &Signature) -> Ranges {
    let coords: Vec<&Ident> = spec.layout.coords.iter().map(|c| &c.name).collect();
    let mut out = Ranges {
        coords: vec![None; coords.len()],
        params: vec![None; sig.params.len()],
    };
    for r in &spec.ranges {
        let param = sig.params.iter().position(|p| *p == r.name);
        let coord = coords.iter().position(|c| **c == r.name);
        match (param, coord) {
            (Some(_), Some(_)) => cx.error_spanned_by(
                &r.name,
                format!(
                    "`{}` is both a parameter and a coordinate, so `ranges({} = ...)` is ambiguous: rename the parameter",
                    r.name, r.name
                ),
            ),
            (Some(i), None) => out.params[i] = Some((r.lo, r.hi)),
            (None, Some(i)) => out.coords[i] = Some((r.lo, r.hi)),
            (None, None) => {
                let names: Vec<String> = sig
                    .params
                    .iter()
                    .chain(coords.iter().copied())
                    .map(|n| format!("`{n}`"))
                    .collect();
                cx.error_spanned_by(
                    &r.name,
                    format!(
                        "`{}` is not a parameter or coordinate; `ranges(...)` accepts the parameters and coordinates: {}",
                        r.name,
                        names.join(", ")
                    ),
                );
            }
        }
    }
    out
}
