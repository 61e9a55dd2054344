//! Deterministic generator of random discrete Lagrangians for `tests/random_derivatives.rs`.
//!
//! [`generate`] renders [`CASES`] cases into the text of `tests/random_exprs/cases.rs`. Each case
//! is one G-invariant discrete Lagrangian `L_d(q0, q1)` over shape coordinates `(a, b)` and group
//! coordinates `(c)` or `(c, d)`, sometimes with a nonzero connection matrix, written twice:
//!
//! * as an `f64` function annotated with `#[reduced_lagrangian]` (the macro's input), and
//! * as a generic function over `num_dual::DualNum` (the oracle's input), rendered from the same
//!   syntax tree with literals lifted into `T` and `powf` with a non-literal exponent written as
//!   `powd`.
//!
//! The leaves are `q0.a, q0.b, q1.a, q1.b`, the shape differences `q1.a − q0.a`, the group
//! differences `q1.c − q0.c` (the only way group coordinates enter, so every case is
//! G-invariant), the parameters `h, p`, float literals and `f64::consts`. Operations are `+ − * /`, unary `−` and every function the macro supports;
//! each case features one operation at its root (case `i` features `OPS[i % OPS.len()]`), so every
//! operation appears at least `CASES / OPS.len()` times. Some cases use `let` bindings, tuple
//! destructuring and tuple fields, arrays (literal, repeat, element assignment) with constant
//! indices and `for` loops over constant ranges (nested, with `+= -= *=` and `i as f64`).
//!
//! Arguments are kept in well-conditioned domains by construction: every node carries an upper
//! bound on `|value|` over the sampled box (computed with `+ − * /` only, so it is reproducible
//! bit for bit), large arguments are squashed through `sin`/`cos`/`tanh`/`atan`, and
//! `sqrt`/`ln`/`powf`/`recip`/negative `powi`/`/` only ever see arguments bounded away from zero,
//! `asin`/`acos` see `c · w` with `|w| ≤ 1`, `c ≤ 0.8`, and `tan` sees `|arg| ≤ 1.2`.
//!
//! The sampled box, which these bounds assume and `random_derivatives.rs` uses:
//! `x0, x1, g1 ∈ [−1, 1]`, `h ∈ [0.5, 1.5]`, `p ∈ [−1, 1]`, connection entries `|B| ≤ 1.2`.

use std::fmt::Write as _;

/// The generator's seed.
pub const SEED: u64 = 0x00D1_2AC0_0DE5_EED5;
/// Number of cases generated.
pub const CASES: usize = 210;
/// Upper bound kept on `|value|` of every generated subexpression.
const LIMIT: f64 = 20.0;

/// The operations every case set must cover.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Neg,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Exp,
    Ln,
    Sqrt,
    Sinh,
    Cosh,
    Tanh,
    Recip,
    Powi,
    Powf,
    Atan2,
}

pub const OPS: [Op; 21] = [
    Op::Add,
    Op::Sub,
    Op::Mul,
    Op::Div,
    Op::Neg,
    Op::Sin,
    Op::Cos,
    Op::Tan,
    Op::Asin,
    Op::Acos,
    Op::Atan,
    Op::Exp,
    Op::Ln,
    Op::Sqrt,
    Op::Sinh,
    Op::Cosh,
    Op::Tanh,
    Op::Recip,
    Op::Powi,
    Op::Powf,
    Op::Atan2,
];

impl Op {
    fn index(self) -> usize {
        OPS.iter().position(|&o| o == self).expect("listed")
    }

    fn method(self) -> &'static str {
        match self {
            Op::Sin => "sin",
            Op::Cos => "cos",
            Op::Tan => "tan",
            Op::Asin => "asin",
            Op::Acos => "acos",
            Op::Atan => "atan",
            Op::Exp => "exp",
            Op::Ln => "ln",
            Op::Sqrt => "sqrt",
            Op::Sinh => "sinh",
            Op::Cosh => "cosh",
            Op::Tanh => "tanh",
            Op::Recip => "recip",
            Op::Powi => "powi",
            Op::Powf => "powf",
            Op::Atan2 => "atan2",
            Op::Add => "+",
            Op::Sub => "-",
            Op::Mul => "*",
            Op::Div => "/",
            Op::Neg => "neg",
        }
    }
}

/// Syntax features counted for the coverage report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    PathCall,
    Const,
    Let,
    LetAnnotated,
    LetTuple,
    TupleField,
    Array,
    ArrayRepeat,
    ArrayAssign,
    ForLoop,
    NestedFor,
    InclusiveRange,
    LoopIndexCast,
    CompoundAssign,
    K2,
    Connection,
    ParamConnection,
}

pub const FEATURES: [Feature; 17] = [
    Feature::PathCall,
    Feature::Const,
    Feature::Let,
    Feature::LetAnnotated,
    Feature::LetTuple,
    Feature::TupleField,
    Feature::Array,
    Feature::ArrayRepeat,
    Feature::ArrayAssign,
    Feature::ForLoop,
    Feature::NestedFor,
    Feature::InclusiveRange,
    Feature::LoopIndexCast,
    Feature::CompoundAssign,
    Feature::K2,
    Feature::Connection,
    Feature::ParamConnection,
];

/// The generated text and its coverage.
pub struct Generated {
    pub text: String,
    /// Occurrences of each of [`OPS`] over all cases.
    pub op_counts: [usize; 21],
    /// Number of cases using each of [`FEATURES`].
    pub feature_counts: [usize; 17],
    pub cases: usize,
}

// ---------------------------------------------------------------------------------------------
// PRNG
// ---------------------------------------------------------------------------------------------

/// splitmix64.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n`.
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `num / den`.
    fn chance(&mut self, num: usize, den: usize) -> bool {
        self.below(den) < num
    }

    /// An index drawn with the given weights.
    fn weighted(&mut self, weights: &[usize]) -> usize {
        let total: usize = weights.iter().sum();
        let mut r = self.below(total);
        for (i, &w) in weights.iter().enumerate() {
            if r < w {
                return i;
            }
            r -= w;
        }
        unreachable!()
    }

    /// A literal `k / 100` with `k` in `lo..=hi` (so it prints exactly as written).
    fn lit(&mut self, lo: u32, hi: u32) -> f64 {
        let k = lo + self.below((hi - lo + 1) as usize) as u32;
        f64::from(k) / 100.0
    }
}

