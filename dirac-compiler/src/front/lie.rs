//! Systems on rotation groups: an attribute with `rotation(..)` or `direction(..)`
//! coordinates (see `dirac::runtime::lie`).
//!
//! ```text
//! #[reduced_lagrangian(rotation(r), step = h)]
//! fn rigid_body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
//!     let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
//!     ((Matrix3::identity() - q0.r.transpose() * q1.r) * jd).trace() / h
//! }
//! ```
//!
//! The coordinates are `rotation(..)` (3 × 3 matrices), `direction(..)` (unit 3-vectors),
//! `pose(..)` (rigid motions: a rotation and a translation) and `shape(..)`, `group(..)`
//! (scalars), in the order the attribute lists them; `step = ..` and `name = ..` as for any
//! system. This stage records which key declared each coordinate; what a kind of coordinate is
//! (its point, chart and step) is [`crate::ir::group`]'s, which resolves the keys.

use proc_macro2::{Span, TokenStream, TokenTree};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Expr, Ident, Token};

use crate::ctxt::Ctxt;
use crate::front::rule::Rule;
use crate::symbol::{
    self, KeyArg, Symbol, ADAPT, AXIS, CONTROLS, FORCE, GROUP, GROUP_COORDINATES, NAME, RULE,
    SHAPE, STEP, SYMMETRY, TIME,
};

/// What the attribute of a system on rotation groups accepts, for messages.
pub const LIE_KEYS: &str = "`rotation(R, ...)` (rotation matrices), `direction(n, ...)` (unit \
vectors), `pose(X, ...)` (rigid motions: `X.rotation`, `X.translation`), `shape(x, ...)` \
(scalar coordinates), `group(x, ...)` (scalar coordinates whose \
translations are a symmetry), `rule = trapezoid | left | right` (for \
`L(q: Config, v: Velocity, ...)`), `force = |dq| ...` (or `|dq0, dq1|` for a discrete \
Lagrangian), `controls(u, ...)`, `symmetry(R)` (every rotation `R ↦ g R`) or \
`symmetry(R, n, ..., axis = z)` (rotations about a coordinate axis) or `symmetry(X)` (every \
rigid motion of a pose `X`), `time(t), adapt = |q| \
<monitor>` (adaptive steps), `step = <parameter>`, `name = <TypeName>`";

/// One declared coordinate: its name and the key that declared it (`shape`, `group`,
/// `rotation`, `direction`, `pose`), the name of its kind.
#[derive(Clone, Debug)]
pub struct LieCoord {
    pub name: Ident,
    pub kind: Symbol,
}

/// Which rotations a `symmetry(..)` declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SymmetryKind {
    /// Every rotation `R ↦ g R` of one rotation coordinate (`symmetry(R)`): `SO(3)`.
    Rotations,
    /// The rotations about coordinate axis `0`, `1` or `2` (`x`, `y`, `z`) of every listed
    /// coordinate together (`symmetry(R, n, .., axis = z)`): `SO(2)`.
    Axis(usize),
    /// Every rigid motion `(A, a)·(R, x) = (A R, A x + a)` of one pose coordinate
    /// (`symmetry(X)`): `SE(3)`.
    RigidMotions,
}

/// A declared rotation symmetry.
#[derive(Clone, Debug)]
pub struct Symmetry {
    pub kind: SymmetryKind,
    /// The coordinates it acts on (indices into [`LieAttr::coords`]), with their names as
    /// written.
    pub coords: Vec<(usize, Ident)>,
}

/// `symmetry(..)` as written: the listed coordinates and the axis, before the kinds of the
/// listed coordinates are checked against it (`crate::ir::lie::LieSpec::resolve`).
#[derive(Clone, Debug)]
pub struct SymmetryDecl {
    /// `axis = x | y | z`: 0, 1 or 2.
    pub axis: Option<usize>,
    /// The listed coordinates (indices into [`LieAttr::coords`]), with their names as written.
    pub coords: Vec<(usize, Ident)>,
}

