//! `impl ContinuousLagrangian<N>` for a continuous Lagrangian: `L` calls the user's function,
//! the Legendre map, its Jacobian and the energy are straight-line code from the graph
//! ([`crate::ir::discretize::Continuous`]).

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use crate::back::backend::residual_jacobian;
use crate::back::emit::straight_line;
use crate::back::impls::{self, Bodies, Target};
use crate::ir::discretize::Continuous;
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
    impls::continuous_lagrangian(t, c.rule.describe(), &pj.backend).render(&Bodies::Real(bodies))
}
