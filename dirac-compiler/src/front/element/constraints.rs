//! The holonomic constraints of an element-wise system, split into families of rows: the
//! closure `|q| { let mut phi = vec![0.0; <count>]; .. phi }` assigns every row once, each
//! assignment `phi[<row>] = <φ>` (in a nest of loops over sizes, or outside loops) being a family
//! whose elements are the nest's iterations — one row each, at the affine index `<row>` — and
//! whose element body is `φ` over its stencil's slots, as the body's families are
//! ([`super::families`]). The rows' count is an integer expression in the sizes; that every row
//! is assigned exactly once is checked by the runtime for the sizes of a run.
//!
//! ```text
//! let <preamble>;
//! let mut phi = vec![0.0; <count>];
//! phi[<row>] = <φ>;                      // one row
//! for i in lo..hi { let <locals>; phi[<row>] = <φ>; for j in .. { .. } }
//! phi
//! ```

use syn::{Block, Expr, ExprClosure, Ident, Stmt};

use super::families::{Elements, FamilySpec, Loop};
use super::index::Index;
use super::ElementCoord;
use crate::ctxt::Ctxt;

/// One family of constraint rows.
pub struct ConstraintFamily {
    pub family: FamilySpec,
    /// The row each element assigns, in the loop indices and sizes.
    pub row: Index,
}

/// The constraints, split.
pub struct ConstraintSplit {
    /// The number of rows, in the sizes.
    pub count: Index,
    pub families: Vec<ConstraintFamily>,
    /// The closure's configuration name.
    pub config: Ident,
}

const SHAPE: &str = "constraints of a system with run-time sizes are written `|q| { let mut phi = \
vec![0.0; <count>]; for i in 0..n { phi[<row>] = <φ>; } phi }`: `let` bindings, the constraint \
vector, assignments of its rows (in loops over sizes or outside them) and the vector as the tail";

/// Splits the constraint closure; `None` after errors (recorded with their spans).
pub fn split(
    cx: &Ctxt,
    closure: &ExprClosure,
    sizes: &[Ident],
    coords: &[ElementCoord],
) -> Option<ConstraintSplit> {
    let config = match closure.inputs.iter().collect::<Vec<_>>().as_slice() {
        [syn::Pat::Ident(pi)] => pi.ident.clone(),
        _ => {
            cx.error_spanned_by(
                &closure.inputs,
                "the constraints take one argument, the configuration: `|q| { .. }`",
            );
            return None;
        }
    };
    let block: Block = match &*closure.body {
        Expr::Block(b) => b.block.clone(),
        other => {
            cx.error_spanned_by(other, SHAPE);
            return None;
        }
    };
    let configs = [&config];
    let mut walker = Walker {
        cx,
        sizes,
        elements: Elements::new(cx, sizes, coords, &configs),
        vector: None,
        count: None,
        families: Vec::new(),
        assignments: 0,
    };
    let (stmts, tail) = match block.stmts.split_last() {
        Some((Stmt::Expr(tail, None), rest)) => (rest, Some(tail)),
        _ => (&block.stmts[..], None),
    };
    let mut preamble = Vec::new();
    for st in stmts {
        match st {
            Stmt::Local(l) if walker.vector.is_none() && walker.is_vector_decl(l) => {}
            Stmt::Local(_) => preamble.push(st.clone()),
            Stmt::Expr(Expr::ForLoop(f), _) => walker.nest(f, &[], &preamble, &[]),
            Stmt::Expr(Expr::Assign(a), _) => walker.row(a, Vec::new(), &preamble, &[]),
            other => cx.error_spanned_by(other, SHAPE),
        }
    }
    let Some(vector) = walker.vector.clone() else {
        cx.error_spanned_by(&closure.body, SHAPE);
        return None;
    };
    match tail {
        Some(Expr::Path(p)) if p.path.is_ident(&vector) => {}
        Some(other) => cx.error_spanned_by(
            other,
            format!("the constraints end with the constraint vector `{vector}`"),
        ),
        None => cx.error_spanned_by(
            &closure.body,
            format!("the constraints end with the constraint vector `{vector}`"),
        ),
    }
    if walker.assignments == 0 {
        cx.error_spanned_by(
            &closure.body,
            format!("no row of `{vector}` is assigned: write `{vector}[<row>] = <φ>;`"),
        );
    }
    Some(ConstraintSplit {
        count: walker.count?,
        families: walker.families,
        config,
    })
}

