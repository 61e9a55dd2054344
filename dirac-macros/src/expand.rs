//! Ties the stages together and assembles the emitted items: the configuration struct, the
//! user's function (still callable), the parameter struct, and the trait implementations the
//! runtime drives.

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote};
use syn::parse::Parser;
use syn::{Ident, ItemFn};

use crate::adapted;
use crate::check;
use crate::continuous;
use crate::ctxt::Ctxt;
use crate::emit::straight_line;
use crate::graph::{Graph, Node, NodeId, Sym};
use crate::lints;
use crate::lower::{Lowering, Names};
use crate::reduce::{
    eliminate_group, lagrangian_hessian, reduced_lagrangian, reduced_stepper, unreduced_stepper,
    Eliminated, Side, Stepper, GROUP_ORIGINS,
};
use crate::spec::{parse_signature, parse_spec, resolve_ranges, Coord, Signature, Spec};

/// Systems with at most this many configuration coordinates get the dense fixed-size backend
/// (`Lu<N>`, everything on the stack); larger ones the sparse backend (`SparseLu` on the
/// compile-time pattern of the step Jacobian), and no Hessian impl or momentum-level elimination
/// (whose `S × S` matrices are dense). Equal to `dirac_runtime::DENSE_MAX`, which documents the
/// choice (checked by `tests/backends.rs`).
pub const DENSE_MAX: usize = 16;

pub fn expand(args: TokenStream, item: TokenStream) -> TokenStream {
    let func: ItemFn = match syn::parse2(item) {
        Ok(f) => f,
        Err(e) => {
            let mut e = e;
            e.combine(syn::Error::new(
                Span::call_site(),
                "`#[reduced_lagrangian]` applies to a function `fn name(q0: Config, q1: Config, h: f64, ...) -> f64`",
            ));
            return e.into_compile_error();
        }
    };
    let cx = Ctxt::default();
    let spec = parse_spec(&cx, args);
    let sig = parse_signature(
        &cx,
        &func.sig,
        spec.as_ref().and_then(|s| s.step.as_ref()),
        spec.as_ref().and_then(|s| s.rule.as_ref()),
        spec.as_ref().is_some_and(|s| s.rule_written),
    );
    let compiled = match (&spec, &sig) {
        (Some(spec), Some(sig)) => compile(&cx, spec, sig, &func),
        _ => None,
    };
    match (cx.into_result(), spec, sig, compiled) {
        (Ok(()), Some(spec), Some(sig), Some(compiled)) => generate(&spec, &sig, &func, &compiled),
        (Err(errors), spec, sig, _) => {
            let mut out = errors.into_compile_error();
            out.extend(fallback(spec.as_ref(), sig.as_ref(), &func));
            out
        }
        _ => unreachable!("every failed stage records an error"),
    }
}

/// The graph and its roots.
struct Compiled {
    graph: Graph,
    /// `L_d(q0, q1)`, the lowered body.
    body: NodeId,
    /// Rows of the connection matrix `B`.
    b: Vec<Vec<NodeId>>,
    /// The reduced (+) equations, eq. (4.6).
    plus: SideCode,
    /// The reduced (−) equations, eq. (4.8) with the signs of Definition 2.8.
    minus: SideCode,
    /// The unreduced stepper, Definitions 2.7/2.8.
    unreduced: Stepper,
    /// `(D11, D12, D22)` of `L_d`, for the step-map Jacobian (dense systems only).
    hessian: Option<[Vec<Vec<NodeId>>; 3]>,
    /// The Legendre map and energy of a continuous Lagrangian.
    continuous: Option<continuous::Continuous>,
}

/// What one side of the reduced equations compiles to.
struct SideCode {
    side: Side,
    /// The reduced Lagrangian at the paper's group origin (`α = 0`: eqs. (4.5), (4.7)).
    lagrangian: NodeId,
    /// The general stepper, at the group origin with the least code.
    stepper: Stepper,
    /// The stepper with its group unknowns eliminated, when they enter affinely.
    eliminated: Option<Eliminated>,
    /// Whether the eliminated stepper is the better default (no more code than the general).
    elimination_pays: bool,
}

