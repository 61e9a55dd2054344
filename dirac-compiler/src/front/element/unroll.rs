//! Loops with constant bounds inside an element (`for d in 0..3`, the components of a point
//! stored with strided indices `x[3 * i + d]`): unrolled before the element's coordinate reads
//! become slots, so each iteration's reads are slots of their own (`x[3 * i + 0]`, …) and the
//! element's stencil covers them all.

use std::collections::HashMap;

use syn::visit_mut::VisitMut;
use syn::{Expr, ExprForLoop, Ident, Stmt};

use super::index::Index;

/// The variable and the constant range `lo..hi` (exclusive) of `f`, when both bounds are integer
/// expressions of literals alone (`0..3`, `0..=2`, `1 + 1..3`).
pub fn constant_range(f: &ExprForLoop) -> Option<(Ident, i64, i64)> {
    let syn::Pat::Ident(pi) = &*f.pat else {
        return None;
    };
    let Expr::Range(range) = &*f.expr else {
        return None;
    };
    let constant = |e: &Option<Box<Expr>>| -> Option<i64> {
        let index = Index::try_parse(e.as_deref()?, &[], &[], &HashMap::new())?;
        index.eval(&[], &[]).ok()
    };
    let (lo, mut hi) = (constant(&range.start)?, constant(&range.end)?);
    if matches!(range.limits, syn::RangeLimits::Closed(_)) {
        hi += 1;
    }
    Some((pi.ident.clone(), lo, hi))
}

/// `f` unrolled: a block of one block per iteration, the loop variable replaced by its value
/// (an integer literal), nested constant loops unrolled too. `None` when `f` is not a loop over
/// a constant range.
pub fn unroll(f: &ExprForLoop) -> Option<Stmt> {
    let (var, lo, hi) = constant_range(f)?;
    let iterations: Vec<Stmt> = (lo..hi)
        .map(|k| {
            let mut body = f.body.clone();
            Substitute {
                var: &var,
                value: k,
            }
            .visit_block_mut(&mut body);
            UnrollAll.visit_block_mut(&mut body);
            Stmt::Expr(
                Expr::Block(syn::ExprBlock {
                    attrs: Vec::new(),
                    label: None,
                    block: body,
                }),
                None,
            )
        })
        .collect();
    Some(Stmt::Expr(
        Expr::Block(syn::ExprBlock {
            attrs: Vec::new(),
            label: None,
            block: syn::Block {
                brace_token: Default::default(),
                stmts: iterations,
            },
        }),
        None,
    ))
}

/// Whether `stmts` (and the blocks and constant loops in them) contain a statement for which
/// `adds` holds: an addition to the accumulator.
pub fn contains(stmts: &[Stmt], adds: &dyn Fn(&Expr) -> bool) -> bool {
    stmts.iter().any(|st| match st {
        Stmt::Expr(Expr::ForLoop(f), _) => contains(&f.body.stmts, adds),
        Stmt::Expr(Expr::Block(b), _) => contains(&b.block.stmts, adds),
        Stmt::Expr(e, _) => adds(e),
        _ => false,
    })
}

/// Replaces the loop variable by its value.
struct Substitute<'a> {
    var: &'a Ident,
    value: i64,
}

impl VisitMut for Substitute<'_> {
    fn visit_expr_mut(&mut self, e: &mut Expr) {
        if matches!(e, Expr::Path(p) if p.path.is_ident(self.var)) {
            let lit = syn::LitInt::new(&self.value.to_string(), proc_macro2::Span::call_site());
            *e = syn::parse_quote!(#lit);
            return;
        }
        syn::visit_mut::visit_expr_mut(self, e);
    }
}

/// Unrolls every loop over a constant range, innermost first.
struct UnrollAll;

impl VisitMut for UnrollAll {
    fn visit_stmt_mut(&mut self, st: &mut Stmt) {
        if let Stmt::Expr(Expr::ForLoop(f), _) = st {
            if let Some(unrolled) = unroll(f) {
                *st = unrolled;
                return;
            }
        }
        syn::visit_mut::visit_stmt_mut(self, st);
    }
}
