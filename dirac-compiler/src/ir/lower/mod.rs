//! Lowering: the function body → the expression graph. Unsupported syntax is rejected with a
//! span and a message listing what is accepted; lowering continues past an error so that one
//! compilation reports every mistake.

use std::collections::HashMap;

use quote::ToTokens;
use syn::spanned::Spanned;
use syn::{Block, Expr, Ident, Lit, Pat, Stmt, UnOp};

use crate::ctxt::Ctxt;
use crate::front::layout::CoordName;
use crate::ir::graph::{Graph, NodeId};

mod matrix;
mod names;
mod ops;

use matrix::Mat;

/// What the body language accepts, for error messages.
pub const ACCEPTED: &str = "accepted: f64 literals, parameters, coordinates (`q0.x`), locals \
(`let`, `let mut`, tuples), `+ - * /`, unary `-`, blocks, arrays with constant indices, `for` over \
constant ranges, and the f64 functions sin cos tan asin acos atan exp ln sqrt sinh cosh tanh recip \
powi powf atan2";

const METHODS: &str =
    "sin, cos, tan, asin, acos, atan, exp, ln, sqrt, sinh, cosh, tanh, recip, powi, powf, atan2";

/// Upper bound on unrolled loop iterations per loop, to keep expansion time bounded.
const MAX_UNROLL: i64 = 4096;

/// A value during lowering.
#[derive(Clone, Debug)]
enum Value {
    Scalar(NodeId),
    /// An integer constant: a loop index, an index expression or a `powi` exponent.
    Int(i64),
    Tuple(Vec<Value>),
    Array(Vec<Value>),
    /// A matrix or vector (rotation and direction coordinates, [`matrix`]).
    Mat(Mat),
    /// A coordinate on a group with named parts (a pose's `rotation` and `translation`), read
    /// one part at a time.
    Parts(Vec<(&'static str, Value)>),
    Unit,
    /// A name whose initializer was rejected: uses fail silently, so one mistake is reported once.
    Poison,
}

/// An operand of a binary operation: its value, and the expression it came from (where an
/// error about it points).
struct Operand<'e> {
    value: Value,
    at: &'e Expr,
}

impl<'e> Operand<'e> {
    fn new(value: Value, at: &'e Expr) -> Self {
        Operand { value, at }
    }
}

impl Value {
    /// Its node if it is a scalar; else `None`, after `fail` has recorded the error given what
    /// was found ([`Self::kind`]).
    fn scalar_or(self, fail: impl FnOnce(String)) -> Option<NodeId> {
        match self {
            Value::Scalar(n) => Some(n),
            other => {
                fail(other.kind());
                None
            }
        }
    }

    fn kind(&self) -> String {
        match self {
            Value::Scalar(_) => "an f64",
            Value::Int(_) => "an integer",
            Value::Tuple(_) => "a tuple",
            Value::Array(_) => "an array",
            Value::Mat(m) => return m.kind(),
            Value::Parts(parts) => {
                let names: Vec<String> = parts.iter().map(|(n, _)| format!("`.{n}`")).collect();
                return format!("a value with the parts {}", names.join(", "));
            }
            Value::Unit => "`()`",
            Value::Poison => "an invalid value",
        }
        .to_string()
    }
}

struct Local {
    value: Value,
    mutable: bool,
}

/// The names visible in the body.
pub struct Names<'a> {
    /// Configuration argument names (`q0`, `q1`).
    pub q0: &'a Ident,
    pub q1: &'a Ident,
    /// The coordinates the body reads, in the order of the user's configuration.
    pub coords: Vec<CoordName>,
    /// Parameters in declaration order.
    pub params: Vec<String>,
    /// The virtual displacements a force's virtual work reads (`dq`, or `dq0, dq1`); empty
    /// when lowering the Lagrangian.
    pub dq: Vec<Ident>,
}

impl<'a> Names<'a> {
    /// The names of a body with the signature `sig` reading `coords`: its configurations and
    /// parameters, no virtual displacements.
    pub fn of(sig: &'a crate::front::signature::Signature, coords: Vec<CoordName>) -> Self {
        Names {
            q0: &sig.q0,
            q1: &sig.q1,
            coords,
            params: sig.params.iter().map(ToString::to_string).collect(),
            dq: Vec::new(),
        }
    }
}

