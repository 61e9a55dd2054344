//! One element of each family of an element-wise system, lowered and differentiated as a
//! fixed-size system over its stencil's slots: the element's discrete Lagrangian `L_d^e(q0, q1)`
//! (formed by the rule from a continuous `L^e(q, v)`), `D_1 L_d^e`, `D_1 D_2 L_d^e` (one forward
//! pass per column over `D_1 L_d^e`), `D_2 L_d^e` and, for a continuous Lagrangian, the element
//! energy `E^e = ⟨∂L^e/∂v, v⟩ − L^e`. The whole system's step (`dirac::runtime::element`) is the
//! sum over elements: `R = p_k + Σ_e D_1 L_d^e`, `∂R/∂q_{k+1} = Σ_e D_1 D_2 L_d^e`,
//! `p_{k+1} = Σ_e D_2 L_d^e`.

use crate::ctxt::Ctxt;
use crate::front::element::families::{loop_param, size_param, slot_name, FamilySpec};
use crate::front::element::ElementSpec;
use crate::front::layout::CoordName;
use crate::ir::compile::mode_for;
use crate::ir::diff::derivatives;
use crate::ir::discretize::{continuous, discretize};
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};
use crate::ir::reduce::{firsts, Mode};

/// One family's element, differentiated.
pub struct ElementCode {
    pub graph: Graph,
    /// Stencil width `S`.
    pub width: usize,
    /// `L_d^e`.
    pub value: NodeId,
    /// `D_1 L_d^e`.
    pub d1: Vec<NodeId>,
    /// `D_1 D_2 L_d^e`, row `a`: `∂(D_1 L_d^e)_a / ∂q1_b`.
    pub d12: Vec<Vec<NodeId>>,
    /// `D_2 L_d^e`.
    pub d2: Vec<NodeId>,
    /// `E^e(q, v)` (over `Q0 = q`, `Q1 = v`) of a continuous Lagrangian.
    pub energy: Option<NodeId>,
    /// `∂L^e/∂v` and `∂²L^e/∂v²` (row `a`), over `Q0 = q`, `Q1 = v`, of a continuous
    /// Lagrangian: the element's share of the Legendre map and its Jacobian.
    pub legendre: Option<(Vec<NodeId>, Vec<Vec<NodeId>>)>,
    /// Whether this is an element of the forces ([`force_element`]).
    pub force: bool,
    /// The step partials a sensitivity needs ([`StepBlocks`]).
    pub blocks: StepBlocks,
}

/// The partial derivatives of an element's share of the step that its sensitivity needs (the
/// implicit-function theorem on `R = p_k + Σ_e d1^e`, `p_{k+1} = Σ_e d2^e`, with `d1^e`, `d2^e`
/// the element's `D_1 L_d^e`, `D_2 L_d^e` or discrete forces), row `a`, column `b`.
pub struct StepBlocks {
    /// `∂d1^e_a / ∂q0_b`.
    pub d11: Vec<Vec<NodeId>>,
    /// `∂d2^e_a / ∂q0_b`.
    pub d21: Vec<Vec<NodeId>>,
    /// `∂d2^e_a / ∂q1_b`.
    pub d22: Vec<Vec<NodeId>>,
    /// `∂d1^e_a / ∂u_c`, one column per control.
    pub u1: Vec<Vec<NodeId>>,
    /// `∂d2^e_a / ∂u_c`.
    pub u2: Vec<Vec<NodeId>>,
}

/// `∂rows_a / ∂vars_b`, row by row (one forward pass per variable).
fn jacobian(g: &mut Graph, rows: &[NodeId], vars: &[Sym]) -> Vec<Vec<NodeId>> {
    let columns: Vec<Vec<NodeId>> = vars.iter().map(|&v| derivatives(g, rows, v)).collect();
    (0..rows.len())
        .map(|a| columns.iter().map(|c| c[a]).collect())
        .collect()
}

/// The [`StepBlocks`] of an element whose step shares are `d1`, `d2`.
fn step_blocks(
    g: &mut Graph,
    spec: &ElementSpec,
    width: usize,
    d1: &[NodeId],
    d2: &[NodeId],
) -> StepBlocks {
    let controls: Vec<usize> = spec
        .controls
        .iter()
        .map(|c| {
            spec.sig
                .params
                .iter()
                .position(|p| p == c)
                .expect("a control is a parameter (checked when parsed)")
        })
        .collect();
    step_blocks_of(g, width, &controls, d1, d2)
}

