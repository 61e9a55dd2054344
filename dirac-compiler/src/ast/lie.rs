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
    self, KeyArg, ADAPT, AXIS, CONTROLS, DIRECTION, FORCE, GROUP, NAME, ROTATION, RULE, SHAPE,
    STEP, SYMMETRY, TIME,
};

/// What the attribute of a system on rotation groups accepts, for messages.
pub const LIE_KEYS: &str = "`rotation(R, ...)` (rotation matrices), `direction(n, ...)` (unit \
vectors), `shape(x, ...)` (scalar coordinates), `group(x, ...)` (scalar coordinates whose \
translations are a symmetry), `rule = trapezoid | left | right` (for \
`L(q: Config, v: Velocity, ...)`), `force = |dq| ...` (or `|dq0, dq1|` for a discrete \
Lagrangian), `controls(u, ...)`, `symmetry(R)` (every rotation `R ↦ g R`) or \
`symmetry(R, n, ..., axis = z)` (rotations about a coordinate axis), `time(t), adapt = |q| \
<monitor>` (adaptive steps), `step = <parameter>`, `name = <TypeName>`";

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

/// Which rotations a `symmetry(..)` declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SymmetryKind {
    /// Every rotation `R ↦ g R` of one rotation coordinate (`symmetry(R)`): `SO(3)`.
    Rotations,
    /// The rotations about coordinate axis `0`, `1` or `2` (`x`, `y`, `z`) of every listed
    /// coordinate together (`symmetry(R, n, .., axis = z)`): `SO(2)`.
    Axis(usize),
}

/// A declared rotation symmetry.
#[derive(Clone, Debug)]
pub struct Symmetry {
    pub kind: SymmetryKind,
    /// The coordinates it acts on (indices into [`LieSpec::coords`]), with their names as
    /// written.
    pub coords: Vec<(usize, Ident)>,
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
    /// `symmetry(..)`: the rotations under which `L_d` is invariant.
    pub symmetry: Option<Symmetry>,
    /// `time(t), adapt = |q| g`: adaptive steps (see [`crate::ir::adapt`]).
    pub adapt: Option<LieAdapt>,
}

/// `time(t), adapt = |q| g` on rotation groups: the scalar group coordinate that is physical
/// time and the step monitor, a function of the configuration.
pub struct LieAdapt {
    /// The time coordinate as written.
    pub time: Ident,
    /// Its index in [`LieSpec::coords`].
    pub coord: usize,
    /// `|q| g(q)`.
    pub monitor: syn::ExprClosure,
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
    let mut symmetry: Option<(&Ident, &Punctuated<Expr, Token![,]>)> = None;
    let (mut time, mut adapt) = (None, None);
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
    let symmetry = symmetry.and_then(|(key, list)| parse_symmetry(cx, &coords, key, list));
    let adapt = crate::ast::attr::pair_adapt(cx, time, adapt).and_then(|(t, k, monitor)| {
        match coords.iter().position(|c| c.name == t) {
            Some(coord) if coords[coord].group => {
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
                cx.error_spanned_by(&t, crate::ast::attr::not_group_time(&t));
                None
            }
        }
    });
    Some(LieSpec {
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

/// `symmetry(R)` or `symmetry(a, b, .., axis = x | y | z)`, against the declared coordinates.
fn parse_symmetry(
    cx: &Ctxt,
    coords: &[LieCoord],
    key: &Ident,
    list: &Punctuated<Expr, Token![,]>,
) -> Option<Symmetry> {
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
                    Some(i) if coords[i].kind == Kind::Scalar => error(
                        id,
                        format!(
                            "`{id}` is a scalar coordinate; `symmetry(..)` lists rotation and \
                             direction coordinates (declare translations of a scalar with \
                             `group({id})`)"
                        ),
                    ),
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
    let kind = match axis {
        Some(k) => SymmetryKind::Axis(k),
        None => {
            if let Some((i, id)) = listed
                .iter()
                .find(|(i, _)| coords[*i].kind != Kind::Rotation)
            {
                let _ = i;
                cx.error_spanned_by(
                    id,
                    format!(
                        "every rotation of a direction leaves only the rotations about it; \
                         `symmetry(..)` without an axis acts on one rotation coordinate (`R ↦ g R`), \
                         and `{id}` is a direction: declare the rotations about a fixed axis, \
                         `symmetry({id}, axis = z)`"
                    ),
                );
                return None;
            }
            if let Some((_, id)) = listed.get(1) {
                cx.error_spanned_by(
                    id,
                    "`symmetry(..)` without an axis reduces by every rotation of one rotation \
                     coordinate; list one (rotations acting on several bodies at once are \
                     available about a fixed axis: `symmetry(R1, R2, axis = z)`)",
                );
                return None;
            }
            SymmetryKind::Rotations
        }
    };
    Some(Symmetry {
        kind,
        coords: listed,
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
