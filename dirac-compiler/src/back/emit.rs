//! Graph → straight-line Rust. Each live operation node becomes one local assigned once; leaves
//! are read directly; constants are inlined; nodes no output depends on are never emitted.
//!
//! Every `let` opens a lexical scope nested in the previous one, and with debug info LLVM walks
//! those scopes recursively: a 200-particle lattice (≈ 10⁵ operations, one `let` each)
//! overflowed rustc's stack in a debug build. So a function with more than [`PLAIN_LETS_MAX`]
//! locals declares them [`DECLARE_CHUNK`] at a time (`let (a, b, ..): (f64, ..);` then
//! `a = ..; b = ..;`), and its nesting depth is the number of chunks; smaller functions (the
//! paper's systems) keep one readable `let` per operation.

use rustc_hash::FxHashMap as HashMap;

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use crate::ir::graph::{Graph, Node, NodeId, Sym};

/// Straight-line code computing `outputs`: the statements and one expression per output.
pub struct StraightLine {
    pub stmts: TokenStream,
    pub outputs: Vec<TokenStream>,
    /// Number of `let` statements emitted for operations.
    pub operations: usize,
}

/// Emits the code for `outputs`; `leaf` gives the expression that reads a symbol.
pub fn straight_line(
    g: &Graph,
    outputs: &[NodeId],
    leaf: &dyn Fn(Sym) -> TokenStream,
) -> StraightLine {
    let mut expr: HashMap<NodeId, TokenStream> = HashMap::default();
    let mut bindings: Vec<(Ident, TokenStream)> = Vec::new();
    let mut operations = 0;
    let mut bound_leaves: HashMap<Sym, Ident> = HashMap::default();
    for id in g.cone(outputs) {
        let e = |n: NodeId| expr[&n].clone();
        let node = g.node(id);
        let value = match node {
            Node::Const(bits) => {
                expr.insert(id, literal(f64::from_bits(bits)));
                continue;
            }
            Node::Var(sym) => {
                let name = bound_leaves
                    .entry(sym)
                    .or_insert_with(|| leaf_name(sym))
                    .clone();
                let read = leaf(sym);
                bindings.push((name.clone(), quote! { #read }));
                expr.insert(id, quote! { #name });
                continue;
            }
            Node::Neg(a) => {
                let a = e(a);
                quote! { -#a }
            }
            Node::Add(a, b) => binary(e(a), quote!(+), e(b)),
            Node::Sub(a, b) => binary(e(a), quote!(-), e(b)),
            Node::Mul(a, b) => binary(e(a), quote!(*), e(b)),
            Node::Div(a, b) => binary(e(a), quote!(/), e(b)),
            Node::Fun(f, a) => {
                let a = e(a);
                let m = Ident::new(f.name(), Span::call_site());
                quote! { #a.#m() }
            }
            Node::Powi(a, n) => {
                let a = e(a);
                quote! { #a.powi(#n) }
            }
            Node::Powf(a, b) => {
                let (a, b) = (e(a), e(b));
                quote! { #a.powf(#b) }
            }
            Node::Atan2(y, x) => {
                let (y, x) = (e(y), e(x));
                quote! { #y.atan2(#x) }
            }
        };
        let name = format_ident!("__t{}", id.0);
        bindings.push((name.clone(), value));
        operations += 1;
        expr.insert(id, quote! { #name });
    }
    let outputs = outputs.iter().map(|o| expr[o].clone()).collect();
    let stmts = declare_in_chunks(&bindings);
    StraightLine {
        stmts,
        outputs,
        operations,
    }
}

/// Most locals a function declares with one `let` each; see the module documentation.
const PLAIN_LETS_MAX: usize = 2048;

/// Locals declared per `let` above [`PLAIN_LETS_MAX`]; see the module documentation.
const DECLARE_CHUNK: usize = 64;

/// `let a: f64 = ..;` per binding up to [`PLAIN_LETS_MAX`] bindings; above, for each chunk of
/// bindings in order, `let (a, b, ..): (f64, f64, ..); a = ..; b = ..;`.
fn declare_in_chunks(bindings: &[(Ident, TokenStream)]) -> TokenStream {
    let mut stmts = TokenStream::new();
    if bindings.len() <= PLAIN_LETS_MAX {
        for (name, value) in bindings {
            stmts.extend(quote! { let #name: f64 = #value; });
        }
        return stmts;
    }
    for chunk in bindings.chunks(DECLARE_CHUNK) {
        let names = chunk.iter().map(|(name, _)| name);
        let types = chunk.iter().map(|_| quote!(f64));
        stmts.extend(quote! { let (#(#names,)*): (#(#types,)*); });
        for (name, value) in chunk {
            stmts.extend(quote! { #name = #value; });
        }
    }
    stmts
}

fn binary(a: TokenStream, op: TokenStream, b: TokenStream) -> TokenStream {
    quote! { #a #op #b }
}

fn leaf_name(sym: Sym) -> Ident {
    match sym {
        Sym::Q0(i) => format_ident!("__q0_{}", i),
        Sym::Q1(i) => format_ident!("__q1_{}", i),
        Sym::X0(i) => format_ident!("__x0_{}", i),
        Sym::X1(i) => format_ident!("__x1_{}", i),
        Sym::G1(i) => format_ident!("__g1_{}", i),
        Sym::G0(i) => format_ident!("__g0_{}", i),
        Sym::P(i) => format_ident!("__p_{}", i),
        Sym::W(i) => format_ident!("__w_{}", i),
        Sym::Mu(i) => format_ident!("__mu_{}", i),
        Sym::Param(i) => format_ident!("__p{}", i),
        Sym::D0(i) => format_ident!("__d0_{}", i),
        Sym::D1(i) => format_ident!("__d1_{}", i),
        Sym::Lambda(i) => format_ident!("__lambda_{}", i),
        Sym::Base(i) => format_ident!("__b_{}", i),
        Sym::Chart0(i) => format_ident!("__xi_{}", i),
        Sym::Chart1(i) => format_ident!("__z_{}", i),
        Sym::Rel(i) => format_ident!("__rel_{}", i),
    }
}

/// An f64 literal token, parenthesized when negative; non-finite values by name.
pub fn literal(v: f64) -> TokenStream {
    if v.is_nan() {
        quote! { f64::NAN }
    } else if v.is_infinite() {
        if v > 0.0 {
            quote! { f64::INFINITY }
        } else {
            quote! { f64::NEG_INFINITY }
        }
    } else if v < 0.0 {
        let l = Literal::f64_suffixed(-v);
        quote! { (-#l) }
    } else {
        let l = Literal::f64_suffixed(v);
        quote! { #l }
    }
}