pub struct Lowering<'a> {
    g: &'a mut Graph,
    cx: &'a Ctxt,
    names: &'a Names<'a>,
    scopes: Vec<HashMap<String, Local>>,
    /// Whether coordinates may appear (false for connection entries).
    allow_coords: bool,
    /// Each `vee(&m)`: the entries of `m + mᵀ` that must vanish (its argument must be
    /// skew-symmetric, an element of `so(3)`), and the span of the call, for a check at sample
    /// configurations once the coordinates' manifolds are known ([`Self::skew_checks`]).
    skew: Vec<(Vec<NodeId>, proc_macro2::Span)>,
}

impl<'a> Lowering<'a> {
    pub fn new(g: &'a mut Graph, cx: &'a Ctxt, names: &'a Names<'a>) -> Self {
        Self {
            g,
            cx,
            names,
            scopes: vec![HashMap::new()],
            allow_coords: true,
            skew: Vec::new(),
        }
    }

    /// The skew-symmetry obligations of the `vee` calls lowered so far.
    pub fn skew_checks(&self) -> &[(Vec<NodeId>, proc_macro2::Span)] {
        &self.skew
    }

    /// Lowers the function body; `None` after errors (already recorded).
    pub fn body(&mut self, block: &Block) -> Option<NodeId> {
        let value = self.block(block)?;
        match value {
            Value::Scalar(n) => Some(n),
            other => {
                let span = block.stmts.last().map_or(block.span(), |s| s.span());
                let hint = if matches!(other, Value::Mat(_)) {
                    ": reduce the matrix or vector to a number, e.g. with `.trace()`, `.dot(&b)`, \
                     `.norm_squared()` or an entry `m[(i, j)]`"
                } else {
                    ""
                };
                self.cx.error_at(
                    span,
                    format!(
                        "the body must evaluate to an f64, found {}{hint}",
                        other.kind()
                    ),
                );
                None
            }
        }
    }

    /// Lowers an expression that evaluates to an f64 (a force's virtual work); `None` after
    /// errors (already recorded).
    pub fn scalar_expr(&mut self, e: &Expr, what: &str) -> Option<NodeId> {
        self.expr(e)?.scalar_or(|found| {
            self.cx
                .error_spanned_by(e, format!("{what} must evaluate to an f64, found {found}"));
        })
    }

    /// Lowers an expression that evaluates to an f64, or an array or tuple of f64 (the values
    /// of the constraints); `None` after errors (already recorded).
    pub fn scalars_expr(&mut self, e: &Expr, what: &str) -> Option<Vec<NodeId>> {
        let items = match self.expr(e)? {
            Value::Scalar(n) => return Some(vec![n]),
            Value::Array(items) | Value::Tuple(items) => items,
            other => {
                self.cx.error_spanned_by(
                    e,
                    format!(
                        "{what} must be an f64 or an array of f64, found {}",
                        other.kind()
                    ),
                );
                return None;
            }
        };
        items
            .into_iter()
            .map(|v| {
                v.scalar_or(|found| {
                    self.cx.error_spanned_by(
                        e,
                        format!("each of {what} must be an f64, found {found}"),
                    );
                })
            })
            .collect()
    }

    /// Lowers a body that evaluates to a tuple or array of `n` f64 (a chart transition's new
    /// coordinates); `None` after errors (already recorded).
    pub fn body_tuple(&mut self, block: &Block, n: usize) -> Option<Vec<NodeId>> {
        let value = self.block(block)?;
        let span = block.stmts.last().map_or(block.span(), |s| s.span());
        let items = match value {
            Value::Tuple(items) | Value::Array(items) if items.len() == n => items,
            other => {
                self.cx.error_at(
                    span,
                    format!(
                        "the body must evaluate to a tuple of the {n} new coordinates (shape, then \
                         group, in the order of `to(...)`), found {}{}",
                        other.kind(),
                        match &other {
                            Value::Tuple(i) | Value::Array(i) => format!(" of {} elements", i.len()),
                            _ => String::new(),
                        }
                    ),
                );
                return None;
            }
        };
        items
            .into_iter()
            .map(|v| {
                v.scalar_or(|found| {
                    self.cx.error_at(
                        span,
                        format!("each new coordinate must be an f64, found {found}"),
                    );
                })
            })
            .collect()
    }

    /// Lowers one entry of the connection matrix: literals and parameters only.
    pub fn constant_entry(&mut self, expr: &Expr) -> Option<NodeId> {
        self.allow_coords = false;
        let v = self.expr(expr);
        self.allow_coords = true;
        self.scalar(v?, expr)
    }

