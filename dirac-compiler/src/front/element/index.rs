//! Index expressions of an element-wise body: integer code in the sizes, the element loops'
//! indices and literals, affine in the loop indices (`i`, `i + 1`, `(i + 1) % n`, `i * m + j`,
//! `n - 1`). Parsed from the body, evaluated on sample sizes by the range check, and emitted as
//! `i64` code for the run-time stencils.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;
use syn::{BinOp, Expr, Ident, Lit};

use crate::ctxt::Ctxt;

/// What an index may be built from, for messages.
pub const INDEX_ACCEPTED: &str = "integer literals, the sizes, the indices of the enclosing \
`for` loops over sizes, `+`, `-`, `*` (by a literal or a size, so the index stays affine in the \
loop indices) and `%` (by a literal or a size), e.g. `x[i + 1]`, `x[(i + 1) % n]`, `u[i][(j + 1) % m]`";

/// An integer expression over the sizes and the loop indices.
#[derive(Clone, Debug)]
pub enum Index {
    Lit(i64),
    /// The index of the `k`-th enclosing element loop (outermost first).
    Loop(usize),
    /// The `k`-th size.
    Size(usize),
    Add(Box<Index>, Box<Index>),
    Sub(Box<Index>, Box<Index>),
    Mul(Box<Index>, Box<Index>),
    Rem(Box<Index>, Box<Index>),
}

/// Why an index could not be evaluated.
#[derive(Debug, PartialEq, Eq)]
pub enum EvalError {
    /// A subtraction went below zero (a `usize` underflow in the user's function).
    Underflow,
    /// `% 0`.
    ZeroModulus,
}

impl Index {
    /// Parses `e` with `loops` the enclosing element loops' indices and `sizes` the sizes;
    /// `None` after an error (recorded with its span).
    pub fn parse(cx: &Ctxt, e: &Expr, loops: &[Ident], sizes: &[Ident]) -> Option<Index> {
        Self::parse_with(cx, e, loops, sizes, &HashMap::new())
    }

    /// Whether `e` is an index expression (no error recorded either way).
    pub fn try_parse(
        e: &Expr,
        loops: &[Ident],
        sizes: &[Ident],
        aliases: &HashMap<String, Index>,
    ) -> Option<Index> {
        let cx = Ctxt::new();
        let parsed = Self::parse_with(&cx, e, loops, sizes, aliases);
        cx.finish(parsed).ok()
    }

    /// [`Self::parse`] where the names of `aliases` (integer `let`s of the body, `let j = (i +
    /// 1) % n;`) stand for their index expressions.
    pub fn parse_with(
        cx: &Ctxt,
        e: &Expr,
        loops: &[Ident],
        sizes: &[Ident],
        aliases: &HashMap<String, Index>,
    ) -> Option<Index> {
        let fail = |what: String| {
            cx.error_spanned_by(
                e,
                format!("{what}; an index is built from {INDEX_ACCEPTED}"),
            );
            None
        };
        match e {
            Expr::Paren(p) => Self::parse_with(cx, &p.expr, loops, sizes, aliases),
            Expr::Group(g) => Self::parse_with(cx, &g.expr, loops, sizes, aliases),
            Expr::Lit(l) => match &l.lit {
                Lit::Int(i) => match i.base10_parse::<i64>() {
                    Ok(v) => Some(Index::Lit(v)),
                    Err(_) => fail(format!("`{}` is not an integer that fits i64", i)),
                },
                _ => fail(format!("`{}` is not an integer", crate::ctxt::show(&l))),
            },
            Expr::Path(p) => {
                let Some(id) = p.path.get_ident() else {
                    return fail(format!(
                        "`{}` is not a size or a loop index",
                        crate::ctxt::show(&p)
                    ));
                };
                if let Some(k) = loops.iter().rposition(|l| l == id) {
                    Some(Index::Loop(k))
                } else if let Some(k) = sizes.iter().position(|s| s == id) {
                    Some(Index::Size(k))
                } else if let Some(index) = aliases.get(&id.to_string()) {
                    Some(index.clone())
                } else {
                    fail(format!(
                        "`{id}` is neither a size (a `usize` argument) nor the index of an enclosing `for` loop over sizes"
                    ))
                }
            }
            Expr::Binary(b) => {
                let l = Self::parse_with(cx, &b.left, loops, sizes, aliases);
                let r = Self::parse_with(cx, &b.right, loops, sizes, aliases);
                let (l, r) = (Box::new(l?), Box::new(r?));
                match b.op {
                    BinOp::Add(_) => Some(Index::Add(l, r)),
                    BinOp::Sub(_) => Some(Index::Sub(l, r)),
                    BinOp::Mul(_) => {
                        if l.reads_loop() && r.reads_loop() {
                            fail(format!(
                                "`{}` multiplies loop indices: the index would not be affine in the loop indices",
                                crate::ctxt::show(&e)
                            ))
                        } else {
                            Some(Index::Mul(l, r))
                        }
                    }
                    BinOp::Rem(_) => {
                        if r.reads_loop() {
                            fail(format!(
                                "`{}`: the modulus must be a literal or a size, not a loop index",
                                crate::ctxt::show(&e)
                            ))
                        } else {
                            Some(Index::Rem(l, r))
                        }
                    }
                    _ => fail(format!(
                        "the operator `{}` is not accepted in an index",
                        crate::ctxt::show(&b.op)
                    )),
                }
            }
            _ => fail(format!(
                "`{}` is not an index expression",
                crate::ctxt::show(&e)
            )),
        }
    }