// ---------------------------------------------------------------------------------------------
// Syntax
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Debug)]
enum E {
    /// `q{0,1}.{a,b}`: configuration `which`, shape coordinate `i`.
    Coord(u8, usize),
    /// `(q1.g − q0.g)` for group coordinate `j`.
    Diff(usize),
    /// `h` or `p`.
    Param(usize),
    /// A non-negative literal.
    Lit(f64),
    /// `std::f64::consts::NAME`.
    Const(&'static str),
    /// A local, an array element `arr[0]`/`arr[i]` or a tuple field `(pair.0)`: same text in both
    /// renderings.
    Local(String),
    /// `(i as f64)`.
    LoopVar(String),
    Neg(Box<E>),
    Bin(char, Box<E>, Box<E>),
    /// Unary function; `true` renders the path form `f64::sin(x)` in the macro input.
    Call(Op, Box<E>, bool),
    Powi(Box<E>, i32, bool),
    Powf(Box<E>, Box<E>, bool),
    /// `y.atan2(x)`.
    Atan2(Box<E>, Box<E>, bool),
}

const CONSTS: [(&str, f64); 6] = [
    ("PI", 3.15),
    ("E", 2.72),
    ("FRAC_PI_4", 0.79),
    ("SQRT_2", 1.42),
    ("LN_2", 0.7),
    ("FRAC_1_PI", 0.32),
];

const SHAPE: [&str; 2] = ["a", "b"];
const GROUP: [&str; 2] = ["c", "d"];
const PARAMS: [&str; 2] = ["h", "p"];

#[derive(Clone, Copy, PartialEq)]
enum Style {
    /// The `f64` macro input.
    Macro,
    /// The generic num-dual reference.
    Ref,
}

fn render(e: &E, st: Style) -> String {
    let r = |e: &E| render(e, st);
    match e {
        E::Coord(w, i) => match st {
            Style::Macro => format!("q{w}.{}", SHAPE[*i]),
            Style::Ref => format!("q{w}[{i}]"),
        },
        E::Diff(j) => match st {
            Style::Macro => format!("(q1.{g} - q0.{g})", g = GROUP[*j]),
            Style::Ref => format!("(q1[{i}] - q0[{i}])", i = 2 + j),
        },
        E::Param(i) => PARAMS[*i].to_string(),
        E::Lit(v) => match st {
            Style::Macro => format!("{v:?}"),
            Style::Ref => format!("c::<T>({v:?})"),
        },
        E::Const(name) => match st {
            Style::Macro => format!("std::f64::consts::{name}"),
            Style::Ref => format!("c::<T>(std::f64::consts::{name})"),
        },
        E::Local(s) => s.clone(),
        E::LoopVar(i) => match st {
            Style::Macro => format!("({i} as f64)"),
            Style::Ref => format!("c::<T>({i} as f64)"),
        },
        E::Neg(a) => format!("(-{})", r(a)),
        E::Bin(op, a, b) => format!("({} {op} {})", r(a), r(b)),
        // A receiver without variables would be an ambiguous `{float}` in the macro input (kept as
        // ordinary Rust), so such calls always take the path form there.
        E::Call(op, a, path) => match (st, *path || !has_var(a)) {
            (Style::Macro, true) => format!("f64::{}({})", op.method(), r(a)),
            _ => format!("{}.{}()", r(a), op.method()),
        },
        E::Powi(a, n, path) => match (st, *path || !has_var(a)) {
            (Style::Macro, true) => format!("f64::powi({}, {n})", r(a)),
            _ => format!("{}.powi({n})", r(a)),
        },
        E::Powf(a, b, path) => match (st, *path || !has_var(a), &**b) {
            (Style::Macro, true, _) => format!("f64::powf({}, {})", r(a), r(b)),
            (Style::Macro, false, _) => format!("{}.powf({})", r(a), r(b)),
            // num-dual's `powf` takes a primitive exponent; a dual exponent is `powd`.
            (Style::Ref, _, exponent) => match literal_value(exponent) {
                Some(v) => format!("{}.powf({v:?})", r(a)),
                None => format!("{}.powd({})", r(a), r(b)),
            },
        },
        E::Atan2(y, x, path) => match (st, *path || !has_var(y)) {
            (Style::Macro, true) => format!("f64::atan2({}, {})", r(y), r(x)),
            _ => format!("{}.atan2({})", r(y), r(x)),
        },
    }
}

/// The value of a literal `c` or a negated literal `(-c)`.
fn literal_value(e: &E) -> Option<f64> {
    match e {
        E::Lit(v) => Some(*v),
        E::Neg(inner) => match **inner {
            E::Lit(v) => Some(-v),
            _ => None,
        },
        _ => None,
    }
}

/// Whether `e` reads anything but literals, so that its Rust type is `f64` (not `{float}`),
/// which method calls in the macro input (kept as ordinary Rust) need.
fn has_var(e: &E) -> bool {
    match e {
        E::Lit(_) | E::Const(_) => false,
        E::Coord(..) | E::Diff(_) | E::Param(_) | E::Local(_) | E::LoopVar(_) => true,
        E::Neg(a) | E::Call(_, a, _) | E::Powi(a, _, _) => has_var(a),
        E::Bin(_, a, b) | E::Powf(a, b, _) | E::Atan2(a, b, _) => has_var(a) || has_var(b),
    }
}

fn count_ops(e: &E, ops: &mut [usize; 21], features: &mut [bool; 17]) {
    let mut feat =
        |f: Feature| features[FEATURES.iter().position(|&g| g == f).expect("listed")] = true;
    match e {
        E::Coord(..) | E::Diff(_) | E::Param(_) | E::Lit(_) => {}
        E::Local(name) => {
            if name.contains(".0") || name.contains(".1") {
                feat(Feature::TupleField);
            }
        }
        E::Const(_) => feat(Feature::Const),
        E::LoopVar(_) => feat(Feature::LoopIndexCast),
        E::Neg(a) => {
            ops[Op::Neg.index()] += 1;
            count_ops(a, ops, features);
        }
        E::Bin(op, a, b) => {
            let op = match op {
                '+' => Op::Add,
                '-' => Op::Sub,
                '*' => Op::Mul,
                _ => Op::Div,
            };
            ops[op.index()] += 1;
            count_ops(a, ops, features);
            count_ops(b, ops, features);
        }
        E::Call(op, a, path) => {
            if *path {
                feat(Feature::PathCall);
            }
            ops[op.index()] += 1;
            count_ops(a, ops, features);
        }
        E::Powi(a, _, path) => {
            if *path {
                feat(Feature::PathCall);
            }
            ops[Op::Powi.index()] += 1;
            count_ops(a, ops, features);
        }
        E::Powf(a, b, path) | E::Atan2(a, b, path) => {
            let op = if let E::Powf(..) = e {
                Op::Powf
            } else {
                Op::Atan2
            };
            if *path {
                feat(Feature::PathCall);
            }
            ops[op.index()] += 1;
            count_ops(a, ops, features);
            count_ops(b, ops, features);
        }
    }
}

#[derive(Clone, Debug)]
enum Val {
    Scalar(E),
    Tuple(Vec<E>),
    Array(Vec<E>),
    Repeat(E, usize),
}

#[derive(Clone, Debug)]
enum Stmt {
    /// `let [mut] pat[: f64] = val;` — `names.len() > 1` is a tuple pattern.
    Let {
        names: Vec<String>,
        mutable: bool,
        annotated: bool,
        val: Val,
    },
    /// `target op value;` with `op` one of `= += -= *= /=`.
    Assign {
        target: String,
        op: &'static str,
        value: E,
    },
    For {
        var: String,
        lo: i64,
        hi: i64,
        inclusive: bool,
        body: Vec<Stmt>,
    },
}

fn render_stmts(stmts: &[Stmt], st: Style, indent: usize, out: &mut String) {
    let pad = "    ".repeat(indent);
    for s in stmts {
        match s {
            Stmt::Let {
                names,
                mutable,
                annotated,
                val,
            } => {
                let pat = if names.len() == 1 {
                    names[0].clone()
                } else {
                    format!("({})", names.join(", "))
                };
                let m = if *mutable { "mut " } else { "" };
                let ty = match (annotated, st) {
                    (false, _) => "",
                    (true, Style::Macro) => ": f64",
                    (true, Style::Ref) => ": T",
                };
                let list = |es: &[E]| {
                    es.iter()
                        .map(|e| render(e, st))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                let v = match val {
                    Val::Scalar(e) => render(e, st),
                    Val::Tuple(es) => format!("({})", list(es)),
                    Val::Array(es) => format!("[{}]", list(es)),
                    Val::Repeat(e, n) => format!("[{}; {n}]", render(e, st)),
                };
                let _ = writeln!(out, "{pad}let {m}{pat}{ty} = {v};");
            }
            Stmt::Assign { target, op, value } => {
                let _ = writeln!(out, "{pad}{target} {op} {};", render(value, st));
            }
            Stmt::For {
                var,
                lo,
                hi,
                inclusive,
                body,
            } => {
                let dots = if *inclusive { "..=" } else { ".." };
                let _ = writeln!(out, "{pad}for {var} in {lo}{dots}{hi} {{");
                render_stmts(body, st, indent + 1, out);
                let _ = writeln!(out, "{pad}}}");
            }
        }
    }
}

fn walk_stmts(stmts: &[Stmt], ops: &mut [usize; 21], f: &mut [bool; 17], depth: usize) {
    let feat = |f: &mut [bool; 17], g: Feature| {
        f[FEATURES.iter().position(|&h| h == g).expect("listed")] = true
    };
    for s in stmts {
        match s {
            Stmt::Let {
                names,
                annotated,
                val,
                ..
            } => {
                feat(f, Feature::Let);
                if *annotated {
                    feat(f, Feature::LetAnnotated);
                }
                if names.len() > 1 {
                    feat(f, Feature::LetTuple);
                }
                match val {
                    Val::Scalar(e) => count_ops(e, ops, f),
                    Val::Tuple(es) => es.iter().for_each(|e| count_ops(e, ops, f)),
                    Val::Array(es) => {
                        feat(f, Feature::Array);
                        es.iter().for_each(|e| count_ops(e, ops, f));
                    }
                    Val::Repeat(e, _) => {
                        feat(f, Feature::ArrayRepeat);
                        count_ops(e, ops, f);
                    }
                }
            }
            Stmt::Assign { target, op, value } => {
                if target.contains('[') {
                    feat(f, Feature::ArrayAssign);
                }
                if *op != "=" {
                    feat(f, Feature::CompoundAssign);
                }
                count_ops(value, ops, f);
            }
            Stmt::For {
                inclusive, body, ..
            } => {
                feat(f, Feature::ForLoop);
                if depth > 0 {
                    feat(f, Feature::NestedFor);
                }
                if *inclusive {
                    feat(f, Feature::InclusiveRange);
                }
                walk_stmts(body, ops, f, depth + 1);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Random expressions with magnitude bounds
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Debug)]
struct Node {
    e: E,
    /// Upper bound on `|value|` over the sampled box.
    bound: f64,
}

fn node(e: E, bound: f64) -> Node {
    Node { e, bound }
}

/// A positive expression bounded away from zero: `min ≤ value ≤ max`.
struct Pos {
    e: E,
    min: f64,
    max: f64,
}

/// What the case's variables are and which locals are in scope.
struct Gen {
    rng: Rng,
    k: usize,
    /// Locals in scope (scalars, elements, fields, loop-indexed elements) with their bounds.
    locals: Vec<(E, f64)>,
    /// Loop variables in scope with their largest value.
    loop_vars: Vec<(String, i64)>,
    path_calls: bool,
}

/// `x^n` for `n ≥ 0` by repeated multiplication (reproducible bit for bit).
fn ipow(x: f64, n: i32) -> f64 {
    (0..n).fold(1.0, |acc, _| acc * x)
}

fn bx(e: E) -> Box<E> {
    Box::new(e)
}

impl Gen {
    fn leaf(&mut self) -> Node {
        let has_locals = !self.locals.is_empty() || !self.loop_vars.is_empty();
        let kind = self
            .rng
            .weighted(&[if has_locals { 8 } else { 0 }, 9, 2, 3, 1]);
        match kind {
            0 => {
                let n = self.locals.len() + self.loop_vars.len();
                let i = self.rng.below(n);
                if i < self.locals.len() {
                    let (e, b) = self.locals[i].clone();
                    node(e, b)
                } else {
                    let (v, hi) = self.loop_vars[i - self.locals.len()].clone();
                    node(E::LoopVar(v), hi as f64)
                }
            }
            1 => self.coordinate(),
            2 => {
                let i = self.rng.below(2);
                node(E::Param(i), 1.5)
            }
            3 => {
                let v = self.rng.lit(5, 250);
                node(E::Lit(v), v)
            }
            _ => {
                let (name, v) = CONSTS[self.rng.below(CONSTS.len())];
                node(E::Const(name), v)
            }
        }
    }

    /// A coordinate leaf: `q0.a … q1.b`, a shape difference `(q1.a − q0.a)` (which couples `x0`
    /// and `x1`, as kinetic terms do) or a group difference `(q1.c − q0.c)`.
    fn coordinate(&mut self) -> Node {
        let i = self.rng.below(6 + self.k);
        if i < 4 {
            node(E::Coord((i / 2) as u8, i % 2), 1.0)
        } else if i < 6 {
            let s = i - 4;
            node(E::Bin('-', bx(E::Coord(1, s)), bx(E::Coord(0, s))), 2.0)
        } else {
            // |g1 + B (x1 − x0)| ≤ 1 + 2 · 1.2 · 2.
            node(E::Diff(i - 6), 6.0)
        }
    }

    fn path(&mut self) -> bool {
        self.path_calls && self.rng.chance(1, 4)
    }

    /// Any expression, `|value| ≤ LIMIT`.
    fn expr(&mut self, depth: u32) -> Node {
        if depth == 0 || self.rng.chance(1, 5) {
            return self.leaf();
        }
        let mut weights = [1usize; 21];
        for op in [Op::Add, Op::Sub, Op::Mul] {
            weights[op.index()] = 4;
        }
        weights[Op::Div.index()] = 2;
        let op = OPS[self.rng.weighted(&weights)];
        self.op(op, depth)
    }

    /// An expression that reads a variable (so that it is typed `f64` in the macro input).
    fn expr_v(&mut self, depth: u32) -> Node {
        let n = self.expr(depth);
        if has_var(&n.e) {
            return n;
        }
        let v = self.coordinate();
        let b = n.bound * v.bound;
        let combined = node(E::Bin('*', bx(n.e), bx(v.e)), b);
        self.limit(combined)
    }

    /// Squashes `n` through a bounded function if its bound exceeds `LIMIT`.
    fn limit(&mut self, n: Node) -> Node {
        if n.bound <= LIMIT {
            n
        } else {
            self.squash(n)
        }
    }

    /// `f(n)` with `f` one of sin, cos, tanh, atan: `|value| ≤ 1.571`.
    fn squash(&mut self, n: Node) -> Node {
        let op = [Op::Sin, Op::Cos, Op::Tanh, Op::Atan][self.rng.below(4)];
        let b = if op == Op::Atan { 1.571 } else { 1.0 };
        let p = self.path();
        node(E::Call(op, bx(n.e), p), b)
    }

    /// An expression reading a variable with `|value| ≤ 1`.
    fn unit(&mut self, depth: u32) -> Node {
        let n = self.expr_v(depth);
        if n.bound <= 1.0 {
            return n;
        }
        let op = [Op::Sin, Op::Cos, Op::Tanh][self.rng.below(3)];
        let p = self.path();
        node(E::Call(op, bx(n.e), p), 1.0)
    }

    /// A positive expression bounded away from zero, `max ≤ LIMIT`.
    fn pos(&mut self, depth: u32) -> Pos {
        let d = depth.saturating_sub(1);
        match self.rng.below(7) {
            0 => {
                // L + u², u² ≤ LIMIT − 2.5.
                let l = self.rng.lit(50, 250);
                let mut u = self.expr_v(d);
                if u.bound * u.bound > LIMIT - 2.5 {
                    u = self.squash(u);
                }
                let sq = E::Bin('*', bx(u.e.clone()), bx(u.e));
                Pos {
                    e: E::Bin('+', bx(E::Lit(l)), bx(sq)),
                    min: l,
                    max: l + u.bound * u.bound,
                }
            }
            1 => {
                // L + sin(u), L + cos(u) or L + tanh(u), L ≥ 1.5.
                let l = self.rng.lit(150, 300);
                let u = self.expr_v(d);
                let op = [Op::Sin, Op::Cos, Op::Tanh][self.rng.below(3)];
                let p = self.path();
                Pos {
                    e: E::Bin('+', bx(E::Lit(l)), bx(E::Call(op, bx(u.e), p))),
                    min: l - 1.0,
                    max: l + 1.0,
                }
            }
            2 => {
                // exp(c · w), |c · w| ≤ 2.
                let c = self.rng.lit(10, 200);
                let w = self.unit(d);
                let p = self.path();
                Pos {
                    e: E::Call(Op::Exp, bx(E::Bin('*', bx(E::Lit(c)), bx(w.e))), p),
                    min: 0.135,
                    max: 7.4,
                }
            }
            3 => {
                // cosh(c · w), |c · w| ≤ 2.
                let c = self.rng.lit(10, 200);
                let w = self.unit(d);
                let p = self.path();
                Pos {
                    e: E::Call(Op::Cosh, bx(E::Bin('*', bx(E::Lit(c)), bx(w.e))), p),
                    min: 1.0,
                    max: 3.8,
                }
            }
            4 => Pos {
                e: E::Param(0),
                min: 0.5,
                max: 1.5,
            },
            5 => {
                // sqrt(L + u²).
                let l = self.rng.lit(50, 250);
                let mut u = self.expr_v(d);
                if u.bound * u.bound > LIMIT - 2.5 {
                    u = self.squash(u);
                }
                let sq = E::Bin('*', bx(u.e.clone()), bx(u.e));
                let p = self.path();
                Pos {
                    e: E::Call(Op::Sqrt, bx(E::Bin('+', bx(E::Lit(l)), bx(sq))), p),
                    min: 0.7,
                    max: LIMIT,
                }
            }
            _ => {
                // L + h · h.
                let l = self.rng.lit(20, 150);
                Pos {
                    e: E::Bin(
                        '+',
                        bx(E::Lit(l)),
                        bx(E::Bin('*', bx(E::Param(0)), bx(E::Param(0)))),
                    ),
                    min: l + 0.25,
                    max: l + 2.25,
                }
            }
        }
    }

    /// A positive expression in `[0.5, 3.5]`, for `powf` bases.
    fn moderate_pos(&mut self, depth: u32) -> Pos {
        let d = depth.saturating_sub(1);
        match self.rng.below(4) {
            0 => {
                let l = self.rng.lit(150, 250);
                let u = self.expr_v(d);
                let op = [Op::Sin, Op::Cos, Op::Tanh][self.rng.below(3)];
                let p = self.path();
                Pos {
                    e: E::Bin('+', bx(E::Lit(l)), bx(E::Call(op, bx(u.e), p))),
                    min: l - 1.0,
                    max: l + 1.0,
                }
            }
            1 => {
                let w = self.unit(d);
                let sq = E::Bin('*', bx(w.e.clone()), bx(w.e));
                Pos {
                    e: E::Bin('+', bx(E::Lit(1.0)), bx(sq)),
                    min: 1.0,
                    max: 2.0,
                }
            }
            2 => {
                let w = self.unit(d);
                let p = self.path();
                Pos {
                    e: E::Call(Op::Cosh, bx(w.e), p),
                    min: 1.0,
                    max: 1.6,
                }
            }
            _ => Pos {
                e: E::Param(0),
                min: 0.5,
                max: 1.5,
            },
        }
    }

    /// A positive or negative expression bounded away from zero: `|value| ≥ min`.
    fn nonzero(&mut self, depth: u32) -> Pos {
        let p = self.pos(depth);
        if self.rng.chance(1, 3) {
            Pos {
                e: E::Neg(bx(p.e)),
                ..p
            }
        } else {
            p
        }
    }

    /// An expression whose root is `op`, `|value| ≤ LIMIT`.
    fn op(&mut self, op: Op, depth: u32) -> Node {
        let d = depth.saturating_sub(1);
        let path = self.path();
        match op {
            Op::Add | Op::Sub => {
                let a = self.expr(d);
                let mut b = self.expr(d);
                if a.bound + b.bound > LIMIT {
                    b = self.squash(b);
                }
                let n = node(
                    E::Bin(if op == Op::Add { '+' } else { '-' }, bx(a.e), bx(b.e)),
                    a.bound + b.bound,
                );
                self.limit(n)
            }
            Op::Mul => {
                let a = self.expr(d);
                let mut b = self.expr(d);
                if a.bound * b.bound > LIMIT {
                    b = self.squash(b);
                }
                let n = node(E::Bin('*', bx(a.e), bx(b.e)), a.bound * b.bound);
                self.limit(n)
            }
            Op::Div => {
                let a = self.expr(d);
                let q = self.nonzero(d);
                let n = node(E::Bin('/', bx(a.e), bx(q.e)), a.bound / q.min);
                self.limit(n)
            }
            Op::Neg => {
                let a = self.expr(d);
                node(E::Neg(bx(a.e)), a.bound)
            }
            Op::Sin | Op::Cos | Op::Tanh | Op::Atan => {
                let a = self.expr_v(d);
                let b = if op == Op::Atan { 1.571 } else { 1.0 };
                node(E::Call(op, bx(a.e), path), b)
            }
            Op::Tan => {
                // |c · w| ≤ 1.2.
                let c = self.rng.lit(20, 120);
                let w = self.unit(d);
                node(
                    E::Call(op, bx(E::Bin('*', bx(E::Lit(c)), bx(w.e))), path),
                    2.6,
                )
            }
            Op::Asin | Op::Acos => {
                // |c · w| ≤ 0.8.
                let c = self.rng.lit(10, 80);
                let w = self.unit(d);
                node(
                    E::Call(op, bx(E::Bin('*', bx(E::Lit(c)), bx(w.e))), path),
                    3.15,
                )
            }
            Op::Exp | Op::Sinh | Op::Cosh => {
                // |arg| ≤ 3.
                let a = self.expr_v(d);
                let arg = if a.bound <= 3.0 {
                    a.e
                } else {
                    let c = self.rng.lit(50, 250);
                    let w = self.unit(d);
                    E::Bin('*', bx(E::Lit(c)), bx(w.e))
                };
                node(E::Call(op, bx(arg), path), 20.1)
            }
            Op::Ln => {
                let q = self.pos(d);
                // |ln v| ≤ max(v − 1, ln(1 / min)) with min ≥ 0.1.
                node(E::Call(op, bx(q.e), path), (q.max - 1.0).max(2.31))
            }
            Op::Sqrt => {
                let q = self.pos(d);
                node(E::Call(op, bx(q.e), path), 0.5 * (q.max + 1.0))
            }
            Op::Recip => {
                let q = self.nonzero(d);
                node(E::Call(op, bx(q.e), path), 1.0 / q.min)
            }
            Op::Powi => {
                let n = [-3, -2, -1, 0, 1, 2, 2, 3, 3, 4][self.rng.below(10)];
                if n < 0 {
                    let q = self.nonzero(d);
                    let b = ipow(1.0 / q.min, -n).max(1.0);
                    self.limit(node(E::Powi(bx(q.e), n, path), b))
                } else {
                    let mut a = self.expr_v(d);
                    if ipow(a.bound, n) > LIMIT {
                        a = self.squash(a);
                    }
                    let b = ipow(a.bound, n).max(1.0);
                    node(E::Powi(bx(a.e), n, path), b)
                }
            }
            Op::Powf => {
                let base = self.moderate_pos(d);
                let exponent = if self.rng.chance(1, 2) {
                    // A literal in [0.05, 2.45] or [−1.5, −0.05], never an integer.
                    let mut v = self.rng.lit(5, 245);
                    if v.fract() == 0.0 {
                        v += 0.25;
                    }
                    if self.rng.chance(1, 3) {
                        let v = self.rng.lit(5, 150);
                        let v = if v.fract() == 0.0 { v - 0.25 } else { v };
                        // `(-v)` in the macro input, the literal `-v` in the reference.
                        E::Neg(bx(E::Lit(v)))
                    } else {
                        E::Lit(v)
                    }
                } else {
                    let c = self.rng.lit(10, 150);
                    let w = self.unit(d);
                    E::Bin('*', bx(E::Lit(c)), bx(w.e))
                };
                node(E::Powf(bx(base.e), bx(exponent), path), 23.0)
            }
            Op::Atan2 => {
                let y = self.expr_v(d);
                let x = self.nonzero(d);
                node(E::Atan2(bx(y.e), bx(x.e), path), 3.15)
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Cases
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug)]
enum Template {
    Plain,
    Lets,
    Tuple,
    Array,
    Loop,
    Mixed,
}

const TEMPLATES: [Template; 10] = [
    Template::Plain,
    Template::Lets,
    Template::Plain,
    Template::Tuple,
    Template::Plain,
    Template::Array,
    Template::Plain,
    Template::Loop,
    Template::Plain,
    Template::Mixed,
];

/// A connection entry: `c` or `c · p`.
#[derive(Clone, Copy, Debug)]
enum Entry {
    Lit(f64),
    P(f64),
}

fn render_entry(e: Entry) -> String {
    match e {
        Entry::Lit(v) => format!("{v:?}"),
        Entry::P(v) => {
            if v == 1.0 {
                "p".to_string()
            } else {
                format!("{v:?} * p")
            }
        }
    }
}

struct Case {
    name: String,
    k: usize,
    connection: Option<Vec<Vec<Entry>>>,
    stmts: Vec<Stmt>,
    result: E,
    template: Template,
    featured: Op,
}

impl Gen {
    /// `let` bindings of scalars, some annotated, later ones reading earlier ones.
    fn lets(&mut self, stmts: &mut Vec<Stmt>, prefix: &str) {
        let n = 2 + self.rng.below(2);
        for j in 0..n {
            let depth = 1 + self.rng.below(2) as u32;
            let v = self.expr_v(depth);
            let name = format!("{prefix}{j}");
            stmts.push(Stmt::Let {
                names: vec![name.clone()],
                mutable: false,
                annotated: self.rng.chance(1, 3),
                val: Val::Scalar(v.e),
            });
            self.locals.push((E::Local(name), v.bound));
        }
    }

    fn tuples(&mut self, stmts: &mut Vec<Stmt>) {
        let (u, v) = (self.expr_v(2), self.expr_v(1));
        stmts.push(Stmt::Let {
            names: vec!["u0".into(), "u1".into()],
            mutable: false,
            annotated: false,
            val: Val::Tuple(vec![u.e, v.e]),
        });
        self.locals.push((E::Local("u0".into()), u.bound));
        self.locals.push((E::Local("u1".into()), v.bound));
        let (a, b) = (self.expr_v(1), self.expr_v(2));
        stmts.push(Stmt::Let {
            names: vec!["pair".into()],
            mutable: false,
            annotated: false,
            val: Val::Tuple(vec![a.e, b.e]),
        });
        self.locals.push((E::Local("(pair.0)".into()), a.bound));
        self.locals.push((E::Local("(pair.1)".into()), b.bound));
    }

    /// A literal array and a repeat array with one element reassigned.
    fn arrays(&mut self, stmts: &mut Vec<Stmt>) -> Vec<f64> {
        let len = 3;
        let items: Vec<Node> = (0..len)
            .map(|_| {
                let depth = 1 + self.rng.below(2) as u32;
                self.expr_v(depth)
            })
            .collect();
        let bounds: Vec<f64> = items.iter().map(|n| n.bound).collect();
        stmts.push(Stmt::Let {
            names: vec!["arr".into()],
            mutable: false,
            annotated: false,
            val: Val::Array(items.into_iter().map(|n| n.e).collect()),
        });
        for (i, &b) in bounds.iter().enumerate() {
            self.locals.push((E::Local(format!("arr[{i}]")), b));
        }
        let fill = self.expr_v(1);
        let other = self.expr_v(2);
        stmts.push(Stmt::Let {
            names: vec!["w".into()],
            mutable: true,
            annotated: false,
            val: Val::Repeat(fill.e, 2),
        });
        stmts.push(Stmt::Assign {
            target: "w[1]".into(),
            op: "=",
            value: other.e,
        });
        self.locals.push((E::Local("w[0]".into()), fill.bound));
        self.locals.push((E::Local("w[1]".into()), other.bound));
        bounds
    }

    /// `for` loops accumulating over `arr` (which must be in scope with the given bounds).
    fn loops(&mut self, stmts: &mut Vec<Stmt>, arr: &[f64]) {
        let arr_bound = arr.iter().copied().fold(0.0, f64::max);
        // A sum over one loop: acc ±= arr[i] · f(i).
        stmts.push(Stmt::Let {
            names: vec!["acc".into()],
            mutable: true,
            annotated: true,
            val: Val::Scalar(E::Lit(0.0)),
        });
        let (hi, inclusive) = if self.rng.chance(1, 2) {
            (3, false)
        } else {
            (2, true)
        };
        self.loop_vars.push(("i".into(), 2));
        self.locals.push((E::Local("arr[i]".into()), arr_bound));
        let mut g = self.expr_v(2);
        if self.rng.chance(1, 2) {
            // An explicit `(i as f64)`: the loop index as a number.
            let c = self.rng.lit(10, 50);
            let f = E::Bin(
                '+',
                bx(E::Lit(1.0)),
                bx(E::Bin('*', bx(E::Lit(c)), bx(E::LoopVar("i".into())))),
            );
            g = node(E::Bin('*', bx(f), bx(g.e)), 2.0 * g.bound);
        }
        if arr_bound * g.bound > LIMIT / 3.0 {
            g = self.squash(g);
        }
        let term = node(
            E::Bin('*', bx(E::Local("arr[i]".into())), bx(g.e)),
            arr_bound * g.bound,
        );
        let term = if term.bound > LIMIT / 3.0 {
            self.squash(term)
        } else {
            term
        };
        self.locals.pop();
        self.loop_vars.pop();
        let op = ["+=", "-=", "="][self.rng.below(3)];
        let value = if op == "=" {
            E::Bin('+', bx(E::Local("acc".into())), bx(term.e))
        } else {
            term.e
        };
        stmts.push(Stmt::For {
            var: "i".into(),
            lo: 0,
            hi,
            inclusive,
            body: vec![Stmt::Assign {
                target: "acc".into(),
                op,
                value,
            }],
        });
        self.locals.push((E::Local("acc".into()), 3.0 * term.bound));

        // A product over a nested loop: prod *= (1 + c · w(i, j)) or prod /= (…), |c| ≤ 0.3.
        if self.rng.chance(2, 3) {
            let op = if self.rng.chance(1, 2) { "*=" } else { "/=" };
            stmts.push(Stmt::Let {
                names: vec!["prod".into()],
                mutable: true,
                annotated: true,
                val: Val::Scalar(E::Lit(1.0)),
            });
            self.loop_vars.push(("i".into(), 1));
            self.loop_vars.push(("j".into(), 1));
            self.locals.push((E::Local("arr[i + j]".into()), arr_bound));
            let w = self.unit(2);
            self.locals.pop();
            self.loop_vars.pop();
            self.loop_vars.pop();
            let c = self.rng.lit(5, 30);
            let factor = E::Bin(
                '+',
                bx(E::Lit(1.0)),
                bx(E::Bin('*', bx(E::Lit(c)), bx(w.e))),
            );
            stmts.push(Stmt::For {
                var: "i".into(),
                lo: 0,
                hi: 2,
                inclusive: false,
                body: vec![Stmt::For {
                    var: "j".into(),
                    lo: 0,
                    hi: 1,
                    inclusive: true,
                    body: vec![Stmt::Assign {
                        target: "prod".into(),
                        op,
                        value: factor,
                    }],
                }],
            });
            // 1.3⁴ < 3 and 0.7⁻⁴ < 4.5.
            self.locals.push((E::Local("prod".into()), 4.5));
        }
    }

    fn case(&mut self, index: usize) -> Case {
        let featured = OPS[index % OPS.len()];
        let template = TEMPLATES[index % TEMPLATES.len()];
        self.k = if index % 5 == 3 { 2 } else { 1 };
        self.locals.clear();
        self.loop_vars.clear();
        self.path_calls = !index.is_multiple_of(3);
        let connection = (index % 4 == 1).then(|| {
            (0..self.k)
                .map(|_| {
                    (0..2)
                        .map(|_| {
                            let v = self.rng.lit(10, 120);
                            let v = if self.rng.chance(1, 2) { -v } else { v };
                            if self.rng.chance(1, 3) {
                                Entry::P(if self.rng.chance(1, 2) { 1.0 } else { v })
                            } else {
                                Entry::Lit(v)
                            }
                        })
                        .collect()
                })
                .collect()
        });
        let mut stmts = Vec::new();
        match template {
            Template::Plain => {}
            Template::Lets => self.lets(&mut stmts, "t"),
            Template::Tuple => self.tuples(&mut stmts),
            Template::Array => {
                self.arrays(&mut stmts);
            }
            Template::Loop => {
                let arr = self.arrays(&mut stmts);
                self.loops(&mut stmts, &arr);
            }
            Template::Mixed => {
                self.lets(&mut stmts, "s");
                let arr = self.arrays(&mut stmts);
                self.loops(&mut stmts, &arr);
                self.tuples(&mut stmts);
            }
        }
        let depth = 3 + self.rng.below(3) as u32;
        let root = self.op(featured, depth);
        let result = if self.rng.chance(1, 2) {
            let rest = self.expr(depth - 1);
            let rest = if rest.bound > LIMIT {
                self.squash(rest)
            } else {
                rest
            };
            E::Bin(
                if self.rng.chance(1, 2) { '+' } else { '-' },
                bx(root.e),
                bx(rest.e),
            )
        } else {
            root.e
        };
        let result = self.use_all_locals(&stmts, result);
        let result = self.use_all_group_coordinates(&stmts, result);
        Case {
            name: format!("case_{index:03}"),
            k: self.k,
            connection,
            stmts,
            result,
            template,
            featured,
        }
    }
}

/// The local variables `e` reads (`arr` for `arr[i]`, `pair` for `(pair.0)`).
fn names_in(e: &E, out: &mut Vec<String>) {
    match e {
        E::Local(s) => {
            let base: String = s
                .trim_start_matches('(')
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            out.push(base);
        }
        E::Coord(..) | E::Diff(_) | E::Param(_) | E::Lit(_) | E::Const(_) | E::LoopVar(_) => {}
        E::Neg(a) | E::Call(_, a, _) | E::Powi(a, _, _) => names_in(a, out),
        E::Bin(_, a, b) | E::Powf(a, b, _) | E::Atan2(a, b, _) => {
            names_in(a, out);
            names_in(b, out);
        }
    }
}

/// Backward liveness over `stmts`: adds to `live` every local that a live value reads.
fn liveness(stmts: &[Stmt], live: &mut Vec<String>) {
    for s in stmts.iter().rev() {
        match s {
            Stmt::Let { names, val, .. } => {
                if names.iter().any(|n| live.contains(n)) {
                    match val {
                        Val::Scalar(e) | Val::Repeat(e, _) => names_in(e, live),
                        Val::Tuple(es) | Val::Array(es) => {
                            es.iter().for_each(|e| names_in(e, live))
                        }
                    }
                }
            }
            Stmt::Assign { target, value, .. } => {
                let base: String = target
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if live.contains(&base) {
                    names_in(value, live);
                }
            }
            Stmt::For { body, .. } => {
                // Twice: a value read in one iteration may feed the next.
                liveness(body, live);
                liveness(body, live);
            }
        }
    }
}

impl Gen {
    /// Adds `result ± c · (dead locals)` so that every statement feeds the Lagrangian (the macro
    /// only differentiates what the result depends on).
    fn use_all_locals(&mut self, stmts: &[Stmt], result: E) -> E {
        let mut live = Vec::new();
        names_in(&result, &mut live);
        liveness(stmts, &mut live);
        let mut dead = Vec::new();
        for s in stmts {
            if let Stmt::Let { names, .. } = s {
                dead.extend(names.iter().filter(|n| !live.contains(n)).cloned());
            }
        }
        if dead.is_empty() {
            return result;
        }
        let mut tail: Option<Node> = None;
        let texts: Vec<String> = dead
            .into_iter()
            .flat_map(|name| match name.as_str() {
                "arr" => vec![format!("arr[{}]", self.rng.below(3))],
                "w" => vec!["w[0]".to_string(), "w[1]".to_string()],
                "pair" => vec!["(pair.0)".to_string(), "(pair.1)".to_string()],
                _ => vec![name],
            })
            .collect();
        for text in texts {
            let bound = self
                .locals
                .iter()
                .find(|(e, _)| matches!(e, E::Local(s) if *s == text))
                .map_or(LIMIT, |(_, b)| *b);
            let c = self.rng.lit(5, 50);
            let term = node(E::Bin('*', bx(E::Lit(c)), bx(E::Local(text))), c * bound);
            tail = Some(match tail {
                None => term,
                Some(t) => {
                    let b = t.bound + term.bound;
                    node(E::Bin('+', bx(t.e), bx(term.e)), b)
                }
            });
        }
        let tail = self.limit(tail.expect("nonempty"));
        E::Bin('+', bx(result), bx(tail.e))
    }
}

/// Whether `e` reads the group difference `j`.
fn reads_diff(e: &E, j: usize) -> bool {
    match e {
        E::Diff(i) => *i == j,
        E::Coord(..) | E::Param(_) | E::Lit(_) | E::Const(_) | E::Local(_) | E::LoopVar(_) => false,
        E::Neg(a) | E::Call(_, a, _) | E::Powi(a, _, _) => reads_diff(a, j),
        E::Bin(_, a, b) | E::Powf(a, b, _) | E::Atan2(a, b, _) => {
            reads_diff(a, j) || reads_diff(b, j)
        }
    }
}

fn stmts_read_diff(stmts: &[Stmt], j: usize) -> bool {
    stmts.iter().any(|s| match s {
        Stmt::Let { val, .. } => match val {
            Val::Scalar(e) | Val::Repeat(e, _) => reads_diff(e, j),
            Val::Tuple(es) | Val::Array(es) => es.iter().any(|e| reads_diff(e, j)),
        },
        Stmt::Assign { value, .. } => reads_diff(value, j),
        Stmt::For { body, .. } => stmts_read_diff(body, j),
    })
}

impl Gen {
    /// Adds `c · f((q1.g − q0.g) · leaf)` for each group coordinate `g` the case does not read yet,
    /// so that every row and column of the Jacobian is exercised.
    fn use_all_group_coordinates(&mut self, stmts: &[Stmt], mut result: E) -> E {
        for j in 0..self.k {
            if reads_diff(&result, j) || stmts_read_diff(stmts, j) {
                continue;
            }
            let leaf = self.coordinate();
            let product = node(E::Bin('*', bx(E::Diff(j)), bx(leaf.e)), 6.0 * leaf.bound);
            let squashed = self.squash(product);
            let c = self.rng.lit(10, 90);
            let term = E::Bin('*', bx(E::Lit(c)), bx(squashed.e));
            result = E::Bin('+', bx(result), bx(term));
        }
        result
    }
}

fn camel(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
        })
        .collect()
}

fn render_case(case: &Case, out: &mut String) {
    let k = case.k;
    let n = 2 + k;
    let m = 4 + k;
    let group = GROUP[..k].join(", ");
    let conn = case.connection.as_ref().map_or(String::new(), |rows| {
        let rows: Vec<String> = rows
            .iter()
            .map(|r| {
                format!(
                    "[{}]",
                    r.iter()
                        .map(|&e| render_entry(e))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })
            .collect();
        format!(", connection = [{}]", rows.join(", "))
    });
    let _ = writeln!(
        out,
        "// {}: features `{}`, template {:?}, K = {k}{}.",
        case.name,
        case.featured.method(),
        case.template,
        if case.connection.is_some() {
            ", nonzero connection"
        } else {
            ""
        }
    );
    let _ = writeln!(
        out,
        "#[reduced_lagrangian(shape(a, b), group({group}){conn})]"
    );
    let _ = writeln!(
        out,
        "fn {}(q0: Config, q1: Config, h: f64, p: f64) -> f64 {{",
        case.name
    );
    render_stmts(&case.stmts, Style::Macro, 1, out);
    let _ = writeln!(out, "    {}", render(&case.result, Style::Macro));
    let _ = writeln!(out, "}}\n");

    let _ = writeln!(
        out,
        "fn {}_ref<T: DualNum<Primitive = f64> + Copy>(q0: [T; {n}], q1: [T; {n}], h: T, p: T) -> T {{",
        case.name
    );
    render_stmts(&case.stmts, Style::Ref, 1, out);
    let _ = writeln!(out, "    {}", render(&case.result, Style::Ref));
    let _ = writeln!(out, "}}\n");

    let entries: Vec<String> = match &case.connection {
        None => vec!["0.0".to_string(); 2 * k],
        Some(rows) => rows.iter().flatten().map(|&e| render_entry(e)).collect(),
    };
    let _ = writeln!(
        out,
        "fn {}_connection(h: f64, p: f64) -> SMatrix<f64, {k}, 2> {{\n    SMatrix::from_row_slice(&[{}])\n}}\n",
        case.name,
        entries.join(", ")
    );
    let _ = m;
}

fn render_check(case: &Case, out: &mut String) {
    let k = case.k;
    let (n, m) = (2 + k, 4 + k);
    let ty = camel(&case.name);
    let name = &case.name;
    let _ = writeln!(
        out,
        "    super::check_case::<{ty}, 2, {k}, {n}, {m}>(stats, \"{name}\", |h, p| {ty} {{ h, p }}, \
         {name}_connection, {name}_ref::<Dual2SVec64<{m}>>, {name}_ref::<f64>);"
    );
}

/// Renders all cases: the text of `tests/random_exprs/cases.rs` and its coverage.
pub fn generate() -> Generated {
    let mut g = Gen {
        rng: Rng(SEED),
        k: 1,
        locals: Vec::new(),
        loop_vars: Vec::new(),
        path_calls: true,
    };
    let cases: Vec<Case> = (0..CASES).map(|i| g.case(i)).collect();

    let mut op_counts = [0usize; 21];
    let mut feature_counts = [0usize; 17];
    for case in &cases {
        let mut f = [false; 17];
        walk_stmts(&case.stmts, &mut op_counts, &mut f, 0);
        count_ops(&case.result, &mut op_counts, &mut f);
        let mut feat =
            |g: Feature| f[FEATURES.iter().position(|&h| h == g).expect("listed")] = true;
        if case.k == 2 {
            feat(Feature::K2);
        }
        if let Some(rows) = &case.connection {
            feat(Feature::Connection);
            if rows.iter().flatten().any(|e| matches!(e, Entry::P(_))) {
                feat(Feature::ParamConnection);
            }
        }
        for (c, hit) in feature_counts.iter_mut().zip(f) {
            *c += usize::from(hit);
        }
    }

    let mut out = String::new();
    let _ = writeln!(
        out,
        "// @generated by tests/random_exprs/generate.rs (seed {SEED:#018x}): do not edit.\n\
         // Regenerate with `DIRAC_BLESS=1 cargo test --test random_derivatives cases_are_current`.\n\
         //\n\
         // {CASES} random discrete Lagrangians, each written twice: the `#[reduced_lagrangian]` input\n\
         // `case_NNN` and the num-dual reference `case_NNN_ref`, plus the reference connection\n\
         // matrix `case_NNN_connection`. `run_all` hands every case to `check_case`.\n\
         //\n\
         // Operation counts over all cases:"
    );
    for (op, c) in OPS.iter().zip(op_counts) {
        let _ = writeln!(out, "//   {:<6} {c}", op.method());
    }
    let _ = writeln!(out, "// Cases using each syntax feature:");
    for (f, c) in FEATURES.iter().zip(feature_counts) {
        let _ = writeln!(out, "//   {:<16} {c}", format!("{f:?}"));
    }
    let _ = writeln!(
        out,
        "\nuse dirac::nalgebra::SMatrix;\nuse dirac::reduced_lagrangian;\nuse num_dual::{{Dual2SVec64, DualNum}};\n\n\
         /// A literal in the reference's number type.\n\
         fn c<T: DualNum<Primitive = f64>>(v: f64) -> T {{\n    T::from(v)\n}}\n\n\
         /// Number of cases in this file.\n\
         pub const CASES: usize = {CASES};\n"
    );
    for case in &cases {
        render_case(case, &mut out);
    }
    let _ = writeln!(out, "/// Checks every case with `super::check_case`.");
    let _ = writeln!(out, "pub fn run_all(stats: &mut super::Stats) {{");
    for case in &cases {
        render_check(case, &mut out);
    }
    let _ = writeln!(out, "}}");

    Generated {
        text: out,
        op_counts,
        feature_counts,
        cases: cases.len(),
    }
}
