//! `#[chart_transition]`'s middle: the body lowered to the new coordinates `φ(q)`, the columns
//! of `Dφ` by forward-mode differentiation, and the equivariance check on them.
//!
//! Both charts must trivialize the same symmetry by translation, so `φ` must be equivariant:
//! `φ(x, g + a) = φ(x, g) + (0, a)`, i.e. `x_to = ψ(x_from)` and `g_to = g_from + c(x_from)`.
//! This is checked symbolically on the derivative graph: `∂x_to/∂g_from` must fold to 0 and
//! `∂g_to/∂g_from` to the identity. A transition that fails the check is a compile error.

use proc_macro2::Span;
use syn::{Ident, ItemFn};

use crate::ctxt::Ctxt;
use crate::front::layout::CoordName;
use crate::front::transition::TransitionSpec;
use crate::ir::diff::derivatives;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};

/// A lowered transition: `φ` and the columns of `Dφ`.
pub struct Transition {
    /// The graph of both.
    pub graph: Graph,
    /// `φ(q)`: the new coordinates, shape then group.
    pub phi: Vec<NodeId>,
    /// `Dφ` by columns: `columns[j][i] = ∂φ_i/∂q_j`.
    pub columns: Vec<Vec<NodeId>>,
}

/// Lowers and differentiates the body; `None` after errors, all recorded in `cx`.
pub fn lower(cx: &Ctxt, spec: &TransitionSpec, q: &Ident, func: &ItemFn) -> Option<Transition> {
    let n = spec.from.shape.len() + spec.from.group.len();
    // The body reads `q.name` as a coordinate of `q0`; the `q1` slot is a name no body can use.
    let unused = Ident::new("__dirac_no_second_configuration", Span::call_site());
    let names = Names {
        q0: q,
        q1: &unused,
        coords: CoordName::scalars(
            spec.from
                .shape
                .iter()
                .chain(&spec.from.group)
                .map(Ident::to_string),
        ),
        params: Vec::new(),
        dq: Vec::new(),
    };
    let mut graph = Graph::default();
    let phi = Lowering::new(&mut graph, cx, &names).body_tuple(&func.block, n)?;
    // Dφ by columns: one forward pass per coordinate of the old chart.
    let columns: Vec<Vec<NodeId>> = (0..n)
        .map(|j| derivatives(&mut graph, &phi, Sym::Q0(j)))
        .collect();
    Some(Transition {
        graph,
        phi,
        columns,
    })
}

/// `∂x_to/∂g_from = 0` and `∂g_to/∂g_from = I`, structurally (after folding); every violation is
/// recorded in `cx`.
pub fn check_equivariance(cx: &Ctxt, spec: &TransitionSpec, t: &Transition, func: &ItemFn) {
    let (graph, columns) = (&t.graph, &t.columns);
    let s = spec.from.shape.len();
    let to: Vec<&Ident> = spec.to.shape.iter().chain(&spec.to.group).collect();
    for (jg, g_from) in spec.from.group.iter().enumerate() {
        for (i, to_name) in to.iter().enumerate() {
            let expected = if i == s + jg { 1.0 } else { 0.0 };
            if graph.as_const(columns[s + jg][i]) != Some(expected) {
                let what = if i < s {
                    format!("the shape coordinate `{to_name}` must not depend on `{g_from}`")
                } else if i == s + jg {
                    format!(
                        "`{to_name}` must be `{g_from}` plus a function of the shape coordinates"
                    )
                } else {
                    format!("`{to_name}` must not depend on `{g_from}`")
                };
                cx.error_spanned_by(
                    &func.sig.ident,
                    format!(
                        "the transition is not equivariant (the symmetry must act by translation \
                         of the group coordinates in both charts, so `x_to = ψ(x_from)` and \
                         `g_to = g_from + c(x_from)`): {what}"
                    ),
                );
            }
        }
    }
}
