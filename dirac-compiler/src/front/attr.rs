//! The attribute grammar of `#[reduced_lagrangian(...)]`: which coordinates are shape and which
//! are group (or the user's coordinates and their translations), the connection, the time step,
//! the type name, the quadrature rule and the sampling ranges. Every mistake is recorded with its
//! span; the keys are the constants of [`crate::symbol`].
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
//! [`crate::ir::discretize`]); the time step need not be an argument of `L`, the emitted type has a
//! field for it either way:
//!
//! ```text
//! #[reduced_lagrangian(shape(x, y, z), group(theta), rule = left)]
//! fn l(q: Config, v: Velocity, m: f64) -> f64 { … }
//! ```
//!
//! A coordinate may be an array of constant length, `shape(x[199], y)`, read in the body as
//! `q0.x[i]`. Or the symmetry is declared on the user's own coordinates (see [`crate::front::layout::Layout`]):
//!
//! ```text
//! #[reduced_lagrangian(coordinates(x[4], y[4]), translate(x), translate(y))]
//! ```
//!
//! Forces are declared by their virtual work, a closure linear in the virtual displacements:
//! `force = |dq| <⟨F(q, v), dq⟩>` for a continuous Lagrangian (the rule forms `f_d^±`), or
//! `force = |dq0, dq1| <⟨f_d^−, dq0⟩ + ⟨f_d^+, dq1⟩>` for a discrete one; `controls(u, ..)` names
//! parameters that a control law may set before every step (see [`crate::ir::force`]).

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Expr, Ident, Token};

use crate::ctxt::Ctxt;
use crate::front::domain::{domain_bounds, domain_entries, DomainEntry};
use crate::front::layout::{Coord, GroupDecl, Layout, MAX_COMPONENTS};
use crate::front::ranges::{parse_ranges, Range, RangeArg, RANGES as RANGES_ACCEPTED};
use crate::front::rule::{Rule, RULES};
use crate::symbol::{
    self, KeyArg, Symbol, ADAPT, CONNECTION, CONSTRAINTS, CONTROLS, COORDINATES, DOMAIN, FORCE,
    GROUP, NAME, NONHOLONOMIC, RANGES, RULE, SHAPE, STEP, TIME, TRANSLATE,
};

pub use crate::front::domain::{DomainBound, DomainRelation, DOMAIN_ACCEPTED};

const KEYS: &str = "`shape(...)`, `group(...)` (or `coordinates(...)` with `translate(...)`), `connection = [[...], ...]`, `step = <parameter>`, `name = <TypeName>`, `rule = midpoint | trapezoid | left | right`, `ranges(<name> = (lo, hi), ...)`, `controls(<parameter>, ...)`, `force = |dq| <virtual work>` (or `|dq0, dq1|` for a discrete Lagrangian) `constraints = |q| [<φ_1>, ...]` or `nonholonomic = |q, v| [<A_1(q) v>, ...]`, `time(t), adapt = |q| <monitor>` (adaptive steps), `domain(<coordinate> > <number>, ...)`";

/// The parsed attribute.
pub struct Spec {
    /// The coordinates: the user's, and the configuration vector the system works in.
    pub layout: Layout,
    /// Rows of `B`, one per group coordinate, each with one entry per shape coordinate.
    pub connection: Option<Vec<Vec<Expr>>>,
    /// `step = h`: the time-step parameter, if not the default `h`.
    pub step: Option<Ident>,
    /// `name = Type`: the emitted type, if not the function's name in CamelCase.
    pub name: Option<Ident>,
    /// Sampling ranges declared with `ranges(...)` for the invariance check, by name.
    pub ranges: Vec<Range>,
    /// `rule = ...`: the quadrature rule of a continuous Lagrangian, with the key's token.
    pub rule: Option<(Ident, Rule)>,
    /// Whether `rule = ...` was written, valid or not (an invalid one is already reported).
    pub rule_written: bool,
    /// `controls(u, ...)`: parameters that a control law sets before every step.
    pub controls: Vec<Ident>,
    /// `force = |dq| ...` (continuous) or `force = |dq0, dq1| ...` (discrete): the virtual work
    /// of the forces, linear in the virtual displacements.
    pub force: Option<syn::ExprClosure>,
    /// `constraints = |q| [φ_1, ...]`: holonomic constraints `φ(q) = 0` (continuous
    /// Lagrangians).
    pub constraints: Option<syn::ExprClosure>,
    /// Whether `constraints` are nonholonomic (`nonholonomic = |q, v| [..]`, `A(q) v = 0`).
    pub nonholonomic: bool,
    /// `time(t), adapt = |q| g`: adaptive steps (see [`crate::ir::adapt`]).
    pub adapt: Option<Adapt>,
    /// `domain(r > 0.0, ..)`: bounds on coordinates of `q = (x, g)`, checked after every step.
    pub domain: Vec<DomainBound>,
}

