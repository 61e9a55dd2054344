//! The kinds of coordinate of a system on groups, as data: each is one implementation of
//! [`Group`] — its point, chart and velocity, the chart `φ_q(ξ)` on the graph, how a force and a
//! momentum enter its chart, how the body reads it, what the symmetry checks move, and the
//! fields of the emitted types — in its own file, so that a new group is a new file and one line
//! of [`KINDS`] (manif's `LieGroupBase`, symbolically; the runtime's `CoordinateKind` is the
//! same list, numerically, and resolves [`Group::name`]).
//!
//! | kind | point `P` | chart `N` | velocity | `φ_q(ξ)` |
//! |------|-----------|-----------|----------|----------|
//! | `shape`, `group` ([`scalar`]) | `x` (1) | 1 | `ẋ` | `x + ξ` |
//! | `rotation` ([`rotation`]) | `R` row by row (9) | 3 | body `Ω` | `R cay(ξ)` |
//! | `direction` ([`direction`]) | its frame `[e1 e2 n]` (9) | 2 | `ṅ` | the sphere's retraction |
//! | `pose` ([`pose`]) | `R` (9), then `x` (3) | 6 | body `Ω`, spatial `ẋ` | `(R cay(ξ), x + v)` |
//!
//! Every chart is centred (`φ_q(0) = q`) and inverse by sign (`φ_{φ_q(z)}(−z) = q`), which the
//! (−) step relies on.

use std::fmt::Debug;
use std::ops::Deref;

use proc_macro2::TokenStream;
use syn::Ident;

use crate::front::layout::Reading;
use crate::ir::graph::{Graph, NodeId};
use crate::symbol::Symbol;

mod direction;
mod pose;
mod rotation;
mod scalar;

pub use rotation::{cayley, cayley_value, product};

/// Every kind, the one registration list: a new group is its file and a line here.
pub const KINDS: [Kind; 5] = [
    Kind(&scalar::SHAPE),
    Kind(&scalar::GROUP),
    Kind(&rotation::Rotation),
    Kind(&direction::Direction),
    Kind(&pose::Pose),
];

/// What a coordinate of a system on groups is: a handle on its kind's implementation, compared
/// by name (the runtime's `CoordinateKind` is the same list, numerically).
#[derive(Clone, Copy)]
pub struct Kind(&'static dyn Group);

impl Kind {
    /// The kind an attribute key declares (`shape`, `group`, `rotation`, `direction`, `pose`),
    /// the name the runtime's `CoordinateKind::by_name` resolves too.
    pub fn by_name(name: &str) -> Option<Kind> {
        KINDS.into_iter().find(|k| k.name() == name)
    }
}

/// The kind's implementation: `kind.name()` (the attribute key that declares it, which the
/// runtime's `CoordinateKind::by_name` resolves), `point_len()`, `chart_len()`, `velocity_len()`
/// and the rest of the group's `Group` implementation, read through the handle.
impl Deref for Kind {
    type Target = dyn Group;

    fn deref(&self) -> &Self::Target {
        self.0
    }
}

impl PartialEq for Kind {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Kind {}

impl std::hash::Hash for Kind {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.name().hash(state);
    }
}

impl Debug for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a `symmetry(..)` may do with a coordinate of this kind.
#[derive(Clone, Copy, Debug)]
pub enum Rotated {
    /// Every rotation `g` acts on it (`symmetry(R)`, `SO(3)`), and so do the rotations about a
    /// fixed axis.
    Every,
    /// Only the rotations about a fixed axis (`symmetry(n, axis = z)`): the message for
    /// `symmetry(n)` without an axis, given the name as written.
    AboutAxis(fn(&Ident) -> String),
    /// Every rigid motion `(A, a)·(R, x) = (A R, A x + a)` (`symmetry(X)` of a pose, `SE(3)`):
    /// the message for listing it with an axis, given the name as written.
    Rigid(fn(&Ident) -> String),
    /// None: the message for listing it, given the name as written.
    Refused(fn(&Ident) -> String),
}

/// The nalgebra and runtime paths the emitted code names.
pub struct Paths {
    /// `::dirac::nalgebra`.
    pub na: TokenStream,
    /// `::dirac::runtime`.
    pub rt: TokenStream,
}

/// A kind as data: its attribute key, the sizes of its blocks (manif's `RepSize` and `DoF`, and
/// the velocity a continuous Lagrangian reads) and the facts about it that the reduction and the
/// checks read ([`Group::translations`], [`Group::rotation`], [`Group::spatial`]).
#[derive(Clone, Copy, Debug)]
pub struct KindSpec {
    name: &'static str,
    point: usize,
    chart: usize,
    velocity: usize,
    translations: bool,
    rotation: Option<usize>,
    spatial: &'static [usize],
}

impl KindSpec {
    /// The kind declared by `key`, with `point` entries of its stored point, `chart` of its
    /// chart (and momentum) and `velocity` of its velocity; no declared translations, no
    /// rotation matrix, no spatial vectors.
    pub const fn new(key: Symbol, point: usize, chart: usize, velocity: usize) -> KindSpec {
        KindSpec {
            name: key.0,
            point,
            chart,
            velocity,
            translations: false,
            rotation: None,
            spatial: &[],
        }
    }

    /// Its translations are a declared symmetry ([`Group::translations`]).
    pub const fn translations(self) -> KindSpec {
        KindSpec {
            translations: true,
            ..self
        }
    }

    /// A rotation matrix stands at `at` in its point ([`Group::rotation`]).
    pub const fn rotation_at(self, at: usize) -> KindSpec {
        KindSpec {
            rotation: Some(at),
            ..self
        }
    }

    /// 3-vectors in space stand at `at` among its velocity components ([`Group::spatial`]).
    pub const fn spatial_at(self, at: &'static [usize]) -> KindSpec {
        KindSpec {
            spatial: at,
            ..self
        }
    }
}

/// One coordinate's step from `q0` to `q1` (their points, this coordinate's blocks), as its
/// velocity reads it: `rel` the relative rotation's 9 symbols where [`Group::rotation`] is some
/// (else empty), `inv_h = 1/h`.
pub struct Step<'a> {
    /// The point at the start of the step.
    pub q0: &'a [NodeId],
    /// The point at its end.
    pub q1: &'a [NodeId],
    /// The relative rotation `R0ᵀ R1`'s 9 symbols, row by row (empty without a rotation).
    pub rel: &'a [NodeId],
    /// `1/h`.
    pub inv_h: NodeId,
}

