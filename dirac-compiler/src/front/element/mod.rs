//! Element-wise systems: a Lagrangian whose function takes `usize` sizes, with coordinates whose
//! lengths are those sizes, written as sums over elements (see `dirac::runtime::element`).
//!
//! ```text
//! #[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
//! fn toda(q: Config, v: Velocity, m: f64, d: f64, n: usize) -> f64 {
//!     let mut l = 0.0;
//!     for i in 0..n { l += 0.5 * m * v.x[i] * v.x[i]; }
//!     for i in 0..n - 1 { l -= (-(q.x[i + 1] - q.x[i] - d)).exp(); }
//!     l - (-(q.x[0] + n as f64 * d - q.x[n - 1] - d)).exp()
//! }
//! ```
//!
//! The attribute accepts `coordinates(..)` whose lengths are sizes or literals (`x[n]`, a grid
//! `u[nx][ny]`, a scalar `c`), `translate(..)`, `rule = ..`, `name = ..` and `step = ..`; the
//! body is split into families of elements by [`families`].

pub mod constraints;
pub mod families;
pub mod index;
pub mod unroll;

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Expr, Ident, ItemFn, Token};

use crate::ctxt::Ctxt;
use crate::front::rule::{Rule, RULES};
use crate::front::signature::{parse_signature, Signature};
use crate::symbol::{
    self, KeyArg, CONNECTION, CONSTRAINTS, CONTROLS, COORDINATES, FORCE, GROUP, NAME, NONHOLONOMIC,
    RANGES, RULE, SHAPE, STEP, TRANSLATE,
};

/// What the attribute of an element-wise system accepts, for messages.
pub const ELEMENT_KEYS: &str = "`coordinates(x[n], u[nx][ny], c, ...)` (lengths are sizes — the \
function's `usize` arguments — or integer literals), `translate(<coordinate>, ...)`, \
`rule = midpoint | trapezoid | left | right`, `force = |dq| <virtual work>` (or `|dq0, dq1|` for \
a discrete Lagrangian; written with loops like the body), `controls(u, ...)` (parameters a control \
law sets before every step), `constraints = |q| { let mut phi = vec![0.0; <count>]; for i in .. { phi[<row>] = <φ>; } phi }` (holonomic constraints of a continuous Lagrangian, one row per assignment), `name = <TypeName>`, `step = <parameter>`";

/// One dimension of a coordinate: a size or a literal length.
#[derive(Clone, Debug)]
pub enum Dim {
    Size(usize),
    Fixed(usize),
    /// A literal multiple of a size, `x[3 * n]`: `n` points of 3 components, read with strided
    /// indices (`x[3 * i + d]`).
    Scaled(usize, usize),
}

/// A coordinate of an element-wise system.
#[derive(Clone, Debug)]
pub struct ElementCoord {
    pub name: Ident,
    /// Empty for a scalar.
    pub dims: Vec<Dim>,
}

/// The parsed attribute and signature of an element-wise system.
pub struct ElementSpec {
    /// The sizes: the function's `usize` arguments, in order.
    pub sizes: Vec<Ident>,
    pub coords: Vec<ElementCoord>,
    /// Each `translate(..)`: the coordinates it moves together.
    pub translates: Vec<Vec<usize>>,
    pub rule: Option<Rule>,
    pub name: Option<Ident>,
    /// `force = |dq| W`: the virtual work, a sum over elements like the body.
    pub force: Option<syn::ExprClosure>,
    /// `controls(u, ..)`: parameters a control law sets before every step.
    pub controls: Vec<Ident>,
    /// `constraints = |q| { let mut phi = vec![0.0; m]; .. phi }`: holonomic constraints,
    /// one row per assignment `phi[<row>] = <φ>` (in loops over elements or outside them).
    pub constraints: Option<syn::ExprClosure>,
    /// The signature without the sizes (what the fixed-size front end checks).
    pub sig: Signature,
}

/// Whether `func` takes a `usize` argument: then it is an element-wise system.
pub fn is_element_wise(func: &ItemFn) -> bool {
    func.sig.inputs.iter().any(|a| match a {
        syn::FnArg::Typed(t) => is_usize(&t.ty),
        _ => false,
    })
}

fn is_usize(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("usize"))
}

/// One `key(...)` or `key = value` of the attribute.
type Item = KeyArg<Punctuated<Expr, Token![,]>, Expr>;

impl Parse for Item {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        KeyArg::parse_with(
            input,
            |_, content| Punctuated::parse_terminated(content),
            |_, input| input.parse(),
            |key| symbol::list_or_value(key, ELEMENT_KEYS),
        )
    }
}

