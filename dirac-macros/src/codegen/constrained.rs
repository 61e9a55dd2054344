//! The impls of a system with holonomic constraints (`constraints = |q| [..]`): the runtime's
//! `Constrained` (unreduced) and `ReducedConstrained` (each side), whose position steps and
//! projections are built in [`crate::ir::constraint`].

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use crate::codegen::backend::{stepper_fns, Backend};
use crate::codegen::emit::straight_line;
use crate::codegen::impls::{Bodies, ImplBlock, Item, Kind, Target};
use crate::codegen::lints;
use crate::ir::compile::Compiled;
use crate::ir::constraint::ConstrainedCode;
use crate::ir::graph::Sym;
use crate::ir::reduce::Side;

fn method(name: &'static str, sig: TokenStream) -> Item {
    Item {
        name,
        kind: Kind::Method {
            attrs: quote!(#[allow(unused_variables)]), // a step need not read every input
            sig,
            provided: false,
        },
    }
}

fn fixed(name: &'static str, tokens: TokenStream) -> Item {
    Item {
        name,
        kind: Kind::Fixed(tokens),
    }
}

/// The table entry of `Constrained<S, K, N, M, Z>`; `position` and `projection` are the
/// backends of the two solves.
pub fn constrained_table(
    t: &Target,
    m: usize,
    position: &Backend,
    projection: &Backend,
) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let z = n + m;
    let (vn, vz) = (t.vec(n), t.vec(z));
    let (pj, ps) = (position.matrix_type(z), position.solver_type(z));
    let (qj, qs) = (projection.matrix_type(z), projection.solver_type(z));
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl #rt::Constrained<#s, #k, #n, #m, #z> for #ty),
        items: vec![
            Item {
                name: "HOLONOMIC",
                kind: Kind::Const {
                    decl: quote!(const HOLONOMIC: bool),
                    stub: None,
                    documented: false,
                },
            },
            fixed("PositionLinear", quote!(type PositionLinear = #ps;)),
            fixed("ProjectionLinear", quote!(type ProjectionLinear = #qs;)),
            method("position_solver", quote!(fn position_solver(&self) -> #ps)),
            method(
                "projection_solver",
                quote!(fn projection_solver(&self) -> #qs),
            ),
            method(
                "constraint",
                quote!(fn constraint(&self, q: #vn) -> #na::SVector<f64, #m>),
            ),
            method(
                "constrained_residual",
                quote!(fn constrained_residual(&self, q_k: #vn, p_k: #vn, z: #vz) -> #na::SVector<f64, #z>),
            ),
            method(
                "constrained_residual_jacobian",
                quote!(fn constrained_residual_jacobian(&self, q_k: #vn, p_k: #vn, z: #vz) -> (#na::SVector<f64, #z>, #pj)),
            ),
            method(
                "constrained_momentum",
                quote!(fn constrained_momentum(&self, q_k: #vn, z: #vz) -> #na::SVector<f64, #n>),
            ),
            method(
                "projection_residual",
                quote!(fn projection_residual(&self, q1: #vn, p1: #vn, y: #vz) -> #na::SVector<f64, #z>),
            ),
            method(
                "projection_residual_jacobian",
                quote!(fn projection_residual_jacobian(&self, q1: #vn, p1: #vn, y: #vz) -> (#na::SVector<f64, #z>, #qj)),
            ),
            method(
                "projected_momentum",
                quote!(fn projected_momentum(&self, q1: #vn, y: #vz) -> #na::SVector<f64, #n>),
            ),
        ],
    }
}

/// The table entry of `ReducedConstrained<D, S, K, N, M, Z>`.
pub fn reduced_constrained_table(
    t: &Target,
    side: Side,
    m: usize,
    position: &Backend,
    projection: &Backend,
) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let z = n + m;
    let (vs, vk, vz) = (t.vec(s), t.vec(k), t.vec(z));
    let marker = match side {
        Side::Plus => quote!(#rt::Plus),
        Side::Minus => quote!(#rt::Minus),
    };
    let (pj, ps) = (position.matrix_type(z), position.solver_type(z));
    let (qj, qs) = (projection.matrix_type(z), projection.solver_type(z));
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl #rt::ReducedConstrained<#marker, #s, #k, #n, #m, #z> for #ty),
        items: vec![
            Item {
                name: "CONSTRAINED_GROUP_FORCED",
                kind: Kind::Const {
                    decl: quote!(const CONSTRAINED_GROUP_FORCED: bool),
                    stub: None,
                    documented: false,
                },
            },
            Item {
                name: "reduced_constrained_impulse",
                kind: Kind::Method {
                    attrs: quote!(#[allow(unused_variables)]),
                    sig: quote!(fn reduced_constrained_impulse(&self, x_k: #vs, z: #vz) -> #na::SVector<f64, #k>),
                    provided: true,
                },
            },
            fixed(
                "ReducedPositionLinear",
                quote!(type ReducedPositionLinear = #ps;),
            ),
            fixed(
                "ReducedProjectionLinear",
                quote!(type ReducedProjectionLinear = #qs;),
            ),
            method(
                "reduced_position_solver",
                quote!(fn reduced_position_solver(&self) -> #ps),
            ),
            method(
                "reduced_projection_solver",
                quote!(fn reduced_projection_solver(&self) -> #qs),
            ),
            method(
                "reduced_constrained_residual",
                quote!(fn reduced_constrained_residual(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vz) -> #na::SVector<f64, #z>),
            ),
            method(
                "reduced_constrained_residual_jacobian",
                quote!(fn reduced_constrained_residual_jacobian(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vz) -> (#na::SVector<f64, #z>, #pj)),
            ),
            method(
                "reduced_constrained_momentum",
                quote!(fn reduced_constrained_momentum(&self, x_k: #vs, z: #vz) -> #na::SVector<f64, #s>),
            ),
            method(
                "reduced_projection_residual",
                quote!(fn reduced_projection_residual(&self, x1: #vs, w1: #vs, mu1: #vk, y: #vz) -> #na::SVector<f64, #z>),
            ),
            method(
                "reduced_projection_residual_jacobian",
                quote!(fn reduced_projection_residual_jacobian(&self, x1: #vs, w1: #vs, mu1: #vk, y: #vz) -> (#na::SVector<f64, #z>, #qj)),
            ),
            method(
                "reduced_projected_momentum",
                quote!(fn reduced_projected_momentum(&self, x1: #vs, mu1: #vk, y: #vz) -> #na::SVector<f64, #n>),
            ),
        ],
    }
}

/// The stub impls of a constrained system whose compilation failed: the same tables, with the
/// backend the size calls for; `m` is the number of constraints the attribute lists.
pub fn stubs(t: &Target, m: usize) -> TokenStream {
    let backend = Backend::for_size(t.n + m);
    let stub = Bodies::Stub("reduced_lagrangian");
    let mut out = constrained_table(t, m, &backend, &backend).render(&stub);
    for side in [Side::Plus, Side::Minus] {
        out.extend(reduced_constrained_table(t, side, m, &backend, &backend).render(&stub));
    }
    out
}

/// The number of constraints `constraints = |q| [..]` lists (1 for a single value).
pub fn count(closure: &syn::ExprClosure) -> usize {
    match &*closure.body {
        syn::Expr::Array(a) => a.elems.len(),
        syn::Expr::Tuple(t) => t.elems.len(),
        _ => 1,
    }
}

/// The constrained impls of a compiled system.
pub fn emit(t: &Target, c: &Compiled, code: &ConstrainedCode) -> TokenStream {
    let g = &c.graph;
    let (s, n, m) = (t.s, t.n, code.m);
    let z = n + m;
    let na = &t.na;
    let param = |i: usize| t.param_leaf(i);
    // Unreduced.
    let pos_leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote!(q_k[#i]),
        Sym::Q1(i) => quote!(z[#i]),
        Sym::Lambda(j) => {
            let j = n + j;
            quote!(z[#j])
        }
        Sym::P(i) => quote!(p_k[#i]),
        Sym::Param(i) => param(i),
        other => unreachable!("the constrained step reads q_k, p_k and z, not {other:?}"),
    };
    let proj_leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote!(q1[#i]),
        Sym::Q1(i) => quote!(y[#i]),
        Sym::Lambda(j) => {
            let j = n + j;
            quote!(y[#j])
        }
        Sym::P(i) => quote!(p1[#i]),
        Sym::Param(i) => param(i),
        other => unreachable!("the projection reads q1, p1 and y, not {other:?}"),
    };
    let pos = stepper_fns(g, &code.position, &pos_leaf, z, n);
    let proj = stepper_fns(g, &code.projection, &proj_leaf, z, n);
    let phi = straight_line(g, &code.phi, &|sym| match sym {
        Sym::Q0(i) => quote!(q[#i]),
        Sym::Param(i) => param(i),
        other => unreachable!("the constraints read q, not {other:?}"),
    });
    let (phi_stmts, phi_out) = (&phi.stmts, &phi.outputs);
    let holonomic = code.holonomic;
    let constraint_body = if holonomic {
        quote! { #phi_stmts #na::SVector::<f64, #m>::from([ #( #phi_out ),* ]) }
    } else {
        quote! { #na::SVector::<f64, #m>::zeros() }
    };
    let mut out = constrained_table(t, m, &pos.backend, &proj.backend).render(&Bodies::Real(
        HashMap::from([
            ("HOLONOMIC", quote!(#holonomic)),
            ("position_solver", pos.solver_new.clone()),
            ("projection_solver", proj.solver_new.clone()),
            ("constraint", constraint_body),
            ("constrained_residual", pos.residual.clone()),
            (
                "constrained_residual_jacobian",
                pos.residual_jacobian.clone(),
            ),
            ("constrained_momentum", pos.momentum.clone()),
            ("projection_residual", proj.residual.clone()),
            (
                "projection_residual_jacobian",
                proj.residual_jacobian.clone(),
            ),
            ("projected_momentum", proj.momentum.clone()),
        ]),
    ));
    // Reduced, each side.
    for (side, (position, projection)) in [(Side::Plus, &code.plus), (Side::Minus, &code.minus)] {
        let pos_leaf = |sym: Sym| match sym {
            Sym::X0(i) => quote!(x_k[#i]),
            Sym::X1(i) => quote!(z[#i]),
            Sym::G1(j) | Sym::G0(j) => {
                let j = s + j;
                quote!(z[#j])
            }
            Sym::Lambda(j) => {
                let j = n + j;
                quote!(z[#j])
            }
            Sym::W(i) => quote!(w_k[#i]),
            Sym::Mu(j) => quote!(mu_k[#j]),
            Sym::Param(i) => param(i),
            other => unreachable!(
                "the reduced constrained step reads x_k, w_k, μ_k and z, not {other:?}"
            ),
        };
        let proj_leaf = |sym: Sym| match sym {
            Sym::Q0(i) => quote!(x1[#i]),
            Sym::Q1(i) => quote!(y[#i]),
            Sym::Lambda(j) => {
                let j = n + j;
                quote!(y[#j])
            }
            Sym::W(i) => quote!(w1[#i]),
            Sym::Mu(j) => quote!(mu1[#j]),
            Sym::Param(i) => param(i),
            other => unreachable!("the reduced projection reads x1, w1, μ1 and y, not {other:?}"),
        };
        let pos = stepper_fns(g, position, &pos_leaf, z, s);
        let proj = stepper_fns(g, projection, &proj_leaf, z, n);
        let mut bodies = HashMap::new();
        if !position.impulse.is_empty() {
            let code = straight_line(g, &position.impulse, &pos_leaf);
            let (stmts, out) = (&code.stmts, &code.outputs);
            let k = t.k;
            bodies.insert("CONSTRAINED_GROUP_FORCED", quote!(true));
            bodies.insert(
                "reduced_constrained_impulse",
                quote! { #stmts #na::SVector::<f64, #k>::from_column_slice(&[ #( #out ),* ]) },
            );
        }
        out.extend(
            reduced_constrained_table(t, side, m, &pos.backend, &proj.backend).render(
                &Bodies::Real({
                    bodies.extend(HashMap::from([
                        ("reduced_position_solver", pos.solver_new.clone()),
                        ("reduced_projection_solver", proj.solver_new.clone()),
                        ("reduced_constrained_residual", pos.residual.clone()),
                        (
                            "reduced_constrained_residual_jacobian",
                            pos.residual_jacobian.clone(),
                        ),
                        ("reduced_constrained_momentum", pos.momentum.clone()),
                        ("reduced_projection_residual", proj.residual.clone()),
                        (
                            "reduced_projection_residual_jacobian",
                            proj.residual_jacobian.clone(),
                        ),
                        ("reduced_projected_momentum", proj.momentum.clone()),
                    ]));
                    bodies
                }),
            ),
        );
    }
    out
}