impl Step<'_> {
    /// The chord velocity `(q1 − q0)/h` of the point's `entries` (a scalar's `ẋ`, a direction's
    /// `ṅ`, a pose's spatial `ẋ`). In a step, where `q1` is the chart's `x + v` at the centre
    /// `x`, the graph takes `q1 − q0` as the increment `v` itself ([`Graph::sub`]), not `v`
    /// rounded at `|x|`.
    pub fn chord(&self, g: &mut Graph, entries: impl IntoIterator<Item = usize>) -> Vec<NodeId> {
        entries
            .into_iter()
            .map(|i| {
                let d = g.sub(self.q1[i], self.q0[i]);
                g.mul(d, self.inv_h)
            })
            .collect()
    }
}

/// One kind of coordinate of a system on groups, symbolically: a manifold `Q_i` with a stored
/// point of [`Self::point_len`] entries, a centred chart `φ_q : ℝ^N → Q_i` of
/// [`Self::chart_len`] entries in which momenta and forces are covectors, and the velocity a
/// continuous Lagrangian reads ([`Self::velocity_len`] entries, the same components as a
/// virtual displacement). Offsets into a system's vectors are the caller's: every slice a method
/// takes or returns is this coordinate's own block.
pub trait Group: Sync {
    /// Its name, sizes and the facts the reduction and the checks read, as data.
    fn spec(&self) -> &KindSpec;