/// The attribute and signature; `None` after errors (recorded).
pub fn parse(cx: &Ctxt, args: proc_macro2::TokenStream, func: &ItemFn) -> Option<ElementSpec> {
    let items = symbol::parse_args::<Item>(cx, args)?;
    // The sizes, and the signature without them.
    let mut sizes = Vec::new();
    let mut fixed_sig = func.sig.clone();
    fixed_sig.inputs = func
        .sig
        .inputs
        .iter()
        .filter(|a| match a {
            syn::FnArg::Typed(t) if is_usize(&t.ty) => {
                match &*t.pat {
                    syn::Pat::Ident(pi) => sizes.push(pi.ident.clone()),
                    other => cx.error_spanned_by(other, "expected a plain size name"),
                }
                false
            }
            _ => true,
        })
        .cloned()
        .collect();
    let (mut coords, mut translates, mut rule, mut name, mut step) =
        (Vec::new(), Vec::new(), None, None, None);
    let (mut rule_key, mut translate_names) = (None, Vec::new());
    let (mut force, mut controls, mut constraints) = (None, Vec::new(), None);
    for item in &items {
        let key = item.key().to_string();
        match (symbol::key(item.key()), item) {
            (Some(COORDINATES), KeyArg::List(_, list)) => {
                for e in list {
                    if let Some(c) = coordinate(cx, e, &sizes) {
                        coords.push(c);
                    }
                }
            }
            (Some(TRANSLATE), KeyArg::List(_, list)) => translate_names.push(list),
            (Some(RULE), KeyArg::Value(k, Expr::Path(p))) if p.path.get_ident().is_some() => {
                let id = p.path.get_ident().expect("checked");
                match Rule::from_ident(id) {
                    Some(r) => {
                        rule = Some(r);
                        rule_key = Some((k.clone(), r));
                    }
                    None => cx.error_spanned_by(id, format!("unknown rule `{id}`; accepted: {RULES}")),
                }
            }
            (Some(NAME), KeyArg::Value(_, Expr::Path(p))) if p.path.get_ident().is_some() => {
                name = p.path.get_ident().cloned();
            }
            (Some(STEP), KeyArg::Value(_, Expr::Path(p))) if p.path.get_ident().is_some() => {
                step = p.path.get_ident().cloned();
            }
            (Some(FORCE), KeyArg::Value(_, Expr::Closure(c))) => force = Some(c.clone()),
            (Some(CONSTRAINTS), KeyArg::Value(_, Expr::Closure(c))) => {
                constraints = Some(c.clone())
            }
            (Some(CONSTRAINTS), _) => cx.error_spanned_by(
                item.key(),
                "expected `constraints = |q| { let mut phi = vec![0.0; <count>]; for i in 0..n { \
                 phi[<row>] = <φ>; } phi }`: a closure assigning every constraint row once",
            ),
            (Some(CONTROLS), KeyArg::List(_, list)) => {
                for e in list {
                    match e {
                        Expr::Path(p) if p.path.get_ident().is_some() => {
                            controls.push(p.path.get_ident().expect("checked").clone());
                        }
                        other => cx.error_spanned_by(other, "expected a parameter name"),
                    }
                }
            }
            (Some(FORCE), _) => cx.error_spanned_by(
                item.key(),
                "expected `force = |dq| <virtual work>`: a closure whose body sums `F * dq.x[i]` over the \
                 elements, e.g. `force = |dq| { let mut w = 0.0; for i in 0..n { w -= c * v.x[i] * dq.x[i]; } w }`",
            ),
            (
                Some(SHAPE | GROUP | CONNECTION | RANGES | NONHOLONOMIC),
                _,
            ) => cx.error_spanned_by(
                item.key(),
                format!(
                    "`{key}` is not available for systems with run-time sizes (a `usize` argument); accepted: {ELEMENT_KEYS}"
                ),
            ),
            _ => cx.error_spanned_by(
                item.key(),
                format!("unexpected `{key}` here; accepted: {ELEMENT_KEYS}"),
            ),
        }
    }
    if coords.is_empty() && !items.iter().any(|i| i.key() == COORDINATES) {
        cx.error_at(
            Span::call_site(),
            format!("a system with run-time sizes declares its coordinates: {ELEMENT_KEYS}"),
        );
    }
    for list in translate_names {
        let mut members = Vec::new();
        for e in list {
            let found = match e {
                Expr::Path(p) => p
                    .path
                    .get_ident()
                    .and_then(|id| coords.iter().position(|c: &ElementCoord| c.name == *id)),
                _ => None,
            };
            match found {
                Some(c)
                    if translates.iter().any(|t: &Vec<usize>| t.contains(&c))
                        || members.contains(&c) =>
                {
                    cx.error_spanned_by(e, "this coordinate is already moved by a `translate(...)`")
                }
                Some(c) => members.push(c),
                None => cx.error_spanned_by(
                    e,
                    format!(
                        "`{}` is not a declared coordinate; declared: {}",
                        crate::ctxt::show(&e),
                        coords
                            .iter()
                            .map(|c| format!("`{}`", c.name))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ),
            }
        }
        if !members.is_empty() {
            translates.push(members);
        }
    }
    let sig = parse_signature(
        cx,
        &fixed_sig,
        step.as_ref(),
        rule_key.as_ref(),
        rule_key.is_some(),
    )?;
    crate::front::signature::check_controls(cx, &controls, &sig);
    if let (Some(c), false) = (&constraints, sig.continuous) {
        cx.error_spanned_by(
            c.or1_token,
            "constraints need a continuous Lagrangian `fn(q: Config, v: Velocity, ..)` with a \
             `rule`: the projection of the momenta uses its Legendre map",
        );
    }
    Some(ElementSpec {
        sizes,
        coords,
        translates,
        rule,
        name,
        force,
        controls,
        constraints,
        sig,
    })
}

/// `m * n` with `m` a positive integer literal and `n` a size: `Dim::Scaled`.
fn scaled(m: &Expr, n: &Expr, sizes: &[Ident]) -> Option<Dim> {
    let Expr::Lit(syn::ExprLit {
        lit: syn::Lit::Int(m),
        ..
    }) = m
    else {
        return None;
    };
    let m = m.base10_parse::<usize>().ok().filter(|&m| m > 0)?;
    let Expr::Path(p) = n else { return None };
    let id = p.path.get_ident()?;
    sizes
        .iter()
        .position(|s| s == id)
        .map(|k| Dim::Scaled(k, m))
}

/// `x`, `x[n]`, `u[nx][ny]`, `x[3]`, `x[3 * n]`.
fn coordinate(cx: &Ctxt, e: &Expr, sizes: &[Ident]) -> Option<ElementCoord> {
    let mut dims = Vec::new();
    let mut cur = e;
    loop {
        match cur {
            Expr::Index(ix) => {
                let dim = match &*ix.index {
                    Expr::Path(p) => match p.path.get_ident() {
                        Some(id) => match sizes.iter().position(|s| s == id) {
                            Some(k) => Dim::Size(k),
                            None => {
                                cx.error_spanned_by(
                                    &ix.index,
                                    format!("`{id}` is not a size: sizes are the function's `usize` arguments ({})", sizes.iter().map(|s| format!("`{s}`")).collect::<Vec<_>>().join(", ")),
                                );
                                return None;
                            }
                        },
                        None => {
                            cx.error_spanned_by(
                                &ix.index,
                                "a length is a size or an integer literal",
                            );
                            return None;
                        }
                    },
                    Expr::Binary(b) if matches!(b.op, syn::BinOp::Mul(_)) => {
                        match scaled(&b.left, &b.right, sizes)
                            .or_else(|| scaled(&b.right, &b.left, sizes))
                        {
                            Some(dim) => dim,
                            None => {
                                cx.error_spanned_by(
                                    &ix.index,
                                    "a length is a size, an integer literal or a literal times a size (`x[3 * n]`)",
                                );
                                return None;
                            }
                        }
                    }
                    Expr::Lit(syn::ExprLit {
                        lit: syn::Lit::Int(i),
                        ..
                    }) => match i.base10_parse::<usize>() {
                        Ok(v) if v > 0 => Dim::Fixed(v),
                        _ => {
                            cx.error_spanned_by(i, "a length must be a positive integer");
                            return None;
                        }
                    },
                    other => {
                        cx.error_spanned_by(other, "a length is a size or an integer literal");
                        return None;
                    }
                };
                dims.push(dim);
                cur = &ix.expr;
            }
            Expr::Path(p) if p.path.get_ident().is_some() => {
                dims.reverse();
                if dims.len() > 2 {
                    cx.error_spanned_by(e, "coordinates have at most two dimensions (`u[nx][ny]`)");
                    return None;
                }
                return Some(ElementCoord {
                    name: p.path.get_ident().expect("checked").clone(),
                    dims,
                });
            }
            other => {
                cx.error_spanned_by(
                    other,
                    format!("expected a coordinate `x`, `x[n]` or `u[nx][ny]`; {ELEMENT_KEYS}"),
                );
                return None;
            }
        }
    }
}
