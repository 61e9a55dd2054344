//! Element-wise systems given as text: the phases of `#[reduced_lagrangian]` for a function that
//! takes `usize` sizes (the body split into families of elements with the stencils' range check,
//! each family's element lowered and differentiated), ending in each family's stencil as index
//! expressions and its kernels as straight-line [`Program`]s over the stencil's slots — what the
//! runtime's `ElementLagrangian` and `Family` need, for any sizes.

use proc_macro2::TokenStream;
use syn::ItemFn;

use crate::back::program::{program, Program};
use crate::expand::{compile_element as compile_phases, ElementCompiled};
use crate::front::element::families::FamilySpec;
use crate::front::element::index::Index;
use crate::front::element::Dim;
use crate::ir::element::{ElementCode, StepBlocks};
use crate::ir::graph::{Graph, NodeId};

/// An element-wise system compiled from text: a discrete Lagrangian that is a sum over families
/// of elements, each element reading a stencil of `S` coordinates given by index expressions in
/// the sizes and the loop indices. Every kernel reads its element's slots as `Q0`, `Q1` (`S`
/// entries each) and as parameters first [`Self::parameters`], then the sizes as numbers, then
/// the element's loop indices as numbers (`Param(P + k)` is size `k`, `Param(P + Z + d)` loop
/// index `d`, with `P` parameters and `Z` sizes).
#[derive(Clone, Debug)]
pub struct ElementSystem {
    /// The type name `#[reduced_lagrangian]` would emit.
    pub name: String,
    /// The parameters, in declaration order (the time step included).
    pub parameters: Vec<String>,
    /// The index of the time step among [`Self::parameters`].
    pub step: usize,
    /// The sizes (the function's `usize` arguments), in order.
    pub sizes: Vec<String>,
    /// The controls (`controls(..)`), as indices into [`Self::parameters`].
    pub controls: Vec<usize>,
    /// Whether the Lagrangian is a continuous `L(q, v)` (discretized by its rule).
    pub continuous: bool,
    /// The smallest value of every size for which every stencil stays inside its coordinate.
    pub min_size: usize,
    /// The coordinates, in the order of the flat configuration vector.
    pub coordinates: Vec<ElementCoordinate>,
    /// Each declared translation (`translate(..)`): the coordinates it moves together.
    pub translations: Vec<Vec<usize>>,
    /// The families of elements: the Lagrangian's, then the forces'.
    pub families: Vec<ElementFamily>,
    /// The holonomic constraints (`constraints = |q| ..`), when declared.
    pub constraints: Option<ElementConstraints>,
}

/// A coordinate of an element-wise system: a scalar, a vector or a grid, its lengths in the
/// sizes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ElementCoordinate {
    /// Its name in the text.
    pub name: String,
    /// Its lengths, one per dimension (none for a scalar).
    pub dims: Vec<Length>,
}

/// The length of one dimension of a coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Length {
    /// Size `k`.
    Size(usize),
    /// A literal length.
    Fixed(usize),
    /// A literal multiple `m` of size `k` (`x[3 * n]`).
    Scaled(usize, usize),
}

impl Length {
    /// The length for `sizes`.
    pub fn eval(self, sizes: &[i64]) -> i64 {
        match self {
            Length::Size(k) => sizes[k],
            Length::Fixed(v) => v as i64,
            Length::Scaled(k, m) => m as i64 * sizes[k],
        }
    }
}

/// An index expression of a stencil: integer code in the sizes and the element loops' indices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum IndexExpr {
    /// A literal.
    Lit(i64),
    /// The index of the `k`-th enclosing element loop (outermost first).
    Loop(usize),
    /// The `k`-th size.
    Size(usize),
    /// `a + b`.
    Add(Box<IndexExpr>, Box<IndexExpr>),
    /// `a − b`.
    Sub(Box<IndexExpr>, Box<IndexExpr>),
    /// `a · b`.
    Mul(Box<IndexExpr>, Box<IndexExpr>),
    /// `a % b`, as the emitted code computes it: `a.rem_euclid(b.max(1))`.
    Rem(Box<IndexExpr>, Box<IndexExpr>),
}