/// The parsed attribute.
pub struct LieAttr {
    pub coords: Vec<LieCoord>,
    pub step: Option<Ident>,
    pub name: Option<Ident>,
    /// The quadrature rule of a continuous Lagrangian `L(q, v)`.
    pub rule: Option<(Ident, Rule)>,
    /// Whether `rule = ..` was written (even if rejected: no follow-on error then).
    pub rule_written: bool,
    /// `force = |dq| W` or `|dq0, dq1| W`: the virtual work, whose displacements read a
    /// rotation's `η` (`δR = R η̂`, body frame), a direction's tangent `δn`, a scalar's `δx`.
    pub force: Option<syn::ExprClosure>,
    /// `controls(u, ..)`: parameters a control law sets before every step.
    pub controls: Vec<Ident>,
    /// `symmetry(..)`: the rotations under which `L_d` is invariant.
    pub symmetry: Option<SymmetryDecl>,
    /// `time(t), adapt = |q| g`: adaptive steps (see [`crate::ir::adapt`]).
    pub adapt: Option<LieAdapt>,
}

/// `time(t), adapt = |q| g` on rotation groups: the scalar group coordinate that is physical
/// time and the step monitor, a function of the configuration.
pub struct LieAdapt {
    /// The time coordinate as written.
    pub time: Ident,
    /// Its index in [`LieAttr::coords`].
    pub coord: usize,
    /// `|q| g(q)`.
    pub monitor: syn::ExprClosure,
}

/// Whether the attribute declares a coordinate on a group other than the line (`rotation(..)`,
/// `direction(..)`, `pose(..)`).
pub fn is_lie(args: &TokenStream) -> bool {
    let mut tokens = args.clone().into_iter().peekable();
    while let Some(t) = tokens.next() {
        if let TokenTree::Ident(id) = &t {
            if GROUP_COORDINATES.iter().any(|k| id == k)
                && matches!(tokens.peek(), Some(TokenTree::Group(_)))
            {
                return true;
            }
        }
    }
    false
}

/// One `key(...)` or `key = value` of the attribute.
type Item = KeyArg<Punctuated<Expr, Token![,]>, Expr>;

struct LieItem(Item);

impl Parse for LieItem {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        KeyArg::parse_with(
            input,
            |_, content| Punctuated::parse_terminated(content),
            |_, input| input.parse(),
            |key| symbol::list_or_value(key, LIE_KEYS),
        )
        .map(LieItem)
    }
}

