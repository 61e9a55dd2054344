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
//! The coordinates are `rotation(..)` (3 × 3 matrices), `direction(..)` (unit 3-vectors) and
//! `shape(..)` (scalars), in the order the attribute lists them; `step = ..` and `name = ..`
//! as for any system.

use proc_macro2::{Span, TokenStream, TokenTree};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Expr, Ident, Token};

use crate::ast::layout::CoordName;
use crate::ast::rule::Rule;
use crate::ctxt::Ctxt;
use crate::symbol::{
    self, KeyArg, CONTROLS, DIRECTION, FORCE, GROUP, NAME, ROTATION, RULE, SHAPE, STEP,
};

/// What the attribute of a system on rotation groups accepts, for messages.
pub const LIE_KEYS: &str = "`rotation(R, ...)` (rotation matrices), `direction(n, ...)` (unit \
vectors), `shape(x, ...)` (scalar coordinates), `group(x, ...)` (scalar coordinates whose \
translations are a symmetry), `rule = trapezoid | left | right` (for \
`L(q: Config, v: Velocity, ...)`), `force = |dq| ...` (or `|dq0, dq1|` for a discrete \
Lagrangian), `controls(u, ...)`, `step = <parameter>`, `name = <TypeName>`";

/// What a coordinate is (the runtime's `CoordinateKind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Scalar,
    Rotation,
    Direction,
}

impl Kind {
    /// Entries of the stored point.
    pub fn point_len(self) -> usize {
        match self {
            Kind::Scalar => 1,
            Kind::Rotation | Kind::Direction => 9,
        }
    }

    /// Entries of the chart and the momentum.
    pub fn chart_len(self) -> usize {
        match self {
            Kind::Scalar => 1,
            Kind::Rotation => 3,
            Kind::Direction => 2,
        }
    }

    /// Entries of the velocity a continuous Lagrangian reads: the body angular velocity `Ω` of a
    /// rotation, the velocity `ṅ` of a direction (a 3-vector), a scalar's rate.
    pub fn velocity_len(self) -> usize {
        match self {
            Kind::Scalar => 1,
            Kind::Rotation | Kind::Direction => 3,
        }
    }
}

/// One declared coordinate, with its place in the point and the chart.
#[derive(Clone, Debug)]
pub struct LieCoord {
    pub name: Ident,
    pub kind: Kind,
    pub point: usize,
    pub chart: usize,
    /// The first of its velocity symbols (a continuous Lagrangian's `v`).
    pub velocity: usize,
    /// A scalar declared in `group(..)`: its translations are a symmetry.
    pub group: bool,
}

/// The parsed attribute.
pub struct LieSpec {
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
}

impl LieSpec {
    /// `P`, the length of a stored point.
    pub fn p(&self) -> usize {
        self.coords.iter().map(|c| c.kind.point_len()).sum()
    }

    /// The length of a continuous Lagrangian's velocity.
    pub fn velocity_len(&self) -> usize {
        self.coords.iter().map(|c| c.kind.velocity_len()).sum()
    }

    /// `N = dim Q`, the length of the chart and the momentum.
    pub fn n(&self) -> usize {
        self.coords.iter().map(|c| c.kind.chart_len()).sum()
    }

    /// The coordinates as the body reads them: a rotation whole (3 × 3, its point entries row
    /// by row), a direction as the third column of its frame, a scalar as one entry.
    ///
    /// The velocity argument of a continuous Lagrangian reads a rotation's body angular velocity
    /// and a direction's velocity as 3-vectors, a scalar's rate as an f64, each from its own
    /// velocity symbols.
    pub fn lowering_coords(&self) -> Vec<CoordName> {
        self.coords
            .iter()
            .map(|c| {
                let (p, v) = (c.point, c.velocity);
                let matrix = match c.kind {
                    Kind::Scalar => None,
                    Kind::Rotation => Some((3, 3, (p..p + 9).collect())),
                    Kind::Direction => Some((3, 1, vec![p + 2, p + 5, p + 8])),
                };
                let velocity = match c.kind {
                    Kind::Scalar => (1, 1, vec![v]),
                    Kind::Rotation | Kind::Direction => (3, 1, (v..v + 3).collect()),
                };
                CoordName {
                    name: c.name.to_string(),
                    len: None,
                    components: vec![crate::ast::layout::Component::Var(p)],
                    matrix,
                    velocity: self.rule.is_some().then_some(velocity.clone()),
                    displacement: Some(velocity),
                }
            })
            .collect()
    }
}

/// Whether the attribute declares a `rotation(..)` or `direction(..)` coordinate.
pub fn is_lie(args: &TokenStream) -> bool {
    let mut tokens = args.clone().into_iter().peekable();
    while let Some(t) = tokens.next() {
        if let TokenTree::Ident(id) = &t {
            if (id == ROTATION.0 || id == DIRECTION.0)
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
pub fn parse(cx: &Ctxt, args: TokenStream) -> Option<LieSpec> {
    let items = symbol::parse_args::<LieItem>(cx, args)?;
    let (mut coords, mut step, mut name, mut rule) = (Vec::<LieCoord>::new(), None, None, None);
    let (mut force, mut controls) = (None, Vec::new());
    let (mut point, mut chart, mut velocity) = (0, 0, 0);
    for LieItem(item) in &items {
        let key = item.key();
        let kind = if key == ROTATION {
            Some(Kind::Rotation)
        } else if key == DIRECTION {
            Some(Kind::Direction)
        } else if key == SHAPE || key == GROUP {
            Some(Kind::Scalar)
        } else {
            None
        };
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
                    coords.push(LieCoord {
                        name: id,
                        kind,
                        point,
                        chart,
                        velocity,
                        group: key == GROUP,
                    });
                    point += kind.point_len();
                    chart += kind.chart_len();
                    velocity += kind.velocity_len();
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
        [ROTATION, DIRECTION, SHAPE, GROUP]
            .iter()
            .any(|k| i.key() == k)
    });
    if coords.is_empty() && !listed {
        cx.error_at(
            Span::call_site(),
            format!("declare the coordinates: {LIE_KEYS}"),
        );
    }
    let rule_written = items.iter().any(|LieItem(i)| i.key() == RULE);
    Some(LieSpec {
        coords,
        step,
        name,
        rule,
        rule_written,
        force,
        controls,
    })
}

impl LieSpec {
    /// The name of coordinate `c`'s kind, as the runtime spells it.
    pub fn kind_path(c: &LieCoord) -> Ident {
        let name = match c.kind {
            Kind::Scalar if c.group => "Group",
            Kind::Scalar => "Scalar",
            Kind::Rotation => "Rotation",
            Kind::Direction => "Direction",
        };
        Ident::new(name, Span::call_site())
    }
}
