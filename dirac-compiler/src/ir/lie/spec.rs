//! The attribute of a system on groups with its coordinates resolved to their kinds
//! ([`crate::ir::group`]): each coordinate's place in the point, the chart and the velocity, and
//! the declared symmetry checked against the kinds it lists.

use proc_macro2::Span;
use syn::Ident;

use crate::ctxt::Ctxt;
use crate::front::layout::{Component, CoordName};
use crate::front::lie::{LieAttr, Symmetry, SymmetryKind};
use crate::ir::group::{Kind, Rotated};

/// One declared coordinate, with its kind and its place in the point and the chart.
#[derive(Clone, Debug)]
pub struct LieCoord {
    pub name: Ident,
    pub kind: Kind,
    /// The first of its point entries.
    pub point: usize,
    /// The first of its chart (and momentum) entries.
    pub chart: usize,
    /// The first of its velocity symbols (a continuous Lagrangian's `v`, a force's `dq`).
    pub velocity: usize,
}

impl LieCoord {
    /// A scalar declared in `group(..)`: its translations are a symmetry.
    pub fn group(&self) -> bool {
        self.kind.translations()
    }
}

/// A system on groups: the attribute, the coordinates resolved, the symmetry checked.
pub struct LieSpec {
    /// The attribute as written.
    pub attr: LieAttr,
    /// The coordinates, in the order of the point and the chart.
    pub coords: Vec<LieCoord>,
    /// `symmetry(..)`, when it lists coordinates that its rotations can act on.
    pub symmetry: Option<Symmetry>,
}

impl LieSpec {
    /// Resolves the attribute's coordinates to their kinds and checks the declared symmetry
    /// against them (errors in `cx`, spanned at the coordinate as listed).
    pub fn resolve(cx: &Ctxt, attr: LieAttr) -> LieSpec {
        let (mut point, mut chart, mut velocity) = (0, 0, 0);
        let coords: Vec<LieCoord> = attr
            .coords
            .iter()
            .map(|c| {
                let kind = Kind::by_name(c.kind.0).expect("every coordinate key names a kind");
                let coord = LieCoord {
                    name: c.name.clone(),
                    kind,
                    point,
                    chart,
                    velocity,
                };
                point += kind.point_len();
                chart += kind.chart_len();
                velocity += kind.velocity_len();
                coord
            })
            .collect();
        let symmetry = attr
            .symmetry
            .as_ref()
            .and_then(|s| check_symmetry(cx, &coords, s));
        LieSpec {
            attr,
            coords,
            symmetry,
        }
    }

    /// Where each rotation block whose relative rotation is read (`Sym::Rel`) sits: its first
    /// point entry and its first chart entry (its Cayley coordinates are the first three of the
    /// coordinate's chart, [`crate::ir::group::Group::rotation`]).
    pub fn rotations(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.coords
            .iter()
            .filter_map(|c| c.kind.rotation().map(|at| (c.point + at, c.chart)))
    }

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

    /// The coordinates as the body reads them ([`crate::ir::group::Group::reads`]): a rotation
    /// whole (3 × 3, its point entries row by row), a direction as the third column of its
    /// frame, a pose as its parts, a scalar as one entry; the velocity argument of a continuous
    /// Lagrangian and a force's virtual displacement each from their own symbols.
    pub fn lowering_coords(&self) -> Vec<CoordName> {
        self.coords
            .iter()
            .map(|c| {
                let velocity = c.kind.reads_velocity(c.velocity);
                CoordName {
                    name: c.name.to_string(),
                    len: None,
                    components: vec![Component::Var(c.point)],
                    matrix: c.kind.reads(c.point),
                    velocity: self.attr.rule.is_some().then(|| velocity.clone()),
                    displacement: Some(velocity),
                }
            })
            .collect()
    }

    /// The runtime's constant for the kind of coordinate `c`: `CoordinateKind::ROTATION` for
    /// `rotation`, `SHAPE` for `shape`, ... (its name in capitals).
    pub fn kind_path(c: &LieCoord) -> Ident {
        Ident::new(&c.kind.name().to_uppercase(), Span::call_site())
    }
}

/// The declared symmetry, if every listed coordinate's kind admits it
/// ([`crate::ir::group::Group::rotated`]).
fn check_symmetry(
    cx: &Ctxt,
    coords: &[LieCoord],
    decl: &crate::front::lie::SymmetryDecl,
) -> Option<Symmetry> {
    let mut failed = false;
    for (i, id) in &decl.coords {
        if let Rotated::Refused(why) = coords[*i].kind.rotated() {
            cx.error_spanned_by(id, why(id));
            failed = true;
        }
    }
    if failed {
        return None;
    }
    // A pose is reduced by every rigid motion, alone and without an axis.
    let rigid = decl
        .coords
        .iter()
        .find_map(|(i, id)| match coords[*i].kind.rotated() {
            Rotated::Rigid(why) => Some((id, why)),
            _ => None,
        });
    if let Some((id, why)) = rigid {
        if decl.axis.is_some() || decl.coords.len() > 1 {
            cx.error_spanned_by(id, why(id));
            return None;
        }
        return Some(Symmetry {
            kind: SymmetryKind::RigidMotions,
            coords: decl.coords.clone(),
        });
    }
    let kind = match decl.axis {
        Some(k) => SymmetryKind::Axis(k),
        None => {
            for (i, id) in &decl.coords {
                if let Rotated::AboutAxis(why) = coords[*i].kind.rotated() {
                    cx.error_spanned_by(id, why(id));
                    return None;
                }
            }
            if let Some((_, id)) = decl.coords.get(1) {
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
        coords: decl.coords.clone(),
    })
}
