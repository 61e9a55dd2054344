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
//!
//! A coordinate may be an array of constant length, `shape(x[199], y)`, read in the body as
//! `q0.x[i]`. Or the symmetry is declared on the user's own coordinates (see [`Layout`]):
//!
//! ```text
//! #[reduced_lagrangian(coordinates(x[4], y[4]), translate(x), translate(y))]
//! ```

use proc_macro2::Span;
use quote::ToTokens;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::spanned::Spanned;
use syn::{Expr, Ident, Token};

use crate::continuous::{Rule, RULES};
use crate::ctxt::Ctxt;
use crate::lower::{Component, CoordName};

const KEYS: &str = "`shape(...)`, `group(...)` (or `coordinates(...)` with `translate(...)`), `connection = [[...], ...]`, `step = <parameter>`, `name = <TypeName>`, `rule = midpoint | trapezoid | left | right` and `ranges(<name> = (lo, hi), ...)`";

/// What `ranges(...)` accepts, for error messages.
const RANGES: &str = "`ranges(name = (lo, hi), ...)` with a parameter or coordinate name and finite f64 literals lo < hi, e.g. `ranges(h = (0.001, 0.1))`";

/// The parsed attribute.
pub struct Spec {
    /// The coordinates: the user's, and the configuration vector the system works in.
    pub layout: Layout,
    /// Whether every array length in the attribute was valid; if not (already reported), the
    /// body is not lowered, so a bad length causes no follow-on errors.
    pub lengths_ok: bool,
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
    /// One per user coordinate (an array coordinate's range applies to all its components), in
    /// the order of [`Layout::coords`].
    pub coords: Vec<Option<(f64, f64)>>,
    /// One per parameter, in declaration order.
    pub params: Vec<Option<(f64, f64)>>,
}

/// Largest accepted length of an array coordinate (the configuration vector is a fixed-size
/// nalgebra vector, and every component is a leaf of the expression graph).
pub const MAX_COMPONENTS: usize = 4096;

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

/// A declared coordinate: a scalar (`len = None`) or an array of `len` components.
#[derive(Clone)]
pub struct Coord {
    pub name: Ident,
    pub len: Option<usize>,
}

impl Coord {
    /// The names of its components: `x`, or `x[0]`, `x[1]`, ….
    pub fn component_names(&self) -> Vec<String> {
        match self.len {
            None => vec![self.name.to_string()],
            Some(n) => (0..n).map(|i| format!("{}[{i}]", self.name)).collect(),
        }
    }

    /// `x` or `x[3]`, as declared.
    pub fn declared(&self) -> String {
        match self.len {
            None => self.name.to_string(),
            Some(n) => format!("{}[{n}]", self.name),
        }
    }
}

/// What one group dimension is, for messages: a declared group coordinate (component), or a
/// `translate(...)` key.
pub enum GroupDecl {
    /// `group(theta)` or a component of `group(c[3])`: the name of the component (`c[1]`).
    Coordinate { ident: Ident, component: String },
    /// `translate(a, b, ...)`: the key and the coordinates it moves together.
    Translate { key: Ident, names: Vec<Ident> },
}

/// The coordinates: the user's (the fields of `<Name>Config`, flattened in order into the user
/// configuration vector) and the configuration vector the system works in, `q = (x, g)` with
/// `S` shape and `K` group coordinates (the trivialization `Q = Σ × G` of §2.2.1).
///
/// With `shape(...), group(...)` the two vectors are the same. With `coordinates(...)` and
/// `translate(...)` keys they are related by a unimodular `q_user = T q`: for the `j`-th
/// `translate(a, b, ...)`, the group coordinate `g_j` is the first component `a[0]` of the
/// first listed coordinate, and every other component `c` of the listed coordinates becomes the
/// shape coordinate `r_c = c − a[0]`, so `a[0] = g_j`, `c = g_j + r_c`; coordinates in no
/// `translate` stay shape coordinates unchanged. The shape coordinates follow the order of the
/// user's flattened components (skipping the group components), then the `K` group coordinates
/// follow in the order of the `translate` keys. Translating `g_j` moves every listed component
/// together: the declared symmetry, now a translation of a group coordinate with `B = 0`.
pub struct Layout {
    /// The user's coordinates, in the order of `<Name>Config`'s fields.
    pub coords: Vec<Coord>,
    /// Names of the `S` shape coordinates (`x`, `x[3]`, `x[3] - x[0]`).
    pub shape: Vec<String>,
    /// Names of the `K` group coordinates.
    pub group: Vec<String>,
    /// One per group coordinate.
    pub group_decls: Vec<GroupDecl>,
    /// One per component of the user configuration vector: its expression in `q`.
    pub components: Vec<Component>,
    /// Whether the symmetry is declared on the user's coordinates (`translate`): then
    /// `q_user ≠ q` in general and the emitted code converts.
    pub declared: bool,
}