/// `time(t), adapt = |q| g`: the group coordinate that is physical time and the step monitor.
pub struct Adapt {
    /// The time coordinate as written.
    pub time: Ident,
    /// Its index among the group coordinates.
    pub index: usize,
    /// `|q| g(q)`.
    pub monitor: syn::ExprClosure,
}

/// One entry of `shape(...)`, `group(...)`, `coordinates(...)` or `translate(...)`: a name,
/// optionally with an array length, `x[3]` (checked later, with a span per mistake).
struct CoordArg {
    name: Ident,
    len: Option<(syn::token::Bracket, Expr)>,
}

impl Parse for CoordArg {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        let len = if input.peek(syn::token::Bracket) {
            let content;
            let bracket = syn::bracketed!(content in input);
            Some((bracket, content.parse()?))
        } else {
            None
        };
        Ok(CoordArg { name, len })
    }
}

/// The contents of `key(...)`: coordinates (`shape`, `group`, `coordinates`, `translate`,
/// `controls`), or sampling ranges (`ranges`).
enum List {
    Coords(Punctuated<CoordArg, Token![,]>),
    Ranges(Punctuated<RangeArg, Token![,]>),
    /// The contents as written, read by [`domain_entries`] so that a mistake gets the key's
    /// message rather than the expression parser's.
    Domain(proc_macro2::TokenStream),
}

type Arg = KeyArg<List, Expr>;

impl Parse for Arg {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        KeyArg::parse_with(
            input,
            |key, content| {
                Ok(if key == RANGES {
                    List::Ranges(Punctuated::parse_terminated(content)?)
                } else if key == DOMAIN {
                    List::Domain(content.parse()?)
                } else {
                    List::Coords(Punctuated::parse_terminated(content)?)
                })
            },
            |_, input| input.parse(),
            |key| symbol::list_or_value(key, KEYS),
        )
    }
}