/// The [`StepBlocks`] of an element of `width` slots whose step shares are `d1`, `d2`, with the
/// controls the parameters `controls` (their indices).
pub fn step_blocks_of(
    g: &mut Graph,
    width: usize,
    controls: &[usize],
    d1: &[NodeId],
    d2: &[NodeId],
) -> StepBlocks {
    let q0: Vec<Sym> = (0..width).map(Sym::Q0).collect();
    let q1: Vec<Sym> = (0..width).map(Sym::Q1).collect();
    let controls: Vec<Sym> = controls.iter().map(|&i| Sym::Param(i)).collect();
    StepBlocks {
        d11: jacobian(g, d1, &q0),
        d21: jacobian(g, d2, &q0),
        d22: jacobian(g, d2, &q1),
        u1: jacobian(g, d1, &controls),
        u2: jacobian(g, d2, &controls),
    }
}

/// The names of the parameters an element body reads: the function's, then the sizes and the
/// loop indices as f64 (`depth` of them).
pub fn param_names(spec: &ElementSpec, depth: usize) -> Vec<String> {
    spec.sig
        .params
        .iter()
        .map(|p| p.to_string())
        .chain((0..spec.sizes.len()).map(|k| size_param(k).to_string()))
        .chain((0..depth).map(|k| loop_param(k).to_string()))
        .collect()
}

/// The time step (a parameter) and the rule of a continuous Lagrangian.
fn step_and_rule(g: &mut Graph, spec: &ElementSpec) -> (NodeId, crate::front::rule::Rule) {
    let step = spec.sig.step_index();
    let h = g.var(Sym::Param(step));
    (h, spec.rule.expect("a continuous Lagrangian has a rule"))
}

