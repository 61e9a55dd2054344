//! One element of each family of an element-wise system, lowered and differentiated as a
//! fixed-size system over its stencil's slots: the element's discrete Lagrangian `L_d^e(q0, q1)`
//! (formed by the rule from a continuous `L^e(q, v)`), `D_1 L_d^e`, `D_1 D_2 L_d^e` (one forward
//! pass per column over `D_1 L_d^e`), `D_2 L_d^e` and, for a continuous Lagrangian, the element
//! energy `E^e = ⟨∂L^e/∂v, v⟩ − L^e`. The whole system's step (`dirac::runtime::element`) is the
//! sum over elements: `R = p_k + Σ_e D_1 L_d^e`, `∂R/∂q_{k+1} = Σ_e D_1 D_2 L_d^e`,
//! `p_{k+1} = Σ_e D_2 L_d^e`.

use crate::ast::element::families::{loop_param, size_param, slot_name, FamilySpec};
use crate::ast::element::ElementSpec;
use crate::ast::layout::CoordName;
use crate::ctxt::Ctxt;
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
        let step = spec
            .sig
            .params
            .iter()
            .position(|p| *p == spec.sig.step)
            .expect("the time step is a parameter");
        let h = g.var(Sym::Param(step));
        let rule = spec.rule.expect("a continuous Lagrangian has a rule");
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
    // The element must be invariant under each declared translation (slots of one coordinate
    // move together).
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
        crate::ir::check::element_invariance(cx, g, ld, &translation_of, &names, &at);
    }
    Some(ElementCode {
        graph,
        width,
        value: ld,
        d1,
        d12,
        d2,
        energy,
        legendre,
    })
}