/// Parses the attribute arguments, recording every mistake in `cx`.
pub fn parse_spec(cx: &Ctxt, args: proc_macro2::TokenStream) -> Option<Spec> {
    let args = symbol::parse_args::<Arg>(cx, args)?;
    let mut shape: Option<Vec<Coord>> = None;
    let mut group: Option<Vec<Coord>> = None;
    let mut coordinates: Option<Vec<Coord>> = None;
    let mut translates: Vec<(Ident, Vec<Ident>)> = Vec::new();
    let mut connection: Option<(Expr, Vec<Vec<Expr>>)> = None;
    let mut step: Option<Ident> = None;
    let mut name: Option<Ident> = None;
    let mut ranges: Vec<Range> = Vec::new();
    let mut rule: Option<(Ident, Rule)> = None;
    let mut controls: Vec<Ident> = Vec::new();
    let mut force: Option<syn::ExprClosure> = None;
    let mut constraints: Option<syn::ExprClosure> = None;
    let mut nonholonomic = false;
    let mut time: Option<(Ident, Ident)> = None;
    let mut adapt: Option<(Ident, syn::ExprClosure)> = None;
    let mut domain: Vec<DomainEntry> = Vec::new();
    let mut seen: Vec<String> = Vec::new();
    // Which way the symmetry is declared: the first of `shape`/`group` or
    // `coordinates`/`translate` decides; a key of the other family is an error.
    let mut family: Option<Symbol> = None;
    for arg in args {
        let key = arg.key().clone();
        let key_name = key.to_string();
        let word = symbol::key(&key);
        // `translate(...)` may be repeated: each one is a group dimension.
        if seen.contains(&key_name) && word != Some(TRANSLATE) {
            cx.error_spanned_by(&key, format!("duplicate `{key_name}` argument"));
            continue;
        }
        seen.push(key_name.clone());
        let this_family = match word {
            Some(SHAPE | GROUP) => Some(SHAPE),
            Some(COORDINATES | TRANSLATE) => Some(COORDINATES),
            _ => None,
        };
        if let Some(f) = this_family {
            match family {
                Some(earlier) if earlier != f => {
                    cx.error_spanned_by(
                        &key,
                        format!(
                            "`{key_name}(...)` cannot be combined with {}: declare either the shape and group coordinates, \
                             `shape(...), group(...)`, or your own coordinates and their translations, `coordinates(...), translate(...)`",
                            if earlier == SHAPE { "`shape(...)`/`group(...)`" } else { "`coordinates(...)`/`translate(...)`" }
                        ),
                    );
                    continue;
                }
                _ => family = Some(f),
            }
        }
        let connection_clash = (word == Some(CONNECTION) && family == Some(COORDINATES))
            || (this_family == Some(COORDINATES) && connection.is_some());
        if connection_clash {
            cx.error_spanned_by(
                &key,
                "`connection = ...` cannot be combined with `coordinates(...)`/`translate(...)`: the adapted coordinates \
                 the compiler builds from `translate(...)` have the connection B = 0; use `shape(...), group(...), connection = ...` \
                 for a nonzero B",
            );
            if word == Some(CONNECTION) {
                continue;
            }
            // The connection came first: keep the coordinates, drop the connection.
            connection = None;
        }
        match (word, arg) {
            (Some(SHAPE), KeyArg::List(_, List::Coords(list))) => {
                shape = Some(coord_list(cx, list));
            }
            // `group()` declares no symmetry: a plain variational integrator (K = 0).
            (Some(GROUP), KeyArg::List(_, List::Coords(list))) => {
                group = Some(coord_list(cx, list));
            }
            (Some(COORDINATES), KeyArg::List(_, List::Coords(list))) => {
                coordinates = Some(coord_list(cx, list));
            }
            (Some(TRANSLATE), KeyArg::List(k, List::Coords(list))) => {
                let mut names = Vec::new();
                for c in list {
                    if let Some((_, len)) = &c.len {
                        cx.error_spanned_by(
                            len,
                            format!(
                                "`translate(...)` lists whole coordinates, found `{}[{}]`: write `translate({})` to translate every component of `{}`",
                                c.name,
                                crate::ctxt::show(&len),
                                c.name,
                                c.name
                            ),
                        );
                    }
                    names.push(c.name);
                }
                if names.is_empty() {
                    cx.error_spanned_by(
                        &k,
                        "`translate()` is empty: list the coordinates the translation moves together, e.g. `translate(x)` or `translate(x, y)`",
                    );
                } else {
                    translates.push((k, names));
                }
            }
            (Some(CONNECTION), KeyArg::Value(_, value)) => {
                connection = parse_matrix(cx, &value).map(|rows| (value, rows))
            }
            (Some(STEP), KeyArg::Value(_, value)) => {
                step = parse_ident(cx, value, "the time-step parameter, e.g. `step = h`")
            }
            (Some(NAME), KeyArg::Value(_, value)) => {
                name = parse_ident(cx, value, "a type name, e.g. `name = Particle`")
            }
            (Some(RANGES), KeyArg::List(_, List::Ranges(list))) => ranges = parse_ranges(cx, list),
            (Some(CONTROLS), KeyArg::List(k, List::Coords(list))) => {
                for c in list {
                    if let Some((_, len)) = &c.len {
                        cx.error_spanned_by(
                            len,
                            format!(
                                "a control is one `f64` parameter, found `{}[{}]`: list each control parameter, e.g. `controls(u1, u2)`",
                                c.name,
                                crate::ctxt::show(&len)
                            ),
                        );
                    } else if controls.contains(&c.name) {
                        cx.error_spanned_by(&c.name, format!("control `{}` is listed twice", c.name));
                    } else {
                        controls.push(c.name);
                    }
                }
                if controls.is_empty() {
                    cx.error_spanned_by(
                        &k,
                        "`controls()` is empty: list the `f64` parameters a control law sets before every step, e.g. `controls(u)`",
                    );
                }
            }
            (Some(FORCE), KeyArg::Value(_, Expr::Closure(closure))) => force = Some(closure),
            (Some(TIME), KeyArg::List(k, List::Coords(list))) => {
                let names: Vec<&CoordArg> = list.iter().collect();
                match names.as_slice() {
                    [c] if c.len.is_none() => time = Some((k, c.name.clone())),
                    _ => cx.error_spanned_by(
                        &k,
                        "`time(...)` names one group coordinate, the physical time: e.g. `group(t), time(t)`",
                    ),
                }
            }
            (Some(DOMAIN), KeyArg::List(k, List::Domain(tokens))) => {
                if let Some(entries) = domain_entries(cx, &k, tokens) {
                    domain = entries;
                }
            }
            (Some(DOMAIN), _) => cx.error_spanned_by(
                &key,
                format!("expected `domain(...)`; accepted: {DOMAIN_ACCEPTED}"),
            ),
            (Some(ADAPT), KeyArg::Value(k, Expr::Closure(closure))) => adapt = Some((k, closure)),
            (Some(ADAPT), KeyArg::Value(_, value)) => cx.error_spanned_by(
                &value,
                "expected `adapt = |q| <monitor>`: the step monitor `g(q) > 0`, a function of the shape coordinates (`dt = g(q) dτ`)",
            ),
            (Some(ADAPT), KeyArg::List(k, _)) => cx.error_spanned_by(
                &k,
                "expected `adapt = |q| <monitor>`, found `adapt(...)`",
            ),
            (Some(TIME), KeyArg::Value(k, _)) => cx.error_spanned_by(
                &k,
                "expected `time(t)`: the group coordinate that is physical time",
            ),
            (Some(FORCE), KeyArg::Value(_, value)) => cx.error_spanned_by(
                &value,
                format!(
                    "expected the forces as their virtual work, a closure linear in the virtual displacement: \
                     `force = |dq| -c * v.x * dq.x` (continuous Lagrangian) or `force = |dq0, dq1| ...` (discrete), found `{}`",
                    crate::ctxt::show(&value)
                ),
            ),
            (Some(CONSTRAINTS | NONHOLONOMIC), KeyArg::Value(k, Expr::Closure(closure))) => {
                if constraints.is_some() {
                    cx.error_spanned_by(
                        &k,
                        "a system declares either holonomic `constraints = |q| [..]` or `nonholonomic = |q, v| [..]`, not both",
                    );
                } else {
                    nonholonomic = k == NONHOLONOMIC;
                    constraints = Some(closure);
                }
            }
            (Some(NONHOLONOMIC), KeyArg::Value(_, value)) => cx.error_spanned_by(
                &value,
                format!(
                    "expected the nonholonomic constraints as a closure of the configuration and the velocity, linear in the \
                     velocity: `nonholonomic = |q, v| [q.theta.sin() * v.x - q.theta.cos() * v.y]`, found `{}`",
                    crate::ctxt::show(&value)
                ),
            ),
            (Some(NONHOLONOMIC), KeyArg::List(k, _)) => cx.error_spanned_by(
                &k,
                "expected `nonholonomic = |q, v| [<A_1(q) v>, ...]`, found `nonholonomic(...)`",
            ),
            (Some(CONSTRAINTS), KeyArg::Value(_, value)) => cx.error_spanned_by(
                &value,
                format!(
                    "expected the holonomic constraints as a closure of the configuration returning their values, \
                     `constraints = |q| [q.x * q.x + q.y * q.y - l * l]`, found `{}`",
                    crate::ctxt::show(&value)
                ),
            ),
            (Some(CONSTRAINTS), KeyArg::List(k, _)) => cx.error_spanned_by(
                &k,
                "expected `constraints = |q| [<φ_1>, ...]`, found `constraints(...)`",
            ),
            (Some(FORCE), KeyArg::List(k, _)) => cx.error_spanned_by(
                &k,
                "expected `force = |dq| <virtual work>` (or `|dq0, dq1|` for a discrete Lagrangian), found `force(...)`",
            ),
            (Some(RULE), KeyArg::Value(k, value)) => {
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
                            crate::ctxt::show(&value)
                        ),
                    ),
                }
            }
            (Some(RULE), KeyArg::List(k, _)) => cx.error_spanned_by(
                &k,
                format!("expected `rule = <name>`, found `rule(...)`; accepted: {RULES}"),
            ),
            (Some(RANGES), KeyArg::Value(k, _)) => cx.error_spanned_by(
                &k,
                format!(
                    "expected `ranges(...)`, found `ranges = ...`; accepted: {RANGES_ACCEPTED}"
                ),
            ),
            (Some(SHAPE | GROUP | COORDINATES | TRANSLATE | CONTROLS), KeyArg::Value(k, _)) => {
                cx.error_spanned_by(&k, format!("expected a list: `{k}(a, b, ...)`"))
            }
            (Some(CONNECTION), KeyArg::List(k, _)) => cx.error_spanned_by(
                &k,
                "expected `connection = [[b11, b12, ...], ...]`, found `connection(...)`",
            ),
            (Some(STEP), KeyArg::List(k, _)) => {
                cx.error_spanned_by(&k, "expected `step = <parameter>`, found `step(...)`")
            }
            (Some(NAME), KeyArg::List(k, _)) => {
                cx.error_spanned_by(&k, "expected `name = <TypeName>`, found `name(...)`")
            }
            (_, _) => cx.error_spanned_by(
                &key,
                format!("unknown argument `{key_name}`; accepted: {KEYS}"),
            ),
        }
    }
    let layout = if family == Some(COORDINATES) {
        let Some(coords) = coordinates else {
            if !seen.iter().any(|k| *k == COORDINATES) {
                let at = translates.first().map(|(k, _)| k.span());
                cx.error_at(
                    at.unwrap_or_else(Span::call_site),
                    "`translate(...)` needs `coordinates(...)`: list your coordinates, e.g. `coordinates(x[4], y[4]), translate(x), translate(y)`",
                );
            }
            return None;
        };
        if coords.is_empty() {
            cx.error_at(
                Span::call_site(),
                "no coordinates: `coordinates()` is empty; declare at least one coordinate, e.g. `coordinates(x[3])`",
            );
        }
        check_coordinates(cx, &coords, &[]);
        Layout::declared(cx, coords, &translates)
    } else {
        if shape.is_none() && !seen.iter().any(|k| *k == SHAPE) {
            cx.error_at(
                Span::call_site(),
                "missing `shape(...)`: list the shape coordinates, e.g. `shape(x, y)` (or `shape()` for none)",
            );
        }
        if group.is_none() && !seen.iter().any(|k| *k == GROUP) {
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
        Layout::explicit(shape, group)
    };
    let connection = connection.map(|(value, rows)| {
        check_connection_shape(cx, &value, &rows, layout.s(), layout.k());
        rows
    });
    let adapt = pair_adapt(cx, time, adapt).and_then(|(t, _, monitor)| {
        let index = layout.group.iter().position(|g| t == g);
        // With `translate(..)` the time is a coordinate translated alone: its own group
        // coordinate, which no other coordinate is measured from.
        let alone = !layout.declared
            || layout.group_decls.iter().any(
                |d| matches!(d, GroupDecl::Translate { names, .. } if names.len() == 1 && names[0] == t),
            );
        if !alone {
            cx.error_spanned_by(
                &t,
                format!(
                    "`{t}` is not translated alone: physical time is a coordinate the Lagrangian does not read, \
                     with a translation of its own, `translate({t})`"
                ),
            );
            None
        } else if let Some(index) = index {
            Some(Adapt {
                time: t,
                index,
                monitor,
            })
        } else {
            cx.error_spanned_by(&t, not_group_time(&t));
            None
        }
    });
    let domain = domain
        .iter()
        .flat_map(|entry| domain_bounds(cx, &layout, entry))
        .collect();
    Some(Spec {
        layout,
        domain,
        connection,
        step,
        name,
        ranges,
        rule,
        rule_written: seen.iter().any(|k| *k == RULE),
        controls,
        force,
        constraints,
        nonholonomic,
        adapt,
    })
}