/// Checks that `value`, an element's function of its slots, is invariant under each declared
/// translation (slots of one coordinate move together); errors at the family's loop.
fn check_invariance(
    cx: &Ctxt,
    g: &Graph,
    spec: &ElementSpec,
    family: &FamilySpec,
    value: NodeId,
    what: &str,
) {
    let translation_of: Vec<Option<usize>> = family
        .slots
        .iter()
        .map(|slot| spec.translates.iter().position(|t| t.contains(&slot.coord)))
        .collect();
    let names: Vec<String> = spec
        .translates
        .iter()
        .map(|t| {
            t.iter()
                .map(|&c| spec.coords[c].name.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        })
        .collect();
    let at = family
        .loops
        .last()
        .map(|l| l.tokens.clone())
        .or_else(|| family.slots.first().map(|s| s.tokens.clone()));
    if let Some(at) = at {
        crate::ir::check::element_invariance(cx, g, value, &translation_of, &names, &at, what);
    }
}

/// One family of constraint rows, differentiated: `φ^e` and `∂φ^e/∂q` over its stencil's slots
/// (read as `Q0`).
pub struct ConstraintCode {
    pub graph: Graph,
    pub width: usize,
    pub value: NodeId,
    pub gradient: Vec<NodeId>,
}

/// Lowers and differentiates one family of constraint rows, and checks its invariance under
/// the declared translations (the momentum map is kept only for invariant constraints: their
/// forces `Dφᵀ λ` have no component along a translation); `None` after errors (recorded).
pub fn constraint_element(
    cx: &Ctxt,
    spec: &ElementSpec,
    family: &FamilySpec,
    depth: usize,
    config: &syn::Ident,
) -> Option<ConstraintCode> {
    let width = family.slots.len();
    let unused = syn::Ident::new("__no_velocity", proc_macro2::Span::call_site());
    let names = Names {
        q0: config,
        q1: &unused,
        coords: CoordName::scalars((0..width).map(slot_name)),
        params: param_names(spec, depth),
        dq: Vec::new(),
    };
    let mut graph = Graph::default();
    let value = Lowering::new(&mut graph, cx, &names).body(&family.block)?;
    let q: Vec<Sym> = (0..width).map(Sym::Q0).collect();
    let gradient = firsts(&mut graph, mode_for(width), value, &q);
    check_invariance(cx, &graph, spec, family, value, "constraint φ");
    Some(ConstraintCode {
        graph,
        width,
        value,
        gradient,
    })
}

/// Lowers and differentiates one family's element; `None` after errors (recorded).
pub fn element(
    cx: &Ctxt,
    spec: &ElementSpec,
    family: &FamilySpec,
    depth: usize,
) -> Option<ElementCode> {
    let width = family.slots.len();
    let names = Names {
        q0: &spec.sig.q0,
        q1: &spec.sig.q1,
        coords: CoordName::scalars((0..width).map(slot_name)),
        params: param_names(spec, depth),
        dq: Vec::new(),
    };
    let mut graph = Graph::default();
    let body = Lowering::new(&mut graph, cx, &names).body(&family.block)?;
    let g = &mut graph;
    let (ld, energy, legendre) = if spec.sig.continuous {
        let (h, rule) = step_and_rule(g, spec);
        let c = continuous(g, body, width, rule, Mode::Forward);
        (
            discretize(g, body, width, h, rule),
            Some(c.energy),
            Some((c.legendre, c.hessian)),
        )
    } else {
        (body, None, None)
    };
    let mode = mode_for(width);
    let q0: Vec<Sym> = (0..width).map(Sym::Q0).collect();
    let q1: Vec<Sym> = (0..width).map(Sym::Q1).collect();
    let d1 = firsts(g, mode, ld, &q0);
    let columns: Vec<Vec<NodeId>> = (0..width)
        .map(|b| derivatives(g, &d1, Sym::Q1(b)))
        .collect();
    let d12 = (0..width)
        .map(|a| (0..width).map(|b| columns[b][a]).collect())
        .collect();
    let d2 = firsts(g, mode, ld, &q1);
    // The element must be invariant under each declared translation.
    check_invariance(cx, g, spec, family, ld, "L_d");
    let blocks = step_blocks(g, spec, width, &d1, &d2);
    Some(ElementCode {
        graph,
        width,
        value: ld,
        d1,
        d12,
        d2,
        energy,
        legendre,
        force: false,
        blocks,
    })
}

/// One family's element of the forces `force = |dq| W` (`W = Σ_e W^e`, each `W^e` linear in the
/// displacements of its stencil), as an element the assembly sums like the Lagrangian's: its
/// discrete forces in the places of `D_1 L_d^e` and `D_2 L_d^e` — the forced step is
/// `R = p_k + Σ_e (D_1 L_d^e + f_d^{e−})`, `p_{k+1} = Σ_e (D_2 L_d^e + f_d^{e+})` — with
/// `∂f_d^{e−}/∂q_{k+1}` in the place of `D_1 D_2 L_d^e`, no value, no energy and no share of
/// the Legendre map. A continuous `F^e(q, v)` is formed into `f_d^{e±}` by the rule, as for
/// fixed sizes ([`crate::ir::force`]). `None` after errors (recorded).
pub fn force_element(
    cx: &Ctxt,
    spec: &ElementSpec,
    family: &FamilySpec,
    depth: usize,
    closure: &syn::ExprClosure,
) -> Option<ElementCode> {
    let width = family.slots.len();
    let expected = if spec.sig.continuous { 1 } else { 2 };
    let dq = crate::ir::force::closure_args(cx, closure, expected)?;
    let names = Names {
        q0: &spec.sig.q0,
        q1: &spec.sig.q1,
        coords: CoordName::scalars((0..width).map(slot_name)),
        params: param_names(spec, depth),
        dq,
    };
    let mut graph = Graph::default();
    let w = Lowering::new(&mut graph, cx, &names).body(&family.block)?;
    let g = &mut graph;
    let parts = crate::ir::force::parts_of(cx, g, w, width, expected, &closure.body)?;
    let forces = if spec.sig.continuous {
        let (h, rule) = step_and_rule(g, spec);
        crate::ir::force::discretize(g, &parts[0], width, h, rule)
    } else {
        crate::ir::force::Forces {
            minus: parts[0].clone(),
            plus: parts[1].clone(),
        }
    };
    let columns: Vec<Vec<NodeId>> = (0..width)
        .map(|b| derivatives(g, &forces.minus, Sym::Q1(b)))
        .collect();
    let d12 = (0..width)
        .map(|a| (0..width).map(|b| columns[b][a]).collect())
        .collect();
    let blocks = step_blocks(g, spec, width, &forces.minus, &forces.plus);
    let zero = g.constant(0.0);
    let continuous = spec.sig.continuous;
    Some(ElementCode {
        graph,
        width,
        value: zero,
        d1: forces.minus,
        d12,
        d2: forces.plus,
        energy: continuous.then_some(zero),
        legendre: continuous.then(|| (vec![zero; width], vec![vec![zero; width]; width])),
        force: true,
        blocks,
    })
}