fn compile(cx: &Ctxt, spec: &Spec, sig: &Signature, func: &ItemFn) -> Option<Compiled> {
    let names = Names {
        q0: &sig.q0,
        q1: &sig.q1,
        coords: spec.layout.lowering_coords(),
        params: sig.params.iter().map(Ident::to_string).collect(),
    };
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let ranges = resolve_ranges(cx, spec, sig);
    if !spec.lengths_ok {
        // A bad array length (reported) would make every index into it a follow-on error.
        return None;
    }
    let mut graph = Graph::default();
    let body = Lowering::new(&mut graph, cx, &names).body(&func.block);
    // A continuous L(q, v): keep it for the Legendre map and energy, and form L_d by the rule.
    let (body, continuous) = match (body, spec.rule.as_ref().filter(|_| sig.continuous)) {
        (Some(l), Some(&(_, rule))) => {
            let step = sig.params.iter().position(|p| *p == sig.step);
            let h = graph.var(Sym::Param(step.expect("the step is a parameter")));
            let parts = continuous::continuous(&mut graph, l, s + k, rule);
            (
                Some(continuous::discretize(&mut graph, l, s + k, h, rule)),
                Some(parts),
            )
        }
        (body, _) => (body, None),
    };
    let b: Option<Vec<Vec<NodeId>>> = match &spec.connection {
        None => {
            let zero = graph.constant(0.0);
            Some(vec![vec![zero; s]; k])
        }
        Some(rows) => rows
            .iter()
            .map(|row| {
                row.iter()
                    .map(|e| Lowering::new(&mut graph, cx, &names).constant_entry(e))
                    .collect()
            })
            .collect(),
    };
    let (body, b) = (body?, b?);
    if cx.has_errors() {
        return None;
    }
    // The reduction below is only valid for a G-invariant L_d.
    check::check(cx, &graph, body, &b, spec, sig, &ranges, &func.block);
    if cx.has_errors() {
        return None;
    }
    // The reduced Lagrangians (4.5), (4.7) with the group origin α that gives the least
    // straight-line code: by G-invariance every α gives the same function (eq. (4.5) is α = 0),
    // but e.g. a midpoint rule at α = ½ no longer carries the group unknown through its
    // trigonometric terms. Ties go to the paper's α = 0.
    let build = |side: Side| {
        let b = &b;
        move |g: &mut Graph, alpha: f64| {
            let l = reduced_lagrangian(g, side, body, s, b, alpha);
            reduced_stepper(g, side, l, s, k)
        }
    };
    let plus = cheapest(&mut graph, build(Side::Plus));
    let minus = cheapest(&mut graph, build(Side::Minus));
    let unreduced = unreduced_stepper(&mut graph, body, s + k);
    let dense = s + k <= DENSE_MAX;
    let hessian = dense.then(|| lagrangian_hessian(&mut graph, body, s + k));
    // Elimination: the cheapest origin at which the momentum equations are structurally affine
    // (dense systems only: its shape Jacobian is a dense `S × S` matrix).
    let (plus_eliminated, minus_eliminated) = if dense {
        (
            cheapest_eliminated(&mut graph, Side::Plus, s, k, build(Side::Plus)),
            cheapest_eliminated(&mut graph, Side::Minus, s, k, build(Side::Minus)),
        )
    } else {
        (None, None)
    };
    // Use the elimination by default only where it does not cost more code per Newton iteration
    // than the general path (10% slack: it also shrinks the linear solve and, for the paper's charged
    // particle, makes each step linear). Substituting the closed form and differentiating through
    // it can make the shape Jacobian larger than the full one — measured on the double spherical
    // pendulum: 913 against 745 operations, and 12% slower.
    let pays = |e: &Option<Eliminated>, full: &Stepper, g: &Graph| {
        e.as_ref().is_some_and(|e| {
            10 * cost(g, &e.residual, &e.jacobian) <= 11 * cost(g, &full.residual, &full.jacobian)
        })
    };
    let side_code = |graph: &mut Graph, side, stepper, eliminated| {
        let elimination_pays = pays(&eliminated, &stepper, graph);
        // Built last, so the nodes of the steppers above keep their numbers (and names).
        let lagrangian = reduced_lagrangian(graph, side, body, s, &b, 0.0);
        SideCode {
            side,
            lagrangian,
            stepper,
            eliminated,
            elimination_pays,
        }
    };
    let plus = side_code(&mut graph, Side::Plus, plus, plus_eliminated);
    let minus = side_code(&mut graph, Side::Minus, minus, minus_eliminated);
    Some(Compiled {
        graph,
        body,
        b,
        plus,
        minus,
        unreduced,
        hessian,
        continuous,
    })
}

/// Operations in the straight line that computes a residual and its Jacobian together.
fn cost(g: &Graph, residual: &[NodeId], jacobian: &[Vec<NodeId>]) -> usize {
    let roots: Vec<NodeId> = residual
        .iter()
        .chain(jacobian.iter().flatten())
        .copied()
        .collect();
    g.cone(&roots)
        .into_iter()
        .filter(|&n| !matches!(g.node(n), Node::Const(_) | Node::Var(_)))
        .count()
}

/// The stepper built at the group origin (see [`GROUP_ORIGINS`]) with the least code.
fn cheapest(g: &mut Graph, build: impl Fn(&mut Graph, f64) -> Stepper) -> Stepper {
    let candidates: Vec<Stepper> = GROUP_ORIGINS.iter().map(|&alpha| build(g, alpha)).collect();
    candidates
        .into_iter()
        .min_by_key(|st| cost(g, &st.residual, &st.jacobian))
        .expect("at least one group origin")
}

/// The eliminated stepper with the least code over the group origins where elimination applies.
fn cheapest_eliminated(
    g: &mut Graph,
    side: Side,
    s: usize,
    k: usize,
    build: impl Fn(&mut Graph, f64) -> Stepper,
) -> Option<Eliminated> {
    let candidates: Vec<Eliminated> = GROUP_ORIGINS
        .iter()
        .filter_map(|&alpha| {
            let st = build(g, alpha);
            eliminate_group(g, side, &st, s, k)
        })
        .collect();
    candidates
        .into_iter()
        .min_by_key(|e| cost(g, &e.residual, &e.jacobian))
}

fn type_name(spec: &Spec, func: &ItemFn) -> Ident {
    if let Some(name) = &spec.name {
        return name.clone();
    }
    let camel: String = func
        .sig
        .ident
        .to_string()
        .split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
        })
        .collect();
    Ident::new(&camel, func.sig.ident.span())
}