/// The entries of `shape(...)`, `group(...)` or `coordinates(...)`, with their lengths checked.
fn coord_list(cx: &Ctxt, list: Punctuated<CoordArg, Token![,]>) -> Vec<Coord> {
    list.into_iter()
        .map(|c| {
            let len = match &c.len {
                None => None,
                Some((_, e)) => {
                    // A length passed through `macro_rules!` (`x[$n]`) arrives in an invisible
                    // group.
                    let mut inner = e;
                    while let Expr::Group(g) = inner {
                        inner = &g.expr;
                    }
                    let n = match inner {
                        Expr::Lit(syn::ExprLit {
                            lit: syn::Lit::Int(i),
                            ..
                        }) => i.base10_parse::<usize>().ok(),
                        _ => None,
                    };
                    match n {
                        Some(n) if (1..=MAX_COMPONENTS).contains(&n) => Some(n),
                        Some(n) => {
                            cx.error_spanned_by(
                                e,
                                format!(
                                    "array coordinate `{}` has length {n}; accepted: an integer literal from 1 to {MAX_COMPONENTS}, e.g. `{}[3]`",
                                    c.name, c.name
                                ),
                            );
                            Some(1)
                        }
                        None => {
                            cx.error_spanned_by(
                                e,
                                format!(
                                    "the length of array coordinate `{}` must be an integer literal, found `{}`; accepted: `{}[3]` (a constant length from 1 to {MAX_COMPONENTS})",
                                    c.name,
                                    crate::ctxt::show(&e),
                                    c.name
                                ),
                            );
                            Some(1)
                        }
                    }
                }
            };
            Coord { name: c.name, len }
        })
        .collect()
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
        other => format!("`{}`", crate::ctxt::show(&other)),
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

fn check_coordinates(cx: &Ctxt, shape: &[Coord], group: &[Coord]) {
    let mut seen: Vec<&Ident> = Vec::new();
    for id in shape.iter().chain(group).map(|c| &c.name) {
        if let Some(first) = seen.iter().find(|s| **s == id) {
            let in_shape = |x: &Ident| shape.iter().any(|s| s.name == *x);
            let in_group = |x: &Ident| group.iter().any(|s| s.name == *x);
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

/// `time(t)` and `adapt = |q| g` come together: `(t, the adapt key, the monitor)` when both are
/// written, `None` (with an error at the one written) otherwise.
pub fn pair_adapt(
    cx: &Ctxt,
    time: Option<(Ident, Ident)>,
    adapt: Option<(Ident, syn::ExprClosure)>,
) -> Option<(Ident, Ident, syn::ExprClosure)> {
    match (time, adapt) {
        (None, None) => None,
        (Some((k, _)), None) => {
            cx.error_spanned_by(
                &k,
                "`time(t)` comes with `adapt = |q| <monitor>`: the monitor `g(q) > 0` sets the physical step `dt = g(q) dτ`",
            );
            None
        }
        (None, Some((k, _))) => {
            cx.error_spanned_by(
                &k,
                "`adapt = |q| ..` needs `time(t)`: declare a group coordinate `t` for the physical time, e.g. `group(t), time(t)`",
            );
            None
        }
        (Some((_, t)), Some((k, monitor))) => Some((t, k, monitor)),
    }
}

/// The message of a `time(t)` whose `t` is not a group coordinate.
pub fn not_group_time(t: &Ident) -> String {
    format!(
        "`{t}` is not a group coordinate: physical time is a coordinate the Lagrangian does not read, declared in `group(..)`, e.g. `group({t}), time({t})`"
    )
}