/// The attribute; `None` after errors (recorded).
pub fn parse(cx: &Ctxt, args: TokenStream) -> Option<LieAttr> {
    let items = symbol::parse_args::<LieItem>(cx, args)?;
    let (mut coords, mut step, mut name, mut rule) = (Vec::<LieCoord>::new(), None, None, None);
    let (mut force, mut controls) = (None, Vec::new());
    let mut symmetry: Option<(&Ident, &Punctuated<Expr, Token![,]>)> = None;
    let (mut time, mut adapt) = (None, None);
    for LieItem(item) in &items {
        let key = item.key();
        let kind = [SHAPE, GROUP]
            .into_iter()
            .chain(GROUP_COORDINATES)
            .find(|k| key == k);
        match (kind, item) {
            (Some(kind), KeyArg::List(_, list)) => {
                for e in list {
                    let id = match e {
                        Expr::Path(p) if p.path.get_ident().is_some() => {
                            p.path.get_ident().expect("checked").clone()
                        }
                        other => {
                            cx.error_spanned_by(
                                other,
                                format!(
                                    "expected a coordinate name; `{key}(..)` lists names, e.g. `{key}(a, b)` (arrays are not accepted with rotations or directions)"
                                ),
                            );
                            continue;
                        }
                    };
                    if coords.iter().any(|c| c.name == id) {
                        cx.error_spanned_by(&id, format!("coordinate `{id}` is declared twice"));
                        continue;
                    }
                    coords.push(LieCoord { name: id, kind });
                }
            }
            (None, KeyArg::Value(_, Expr::Path(p)))
                if key == STEP && p.path.get_ident().is_some() =>
            {
                step = p.path.get_ident().cloned();
            }
            (None, KeyArg::Value(_, Expr::Path(p)))
                if key == NAME && p.path.get_ident().is_some() =>
            {
                name = p.path.get_ident().cloned();
            }
            (None, KeyArg::Value(_, Expr::Path(p)))
                if key == RULE && p.path.get_ident().is_some() =>
            {
                let id = p.path.get_ident().expect("checked");
                match Rule::from_ident(id) {
                    Some(Rule::Midpoint) => cx.error_spanned_by(
                        id,
                        "`rule = midpoint` is not available with rotation or direction coordinates: \
                         the mean of two rotations is not a rotation, nor that of two unit vectors a \
                         unit vector; use `rule = trapezoid` (symmetric, order 2), `left` or `right`",
                    ),
                    Some(r) => rule = Some((id.clone(), r)),
                    None => cx.error_spanned_by(
                        id,
                        "unknown rule; accepted: `rule = trapezoid`, `rule = left` or `rule = right`",
                    ),
                }
            }
            (None, KeyArg::Value(_, Expr::Closure(c))) if key == FORCE => force = Some(c.clone()),
            (None, KeyArg::List(_, list)) if key == TIME => match list.iter().collect::<Vec<_>>()[..] {
                [Expr::Path(p)] if p.path.get_ident().is_some() => {
                    time = Some((key.clone(), p.path.get_ident().expect("checked").clone()));
                }
                _ => cx.error_spanned_by(
                    key,
                    "`time(...)` names one group coordinate, the physical time: e.g. `group(t), time(t)`",
                ),
            },
            (None, KeyArg::Value(_, Expr::Closure(c))) if key == ADAPT => {
                adapt = Some((key.clone(), c.clone()));
            }
            (None, _) if key == TIME || key == ADAPT => cx.error_spanned_by(
                key,
                "expected `time(t), adapt = |q| <monitor>`: the group coordinate that is physical time and the \
                 step monitor `g(q) > 0` (`dt = g(q) dτ`)",
            ),
            (None, KeyArg::List(_, list)) if key == CONTROLS => {
                for e in list {
                    match e {
                        Expr::Path(p) if p.path.get_ident().is_some() => {
                            controls.push(p.path.get_ident().expect("checked").clone());
                        }
                        other => cx.error_spanned_by(other, "expected a parameter name"),
                    }
                }
            }
            (None, KeyArg::List(_, list)) if key == SYMMETRY => {
                if symmetry.is_some() {
                    cx.error_spanned_by(
                        key,
                        "`symmetry(..)` is declared twice; declare one symmetry (list every \
                         coordinate it rotates in it)",
                    );
                } else {
                    symmetry = Some((key, list));
                }
            }
            (None, _) if key == SYMMETRY => cx.error_spanned_by(
                key,
                "expected `symmetry(R)` (every rotation of the rotation `R`) or \
                 `symmetry(R, n, .., axis = z)` (rotations about a coordinate axis)",
            ),
            (None, _) if key == FORCE => cx.error_spanned_by(
                key,
                format!("expected `force = |dq| <virtual work>`; accepted: {LIE_KEYS}"),
            ),
            (None, _) if key == STEP || key == NAME || key == RULE => cx.error_spanned_by(
                key,
                format!("expected `{key} = <name>`; accepted: {LIE_KEYS}"),
            ),
            (Some(_), KeyArg::Value(..)) => cx.error_spanned_by(
                key,
                format!("expected `{key}(a, b, ...)`; accepted: {LIE_KEYS}"),
            ),
            (None, _) => {
                let why = if symbol::key(key).is_some() {
                    "is not available with rotation or direction coordinates yet"
                } else {
                    "is not a key of this attribute"
                };
                cx.error_spanned_by(key, format!("`{key}` {why}; accepted: {LIE_KEYS}"));
            }
        }
    }
    let listed = items.iter().any(|LieItem(i)| {
        [SHAPE, GROUP]
            .iter()
            .chain(&GROUP_COORDINATES)
            .any(|k| i.key() == k)
    });
    if coords.is_empty() && !listed {
        cx.error_at(
            Span::call_site(),
            format!("declare the coordinates: {LIE_KEYS}"),
        );
    }
    let rule_written = items.iter().any(|LieItem(i)| i.key() == RULE);
    let symmetry = symmetry.and_then(|(key, list)| parse_symmetry(cx, &coords, key, list));
    let adapt = crate::front::attr::pair_adapt(cx, time, adapt).and_then(|(t, k, monitor)| {
        match coords.iter().position(|c| c.name == t) {
            Some(coord) if coords[coord].kind == GROUP => {
                if rule.is_none() {
                    cx.error_spanned_by(
                        &k,
                        "adaptive steps transform a continuous Lagrangian: write `fn l(q: Config, v: Velocity, ..)` \
                         with `rule = trapezoid | left | right`",
                    );
                    return None;
                }
                Some(LieAdapt {
                    time: t,
                    coord,
                    monitor,
                })
            }
            _ => {
                cx.error_spanned_by(&t, crate::front::attr::not_group_time(&t));
                None
            }
        }
    });
    Some(LieAttr {
        coords,
        step,
        name,
        rule,
        rule_written,
        force,
        controls,
        symmetry,
        adapt,
    })
}

