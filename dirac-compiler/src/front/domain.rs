//! `domain(<coordinate> <op> <number>, ...)`: bounds on coordinates of the configuration vector
//! `q = (x, g)`, checked after every step. An entry is read before the coordinates are known
//! ([`DomainEntry`]) and resolved against the layout once they are ([`domain_bounds`]).

use syn::punctuated::Punctuated;
use syn::{Expr, Ident, Token};

use crate::ctxt::Ctxt;
use crate::front::layout::Layout;

/// What `domain(...)` accepts, for its messages.
pub const DOMAIN_ACCEPTED: &str = "`domain(<coordinate> <op> <number>, ...)`: each entry bounds one coordinate by a number \
     literal, with `<op>` one of `>`, `>=`, `<`, `<=`, e.g. `domain(r > 0.0)`, `domain(x[2] >= -1.0, theta < 3.2)` \
     (a whole array coordinate, `x > 0.0`, bounds each of its components)";

/// One bound of `domain(...)`: coordinate `coordinate` of the configuration vector `q = (x, g)`
/// stands in `relation` to `value`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomainBound {
    /// The coordinate's index in `q = (x, g)`.
    pub coordinate: usize,
    /// How it relates to `value`.
    pub relation: DomainRelation,
    /// The bound.
    pub value: f64,
}

/// The relation of a [`DomainBound`]: `>`, `>=`, `<` or `<=`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DomainRelation {
    /// `q > value`.
    Above,
    /// `q >= value`.
    AtLeast,
    /// `q < value`.
    Below,
    /// `q <= value`.
    AtMost,
}

impl DomainRelation {
    /// The variant's name, as the runtime's `Relation` spells it.
    pub fn name(self) -> &'static str {
        match self {
            DomainRelation::Above => "Above",
            DomainRelation::AtLeast => "AtLeast",
            DomainRelation::Below => "Below",
            DomainRelation::AtMost => "AtMost",
        }
    }

    /// The relation with its sides swapped (`0.0 < r` is `r > 0.0`).
    fn flipped(self) -> Self {
        match self {
            DomainRelation::Above => DomainRelation::Below,
            DomainRelation::AtLeast => DomainRelation::AtMost,
            DomainRelation::Below => DomainRelation::Above,
            DomainRelation::AtMost => DomainRelation::AtLeast,
        }
    }
}

/// One entry of `domain(...)` as written, before the coordinates are known: the coordinate's
/// name, its component if indexed, the relation and the value.
pub(crate) struct DomainEntry {
    expr: Expr,
    name: Ident,
    component: Option<usize>,
    relation: DomainRelation,
    value: f64,
}

/// The entries of `domain(...)` (the key `key`, its contents `tokens` as written), each read by
/// [`domain_entry`]; `None`, with an error, when the contents are not a list of expressions.
pub(crate) fn domain_entries(
    cx: &Ctxt,
    key: &Ident,
    tokens: proc_macro2::TokenStream,
) -> Option<Vec<DomainEntry>> {
    use syn::parse::Parser;
    let list = match Punctuated::<Expr, Token![,]>::parse_terminated.parse2(tokens) {
        Ok(list) => list,
        Err(e) => {
            cx.error_at(
                e.span(),
                format!(
                    "expected a bound `<coordinate> <op> <number>`; accepted: {DOMAIN_ACCEPTED}"
                ),
            );
            return None;
        }
    };
    if list.is_empty() {
        cx.error_spanned_by(
            key,
            format!("`domain()` is empty; accepted: {DOMAIN_ACCEPTED}"),
        );
    }
    Some(
        list.into_iter()
            .filter_map(|e| domain_entry(cx, e))
            .collect(),
    )
}

/// One entry of `domain(...)`, `r > 0.0` (or `0.0 < r`), read; `None` with an error at the
/// entry for anything else.
fn domain_entry(cx: &Ctxt, expr: Expr) -> Option<DomainEntry> {
    let read = || -> Option<(Ident, Option<usize>, DomainRelation, f64)> {
        let Expr::Binary(binary) = ungrouped(&expr) else {
            return None;
        };
        let relation = match binary.op {
            syn::BinOp::Gt(_) => DomainRelation::Above,
            syn::BinOp::Ge(_) => DomainRelation::AtLeast,
            syn::BinOp::Lt(_) => DomainRelation::Below,
            syn::BinOp::Le(_) => DomainRelation::AtMost,
            _ => return None,
        };
        if let (Some((name, component)), Some(value)) =
            (domain_coordinate(&binary.left), number(&binary.right))
        {
            return Some((name, component, relation, value));
        }
        let (name, component) = domain_coordinate(&binary.right)?;
        Some((name, component, relation.flipped(), number(&binary.left)?))
    };
    match read() {
        Some((name, component, relation, value)) if value.is_finite() => Some(DomainEntry {
            expr,
            name,
            component,
            relation,
            value,
        }),
        _ => {
            cx.error_spanned_by(
                &expr,
                format!(
                    "expected a bound `<coordinate> <op> <number>`, found `{}`; accepted: {DOMAIN_ACCEPTED}",
                    crate::ctxt::show(&expr)
                ),
            );
            None
        }
    }
}