impl Layout {
    /// `shape(...), group(...)`: the user's vector is the configuration vector.
    fn explicit(shape: Vec<Coord>, group: Vec<Coord>) -> Layout {
        let names =
            |cs: &[Coord]| -> Vec<String> { cs.iter().flat_map(Coord::component_names).collect() };
        let (shape_names, group_names) = (names(&shape), names(&group));
        let group_decls = group
            .iter()
            .flat_map(|c| {
                c.component_names()
                    .into_iter()
                    .map(|component| GroupDecl::Coordinate {
                        ident: c.name.clone(),
                        component,
                    })
            })
            .collect();
        let n = shape_names.len() + group_names.len();
        Layout {
            coords: shape.into_iter().chain(group).collect(),
            shape: shape_names,
            group: group_names,
            group_decls,
            components: (0..n).map(Component::Var).collect(),
            declared: false,
        }
    }

    /// `coordinates(...), translate(...), ...`: adapted coordinates (see [`Layout`]).
    fn declared(cx: &Ctxt, coords: Vec<Coord>, translates: &[(Ident, Vec<Ident>)]) -> Layout {
        // Which translate each coordinate belongs to.
        let mut owner: Vec<Option<usize>> = vec![None; coords.len()];
        let mut decls = Vec::new();
        for (key, names) in translates {
            let j = decls.len();
            let mut valid = Vec::new();
            for name in names {
                match coords.iter().position(|c| c.name == *name) {
                    None => cx.error_spanned_by(
                        name,
                        format!(
                            "unknown coordinate `{name}` in `translate(...)`; declared coordinates: {}",
                            coords.iter().map(|c| format!("`{}`", c.name)).collect::<Vec<_>>().join(", ")
                        ),
                    ),
                    Some(i) if owner[i].is_some() => cx.error_spanned_by(
                        name,
                        format!(
                            "coordinate `{name}` is already translated by an earlier `translate(...)`: a coordinate may appear in at most one translation"
                        ),
                    ),
                    Some(i) => {
                        owner[i] = Some(j);
                        valid.push(i);
                    }
                }
            }
            if let Some(&first) = valid.first() {
                decls.push((key.clone(), names.clone(), first));
            }
        }
        let k = decls.len();
        // The flattened user components: (coordinate, name).
        let flat: Vec<(usize, String)> = coords
            .iter()
            .enumerate()
            .flat_map(|(i, c)| c.component_names().into_iter().map(move |n| (i, n)))
            .collect();
        let first_component = |i: usize| {
            flat.iter()
                .position(|(c, _)| *c == i)
                .expect("a coordinate has a component")
        };
        let group_components: Vec<usize> = decls
            .iter()
            .map(|&(_, _, first)| first_component(first))
            .collect();
        let group: Vec<String> = group_components
            .iter()
            .map(|&u| flat[u].1.clone())
            .collect();
        let s = flat.len() - k;
        let mut shape = Vec::with_capacity(s);
        let mut components = Vec::with_capacity(flat.len());
        for (u, (c, name)) in flat.iter().enumerate() {
            if let Some(j) = group_components.iter().position(|&g| g == u) {
                components.push(Component::Var(s + j));
                continue;
            }
            let index = shape.len();
            match owner[*c] {
                Some(j) => {
                    shape.push(format!("{name} - {}", group[j]));
                    components.push(Component::Sum(s + j, index));
                }
                None => {
                    shape.push(name.clone());
                    components.push(Component::Var(index));
                }
            }
        }
        Layout {
            coords,
            shape,
            group,
            group_decls: decls
                .into_iter()
                .map(|(key, names, _)| GroupDecl::Translate { key, names })
                .collect(),
            components,
            declared: true,
        }
    }

    /// Whether some coordinate is an array.
    pub fn has_arrays(&self) -> bool {
        self.coords.iter().any(|c| c.len.is_some())
    }

    /// Number of shape coordinates `S`.
    pub fn s(&self) -> usize {
        self.shape.len()
    }

    /// Number of group coordinates `K`.
    pub fn k(&self) -> usize {
        self.group.len()
    }

    /// Names of the user's components, in the order of the user configuration vector.
    pub fn user_components(&self) -> Vec<String> {
        self.coords
            .iter()
            .flat_map(Coord::component_names)
            .collect()
    }

    /// The coordinates the body reads, and how each component is formed from `q`.
    pub fn lowering_coords(&self) -> Vec<CoordName> {
        let mut at = 0;
        self.coords
            .iter()
            .map(|c| {
                let n = c.len.unwrap_or(1);
                let comps = self.components[at..at + n].to_vec();
                at += n;
                CoordName {
                    name: c.name.to_string(),
                    len: c.len,
                    components: comps,
                }
            })
            .collect()
    }

