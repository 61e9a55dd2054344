//! Code generation for element-wise systems: the system type (parameters, time step, sizes),
//! its configuration type (`Vec`s whose lengths are the sizes), one `Family` impl per family of
//! elements (its stencil as integer code in the loop indices and sizes, its kernels as
//! straight-line f64 code over the stencil's slots) and the `ElementLagrangian` impl that the
//! runtime's assembly drives (`dirac::runtime::element`). Nothing here depends on the sizes'
//! values: the code is the same for every run.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::{Ident, ItemFn};

use crate::back::emit::straight_line;
use crate::back::impls;
use crate::back::items::{camel_case, user_function};
use crate::back::lints;
use crate::front::element::constraints::ConstraintSplit;
use crate::front::element::families::FamilySpec;
use crate::front::element::index::Index;
use crate::front::element::{Dim, ElementSpec};
use crate::ir::element::{ConstraintCode, ElementCode};
use crate::ir::graph::{NodeId, Sym};

/// Every item of an element-wise system.
pub fn generate(
    spec: &ElementSpec,
    func: &ItemFn,
    families: &[FamilySpec],
    codes: &[ElementCode],
    constraints: Option<(&ConstraintSplit, &[ConstraintCode])>,
    min_size: usize,
) -> TokenStream {
    let ty = spec
        .name
        .clone()
        .unwrap_or_else(|| camel_case(&func.sig.ident));
    let config = format_ident!("{}Config", ty);
    let vis = &func.vis;
    let rt = quote!(::dirac::runtime::element);
    let params = &spec.sig.params;
    let sizes = &spec.sizes;
    let n_coords = spec.coords.len();
    let fn_name = &func.sig.ident;

    // Offsets of the coordinates in the flat vector, from the sizes.
    let lengths: Vec<TokenStream> = spec
        .coords
        .iter()
        .map(|c| {
            let factors: Vec<TokenStream> = c
                .dims
                .iter()
                .map(|d| match d {
                    Dim::Size(k) => {
                        let s = &sizes[*k];
                        quote!((self.#s as i64))
                    }
                    Dim::Fixed(v) => {
                        let v = *v as i64;
                        quote!(#v)
                    }
                    Dim::Scaled(k, m) => {
                        let (s, m) = (&sizes[*k], *m as i64);
                        quote!((#m * self.#s as i64))
                    }
                })
                .collect();
            quote!(1i64 #(* #factors)*)
        })
        .collect();
    let offsets_fn = quote! {
        /// The offsets of the coordinates in the flat configuration vector, and its length.
        #[doc(hidden)]
        pub fn __offsets(&self) -> [i64; #n_coords + 1] {
            let mut o = [0i64; #n_coords + 1];
            let lengths: [i64; #n_coords] = [#(#lengths),*];
            for c in 0..#n_coords {
                o[c + 1] = o[c] + lengths[c];
            }
            o
        }
    };

    let mut family_items = TokenStream::new();
    let mut visits = Vec::new();
    let mut described = Vec::new();
    for (f, (family, code)) in families.iter().zip(codes).enumerate() {
        let name = format_ident!("__{}Family{}", ty, f);
        let s = code.width;
        let force = code.force;
        let depth = family.loops.len();
        let body = element_nest(spec, family, None);
        let size_bindings = size_bindings(spec);
        let leaf = |q0: TokenStream, q1: TokenStream| leaf_of(spec, q0, q1);
        let steps = leaf(quote!(q0), quote!(q1));
        let kernel = |outputs: &[NodeId]| straight_line(&code.graph, outputs, &steps);
        let d1_d2: Vec<NodeId> = code.d1.iter().chain(&code.d2).copied().collect();
        let pair = kernel(&d1_d2);
        let (pair_stmts, pair_out) = (&pair.stmts, &pair.outputs);
        let all: Vec<NodeId> = d1_d2
            .iter()
            .copied()
            .chain(code.d12.iter().flatten().copied())
            .collect();
        let all = kernel(&all);
        let (all_stmts, all_out) = (&all.stmts, &all.outputs);
        // The step partials of a sensitivity, one straight-line function whose outputs are
        // the trait's layout: the three blocks row by row, then the control columns.
        let b = &code.blocks;
        let partial_nodes: Vec<NodeId> = [&b.d11, &b.d21, &b.d22, &b.u1, &b.u2]
            .into_iter()
            .flat_map(|rows| rows.iter().flatten().copied())
            .collect();
        let partials = kernel(&partial_nodes);
        let (partial_stmts, partial_out) = (&partials.stmts, &partials.outputs);
        let value = kernel(&[code.value]);
        let (value_stmts, value_out) = (&value.stmts, &value.outputs[0]);
        let energy = match code.energy {
            Some(e) => {
                let el = leaf(quote!(q), quote!(v));
                let line = straight_line(&code.graph, &[e], &el);
                let (st, out) = (&line.stmts, &line.outputs[0]);
                quote! {
                    let (q, v) = (#rt::stencil::<#s>(q), #rt::stencil::<#s>(v));
                    let sys = self.0;
                    #st #out
                }
            }
            None => quote!(f64::NAN),
        };
        let legendre = match &code.legendre {
            Some((p, hessian)) => {
                let el = leaf(quote!(q), quote!(v));
                let outputs: Vec<NodeId> =
                    p.iter().chain(hessian.iter().flatten()).copied().collect();
                let line = straight_line(&code.graph, &outputs, &el);
                let (st, outs) = (&line.stmts, &line.outputs);
                let len = outs.len();
                quote! {
                    let (q, v) = (#rt::stencil::<#s>(q), #rt::stencil::<#s>(v));
                    let sys = self.0;
                    #st
                    *#rt::outputs::<#len>(out) = [#(#outs),*];
                }
            }
            None => quote!(out.fill(f64::NAN);),
        };
        let (pair_len, all_len, partial_len) = (pair_out.len(), all_out.len(), partial_out.len());
        described.push(format!(
            "{}×{s} ({} operations for R + J + p{})",
            depth_word(depth),
            all.operations,
            if force { ", forces" } else { "" }
        ));
        let gen = lints::generated();
        family_items.extend(quote! {
            #[doc(hidden)]
            #[allow(non_camel_case_types)]
            #vis struct #name<'a>(&'a #ty);

            #gen
            #[allow(unused_variables, unused_parens, clippy::identity_op, clippy::erasing_op, clippy::unnecessary_cast, clippy::double_parens, clippy::possible_missing_comma)]
            impl #rt::Family for #name<'_> {
                #[inline]
                fn width(&self) -> usize {
                    #s
                }
                #[inline]
                fn depth(&self) -> usize {
                    #depth
                }
                #[inline]
                fn force(&self) -> bool {
                    #force
                }
                fn elements(&self, visit: &mut dyn FnMut(&[i64], &[i64])) {
                    let sys = self.0;
                    let __o = sys.__offsets();
                    #(#size_bindings)*
                    #body
                }
                #[inline]
                fn d1_d2(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) {
                    let (q0, q1) = (#rt::stencil::<#s>(q0), #rt::stencil::<#s>(q1));
                    let sys = self.0;
                    #pair_stmts
                    *#rt::outputs::<#pair_len>(out) = [#(#pair_out),*];
                }
                #[inline]
                fn d1_d2_d12(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) {
                    let (q0, q1) = (#rt::stencil::<#s>(q0), #rt::stencil::<#s>(q1));
                    let sys = self.0;
                    #all_stmts
                    *#rt::outputs::<#all_len>(out) = [#(#all_out),*];
                }
                fn step_partials(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) -> bool {
                    let (q0, q1) = (#rt::stencil::<#s>(q0), #rt::stencil::<#s>(q1));
                    let sys = self.0;
                    #partial_stmts
                    *#rt::outputs::<#partial_len>(out) = [#(#partial_out),*];
                    true
                }
                fn value(&self, indices: &[i64], q0: &[f64], q1: &[f64]) -> f64 {
                    let (q0, q1) = (#rt::stencil::<#s>(q0), #rt::stencil::<#s>(q1));
                    let sys = self.0;
                    #value_stmts
                    #value_out
                }
                fn energy(&self, indices: &[i64], q: &[f64], v: &[f64]) -> f64 {
                    #energy
                }
                fn legendre(&self, indices: &[i64], q: &[f64], v: &[f64], out: &mut [f64]) {
                    #legendre
                }
            }
        });
        visits.push(quote!(visitor.family(&#name(self));));
    }

    let (constraint_family_items, constraint_lagrangian) =
        constraint_items(spec, vis, &ty, constraints);
    let size_names: Vec<String> = sizes.iter().map(|s| s.to_string()).collect();
    let translations = spec.translates.iter().map(|members| {
        let ranges = members.iter().map(|&c| {
            let c1 = c + 1;
            quote!((o[#c] as usize)..(o[#c1] as usize))
        });
        quote!(vec![#(#ranges),*])
    });
    let continuous = spec.sig.continuous;
    let forced = codes.iter().any(|c| c.force);
    let system = impls::system_impl(
        &ty,
        &impls::Model {
            params,
            step: &spec.sig.step,
            controls: &spec.controls,
            coordinates: spec.coords.iter().map(|c| c.name.to_string()).collect(),
            time: None,
            domain: &[],
        },
    );
    let generated = format!(
        "element-wise, sizes chosen at run time: {} famil{} of elements: {}",
        codes.len(),
        if codes.len() == 1 { "y" } else { "ies" },
        described.join(", ")
    );
    let docs = func.attrs.iter().filter(|a| a.path().is_ident("doc"));
    let note = format!(
        "\n\nThe parameters and sizes of [`{fn_name}`]; emitted by `#[reduced_lagrangian]`, which implements \
         `dirac::runtime::element::ElementLagrangian` for it (integrate with `ElementIntegrator`)."
    );
    let param_docs = params
        .iter()
        .map(|p| format!("The parameter `{p}` of [`{fn_name}`]."));
    let size_docs = sizes
        .iter()
        .map(|s| format!("The size `{s}` of [`{fn_name}`]."));

    // The configuration type: one field per coordinate.
    let fields = spec.coords.iter().map(|c| {
        let name = &c.name;
        let t = match c.dims.len() {
            0 => quote!(f64),
            1 => quote!(::std::vec::Vec<f64>),
            _ => quote!(::std::vec::Vec<::std::vec::Vec<f64>>),
        };
        let doc = format!("The coordinate `{name}`.");
        quote!(#[doc = #doc] pub #name: #t)
    });
    let dim_of = |c: &crate::front::element::ElementCoord, k: usize| match &c.dims[k] {
        Dim::Size(s) => {
            let s = &sizes[*s];
            quote!(self.#s)
        }
        Dim::Fixed(v) => quote!(#v),
        Dim::Scaled(s, m) => {
            let s = &sizes[*s];
            quote!((#m * self.#s))
        }
    };
    let to_config = spec.coords.iter().enumerate().map(|(c, coord)| {
        let name = &coord.name;
        match coord.dims.len() {
            0 => quote!(#name: q[o[#c] as usize]),
            1 => quote!(#name: q.as_slice()[o[#c] as usize..o[#c + 1] as usize].to_vec()),
            _ => {
                let d1 = dim_of(coord, 1);
                quote!(#name: q.as_slice()[o[#c] as usize..o[#c + 1] as usize].chunks(#d1).map(|r| r.to_vec()).collect())
            }
        }
    });
    let to_vector = spec.coords.iter().map(|coord| {
        let name = &coord.name;
        match coord.dims.len() {
            0 => quote!(v.push(c.#name);),
            1 => quote!(v.extend_from_slice(&c.#name);),
            _ => quote!(for row in &c.#name { v.extend_from_slice(row); }),
        }
    });
    let config_doc = format!("A configuration (or velocity) of [`{ty}`], coordinate by coordinate; lengths are the sizes.");
    let mut user_func = func.clone();
    user_func.attrs.push(syn::parse_quote!(#[allow(
        clippy::needless_pass_by_value,
        reason = "the configurations hold `Vec`s whose lengths are the sizes; the attribute passes them by value as it does fixed-size ones"
    )]));
    // Parameters that only the forces or the constraints read are still arguments of the
    // function: mark them used.
    let mut touch: Vec<Ident> = if spec.force.is_some() || spec.constraints.is_some() {
        spec.sig.fn_params().to_vec()
    } else {
        Vec::new()
    };
    // The configuration the constraints read, whether or not the body reads it.
    if spec.constraints.is_some() {
        touch.push(spec.sig.q0.clone());
    }
    let user = user_function(&user_func, &config, false, &touch, true);
    let gen = lints::generated();
    quote! {
        #user

        // The function is the system's reference implementation: not dead code when unused.
        const _: () = {
            let _ = #fn_name;
        };

        #( #docs )*
        #[doc = #note]
        #[derive(Clone, Copy, Debug, PartialEq)]
        #vis struct #ty {
            #( #[doc = #param_docs] pub #params: f64, )*
            #( #[doc = #size_docs] pub #sizes: usize, )*
        }

        #[doc = #config_doc]
        #[derive(Clone, Debug, PartialEq)]
        #vis struct #config {
            #(#fields,)*
        }

        #gen
        #[allow(
            clippy::identity_op,
            clippy::erasing_op,
            unused_parens,
            clippy::possible_missing_comma,
            reason = "generated with the attribute's span: array entries are one-line products, not missing commas"
        )]
        impl #ty {
            /// What the compiler generated.
            pub const GENERATED: &'static str = #generated;
            #offsets_fn
            /// The number of coordinates for these sizes.
            pub fn dim(&self) -> usize {
                self.__offsets()[#n_coords] as usize
            }
            /// The configuration `q` (a flat vector of [`Self::dim`] components), coordinate by
            /// coordinate.
            ///
            /// # Panics
            /// If `q` has fewer than [`Self::dim`] components.
            pub fn config(&self, q: &::dirac::nalgebra::DVector<f64>) -> #config {
                let o = self.__offsets();
                #config { #(#to_config,)* }
            }
            /// The flat vector of `c`, coordinate after coordinate (rows of a grid in order).
            pub fn vector(&self, c: &#config) -> ::dirac::nalgebra::DVector<f64> {
                let mut v: ::std::vec::Vec<f64> = ::std::vec::Vec::with_capacity(self.dim());
                #(#to_vector)*
                ::dirac::nalgebra::DVector::from_vec(v)
            }
        }

        #family_items
        #constraint_family_items

        #system

        impl #rt::ElementLagrangian for #ty {
            const SIZES: &'static [&'static str] = &[#(#size_names),*];
            const MIN_SIZE: usize = #min_size;
            const CONTINUOUS: bool = #continuous;
            const FORCED: bool = #forced;
            fn sizes(&self) -> ::std::vec::Vec<usize> {
                ::std::vec![#(self.#sizes),*]
            }
            fn dim(&self) -> usize {
                #ty::dim(self)
            }
            fn translations(&self) -> ::std::vec::Vec<::std::vec::Vec<::std::ops::Range<usize>>> {
                let o = self.__offsets();
                ::std::vec![#(#translations),*]
            }
            fn families<V: #rt::FamilyVisitor>(&self, visitor: &mut V) {
                #(#visits)*
            }
            #constraint_lagrangian
        }
    }
}

fn depth_word(depth: usize) -> &'static str {
    match depth {
        0 => "1 element",
        1 => "n elements",
        2 => "pairs/grid",
        _ => "nested",
    }
}

/// The loop nest of `family` calling `visit(indices, [row,] stencil)` for every element, its
/// stencil as integer code in the loop indices `__i<k>` and the sizes `__n<k>` (bound by
/// [`size_bindings`]) over the offsets `__o`; a constraint family passes its row.
fn element_nest(spec: &ElementSpec, family: &FamilySpec, row: Option<&Index>) -> TokenStream {
    let depth = family.loops.len();
    let loop_vars: Vec<Ident> = (0..depth).map(|k| format_ident!("__i{}", k)).collect();
    let size_tok = |k: usize| {
        let s = format_ident!("__n{}", k);
        quote!(#s)
    };
    let loop_tok = |k: usize| {
        let v = &loop_vars[k];
        quote!(#v)
    };
    let stencil: Vec<TokenStream> = family
        .slots
        .iter()
        .map(|slot| {
            let c = slot.coord;
            let coord = &spec.coords[c];
            let ix: Vec<TokenStream> = slot
                .index
                .iter()
                .map(|i| i.tokens(&size_tok, &loop_tok))
                .collect();
            match (coord.dims.as_slice(), ix.as_slice()) {
                ([], []) => quote!(__o[#c]),
                ([_], [i]) => quote!(__o[#c] + #i),
                ([_, d1], [i, j]) => {
                    let len1 = match d1 {
                        Dim::Size(k) => size_tok(*k),
                        Dim::Fixed(v) => {
                            let v = *v as i64;
                            quote!(#v)
                        }
                        Dim::Scaled(k, m) => {
                            let (s, m) = (size_tok(*k), *m as i64);
                            quote!((#m * #s))
                        }
                    };
                    quote!(__o[#c] + #i * #len1 + #j)
                }
                _ => unreachable!("the rewriter checks the number of indices"),
            }
        })
        .collect();
    let row = row.map(|r| {
        let r = r.tokens(&size_tok, &loop_tok);
        quote!(#r,)
    });
    let mut body = quote!(visit(&[#(#loop_vars),*], #row &[#(#stencil),*]););
    for k in (0..depth).rev() {
        let v = &loop_vars[k];
        let (lo, hi) = (
            family.loops[k].lo.tokens(&size_tok, &loop_tok),
            family.loops[k].hi.tokens(&size_tok, &loop_tok),
        );
        body = quote! { for #v in (#lo)..(#hi) { #body } };
    }
    body
}

/// `let __n<k> = sys.<size> as i64;` for every size.
fn size_bindings(spec: &ElementSpec) -> Vec<TokenStream> {
    spec.sizes
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let n = format_ident!("__n{}", k);
            quote!(let #n = sys.#s as i64;)
        })
        .collect()
}

/// The leaves of an element's kernels: `Q0(a)`, `Q1(a)` as `q0[a]`, `q1[a]` (the names given),
/// parameters as `sys.<p>`, sizes and loop indices as f64.
fn leaf_of(
    spec: &ElementSpec,
    q0: TokenStream,
    q1: TokenStream,
) -> impl Fn(Sym) -> TokenStream + '_ {
    let (params, sizes) = (&spec.sig.params, &spec.sizes);
    let n_user = params.len();
    move |sym: Sym| -> TokenStream {
        match sym {
            Sym::Q0(a) => quote!(#q0[#a]),
            Sym::Q1(a) => quote!(#q1[#a]),
            Sym::Param(i) if i < n_user => {
                let p = &params[i];
                quote!(sys.#p)
            }
            Sym::Param(i) if i < n_user + sizes.len() => {
                let s = &sizes[i - n_user];
                quote!((sys.#s as f64))
            }
            Sym::Param(i) => {
                let k = i - n_user - sizes.len();
                quote!((indices[#k] as f64))
            }
            other => unreachable!("an element reads no {other:?}"),
        }
    }
}

/// The constraint families' items (one `ConstraintFamily` impl each) and the
/// `ElementLagrangian` items that expose them: `CONSTRAINED`, `constraint_count` and
/// `constraint_families`.
fn constraint_items(
    spec: &ElementSpec,
    vis: &syn::Visibility,
    ty: &Ident,
    constraints: Option<(&ConstraintSplit, &[ConstraintCode])>,
) -> (TokenStream, TokenStream) {
    let Some((split, codes)) = constraints else {
        return (TokenStream::new(), TokenStream::new());
    };
    let rt = quote!(::dirac::runtime::element);
    let mut items = TokenStream::new();
    let mut visits = Vec::new();
    for (f, (cf, code)) in split.families.iter().zip(codes).enumerate() {
        let name = format_ident!("__{}Constraint{}", ty, f);
        let (s, depth) = (code.width, cf.family.loops.len());
        let body = element_nest(spec, &cf.family, Some(&cf.row));
        let bindings = size_bindings(spec);
        let leaf = leaf_of(spec, quote!(q), quote!(q));
        let outputs: Vec<NodeId> = std::iter::once(code.value)
            .chain(code.gradient.iter().copied())
            .collect();
        let line = straight_line(&code.graph, &outputs, &leaf);
        let (stmts, outs) = (&line.stmts, &line.outputs);
        let len = outs.len();
        let gen = lints::generated();
        items.extend(quote! {
            #[doc(hidden)]
            #[allow(non_camel_case_types)]
            #vis struct #name<'a>(&'a #ty);

            #gen
            #[allow(unused_variables, unused_parens, clippy::identity_op, clippy::erasing_op, clippy::unnecessary_cast, clippy::double_parens, clippy::possible_missing_comma)]
            impl #rt::ConstraintFamily for #name<'_> {
                #[inline]
                fn width(&self) -> usize {
                    #s
                }
                #[inline]
                fn depth(&self) -> usize {
                    #depth
                }
                fn elements(&self, visit: &mut dyn FnMut(&[i64], i64, &[i64])) {
                    let sys = self.0;
                    let __o = sys.__offsets();
                    #(#bindings)*
                    #body
                }
                fn value_gradient(&self, indices: &[i64], q: &[f64], out: &mut [f64]) {
                    let q = #rt::stencil::<#s>(q);
                    let sys = self.0;
                    #stmts
                    *#rt::outputs::<#len>(out) = [#(#outs),*];
                }
            }
        });
        visits.push(quote!(visitor.constraint(&#name(self));));
    }
    let size_tok = |k: usize| {
        let s = format_ident!("__n{}", k);
        quote!(#s)
    };
    let count = split
        .count
        .tokens(&size_tok, &|_| unreachable!("a count reads no loop index"));
    let bindings = size_bindings(spec);
    let lagrangian = quote! {
        const CONSTRAINED: bool = true;
        fn constraint_count(&self) -> usize {
            let sys = self;
            #(#bindings)*
            usize::try_from(#count).unwrap_or(0)
        }
        fn constraint_families<V: #rt::ConstraintVisitor>(&self, visitor: &mut V) {
            #(#visits)*
        }
    };
    (items, lagrangian)
}
