//! `shape(x)` and `group(x)`: a real coordinate, its chart the translation `x + ξ`; a `group`
//! coordinate's translations are a declared symmetry (§2.2.1), so its momentum is conserved by
//! the explicit discrete Noether balance.

use proc_macro2::TokenStream;
use quote::quote;
use syn::Ident;

use super::{Group, KindSpec, Paths, Rotated, Step};
use crate::front::layout::Reading;
use crate::ir::graph::{Graph, NodeId};

/// A real coordinate: `shape(x)`, or `group(x)` when its spec declares translations.
pub struct Scalar(KindSpec);

/// `shape(x)`.
pub static SHAPE: Scalar = Scalar(KindSpec::new(crate::symbol::SHAPE, 1, 1, 1));

/// `group(x)`.
pub static GROUP: Scalar = Scalar(KindSpec::new(crate::symbol::GROUP, 1, 1, 1).translations());

impl Group for Scalar {
    fn spec(&self) -> &KindSpec {
        &self.0
    }

    fn reads(&self, _point: usize) -> Option<Reading> {
        None
    }

    fn reads_velocity(&self, velocity: usize) -> Reading {
        Reading::block(1, 1, velocity)
    }

    fn chart(&self, g: &mut Graph, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId> {
        vec![g.add(base[0], xi[0])]
    }

    /// `(x1 − x0)/h`.
    fn velocity(&self, g: &mut Graph, step: &Step) -> Vec<NodeId> {
        step.chord(g, [0])
    }

    fn rotated(&self) -> Rotated {
        Rotated::Refused(|id| {
            format!(
                "`{id}` is a scalar coordinate; `symmetry(..)` lists rotation and direction coordinates \
                 (declare translations of a scalar with `group({id})`)"
            )
        })
    }

    fn sample(&self, t: f64, at: usize) -> [Vec<f64>; 2] {
        let k = at as f64;
        [
            vec![0.3 + 0.2 * t + 0.11 * k],
            vec![-0.4 + 0.1 * t - 0.07 * k],
        ]
    }

    fn rotate(&self, _g: &[[f64; 3]; 3], _point: &mut [f64]) {}

    fn config_field(&self, _: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        (quote!(f64), format!("The coordinate `{name}`."))
    }

    fn read_point(&self, _: &Paths, _: &Ident, at: usize) -> TokenStream {
        quote!(q[#at])
    }

    fn write_point(&self, _: &Paths, name: &Ident, at: usize) -> TokenStream {
        quote!(q[#at] = self.#name;)
    }

    fn momentum_field(&self, _: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        (quote!(f64), format!("The momentum conjugate to `{name}`."))
    }

    fn read_chart(&self, _: &Paths, _: &Ident, _at: usize, ch: usize) -> TokenStream {
        quote!(p[#ch])
    }

    fn write_chart(&self, _: &Paths, name: &Ident, _at: usize, ch: usize) -> TokenStream {
        quote!(p[#ch] = self.#name;)
    }

    fn velocity_field(&self, _: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        (quote!(f64), format!("The rate of `{name}`."))
    }

    fn velocity_entries(&self, v: &TokenStream) -> Vec<TokenStream> {
        vec![v.clone()]
    }
}
