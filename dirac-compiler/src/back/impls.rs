//! The one table of the trait implementations the attributes emit: each impl's header, its
//! associated types and constants, and its method signatures, written once and rendered twice —
//! with the compiler's bodies ([`Bodies::Real`]), or, after an error, with bodies that are never
//! reached ([`Bodies::Stub`]) so that the user's other code still type-checks and the user sees
//! the real error, not a cascade of follow-on ones (thiserror's `fallback.rs`). A stub cannot
//! drift from the impl it stands in for: both come from the same entry.
//!
//! What an entry depends on — the dimensions, the backend (see [`Backend`]), whether the
//! Lagrangian is continuous — is known from the attribute and the signature alone, before the
//! body is compiled; only the bodies (and a few computed constants) need the compiled graph.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;
use syn::Ident;

use crate::back::backend::Backend;
use crate::back::lints;
use crate::ir::reduce::Side;

/// What every emitted impl shares: the type, the dimensions, the paths, how parameters are read.
pub struct Target<'a> {
    /// The emitted type.
    pub ty: Ident,
    /// Number of shape coordinates `S`.
    pub s: usize,
    /// Number of group coordinates `K`.
    pub k: usize,
    /// `N = S + K`.
    pub n: usize,
    /// The parameters, fields of the emitted type (the time step last when it is not an argument).
    pub params: &'a [Ident],
    /// `::dirac::runtime`.
    pub rt: TokenStream,
    /// `::dirac::nalgebra`.
    pub na: TokenStream,
}

impl<'a> Target<'a> {
    /// The target of a system with `s` shape and `k` group coordinates.
    pub fn new(ty: Ident, s: usize, k: usize, params: &'a [Ident]) -> Self {
        Target {
            ty,
            s,
            k,
            n: s + k,
            params,
            rt: quote!(::dirac::runtime),
            na: quote!(::dirac::nalgebra),
        }
    }