    fn error<T: ToTokens>(&self, tokens: T, message: impl std::fmt::Display) -> Option<Value> {
        self.cx.error_spanned_by(tokens, message);
        None
    }

    fn block(&mut self, block: &Block) -> Option<Value> {
        self.scopes.push(HashMap::new());
        let mut last = Some(Value::Unit);
        let mut failed = false;
        for (i, stmt) in block.stmts.iter().enumerate() {
            let is_last = i + 1 == block.stmts.len();
            let v = self.stmt(stmt, is_last);
            failed |= v.is_none();
            last = v;
        }
        self.scopes.pop();
        if failed {
            None
        } else {
            last
        }
    }

    fn stmt(&mut self, stmt: &Stmt, is_last: bool) -> Option<Value> {
        match stmt {
            Stmt::Local(local) => {
                let Some(init) = &local.init else {
                    return self.error(local, "`let` needs an initial value: `let name = expr;`");
                };
                if let Some((_, diverge)) = &init.diverge {
                    return self.error(
                        diverge,
                        format!("`let ... else` is not supported; {ACCEPTED}"),
                    );
                }
                match self.expr(&init.expr) {
                    Some(value) => {
                        self.bind(&local.pat, value)?;
                        Some(Value::Unit)
                    }
                    None => {
                        self.poison(&local.pat);
                        None
                    }
                }
            }
            Stmt::Expr(expr, semi) => {
                let v = self.expr(expr)?;
                if semi.is_some() || !is_last {
                    Some(Value::Unit)
                } else {
                    Some(v)
                }
            }
            Stmt::Item(item) => self.error(
                item,
                format!("items inside the body are not supported; {ACCEPTED}"),
            ),
            Stmt::Macro(m) => self.error(
                &m.mac.path,
                format!("macros are not supported in the body; {ACCEPTED}"),
            ),
        }
    }

    fn bind(&mut self, pat: &Pat, value: Value) -> Option<()> {
        match pat {
            Pat::Ident(pi) => {
                if pi.by_ref.is_some() || pi.subpat.is_some() {
                    self.error(pi, "expected a plain name, `mut name` or a tuple of names")?;
                }
                if let Value::Unit = value {
                    self.error(pi, "this expression has no value")?;
                }
                let name = pi.ident.to_string();
                self.scopes.last_mut().expect("a scope").insert(
                    name,
                    Local {
                        value,
                        mutable: pi.mutability.is_some(),
                    },
                );
                Some(())
            }
            Pat::Wild(_) => Some(()),
            Pat::Type(pt) => {
                let ok = matches!(&*pt.ty, syn::Type::Path(p) if p.path.is_ident("f64"));
                if !ok || !matches!(value, Value::Scalar(_)) {
                    self.error(&pt.ty, "only `f64` type annotations are accepted on `let`")?;
                }
                self.bind(&pt.pat, value)
            }
            Pat::Tuple(pt) => {
                let Value::Tuple(items) = value else {
                    self.error(
                        pt,
                        format!("cannot destructure {} as a tuple", value.kind()),
                    )?;
                    return None;
                };
                if items.len() != pt.elems.len() {
                    self.error(
                        pt,
                        format!(
                            "tuple pattern has {} names but the value has {} elements",
                            pt.elems.len(),
                            items.len()
                        ),
                    )?;
                }
                let mut ok = Some(());
                for (p, v) in pt.elems.iter().zip(items) {
                    ok = ok.and(self.bind(p, v));
                }
                ok
            }
            Pat::Paren(pp) => self.bind(&pp.pat, value),
            other => {
                self.error(
                    other,
                    "unsupported pattern: expected a name, `mut name`, `_` or a tuple of those",
                )?;
                None
            }
        }
    }

    /// Binds every name in `pat` to [`Value::Poison`].
    fn poison(&mut self, pat: &Pat) {
        match pat {
            Pat::Ident(pi) => {
                let local = Local {
                    value: Value::Poison,
                    mutable: true,
                };
                self.scopes
                    .last_mut()
                    .expect("a scope")
                    .insert(pi.ident.to_string(), local);
            }
            Pat::Type(pt) => self.poison(&pt.pat),
            Pat::Paren(pp) => self.poison(&pp.pat),
            Pat::Tuple(pt) => pt.elems.iter().for_each(|p| self.poison(p)),
            _ => {}
        }
    }