    /// Whether the expression reads a loop index.
    pub fn reads_loop(&self) -> bool {
        match self {
            Index::Loop(_) => true,
            Index::Lit(_) | Index::Size(_) => false,
            Index::Add(a, b) | Index::Sub(a, b) | Index::Mul(a, b) | Index::Rem(a, b) => {
                a.reads_loop() || b.reads_loop()
            }
        }
    }

    /// The value at the given sizes and loop indices, with `usize` semantics (a negative
    /// intermediate is an underflow).
    pub fn eval(&self, sizes: &[i64], loops: &[i64]) -> Result<i64, EvalError> {
        let v = match self {
            Index::Lit(v) => *v,
            Index::Loop(k) => loops[*k],
            Index::Size(k) => sizes[*k],
            Index::Add(a, b) => a.eval(sizes, loops)? + b.eval(sizes, loops)?,
            Index::Sub(a, b) => a.eval(sizes, loops)? - b.eval(sizes, loops)?,
            Index::Mul(a, b) => a.eval(sizes, loops)? * b.eval(sizes, loops)?,
            Index::Rem(a, b) => {
                let m = b.eval(sizes, loops)?;
                if m == 0 {
                    return Err(EvalError::ZeroModulus);
                }
                a.eval(sizes, loops)? % m
            }
        };
        if v < 0 {
            Err(EvalError::Underflow)
        } else {
            Ok(v)
        }
    }

    /// `i64` code: `size(k)` and `loop_var(k)` give the expressions of the sizes and indices.
    /// (At run time the stencil is checked as a whole, so `%` is `rem_euclid` and a negative
    /// value is reported, not wrapped.)
    pub fn tokens(
        &self,
        size: &dyn Fn(usize) -> TokenStream,
        loop_var: &dyn Fn(usize) -> TokenStream,
    ) -> TokenStream {
        match self {
            Index::Lit(v) => quote!((#v as i64)),
            Index::Loop(k) => loop_var(*k),
            Index::Size(k) => size(*k),
            Index::Add(a, b) => {
                let (a, b) = (a.tokens(size, loop_var), b.tokens(size, loop_var));
                quote!((#a + #b))
            }
            Index::Sub(a, b) => {
                let (a, b) = (a.tokens(size, loop_var), b.tokens(size, loop_var));
                quote!((#a - #b))
            }
            Index::Mul(a, b) => {
                let (a, b) = (a.tokens(size, loop_var), b.tokens(size, loop_var));
                quote!((#a * #b))
            }
            Index::Rem(a, b) => {
                let (a, b) = (a.tokens(size, loop_var), b.tokens(size, loop_var));
                quote!((#a).rem_euclid((#b).max(1)))
            }
        }
    }

    /// A canonical text, to merge equal stencil reads into one slot.
    pub fn key(&self) -> String {
        format!("{self:?}")
    }
}
