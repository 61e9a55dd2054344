//! The body of an element-wise system, split into families of elements: every `for` loop over
//! sizes whose body adds to the accumulator is a family (nested loops — pairs `for j in i + 1..n`,
//! grids — are families of their own, one element per iteration of the whole nest), and the
//! terms outside loops form one family of a single element. Each family's element body is the
//! loop body with every coordinate read `q.x[<index>]` replaced by a slot of the element's
//! stencil (`q.__s0`, …), so the fixed-size front end lowers and differentiates one element;
//! the slots' indices are kept as integer code ([`Index`]).
//!
//! The body's shape:
//!
//! ```text
//! let <preamble>;                 // any number of `let`s, visible to every element
//! let mut l = <init>;            // the accumulator (its initial value is a term outside loops)
//! for i in lo..hi {              // bounds: sizes, literals, enclosing loop indices
//!     let <locals>;
//!     l += <term>;  l -= <term>;
//!     for j in i + 1..hi { .. }  // a nested family
//! }
//! l += <term>;                   // terms outside loops
//! l ± <term> ± ..                // the tail
//! ```

use std::collections::HashMap;

use quote::{format_ident, ToTokens};
use syn::spanned::Spanned;
use syn::visit_mut::VisitMut;
use syn::{BinOp, Block, Expr, Ident, Member, Stmt};

use super::index::{EvalError, Index};
use super::{Dim, ElementCoord};
use crate::ctxt::Ctxt;

/// A loop of a family's nest.
#[derive(Clone, Debug)]
pub struct Loop {
    pub var: Ident,
    pub lo: Index,
    /// Exclusive.
    pub hi: Index,
    /// The range's tokens, for messages.
    pub tokens: proc_macro2::TokenStream,
}

/// A coordinate read of an element: the coordinate and one index per dimension.
#[derive(Clone, Debug)]
pub struct Slot {
    pub coord: usize,
    pub index: Vec<Index>,
    /// The first read's tokens, for messages.
    pub tokens: proc_macro2::TokenStream,
    pub text: String,
}

/// One family of elements.
pub struct FamilySpec {
    pub loops: Vec<Loop>,
    pub slots: Vec<Slot>,
    /// The element's body over the slots.
    pub block: Block,
}

/// The name of slot `k` in an element body.
pub fn slot_name(k: usize) -> String {
    format!("__s{k}")
}

/// The parameter an element body reads for the `k`-th size as an f64.
pub fn size_param(k: usize) -> Ident {
    format_ident!("__size{}", k)
}

/// The parameter an element body reads for the `k`-th loop index as an f64.
pub fn loop_param(k: usize) -> Ident {
    format_ident!("__index{}", k)
}

/// The statements of the body before the tail, and the tail.
struct Splitter<'a> {
    cx: &'a Ctxt,
    sizes: &'a [Ident],
    coords: &'a [ElementCoord],
    /// The configuration names (`q`, `v` or `q0`, `q1`, and a force's displacements).
    configs: &'a [&'a Ident],
    acc: Option<Ident>,
    families: Vec<FamilySpec>,
    /// Terms outside loops, as statements adding to the accumulator.
    outside: Vec<Stmt>,
}

