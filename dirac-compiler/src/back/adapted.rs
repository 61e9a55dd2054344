//! Adapted coordinates of a symmetry declared on the user's coordinates (`coordinates(...)`,
//! `translate(...)`): `impl AdaptedCoordinates<N>`, the unimodular change of coordinates
//! `q_user = T q` of the trivialization `Q = Σ × G` (§2.2.1), as straight-line sums and
//! differences. See [`crate::front::layout::Layout`] for `T`.
//!
//! With `shape(...), group(...)` the user's vector is the configuration vector and every map is
//! the identity.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::Ident;

use crate::back::lints;
use crate::front::layout::Component;
use crate::front::layout::Layout;

/// `impl ::dirac::runtime::AdaptedCoordinates<N> for ty`.
pub fn adapted_impl(layout: &Layout, ty: &Ident) -> TokenStream {
    let n = layout.components.len();
    let rt = quote!(::dirac::runtime);
    let na = quote!(::dirac::nalgebra);
    let vn = quote!(&#na::SVector<f64, #n>);
    let rn = quote!(#na::SVector<f64, #n>);
    let allow = lints::generated();
    let (to, from, p_to, p_from) = if layout.declared {
        let maps = Maps::new(layout);
        (
            maps.user_to_adapted(),
            maps.adapted_to_user(),
            maps.momentum_user_to_adapted(),
            maps.momentum_adapted_to_user(),
        )
    } else {
        let id = |v: TokenStream| quote!(*#v);
        (
            id(quote!(q_user)),
            id(quote!(q)),
            id(quote!(p_user)),
            id(quote!(p)),
        )
    };
    quote! {
        #allow
        #[automatically_derived]
        impl #rt::AdaptedCoordinates<#n> for #ty {
            #[inline]
            fn to_adapted(q_user: #vn) -> #rn {
                #to
            }

            #[inline]
            fn from_adapted(q: #vn) -> #rn {
                #from
            }

            #[inline]
            fn momentum_to_adapted(p_user: #vn) -> #rn {
                #p_to
            }

            #[inline]
            fn momentum_from_adapted(p: #vn) -> #rn {
                #p_from
            }
        }
    }
}

/// `<Config>::from_vector(q)` on a vector `q` of the system: through `from_adapted` when the
/// coordinates are adapted, so the user's function reads the user's coordinates.
pub fn user_config(layout: &Layout, ty: &Ident, config: &Ident, q: TokenStream) -> TokenStream {
    if layout.declared {
        let n = layout.components.len();
        quote! {
            #config::from_vector(&<#ty as ::dirac::runtime::AdaptedCoordinates<#n>>::from_adapted(#q))
        }
    } else {
        quote! { #config::from_vector(#q) }
    }
}

/// The four maps as index arithmetic: user component `u` is `q[a]` (`Var`) or `q[g] + q[r]`
/// (`Sum`).
struct Maps<'a> {
    layout: &'a Layout,
    n: usize,
}

impl<'a> Maps<'a> {
    fn new(layout: &'a Layout) -> Self {
        Maps {
            layout,
            n: layout.components.len(),
        }
    }

    /// The vector of `entries`, each bound to a local first (one line each, as the rest of the
    /// generated code; a sum inside an array literal trips `clippy::possible_missing_comma`).
    fn vector(&self, entries: Vec<TokenStream>) -> TokenStream {
        let n = self.n;
        let names: Vec<Ident> = (0..n).map(|i| format_ident!("__e{}", i)).collect();
        quote! {
            #( let #names = #entries; )*
            ::dirac::nalgebra::SVector::<f64, #n>::from([ #( #names ),* ])
        }
    }

    /// For each adapted index, the user component it comes from (the group coordinate's own
    /// component for a group index).
    fn source(&self) -> Vec<usize> {
        let mut source = vec![0; self.n];
        for (u, c) in self.layout.components.iter().enumerate() {
            match *c {
                Component::Var(a) => source[a] = u,
                Component::Sum(_, r) => source[r] = u,
            }
        }
        source
    }

    /// The user component that carries group coordinate `g` (`a[0]`).
    fn group_source(&self, g: usize) -> usize {
        self.layout
            .components
            .iter()
            .position(|c| *c == Component::Var(g))
            .expect("every group coordinate is a user component")
    }

    /// `q = T⁻¹ q_user`: `g_j = a[0]`, `r_c = c − a[0]`, other coordinates unchanged.
    fn user_to_adapted(&self) -> TokenStream {
        let source = self.source();
        let entries = (0..self.n)
            .map(|a| {
                let u = source[a];
                match self.layout.components[u] {
                    Component::Sum(g, _) => {
                        let u0 = self.group_source(g);
                        quote!(q_user[#u] - q_user[#u0])
                    }
                    Component::Var(_) => quote!(q_user[#u]),
                }
            })
            .collect();
        self.vector(entries)
    }

    /// `q_user = T q`: `a[0] = g_j`, `c = g_j + r_c` (the sum the lowered body forms).
    fn adapted_to_user(&self) -> TokenStream {
        let entries = self
            .layout
            .components
            .iter()
            .map(|c| match *c {
                Component::Var(a) => quote!(q[#a]),
                Component::Sum(g, r) => quote!(q[#g] + q[#r]),
            })
            .collect();
        self.vector(entries)
    }

    /// `p = Tᵀ p_user`: `p_{r_c} = p_user_c`, `p_{g_j} = Σ` of the momenta of every component the
    /// translation moves (the total momentum, its momentum map).
    fn momentum_user_to_adapted(&self) -> TokenStream {
        let source = self.source();
        let s = self.layout.s();
        let entries = (0..self.n)
            .map(|a| {
                if a < s {
                    let u = source[a];
                    return quote!(p_user[#u]);
                }
                let moved: Vec<usize> = self
                    .layout
                    .components
                    .iter()
                    .enumerate()
                    .filter(
                        |(_, c)| matches!(**c, Component::Var(g) | Component::Sum(g, _) if g == a),
                    )
                    .map(|(u, _)| u)
                    .collect();
                quote!(#( p_user[#moved] )+*)
            })
            .collect();
        self.vector(entries)
    }

    /// `p_user = T⁻ᵀ p`: `p_user_c = p_{r_c}`, `p_user_{a[0]} = p_{g_j} − Σ_{c ≠ a[0]} p_{r_c}`.
    fn momentum_adapted_to_user(&self) -> TokenStream {
        let entries = self
            .layout
            .components
            .iter()
            .map(|c| match *c {
                Component::Sum(_, r) => quote!(p[#r]),
                Component::Var(a) if a < self.layout.s() => quote!(p[#a]),
                Component::Var(g) => {
                    let shapes: Vec<usize> = self
                        .layout
                        .components
                        .iter()
                        .filter_map(|c| match *c {
                            Component::Sum(h, r) if h == g => Some(r),
                            _ => None,
                        })
                        .collect();
                    quote!(p[#g] #( - p[#shapes] )*)
                }
            })
            .collect();
        self.vector(entries)
    }
}
