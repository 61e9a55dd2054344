//! The items of a system on groups: the user's function over `<Name>Config` (fields
//! `nalgebra::Matrix3` for rotations, `Vector3` for directions, `<Name>Pose` for poses, `f64`
//! for scalars: each kind's own, [`crate::ir::group::Group::config_field`]), `<Name>Momentum`
//! (body momenta of rotations, momenta of directions as vectors tangent to the sphere, a pose's
//! body angular and spatial linear momenta), the parameter struct, and
//! `impl LieLagrangian<P, N>` with the straight-line step of [`crate::ir::lie`].

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::{Ident, ItemFn};

use crate::back::backend::{stepper_fns, SteppedFns};
use crate::back::impls;
use crate::back::items::{camel_case, param_struct, user_function};
use crate::back::lints;
use crate::front::lie::SymmetryKind;
use crate::front::signature::Signature;
use crate::ir::graph::{Graph, Sym};
use crate::ir::group::{Kind, Paths};
use crate::ir::lie::{LieCode, LieSpec};

/// Every item the attribute emits for a system on rotation groups.
pub fn generate(
    spec: &LieSpec,
    sig: &Signature,
    func: &ItemFn,
    g: &Graph,
    code: &LieCode,
) -> TokenStream {
    let ty = spec
        .attr
        .name
        .clone()
        .unwrap_or_else(|| camel_case(&func.sig.ident));
    let config = format_ident!("{}Config", ty);
    let momentum = format_ident!("{}Momentum", ty);
    let (p, n) = (spec.p(), spec.n());
    let (na, rt) = (quote!(::dirac::nalgebra), quote!(::dirac::runtime));
    let params = &sig.params;
    let leaf = |sym: Sym| match sym {
        Sym::Base(i) => quote! { q_k[#i] },
        Sym::Chart1(j) => quote! { z[#j] },
        Sym::P(j) => quote! { p_k[#j] },
        Sym::Param(i) => {
            let p = &params[i];
            quote! { self.#p }
        }
        other => unreachable!("the step reads q_k, z, p_k and parameters, not {other:?}"),
    };
    let fns = stepper_fns(g, &code.stepper, &leaf, n, n);
    let retract = crate::back::emit::straight_line(g, &code.retract, &leaf);
    let (retract_stmts, retract_out) = (&retract.stmts, &retract.outputs);
    let solver_new = &fns.solver_new;
    let step_methods = step_methods("", &fns, p, n);
    let partials_fn = code.partials.as_ref().map(|parts| {
        let roots: Vec<_> = parts.blocks.iter().flatten().flatten().copied().collect();
        let line = crate::back::emit::straight_line(g, &roots, &leaf);
        let stmts = &line.stmts;
        let mut outputs = line.outputs.iter();
        let names = ["r_w", "r_y", "r_u", "o_w", "o_y", "o_u"];
        let fills = parts
            .blocks
            .iter()
            .zip(names)
            .map(|(block, name)| {
                let field = format_ident!("{}", name);
                let (rows, cols) = (block.len(), block.first().map_or(0, Vec::len));
                let sets = (0..rows)
                    .flat_map(|r| (0..cols).map(move |c| (r, c)))
                    .map(|(r, c)| {
                        let e = outputs.next().expect("one output per entry");
                        quote! { m[(#r, #c)] = #e; }
                    })
                    .collect::<Vec<_>>();
                quote! {
                    #field: {
                        let mut m = #na::DMatrix::<f64>::zeros(#rows, #cols);
                        #( #sets )*
                        m
                    }
                }
            })
            .collect::<Vec<_>>();
        quote! {
            fn step_partials(
                &self,
                q_k: &#na::SVector<f64, #p>,
                p_k: &#na::SVector<f64, #n>,
                z: &#na::SVector<f64, #n>,
            ) -> ::core::option::Option<#rt::lie::LiePartials> {
                #stmts
                ::core::option::Option::Some(#rt::lie::LiePartials { #( #fills, )* })
            }
        }
    });
    let solver = fns.backend.solver_type(n);
    let fn_name = &func.sig.ident;
    let fn_params = sig.fn_params();
    let system = impls::system_impl(
        &ty,
        &impls::Model {
            params,
            step: &sig.step,
            controls: &spec.attr.controls,
            coordinates: spec.coords.iter().map(|c| c.name.to_string()).collect(),
            time: code.adapt.as_ref().map(|a| a.coord),
            domain: &[],
        },
    );
    let coords: Vec<TokenStream> = spec
        .coords
        .iter()
        .map(|c| {
            let name = c.name.to_string();
            let kind = LieSpec::kind_path(c);
            quote!((#name, #rt::lie::CoordinateKind::#kind))
        })
        .collect();
    let counts = format!(
        "{}; {} operations for the retraction",
        fns.counts, retract.operations
    );
    let allow = lints::generated();
    let velocity = format_ident!("{}Velocity", ty);
    // Parameters the body does not read (only the force does) are still arguments of the
    // function; mark them used there.
    let read = g.symbols(&[code.lagrangian]);
    let touch: Vec<Ident> = params
        .iter()
        .enumerate()
        .filter(|&(i, p)| {
            !read.contains(&Sym::Param(i)) && sig.fn_params().contains(p) && *p != sig.step
        })
        .map(|(_, p)| p.clone())
        .collect();
    let user_fn = if sig.continuous {
        continuous_user_function(func, &config, &velocity, &touch)
    } else {
        user_function(func, &config, false, &touch, false)
    };
    let params_item = param_struct(sig, func, &ty);
    let mut structs = config_and_momentum(spec, func, &ty, (&config, &momentum), sig.continuous);
    if sig.continuous {
        structs.extend(velocity_struct(spec, func, &ty, &velocity));
    }
    // L_d: the user's function, or formed from a continuous L by its rule (then from the graph,
    // the relative rotations computed from the two points).
    let lagrangian_body = if sig.continuous {
        let rels = spec.rotations().map(|(at, _)| {
            let f = format_ident!("__rel_matrix_{}", at);
            let rows: Vec<usize> = (at..at + 9).collect();
            quote! {
                let #f = #na::Matrix3::new( #( q0[#rows] ),* ).transpose()
                    * #na::Matrix3::new( #( q1[#rows] ),* );
            }
        });
        let code = crate::back::emit::straight_line(g, &[code.lagrangian], &|sym| match sym {
            Sym::Q0(i) => quote! { q0[#i] },
            Sym::Q1(i) => quote! { q1[#i] },
            Sym::Rel(i) => {
                let (at, _) = spec
                    .rotations()
                    .find(|&(at, _)| (at..at + 9).contains(&i))
                    .expect("Rel reads a rotation");
                let f = format_ident!("__rel_matrix_{}", at);
                let (r, col) = ((i - at) / 3, (i - at) % 3);
                quote! { #f[(#r, #col)] }
            }
            Sym::Param(i) => {
                let p = &params[i];
                quote! { self.#p }
            }
            other => {
                unreachable!("L_d reads q0, q1, relative rotations and parameters, not {other:?}")
            }
        });
        let (stmts, out) = (&code.stmts, &code.outputs[0]);
        quote! { #( #rels )* #stmts #out }
    } else {
        quote! { #fn_name(#config::from_point(q0), #config::from_point(q1), #( self.#fn_params ),*) }
    };
    let symmetric = symmetry_impl(spec, g, code, &ty, &leaf);
    let (adapt_trait, adapt_inherent) = adaptive_items(spec, g, code, params, &config, &velocity);
    let doc_p = format!("Length `P` of a stored point of [`{ty}`] (`LieState::q`).");
    let doc_n = format!("Dimension `N` of the configuration space of [`{ty}`] (`LieState::p`).");
    quote! {
        #user_fn
        #params_item
        #structs

        #allow
        impl #ty {
            #[doc = #doc_p]
            pub const POINT_DIM: usize = #p;
            #[doc = #doc_n]
            pub const CONFIG_DIM: usize = #n;
            /// What the compiler generated: operation counts of the straight-line step.
            pub const GENERATED: &'static str = #counts;

            /// The state at the configuration `q` with the momenta `p`.
            pub fn state(&self, q: &#config, p: &#momentum) -> #rt::LieState<#p, #n> {
                let point = q.to_point();
                #rt::LieState { q: point, p: p.to_chart(&point) }
            }

            /// The configuration of `state`.
            pub fn config(&self, state: &#rt::LieState<#p, #n>) -> #config {
                #config::from_point(&state.q)
            }

            /// The momenta of `state`.
            pub fn momenta(&self, state: &#rt::LieState<#p, #n>) -> #momentum {
                #momentum::from_chart(&state.q, &state.p)
            }

            #adapt_inherent
        }

        #allow
        #[automatically_derived]
        impl #rt::LieLagrangian<#p, #n> for #ty {
            const COORDINATES: &'static [(&'static str, #rt::lie::CoordinateKind)] = &[ #( #coords ),* ];
            type Linear = #solver;

            #adapt_trait

            fn linear_solver(&self) -> Self::Linear {
                #solver_new
            }

            fn lagrangian(&self, q0: &#na::SVector<f64, #p>, q1: &#na::SVector<f64, #p>) -> f64 {
                #lagrangian_body
            }

            fn retract(&self, q_k: &#na::SVector<f64, #p>, z: &#na::SVector<f64, #n>) -> #na::SVector<f64, #p> {
                #retract_stmts
                #na::SVector::<f64, #p>::from([ #( #retract_out ),* ])
            }

            #step_methods

            #partials_fn
        }

        #system

        #symmetric
    }
}

/// Adaptive steps: `TIME` and `monitor` of `LieLagrangian`, and the inherent `unreduced_state`
/// (the state on the level set at a physical configuration and velocity,
/// [`crate::ir::lie::LieAdaptive`]). Empty for a system stepped in physical time.
fn adaptive_items(
    spec: &LieSpec,
    g: &Graph,
    code: &LieCode,
    params: &[Ident],
    config: &Ident,
    velocity: &Ident,
) -> (TokenStream, TokenStream) {
    let Some(adapt) = &code.adapt else {
        return (TokenStream::new(), TokenStream::new());
    };
    let (p, n) = (spec.p(), spec.n());
    let (na, rt) = (quote!(::dirac::nalgebra), quote!(::dirac::runtime));
    let leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote! { q[#i] },
        Sym::Q1(i) => quote! { v[#i] },
        Sym::Param(i) => {
            let p = &params[i];
            quote! { self.#p }
        }
        other => {
            unreachable!("the monitor and the level set read q, v and parameters, not {other:?}")
        }
    };
    let monitor = crate::back::emit::straight_line(g, &[adapt.monitor], &leaf);
    let (monitor_stmts, monitor_out) = (&monitor.stmts, &monitor.outputs[0]);
    let mut roots = vec![adapt.monitor];
    roots.extend(&adapt.momentum);
    let level = crate::back::emit::straight_line(g, &roots, &leaf);
    let (level_stmts, level_monitor, level_p) =
        (&level.stmts, &level.outputs[0], &level.outputs[1..]);
    let entries = spec.coords.iter().flat_map(|c| {
        let name = &c.name;
        c.kind.velocity_entries(&quote! { v.#name })
    });
    let time = adapt.coord;
    let time_name = spec.coords[time].name.to_string();
    let doc = format!(
        "The state of adaptive steps at the configuration `q` (its `{time_name}` the physical time) and the \
         physical velocity `v` (its `{time_name}` ignored: the rate of physical time is 1): the physical \
         momenta `∂L/∂v` and `p_{time_name} = −E(q, v)`, on the level set where the time-transformed \
         system's solutions are the physical ones (see `dirac::adaptive`). `Err` with \
         `StepError::InvalidMonitor` where the monitor is not positive and finite."
    );
    let trait_items = quote! {
        fn monitor(&self, q: &#na::SVector<f64, #p>) -> ::core::option::Option<f64> {
            #monitor_stmts
            ::core::option::Option::Some(#monitor_out)
        }
    };
    let inherent = quote! {
        #[doc = #doc]
        pub fn unreduced_state(
            &self,
            q: &#config,
            v: &#velocity,
        ) -> ::core::result::Result<#rt::LieState<#p, #n>, #rt::StepError> {
            let q = q.to_point();
            let v = [ #( #entries ),* ];
            #level_stmts
            let value = #level_monitor;
            if !(value > 0.0 && value.is_finite()) {
                return ::core::result::Result::Err(#rt::StepError::InvalidMonitor { step: 0, value });
            }
            ::core::result::Result::Ok(#rt::LieState {
                q,
                p: #na::SVector::<f64, #n>::from([ #( #level_p ),* ]),
            })
        }
    };
    (trait_items, inherent)
}

/// `impl LieSymmetric<P, N>` for a system with `symmetry(..)`: the declared action, whether the
/// forces act on it, and for every rotation of a rotation coordinate the reduced step's
/// functions (the step with that rotation replaced by the identity).
fn symmetry_impl(
    spec: &LieSpec,
    g: &Graph,
    code: &LieCode,
    ty: &Ident,
    leaf: &dyn Fn(Sym) -> TokenStream,
) -> TokenStream {
    let Some(symmetry) = &spec.symmetry else {
        return TokenStream::new();
    };
    let (p, n) = (spec.p(), spec.n());
    let rt = quote!(::dirac::runtime);
    let kind = match symmetry.kind {
        SymmetryKind::Rotations => {
            let coordinate = symmetry.coords[0].0;
            quote!(#rt::lie::RotationSymmetry::Rotations { coordinate: #coordinate })
        }
        SymmetryKind::RigidMotions => {
            let coordinate = symmetry.coords[0].0;
            quote!(#rt::lie::RotationSymmetry::RigidMotions { coordinate: #coordinate })
        }
        SymmetryKind::Axis(axis) => {
            let coordinates = symmetry.coords.iter().map(|(i, _)| *i);
            quote!(#rt::lie::RotationSymmetry::Axis { axis: #axis, coordinates: &[ #( #coordinates ),* ] })
        }
    };
    let forced = code.symmetry_forced;
    let reduced = code
        .reduced
        .as_ref()
        .map(|stepper| step_methods("reduced_", &stepper_fns(g, stepper, leaf, n, n), p, n));
    let allow = lints::generated();
    quote! {
        #allow
        #[automatically_derived]
        impl #rt::lie::LieSymmetric<#p, #n> for #ty {
            const SYMMETRY: #rt::lie::RotationSymmetry<'static> = #kind;
            const SYMMETRY_FORCED: bool = #forced;
            #reduced
        }
    }
}

/// `<Name>Config` and `<Name>Momentum`, with their conversions to and from the stored point and
/// the chart momentum.
fn config_and_momentum(
    spec: &LieSpec,
    func: &ItemFn,
    ty: &Ident,
    names: (&Ident, &Ident),
    continuous: bool,
) -> TokenStream {
    let (config, momentum) = names;
    let vis = &func.vis;
    let (p, n) = (spec.p(), spec.n());
    let (na, rt) = (quote!(::dirac::nalgebra), quote!(::dirac::runtime));
    let mut config_fields = Vec::new();
    let mut momentum_fields = Vec::new();
    let (mut from_point, mut to_point) = (Vec::new(), Vec::new());
    let (mut from_chart, mut to_chart) = (Vec::new(), Vec::new());
    let paths = Paths {
        na: na.clone(),
        rt: rt.clone(),
    };
    for c in &spec.coords {
        let (name, kind) = (&c.name, c.kind);
        let (at, ch) = (c.point, c.chart);
        let (ty_config, doc) = kind.config_field(&paths, name, ty);
        config_fields.push(quote!(#[doc = #doc] pub #name: #ty_config));
        let (ty_momentum, doc) = kind.momentum_field(&paths, name, ty);
        momentum_fields.push(quote!(#[doc = #doc] pub #name: #ty_momentum));
        let value = kind.read_point(&paths, ty, at);
        from_point.push(quote!(#name: #value));
        to_point.push(kind.write_point(&paths, name, at));
        let value = kind.read_chart(&paths, ty, at, ch);
        from_chart.push(quote!(#name: #value));
        to_chart.push(kind.write_chart(&paths, name, at, ch));
    }
    let kinds = distinct_kinds(spec);
    let items = kinds.iter().map(|k| k.items(&paths, ty, vis, continuous));
    let allow = lints::generated();
    let config_doc =
        format!("A configuration of [`{ty}`]: its coordinates as matrices, vectors and scalars.");
    let momentum_doc = format!("The momenta of a state of [`{ty}`].");
    quote! {
        #( #items )*

        #[doc = #config_doc]
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[allow(non_snake_case, reason = "coordinates keep the user's names (R, n)")]
        #vis struct #config {
            #( #config_fields, )*
        }

        #[doc = #momentum_doc]
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[allow(non_snake_case, reason = "momenta keep the names of their coordinates")]
        #vis struct #momentum {
            #( #momentum_fields, )*
        }

        #allow
        impl #config {
            /// Reads a stored point (`LieState::q`).
            pub fn from_point(q: &#na::SVector<f64, #p>) -> Self {
                Self { #( #from_point, )* }
            }

            /// The stored point: each rotation row by row, each direction with the frame
            /// `dirac::lie::direction_frame` completes it to (a direction that is not a unit
            /// vector to `dirac::lie::UNIT_TOLERANCE` is stored as given, and a run refuses it).
            pub fn to_point(&self) -> #na::SVector<f64, #p> {
                let mut q = #na::SVector::<f64, #p>::zeros();
                #( #to_point )*
                q
            }
        }

        #allow
        impl #momentum {
            /// Reads the chart momentum `p` of a state at the stored point `q`.
            pub fn from_chart(q: &#na::SVector<f64, #p>, p: &#na::SVector<f64, #n>) -> Self {
                Self { #( #from_chart, )* }
            }

            /// The chart momentum at the stored point `q` (`LieState::p`).
            pub fn to_chart(&self, q: &#na::SVector<f64, #p>) -> #na::SVector<f64, #n> {
                let mut p = #na::SVector::<f64, #n>::zeros();
                #( #to_chart )*
                p
            }
        }
    }
}

/// Each kind among the coordinates once, in the order of their first coordinate.
fn distinct_kinds(spec: &LieSpec) -> Vec<Kind> {
    let mut kinds: Vec<Kind> = Vec::new();
    for c in &spec.coords {
        if !kinds.contains(&c.kind) {
            kinds.push(c.kind);
        }
    }
    kinds
}

/// The user's continuous `L(q: Config, v: Velocity, ..)` with the emitted types.
fn continuous_user_function(
    func: &ItemFn,
    config: &Ident,
    velocity: &Ident,
    touch: &[Ident],
) -> TokenStream {
    let mut func = func.clone();
    for p in touch.iter().rev() {
        func.block.stmts.insert(0, syn::parse_quote!(let _ = #p;));
    }
    for (input, ty) in func.sig.inputs.iter_mut().zip([config, velocity]) {
        if let syn::FnArg::Typed(pt) = input {
            *pt.ty = syn::parse_quote!(#ty);
        }
    }
    let allow = lints::user_function();
    quote! {
        #allow
        #[allow(dead_code, reason = "the step reads L through the compiled L_d; the function stays callable")]
        #func
    }
}

/// `<Name>Velocity`: what a continuous Lagrangian's `v` holds.
fn velocity_struct(spec: &LieSpec, func: &ItemFn, ty: &Ident, velocity: &Ident) -> TokenStream {
    let vis = &func.vis;
    let na = quote!(::dirac::nalgebra);
    let paths = Paths {
        na: na.clone(),
        rt: quote!(::dirac::runtime),
    };
    let fields = spec.coords.iter().map(|c| {
        let name = &c.name;
        let (field, doc) = c.kind.velocity_field(&paths, name, ty);
        quote!(#[doc = #doc] pub #name: #field)
    });
    let doc = format!("A velocity of [`{ty}`], as its continuous Lagrangian reads it.");
    quote! {
        #[doc = #doc]
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #[allow(non_snake_case, reason = "velocities keep the names of their coordinates")]
        #vis struct #velocity {
            #( #fields, )*
        }
    }
}

/// The three step methods of a [`SteppedFns`] — `{prefix}residual`, `{prefix}residual_jacobian`
/// and `{prefix}momentum` over `(q_k, p_k, z)` — for the unreduced step (`""`) and the reduced
/// one (`"reduced_"`).
fn step_methods(prefix: &str, fns: &SteppedFns, p: usize, n: usize) -> TokenStream {
    let na = quote!(::dirac::nalgebra);
    let matrix = fns.backend.matrix_type(n);
    let (residual, residual_jacobian, momentum) =
        (&fns.residual, &fns.residual_jacobian, &fns.momentum);
    let name = |what: &str| format_ident!("{prefix}{what}");
    let (r, rj, m) = (
        name("residual"),
        name("residual_jacobian"),
        name("momentum"),
    );
    let args = quote! {
        &self,
        q_k: &#na::SVector<f64, #p>,
        p_k: &#na::SVector<f64, #n>,
        z: &#na::SVector<f64, #n>,
    };
    quote! {
        #[allow(unused_variables, reason = "a step function need not read all of its inputs (a reduced step drops the rotation it removes, only group momenta read p_k)")]
        fn #r(#args) -> #na::SVector<f64, #n> {
            #residual
        }

        #[allow(unused_variables, reason = "a step function need not read all of its inputs (a reduced step drops the rotation it removes, only group momenta read p_k)")]
        fn #rj(#args) -> (#na::SVector<f64, #n>, #matrix) {
            #residual_jacobian
        }

        #[allow(unused_variables, reason = "a step function need not read all of its inputs (a reduced step drops the rotation it removes, only group momenta read p_k)")]
        fn #m(#args) -> #na::SVector<f64, #n> {
            #momentum
        }
    }
}