/// Splits `block` into families; `None` after errors (recorded with their spans).
pub fn split(
    cx: &Ctxt,
    block: &Block,
    sizes: &[Ident],
    coords: &[ElementCoord],
    configs: &[&Ident],
) -> Option<Vec<FamilySpec>> {
    let mut s = Splitter {
        cx,
        sizes,
        coords,
        configs,
        acc: None,
        families: Vec::new(),
        outside: Vec::new(),
    };
    let (stmts, tail) = match block.stmts.split_last() {
        Some((Stmt::Expr(tail, None), rest)) => (rest, tail),
        _ => {
            cx.error_spanned_by(
                block,
                "the body must end with the accumulated Lagrangian, e.g. `l` or `l - <term>`",
            );
            return None;
        }
    };
    // The accumulator: the leftmost name of the tail.
    let mut leftmost = tail;
    while let Expr::Binary(b) = leftmost {
        leftmost = &b.left;
    }
    if let Expr::Path(p) = leftmost {
        if let Some(id) = p.path.get_ident() {
            let declared = stmts.iter().any(|st| matches!(st, Stmt::Local(l) if matches!(&l.pat, syn::Pat::Ident(pi) if pi.ident == *id && pi.mutability.is_some())));
            if declared {
                s.acc = Some(id.clone());
            }
        }
    }
    let mut preamble: Vec<Stmt> = Vec::new();
    for st in stmts {
        match st {
            Stmt::Local(l) if s.is_acc_decl(l) => {
                let init = l.init.as_ref().map(|i| &*i.expr);
                if let Some(init) = init.filter(|e| !is_zero(e)) {
                    let acc = s.acc.clone().expect("declared");
                    s.outside.push(syn::parse_quote!(#acc += #init;));
                }
            }
            Stmt::Local(_) => preamble.push(st.clone()),
            Stmt::Expr(Expr::ForLoop(f), _) => s.family(f, &[], &preamble, &[]),
            Stmt::Expr(e, _) if s.adds_to_acc(e) => s.outside.push(st.clone()),
            other => cx.error_spanned_by(
                other,
                "expected `let` bindings, `for` loops over sizes and additions to the accumulator (`l += ...`, `l -= ...`)",
            ),
        }
    }
    // The tail: `acc ± term ± ...` or, without an accumulator, one term.
    match &s.acc {
        Some(acc) => {
            let mut cur = tail;
            let mut terms = Vec::new();
            while let Expr::Binary(b) = cur {
                match b.op {
                    BinOp::Add(_) | BinOp::Sub(_) => {
                        terms.push((b.op, (*b.right).clone()));
                        cur = &b.left;
                    }
                    _ => break,
                }
            }
            if !matches!(cur, Expr::Path(p) if p.path.is_ident(acc)) {
                cx.error_spanned_by(
                    tail,
                    format!("the tail must be `{acc}` or `{acc} ± <term> ± ...`"),
                );
            }
            for (op, term) in terms.into_iter().rev() {
                let stmt: Stmt = match op {
                    BinOp::Add(_) => syn::parse_quote!(#acc += #term;),
                    _ => syn::parse_quote!(#acc -= #term;),
                };
                s.outside.push(stmt);
            }
        }
        None => {
            if !s.families.is_empty() {
                cx.error_spanned_by(tail, "declare an accumulator (`let mut l = 0.0;`), add to it in the loops and end the body with it");
            }
            let acc = format_ident!("__l");
            s.acc = Some(acc.clone());
            s.outside.push(syn::parse_quote!(#acc += #tail;));
        }
    }
    if !s.outside.is_empty() {
        let outside = std::mem::take(&mut s.outside);
        let block = s.element_block(&preamble, &[], &outside);
        s.push_family(Vec::new(), block);
    }
    Some(s.families)
}

fn is_zero(e: &Expr) -> bool {
    matches!(e, Expr::Lit(l) if matches!(&l.lit, syn::Lit::Float(f) if f.base10_parse::<f64>().ok() == Some(0.0)))
        || matches!(e, Expr::Lit(l) if matches!(&l.lit, syn::Lit::Int(i) if i.base10_parse::<i64>().ok() == Some(0)))
}

impl Splitter<'_> {
    fn is_acc_decl(&self, l: &syn::Local) -> bool {
        matches!((&l.pat, &self.acc), (syn::Pat::Ident(pi), Some(acc)) if pi.ident == *acc)
    }

    fn adds_to_acc(&self, e: &Expr) -> bool {
        matches!((e, &self.acc), (Expr::Binary(b), Some(acc))
            if matches!(b.op, BinOp::AddAssign(_) | BinOp::SubAssign(_))
                && matches!(&*b.left, Expr::Path(p) if p.path.is_ident(acc)))
    }

    /// The nest `outer` with loop `f` inside it; `None` after errors (recorded).
    fn nest_of(&self, f: &syn::ExprForLoop, outer: &[Loop]) -> Option<Vec<Loop>> {
        let var = match &*f.pat {
            syn::Pat::Ident(pi) => pi.ident.clone(),
            other => {
                self.cx.error_spanned_by(
                    other,
                    "a loop over elements binds one index, e.g. `for i in 0..n`",
                );
                return None;
            }
        };
        let Expr::Range(range) = &*f.expr else {
            self.cx.error_spanned_by(
                &f.expr,
                "a loop over elements runs over a range such as `0..n` or `i + 1..n`",
            );
            return None;
        };
        let vars: Vec<Ident> = outer.iter().map(|l| l.var.clone()).collect();
        let bound = |e: &Option<Box<Expr>>| -> Option<Index> {
            match e {
                Some(e) => Index::parse(self.cx, e, &vars, self.sizes),
                None => {
                    self.cx
                        .error_spanned_by(range, "the range must have both bounds, e.g. `0..n`");
                    None
                }
            }
        };
        let (lo, hi) = (bound(&range.start), bound(&range.end));
        let (lo, mut hi) = (lo?, hi?);
        if matches!(range.limits, syn::RangeLimits::Closed(_)) {
            hi = Index::Add(Box::new(hi), Box::new(Index::Lit(1)));
        }
        let mut nest = outer.to_vec();
        nest.push(Loop {
            var,
            lo,
            hi,
            tokens: range.to_token_stream(),
        });
        Some(nest)
    }

    /// The family of loop `f` inside the nest `outer`, with the `let`s visible to it.
    fn family(&mut self, f: &syn::ExprForLoop, outer: &[Loop], preamble: &[Stmt], locals: &[Stmt]) {
        let Some(nest) = self.nest_of(f, outer) else {
            return;
        };
        let mut own: Vec<Stmt> = Vec::new();
        let mut visible = locals.to_vec();
        let mut has_terms = false;
        for st in &f.body.stmts {
            match st {
                // A loop over a constant range (`for d in 0..3`) is part of the element.
                Stmt::Expr(Expr::ForLoop(inner), _)
                    if super::unroll::constant_range(inner).is_some() =>
                {
                    if super::unroll::contains(&inner.body.stmts, &|e| self.adds_to_acc(e)) {
                        has_terms = true;
                    }
                    own.extend(super::unroll::unroll(inner));
                }
                Stmt::Expr(Expr::ForLoop(inner), _) => {
                    self.family(inner, &nest, preamble, &visible);
                }
                Stmt::Local(_) => {
                    own.push(st.clone());
                    visible.push(st.clone());
                }
                Stmt::Expr(e, _) if self.adds_to_acc(e) => {
                    has_terms = true;
                    own.push(st.clone());
                }
                other => {
                    own.push(other.clone());
                }
            }
        }
        if has_terms {
            let block = self.element_block(preamble, locals, &own);
            self.push_family(nest, block);
        }
    }

    /// `{ preamble; locals; let mut acc = 0.0; stmts; acc }`.
    fn element_block(&self, preamble: &[Stmt], locals: &[Stmt], stmts: &[Stmt]) -> Block {
        let acc = self.acc.clone().unwrap_or_else(|| format_ident!("__l"));
        let mut all: Vec<Stmt> = preamble.to_vec();
        all.extend(locals.iter().cloned());
        all.push(syn::parse_quote!(let mut #acc = 0.0;));
        all.extend(stmts.iter().cloned());
        all.push(Stmt::Expr(syn::parse_quote!(#acc), None));
        Block {
            brace_token: Default::default(),
            stmts: all,
        }
    }

    /// Rewrites the element body over slots and records the family.
    fn push_family(&mut self, loops: Vec<Loop>, mut block: Block) {
        let mut rw = Rewriter {
            cx: self.cx,
            sizes: self.sizes,
            coords: self.coords,
            configs: self.configs,
            loops: &loops,
            slots: Vec::new(),
            keys: HashMap::new(),
            aliases: HashMap::new(),
        };
        rw.visit_block_mut(&mut block);
        let slots = rw.slots;
        self.families.push(FamilySpec {
            loops,
            slots,
            block,
        });
    }
}

/// Replaces coordinate reads by slots, and sizes and loop indices read as values by parameters.
struct Rewriter<'a> {
    cx: &'a Ctxt,
    sizes: &'a [Ident],
    coords: &'a [ElementCoord],
    configs: &'a [&'a Ident],
    loops: &'a [Loop],
    slots: Vec<Slot>,
    keys: HashMap<String, usize>,
    /// Integer `let`s (`let j = (i + 1) % n;`): their index expressions, by name.
    aliases: HashMap<String, Index>,
}

impl Rewriter<'_> {
    /// `q.x[..][..]` → the coordinate, its member and its index expressions (outermost last).
    fn coordinate_read<'e>(
        &self,
        e: &'e Expr,
    ) -> Option<(usize, &'e syn::ExprField, Vec<&'e Expr>)> {
        let mut indices = Vec::new();
        let mut cur = e;
        while let Expr::Index(ix) = cur {
            indices.push(&*ix.index);
            cur = &ix.expr;
        }
        let Expr::Field(f) = cur else { return None };
        let Expr::Path(base) = &*f.base else {
            return None;
        };
        let id = base.path.get_ident()?;
        if !self.configs.contains(&id) {
            return None;
        }
        let Member::Named(m) = &f.member else {
            return None;
        };
        let c = self.coords.iter().position(|c| c.name == *m)?;
        indices.reverse();
        Some((c, f, indices))
    }

    fn slot(&mut self, e: &Expr) -> Option<usize> {
        let (c, f, indices) = self.coordinate_read(e)?;
        let coord = &self.coords[c];
        if indices.len() != coord.dims.len() {
            self.cx.error_spanned_by(
                e,
                format!(
                    "`{}` has {} dimension(s): read one component, e.g. `{}`",
                    coord.name,
                    coord.dims.len(),
                    example(coord, f)
                ),
            );
            return None;
        }
        let vars: Vec<Ident> = self.loops.iter().map(|l| l.var.clone()).collect();
        let parsed: Vec<Option<Index>> = indices
            .iter()
            .map(|ix| Index::parse_with(self.cx, ix, &vars, self.sizes, &self.aliases))
            .collect();
        let index: Vec<Index> = parsed.into_iter().collect::<Option<_>>()?;
        let key = format!(
            "{c}:{}",
            index.iter().map(Index::key).collect::<Vec<_>>().join(",")
        );
        let text = e
            .to_token_stream()
            .to_string()
            .replace(" [", "[")
            .replace(" . ", ".");
        let n = self.slots.len();
        let k = *self.keys.entry(key).or_insert(n);
        if k == n {
            self.slots.push(Slot {
                coord: c,
                index,
                tokens: e.to_token_stream(),
                text,
            });
        }
        Some(k)
    }
}

fn example(coord: &ElementCoord, f: &syn::ExprField) -> String {
    let base = f.to_token_stream().to_string().replace(' ', "");
    match coord.dims.len() {
        0 => base,
        1 => format!("{base}[i]"),
        _ => format!("{base}[i][j]"),
    }
}

impl Rewriter<'_> {
    /// The element parameter standing for `e` when `e` names a loop index or a size.
    fn integer_param(&self, e: &Expr) -> Option<Ident> {
        let e = match e {
            Expr::Paren(p) => &*p.expr,
            other => other,
        };
        let Expr::Path(p) = e else { return None };
        let id = p.path.get_ident()?;
        if let Some(k) = self.loops.iter().rposition(|l| l.var == *id) {
            return Some(loop_param(k));
        }
        self.sizes.iter().position(|s| s == id).map(size_param)
    }
}

impl VisitMut for Rewriter<'_> {
    /// An integer `let` (`let j = (i + 1) % n;`) becomes an alias of its index expression and
    /// leaves the element body; every other statement is rewritten.
    fn visit_block_mut(&mut self, block: &mut Block) {
        let vars: Vec<Ident> = self.loops.iter().map(|l| l.var.clone()).collect();
        let mut kept = Vec::with_capacity(block.stmts.len());
        for mut stmt in std::mem::take(&mut block.stmts) {
            if let Stmt::Local(local) = &stmt {
                if let (syn::Pat::Ident(pi), Some(init)) = (&local.pat, &local.init) {
                    let index = Index::try_parse(&init.expr, &vars, self.sizes, &self.aliases);
                    if let Some(index) = index.filter(|_| init.diverge.is_none()) {
                        self.aliases.insert(pi.ident.to_string(), index);
                        continue;
                    }
                }
            }
            self.visit_stmt_mut(&mut stmt);
            kept.push(stmt);
        }
        block.stmts = kept;
    }

    fn visit_expr_mut(&mut self, e: &mut Expr) {
        if self.coordinate_read(e).is_some() {
            if let Some(k) = self.slot(e) {
                let Some((_, f, _)) = self.coordinate_read(e) else {
                    return;
                };
                let base = f.base.clone();
                let name = format_ident!("{}", slot_name(k), span = e.span());
                *e = syn::parse_quote!(#base.#name);
            }
            return;
        }
        // A size or loop index read as a value: `n as f64` becomes a parameter of the element.
        if let Expr::Cast(c) = e {
            let is_f64 = matches!(&*c.ty, syn::Type::Path(p) if p.path.is_ident("f64"));
            if let (true, Some(param)) = (is_f64, self.integer_param(&c.expr)) {
                *e = syn::parse_quote!(#param);
                return;
            }
        }
        if let Some(param) = self.integer_param(e) {
            let name = e.to_token_stream().to_string();
            self.cx.error_spanned_by(
                &*e,
                format!("`{name}` is an integer (a size or a loop index): read its value as an f64 with `{name} as f64`"),
            );
            *e = syn::parse_quote!(#param);
            return;
        }
        syn::visit_mut::visit_expr_mut(self, e);
    }
}

/// The smallest size, from 1 to [`MAX_MIN_SIZE`], from which every stencil read stays inside
/// its coordinate at every sampled size: each size from it to it + [`SAMPLE_SPAN`], plus
/// [`LARGE_SAMPLE`]. `None` (with an error at the offending read) when there is none.
pub fn min_size(
    cx: &Ctxt,
    families: &[&FamilySpec],
    coords: &[ElementCoord],
    n_sizes: usize,
) -> Option<usize> {
    let mut first_failure: Option<Failure> = None;
    'candidate: for m in 1..=MAX_MIN_SIZE {
        let samples: Vec<i64> = (m..=m + SAMPLE_SPAN)
            .map(|v| v as i64)
            .chain([LARGE_SAMPLE])
            .collect();
        for sizes in combinations(&samples, n_sizes) {
            for f in families {
                if let Err(failure) = check_family(f, coords, &sizes) {
                    if m == MAX_MIN_SIZE || first_failure.is_none() {
                        first_failure = Some(failure);
                    }
                    continue 'candidate;
                }
            }
        }
        return Some(m);
    }
    if let Some((tokens, message)) = first_failure {
        cx.error_spanned_by(tokens, message);
    }
    None
}

/// An escaping read: the tokens to point at, and the message.
type Failure = (proc_macro2::TokenStream, String);

/// Largest smallest size the compiler looks for.
pub const MAX_MIN_SIZE: usize = 8;
/// How far above a candidate smallest size every size is sampled.
pub const SAMPLE_SPAN: usize = 6;
/// A larger size sampled too.
pub const LARGE_SAMPLE: i64 = 23;

fn combinations(samples: &[i64], k: usize) -> Vec<Vec<i64>> {
    let mut out = vec![Vec::new()];
    for _ in 0..k {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                samples.iter().map(move |&s| {
                    let mut p = prefix.clone();
                    p.push(s);
                    p
                })
            })
            .collect();
    }
    out
}

/// Every element of `f` at `sizes`: its reads inside their coordinates.
fn check_family(f: &FamilySpec, coords: &[ElementCoord], sizes: &[i64]) -> Result<(), Failure> {
    let size_text = |sizes: &[i64]| -> String {
        sizes
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut indices = vec![0i64; f.loops.len()];
    fn walk(
        f: &FamilySpec,
        coords: &[ElementCoord],
        sizes: &[i64],
        level: usize,
        indices: &mut Vec<i64>,
        report: &dyn Fn(&[i64], &Slot, String) -> Failure,
    ) -> Result<(), Failure> {
        if level == f.loops.len() {
            for slot in &f.slots {
                let coord = &coords[slot.coord];
                for (d, ix) in slot.index.iter().enumerate() {
                    let len = match coord.dims[d] {
                        Dim::Size(k) => sizes[k],
                        Dim::Fixed(v) => v as i64,
                        Dim::Scaled(k, m) => m as i64 * sizes[k],
                    };
                    match ix.eval(sizes, indices) {
                        Ok(v) if v < len => {}
                        Ok(v) => {
                            return Err(report(indices, slot, format!("reads index {v}, outside 0..{len}")))
                        }
                        Err(EvalError::Underflow) => {
                            return Err(report(indices, slot, "subtracts below zero (a `usize` underflow); write e.g. `(i + n - 1) % n` rather than `(i - 1) % n`".to_string()))
                        }
                        Err(EvalError::ZeroModulus) => {
                            return Err(report(indices, slot, "takes a remainder by zero".to_string()))
                        }
                    }
                }
            }
            return Ok(());
        }
        let l = &f.loops[level];
        let (lo, hi) =
            match (l.lo.eval(sizes, indices), l.hi.eval(sizes, indices)) {
                (Ok(lo), Ok(hi)) => (lo, hi),
                _ => return Err((
                    l.tokens.clone(),
                    "this loop's bounds subtract below zero (a `usize` underflow) for small sizes"
                        .to_string(),
                )),
            };
        for i in lo..hi {
            indices[level] = i;
            walk(f, coords, sizes, level + 1, indices, report)?;
        }
        Ok(())
    }
    let report = |indices: &[i64], slot: &Slot, what: String| -> Failure {
        let at: Vec<String> = f
            .loops
            .iter()
            .zip(indices)
            .map(|(l, v)| format!("{} = {v}", l.var))
            .collect();
        (
            slot.tokens.clone(),
            format!(
                "the stencil escapes its coordinate: `{}` {what} at sizes ({}){}; every read must stay inside the coordinate for all sizes from some smallest size (at most {MAX_MIN_SIZE}) on",
                slot.text,
                size_text(sizes),
                if at.is_empty() { String::new() } else { format!(", {}", at.join(", ")) },
            ),
        )
    };
    walk(f, coords, sizes, 0, &mut indices, &report)
}

/// What a constraint's walker needs of the splitter: loop nests and element bodies over slots,
/// built exactly as the body's families are.
pub struct Elements<'a> {
    splitter: Splitter<'a>,
}

impl<'a> Elements<'a> {
    pub fn new(
        cx: &'a Ctxt,
        sizes: &'a [Ident],
        coords: &'a [ElementCoord],
        configs: &'a [&'a Ident],
    ) -> Self {
        Self {
            splitter: Splitter {
                cx,
                sizes,
                coords,
                configs,
                acc: Some(format_ident!("__l")),
                families: Vec::new(),
                outside: Vec::new(),
            },
        }
    }

    /// The nest `outer` with loop `f` inside it; `None` after errors (recorded).
    pub fn nest_of(&self, f: &syn::ExprForLoop, outer: &[Loop]) -> Option<Vec<Loop>> {
        self.splitter.nest_of(f, outer)
    }

    /// The family of one scalar term `term` over the nest `loops`, with the `let`s visible to
    /// it, rewritten over its stencil's slots.
    pub fn term(
        &mut self,
        loops: Vec<Loop>,
        preamble: &[Stmt],
        locals: &[Stmt],
        term: &Expr,
    ) -> FamilySpec {
        let stmt: Stmt = syn::parse_quote!(__l += #term;);
        let block = self.splitter.element_block(preamble, locals, &[stmt]);
        self.splitter.push_family(loops, block);
        self.splitter.families.pop().expect("just pushed")
    }
}