    /// `q = T⁻¹ q_user`, evaluated (for the invariance check's sample points).
    pub fn to_adapted(&self, user: &[f64]) -> Vec<f64> {
        let mut q = vec![0.0; user.len()];
        for (u, c) in self.components.iter().enumerate() {
            if let Component::Var(a) = *c {
                q[a] = user[u];
            }
        }
        for (u, c) in self.components.iter().enumerate() {
            if let Component::Sum(g, r) = *c {
                q[r] = user[u] - q[g];
            }
        }
        q
    }
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
    List(Ident, Punctuated<CoordArg, Token![,]>),
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
    let mut shape: Option<Vec<Coord>> = None;
    let mut group: Option<Vec<Coord>> = None;
    let mut coordinates: Option<Vec<Coord>> = None;
    let mut translates: Vec<(Ident, Vec<Ident>)> = Vec::new();
    let mut connection: Option<(Expr, Vec<Vec<Expr>>)> = None;
    let mut step: Option<Ident> = None;
    let mut name: Option<Ident> = None;
    let mut ranges: Vec<Range> = Vec::new();
    let mut rule: Option<(Ident, Rule)> = None;
    let mut seen: Vec<String> = Vec::new();
    let mut lengths_ok = true;
    // Which way the symmetry is declared: the first of `shape`/`group` or
    // `coordinates`/`translate` decides; a key of the other family is an error.
    let mut family: Option<&'static str> = None;
    for arg in args {
        let key = match &arg {
            Arg::List(k, _) | Arg::Value(k, _) | Arg::Ranges(k, _) => k.clone(),
        };
        let key_name = key.to_string();
        // `translate(...)` may be repeated: each one is a group dimension.
        if seen.contains(&key_name) && key_name != "translate" {
            cx.error_spanned_by(&key, format!("duplicate `{key_name}` argument"));
            continue;
        }
        seen.push(key_name.clone());
        let this_family = match key_name.as_str() {
            "shape" | "group" => Some("shape"),
            "coordinates" | "translate" => Some("coordinates"),
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
                            if earlier == "shape" { "`shape(...)`/`group(...)`" } else { "`coordinates(...)`/`translate(...)`" }
                        ),
                    );
                    continue;
                }
                _ => family = Some(f),
            }
        }
        let connection_clash = (key_name == "connection" && family == Some("coordinates"))
            || (this_family == Some("coordinates") && connection.is_some());
        if connection_clash {
            cx.error_spanned_by(
                &key,
                "`connection = ...` cannot be combined with `coordinates(...)`/`translate(...)`: the adapted coordinates \
                 the compiler builds from `translate(...)` have the connection B = 0; use `shape(...), group(...), connection = ...` \
                 for a nonzero B",
            );
            if key_name == "connection" {
                continue;
            }
            // The connection came first: keep the coordinates, drop the connection.
            connection = None;
        }
        match (key_name.as_str(), arg) {
            ("shape", Arg::List(_, list)) => {
                shape = Some(coord_list(cx, list, &mut lengths_ok));
            }
            // `group()` declares no symmetry: a plain variational integrator (K = 0).
            ("group", Arg::List(_, list)) => {
                group = Some(coord_list(cx, list, &mut lengths_ok));
            }
            ("coordinates", Arg::List(_, list)) => {
                coordinates = Some(coord_list(cx, list, &mut lengths_ok));
            }
            ("translate", Arg::List(k, list)) => {
                let mut names = Vec::new();
                for c in list {
                    if let Some((_, len)) = &c.len {
                        cx.error_spanned_by(
                            len,
                            format!(
                                "`translate(...)` lists whole coordinates, found `{}[{}]`: write `translate({})` to translate every component of `{}`",
                                c.name,
                                len.to_token_stream(),
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
            ("shape" | "group" | "coordinates" | "translate", Arg::Value(k, _)) => {
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
    let layout = if family == Some("coordinates") {
        let Some(coords) = coordinates else {
            if !seen.iter().any(|k| k == "coordinates") {
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
        Layout::explicit(shape, group)
    };
    let connection = connection.map(|(value, rows)| {
        check_connection_shape(cx, &value, &rows, layout.s(), layout.k());
        rows
    });
    Some(Spec {
        layout,
        lengths_ok,
        connection,
        step,
        name,
        ranges,
        rule,
        rule_written: seen.iter().any(|k| k == "rule"),
    })
}

/// The entries of `shape(...)`, `group(...)` or `coordinates(...)`, with their lengths checked.
fn coord_list(cx: &Ctxt, list: Punctuated<CoordArg, Token![,]>, ok: &mut bool) -> Vec<Coord> {
    list.into_iter()
        .map(|c| {
            let len = match &c.len {
                None => None,
                Some((_, e)) => {
                    let n = match e {
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
                            *ok = false;
                            Some(1)
                        }
                        None => {
                            cx.error_spanned_by(
                                e,
                                format!(
                                    "the length of array coordinate `{}` must be an integer literal, found `{}`; accepted: `{}[3]` (a constant length from 1 to {MAX_COMPONENTS})",
                                    c.name,
                                    e.to_token_stream(),
                                    c.name
                                ),
                            );
                            *ok = false;
                            Some(1)
                        }
                    }
                }
            };
            Coord { name: c.name, len }
        })
        .collect()
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