struct Walker<'a> {
    cx: &'a Ctxt,
    sizes: &'a [Ident],
    elements: Elements<'a>,
    /// The constraint vector's name, once declared.
    vector: Option<Ident>,
    count: Option<Index>,
    families: Vec<ConstraintFamily>,
    /// Assignments seen, valid or not (an invalid one has its own error).
    assignments: usize,
}

impl Walker<'_> {
    /// `let mut phi = vec![0.0; <count>];`: records the vector and its count.
    fn is_vector_decl(&mut self, l: &syn::Local) -> bool {
        let (syn::Pat::Ident(pi), Some(init)) = (&l.pat, &l.init) else {
            return false;
        };
        let Expr::Macro(m) = &*init.expr else {
            return false;
        };
        if !m.mac.path.is_ident("vec") {
            return false;
        }
        let parsed = m.mac.parse_body_with(
            syn::punctuated::Punctuated::<Expr, syn::Token![;]>::parse_separated_nonempty,
        );
        match parsed.ok().filter(|p| p.len() == 2) {
            Some(parts) => {
                let count = Index::parse(self.cx, &parts[1], &[], self.sizes);
                self.vector = Some(pi.ident.clone());
                self.count = count;
                true
            }
            None => {
                self.cx.error_spanned_by(
                    &m.mac,
                    "the constraint vector is `vec![0.0; <count>]`, its count an integer \
                     expression in the sizes (e.g. `n`, `n - 1`, `2 * n`)",
                );
                false
            }
        }
    }

    /// The families of the rows assigned in loop `f` and its nested loops.
    fn nest(&mut self, f: &syn::ExprForLoop, outer: &[Loop], preamble: &[Stmt], locals: &[Stmt]) {
        let Some(nest) = self.elements.nest_of(f, outer) else {
            return;
        };
        let mut visible = locals.to_vec();
        for st in &f.body.stmts {
            match st {
                Stmt::Local(_) => visible.push(st.clone()),
                Stmt::Expr(Expr::ForLoop(inner), _) => self.nest(inner, &nest, preamble, &visible),
                Stmt::Expr(Expr::Assign(a), _) => self.row(a, nest.clone(), preamble, &visible),
                other => self.cx.error_spanned_by(other, SHAPE),
            }
        }
    }

    /// The family of one assignment `phi[<row>] = <φ>`.
    fn row(&mut self, a: &syn::ExprAssign, loops: Vec<Loop>, preamble: &[Stmt], locals: &[Stmt]) {
        self.assignments += 1;
        let Some(vector) = self.vector.clone() else {
            self.cx.error_spanned_by(
                a,
                "declare the constraint vector first: `let mut phi = vec![0.0; <count>];`",
            );
            return;
        };
        let target = match &*a.left {
            Expr::Index(ix) if matches!(&*ix.expr, Expr::Path(p) if p.path.is_ident(&vector)) => {
                &ix.index
            }
            other => {
                self.cx.error_spanned_by(
                    other,
                    format!("expected an assignment of one row of the constraint vector, `{vector}[<row>] = <φ>`"),
                );
                return;
            }
        };
        let vars: Vec<Ident> = loops.iter().map(|l| l.var.clone()).collect();
        let Some(row) = Index::parse(self.cx, target, &vars, self.sizes) else {
            return;
        };
        let family = self.elements.term(loops, preamble, locals, &a.right);
        self.families.push(ConstraintFamily { family, row });
    }
}