    /// The attribute key that declares it, the runtime's name of the kind.
    fn name(&self) -> &'static str {
        self.spec().name
    }

    /// Entries of the stored point.
    fn point_len(&self) -> usize {
        self.spec().point
    }

    /// Entries of the chart and of the momentum.
    fn chart_len(&self) -> usize {
        self.spec().chart
    }

    /// Entries of the velocity a continuous Lagrangian reads, and of a virtual displacement.
    fn velocity_len(&self) -> usize {
        self.spec().velocity
    }

    /// Whether its translations are a declared symmetry (`group(x)`): its momentum is then the
    /// explicit discrete Noether balance, and `L_d` is checked invariant.
    fn translations(&self) -> bool {
        self.spec().translations
    }

    /// The offset in its point of a rotation matrix (row by row) whose relative rotation
    /// `R0ᵀ R1` the body and the velocity read as the symbols `Rel` (so that a step substitutes
    /// `cay(ξ)ᵀ cay(z)` for it, with no round-off from the stored matrices).
    fn rotation(&self) -> Option<usize> {
        self.spec().rotation
    }

    /// How the body reads a configuration's coordinate whole, its point's entries from `point`;
    /// `None` for a scalar (read as one entry, `q0.x`).
    fn reads(&self, point: usize) -> Option<Reading>;

    /// How the body reads a velocity or a virtual displacement of it, its components from
    /// `velocity`.
    fn reads_velocity(&self, velocity: usize) -> Reading;

    /// `φ_q(ξ)`: the point at chart coordinates `xi` (`N` nodes) of the chart centred at `base`
    /// (`P` nodes).
    fn chart(&self, g: &mut Graph, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId>;

    /// The velocity over the step `step`.
    fn velocity(&self, g: &mut Graph, step: &Step) -> Vec<NodeId>;

    /// A covector in velocity components (a force `∂W/∂δq`, a momentum `∂L/∂v`) as a covector
    /// of the chart at `point`: its pull-back by `dφ_point(0)`. By default the components as
    /// they are, for the kinds whose `dφ(0)` is the identity on velocity components (`x + ξ`;
    /// `R cay(ξ)` with `dφ_R(0) η = R η̂` and the velocity `η` itself; a pose's `(R η̂, ζ)`).
    fn covector(&self, _g: &mut Graph, f: &[NodeId], _point: &[NodeId]) -> Vec<NodeId> {
        f.to_vec()
    }

    /// What a declared `symmetry(..)` may do with it.
    fn rotated(&self) -> Rotated;

    /// A sample point `(q0, q1)` for the compile-time checks, varying with the sample `t` and
    /// the offset `at` (so that coordinates differ); a rotation among it consistent with its
    /// [`Self::rotation`] offset.
    fn sample(&self, t: f64, at: usize) -> [Vec<f64>; 2];

    /// The point moved by the rotation `g` about the origin (what `symmetry(..)` does).
    fn rotate(&self, g: &[[f64; 3]; 3], point: &mut [f64]);

    /// The offsets among its velocity components of 3-vectors in space, which a rotation of the
    /// configuration turns (a force on them turns with it); body-frame components do not.
    fn spatial(&self) -> &'static [usize] {
        self.spec().spatial
    }

    /// The field of `<Name>Config` named `name`: its type and documentation (`ty` the system's
    /// type name, for the types [`Self::items`] emits).
    fn config_field(&self, paths: &Paths, name: &Ident, ty: &Ident) -> (TokenStream, String);

    /// The field's value read from the point `q` (its block from `at`).
    fn read_point(&self, paths: &Paths, ty: &Ident, at: usize) -> TokenStream;

    /// Statements writing `self.name` into the point `q` (its block from `at`).
    fn write_point(&self, paths: &Paths, name: &Ident, at: usize) -> TokenStream;

    /// The field of `<Name>Momentum` named `name`: its type and documentation.
    fn momentum_field(&self, paths: &Paths, name: &Ident, ty: &Ident) -> (TokenStream, String);

    /// The momentum read from the chart momentum `p` at the point `q` (blocks from `ch`, `at`).
    fn read_chart(&self, paths: &Paths, ty: &Ident, at: usize, ch: usize) -> TokenStream;

    /// Statements writing `self.name` into the chart momentum `p` at the point `q`.
    fn write_chart(&self, paths: &Paths, name: &Ident, at: usize, ch: usize) -> TokenStream;

    /// The field of `<Name>Velocity` named `name`: its type and documentation.
    fn velocity_field(&self, paths: &Paths, name: &Ident, ty: &Ident) -> (TokenStream, String);

    /// The velocity components of the field `v` (an expression of the field's type), in order.
    fn velocity_entries(&self, v: &TokenStream) -> Vec<TokenStream>;

    /// Types the fields name, emitted once per system that has the kind (`continuous`: a
    /// velocity type too).
    fn items(
        &self,
        _paths: &Paths,
        _ty: &Ident,
        _vis: &syn::Visibility,
        _continuous: bool,
    ) -> TokenStream {
        TokenStream::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::graph::Sym;

    /// Each kind's sample point `q0` (a rotation or frame from `cay`, a pose's position) and a
    /// chart coordinate `z` of modest size.
    fn point_and_z(kind: Kind) -> (Vec<f64>, Vec<f64>) {
        let q = kind.sample(0.7, 3)[0].clone();
        let z = (0..kind.chart_len())
            .map(|j| 0.3 - 0.17 * j as f64)
            .collect();
        (q, z)
    }

    /// `φ_q(0) = q` and `φ_{φ_q(z)}(−z) = q` (to round-off) for every kind: the (−) step inverts
    /// a chart by a sign (`cay(−ξ) = cay(ξ)ᵀ`, the sphere's `M(−w) = M(w)ᵀ`, translations).
    #[test]
    fn every_chart_is_centred_and_inverse_by_sign() {
        for kind in KINDS {
            let (q, z) = point_and_z(kind);
            let mut g = Graph::default();
            let base: Vec<NodeId> = (0..kind.point_len()).map(|i| g.var(Sym::Base(i))).collect();
            let xi: Vec<NodeId> = (0..kind.chart_len())
                .map(|j| g.var(Sym::Chart1(j)))
                .collect();
            let zero = vec![g.constant(0.0); kind.chart_len()];
            let centre = kind.chart(&mut g, &base, &zero);
            let next = kind.chart(&mut g, &base, &xi);
            let minus: Vec<NodeId> = xi.iter().map(|&x| g.neg(x)).collect();
            let back = kind.chart(&mut g, &next, &minus);
            let value = |sym: Sym| match sym {
                Sym::Base(i) => q[i],
                Sym::Chart1(j) => z[j],
                _ => unreachable!(),
            };
            let (c, b) = (g.eval(&centre, &value), g.eval(&back, &value));
            let moved = g.eval(&next, &value);
            for i in 0..q.len() {
                assert!((c[i] - q[i]).abs() < 1e-15, "{kind:?}: φ_q(0) ≠ q at {i}");
                assert!(
                    (b[i] - q[i]).abs() < 1e-14,
                    "{kind:?}: φ_φ(z)(−z) ≠ q at {i}"
                );
            }
            assert!(
                moved.iter().zip(&q).any(|(m, q)| (m - q).abs() > 0.1),
                "{kind:?}: φ_q(z) did not move"
            );
        }
    }

    /// The velocity over a step to `φ_q(h w)` is `w` for the kinds whose velocity is their chart
    /// velocity (scalars `x + hw`, a rotation's `Ω = cay⁻¹(R0ᵀ R1)/h`, a pose's `(Ω, ẋ)`), with
    /// the relative rotation formed from the two points as the body reads it.
    #[test]
    fn the_velocity_of_a_chart_step_is_its_chart_velocity() {
        let h = 0.05;
        for kind in KINDS
            .into_iter()
            .filter(|k| k.velocity_len() == k.chart_len())
        {
            let (q, w) = point_and_z(kind);
            let mut g = Graph::default();
            let q0: Vec<NodeId> = q.iter().map(|&v| g.constant(v)).collect();
            let hw: Vec<NodeId> = w.iter().map(|&v| g.constant(h * v)).collect();
            let q1 = kind.chart(&mut g, &q0, &hw);
            let rel: Vec<NodeId> = match kind.rotation() {
                Some(at) => (0..9)
                    .map(|e| {
                        let (i, j) = (e / 3, e % 3);
                        let (a, b): (Vec<NodeId>, Vec<NodeId>) = (0..3)
                            .map(|k| (q0[at + 3 * k + i], q1[at + 3 * k + j]))
                            .unzip();
                        let terms: Vec<NodeId> =
                            a.iter().zip(&b).map(|(&x, &y)| g.mul(x, y)).collect();
                        let s = g.add(terms[0], terms[1]);
                        g.add(s, terms[2])
                    })
                    .collect(),
                None => Vec::new(),
            };
            let inv_h = g.constant(1.0 / h);
            let step = Step {
                q0: &q0,
                q1: &q1,
                rel: &rel,
                inv_h,
            };
            let v = kind.velocity(&mut g, &step);
            let v = g.eval(&v, &|_| unreachable!("constants only"));
            for (got, want) in v.iter().zip(&w) {
                assert!((got - want).abs() < 1e-12, "{kind:?}: {got} ≠ {want}");
            }
        }
    }

    /// Every kind is found by its name, and the names are the attribute keys.
    #[test]
    fn kinds_are_found_by_their_keys() {
        let keys = [
            crate::symbol::SHAPE,
            crate::symbol::GROUP,
            crate::symbol::ROTATION,
            crate::symbol::DIRECTION,
            crate::symbol::POSE,
        ];
        for key in keys {
            assert_eq!(Kind::by_name(key.0).map(|k| k.name()), Some(key.0));
        }
        assert!(Kind::by_name("translation").is_none());
        let pose = Kind::by_name("pose").unwrap();
        assert_eq!(
            (pose.point_len(), pose.chart_len(), pose.velocity_len()),
            (12, 6, 6)
        );
    }
}