/// The user's function with `Config` replaced by the emitted configuration struct.
fn user_function(
    func: &ItemFn,
    config: &Ident,
    stub: bool,
    touch: &[Ident],
    indexed: bool,
) -> TokenStream {
    let mut func = func.clone();
    // Parameters that only the connection matrix reads are still parameters of the function;
    // mark them used there so the user does not get an unused-variable warning.
    for p in touch.iter().rev() {
        func.block.stmts.insert(0, syn::parse_quote!(let _ = #p;));
    }
    for input in func.sig.inputs.iter_mut().take(2) {
        if let syn::FnArg::Typed(pt) = input {
            *pt.ty = syn::parse_quote!(#config);
        }
    }
    let mut allow = lints::user_function();
    if indexed {
        allow.extend(lints::user_function_indexed());
    }
    func.attrs.extend(
        syn::Attribute::parse_outer
            .parse2(allow)
            .expect("attributes parse"),
    );
    if stub {
        // The body was rejected: keep the signature so callers type-check, without follow-on
        // warnings about the arguments the stub ignores.
        func.attrs
            .push(syn::parse_quote!(#[allow(unused_variables)]));
        *func.block = syn::parse_quote!({
            ::core::unimplemented!("`#[reduced_lagrangian]` reported an error")
        });
    }
    quote! { #func }
}

fn config_struct(spec: &Spec, func: &ItemFn, config: &Ident, type_name: &Ident) -> TokenStream {
    let vis = &func.vis;
    let layout = &spec.layout;
    // Deduplicated, so a coordinate declared twice (already an error) causes no follow-on ones.
    let mut coords: Vec<&Coord> = Vec::new();
    for c in &layout.coords {
        if !coords.iter().any(|d| d.name == c.name) {
            coords.push(c);
        }
    }
    // Fields, and each coordinate's reads from and writes to the user configuration vector.
    let mut fields = Vec::new();
    let mut inits = Vec::new();
    let mut elems = Vec::new();
    let mut at = 0usize;
    for c in &coords {
        let name = &c.name;
        match c.len {
            None => {
                let i = at;
                let doc = format!("The coordinate `{name}`.");
                fields.push(quote!(#[doc = #doc] pub #name: f64));
                inits.push(quote!(#name: q[#i]));
                elems.push(quote!(self.#name));
                at += 1;
            }
            Some(len) => {
                let idx: Vec<usize> = (at..at + len).collect();
                let local = 0..len;
                let doc = format!("The coordinates `{name}[0..{len}]`.");
                fields.push(quote!(#[doc = #doc] pub #name: [f64; #len]));
                inits.push(quote!(#name: [ #( q[#idx] ),* ]));
                elems.extend(local.map(|i| quote!(self.#name[#i])));
                at += len;
            }
        }
    }
    let n = at;
    let allow = lints::generated();
    let list = |cs: &mut dyn Iterator<Item = &Coord>| {
        cs.map(|c| format!("`{}`", c.declared()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let doc = if layout.declared {
        format!(
            "A configuration of [`{type_name}`] in your coordinates ({}), in this order in \
             `to_vector`/`from_vector`. The system's own vectors are in the adapted coordinates of its \
             declared translations (shape `{}`, group `{}`); convert with \
             `dirac::runtime::AdaptedCoordinates`.",
            list(&mut coords.iter().copied()),
            layout.shape.join("`, `"),
            layout.group.join("`, `"),
        )
    } else {
        let n_shape = layout.s();
        let mut shape_count = 0;
        let (mut shape, mut group) = (Vec::new(), Vec::new());
        for c in &coords {
            if shape_count < n_shape {
                shape_count += c.len.unwrap_or(1);
                shape.push(*c);
            } else {
                group.push(*c);
            }
        }
        format!(
            "A configuration of [`{type_name}`]: shape coordinates ({}) then group coordinates ({}).",
            list(&mut shape.into_iter()),
            list(&mut group.into_iter()),
        )
    };
    // `[f64; N]` implements `Default` only up to N = 32.
    let (derive, default_impl) = if coords.iter().all(|c| c.len.unwrap_or(1) <= 32) {
        (
            quote!(#[derive(Clone, Copy, Debug, Default, PartialEq)]),
            quote!(),
        )
    } else {
        let zeros = coords.iter().map(|c| {
            let name = &c.name;
            match c.len {
                None => quote!(#name: 0.0),
                Some(len) => quote!(#name: [0.0; #len]),
            }
        });
        (
            quote!(#[derive(Clone, Copy, Debug, PartialEq)]),
            quote! {
                impl ::core::default::Default for #config {
                    /// Every coordinate zero.
                    fn default() -> Self {
                        Self { #( #zeros, )* }
                    }
                }
            },
        )
    };
    let vector_fns = if layout.declared {
        quote! {
            impl #config {
                /// Reads the user configuration vector: your coordinates, components flattened in
                /// declaration order (not the system's adapted `q`; see `AdaptedCoordinates`).
                pub fn from_vector(q: &::dirac::nalgebra::SVector<f64, #n>) -> Self {
                    Self { #( #inits, )* }
                }

                /// Writes the user configuration vector: your coordinates, components flattened
                /// in declaration order (`AdaptedCoordinates::to_adapted` maps it to `q`).
                pub fn to_vector(&self) -> ::dirac::nalgebra::SVector<f64, #n> {
                    ::dirac::nalgebra::SVector::<f64, #n>::from([ #( #elems, )* ])
                }
            }
        }
    } else {
        quote! {
            impl #config {
                /// Reads `q = (x, g)` in configuration order.
                pub fn from_vector(q: &::dirac::nalgebra::SVector<f64, #n>) -> Self {
                    Self { #( #inits, )* }
                }

                /// Writes `q = (x, g)` in configuration order.
                pub fn to_vector(&self) -> ::dirac::nalgebra::SVector<f64, #n> {
                    ::dirac::nalgebra::SVector::<f64, #n>::from([ #( #elems, )* ])
                }
            }
        }
    };
    quote! {
        #[doc = #doc]
        #derive
        #vis struct #config {
            #( #fields, )*
        }

        #default_impl

        #allow
        #vector_fns
    }
}

fn param_struct(sig: &Signature, func: &ItemFn, type_name: &Ident) -> TokenStream {
    let vis = &func.vis;
    let params = &sig.params;
    let docs = func.attrs.iter().filter(|a| a.path().is_ident("doc"));
    let fn_name = &func.sig.ident;
    let note = format!(
        "\n\nThe parameters of [`{fn_name}`]; emitted by `#[reduced_lagrangian]`, which implements the \
         `dirac` system traits for it."
    );
    let param_docs = params
        .iter()
        .map(|p| format!("The parameter `{p}` of [`{fn_name}`]."));
    quote! {
        #( #docs )*
        #[doc = #note]
        #[derive(Clone, Copy, Debug, PartialEq)]
        #vis struct #type_name {
            #( #[doc = #param_docs] pub #params: f64, )*
        }
    }
}

/// The three functions of a stepper — residual, residual with Jacobian, momentum update — as
/// straight-line code. `inputs` are the leading arguments after `&self`; `leaf` reads a symbol.
struct SteppedFns {
    residual: TokenStream,
    residual_jacobian: TokenStream,
    momentum: TokenStream,
    /// The residual and the momentum update together (they share most subexpressions).
    residual_momentum: TokenStream,
    /// The type of the Jacobian `residual_jacobian` returns.
    jacobian_type: TokenStream,
    /// The linear solver type and the body of the function that builds its workspace.
    solver_type: TokenStream,
    solver_new: TokenStream,
    counts: String,
}

fn stepper_fns(
    g: &Graph,
    stepper: &Stepper,
    leaf: &dyn Fn(Sym) -> TokenStream,
    n: usize,
    m: usize,
) -> SteppedFns {
    let na = quote!(::dirac::nalgebra);
    let r = straight_line(g, &stepper.residual, leaf);
    let (r_stmts, r_out) = (&r.stmts, &r.outputs);
    let ResidualJacobian {
        code: rj_code,
        operations: rj_operations,
        nonzeros,
        jacobian_type,
        solver_type,
        solver_new,
    } = residual_jacobian(g, &stepper.residual, &stepper.jacobian, leaf, n);
    let mo = straight_line(g, &stepper.momentum, leaf);
    let (m_stmts, m_out) = (&mo.stmts, &mo.outputs);
    let fused_roots: Vec<NodeId> = stepper
        .residual
        .iter()
        .chain(&stepper.momentum)
        .copied()
        .collect();
    let rm = straight_line(g, &fused_roots, leaf);
    let (rm_stmts, rm_r, rm_m) = (&rm.stmts, &rm.outputs[..n], &rm.outputs[n..]);
    SteppedFns {
        residual_momentum: quote! {
            #rm_stmts
            (
                #na::SVector::<f64, #n>::from([ #( #rm_r ),* ]),
                #na::SVector::<f64, #m>::from([ #( #rm_m ),* ]),
            )
        },
        residual: quote! {
            #r_stmts
            #na::SVector::<f64, #n>::from([ #( #r_out ),* ])
        },
        residual_jacobian: rj_code,
        jacobian_type,
        solver_type,
        solver_new,
        momentum: quote! {
            #m_stmts
            #na::SVector::<f64, #m>::from([ #( #m_out ),* ])
        },
        counts: format!(
            "{} operations for the residual, {} for the residual with its Jacobian ({} nonzero entries), {} for the momentum update",
            r.operations,
            rj_operations,
            nonzeros,
            mo.operations
        ),
    }
}

/// The straight-line code of a residual `R` (`n` entries) and its Jacobian in the backend the
/// size calls for (see [`DENSE_MAX`]), with the backend's types.
pub struct ResidualJacobian {
    /// Statements and the tuple `(R, J)`.
    pub code: TokenStream,
    pub operations: usize,
    pub nonzeros: usize,
    /// The type of `J`: `SMatrix<f64, n, n>` or `CscValues<nnz>`.
    pub jacobian_type: TokenStream,
    /// The linear solver for `J` (`Lu<n>` or `SparseLu<n, nnz>`) and the body that builds it.
    pub solver_type: TokenStream,
    pub solver_new: TokenStream,
}

/// `R` and `∂R/∂z` together: one straight line, so shared subexpressions are computed once, and
/// structurally zero entries of the Jacobian are never computed or stored. Dense systems get a
/// fixed-size matrix; above [`DENSE_MAX`] the structural nonzeros become a static CSC pattern
/// and the Jacobian is the array of their values.
pub fn residual_jacobian(
    g: &Graph,
    residual: &[NodeId],
    jacobian: &[Vec<NodeId>],
    leaf: &dyn Fn(Sym) -> TokenStream,
    n: usize,
) -> ResidualJacobian {
    let na = quote!(::dirac::nalgebra);
    let mut roots = residual.to_vec();
    let mut entries: Vec<(usize, usize)> = Vec::new();
    for (row, cols) in jacobian.iter().enumerate() {
        for (col, &node) in cols.iter().enumerate() {
            if g.as_const(node) != Some(0.0) {
                entries.push((row, col));
                roots.push(node);
            }
        }
    }
    // The sparse backend stores the entries column by column (compressed sparse columns).
    let sparse = n > DENSE_MAX;
    if sparse {
        let mut order: Vec<usize> = (0..entries.len()).collect();
        order.sort_by_key(|&i| (entries[i].1, entries[i].0));
        let jac_roots: Vec<NodeId> = order.iter().map(|&i| roots[n + i]).collect();
        roots.truncate(n);
        roots.extend(jac_roots);
        entries = order.iter().map(|&i| entries[i]).collect();
    }
    let rj = straight_line(g, &roots, leaf);
    let rj_stmts = &rj.stmts;
    let rj_r = &rj.outputs[..n];
    let rt = quote!(::dirac::runtime);
    let nnz = entries.len();
    let (jacobian_value, jacobian_type, solver_type, solver_new) = if sparse {
        let values = &rj.outputs[n..];
        let mut col_ptr = vec![0usize; n + 1];
        for &(_, col) in &entries {
            col_ptr[col + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx = entries.iter().map(|&(row, _)| row);
        (
            quote! { #rt::CscValues([ #( #values ),* ]) },
            quote!(#rt::CscValues<#nnz>),
            quote!(#rt::SparseLu<#n, #nnz>),
            quote! {
                static PATTERN: #rt::CscPattern = #rt::CscPattern {
                    n: #n,
                    col_ptr: &[ #( #col_ptr ),* ],
                    row_idx: &[ #( #row_idx ),* ],
                };
                #rt::SparseLu::new(&PATTERN)
            },
        )
    } else {
        let assigns = entries
            .iter()
            .zip(&rj.outputs[n..])
            .map(|((row, col), e)| quote! { __jac[(#row, #col)] = #e; });
        let jac_mut = if entries.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        (
            quote! {{
                let #jac_mut __jac = #na::SMatrix::<f64, #n, #n>::zeros();
                #( #assigns )*
                __jac
            }},
            quote!(#na::SMatrix<f64, #n, #n>),
            quote!(#rt::Lu<#n>),
            quote!(#rt::Lu::empty()),
        )
    };
    ResidualJacobian {
        code: quote! {
            #rj_stmts
            (#na::SVector::<f64, #n>::from([ #( #rj_r ),* ]), #jacobian_value)
        },
        operations: rj.operations,
        nonzeros: nnz,
        jacobian_type,
        solver_type,
        solver_new,
    }
}

/// What every emitted impl shares: the type, the dimensions, the paths, how parameters are read.
struct Target<'a> {
    ty: Ident,
    s: usize,
    k: usize,
    n: usize,
    params: &'a [Ident],
    rt: TokenStream,
    na: TokenStream,
}

impl Target<'_> {
    /// `self.<parameter i>`.
    fn param_leaf(&self, i: usize) -> TokenStream {
        let p = &self.params[i];
        quote! { self.#p }
    }

    /// `&SVector<f64, d>`.
    fn vec(&self, d: usize) -> TokenStream {
        let na = &self.na;
        quote!(&#na::SVector<f64, #d>)
    }

    /// Leaves of the reduced steppers: `x_k`, the unknowns `z = (x_{k+1}, u)`, `w_k`, `μ_k`.
    fn reduced_leaf(&self, sym: Sym) -> TokenStream {
        match sym {
            Sym::X0(i) => quote! { x_k[#i] },
            Sym::X1(i) => quote! { z[#i] },
            Sym::G1(j) | Sym::G0(j) => {
                let j = self.s + j;
                quote! { z[#j] }
            }
            Sym::W(i) => quote! { w_k[#i] },
            Sym::Mu(j) => quote! { mu_k[#j] },
            Sym::Param(i) => self.param_leaf(i),
            Sym::Q0(_) | Sym::Q1(_) | Sym::P(_) => {
                unreachable!("reduced Lagrangians read x0, x1 and g")
            }
        }
    }
}

/// One side's `impl Reduced<Side, S, K, N>`, its code counts and its elimination note: the
/// (+) and (−) impls come from this one function.
fn reduced_impl(t: &Target, g: &Graph, side: &SideCode) -> (TokenStream, String, String) {
    let Target {
        ty,
        s,
        k,
        n,
        rt,
        na,
        ..
    } = t;
    let (s, k, n) = (*s, *k, *n);
    let (vs, vk, vn) = (t.vec(s), t.vec(k), t.vec(n));
    let leaf = |sym| t.reduced_leaf(sym);
    let (marker, label) = match side.side {
        Side::Plus => (quote!(#rt::Plus), "(+)"),
        Side::Minus => (quote!(#rt::Minus), "(−)"),
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
    let (r, rj, m, rm) = (
        &general.residual,
        &general.residual_jacobian,
        &general.momentum,
        &general.residual_momentum,
    );
    let (jt, st, sn) = (
        &general.jacobian_type,
        &general.solver_type,
        &general.solver_new,
    );
    // The eliminated stepper: Newton on x_{k+1} alone; the third function returns the group
    // unknowns in closed form.
    let (eliminated, note) = match &side.eliminated {
        None if n > DENSE_MAX => (
            quote!(),
            format!("{label} not used on the sparse backend (its shape Jacobian is dense)"),
        ),
        None => (
            quote!(),
            format!(
                "{label} not available (the momentum equations are not affine in the group unknowns)"
            ),
        ),
        Some(e) => {
            let as_stepper = Stepper {
                residual: e.residual.clone(),
                jacobian: e.jacobian.clone(),
                momentum: e.group.clone(),
            };
            let f = stepper_fns(g, &as_stepper, &leaf, s, k);
            let (r, rj, grp) = (&f.residual, &f.residual_jacobian, &f.momentum);
            let pays = side.elimination_pays;
            let note = format!(
                "{label} group unknowns in closed form, Newton on the shape unknowns: {} (the third count is the closed form); \
                 used by default: {}",
                f.counts,
                if pays { "yes" } else { "no, the general path has less code" }
            );
            let a_flat: Vec<NodeId> = e.block.iter().flatten().copied().collect();
            let a_code = straight_line(g, &a_flat, &leaf);
            let (a_stmts, a_out) = (&a_code.stmts, &a_code.outputs);
            let tokens = quote! {
                const ELIMINATES_GROUP: bool = true;
                const ELIMINATION_PAYS: bool = #pays;

                #[inline]
                #[allow(unused_variables)] // a closed form need not read every input
                fn eliminated_residual(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs) -> ::core::option::Option<#na::SVector<f64, #s>> {
                    ::core::option::Option::Some({ #r })
                }

                #[inline]
                #[allow(unused_variables)] // a closed form need not read every input
                fn eliminated_residual_jacobian(
                    &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs,
                ) -> ::core::option::Option<(#na::SVector<f64, #s>, #na::SMatrix<f64, #s, #s>)> {
                    ::core::option::Option::Some({ #rj })
                }

                #[inline]
                #[allow(unused_variables)] // a closed form need not read every input
                fn eliminated_group(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs) -> ::core::option::Option<#na::SVector<f64, #k>> {
                    ::core::option::Option::Some({ #grp })
                }

                #[inline]
                #[allow(unused_variables)] // a closed form need not read every input
                fn eliminated_group_block(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vs) -> ::core::option::Option<#na::SMatrix<f64, #k, #k>> {
                    #a_stmts
                    ::core::option::Option::Some(#na::SMatrix::<f64, #k, #k>::from_row_slice(&[ #( #a_out ),* ]))
                }
            };
            (tokens, note)
        }
    };
    let allow = lints::generated();
    let tokens = quote! {
        #allow
        #[automatically_derived]
        impl #rt::Reduced<#marker, #s, #k, #n> for #ty {
            type Linear = #st;

            fn linear_solver(&self) -> #st {
                #sn
            }

            #[allow(unused_variables)] // a Lagrangian need not read every coordinate
            fn reduced_lagrangian(&self, x0: #vs, x1: #vs, u: #vk) -> f64 {
                #l_stmts
                #l_out
            }

            #[inline]
            fn residual(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn) -> #na::SVector<f64, #n> {
                #r
            }

            #[inline]
            fn residual_jacobian(
                &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn,
            ) -> (#na::SVector<f64, #n>, #jt) {
                #rj
            }

            #[inline]
            fn momentum(&self, x_k: #vs, z: #vn) -> #na::SVector<f64, #s> {
                #m
            }

            #[inline]
            #[allow(unused_variables)] // the momentum update need not read every input
            fn residual_momentum(
                &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn,
            ) -> (#na::SVector<f64, #n>, #na::SVector<f64, #s>) {
                #rm
            }

            #eliminated
        }
    };
    (tokens, general.counts, note)
}

fn generate(spec: &Spec, sig: &Signature, func: &ItemFn, c: &Compiled) -> TokenStream {
    let ty = type_name(spec, func);
    let config = format_ident!("{}Config", ty);
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let n = s + k;
    let fn_name = &func.sig.ident;
    let params = &sig.params;
    let step = &sig.step;
    let (shape_names, group_names) = (&spec.layout.shape, &spec.layout.group);
    let param_names = params.iter().map(Ident::to_string);
    let target = Target {
        ty: ty.clone(),
        s,
        k,
        n,
        params,
        rt: quote!(::dirac::runtime),
        na: quote!(::dirac::nalgebra),
    };
    let (rt, na) = (&target.rt, &target.na);
    let param_leaf = |i: usize| target.param_leaf(i);
    let unreduced_leaf = |sym: Sym| match sym {
        Sym::Q0(i) => quote! { q_k[#i] },
        Sym::Q1(i) => quote! { z[#i] },
        Sym::P(i) => quote! { p_k[#i] },
        Sym::Param(i) => param_leaf(i),
        _ => unreachable!("the unreduced equations read q0, q1 and p"),
    };
    let vn = target.vec(n);
    let (plus_impl, plus_counts, plus_note) = reduced_impl(&target, &c.graph, &c.plus);
    let (minus_impl, minus_counts, minus_note) = reduced_impl(&target, &c.graph, &c.minus);
    let elimination_note = format!(" Momentum-level elimination: {plus_note}; {minus_note}.");
    let unreduced = stepper_fns(&c.graph, &c.unreduced, &unreduced_leaf, n, n);
    let hessian_impl = c.hessian.as_ref().map(|hessian| {
        let hessian_roots: Vec<NodeId> = hessian.iter().flatten().flatten().copied().collect();
        let hessian_code = straight_line(&c.graph, &hessian_roots, &|sym| match sym {
            Sym::Q0(i) => quote! { q0[#i] },
            Sym::Q1(i) => quote! { q1[#i] },
            Sym::Param(i) => param_leaf(i),
            _ => unreachable!("L_d reads q0, q1 and its parameters"),
        });
        let hessian_stmts = &hessian_code.stmts;
        let hessian_blocks = hessian_code.outputs.chunks(n * n).map(|block| {
            quote! { #na::SMatrix::<f64, #n, #n>::from_row_slice(&[ #( #block ),* ]) }
        });
        let allow = lints::generated();
        quote! {
            #allow
            #[automatically_derived]
            impl #rt::LagrangianHessian<#s, #k, #n> for #ty {
                #[allow(unused_variables)] // a Lagrangian need not read every coordinate
                fn lagrangian_hessian(
                    &self, q0: #vn, q1: #vn,
                ) -> (#na::SMatrix<f64, #n, #n>, #na::SMatrix<f64, #n, #n>, #na::SMatrix<f64, #n, #n>) {
                    #hessian_stmts
                    ( #( #hessian_blocks ),* )
                }
            }
        }
    });
    let (un_r, un_rj, un_m) = (
        &unreduced.residual,
        &unreduced.residual_jacobian,
        &unreduced.momentum,
    );
    let (un_jt, un_st, un_sn) = (
        &unreduced.jacobian_type,
        &unreduced.solver_type,
        &unreduced.solver_new,
    );

    let b_flat: Vec<NodeId> = c.b.iter().flatten().copied().collect();
    let b_code = straight_line(&c.graph, &b_flat, &|sym| match sym {
        Sym::Param(i) => param_leaf(i),
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
    let allow = lints::generated();
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
        continuous::emit_impl(&c.graph, parts, &ty, n, &param_leaf, &allow, &call_l)
    });
    let counts = format!(
        "Generated straight-line code: reduced (+) stepper: {}; reduced (−) stepper: {}; unreduced stepper: {}.",
        plus_counts, minus_counts, unreduced.counts
    ) + &elimination_note;

    quote! {
        #config_item

        #adapted_item

        #user_fn

        #param_item

        #continuous_impl

        #allow
        impl #ty {
            /// Number of shape coordinates `S`.
            pub const SHAPE_DIM: usize = #s;
            /// Number of group coordinates `K`.
            pub const GROUP_DIM: usize = #k;
            /// Number of configuration coordinates `N = S + K`.
            pub const CONFIG_DIM: usize = #n;
            #[doc = #counts]
            pub const GENERATED: &'static str = #counts;
        }

        #allow
        #[automatically_derived]
        impl #rt::DiscreteLagrangian<#s, #k, #n> for #ty {
            const SHAPE: [&'static str; #s] = [ #( #shape_names ),* ];
            const GROUP: [&'static str; #k] = [ #( #group_names ),* ];
            const PARAMETERS: &'static [&'static str] = &[ #( #param_names ),* ];

            fn lagrangian(&self, q0: #vn, q1: #vn) -> f64 {
                #lagrangian_body
            }

            fn connection(&self) -> #na::SMatrix<f64, #k, #s> {
                #connection_body
            }

            fn time_step(&self) -> f64 {
                self.#step
            }

            fn with_time_step(&self, h: f64) -> Self {
                let mut system = *self;
                system.#step = h;
                system
            }

            fn parameter_values(&self) -> ::std::vec::Vec<f64> {
                ::std::vec![ #( self.#params ),* ]
            }
        }

        #plus_impl

        #minus_impl

        #allow
        #[automatically_derived]
        impl #rt::Unreduced<#s, #k, #n> for #ty {
            type UnreducedLinear = #un_st;

            fn unreduced_linear_solver(&self) -> #un_st {
                #un_sn
            }

            #[inline]
            fn unreduced_residual(&self, q_k: #vn, p_k: #vn, z: #vn) -> #na::SVector<f64, #n> {
                #un_r
            }

            #[inline]
            fn unreduced_residual_jacobian(
                &self, q_k: #vn, p_k: #vn, z: #vn,
            ) -> (#na::SVector<f64, #n>, #un_jt) {
                #un_rj
            }

            #[inline]
            fn unreduced_momentum(&self, q_k: #vn, z: #vn) -> #na::SVector<f64, #n> {
                #un_m
            }
        }

        #hessian_impl
    }
}

/// Parameters the body never reads but the connection matrix does.
fn connection_only_params(spec: &Spec, sig: &Signature, c: &Compiled) -> Vec<Ident> {
    if spec.connection.is_none() {
        return Vec::new();
    }
    let b_flat: Vec<NodeId> = c.b.iter().flatten().copied().collect();
    let in_b = c.graph.symbols(&b_flat);
    let in_body = c.graph.symbols(&[c.body]);
    sig.fn_params()
        .iter()
        .enumerate()
        .filter(|(i, _)| in_b.contains(&Sym::Param(*i)) && !in_body.contains(&Sym::Param(*i)))
        .map(|(_, p)| p.clone())
        .collect()
}

/// After an error, still emit the items the user's other code refers to, with the right
/// signatures, so the real error is not buried under follow-on ones (thiserror's `fallback`).
fn fallback(spec: Option<&Spec>, sig: Option<&Signature>, func: &ItemFn) -> TokenStream {
    let Some(spec) = spec else {
        return quote! { #func };
    };
    let ty = type_name(spec, func);
    let config = format_ident!("{}Config", ty);
    let mut out = config_struct(spec, func, &config, &ty);
    out.extend(adapted::adapted_impl(&spec.layout, &ty));
    out.extend(user_function(
        func,
        &config,
        true,
        &[],
        spec.layout.has_arrays(),
    ));
    if let Some(sig) = sig {
        out.extend(param_struct(sig, func, &ty));
        out.extend(stub_impls(spec, sig, &ty));
    }
    out
}

/// The inherent constants and the system traits, with the real signatures and bodies that are
/// never reached (the compilation fails), so `ReducedIntegrator::plus(Name { .. }, ..)` and the
/// like type-check. Trait methods with default bodies are left to their defaults.
fn stub_impls(spec: &Spec, sig: &Signature, ty: &Ident) -> TokenStream {
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let n = s + k;
    let rt = quote!(::dirac::runtime);
    let na = quote!(::dirac::nalgebra);
    let (shape_names, group_names) = (&spec.layout.shape, &spec.layout.group);
    let param_names = sig.params.iter().map(Ident::to_string);
    let vec = |d: usize| quote!(&#na::SVector<f64, #d>);
    let (vs, vk, vn) = (vec(s), vec(k), vec(n));
    let (rn, mnn) = (
        quote!(#na::SVector<f64, #n>),
        quote!(#na::SMatrix<f64, #n, #n>),
    );
    let stub = quote!(::core::unimplemented!(
        "`#[reduced_lagrangian]` reported an error"
    ));
    let generated = "Nothing: `#[reduced_lagrangian]` reported an error.";
    let sides = [quote!(#rt::Plus), quote!(#rt::Minus)];
    quote! {
        impl #ty {
            /// Number of shape coordinates `S`.
            pub const SHAPE_DIM: usize = #s;
            /// Number of group coordinates `K`.
            pub const GROUP_DIM: usize = #k;
            /// Number of configuration coordinates `N = S + K`.
            pub const CONFIG_DIM: usize = #n;
            #[doc = #generated]
            pub const GENERATED: &'static str = #generated;
        }

        // Stubs: the arguments are unused because the bodies are.
        #[allow(unused_variables)]
        impl #rt::DiscreteLagrangian<#s, #k, #n> for #ty {
            const SHAPE: [&'static str; #s] = [ #( #shape_names ),* ];
            const GROUP: [&'static str; #k] = [ #( #group_names ),* ];
            const PARAMETERS: &'static [&'static str] = &[ #( #param_names ),* ];
            fn lagrangian(&self, q0: #vn, q1: #vn) -> f64 { #stub }
            fn connection(&self) -> #na::SMatrix<f64, #k, #s> { #stub }
            fn time_step(&self) -> f64 { #stub }
            fn with_time_step(&self, h: f64) -> Self { #stub }
            fn parameter_values(&self) -> ::std::vec::Vec<f64> { #stub }
        }

        #(
            #[allow(unused_variables)]
            impl #rt::Reduced<#sides, #s, #k, #n> for #ty {
                type Linear = #rt::Lu<#n>;
                fn linear_solver(&self) -> #rt::Lu<#n> { #stub }
                fn reduced_lagrangian(&self, x0: #vs, x1: #vs, u: #vk) -> f64 { #stub }
                fn residual(&self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn) -> #rn { #stub }
                fn residual_jacobian(
                    &self, x_k: #vs, w_k: #vs, mu_k: #vk, z: #vn,
                ) -> (#rn, #mnn) { #stub }
                fn momentum(&self, x_k: #vs, z: #vn) -> #na::SVector<f64, #s> { #stub }
            }
        )*

        #[allow(unused_variables)]
        impl #rt::Unreduced<#s, #k, #n> for #ty {
            type UnreducedLinear = #rt::Lu<#n>;
            fn unreduced_linear_solver(&self) -> #rt::Lu<#n> { #stub }
            fn unreduced_residual(&self, q_k: #vn, p_k: #vn, z: #vn) -> #rn { #stub }
            fn unreduced_residual_jacobian(&self, q_k: #vn, p_k: #vn, z: #vn) -> (#rn, #mnn) {
                #stub
            }
            fn unreduced_momentum(&self, q_k: #vn, z: #vn) -> #rn { #stub }
        }

        #[allow(unused_variables)]
        impl #rt::LagrangianHessian<#s, #k, #n> for #ty {
            fn lagrangian_hessian(&self, q0: #vn, q1: #vn) -> (#mnn, #mnn, #mnn) { #stub }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The expansion of the paper's charged particle, pretty-printed and compared with the
    /// committed snapshot `tests/snapshots/charged_particle.expanded.rs`. Set `DIRAC_BLESS=1`
    /// to rewrite the snapshot after an intended change to the generated code.
    #[test]
    fn charged_particle_expansion_matches_the_snapshot() {
        let args = quote!(shape(x, y, z), group(theta));
        let item = quote! {
            /// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
            pub fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
                let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
                let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
                let s = a_dot_dq + (q1.theta - q0.theta);
                0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
            }
        };
        let file: syn::File = syn::parse2(expand(args, item)).expect("the expansion parses");
        let text = prettyplease::unparse(&file);
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/snapshots/charged_particle.expanded.rs");
        if std::env::var_os("DIRAC_BLESS").is_some() {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &text).unwrap();
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "the expansion changed; review it and rerun with DIRAC_BLESS=1:\n{text}"
        );
    }

    #[test]
    fn a_rejected_body_still_emits_the_items_other_code_uses() {
        let args = quote!(shape(x), group(theta));
        let item = quote! {
            fn f(q0: Config, q1: Config, h: f64) -> f64 { if h > 0.0 { q0.x } else { q1.x } }
        };
        let out = expand(args, item).to_string();
        assert!(out.contains("compile_error"), "{out}");
        assert!(out.contains("struct FConfig"), "{out}");
        assert!(out.contains("struct F"), "{out}");
        assert!(out.contains("fn f"), "{out}");
        for item in [
            "DiscreteLagrangian",
            "Reduced",
            "Plus",
            "Minus",
            "Unreduced",
            "SHAPE_DIM",
        ] {
            assert!(out.contains(item), "{item} missing from {out}");
        }
    }
}
