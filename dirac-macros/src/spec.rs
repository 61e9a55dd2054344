//! The attribute and the function signature: which coordinates are shape and which are group,
//! the parameters, the time step and the connection.
//!
//! ```text
//! #[reduced_lagrangian(
//!     shape(x, y, z),              // shape coordinates x ∈ Σ (required, may be empty: `shape()`)
//!     group(theta),                // group coordinates g ∈ G, translated by the action (required, may be empty: `group()`)
//!     connection = [[0.0, b, 0.0]],// optional K × S matrix B: ω_d = (g1 − g0) − B (x1 − x0)
//!     step = h,                    // optional: the time-step parameter (default: the one named `h`)
//!     name = ChargedParticle,      // optional: the emitted type (default: the function name in CamelCase)
//!     ranges(h = (0.001, 0.1)),    // optional: where the invariance check samples a parameter or coordinate
//! )]
//! fn f(q0: Config, q1: Config, h: f64, m: f64) -> f64 { … }
//! ```
//!
//! or a continuous Lagrangian `L(q, v)` with a quadrature rule that forms `L_d` (see
//! [`crate::continuous`]); the time step need not be an argument of `L`, the emitted type has a
//! field for it either way:
//!
//! ```text
//! #[reduced_lagrangian(shape(x, y, z), group(theta), rule = left)]
//! fn l(q: Config, v: Velocity, m: f64) -> f64 { … }
//! ```

use proc_macro2::Span;
use quote::ToTokens;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::spanned::Spanned;
use syn::{Expr, Ident, Token};

use crate::continuous::{Rule, RULES};
use crate::ctxt::Ctxt;

const KEYS: &str = "`shape(...)`, `group(...)`, `connection = [[...], ...]`, `step = <parameter>`, `name = <TypeName>`, `rule = midpoint | trapezoid | left | right` and `ranges(<name> = (lo, hi), ...)`";

/// What `ranges(...)` accepts, for error messages.
const RANGES: &str = "`ranges(name = (lo, hi), ...)` with a parameter or coordinate name and finite f64 literals lo < hi, e.g. `ranges(h = (0.001, 0.1))`";

/// The parsed attribute.
pub struct Spec {
    pub shape: Vec<Ident>,
    pub group: Vec<Ident>,
    /// Rows of `B`, one per group coordinate, each with one entry per shape coordinate.
    pub connection: Option<Vec<Vec<Expr>>>,
    pub step: Option<Ident>,
    pub name: Option<Ident>,
    /// Sampling ranges declared with `ranges(...)` for the invariance check, by name.
    pub ranges: Vec<Range>,
    /// `rule = ...`: the quadrature rule of a continuous Lagrangian, with the key's token.
    pub rule: Option<(Ident, Rule)>,
    /// Whether `rule = ...` was written, valid or not (an invalid one is already reported).
    pub rule_written: bool,
}

/// One entry of `ranges(name = (lo, hi), ...)`: where the invariance check samples `name`.
pub struct Range {
    pub name: Ident,
    pub lo: f64,
    pub hi: f64,
}

/// The declared sampling ranges resolved against the signature; `None` where the default applies.
pub struct Ranges {
    /// One per coordinate, in configuration order (shape, then group).
    pub coords: Vec<Option<(f64, f64)>>,
    /// One per parameter, in declaration order.
    pub params: Vec<Option<(f64, f64)>>,
}

/// The parsed function signature.
pub struct Signature {
    pub q0: Ident,
    pub q1: Ident,
    pub params: Vec<Ident>,
    /// The time-step parameter.
    pub step: Ident,
    /// Whether the function is a continuous Lagrangian `L(q, v)` (second argument `Velocity`);
    /// then `q0`, `q1` above are the names of `q` and `v`.
    pub continuous: bool,
    /// Whether the time step is a field of the emitted type but not an argument of the function
    /// (a continuous `L` need not take `h`): then it is the last of `params`.
    pub synthetic_step: bool,
}

