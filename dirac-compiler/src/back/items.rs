//! The items around the trait impls: the configuration struct `<Name>Config`, the user's
//! function (still callable, with `Config` replaced), and the parameter struct `<Name>`.

use proc_macro2::TokenStream;
use quote::quote;
use syn::parse::Parser;
use syn::{Ident, ItemFn};

use crate::back::lints;
use crate::front::layout::Coord;
use crate::front::signature::Signature;
use crate::front::Spec;

/// The emitted type's name: `name = ..`, or the function's name in CamelCase.
pub fn type_name(spec: &Spec, func: &ItemFn) -> Ident {
    spec.name
        .clone()
        .unwrap_or_else(|| camel_case(&func.sig.ident))
}

/// `charged_particle` → `ChargedParticle`, with the span of `ident`.
pub fn camel_case(ident: &Ident) -> Ident {
    let camel: String = ident
        .to_string()
        .split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
        })
        .collect();
    Ident::new(&camel, ident.span())
}

/// The user's function with `Config` replaced by the emitted configuration struct.
pub fn user_function(
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

pub fn config_struct(spec: &Spec, func: &ItemFn, config: &Ident, type_name: &Ident) -> TokenStream {
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
    // The two layouts differ only in what the vector holds, which the docs say.
    let (read_doc, write_doc) = if layout.declared {
        (
            " Reads the user configuration vector: your coordinates, components flattened in \
             declaration order (not the system's adapted `q`; see `AdaptedCoordinates`).",
            " Writes the user configuration vector: your coordinates, components flattened in \
             declaration order (`AdaptedCoordinates::to_adapted` maps it to `q`).",
        )
    } else {
        (
            " Reads `q = (x, g)` in configuration order.",
            " Writes `q = (x, g)` in configuration order.",
        )
    };
    let vector_fns = quote! {
        impl #config {
            #[doc = #read_doc]
            pub fn from_vector(q: &::dirac::nalgebra::SVector<f64, #n>) -> Self {
                Self { #( #inits, )* }
            }

            #[doc = #write_doc]
            pub fn to_vector(&self) -> ::dirac::nalgebra::SVector<f64, #n> {
                ::dirac::nalgebra::SVector::<f64, #n>::from([ #( #elems, )* ])
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

pub fn param_struct(sig: &Signature, func: &ItemFn, type_name: &Ident) -> TokenStream {
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
