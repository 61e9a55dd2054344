//! `impl ContinuousLagrangian<N>` for a continuous Lagrangian: `L` calls the user's function,
//! the Legendre map, its Jacobian and the energy are straight-line code from the graph
//! ([`crate::ir::discretize::Continuous`]).

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use crate::back::backend::residual_jacobian;
use crate::back::emit::straight_line;
use crate::back::impls::{self, Bodies, Target};
use crate::ir::discretize::{Continuous, Stage};
use crate::ir::graph::{Graph, NodeId, Sym};

/// `impl ContinuousLagrangian<N>`: `L` calls the user's function (`call_l`), the derivatives are
/// straight-line code.
pub fn emit_impl(g: &Graph, c: &Continuous, t: &Target, call_l: &TokenStream) -> TokenStream {
    let (n, na) = (t.n, &t.na);
    let leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote! { q[#i] },
        Sym::Q1(i) => quote! { v[#i] },
        Sym::Param(i) => t.param_leaf(i),
        _ => unreachable!("L reads q, v and its parameters"),
    };
    let body = |roots: &[NodeId]| {
        let code = straight_line(g, roots, &leaf);
        (code.stmts, code.outputs)
    };
    let (p_stmts, p_out) = body(&c.legendre);
    let pj = residual_jacobian(g, &c.legendre, &c.hessian, &leaf, n);
    let (e_stmts, e_out) = body(&[c.energy]);
    let bodies = HashMap::from([
        ("continuous_lagrangian", call_l.clone()),
        (
            "legendre",
            quote! {
                #p_stmts
                #na::SVector::<f64, #n>::from([ #( #p_out ),* ])
            },
        ),
        ("legendre_solver", pj.solver_new),
        ("legendre_jacobian", pj.code),
        ("energy", quote! { #e_stmts #( #e_out )* }),
    ]);
    let mut out = impls::continuous_lagrangian(t, c.rule.describe(), &pj.backend)
        .render(&Bodies::Real(bodies));
    if let Some(stage) = &c.stage {
        out.extend(stage_impl(g, c, stage, t, &leaf));
    }
    out
}

/// `impl StageDerivatives<N>`: the stage's force and momentum, and with them their Jacobians in
/// `q` and `v` (`∂p/∂v` is the Legendre map's Jacobian), each one straight line.
fn stage_impl(
    g: &Graph,
    c: &Continuous,
    stage: &Stage,
    t: &Target,
    leaf: &dyn Fn(Sym) -> TokenStream,
) -> TokenStream {
    let (n, na, rt) = (t.n, &t.na, &t.rt);
    let first: Vec<NodeId> = stage.force.iter().chain(&c.legendre).copied().collect();
    let code = straight_line(g, &first, leaf);
    let (stmts, f, p) = (&code.stmts, &code.outputs[..n], &code.outputs[n..]);
    let stage_body = quote! {
        #stmts
        (
            #na::SVector::<f64, #n>::from([ #( #f ),* ]),
            #na::SVector::<f64, #n>::from([ #( #p ),* ]),
        )
    };
    // The four blocks' nonzero entries after the force and the momentum.
    let blocks = [
        &stage.force_q,
        &stage.force_v,
        &c.hessian,
        &stage.momentum_q,
    ];
    let mut roots = first.clone();
    let mut entries: Vec<Vec<(usize, usize)>> = vec![Vec::new(); blocks.len()];
    for (b, block) in blocks.iter().enumerate() {
        for (row, cols) in block.iter().enumerate() {
            for (col, &node) in cols.iter().enumerate() {
                if g.as_const(node) != Some(0.0) {
                    entries[b].push((row, col));
                    roots.push(node);
                }
            }
        }
    }
    let code = straight_line(g, &roots, leaf);
    let (stmts, f, p) = (&code.stmts, &code.outputs[..n], &code.outputs[n..2 * n]);
    let mut values = code.outputs[2 * n..].iter();
    let names = [quote!(f_q), quote!(f_v), quote!(p_v), quote!(p_q)];
    let assigns = entries.iter().zip(&names).flat_map(|(block, name)| {
        block
            .iter()
            .zip(values.by_ref())
            .map(|((row, col), e)| quote! { __j.#name[(#row, #col)] = #e; })
            .collect::<Vec<_>>()
    });
    let jacobian_body = quote! {
        #stmts
        let mut __j = #rt::StageJacobian::<#n> {
            f: #na::SVector::<f64, #n>::from([ #( #f ),* ]),
            p: #na::SVector::<f64, #n>::from([ #( #p ),* ]),
            f_q: #na::SMatrix::<f64, #n, #n>::zeros(),
            f_v: #na::SMatrix::<f64, #n, #n>::zeros(),
            p_q: #na::SMatrix::<f64, #n, #n>::zeros(),
            p_v: #na::SMatrix::<f64, #n, #n>::zeros(),
        };
        #( #assigns )*
        __j
    };
    let bodies = HashMap::from([("stage", stage_body), ("stage_jacobian", jacobian_body)]);
    impls::stage_derivatives(t).render(&Bodies::Real(bodies))
}