/// `symmetry(R)` or `symmetry(a, b, .., axis = x | y | z)`, against the declared names (their
/// kinds are checked once resolved, `crate::ir::lie::LieSpec::resolve`).
fn parse_symmetry(
    cx: &Ctxt,
    coords: &[LieCoord],
    key: &Ident,
    list: &Punctuated<Expr, Token![,]>,
) -> Option<SymmetryDecl> {
    let (mut listed, mut axis) = (Vec::new(), None);
    let failed = std::cell::Cell::new(false);
    let error = |tokens: &dyn quote::ToTokens, message: String| {
        failed.set(true);
        cx.error_spanned_by(tokens.to_token_stream(), message);
    };
    for e in list {
        match e {
            Expr::Path(p) if p.path.get_ident().is_some() => {
                let id = p.path.get_ident().expect("checked");
                match coords.iter().position(|c| c.name == *id) {
                    Some(_) if listed.iter().any(|(_, n): &(usize, Ident)| n == id) => {
                        error(id, format!("`{id}` is listed twice"));
                    }
                    Some(i) => listed.push((i, id.clone())),
                    None => error(
                        id,
                        format!(
                            "`{id}` is not a declared coordinate; `symmetry(..)` lists coordinates \
                             declared in `rotation(..)` or `direction(..)`"
                        ),
                    ),
                }
            }
            Expr::Assign(a) if matches!(&*a.left, Expr::Path(p) if p.path.is_ident(AXIS.0)) => {
                let which = match &*a.right {
                    Expr::Path(p) => p
                        .path
                        .get_ident()
                        .and_then(|id| ["x", "y", "z"].iter().position(|a| id == a)),
                    _ => None,
                };
                match which {
                    Some(k) if axis.is_none() => axis = Some(k),
                    Some(_) => error(a, "`axis` is given twice".into()),
                    None => error(
                        &a.right,
                        "expected a coordinate axis: `axis = x`, `axis = y` or `axis = z`".into(),
                    ),
                }
            }
            other => error(
                other,
                "expected a coordinate name or `axis = x | y | z`; e.g. `symmetry(R)` for every \
                 rotation of `R`, `symmetry(n1, n2, axis = z)` for the rotations about the z-axis"
                    .into(),
            ),
        }
    }
    if failed.get() {
        return None;
    }
    if listed.is_empty() {
        cx.error_spanned_by(
            key,
            "`symmetry(..)` lists the coordinates it rotates, e.g. `symmetry(R)` or \
             `symmetry(n1, n2, axis = z)`",
        );
        return None;
    }
    Some(SymmetryDecl {
        axis,
        coords: listed,
    })
}
