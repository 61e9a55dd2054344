//! Lowering: the function body → the expression graph. Unsupported syntax is rejected with a
//! span and a message listing what is accepted; lowering continues past an error so that one
//! compilation reports every mistake.

use std::collections::HashMap;

use quote::ToTokens;
use syn::spanned::Spanned;
use syn::{BinOp, Block, Expr, Ident, Lit, Member, Pat, Stmt, UnOp};

use crate::ctxt::Ctxt;
use crate::graph::{Fun, Graph, NodeId, Sym};

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
    Unit,
    /// A name whose initializer was rejected: uses fail silently, so one mistake is reported once.
    Poison,
}

impl Value {
    fn kind(&self) -> &'static str {
        match self {
            Value::Scalar(_) => "an f64",
            Value::Int(_) => "an integer",
            Value::Tuple(_) => "a tuple",
            Value::Array(_) => "an array",
            Value::Unit => "`()`",
            Value::Poison => "an invalid value",
        }
    }
}

struct Local {
    value: Value,
    mutable: bool,
}

/// How one component of a user coordinate is formed from the configuration vector `q`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Component {
    /// `q[i]`.
    Var(usize),
    /// `q[g] + q[r]`: a component `c = g + r_c` of a coordinate moved by a declared translation,
    /// with `g` its group coordinate and `r_c = c − g` its shape coordinate (§2.2.1).
    Sum(usize, usize),
}

/// A coordinate the body reads as `q0.name` (a scalar) or `q0.name[i]` (an array).
pub struct CoordName {
    pub name: String,
    /// `None` for a scalar, the length for an array.
    pub len: Option<usize>,
    /// One per component.
    pub components: Vec<Component>,
}

impl CoordName {
    /// Scalar coordinates `q[0]`, `q[1]`, … named `names`, in order.
    pub fn scalars(names: impl IntoIterator<Item = String>) -> Vec<CoordName> {
        names
            .into_iter()
            .enumerate()
            .map(|(i, name)| CoordName {
                name,
                len: None,
                components: vec![Component::Var(i)],
            })
            .collect()
    }
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
}

pub struct Lowering<'a> {
    g: &'a mut Graph,
    cx: &'a Ctxt,
    names: &'a Names<'a>,
    scopes: Vec<HashMap<String, Local>>,
    /// Whether coordinates may appear (false for connection entries).
    allow_coords: bool,
}

impl<'a> Lowering<'a> {
    pub fn new(g: &'a mut Graph, cx: &'a Ctxt, names: &'a Names<'a>) -> Self {
        Self {
            g,
            cx,
            names,
            scopes: vec![HashMap::new()],
            allow_coords: true,
        }
    }