impl IndexExpr {
    /// The value at `sizes` and loop indices `loops`, as the attribute's emitted `i64` code
    /// computes it; `None` on overflow.
    pub fn eval(&self, sizes: &[i64], loops: &[i64]) -> Option<i64> {
        let two =
            |a: &IndexExpr, b: &IndexExpr| Some((a.eval(sizes, loops)?, b.eval(sizes, loops)?));
        match self {
            IndexExpr::Lit(v) => Some(*v),
            IndexExpr::Loop(k) => loops.get(*k).copied(),
            IndexExpr::Size(k) => sizes.get(*k).copied(),
            IndexExpr::Add(a, b) => two(a, b).and_then(|(a, b)| a.checked_add(b)),
            IndexExpr::Sub(a, b) => two(a, b).and_then(|(a, b)| a.checked_sub(b)),
            IndexExpr::Mul(a, b) => two(a, b).and_then(|(a, b)| a.checked_mul(b)),
            IndexExpr::Rem(a, b) => two(a, b).map(|(a, b)| a.rem_euclid(b.max(1))),
        }
    }

    fn of(index: &Index) -> IndexExpr {
        let b = |i: &Index| Box::new(IndexExpr::of(i));
        match index {
            Index::Lit(v) => IndexExpr::Lit(*v),
            Index::Loop(k) => IndexExpr::Loop(*k),
            Index::Size(k) => IndexExpr::Size(*k),
            Index::Add(x, y) => IndexExpr::Add(b(x), b(y)),
            Index::Sub(x, y) => IndexExpr::Sub(b(x), b(y)),
            Index::Mul(x, y) => IndexExpr::Mul(b(x), b(y)),
            Index::Rem(x, y) => IndexExpr::Rem(b(x), b(y)),
        }
    }
}

/// The elements of a family: nested loops over index ranges, each element reading its slots.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stencil {
    /// The loops, outermost first: `lo..hi` (exclusive), in the sizes and the outer loops'
    /// indices.
    pub loops: Vec<(IndexExpr, IndexExpr)>,
    /// The slots: each the coordinate it reads and one index per dimension of it.
    pub slots: Vec<(usize, Vec<IndexExpr>)>,
}

impl Stencil {
    fn of(family: &FamilySpec) -> Stencil {
        Stencil {
            loops: family
                .loops
                .iter()
                .map(|l| (IndexExpr::of(&l.lo), IndexExpr::of(&l.hi)))
                .collect(),
            slots: family
                .slots
                .iter()
                .map(|s| (s.coord, s.index.iter().map(IndexExpr::of).collect()))
                .collect(),
        }
    }
}

/// One family of elements and its kernels over the stencil's `S` slots.
#[derive(Clone, Debug)]
pub struct ElementFamily {
    /// Which elements, reading which coordinates.
    pub stencil: Stencil,
    /// Whether the family is one of the forces' (`force = |dq| ..`): its `d1`, `d2` are the
    /// discrete forces `f_d^{e−}`, `f_d^{e+}`, it has no value, energy or Legendre share.
    pub force: bool,
    /// `D_1 L_d^e` and `D_2 L_d^e`: `2S` outputs.
    pub d1_d2: Program,
    /// `D_1 L_d^e`, `D_2 L_d^e` and `D_1 D_2 L_d^e` (row by row): `2S + S²` outputs.
    pub d1_d2_d12: Program,
    /// The step partials: `∂d1/∂q0`, `∂d2/∂q0`, `∂d2/∂q1` (`S × S` each, row by row), then
    /// `∂d1/∂u`, `∂d2/∂u` (`S × U` each, row by row, `U` the controls).
    pub partials: Program,
    /// `L_d^e`: one output.
    pub value: Program,
    /// `E^e(q, v)` of a continuous Lagrangian (`Q0` = `q`, `Q1` = `v`): one output.
    pub energy: Option<Program>,
    /// `∂L^e/∂v` and `∂²L^e/∂v²` (row by row) of a continuous Lagrangian: `S + S²` outputs.
    pub legendre: Option<Program>,
}

/// The holonomic constraints of an element-wise system: one row per element of each family.
#[derive(Clone, Debug)]
pub struct ElementConstraints {
    /// The number of rows, in the sizes.
    pub count: IndexExpr,
    /// The families of rows.
    pub families: Vec<ConstraintFamily>,
}

/// One family of constraint rows.
#[derive(Clone, Debug)]
pub struct ConstraintFamily {
    /// Which elements, reading which coordinates.
    pub stencil: Stencil,
    /// The row each element assigns.
    pub row: IndexExpr,
    /// `φ^e(q)` and its gradient (`Q0` = `q`): `1 + S` outputs.
    pub value_gradient: Program,
}