impl Signature {
    /// The parameters the user's function takes, in order.
    pub fn fn_params(&self) -> &[Ident] {
        let n = self.params.len() - usize::from(self.synthetic_step);
        &self.params[..n]
    }
}

enum Arg {
    List(Ident, Punctuated<Ident, Token![,]>),
    Value(Ident, Expr),
    Ranges(Ident, Punctuated<RangeArg, Token![,]>),
}

/// `name = (lo, hi)` inside `ranges(...)`; the value is checked later, with a span per mistake.
struct RangeArg {
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

impl Parse for Arg {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let key: Ident = input.parse()?;
        if key == "ranges" && input.peek(syn::token::Paren) {
            let content;
            syn::parenthesized!(content in input);
            Ok(Arg::Ranges(key, Punctuated::parse_terminated(&content)?))
        } else if input.peek(syn::token::Paren) {
            let content;
            syn::parenthesized!(content in input);
            let list = Punctuated::parse_terminated(&content)?;
            Ok(Arg::List(key, list))
        } else if input.peek(Token![=]) {
            input.parse::<Token![=]>()?;
            Ok(Arg::Value(key, input.parse()?))
        } else {
            Err(syn::Error::new(
                key.span(),
                format!("expected `{key}(...)` or `{key} = ...`; accepted: {KEYS}"),
            ))
        }
    }
}

/// Parses the attribute arguments, recording every mistake in `cx`.
pub fn parse_spec(cx: &Ctxt, args: proc_macro2::TokenStream) -> Option<Spec> {
    let parser = Punctuated::<Arg, Token![,]>::parse_terminated;
    let args = match syn::parse::Parser::parse2(parser, args) {
        Ok(args) => args,
        Err(e) => {
            cx.syn_error(e);
            return None;
        }
    };
    let mut shape: Option<Vec<Ident>> = None;
    let mut group: Option<Vec<Ident>> = None;
    let mut connection: Option<(Expr, Vec<Vec<Expr>>)> = None;
    let mut step: Option<Ident> = None;
    let mut name: Option<Ident> = None;
    let mut ranges: Vec<Range> = Vec::new();
    let mut rule: Option<(Ident, Rule)> = None;
    let mut seen: Vec<String> = Vec::new();
    for arg in args {
        let key = match &arg {
            Arg::List(k, _) | Arg::Value(k, _) | Arg::Ranges(k, _) => k.clone(),
        };
        let key_name = key.to_string();
        if seen.contains(&key_name) {
            cx.error_spanned_by(&key, format!("duplicate `{key_name}` argument"));
            continue;
        }
        seen.push(key_name.clone());
        match (key_name.as_str(), arg) {
            ("shape", Arg::List(_, list)) => shape = Some(list.into_iter().collect()),
            // `group()` declares no symmetry: a plain variational integrator (K = 0).
            ("group", Arg::List(_, list)) => group = Some(list.into_iter().collect()),
            ("connection", Arg::Value(_, value)) => {
                connection = parse_matrix(cx, &value).map(|rows| (value, rows))
            }
            ("step", Arg::Value(_, value)) => {
                step = parse_ident(cx, value, "the time-step parameter, e.g. `step = h`")
            }
            ("name", Arg::Value(_, value)) => {
                name = parse_ident(cx, value, "a type name, e.g. `name = Particle`")
            }
            ("ranges", Arg::Ranges(_, list)) => ranges = parse_ranges(cx, list),
            ("rule", Arg::Value(k, value)) => {
                let id = match &value {
                    Expr::Path(p) => p.path.get_ident().cloned(),
                    _ => None,
                };
                match id.as_ref().and_then(Rule::from_ident) {
                    Some(r) => rule = Some((k, r)),
                    None => cx.error_spanned_by(
                        &value,
                        format!(
                            "unknown quadrature rule `{}`; accepted: {RULES}",
                            value.to_token_stream()
                        ),
                    ),
                }
            }
            ("rule", Arg::List(k, _)) => cx.error_spanned_by(
                &k,
                format!("expected `rule = <name>`, found `rule(...)`; accepted: {RULES}"),
            ),
            ("ranges", Arg::Value(k, _)) => cx.error_spanned_by(
                &k,
                format!("expected `ranges(...)`, found `ranges = ...`; accepted: {RANGES}"),
            ),
            ("shape" | "group", Arg::Value(k, _)) => {
                cx.error_spanned_by(&k, format!("expected a list: `{k}(a, b, ...)`"))
            }
            ("connection", Arg::List(k, _)) => cx.error_spanned_by(
                &k,
                "expected `connection = [[b11, b12, ...], ...]`, found `connection(...)`",
            ),
            ("step", Arg::List(k, _)) => {
                cx.error_spanned_by(&k, "expected `step = <parameter>`, found `step(...)`")
            }
            ("name", Arg::List(k, _)) => {
                cx.error_spanned_by(&k, "expected `name = <TypeName>`, found `name(...)`")
            }
            (_, _) => cx.error_spanned_by(
                &key,
                format!("unknown argument `{key_name}`; accepted: {KEYS}"),
            ),
        }
    }
    if shape.is_none() && !seen.iter().any(|k| k == "shape") {
        cx.error_at(
            Span::call_site(),
            "missing `shape(...)`: list the shape coordinates, e.g. `shape(x, y)` (or `shape()` for none)",
        );
    }
    if group.is_none() && !seen.iter().any(|k| k == "group") {
        cx.error_at(
            Span::call_site(),
            "missing `group(...)`: list the group coordinates the symmetry translates, e.g. `group(theta)` (or `group()` for none)",
        );
    }
    let (shape, group) = (shape?, group?);
    if shape.is_empty() && group.is_empty() {
        cx.error_at(
            Span::call_site(),
            "no coordinates: `shape()` and `group()` are both empty; declare at least one coordinate, e.g. `shape(x), group()`",
        );
    }
    check_coordinates(cx, &shape, &group);
    let connection = connection.map(|(value, rows)| {
        check_connection_shape(cx, &value, &rows, shape.len(), group.len());
        rows
    });
    Some(Spec {
        shape,
        group,
        connection,
        step,
        name,
        ranges,
        rule,
        rule_written: seen.iter().any(|k| k == "rule"),
    })
}