    fn lookup(&self, name: &str) -> Option<&Local> {
        self.scopes.iter().rev().find_map(|s| s.get(name))
    }

    fn scalar(&mut self, v: Value, at: &Expr) -> Option<NodeId> {
        match v {
            Value::Scalar(n) => Some(n),
            Value::Int(i) => {
                self.error(at, format!("integer `{i}` used as an f64: write `{i}.0`"));
                None
            }
            other => {
                self.error(at, format!("expected an f64, found {}", other.kind()));
                None
            }
        }
    }

    fn int(&mut self, v: Value, at: &Expr) -> Option<i64> {
        match v {
            Value::Int(i) => Some(i),
            other => {
                self.error(
                    at,
                    format!(
                        "expected a constant integer (a literal or a loop index), found {}",
                        other.kind()
                    ),
                );
                None
            }
        }
    }

    fn expr(&mut self, expr: &Expr) -> Option<Value> {
        match expr {
            Expr::Lit(lit) => match &lit.lit {
                Lit::Float(f) => match f.base10_parse::<f64>() {
                    Ok(v) if f.suffix().is_empty() || f.suffix() == "f64" => Some(Value::Scalar(self.g.constant(v))),
                    _ => self.error(f, "expected an f64 literal"),
                },
                Lit::Int(i) => match i.base10_parse::<i64>() {
                    Ok(v) => Some(Value::Int(v)),
                    Err(e) => {
                        self.cx.syn_error(e);
                        None
                    }
                },
                other => self.error(other, format!("unsupported literal; {ACCEPTED}")),
            },
            Expr::Path(p) => self.path(p),
            Expr::Field(f) => self.field(f),
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Block(b) => {
                if let Some(label) = &b.label {
                    return self.error(label, "labels are not supported");
                }
                self.block(&b.block)
            }
            Expr::Unary(u) => match u.op {
                UnOp::Neg(_) => {
                    let v = self.expr(&u.expr)?;
                    match v {
                        Value::Int(i) => Some(Value::Int(-i)),
                        Value::Mat(m) => Some(self.mat_neg(m)),
                        v => {
                            let n = self.scalar(v, &u.expr)?;
                            Some(Value::Scalar(self.g.neg(n)))
                        }
                    }
                }
                _ => self.error(u.op, format!("unsupported operator; {ACCEPTED}")),
            },
            Expr::Binary(b) => self.binary(b),
            Expr::Assign(a) => {
                let v = self.expr(&a.right)?;
                self.assign(&a.left, v)
            }
            Expr::MethodCall(m) => {
                if let Some(t) = &m.turbofish {
                    return self.error(t, "turbofish is not supported");
                }
                let receiver = self.expr(&m.receiver)?;
                let args: Vec<&Expr> = m.args.iter().collect();
                self.call(&m.method, receiver, &m.receiver, &args)
            }
            Expr::Call(c) => {
                if let Expr::Path(p) = &*c.func {
                    let args: Vec<&Expr> = c.args.iter().collect();
                    if let Some(v) = self.mat_call(&p.path, &args) {
                        return v;
                    }
                }
                let name = match &*c.func {
                    Expr::Path(p) if p.qself.is_none() && p.path.segments.len() == 2 && p.path.segments[0].ident == "f64" => {
                        p.path.segments[1].ident.clone()
                    }
                    other => {
                        return self.error(
                            other,
                            format!(
                                "calls to functions are not supported (only f64 functions such as `f64::sin(x)`): inline the function with `let` bindings; {ACCEPTED}"
                            ),
                        )
                    }
                };
                let Some(first) = c.args.first() else {
                    return self.error(c, format!("`f64::{name}` needs an argument"));
                };
                let receiver = self.expr(first)?;
                let rest: Vec<&Expr> = c.args.iter().skip(1).collect();
                self.call(&name, receiver, first, &rest)
            }
            Expr::Tuple(t) => {
                let items: Option<Vec<Value>> = t.elems.iter().map(|e| self.expr(e)).collect();
                Some(Value::Tuple(items?))
            }
            Expr::Array(a) => {
                let items: Option<Vec<Value>> = a.elems.iter().map(|e| self.expr(e)).collect();
                Some(Value::Array(items?))
            }
            Expr::Repeat(r) => {
                let item = self.expr(&r.expr)?;
                let n = self.expr(&r.len)?;
                let n = self.int(n, &r.len)?;
                if !(0..=MAX_UNROLL).contains(&n) {
                    return self.error(&r.len, format!("array length must be between 0 and {MAX_UNROLL}"));
                }
                Some(Value::Array(vec![item; n as usize]))
            }
            Expr::Index(ix) => {
                if let Expr::Field(f) = &*ix.expr {
                    if let Some((which, member)) = self.coordinate_field(f) {
                        if !self.is_matrix_coordinate(member) {
                            return self.coordinate_index(ix, f, which, member);
                        }
                    }
                }
                let base = self.expr(&ix.expr)?;
                let i = self.expr(&ix.index)?;
                if let Value::Mat(m) = base {
                    return self.mat_index(m, i, &ix.index);
                }
                let i = self.int(i, &ix.index)?;
                match base {
                    Value::Array(items) => match usize::try_from(i).ok().and_then(|i| items.get(i)) {
                        Some(v) => Some(v.clone()),
                        None => self.error(&ix.index, format!("index {i} is out of bounds for an array of length {}", items.len())),
                    },
                    other => self.error(&ix.expr, format!("cannot index {}", other.kind())),
                }
            }
            Expr::Cast(c) => {
                let v = self.expr(&c.expr)?;
                let is_f64 = matches!(&*c.ty, syn::Type::Path(p) if p.path.is_ident("f64"));
                match (v, is_f64) {
                    (Value::Int(i), true) => Some(Value::Scalar(self.g.constant(i as f64))),
                    (Value::Scalar(n), true) => Some(Value::Scalar(n)),
                    _ => self.error(c, "only `as f64` casts of integers and f64s are accepted"),
                }
            }
            Expr::ForLoop(f) => self.for_loop(f),
            Expr::Closure(c) => {
                let head = { let (o1, i, o2) = (&c.or1_token, &c.inputs, &c.or2_token); quote::quote!(#o1 #i #o2) };
                self.error(head, format!("closures are not supported in a discrete Lagrangian: bind the value with `let`; {ACCEPTED}"))
            }
            Expr::If(i) => self.error(
                i.if_token,
                format!("`if` is not supported: the Lagrangian must be one smooth expression for its derivatives to exist; {ACCEPTED}"),
            ),
            Expr::Match(m) => self.error(
                m.match_token,
                format!("`match` is not supported: the Lagrangian must be one smooth expression for its derivatives to exist; {ACCEPTED}"),
            ),
            Expr::While(w) => self.error(w.while_token, format!("`while` loops are not supported (bounds must be constant: use `for i in 0..N`); {ACCEPTED}")),
            Expr::Loop(l) => self.error(l.loop_token, format!("`loop` is not supported (use `for i in 0..N`); {ACCEPTED}")),
            Expr::Reference(r) => match self.expr(&r.expr)? {
                // `&v` where nalgebra takes a reference (`a.dot(&b)`, `hat(&v)`).
                Value::Mat(m) if r.mutability.is_none() => Some(Value::Mat(m)),
                _ => self.error(r, format!("references are not supported: coordinates and parameters are plain f64 values; {ACCEPTED}")),
            },
            Expr::Return(r) => self.error(r.return_token, "`return` is not supported: end the body with its value"),
            Expr::Macro(m) => self.error(&m.mac.path, format!("macros are not supported in the body; {ACCEPTED}")),
            Expr::Unsafe(u) => self.error(u.unsafe_token, "`unsafe` is not supported"),
            Expr::Range(r) => self.error(r, "ranges are only accepted as the bounds of a `for` loop"),
            other => self.error(other, format!("unsupported expression; {ACCEPTED}")),
        }
    }
}

fn f64_const(name: &str) -> Option<f64> {
    use std::f64::consts::*;
    Some(match name {
        "PI" => PI,
        "TAU" => TAU,
        "E" => E,
        "FRAC_PI_2" => FRAC_PI_2,
        "FRAC_PI_3" => FRAC_PI_3,
        "FRAC_PI_4" => FRAC_PI_4,
        "FRAC_PI_6" => FRAC_PI_6,
        "FRAC_PI_8" => FRAC_PI_8,
        "FRAC_1_PI" => FRAC_1_PI,
        "FRAC_2_PI" => FRAC_2_PI,
        "SQRT_2" => SQRT_2,
        "FRAC_1_SQRT_2" => FRAC_1_SQRT_2,
        "LN_2" => LN_2,
        "LN_10" => LN_10,
        _ => return None,
    })
}