/// The programs of one family.
fn family(code: &ElementCode, stencil: Stencil) -> ElementFamily {
    family_of(
        &code.graph,
        stencil,
        code.force,
        code.value,
        [&code.d1, &code.d2],
        &code.d12,
        &code.blocks,
        code.energy,
        code.legendre.as_ref().map(|(p, h)| (&p[..], &h[..])),
    )
}

/// The programs of one family from its nodes in `g`: `L_d^e` (`value`), `D_1 L_d^e` and
/// `D_2 L_d^e` (or a force family's `f_d^∓`), `D_1 D_2 L_d^e` (row by row), the step partials
/// and, for a continuous Lagrangian, the energy and the Legendre map with its Jacobian.
#[allow(
    clippy::too_many_arguments,
    reason = "a family's nodes, one argument each"
)]
pub(super) fn family_of(
    g: &Graph,
    stencil: Stencil,
    force: bool,
    value: NodeId,
    [d1, d2]: [&[NodeId]; 2],
    d12: &[Vec<NodeId>],
    b: &StepBlocks,
    energy: Option<NodeId>,
    legendre: Option<(&[NodeId], &[Vec<NodeId>])>,
) -> ElementFamily {
    let d1_d2: Vec<NodeId> = d1.iter().chain(d2).copied().collect();
    let all: Vec<NodeId> = d1_d2
        .iter()
        .copied()
        .chain(d12.iter().flatten().copied())
        .collect();
    let partials: Vec<NodeId> = [&b.d11, &b.d21, &b.d22, &b.u1, &b.u2]
        .into_iter()
        .flat_map(|rows| rows.iter().flatten().copied())
        .collect();
    ElementFamily {
        stencil,
        force,
        d1_d2: program(g, &d1_d2),
        d1_d2_d12: program(g, &all),
        partials: program(g, &partials),
        value: program(g, &[value]),
        energy: energy.map(|e| program(g, &[e])),
        legendre: legendre.map(|(p, h)| {
            let outputs: Vec<NodeId> = p.iter().chain(h.iter().flatten()).copied().collect();
            program(g, &outputs)
        }),
    }
}

/// The phases of `#[reduced_lagrangian]` on an element-wise system, then the programs.
pub(super) fn compile_parts(args: TokenStream, func: &ItemFn) -> syn::Result<ElementSystem> {
    let ElementCompiled {
        spec,
        families,
        codes,
        constraints,
        min_size,
    } = compile_phases(args, func)?;
    let sig = &spec.sig;
    Ok(ElementSystem {
        name: spec
            .name
            .clone()
            .unwrap_or_else(|| crate::back::items::camel_case(&func.sig.ident))
            .to_string(),
        parameters: sig.parameter_names(),
        step: sig.step_index(),
        sizes: spec.sizes.iter().map(ToString::to_string).collect(),
        controls: spec
            .controls
            .iter()
            .filter_map(|u| sig.params.iter().position(|p| p == u))
            .collect(),
        continuous: sig.continuous,
        min_size,
        coordinates: spec
            .coords
            .iter()
            .map(|c| ElementCoordinate {
                name: c.name.to_string(),
                dims: c
                    .dims
                    .iter()
                    .map(|d| match *d {
                        Dim::Size(k) => Length::Size(k),
                        Dim::Fixed(v) => Length::Fixed(v),
                        Dim::Scaled(k, m) => Length::Scaled(k, m),
                    })
                    .collect(),
            })
            .collect(),
        translations: spec.translates.clone(),
        families: families
            .iter()
            .zip(&codes)
            .map(|(f, code)| family(code, Stencil::of(f)))
            .collect(),
        constraints: constraints.map(|(split, codes)| ElementConstraints {
            count: IndexExpr::of(&split.count),
            families: split
                .families
                .iter()
                .zip(&codes)
                .map(|(f, code)| {
                    let outputs: Vec<NodeId> = std::iter::once(code.value)
                        .chain(code.gradient.iter().copied())
                        .collect();
                    ConstraintFamily {
                        stencil: Stencil::of(&f.family),
                        row: IndexExpr::of(&f.row),
                        value_gradient: program(&code.graph, &outputs),
                    }
                })
                .collect(),
        }),
    })
}