/// `e` without the invisible groups of `macro_rules!` and without parentheses.
fn ungrouped(mut e: &Expr) -> &Expr {
    loop {
        match e {
            Expr::Group(g) => e = &g.expr,
            Expr::Paren(p) => e = &p.expr,
            _ => return e,
        }
    }
}

/// `r` or `x[2]`: a coordinate's name and its component.
fn domain_coordinate(e: &Expr) -> Option<(Ident, Option<usize>)> {
    match ungrouped(e) {
        Expr::Path(p) => p.path.get_ident().map(|id| (id.clone(), None)),
        Expr::Index(index) => {
            let Expr::Path(p) = ungrouped(&index.expr) else {
                return None;
            };
            let Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Int(i),
                ..
            }) = ungrouped(&index.index)
            else {
                return None;
            };
            Some((p.path.get_ident()?.clone(), Some(i.base10_parse().ok()?)))
        }
        _ => None,
    }
}

/// A number literal, integer or float, possibly negated.
fn number(e: &Expr) -> Option<f64> {
    match ungrouped(e) {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Float(f),
            ..
        }) => f.base10_parse().ok(),
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(i),
            ..
        }) => i.base10_parse::<i64>().ok().map(|i| i as f64),
        Expr::Unary(syn::ExprUnary {
            op: syn::UnOp::Neg(_),
            expr,
            ..
        }) => number(expr).map(|v| -v),
        _ => None,
    }
}

/// The bounds one entry of `domain(...)` gives once the coordinates are known: one for a scalar
/// or a component, one per component for a whole array; none, with an error at the entry, for a
/// name that is not a coordinate, a component out of range, or a component that is not a
/// coordinate of `q` (one moved by a `translate(...)` other than its first).
pub(crate) fn domain_bounds(cx: &Ctxt, layout: &Layout, entry: &DomainEntry) -> Vec<DomainBound> {
    let mut offset = 0;
    let mut found = None;
    for c in &layout.coords {
        let len = c.len.unwrap_or(1);
        if c.name == entry.name {
            found = Some((offset, c));
        }
        offset += len;
    }
    let Some((offset, coord)) = found else {
        cx.error_spanned_by(
            &entry.expr,
            format!(
                "unknown coordinate `{}` in `domain(...)`; declared coordinates: {}",
                entry.name,
                layout
                    .coords
                    .iter()
                    .map(|c| format!("`{}`", c.name))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        );
        return Vec::new();
    };
    let components: Vec<usize> = match (entry.component, coord.len) {
        (None, len) => (0..len.unwrap_or(1)).collect(),
        (Some(i), Some(len)) if i < len => vec![i],
        (Some(i), len) => {
            cx.error_spanned_by(
                &entry.expr,
                match len {
                    Some(len) => format!(
                        "`{}[{i}]` is out of range: `{}` has {len} components",
                        entry.name, entry.name
                    ),
                    None => format!(
                        "`{}` is a scalar coordinate: bound it as `{}`, without an index",
                        entry.name, entry.name
                    ),
                },
            );
            return Vec::new();
        }
    };
    let mut bounds = Vec::new();
    for i in components {
        match layout.components.get(offset + i) {
            Some(crate::front::layout::Component::Var(j)) => bounds.push(DomainBound {
                coordinate: *j,
                relation: entry.relation,
                value: entry.value,
            }),
            _ => {
                cx.error_spanned_by(
                    &entry.expr,
                    format!(
                        "`{}` is not a coordinate of the system's configuration: a component moved by a \
                         `translate(...)` is stored relative to the first one it lists; bound a coordinate \
                         that `translate(...)` lists first, or one it does not move",
                        coord.component_names().get(i).cloned().unwrap_or_default()
                    ),
                );
                return Vec::new();
            }
        }
    }
    bounds
}
