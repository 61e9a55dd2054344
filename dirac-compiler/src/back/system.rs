//! The real bodies of a `#[reduced_lagrangian]` system's impls, rendered through the table of
//! [`crate::back::impls`]: the Lagrangian and connection, both reduced steppers (and their
//! eliminated forms), the unreduced stepper and the Hessian of `L_d`.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::{Ident, ItemFn};

use crate::back::backend::{stepper_fns, Backend, DENSE_MAX};
use crate::back::emit::straight_line;
use crate::back::impls::{self, Bodies, Target};
use crate::back::items::{config_struct, param_struct, type_name, user_function};
use crate::back::{adapted, continuous};
use crate::front::signature::Signature;
use crate::front::Spec;
use crate::ir::compile::{Compiled, SideCode};
use crate::ir::graph::Graph;
use crate::ir::graph::{NodeId, Sym};
use crate::ir::reduce::{Partials, Side, Stepper};

/// The body of a `step_partials` function: every entry of `p` that is not zero by construction
/// assigned into `out` (a `StepPartials` of zeros, whose other entries stay zero), then `true`.
fn partials_body(g: &Graph, p: &Partials, leaf: &dyn Fn(Sym) -> TokenStream) -> TokenStream {
    let blocks = [
        ("r_y", &p.r_y),
        ("r_u", &p.r_u),
        ("o_y", &p.o_y),
        ("o_z", &p.o_z),
        ("o_u", &p.o_u),
    ];
    let mut roots = Vec::new();
    let mut targets = Vec::new();
    for (name, m) in blocks {
        for (i, row) in m.iter().enumerate() {
            for (j, &node) in row.iter().enumerate() {
                if g.as_const(node) != Some(0.0) {
                    roots.push(node);
                    targets.push((format_ident!("{}", name), i, j));
                }
            }
        }
    }
    let code = straight_line(g, &roots, leaf);
    let stmts = &code.stmts;
    let assigns = targets
        .iter()
        .zip(&code.outputs)
        .map(|((f, i, j), v)| quote! { out.#f[(#i, #j)] = #v; });
    quote! {
        #stmts
        #( #assigns )*
        true
    }
}

/// Leaves of the reduced steppers: `x_k`, the unknowns `z = (x_{k+1}, u)`, `w_k`, `μ_k`.
fn reduced_leaf(t: &Target, sym: Sym) -> TokenStream {
    match sym {
        Sym::X0(i) => quote! { x_k[#i] },
        Sym::X1(i) => quote! { z[#i] },
        Sym::G1(j) | Sym::G0(j) => {
            let j = t.s + j;
            quote! { z[#j] }
        }
        Sym::W(i) => quote! { w_k[#i] },
        Sym::Mu(j) => quote! { mu_k[#j] },
        Sym::Param(i) => t.param_leaf(i),
        Sym::Q0(_)
        | Sym::Q1(_)
        | Sym::P(_)
        | Sym::D0(_)
        | Sym::D1(_)
        | Sym::Lambda(_)
        | Sym::Base(_)
        | Sym::Chart0(_)
        | Sym::Chart1(_)
        | Sym::Rel(_) => {
            unreachable!("reduced Lagrangians read x0, x1 and g")
        }
    }
}

/// One side's `impl Reduced<Side, S, K, N>`, its code counts and its elimination note: the
/// (+) and (−) impls come from this one function.
fn reduced_impl(t: &Target, c: &Compiled, side: &SideCode) -> (TokenStream, String, String) {
    let g = &c.graph;
    let (s, k, n, na) = (t.s, t.k, t.n, &t.na);
    let leaf = |sym| reduced_leaf(t, sym);
    let label = match side.side {
        Side::Plus => "(+)",
        Side::Minus => "(−)",
    };
    // l_{d±} itself, from the graph the derivatives come from (α = 0: eqs. (4.5), (4.7)).
    let l = straight_line(g, &[side.lagrangian], &|sym| match sym {
        Sym::X0(i) => quote! { x0[#i] },
        Sym::X1(i) => quote! { x1[#i] },
        Sym::G1(j) | Sym::G0(j) => quote! { u[#j] },
        Sym::Param(i) => t.param_leaf(i),
        _ => unreachable!("reduced Lagrangians read x0, x1 and the group unknown"),
    });
    let (l_stmts, l_out) = (&l.stmts, &l.outputs[0]);
    let general = stepper_fns(g, &side.stepper, &leaf, n, s);
    let mut bodies: HashMap<&'static str, TokenStream> = HashMap::from([
        ("linear_solver", general.solver_new.clone()),
        ("reduced_lagrangian", quote! { #l_stmts #l_out }),
        ("residual", general.residual.clone()),
        ("residual_jacobian", general.residual_jacobian.clone()),
        ("momentum", general.momentum.clone()),
        ("residual_momentum", general.residual_momentum.clone()),
    ]);
    // The eliminated stepper: Newton on x_{k+1} alone; the third function returns the group
    // unknowns in closed form.
    let note = match &side.eliminated {
        None if n > DENSE_MAX => {
            format!("{label} not used on the sparse backend (its shape Jacobian is dense)")
        }
        None => format!(
            "{label} not available (the momentum equations are not affine in the group unknowns)"
        ),
        Some(e) => {
            let as_stepper = Stepper {
                residual: e.residual.clone(),
                jacobian: e.jacobian.clone(),
                momentum: e.group.clone(),
                impulse: Vec::new(),
            };
            let f = stepper_fns(g, &as_stepper, &leaf, s, k);
            let (r, rj, grp) = (&f.residual, &f.residual_jacobian, &f.momentum);
            let pays = side.elimination_pays;
            let a_flat: Vec<NodeId> = e.block.iter().flatten().copied().collect();
            let a_code = straight_line(g, &a_flat, &leaf);
            let (a_stmts, a_out) = (&a_code.stmts, &a_code.outputs);
            bodies.extend([
                ("ELIMINATES_GROUP", quote!(true)),
                ("ELIMINATION_PAYS", quote!(#pays)),
                (
                    "eliminated_residual",
                    quote!(::core::option::Option::Some({ #r })),
                ),
                (
                    "eliminated_residual_jacobian",
                    quote!(::core::option::Option::Some({ #rj })),
                ),
                (
                    "eliminated_group",
                    quote!(::core::option::Option::Some({ #grp })),
                ),
                (
                    "eliminated_group_block",
                    quote! {
                        #a_stmts
                        ::core::option::Option::Some(#na::SMatrix::<f64, #k, #k>::from_row_slice(&[ #( #a_out ),* ]))
                    },
                ),
            ]);
            format!(
                "{label} group unknowns in closed form, Newton on the shape unknowns: {} (the third count is the closed form); \
                 used by default: {}",
                f.counts,
                if pays { "yes" } else { "no, the general path has less code" }
            )
        }
    };
    if !side.stepper.impulse.is_empty() {
        let code = straight_line(g, &side.stepper.impulse, &leaf);
        let (stmts, out) = (&code.stmts, &code.outputs);
        bodies.extend([
            ("GROUP_FORCED", quote!(true)),
            (
                "group_impulse",
                quote! {
                    #stmts
                    #na::SVector::<f64, #k>::from_column_slice(&[ #( #out ),* ])
                },
            ),
        ]);
    }
    if let Some(p) = &side.partials {
        bodies.insert("step_partials", partials_body(g, p, &leaf));
    }
    let tokens = impls::reduced(t, side.side, &general.backend).render(&Bodies::Real(bodies));
    (tokens, general.counts, note)
}

/// `impl LagrangianHessian` with its body, when the system is dense.
fn hessian_impl(t: &Target, c: &Compiled) -> Option<TokenStream> {
    let (n, na) = (t.n, &t.na);
    let hessian = c.hessian.as_ref()?;
    let hessian_roots: Vec<NodeId> = hessian.iter().flatten().flatten().copied().collect();
    let hessian_code = straight_line(&c.graph, &hessian_roots, &|sym| match sym {
        Sym::Q0(i) => quote! { q0[#i] },
        Sym::Q1(i) => quote! { q1[#i] },
        Sym::Param(i) => t.param_leaf(i),
        _ => unreachable!("L_d reads q0, q1 and its parameters"),
    });
    let hessian_stmts = &hessian_code.stmts;
    let hessian_blocks = hessian_code.outputs.chunks(n * n).map(|block| {
        quote! { #na::SMatrix::<f64, #n, #n>::from_row_slice(&[ #( #block ),* ]) }
    });
    let body = quote! {
        #hessian_stmts
        ( #( #hessian_blocks ),* )
    };
    let block = impls::lagrangian_hessian(t).expect("the Hessian is compiled for dense systems");
    Some(block.render(&Bodies::Real(HashMap::from([("lagrangian_hessian", body)]))))
}

/// `impl DiscreteLagrangian` with its bodies: `lagrangian_body` is `L_d`.
fn discrete_impl(
    t: &Target,
    spec: &Spec,
    sig: &Signature,
    c: &Compiled,
    lagrangian_body: TokenStream,
) -> TokenStream {
    let (s, k, na) = (t.s, t.k, &t.na);
    let b_flat: Vec<NodeId> = c.b.iter().flatten().copied().collect();
    let b_code = straight_line(&c.graph, &b_flat, &|sym| match sym {
        Sym::Param(i) => t.param_leaf(i),
        _ => unreachable!("connection entries are constant"),
    });
    let (b_stmts, b_out) = (&b_code.stmts, &b_code.outputs);
    let b_rows = (0..k).map(|j| {
        let row = &b_out[j * s..(j + 1) * s];
        quote! { #( #row ),* }
    });
    let connection_body = if s == 0 {
        quote! { #na::SMatrix::<f64, #k, #s>::zeros() }
    } else {
        quote! {
            #b_stmts
            #na::SMatrix::<f64, #k, #s>::from_row_slice(&[ #( #b_rows, )* ])
        }
    };
    let mut bodies = HashMap::from([
        ("lagrangian", lagrangian_body),
        ("connection", connection_body),
    ]);
    if let Some((_, monitor, _)) = c.adapt {
        let code = straight_line(&c.graph, &[monitor], &|sym| match sym {
            Sym::Q0(i) => quote! { x[#i] },
            Sym::Param(i) => t.param_leaf(i),
            other => unreachable!("the monitor reads the shape and the parameters, not {other:?}"),
        });
        let (stmts, out) = (&code.stmts, &code.outputs[0]);
        bodies.insert(
            "monitor",
            quote! { #stmts ::core::option::Option::Some(#out) },
        );
        let rt = &t.rt;
        bodies.insert(
            "adaptive_increment",
            quote! { #rt::adaptive::first_increment(self, q, p, h) },
        );
        bodies.insert(
            "level_set_defect",
            quote! { #rt::adaptive::level_set_defect(self, q, p) },
        );
    }
    let model = model(spec, sig);
    let mut out = impls::system(&t.ty, &model).render(&Bodies::Real(impls::system_bodies(&model)));
    out.extend(discrete_table(t, spec).render(&Bodies::Real(bodies)));
    out
}

/// What this system declares of the one system model (`System`): its parameters, time step,
/// controls, coordinates `q = (x, g)`, time coordinate and domain.
fn model<'a>(spec: &'a Spec, sig: &'a Signature) -> impls::Model<'a> {
    impls::Model {
        params: &sig.params,
        step: &sig.step,
        controls: &spec.controls,
        coordinates: spec
            .layout
            .shape
            .iter()
            .chain(&spec.layout.group)
            .cloned()
            .collect(),
        time: spec.adapt.as_ref().map(|a| a.index),
        domain: &spec.domain,
    }
}

/// The table entry of `DiscreteLagrangian` for this system.
pub fn discrete_table(t: &Target, spec: &Spec) -> impls::ImplBlock {
    impls::discrete_lagrangian(
        t,
        &spec.layout.shape,
        &spec.layout.group,
        spec.force.is_some(),
        spec.adapt.is_some(),
    )
}

/// Every item `#[reduced_lagrangian]` emits for a compiled system.
pub fn generate(spec: &Spec, sig: &Signature, func: &ItemFn, c: &Compiled) -> TokenStream {
    let ty = type_name(spec, func);
    let config = format_ident!("{}Config", ty);
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let fn_name = &func.sig.ident;
    let t = Target::new(ty.clone(), s, k, &sig.params);
    let n = t.n;
    let param_leaf = |i: usize| t.param_leaf(i);
    let unreduced_leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote! { q_k[#i] },
        Sym::Q1(i) => quote! { z[#i] },
        Sym::P(i) => quote! { p_k[#i] },
        Sym::Param(i) => param_leaf(i),
        _ => unreachable!("the unreduced equations read q0, q1 and p"),
    };
    let (plus_impl, plus_counts, plus_note) = reduced_impl(&t, c, &c.plus);
    let (minus_impl, minus_counts, minus_note) = reduced_impl(&t, c, &c.minus);
    let elimination_note = format!(" Momentum-level elimination: {plus_note}; {minus_note}.");
    let unreduced = stepper_fns(&c.graph, &c.unreduced, &unreduced_leaf, n, n);
    let mut unreduced_bodies = HashMap::from([
        ("unreduced_linear_solver", unreduced.solver_new.clone()),
        ("unreduced_residual", unreduced.residual.clone()),
        (
            "unreduced_residual_jacobian",
            unreduced.residual_jacobian.clone(),
        ),
        ("unreduced_momentum", unreduced.momentum.clone()),
    ]);
    if let Some(p) = &c.unreduced_partials {
        unreduced_bodies.insert(
            "unreduced_step_partials",
            partials_body(&c.graph, p, &unreduced_leaf),
        );
    }
    let unreduced_impl =
        impls::unreduced(&t, &unreduced.backend).render(&Bodies::Real(unreduced_bodies));
    let hessian_impl = hessian_impl(&t, c);

    let config_item = config_struct(spec, func, &config, &ty);
    let adapted_item = adapted::adapted_impl(&spec.layout, &ty);
    // The user's function reads the user's coordinates; the system's vectors are adapted.
    let user_config = |q: TokenStream| adapted::user_config(&spec.layout, &ty, &config, q);
    let user_fn = user_function(
        func,
        &config,
        false,
        &connection_only_params(spec, sig, c),
        spec.layout.has_arrays(),
    );
    let param_item = param_struct(sig, func, &ty);
    // The discrete Lagrangian: the user's function, or L_d formed from a continuous L.
    let fn_params = sig.fn_params();
    let lagrangian_body = if c.continuous.is_some() {
        let code = straight_line(&c.graph, &[c.body], &|sym| match sym {
            Sym::Q0(i) => quote! { q0[#i] },
            Sym::Q1(i) => quote! { q1[#i] },
            Sym::Param(i) => param_leaf(i),
            _ => unreachable!("L_d reads q0, q1 and its parameters"),
        });
        let (stmts, out) = (&code.stmts, &code.outputs[0]);
        quote! { #stmts #out }
    } else {
        let (c0, c1) = (user_config(quote!(q0)), user_config(quote!(q1)));
        quote! { #fn_name(#c0, #c1, #( self.#fn_params ),*) }
    };
    let continuous_impl = c.continuous.as_ref().map(|parts| {
        let (cq, cv) = (user_config(quote!(q)), user_config(quote!(v)));
        let call_l = quote! {
            #fn_name(#cq, #cv, #( self.#fn_params ),*)
        };
        continuous::emit_impl(&c.graph, parts, &t, &call_l)
    });
    let counts = format!(
        "Generated straight-line code: reduced (+) stepper: {}; reduced (−) stepper: {}; unreduced stepper: {}.",
        plus_counts, minus_counts, unreduced.counts
    ) + &elimination_note;
    let inherent = impls::inherent(&t).render(&Bodies::Real(HashMap::from([(
        "GENERATED",
        quote!(#counts),
    )])));
    let discrete = discrete_impl(&t, spec, sig, c, lagrangian_body);
    let constrained_impls = c
        .constrained
        .as_ref()
        .map(|code| crate::back::constrained::emit(&t, c, code));

    quote! {
        #config_item

        #adapted_item

        #user_fn

        #param_item

        #continuous_impl

        #inherent

        #discrete

        #plus_impl

        #minus_impl

        #unreduced_impl

        #hessian_impl

        #constrained_impls
    }
}

/// Parameters the body never reads but the system does (the connection matrix, the forces, or
/// as controls): the user's function marks them used.
fn connection_only_params(spec: &Spec, sig: &Signature, c: &Compiled) -> Vec<Ident> {
    let mut roots: Vec<NodeId> = c.b.iter().flatten().copied().collect();
    if let Some(f) = &c.forces {
        roots.extend(f.minus.iter().chain(&f.plus));
    }
    if let Some(code) = &c.constrained {
        roots.extend(&code.position.residual);
    }
    // With adaptive steps the compiled body is the transformed one: the user's is its `L`.
    let user_body = match c.adapt {
        Some((_, monitor, l)) => {
            roots.push(monitor);
            l
        }
        None => c.body,
    };
    let in_system = c.graph.symbols(&roots);
    let in_body = c.graph.symbols(&[user_body]);
    sig.fn_params()
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            (in_system.contains(&Sym::Param(*i)) || spec.controls.contains(p))
                && !in_body.contains(&Sym::Param(*i))
        })
        .map(|(_, p)| p.clone())
        .collect()
}

/// The items of a system whose compilation failed, with the signatures of the real ones (the
/// same table) and bodies never reached: what the user's other code refers to type-checks, so
/// the real error is not buried under follow-on ones.
pub fn stubs(spec: &Spec, sig: &Signature, ty: &Ident) -> TokenStream {
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let t = Target::new(ty.clone(), s, k, &sig.params);
    let stub = Bodies::Stub("reduced_lagrangian");
    let backend = Backend::for_size(t.n);
    let mut out = impls::inherent(&t).render(&stub);
    out.extend(impls::system(ty, &model(spec, sig)).render(&stub));
    out.extend(discrete_table(&t, spec).render(&stub));
    for side in [Side::Plus, Side::Minus] {
        out.extend(impls::reduced(&t, side, &backend).render(&stub));
    }
    out.extend(impls::unreduced(&t, &backend).render(&stub));
    if let Some(hessian) = impls::lagrangian_hessian(&t) {
        out.extend(hessian.render(&stub));
    }
    if sig.continuous {
        if let Some((_, rule)) = spec.rule {
            out.extend(impls::continuous_lagrangian(&t, rule.describe(), &backend).render(&stub));
            if backend.is_dense() && spec.constraints.is_none() {
                out.extend(impls::stage_derivatives(&t).render(&stub));
            }
        }
        if let Some(closure) = &spec.constraints {
            let m = crate::back::constrained::count(closure);
            out.extend(crate::back::constrained::stubs(&t, m));
        }
    }
    out
}