    /// Lowers the function body; `None` after errors (already recorded).
    pub fn body(&mut self, block: &Block) -> Option<NodeId> {
        let value = self.block(block)?;
        match value {
            Value::Scalar(n) => Some(n),
            other => {
                let span = block.stmts.last().map_or(block.span(), |s| s.span());
                self.cx.error_at(
                    span,
                    format!("the body must evaluate to an f64, found {}", other.kind()),
                );
                None
            }
        }
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
            .map(|v| match v {
                Value::Scalar(n) => Some(n),
                other => {
                    self.cx.error_at(
                        span,
                        format!("each new coordinate must be an f64, found {}", other.kind()),
                    );
                    None
                }
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
                        return self.coordinate_index(ix, f, which, member);
                    }
                }
                let base = self.expr(&ix.expr)?;
                let i = self.expr(&ix.index)?;
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
            Expr::Reference(r) => self.error(r, format!("references are not supported: coordinates and parameters are plain f64 values; {ACCEPTED}")),
            Expr::Return(r) => self.error(r.return_token, "`return` is not supported: end the body with its value"),
            Expr::Macro(m) => self.error(&m.mac.path, format!("macros are not supported in the body; {ACCEPTED}")),
            Expr::Unsafe(u) => self.error(u.unsafe_token, "`unsafe` is not supported"),
            Expr::Range(r) => self.error(r, "ranges are only accepted as the bounds of a `for` loop"),
            other => self.error(other, format!("unsupported expression; {ACCEPTED}")),
        }
    }

    fn path(&mut self, p: &syn::ExprPath) -> Option<Value> {
        if p.qself.is_none() {
            if let Some(id) = p.path.get_ident() {
                let name = id.to_string();
                if let Some(local) = self.lookup(&name) {
                    return match local.value {
                        Value::Poison => None,
                        ref v => Some(v.clone()),
                    };
                }
                if let Some(i) = self.names.params.iter().position(|q| *q == name) {
                    return Some(Value::Scalar(self.g.var(Sym::Param(i))));
                }
                if id == self.names.q0 || id == self.names.q1 {
                    let example = self.names.coords.first().map_or("x", |c| c.name.as_str());
                    return self.error(
                        id,
                        format!("use a coordinate of `{id}`, e.g. `{id}.{example}`"),
                    );
                }
                if !self.allow_coords {
                    let list: Vec<String> =
                        self.names.params.iter().map(|p| format!("`{p}`")).collect();
                    return self.error(
                        id,
                        format!(
                            "`{name}` is not a parameter; connection entries are f64 literals or parameters: {}",
                            list.join(", ")
                        ),
                    );
                }
                return self.error(
                    id,
                    format!("cannot find `{name}`: not a local, a parameter or a configuration"),
                );
            }
            let segs: Vec<String> = p
                .path
                .segments
                .iter()
                .map(|s| s.ident.to_string())
                .collect();
            let tail = match segs.as_slice() {
                [f, c, n] if f == "f64" && c == "consts" => Some(n.as_str()),
                [s, f, c, n] if (s == "std" || s == "core") && f == "f64" && c == "consts" => {
                    Some(n.as_str())
                }
                _ => None,
            };
            if let Some(v) = tail.and_then(f64_const) {
                return Some(Value::Scalar(self.g.constant(v)));
            }
        }
        self.error(p, format!("unsupported path; {ACCEPTED}"))
    }

    /// `q0.x` or `q1.x` when `f` reads a coordinate (the configuration names not shadowed by a
    /// local): which configuration (0 or 1), and the member.
    fn coordinate_field<'e>(&self, f: &'e syn::ExprField) -> Option<(usize, &'e Member)> {
        let Expr::Path(base) = &*f.base else {
            return None;
        };
        let id = base.path.get_ident()?;
        let which = if id == self.names.q0 {
            0
        } else if id == self.names.q1 {
            1
        } else {
            return None;
        };
        self.lookup(&id.to_string())
            .is_none()
            .then_some((which, &f.member))
    }

    /// The leaf expression of component `c` of configuration `which`.
    fn component(&mut self, which: usize, c: Component) -> Value {
        let sym = |i| if which == 0 { Sym::Q0(i) } else { Sym::Q1(i) };
        let n = match c {
            Component::Var(i) => self.g.var(sym(i)),
            Component::Sum(g, r) => {
                let (g, r) = (self.g.var(sym(g)), self.g.var(sym(r)));
                self.g.add(g, r)
            }
        };
        Value::Scalar(n)
    }

    /// Resolves the coordinate named by `member` (reporting an unknown name); the connection
    /// matrix may not read coordinates.
    fn coordinate(&self, f: &syn::ExprField, member: &Member) -> Option<usize> {
        if !self.allow_coords {
            self.cx.error_spanned_by(
                f,
                format!(
                    "the connection matrix must be constant: entries are f64 literals and parameters, found the coordinate `{}`",
                    f.to_token_stream()
                ),
            );
            return None;
        }
        let Member::Named(member) = member else {
            self.cx
                .error_spanned_by(member, "expected a coordinate name");
            return None;
        };
        let name = member.to_string();
        let found = self.names.coords.iter().position(|c| c.name == name);
        if found.is_none() {
            let declared: Vec<String> = self
                .names
                .coords
                .iter()
                .map(|c| match c.len {
                    None => c.name.clone(),
                    Some(n) => format!("{}[{n}]", c.name),
                })
                .collect();
            self.cx.error_spanned_by(
                member,
                format!(
                    "unknown coordinate `{name}`; declared coordinates: {}",
                    declared.join(", ")
                ),
            );
        }
        found
    }

    /// `q0.x[i]`: a component of an array coordinate; the index must be a constant integer.
    fn coordinate_index(
        &mut self,
        ix: &syn::ExprIndex,
        f: &syn::ExprField,
        which: usize,
        member: &Member,
    ) -> Option<Value> {
        let c = self.coordinate(f, member);
        let index = self.expr(&ix.index);
        let c = c?;
        let name = self.names.coords[c].name.clone();
        let Some(len) = self.names.coords[c].len else {
            return self.error(
                &ix.index,
                format!(
                    "coordinate `{name}` is a scalar and cannot be indexed: write `{}`; only array coordinates, declared with a length such as `{name}[3]`, are indexed",
                    f.to_token_stream()
                ),
            );
        };
        let i = match index? {
            Value::Int(i) => i,
            other => {
                return self.error(
                    &ix.index,
                    format!(
                        "the index of coordinate `{name}` must be a constant integer known at compile time, found {} `{}`; accepted: \
                         an integer literal, a loop index of a `for` loop over a constant range, or `+ - * / %` on those, e.g. `{}[(i + 1) % {len}]`",
                        other.kind(),
                        ix.index.to_token_stream(),
                        f.to_token_stream()
                    ),
                )
            }
        };
        match usize::try_from(i).ok().filter(|&i| i < len) {
            Some(i) => {
                let comp = self.names.coords[c].components[i];
                Some(self.component(which, comp))
            }
            None => self.error(
                &ix.index,
                format!(
                    "index {i} is out of range for coordinate `{name}` of length {len} (valid indices 0..{len}): `{}`",
                    ix.index.to_token_stream()
                ),
            ),
        }
    }

    fn field(&mut self, f: &syn::ExprField) -> Option<Value> {
        if let Some((which, member)) = self.coordinate_field(f) {
            let c = self.coordinate(f, member)?;
            let coord = &self.names.coords[c];
            if let Some(len) = coord.len {
                let name = coord.name.clone();
                return self.error(
                    f,
                    format!(
                        "`{name}` is an array coordinate of length {len}: read one component at a time, `{}[i]`, with a constant index \
                         (a literal, a loop index, or integer arithmetic on those)",
                        f.to_token_stream()
                    ),
                );
            }
            let comp = coord.components[0];
            return Some(self.component(which, comp));
        }
        let base = self.expr(&f.base)?;
        match (&f.member, base) {
            (Member::Unnamed(ix), Value::Tuple(items)) => match items.get(ix.index as usize) {
                Some(v) => Some(v.clone()),
                None => self.error(
                    ix,
                    format!(
                        "no field {} on a tuple of {} elements",
                        ix.index,
                        items.len()
                    ),
                ),
            },
            (m, v) => self.error(
                m,
                format!("no field `{}` on {}", m.to_token_stream(), v.kind()),
            ),
        }
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> Option<Value> {
        let compound = match b.op {
            BinOp::AddAssign(_) => Some(BinOp::Add(Default::default())),
            BinOp::SubAssign(_) => Some(BinOp::Sub(Default::default())),
            BinOp::MulAssign(_) => Some(BinOp::Mul(Default::default())),
            BinOp::DivAssign(_) => Some(BinOp::Div(Default::default())),
            _ => None,
        };
        if let Some(op) = compound {
            let l = self.expr(&b.left);
            let r = self.expr(&b.right);
            let v = self.arith(op, l?, &b.left, r?, &b.right)?;
            return self.assign(&b.left, v);
        }
        match b.op {
            BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Div(_) | BinOp::Rem(_) => {
                let l = self.expr(&b.left);
                let r = self.expr(&b.right);
                self.arith(b.op, l?, &b.left, r?, &b.right)
            }
            op => self.error(op, format!("unsupported operator; {ACCEPTED}")),
        }
    }

    fn arith(&mut self, op: BinOp, l: Value, le: &Expr, r: Value, re: &Expr) -> Option<Value> {
        if let (Value::Int(a), Value::Int(c)) = (&l, &r) {
            let v = match op {
                BinOp::Add(_) => a.checked_add(*c),
                BinOp::Sub(_) => a.checked_sub(*c),
                BinOp::Mul(_) => a.checked_mul(*c),
                // Integer `/` and `%` as in Rust (truncating), for index arithmetic such
                // as `(i + 1) % n`.
                BinOp::Div(_) | BinOp::Rem(_) if *c == 0 => {
                    return self.error(op, "integer division by zero")
                }
                BinOp::Div(_) => a.checked_div(*c),
                BinOp::Rem(_) => a.checked_rem(*c),
                _ => unreachable!("arith is called with + - * / % only"),
            };
            return match v {
                Some(v) => Some(Value::Int(v)),
                None => self.error(op, "integer overflow"),
            };
        }
        if let BinOp::Rem(_) = op {
            return self.error(
                op,
                "`%` is accepted on constant integers only (index arithmetic such as `(i + 1) % n`), not on f64 values",
            );
        }
        let a = self.scalar(l, le);
        let c = self.scalar(r, re);
        let (a, c) = (a?, c?);
        let n = match op {
            BinOp::Add(_) => self.g.add(a, c),
            BinOp::Sub(_) => self.g.sub(a, c),
            BinOp::Mul(_) => self.g.mul(a, c),
            BinOp::Div(_) => self.g.div(a, c),
            _ => unreachable!("arith is called with + - * / on f64 only"),
        };
        Some(Value::Scalar(n))
    }

    fn assign(&mut self, target: &Expr, value: Value) -> Option<Value> {
        match target {
            Expr::Path(p) if p.path.get_ident().is_some() => {
                let id = p.path.get_ident().expect("checked");
                let name = id.to_string();
                let Some(scope) = self.scopes.iter_mut().rev().find(|s| s.contains_key(&name))
                else {
                    if self.names.params.contains(&name) {
                        return self.error(
                            id,
                            format!(
                                "cannot assign to parameter `{name}`: bind a local with `let mut`"
                            ),
                        );
                    }
                    return self.error(
                        id,
                        format!("cannot assign to `{name}`: not a local variable"),
                    );
                };
                let local = scope.get_mut(&name).expect("found");
                if !local.mutable {
                    return self.error(id, format!("cannot assign twice to immutable variable `{name}`: declare it with `let mut {name}`"));
                }
                local.value = value;
                Some(Value::Unit)
            }
            Expr::Index(ix) if matches!(&*ix.expr, Expr::Field(f) if self.coordinate_field(f).is_some()) => {
                self.error(
                    target,
                    "coordinates are inputs and cannot be assigned: bind a local with `let mut`",
                )
            }
            Expr::Index(ix) => {
                let i = self.expr(&ix.index)?;
                let i = self.int(i, &ix.index)?;
                let Expr::Path(p) = &*ix.expr else {
                    return self.error(&ix.expr, "only elements of local arrays can be assigned");
                };
                let Some(id) = p.path.get_ident() else {
                    return self.error(p, "only elements of local arrays can be assigned");
                };
                let name = id.to_string();
                let Some(local) = self.scopes.iter_mut().rev().find_map(|s| s.get_mut(&name))
                else {
                    return self.error(
                        id,
                        format!("cannot assign to `{name}`: not a local variable"),
                    );
                };
                if !local.mutable {
                    return self.error(id, format!("cannot assign to an element of immutable array `{name}`: declare it with `let mut {name}`"));
                }
                let Value::Array(items) = &mut local.value else {
                    return self.error(id, format!("`{name}` is not an array"));
                };
                let len = items.len();
                match usize::try_from(i).ok().and_then(|i| items.get_mut(i)) {
                    Some(slot) => *slot = value,
                    None => {
                        return self.error(
                            &ix.index,
                            format!("index {i} is out of bounds for an array of length {len}"),
                        )
                    }
                }
                Some(Value::Unit)
            }
            Expr::Field(f) if matches!(&*f.base, Expr::Path(p) if p.path.get_ident().is_some_and(|id| id == self.names.q0 || id == self.names.q1)) => {
                self.error(
                    target,
                    "coordinates are inputs and cannot be assigned: bind a local with `let mut`",
                )
            }
            other => self.error(
                other,
                "only local variables and elements of local arrays can be assigned",
            ),
        }
    }

    fn call(
        &mut self,
        method: &Ident,
        receiver: Value,
        receiver_expr: &Expr,
        args: &[&Expr],
    ) -> Option<Value> {
        let name = method.to_string();
        let arity = match name.as_str() {
            "powi" | "powf" | "atan2" => 1,
            n if Fun::from_name(n).is_some() => 0,
            _ => {
                return self.error(
                    method,
                    format!("unsupported method `{name}`; accepted f64 methods: {METHODS}"),
                );
            }
        };
        if args.len() != arity {
            return self.error(
                method,
                format!("`{name}` takes {arity} argument(s), found {}", args.len()),
            );
        }
        if !matches!(receiver, Value::Scalar(_)) {
            return self.error(
                receiver_expr,
                format!("`.{name}()` needs an f64, found {}", receiver.kind()),
            );
        }
        let x = self.scalar(receiver, receiver_expr)?;
        if name == "powi" {
            let e = self.expr(args[0])?;
            let n = self.int(e, args[0])?;
            let Ok(n) = i32::try_from(n) else {
                return self.error(args[0], "the `powi` exponent must fit in an i32");
            };
            return Some(Value::Scalar(self.g.powi(x, n)));
        }
        if name == "powf" || name == "atan2" {
            let e = self.expr(args[0])?;
            let y = self.scalar(e, args[0])?;
            let n = if name == "powf" {
                self.g.powf(x, y)
            } else {
                self.g.atan2(x, y)
            };
            return Some(Value::Scalar(n));
        }
        let f = Fun::from_name(&name).expect("checked above");
        Some(Value::Scalar(self.g.fun(f, x)))
    }

    fn for_loop(&mut self, f: &syn::ExprForLoop) -> Option<Value> {
        if let Some(label) = &f.label {
            return self.error(label, "loop labels are not supported");
        }
        let Expr::Range(range) = &*f.expr else {
            return self.error(
                &f.expr,
                "`for` loops must run over a constant range such as `0..3` or `0..=2`",
            );
        };
        let bound = |s: &mut Self, e: &Option<Box<Expr>>| -> Option<i64> {
            let Some(e) = e else {
                s.error(range, "the range must have both bounds, e.g. `0..3`");
                return None;
            };
            match s.expr(e) {
                Some(Value::Int(i)) => Some(i),
                Some(v) => {
                    s.error(
                        e,
                        format!(
                            "loop bounds must be constant integers (literals or enclosing loop indices) so the loop can be unrolled, found {} `{}`",
                            v.kind(),
                            e.to_token_stream()
                        ),
                    );
                    None
                }
                None => None,
            }
        };
        let start = bound(self, &range.start);
        let end = bound(self, &range.end);
        let (start, mut end) = (start?, end?);
        if matches!(range.limits, syn::RangeLimits::Closed(_)) {
            end += 1;
        }
        if end - start > MAX_UNROLL {
            return self.error(
                range,
                format!("loops are unrolled at compile time: at most {MAX_UNROLL} iterations"),
            );
        }
        for i in start..end {
            self.scopes.push(HashMap::new());
            let bound = self.bind(&f.pat, Value::Int(i));
            let body = bound.and_then(|_| self.block(&f.body));
            self.scopes.pop();
            body?;
        }
        Some(Value::Unit)
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
