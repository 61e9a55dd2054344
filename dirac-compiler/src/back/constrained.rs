//! The impls of a system with constraints (`constraints = |q| [..]`, `nonholonomic = ..`): the
//! runtime's `Constraints` (`φ` itself) and `Constrained` for each form of the step (unreduced,
//! and reduced on each side), whose position steps and projections are built in
//! [`crate::ir::constraint`].

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use crate::back::backend::{stepper_fns, Backend};
use crate::back::emit::straight_line;
use crate::back::impls::{Bodies, ImplBlock, Item, Kind, Target};
use crate::back::lints;
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

/// The form of the constrained steps an impl is for: the unreduced equations on `(q, p)` or the
/// reduced equations of a side on `(x, w, μ, g)`.
#[derive(Clone, Copy)]
enum Form {
    Unreduced,
    Reduced(Side),
}

impl Form {
    const ALL: [Form; 3] = [
        Form::Unreduced,
        Form::Reduced(Side::Plus),
        Form::Reduced(Side::Minus),
    ];

    /// The runtime's marker type of the form.
    fn marker(self, rt: &TokenStream) -> TokenStream {
        match self {
            Form::Unreduced => quote!(#rt::UnreducedForm),
            Form::Reduced(Side::Plus) => quote!(#rt::Plus),
            Form::Reduced(Side::Minus) => quote!(#rt::Minus),
        }
    }

    /// The form's state type, `&UnreducedState<N>` or `&ReducedState<S, K>`.
    fn state(self, t: &Target) -> TokenStream {
        let (rt, s, k, n) = (&t.rt, t.s, t.k, t.n);
        match self {
            Form::Unreduced => quote!(&#rt::UnreducedState<#n>),
            Form::Reduced(_) => quote!(&#rt::ReducedState<#s, #k>),
        }
    }

    /// The dimension of the momentum the position step leaves: `p̃ ∈ R^N` or `w̃ ∈ R^S`.
    fn momentum_dim(self, t: &Target) -> usize {
        match self {
            Form::Unreduced => t.n,
            Form::Reduced(_) => t.s,
        }
    }

    /// How a step function of the form reads a leaf: `input` is the state it reads (`state`
    /// for the position step, `shake` for the projection), `unknowns` its unknowns (`z`, `y`),
    /// `(s, n)` the sizes of the shape and of the configuration.
    fn leaf(
        self,
        sym: Sym,
        (input, unknowns): (&TokenStream, &TokenStream),
        (s, n): (usize, usize),
        param: &dyn Fn(usize) -> TokenStream,
    ) -> TokenStream {
        match (self, sym) {
            (_, Sym::Q1(i)) => quote!(#unknowns[#i]),
            (_, Sym::Lambda(j)) => {
                let j = n + j;
                quote!(#unknowns[#j])
            }
            (_, Sym::Param(i)) => param(i),
            (Form::Unreduced, Sym::Q0(i)) => quote!(#input.q[#i]),
            (Form::Unreduced, Sym::P(i)) => quote!(#input.p[#i]),
            (Form::Reduced(_), Sym::X0(i) | Sym::Q0(i)) => quote!(#input.x[#i]),
            (Form::Reduced(_), Sym::X1(i)) => quote!(#unknowns[#i]),
            (Form::Reduced(_), Sym::G1(j) | Sym::G0(j)) => {
                let j = s + j;
                quote!(#unknowns[#j])
            }
            (Form::Reduced(_), Sym::W(i)) => quote!(#input.w[#i]),
            (Form::Reduced(_), Sym::Mu(j)) => quote!(#input.mu[#j]),
            (_, other) => unreachable!(
                "a constrained step reads its state, its unknowns and the parameters, not {other:?}"
            ),
        }
    }
}

/// The table entry of `Constraints<S, K, N, M>`: whether they are holonomic, and `φ(q)`.
fn constraints_table(t: &Target, m: usize) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let vn = t.vec(n);
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl #rt::Constraints<#s, #k, #n, #m> for #ty),
        items: vec![
            Item {
                name: "HOLONOMIC",
                kind: Kind::Const {
                    decl: quote!(const HOLONOMIC: bool),
                    stub: None,
                    documented: false,
                },
            },
            method(
                "constraint",
                quote!(fn constraint(&self, q: #vn) -> #na::SVector<f64, #m>),
            ),
        ],
    }
}

/// The table entry of `Constrained<F, S, K, N, M, Z>` for the form `form`; `position` and
/// `projection` are the backends of the two solves.
fn constrained_table(
    t: &Target,
    form: Form,
    m: usize,
    position: &Backend,
    projection: &Backend,
) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let z = n + m;
    let vz = t.vec(z);
    let (marker, state, dim) = (form.marker(rt), form.state(t), form.momentum_dim(t));
    let (pj, ps) = (position.matrix_type(z), position.solver_type(z));
    let (qj, qs) = (projection.matrix_type(z), projection.solver_type(z));
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl #rt::Constrained<#marker, #s, #k, #n, #m, #z> for #ty),
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
                name: "constrained_impulse",
                kind: Kind::Method {
                    attrs: quote!(#[allow(unused_variables)]),
                    sig: quote!(fn constrained_impulse(&self, state: #state, z: #vz) -> #na::SVector<f64, #k>),
                    provided: true,
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
                "constrained_residual",
                quote!(fn constrained_residual(&self, state: #state, z: #vz) -> #na::SVector<f64, #z>),
            ),
            method(
                "constrained_residual_jacobian",
                quote!(fn constrained_residual_jacobian(&self, state: #state, z: #vz) -> (#na::SVector<f64, #z>, #pj)),
            ),
            method(
                "constrained_momentum",
                quote!(fn constrained_momentum(&self, state: #state, z: #vz) -> #na::SVector<f64, #dim>),
            ),
            method(
                "projection_residual",
                quote!(fn projection_residual(&self, shake: #state, y: #vz) -> #na::SVector<f64, #z>),
            ),
            method(
                "projection_residual_jacobian",
                quote!(fn projection_residual_jacobian(&self, shake: #state, y: #vz) -> (#na::SVector<f64, #z>, #qj)),
            ),
            method(
                "projected_momentum",
                quote!(fn projected_momentum(&self, shake: #state, y: #vz) -> #na::SVector<f64, #n>),
            ),
        ],
    }
}

/// The stub impls of a constrained system whose compilation failed: the same tables, with the
/// backend the size calls for; `m` is the number of constraints the attribute lists.
pub fn stubs(t: &Target, m: usize) -> TokenStream {
    let backend = Backend::for_size(t.n + m);
    let stub = Bodies::Stub("reduced_lagrangian");
    let mut out = constraints_table(t, m).render(&stub);
    for form in Form::ALL {
        out.extend(constrained_table(t, form, m, &backend, &backend).render(&stub));
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
    let mut out = constraints_table(t, m).render(&Bodies::Real(HashMap::from([
        ("HOLONOMIC", quote!(#holonomic)),
        ("constraint", constraint_body),
    ])));
    let steps = [
        (&code.position, &code.projection),
        (&code.plus.0, &code.plus.1),
        (&code.minus.0, &code.minus.1),
    ];
    for (form, (position, projection)) in Form::ALL.into_iter().zip(steps) {
        let pos_leaf = |sym: Sym| form.leaf(sym, (&quote!(state), &quote!(z)), (s, n), &param);
        let proj_leaf = |sym: Sym| form.leaf(sym, (&quote!(shake), &quote!(y)), (s, n), &param);
        let pos = stepper_fns(g, position, &pos_leaf, z, form.momentum_dim(t));
        let proj = stepper_fns(g, projection, &proj_leaf, z, n);
        let mut bodies = HashMap::from([
            ("position_solver", pos.solver_new),
            ("projection_solver", proj.solver_new),
            ("constrained_residual", pos.residual),
            ("constrained_residual_jacobian", pos.residual_jacobian),
            ("constrained_momentum", pos.momentum),
            ("projection_residual", proj.residual),
            ("projection_residual_jacobian", proj.residual_jacobian),
            ("projected_momentum", proj.momentum),
        ]);
        if !position.impulse.is_empty() {
            let code = straight_line(g, &position.impulse, &pos_leaf);
            let (stmts, out) = (&code.stmts, &code.outputs);
            let k = t.k;
            bodies.insert("CONSTRAINED_GROUP_FORCED", quote!(true));
            bodies.insert(
                "constrained_impulse",
                quote! { #stmts #na::SVector::<f64, #k>::from_column_slice(&[ #( #out ),* ]) },
            );
        }
        out.extend(
            constrained_table(t, form, m, &pos.backend, &proj.backend)
                .render(&Bodies::Real(bodies)),
        );
    }
    out
}