    /// `self.<parameter i>`.
    pub fn param_leaf(&self, i: usize) -> TokenStream {
        let p = &self.params[i];
        quote! { self.#p }
    }

    /// `&SVector<f64, d>`.
    pub fn vec(&self, d: usize) -> TokenStream {
        let na = &self.na;
        quote!(&#na::SVector<f64, #d>)
    }
}

/// One impl block of the table.
pub struct ImplBlock {
    /// Attributes of the block (lint allowances, `#[automatically_derived]`).
    pub attrs: TokenStream,
    /// `impl Trait<..> for Type`, or `impl Type` for inherent items.
    pub header: TokenStream,
    /// The items, in the order they are emitted.
    pub items: Vec<Item>,
}

/// One item of an impl block.
pub struct Item {
    /// The key of its body in [`Bodies::Real`].
    pub name: &'static str,
    /// What it is.
    pub kind: Kind,
}

/// The kinds of items.
pub enum Kind {
    /// An associated type or constant known from the attribute alone: the same in both renderings.
    Fixed(TokenStream),
    /// A constant the compiler computes: `decl = <value>;`. A stub renders `stub` in its place, or
    /// leaves it to the trait's default when `stub` is `None` (and so does the real rendering
    /// when the compiler supplies no value). With `documented`, the value (a string literal) is
    /// also the constant's documentation.
    Const {
        /// `const NAME: Type`, with its visibility.
        decl: TokenStream,
        /// The stub's value, or `None` to use the trait's default.
        stub: Option<TokenStream>,
        /// Whether the value is also the item's `#[doc]`.
        documented: bool,
    },
    /// A method: its attributes and signature. A `provided` method has a default body in the
    /// trait: it is emitted only when the compiler supplies a body, and never as a stub.
    Method {
        /// Attributes on the method.
        attrs: TokenStream,
        /// `fn name(&self, ..) -> Type`.
        sig: TokenStream,
        /// Whether the trait provides a default body.
        provided: bool,
    },
}

/// The bodies an [`ImplBlock`] is rendered with.
pub enum Bodies {
    /// The compiler's bodies and computed constants, by item name.
    Real(HashMap<&'static str, TokenStream>),
    /// After an error: bodies that are never reached, naming the attribute that failed.
    Stub(&'static str),
}

impl ImplBlock {
    /// The block with `bodies`. A required method without a real body is a bug of the compiler,
    /// reported as a panic (never a user's mistake: every required body is generated).
    pub fn render(&self, bodies: &Bodies) -> TokenStream {
        let mut items = TokenStream::new();
        for item in &self.items {
            let real = match bodies {
                Bodies::Real(map) => Some(map.get(item.name)),
                Bodies::Stub(_) => None,
            };
            match (&item.kind, real) {
                (Kind::Fixed(tokens), _) => items.extend(tokens.clone()),
                (
                    Kind::Const {
                        decl, documented, ..
                    },
                    Some(Some(value)),
                ) => {
                    let doc = documented.then(|| quote!(#[doc = #value]));
                    items.extend(quote! { #doc #decl = #value; });
                }
                (Kind::Const { .. }, Some(None)) => {}
                (
                    Kind::Const {
                        decl,
                        stub,
                        documented,
                    },
                    None,
                ) => {
                    if let Some(value) = stub {
                        let doc = documented.then(|| quote!(#[doc = #value]));
                        items.extend(quote! { #doc #decl = #value; });
                    }
                }
                (Kind::Method { attrs, sig, .. }, Some(Some(body))) => {
                    items.extend(quote! { #attrs #sig { #body } });
                }
                (Kind::Method { provided: true, .. }, _) => {}
                (Kind::Method { .. }, Some(None)) => {
                    panic!("dirac-compiler: no body generated for `{}`", item.name)
                }
                (Kind::Method { attrs, sig, .. }, None) => {
                    let Bodies::Stub(attribute) = bodies else {
                        unreachable!("only stubs have no body map")
                    };
                    let message = format!("`#[{attribute}]` reported an error");
                    items.extend(quote! { #attrs #sig { ::core::unreachable!(#message) } });
                }
            }
        }
        let (attrs, header) = (&self.attrs, &self.header);
        // A stub ignores its arguments.
        let stub_allow =
            matches!(bodies, Bodies::Stub(_)).then(|| quote!(#[allow(unused_variables)]));
        quote! {
            #attrs
            #stub_allow
            #header {
                #items
            }
        }
    }
}

fn fixed(name: &'static str, tokens: TokenStream) -> Item {
    Item {
        name,
        kind: Kind::Fixed(tokens),
    }
}

fn method(name: &'static str, attrs: TokenStream, sig: TokenStream) -> Item {
    Item {
        name,
        kind: Kind::Method {
            attrs,
            sig,
            provided: false,
        },
    }
}

fn provided(name: &'static str, attrs: TokenStream, sig: TokenStream) -> Item {
    Item {
        name,
        kind: Kind::Method {
            attrs,
            sig,
            provided: true,
        },
    }
}

/// `#[allow(unused_variables)]` with its reason, for a generated body that may not read every
/// argument.
fn unused(reason: &str) -> TokenStream {
    quote!(#[allow(unused_variables, reason = #reason)])
}

/// The stub value of `GENERATED`.
pub const NOTHING_GENERATED: &str = "Nothing: `#[reduced_lagrangian]` reported an error.";

/// `impl Type { SHAPE_DIM, GROUP_DIM, CONFIG_DIM, GENERATED }`.
pub fn inherent(t: &Target) -> ImplBlock {
    let (ty, s, k, n) = (&t.ty, t.s, t.k, t.n);
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl #ty),
        items: vec![
            fixed(
                "SHAPE_DIM",
                quote! {
                    /// Number of shape coordinates `S` (the first const parameter of the system
                    /// traits, and the length of `ReducedState::x`).
                    pub const SHAPE_DIM: usize = #s;
                },
            ),
            fixed(
                "GROUP_DIM",
                quote! {
                    /// Number of group coordinates `K` (the second const parameter of the system
                    /// traits, and the length of `ReducedState::mu`).
                    pub const GROUP_DIM: usize = #k;
                },
            ),
            fixed(
                "CONFIG_DIM",
                quote! {
                    /// Number of configuration coordinates `N = S + K` (the third const
                    /// parameter of the system traits, and the length of `UnreducedState::q`).
                    pub const CONFIG_DIM: usize = #n;
                },
            ),
            Item {
                name: "GENERATED",
                kind: Kind::Const {
                    decl: quote!(pub const GENERATED: &'static str),
                    stub: Some(quote!(#NOTHING_GENERATED)),
                    documented: true,
                },
            },
        ],
    }
}

/// `impl DiscreteLagrangian<S, K, N>`: the flat family's items (the system model's are
/// [`system`]'s); `adaptive` adds the monitor and the adaptive steps' helpers.
pub fn discrete_lagrangian(
    t: &Target,
    shape: &[String],
    group: &[String],
    forced: bool,
    adaptive: bool,
) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let vn = t.vec(n);
    let mut block = ImplBlock {
        attrs: generated_derived(),
        header: quote!(impl #rt::DiscreteLagrangian<#s, #k, #n> for #ty),
        items: vec![
            fixed(
                "SHAPE",
                quote!(const SHAPE: [&'static str; #s] = [ #( #shape ),* ];),
            ),
            fixed(
                "GROUP",
                quote!(const GROUP: [&'static str; #k] = [ #( #group ),* ];),
            ),
            fixed("FORCED", quote!(const FORCED: bool = #forced;)),
            method(
                "lagrangian",
                quote!(),
                quote!(fn lagrangian(&self, q0: #vn, q1: #vn) -> f64),
            ),
            method(
                "connection",
                quote!(),
                quote!(fn connection(&self) -> #na::SMatrix<f64, #k, #s>),
            ),
        ],
    };
    // Adaptive steps: the monitor (the time coordinate is the system model's).
    if adaptive {
        let vs = t.vec(s);
        block.items.push(method(
            "monitor",
            quote!(#[allow(unused_variables)]), // a monitor need not read every coordinate
            quote!(fn monitor(&self, x: #vs) -> ::core::option::Option<f64>),
        ));
        block.items.push(method(
            "adaptive_increment",
            quote!(),
            quote!(fn adaptive_increment(&self, q: #vn, p: #vn, h: f64) -> ::core::option::Option<#na::SVector<f64, #n>>),
        ));
        block.items.push(method(
            "level_set_defect",
            quote!(),
            quote!(fn level_set_defect(&self, q: #vn, p: #vn) -> ::core::option::Option<(f64, f64)>),
        ));
    }
    block
}

/// What every family's emitted type declares of the one system model
/// (`dirac::runtime::model::System`): the fields that hold the parameters, the time step and the
/// controls, the coordinates' names, the time coordinate of adaptive steps and the domain.
pub struct Model<'a> {
    /// The parameters, fields of the emitted type, in declaration order.
    pub params: &'a [Ident],
    /// The time-step parameter.
    pub step: &'a Ident,
    /// The controls (`controls(..)`), in the order a control vector lists them.
    pub controls: &'a [Ident],
    /// The names of the coordinates, in the order of the configuration.
    pub coordinates: Vec<String>,
    /// Adaptive steps: the index of the time coordinate in the family's list.
    pub time: Option<usize>,
    /// The declared bounds (`domain(..)`), empty for none.
    pub domain: &'a [crate::front::attr::DomainBound],
}

/// `impl System for Type`, the one impl of the system model every family emits (flat, on
/// rotation groups, element-wise): its table entry, for real and stub bodies alike.
pub fn system(ty: &Ident, model: &Model) -> ImplBlock {
    let rt = quote!(::dirac::runtime);
    let params: Vec<String> = model.params.iter().map(Ident::to_string).collect();
    let controls: Vec<String> = model.controls.iter().map(Ident::to_string).collect();
    let mut items = vec![
        fixed(
            "PARAMETERS",
            quote!(const PARAMETERS: &'static [&'static str] = &[ #( #params ),* ];),
        ),
        fixed(
            "CONTROLS",
            quote!(const CONTROLS: &'static [&'static str] = &[ #( #controls ),* ];),
        ),
    ];
    if let Some(j) = model.time {
        items.push(fixed(
            "TIME",
            quote!(const TIME: ::core::option::Option<usize> = ::core::option::Option::Some(#j);),
        ));
    }
    if !model.domain.is_empty() {
        let bounds = model.domain.iter().map(|b| {
            let (i, relation) = (b.coordinate, quote::format_ident!("{}", b.relation.name()));
            let magnitude = proc_macro2::Literal::f64_unsuffixed(b.value.abs());
            let value = if b.value.is_sign_negative() {
                quote!(-#magnitude)
            } else {
                quote!(#magnitude)
            };
            quote!(#rt::domain::Bound::new(#i, #rt::domain::Relation::#relation, #value))
        });
        items.push(fixed(
            "DOMAIN",
            quote!(const DOMAIN: &'static [#rt::domain::Bound] = &[ #( #bounds ),* ];),
        ));
    }
    let ignores_u = if model.controls.is_empty() {
        unused("a system without controls ignores `u`")
    } else {
        quote!()
    };
    items.extend([
        method(
            "parameter_values",
            quote!(),
            quote!(fn parameter_values(&self) -> ::std::vec::Vec<f64>),
        ),
        method("time_step", quote!(), quote!(fn time_step(&self) -> f64)),
        method(
            "with_time_step",
            quote!(),
            quote!(fn with_time_step(&self, h: f64) -> Self),
        ),
        method(
            "with_controls",
            ignores_u,
            quote!(fn with_controls(&self, u: &[f64]) -> Self),
        ),
        method(
            "coordinate_names",
            quote!(),
            quote!(fn coordinate_names(&self) -> ::std::vec::Vec<&str>),
        ),
    ]);
    ImplBlock {
        attrs: generated_derived(),
        header: quote!(impl #rt::System for #ty),
        items,
    }
}

/// The bodies of [`system`]'s methods: the emitted types hold their parameters as `f64` fields
/// and are `Copy`, so the system at another step or with other controls is a copy with fields
/// set.
pub fn system_bodies(model: &Model) -> HashMap<&'static str, TokenStream> {
    let (params, step, names) = (model.params, model.step, &model.coordinates);
    let with_controls = if model.controls.is_empty() {
        quote! { *self }
    } else {
        let (controls, index) = (model.controls, 0..model.controls.len());
        quote! {
            let mut system = *self;
            #( system.#controls = u[#index]; )*
            system
        }
    };
    HashMap::from([
        (
            "parameter_values",
            quote! { ::std::vec![ #( self.#params ),* ] },
        ),
        ("time_step", quote! { self.#step }),
        (
            "with_time_step",
            quote! {
                let mut system = *self;
                system.#step = h;
                system
            },
        ),
        ("with_controls", with_controls),
        ("coordinate_names", quote! { ::std::vec![ #( #names ),* ] }),
    ])
}

/// `impl System` with its bodies: what the families that render no stubs (on rotation groups,
/// element-wise) emit.
pub fn system_impl(ty: &Ident, model: &Model) -> TokenStream {
    system(ty, model).render(&Bodies::Real(system_bodies(model)))
}

/// `impl Reduced<Side, S, K, N>`, one side, on `backend`.
pub fn reduced(t: &Target, side: Side, backend: &Backend) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let (vs, vk, vn) = (t.vec(s), t.vec(k), t.vec(n));
    let marker = match side {
        Side::Plus => quote!(#rt::Plus),
        Side::Minus => quote!(#rt::Minus),
    };
    let (jt, st) = (backend.matrix_type(n), backend.solver_type(n));
    let inline = quote!(#[inline]);
    let closed_form = {
        let allow = quote!(#[allow(unused_variables)]);
        quote!(#[inline] #allow // a closed form need not read every input
        )
    };
    ImplBlock {
        attrs: generated_derived(),
        header: quote!(impl #rt::Reduced<#marker, #s, #k, #n> for #ty),
        items: vec![
            fixed("Linear", quote!(type Linear = #st;)),
            method(
                "linear_solver",
                quote!(),
                quote!(fn linear_solver(&self) -> #st),
            ),
            method(
                "reduced_lagrangian",
                quote!(#[allow(unused_variables)]), // a Lagrangian need not read every coordinate
                quote!(fn reduced_lagrangian(&self, x0: #vs, x1: #vs, u: #vk) -> f64),
            ),
            method(
                "residual",
                inline.clone(),
                quote!(fn residual(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn) -> #na::SVector<f64, #n>),
            ),
            method(
                "residual_jacobian",
                inline.clone(),
                quote!(fn residual_jacobian(
                    &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn,
                ) -> (#na::SVector<f64, #n>, #jt)),
            ),
            method(
                "momentum",
                inline.clone(),
                quote!(fn momentum(&self, x_k: #vs, z: #vn) -> #na::SVector<f64, #s>),
            ),
            provided(
                "residual_momentum",
                quote!(#[inline] #[allow(unused_variables)]), // the momentum update need not read every input
                quote!(fn residual_momentum(
                    &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn,
                ) -> (#na::SVector<f64, #n>, #na::SVector<f64, #s>)),
            ),
            Item {
                name: "GROUP_FORCED",
                kind: Kind::Const {
                    decl: quote!(const GROUP_FORCED: bool),
                    stub: None,
                    documented: false,
                },
            },
            provided(
                "group_impulse",
                closed_form.clone(),
                quote!(fn group_impulse(&self, x_k: #vs, z: #vn) -> #na::SVector<f64, #k>),
            ),
            provided(
                "step_partials",
                closed_form.clone(),
                quote!(fn step_partials(
                    &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn, out: &mut #rt::StepPartials,
                ) -> bool),
            ),
            Item {
                name: "ELIMINATES_GROUP",
                kind: Kind::Const {
                    decl: quote!(const ELIMINATES_GROUP: bool),
                    stub: None,
                    documented: false,
                },
            },
            Item {
                name: "ELIMINATION_PAYS",
                kind: Kind::Const {
                    decl: quote!(const ELIMINATION_PAYS: bool),
                    stub: None,
                    documented: false,
                },
            },
            provided(
                "eliminated_residual",
                closed_form.clone(),
                quote!(fn eliminated_residual(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs) -> ::core::option::Option<#na::SVector<f64, #s>>),
            ),
            provided(
                "eliminated_residual_jacobian",
                closed_form.clone(),
                quote!(fn eliminated_residual_jacobian(
                    &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs,
                ) -> ::core::option::Option<(#na::SVector<f64, #s>, #na::SMatrix<f64, #s, #s>)>),
            ),
            provided(
                "eliminated_group",
                closed_form.clone(),
                quote!(fn eliminated_group(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs) -> ::core::option::Option<#na::SVector<f64, #k>>),
            ),
            provided(
                "eliminated_group_block",
                closed_form,
                quote!(fn eliminated_group_block(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs) -> ::core::option::Option<#na::SMatrix<f64, #k, #k>>),
            ),
        ],
    }
}

/// `impl Unreduced<S, K, N>` on `backend`.
pub fn unreduced(t: &Target, backend: &Backend) -> ImplBlock {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    let vn = t.vec(n);
    let (jt, st) = (backend.matrix_type(n), backend.solver_type(n));
    let inline = quote!(#[inline]);
    ImplBlock {
        attrs: generated_derived(),
        header: quote!(impl #rt::Unreduced<#s, #k, #n> for #ty),
        items: vec![
            fixed("UnreducedLinear", quote!(type UnreducedLinear = #st;)),
            method(
                "unreduced_linear_solver",
                quote!(),
                quote!(fn unreduced_linear_solver(&self) -> #st),
            ),
            method(
                "unreduced_residual",
                inline.clone(),
                quote!(fn unreduced_residual(&self, q_k: #vn, p_k: #vn, z: #vn) -> #na::SVector<f64, #n>),
            ),
            method(
                "unreduced_residual_jacobian",
                inline.clone(),
                quote!(fn unreduced_residual_jacobian(
                    &self, q_k: #vn, p_k: #vn, z: #vn,
                ) -> (#na::SVector<f64, #n>, #jt)),
            ),
            method(
                "unreduced_momentum",
                inline,
                quote!(fn unreduced_momentum(&self, q_k: #vn, z: #vn) -> #na::SVector<f64, #n>),
            ),
            provided(
                "unreduced_step_partials",
                quote!(#[allow(unused_variables)]), // partials need not read every input
                quote!(fn unreduced_step_partials(
                    &self, q_k: #vn, p_k: #vn, z: #vn, out: &mut #rt::StepPartials,
                ) -> bool),
            ),
        ],
    }
}

/// `impl LagrangianHessian<S, K, N>`: dense systems only (see [`Backend`]), `None` otherwise, in
/// the real rendering and the stub alike.
pub fn lagrangian_hessian(t: &Target) -> Option<ImplBlock> {
    let (ty, s, k, n, rt, na) = (&t.ty, t.s, t.k, t.n, &t.rt, &t.na);
    if !Backend::for_size(n).is_dense() {
        return None;
    }
    let vn = t.vec(n);
    Some(ImplBlock {
        attrs: generated_derived(),
        header: quote!(impl #rt::LagrangianHessian<#s, #k, #n> for #ty),
        items: vec![method(
            "lagrangian_hessian",
            quote!(#[allow(unused_variables)]), // a Lagrangian need not read every coordinate
            quote!(fn lagrangian_hessian(
                &self, q0: #vn, q1: #vn,
            ) -> (#na::SMatrix<f64, #n, #n>, #na::SMatrix<f64, #n, #n>, #na::SMatrix<f64, #n, #n>)),
        )],
    })
}

/// `impl ContinuousLagrangian<N>` of a continuous Lagrangian, with the Legendre map's Jacobian on
/// `backend`.
/// `impl StageDerivatives<N>`: what a Gauss–Legendre step evaluates at its stages (a
/// continuous Lagrangian on the dense backend without constraints).
pub fn stage_derivatives(t: &Target) -> ImplBlock {
    let (ty, n, rt, na) = (&t.ty, t.n, &t.rt, &t.na);
    let vn = t.vec(n);
    let allow = lints::generated();
    let unused = unused("L need not read every coordinate and velocity");
    ImplBlock {
        attrs: quote!(#allow #unused),
        header: quote!(impl #rt::StageDerivatives<#n> for #ty),
        items: vec![
            method(
                "stage",
                quote!(),
                quote!(fn stage(&self, q: #vn, v: #vn) -> (#na::SVector<f64, #n>, #na::SVector<f64, #n>)),
            ),
            method(
                "stage_jacobian",
                quote!(),
                quote!(fn stage_jacobian(&self, q: #vn, v: #vn) -> #rt::StageJacobian<#n>),
            ),
        ],
    }
}

pub fn continuous_lagrangian(t: &Target, rule: &str, backend: &Backend) -> ImplBlock {
    let (ty, n, rt, na) = (&t.ty, t.n, &t.rt, &t.na);
    let vn = t.vec(n);
    let (jt, st) = (backend.matrix_type(n), backend.solver_type(n));
    let allow = lints::generated();
    let unused = unused("L need not read every coordinate and velocity");
    ImplBlock {
        attrs: quote!(#allow #unused),
        header: quote!(impl #rt::ContinuousLagrangian<#n> for #ty),
        items: vec![
            fixed("RULE", quote!(const RULE: &'static str = #rule;)),
            method(
                "continuous_lagrangian",
                quote!(),
                quote!(fn continuous_lagrangian(&self, q: #vn, v: #vn) -> f64),
            ),
            method(
                "legendre",
                quote!(),
                quote!(fn legendre(&self, q: #vn, v: #vn) -> #na::SVector<f64, #n>),
            ),
            fixed("LegendreLinear", quote!(type LegendreLinear = #st;)),
            method(
                "legendre_solver",
                quote!(),
                quote!(fn legendre_solver(&self) -> #st),
            ),
            method(
                "legendre_jacobian",
                quote!(),
                quote!(fn legendre_jacobian(&self, q: #vn, v: #vn) -> (#na::SVector<f64, #n>, #jt)),
            ),
            method(
                "energy",
                quote!(),
                quote!(fn energy(&self, q: #vn, v: #vn) -> f64),
            ),
        ],
    }
}

/// `impl Type { FROM, TO }` of a chart transition.
pub fn transition_inherent(ty: &Ident, from: &[String], to: &[String]) -> ImplBlock {
    let n = from.len();
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl #ty),
        items: vec![
            fixed(
                "FROM",
                quote! {
                    /// The coordinates of the old chart, shape then group.
                    pub const FROM: [&'static str; #n] = [ #( #from ),* ];
                },
            ),
            fixed(
                "TO",
                quote! {
                    /// The coordinates of the new chart, shape then group.
                    pub const TO: [&'static str; #n] = [ #( #to ),* ];
                },
            ),
        ],
    }
}

/// `impl ChartTransition<S, K, N>`.
pub fn chart_transition(ty: &Ident, s: usize, k: usize) -> ImplBlock {
    let n = s + k;
    let na = quote!(::dirac::nalgebra);
    let unused = quote!(#[allow(unused_variables)]); // a coordinate the map does not need is still read
    ImplBlock {
        attrs: lints::generated(),
        header: quote!(impl ::dirac::runtime::atlas::ChartTransition<#s, #k, #n> for #ty),
        items: vec![
            method(
                "map",
                unused.clone(),
                quote!(fn map(&self, q: &#na::SVector<f64, #n>) -> #na::SVector<f64, #n>),
            ),
            method(
                "map_jacobian",
                unused,
                quote!(fn map_jacobian(
                    &self,
                    q: &#na::SVector<f64, #n>,
                ) -> (#na::SVector<f64, #n>, #na::SMatrix<f64, #n, #n>)),
            ),
        ],
    }
}

/// The lint allowances and `#[automatically_derived]` of a system trait impl.
fn generated_derived() -> TokenStream {
    let allow = lints::generated();
    quote! {
        #allow
        #[automatically_derived]
    }
}