fn parse_ranges(cx: &Ctxt, list: Punctuated<RangeArg, Token![,]>) -> Vec<Range> {
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
                        other.to_token_stream()
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
                e.to_token_stream()
            ),
        );
        return None;
    };
    if !value.is_finite() {
        cx.error_spanned_by(
            e,
            format!(
                "range bound `{}` is not a finite f64; accepted: {RANGES}",
                e.to_token_stream()
            ),
        );
        return None;
    }
    Some(if negated { -value } else { value })
}

/// Resolves the names in `ranges(...)` against the parameters and coordinates.
pub fn resolve_ranges(cx: &Ctxt, spec: &Spec, sig: &Signature) -> Ranges {
    let coords: Vec<&Ident> = spec.shape.iter().chain(&spec.group).collect();
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

fn parse_ident(cx: &Ctxt, value: Expr, what: &str) -> Option<Ident> {
    if let Expr::Path(p) = &value {
        if let Some(id) = p.path.get_ident() {
            return Some(id.clone());
        }
    }
    let found = match &value {
        Expr::Lit(l) if matches!(l.lit, syn::Lit::Str(_)) => {
            "a string literal: write the name without quotes".to_string()
        }
        other => format!("`{}`", other.to_token_stream()),
    };
    cx.error_spanned_by(&value, format!("expected {what}, found {found}"));
    None
}

fn parse_matrix(cx: &Ctxt, value: &Expr) -> Option<Vec<Vec<Expr>>> {
    let Expr::Array(rows) = value else {
        cx.error_spanned_by(
            value,
            "expected the connection matrix B as nested arrays, one row per group coordinate: `connection = [[b11, b12], ...]`",
        );
        return None;
    };
    let mut out = Vec::new();
    for row in &rows.elems {
        match row {
            Expr::Array(cols) => out.push(cols.elems.iter().cloned().collect()),
            other => {
                cx.error_spanned_by(
                    other,
                    "expected a row of B: `[b1, b2, ...]`, one entry per shape coordinate",
                );
                return None;
            }
        }
    }
    Some(out)
}

fn check_coordinates(cx: &Ctxt, shape: &[Ident], group: &[Ident]) {
    let mut seen: Vec<&Ident> = Vec::new();
    for id in shape.iter().chain(group) {
        if let Some(first) = seen.iter().find(|s| **s == id) {
            let in_shape = |x: &Ident| shape.iter().any(|s| s == x);
            let in_group = |x: &Ident| group.iter().any(|s| s == x);
            if in_shape(first) && in_group(id) {
                cx.error_spanned_by(
                    id,
                    format!("coordinate `{id}` is in both `shape` and `group`: a coordinate is either shape or group"),
                );
            } else {
                cx.error_spanned_by(id, format!("coordinate `{id}` is declared twice"));
            }
        } else {
            seen.push(id);
        }
    }
}

fn check_connection_shape(cx: &Ctxt, value: &Expr, rows: &[Vec<Expr>], s: usize, k: usize) {
    let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let dims = format!(
        "B must be K × S = {k} × {s} (one row per group coordinate, one entry per shape coordinate)"
    );
    let Expr::Array(array) = value else { return };
    if rows.len() != k {
        // Point at the first extra row, or at the whole matrix when rows are missing.
        match array.elems.iter().nth(k) {
            Some(extra) => cx.error_spanned_by(
                extra,
                format!(
                    "extra row: the connection matrix has {}; {dims}",
                    plural(rows.len(), "row")
                ),
            ),
            None => cx.error_spanned_by(
                value,
                format!(
                    "the connection matrix has {}; {dims}",
                    plural(rows.len(), "row")
                ),
            ),
        }
        return;
    }
    for (i, (row, row_expr)) in rows.iter().zip(&array.elems).enumerate() {
        if row.len() != s {
            let message = format!(
                "row {} of the connection matrix has {}; {dims}",
                i + 1,
                plural(row.len(), "entry").replace("entrys", "entries")
            );
            match row.get(s) {
                Some(extra) => cx.error_spanned_by(extra, message),
                None => cx.error_spanned_by(row_expr, message),
            }
        }
    }
}

/// Checks the function signature: `(q0: Config, q1: Config, p1: f64, ...) -> f64`.
pub fn parse_signature(
    cx: &Ctxt,
    sig: &syn::Signature,
    spec_step: Option<&Ident>,
    rule: Option<&(Ident, Rule)>,
    rule_written: bool,
) -> Option<Signature> {
    let mut ok = true;
    let mut velocity: Option<&syn::Type> = None;
    if let Some(g) = sig.generics.params.first() {
        cx.error_spanned_by(
            g,
            "generic parameters are not supported: the Lagrangian is written over f64",
        );
        ok = false;
    }
    for (token, what) in [
        (sig.asyncness.as_ref().map(|t| t.span()), "`async`"),
        (sig.unsafety.as_ref().map(|t| t.span()), "`unsafe`"),
        (sig.constness.as_ref().map(|t| t.span()), "`const`"),
    ] {
        if let Some(span) = token {
            cx.error_at(span, format!("{what} functions are not supported"));
            ok = false;
        }
    }
    match &sig.output {
        syn::ReturnType::Type(_, ty) if is_f64(ty) => {}
        syn::ReturnType::Type(_, ty) => {
            cx.error_spanned_by(
                ty,
                format!(
                    "a discrete Lagrangian returns `f64`, found `{}`",
                    ty.to_token_stream()
                ),
            );
            ok = false;
        }
        syn::ReturnType::Default => {
            cx.error_spanned_by(
                &sig.ident,
                "a discrete Lagrangian returns `f64`: add `-> f64`",
            );
            ok = false;
        }
    }
    let mut names = Vec::new();
    for (i, input) in sig.inputs.iter().enumerate() {
        let syn::FnArg::Typed(pat_ty) = input else {
            cx.error_spanned_by(
                input,
                "`self` is not accepted: the Lagrangian is a free function",
            );
            ok = false;
            continue;
        };
        let syn::Pat::Ident(pi) = &*pat_ty.pat else {
            cx.error_spanned_by(&pat_ty.pat, "expected a plain argument name");
            ok = false;
            continue;
        };
        let ty = &*pat_ty.ty;
        if i < 2 && is_type(ty, "Velocity") {
            velocity = Some(ty);
        }
        if i < 2 {
            if !(is_config(ty) || (i == 1 && is_type(ty, "Velocity"))) {
                cx.error_spanned_by(
                    ty,
                    format!(
                        "the first two arguments are the configurations `q0: Config, q1: Config` (or, for a continuous Lagrangian, `q: Config, v: Velocity`), found `{}: {}`",
                        pi.ident,
                        ty.to_token_stream()
                    ),
                );
                ok = false;
            }
        } else if !is_f64(ty) {
            cx.error_spanned_by(
                ty,
                format!(
                    "parameter `{}` is `{}`; parameters must be `f64` (only scalar parameters are accepted)",
                    pi.ident,
                    ty.to_token_stream()
                ),
            );
            ok = false;
        }
        names.push(pi.ident.clone());
    }
    if names.len() < 2 {
        cx.error_spanned_by(
            &sig.inputs,
            "expected the configurations first: `fn f(q0: Config, q1: Config, h: f64, ...) -> f64`",
        );
        return None;
    }
    let mut params: Vec<Ident> = names.split_off(2);
    let continuous = velocity.is_some();
    match (velocity, rule) {
        (Some(ty), None) if !rule_written => {
            cx.error_spanned_by(
                ty,
                format!("a continuous Lagrangian `L(q: Config, v: Velocity, ...)` needs a quadrature rule to form L_d; add one of {RULES}"),
            );
            ok = false;
        }
        (None, Some((key, _))) => {
            cx.error_spanned_by(
                key,
                "`rule = ...` discretizes a continuous Lagrangian `fn l(q: Config, v: Velocity, ...)`; this function takes two configurations `(q0: Config, q1: Config)`, so it already is L_d: remove `rule` or make the second argument `v: Velocity`",
            );
            ok = false;
        }
        _ => {}
    }
    // A continuous L need not take the time step: the emitted type gets a field for it anyway.
    let mut synthetic_step = false;
    if continuous {
        let name = spec_step.map_or_else(|| Ident::new("h", Span::call_site()), Clone::clone);
        if !params.contains(&name) {
            params.push(name);
            synthetic_step = true;
        }
    }
    let step = match spec_step {
        Some(step) => {
            if !params.contains(step) {
                let list: Vec<String> = params.iter().map(|p| format!("`{p}`")).collect();
                cx.error_spanned_by(
                    step,
                    format!(
                        "`step = {step}` must name one of the `f64` parameters: {}",
                        list.join(", ")
                    ),
                );
                ok = false;
            }
            Some(step.clone())
        }
        None => params.iter().find(|p| *p == "h").cloned(),
    };
    if step.is_none() && ok {
        cx.error_spanned_by(
            &sig.ident,
            "no time step: name a parameter `h: f64`, or declare which parameter it is with `step = <name>`",
        );
        ok = false;
    }
    let step = step.filter(|_| ok)?;
    Some(Signature {
        q0: names[0].clone(),
        q1: names[1].clone(),
        params,
        step,
        continuous,
        synthetic_step,
    })
}

fn is_f64(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("f64"))
}

fn is_config(ty: &syn::Type) -> bool {
    is_type(ty, "Config")
}

fn is_type(ty: &syn::Type, name: &str) -> bool {
    matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident(name))
}
