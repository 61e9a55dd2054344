//! Differentiation fuzzing: random expressions over every operation of the body language are
//! rendered to Rust source, parsed with syn, lowered ([`lower`](crate::ir::lower)), differentiated
//! twice at compile time ([`derivatives`], forward over forward, and forward over [`gradient`]'s
//! reverse accumulation) and evaluated
//! ([`Graph::eval`]). The oracle is num-dual's hyper-dual numbers running the *same* tree at run
//! time: a different implementation of every elementary rule, sharing nothing with the compiler
//! but the tree, so a wrong rule, a misnamed function in lowering or a simplification that is not
//! exact shows as a mismatch in the value, a gradient entry or a Hessian entry.
//!
//! proptest generates the trees (and the sample point) and, on a failure, shrinks them to a
//! minimal case, which it records in `proptest-regressions/fuzz.txt` and replays first on every
//! later run. Run more cases with `PROPTEST_CASES=100000 cargo test -p dirac-compiler fuzz`; never
//! fewer than [`CASES`].
//!
//! **Well-conditioned by construction.** A raw tree ([`Expr`]) may compose anything, e.g.
//! `ln(x − x)`; the comparison runs on its guarded form ([`Guarded`], [`guard`]), which carries an
//! interval enclosing every subexpression's value over the sample box and rewrites an argument
//! only where an operation needs it:
//!
//! * the arguments of `ln` and `sqrt` and the base of `powf` (unless already ≥ 0.5), and
//!   divisors, `recip` and negative `powi` bases (unless already ≥ 0.5 in magnitude) become
//!   `0.5 + u·u` (`u` bound to a `let`, so nested guards do not double the text);
//! * `asin`/`acos` see `|arg| ≤ 0.75`, `tan` `|arg| ≤ 1`, `exp`/`sinh`/`cosh`/`tanh` and `powf`
//!   exponents `|arg| ≤ 2`, by multiplying with an exact power of two (so the argument keeps its
//!   shape, and its derivatives are scaled exactly). For `tanh` this is about round-off, not
//!   range: `tanh' = 1 − tanh²` (num-dual: `(cosh² − sinh²) / cosh²`) loses `log10 cosh² x`
//!   digits to cancellation on both sides, 3 at `|x| = 4`;
//! * `atan2` stays off the origin and off its branch cut, the negative `x` axis, where its value
//!   jumps by 2π: `x ≥ 0.5`, or `x ≤ −0.5` and `|y| ≥ 0.5` (guards as above). On the cut the sign
//!   of a zero `y` decides the value, and the graph keeps a single zero: the fuzzer found
//!   `(0.0 * (-PI)).atan2(-PI)`, which is −π in Rust and π compiled (see
//!   `proptest-regressions/fuzz.txt`);
//! * any subexpression whose bound exceeds [`LIMIT`] is scaled the same way.
//!
//! So no argument comes within 0.5 of a singularity ([`MARGIN`]), no value exceeds 20.25 before
//! scaling or [`LIMIT`] after, and a guard is a function of the raw tree: shrinking keeps every
//! case valid. The margin also bounds the derivatives of `x⁻³`, `1/x`, `ln x`, … and so how much
//! they amplify round-off.
//!
//! **Tolerance.** An entry passes when `|a − b| ≤ 1e-12 · max(1, |a|, |b|, s)` ([`TOL`]), with
//! `s` the largest magnitude among the values the compiled entry is computed from (its cone in
//! the graph). Both sides evaluate the same derivatives with correctly rounded `+ − × ÷` and libm
//! functions, in different orders (num-dual's `tan` and `tanh` are quotients, its `atan2` goes
//! through `atan(y / x)`), so they differ by a few ulps of the terms they sum. Mostly those are
//! no larger than the result, `s` changes nothing, and this is the `1e-12 · max(1, |a|, |b|)` of
//! `tests/random_derivatives.rs`. But a second derivative of a deep composition can be a small
//! difference of large terms: `∂²/∂b²` of `tan((0.5 / (0.5 + t²))³)`, `t = atan(sin(0.5 ·
//! exp(1 / (0.5 + b²))))`, at `b = 0.2450289912550459` is 3.71691231859996487 (mpmath, 50
//! digits); the compiler is off by 2.4e-13 and num-dual by 1.9e-12, round-off of the terms, not a
//! wrong rule. A wrong rule is off by far more than 1e-12 of any intermediate value. Measured
//! over 2·10⁵ cases: the largest `|a − b| / max(1, |a|, |b|, s)` is 4.0e-14, 25 times under the
//! tolerance (and `|a − b| / max(1, |a|, |b|)` reaches 1.6e-13).

use std::collections::HashMap;
use std::fmt::Write as _;

use num_dual::{DualNum, HyperDual64};
use proc_macro2::{Ident, Span};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

use crate::ctxt::Ctxt;
use crate::front::layout::CoordName;
use crate::ir::diff::{derivatives, gradient};
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};

/// Cases per run: at least this many, more if `PROPTEST_CASES` asks for more.
const CASES: u32 = 2000;
/// `|a − b| ≤ TOL · max(1, |a|, |b|, s)`; see the module documentation.
const TOL: f64 = 1e-12;
/// Subexpressions whose bound exceeds this are scaled back under it.
const LIMIT: f64 = 4.0;
/// Distance from a singularity every guarded argument keeps.
const MARGIN: f64 = 0.5;

/// The symbols: coordinates `q0.a, q0.b, q1.a, q1.b`, then parameters `h, p`.
const SYMS: [(&str, Sym); 6] = [
    ("q0.a", Sym::Q0(0)),
    ("q0.b", Sym::Q0(1)),
    ("q1.a", Sym::Q1(0)),
    ("q1.b", Sym::Q1(1)),
    ("h", Sym::Param(0)),
    ("p", Sym::Param(1)),
];

/// Where the sample point lies: coordinates in `[−1, 1]`, `h ∈ [0.5, 1.5]`, `p ∈ [−1, 1]`.
const BOX: [(f64, f64); 6] = [
    (-1.0, 1.0),
    (-1.0, 1.0),
    (-1.0, 1.0),
    (-1.0, 1.0),
    (0.5, 1.5),
    (-1.0, 1.0),
];

/// `f64::consts` leaves, rendered as `f64::consts::NAME` or `std::f64::consts::NAME`.
const CONSTS: [(&str, f64); 4] = [
    ("PI", std::f64::consts::PI),
    ("E", std::f64::consts::E),
    ("LN_2", std::f64::consts::LN_2),
    ("FRAC_1_SQRT_2", std::f64::consts::FRAC_1_SQRT_2),
];

/// Declares the functions of one argument from one list of `Variant method` pairs: the enum
/// [`F1`], the list [`F1S`], each one's name as written in a body (the method's) and the oracle,
/// num-dual's method of that name. The functions are named by the fuzzer itself (not by the
/// compiler's [`Fun`](crate::ir::graph::Fun)), so a function lowered under the wrong name is
/// caught.
macro_rules! functions {
    ($($variant:ident $method:ident),* $(,)?) => {
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        enum F1 {
            $($variant),*
        }

        const F1S: &[F1] = &[$(F1::$variant),*];

        impl F1 {
            fn name(self) -> &'static str {
                match self {
                    $(F1::$variant => stringify!($method)),*
                }
            }

            /// The oracle: num-dual's rule for this function.
            fn apply<T: DualNum<Primitive = f64> + Copy>(self, x: T) -> T {
                match self {
                    $(F1::$variant => x.$method()),*
                }
            }
        }
    };
}

functions!(
    Sin sin, Cos cos, Tan tan, Asin asin, Acos acos, Atan atan, Exp exp, Ln ln, Sqrt sqrt,
    Sinh sinh, Cosh cosh, Tanh tanh, Recip recip,
);

impl F1 {
    /// An interval enclosing `f(x)` for `x ∈ r`, `r` already guarded.
    fn range(self, r: Range) -> Range {
        match self {
            F1::Sin | F1::Cos => Range::new(-1.0, 1.0),
            F1::Cosh => Range::new(1.0, r.mag().cosh()),
            // Monotone on the guarded domains (`recip`: on one side of zero).
            _ => r.map(|x| self.apply(x)),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op2 {
    Add,
    Sub,
    Mul,
    Div,
}

impl Op2 {
    fn token(self) -> &'static str {
        match self {
            Op2::Add => "+",
            Op2::Sub => "-",
            Op2::Mul => "*",
            Op2::Div => "/",
        }
    }
}

/// How a call is written: `x.sin()` or `f64::sin(x)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Form {
    Method,
    Path,
}

/// An expression over the body language, raw or guarded: `A` is what an `atan2` node carries
/// and `S` the constant of a [`Guarded`]'s `Square` (uninhabited in a raw [`Expr`]).
#[derive(Clone, Debug)]
enum Tree<A, S> {
    /// `SYMS[i]`.
    Sym(usize),
    Lit(f64),
    /// `CONSTS[i]`.
    Const(usize),
    Neg(Box<Self>),
    Bin(Op2, Box<Self>, Box<Self>),
    Call(F1, Box<Self>, Form),
    Powi(Box<Self>, i32, Form),
    Powf(Box<Self>, Box<Self>, Form),
    /// `y.atan2(x)`.
    Atan2(Box<Self>, Box<Self>, Form, A),
    /// `c + u·u` with `u` bound to a `let`, so nested guards do not double the text.
    Square(S, Box<Self>),
}

/// A raw random expression: what proptest generates and shrinks. An `atan2`'s `true` puts a
/// guarded `x` on the negative side, `y` then kept off zero (quadrant II, or III for a negative
/// `y`); it has no guards.
type Expr = Tree<bool, std::convert::Infallible>;

/// A guarded expression: what is compiled and what the oracle evaluates.
type Guarded = Tree<(), f64>;

fn bx<T>(t: T) -> Box<T> {
    Box::new(t)
}

// ---------------------------------------------------------------------------------------------
// Generation
// ---------------------------------------------------------------------------------------------

fn leaf() -> impl Strategy<Value = Expr> {
    prop_oneof![
        6 => (0..SYMS.len()).prop_map(Expr::Sym),
        // Tenths print and parse back exactly as the value the oracle uses.
        2 => (-30i32..=30).prop_map(|k| Expr::Lit(f64::from(k) / 10.0)),
        1 => (0..CONSTS.len()).prop_map(Expr::Const),
    ]
}

fn form() -> impl Strategy<Value = Form> {
    prop_oneof![3 => Just(Form::Method), 1 => Just(Form::Path)]
}

/// Random expressions of depth at most 8, every operation equally likely at each inner node:
/// about 13 operations in the median tree, 31 at the 95th percentile, each of the 21 about 1400
/// times in [`CASES`] trees.
fn expr() -> impl Strategy<Value = Expr> {
    leaf().prop_recursive(8, 100, 1, |inner| {
        let op2 = prop_oneof![
            Just(Op2::Add),
            Just(Op2::Sub),
            Just(Op2::Mul),
            Just(Op2::Div)
        ];
        prop_oneof![
            1 => inner.clone().prop_map(|a| Expr::Neg(bx(a))),
            4 => (op2, inner.clone(), inner.clone()).prop_map(|(o, a, b)| Expr::Bin(o, bx(a), bx(b))),
            13 => (proptest::sample::select(F1S.to_vec()), inner.clone(), form())
                .prop_map(|(f, a, s)| Expr::Call(f, bx(a), s)),
            1 => (inner.clone(), -3i32..=4, form()).prop_map(|(a, n, s)| Expr::Powi(bx(a), n, s)),
            1 => (inner.clone(), inner.clone(), form())
                .prop_map(|(a, b, s)| Expr::Powf(bx(a), bx(b), s)),
            1 => (inner.clone(), inner, form(), any::<bool>())
                .prop_map(|(y, x, s, neg)| Expr::Atan2(bx(y), bx(x), s, neg)),
        ]
    })
}

/// A sample point in [`BOX`].
fn point() -> impl Strategy<Value = [f64; 6]> {
    (
        [-1.0..=1.0f64, -1.0..=1.0, -1.0..=1.0, -1.0..=1.0],
        0.5..=1.5f64,
        -1.0..=1.0f64,
    )
        .prop_map(|([a, b, c, d], h, p)| [a, b, c, d, h, p])
}

// ---------------------------------------------------------------------------------------------
// Guards
// ---------------------------------------------------------------------------------------------

/// A closed interval enclosing a subexpression's value over [`BOX`] (up to round-off at the
/// ends, which the guards' margins absorb).
#[derive(Clone, Copy, Debug)]
struct Range {
    lo: f64,
    hi: f64,
}

impl Range {
    fn new(lo: f64, hi: f64) -> Self {
        Self { lo, hi }
    }

    fn point(v: f64) -> Self {
        Self::new(v, v)
    }

    fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// The image under a function monotone on the interval.
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        let (a, b) = (f(self.lo), f(self.hi));
        Self::new(a.min(b), a.max(b))
    }

    /// The hull of `f` at the four corners of `self × other`: the image of a function monotone
    /// in each argument (products; `powf` with a positive base).
    fn corners(self, other: Range, f: impl Fn(f64, f64) -> f64) -> Self {
        let v = [
            f(self.lo, other.lo),
            f(self.lo, other.hi),
            f(self.hi, other.lo),
            f(self.hi, other.hi),
        ];
        Self::new(
            v.iter().copied().fold(f64::INFINITY, f64::min),
            v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }

    fn away_from_zero(self) -> bool {
        self.lo >= MARGIN || self.hi <= -MARGIN
    }
}

/// `e · 2^−k` with the least `k ≥ 0` that brings the bound to `max`: exact, so the argument
/// keeps its digits and its derivatives are scaled exactly.
fn scale_to(e: Guarded, r: Range, max: f64) -> (Guarded, Range) {
    let mut s = 1.0;
    while r.mag() * s > max {
        s *= 0.5;
    }
    if s == 1.0 {
        (e, r)
    } else {
        let r = Range::new(r.lo * s, r.hi * s);
        (Guarded::Bin(Op2::Mul, bx(e), bx(Guarded::Lit(s))), r)
    }
}

/// `e` if it is at least [`MARGIN`], else `MARGIN + u·u` with `u` the scaled `e`, `|u| ≤ 2`.
fn positive(e: Guarded, r: Range) -> (Guarded, Range) {
    if r.lo >= MARGIN {
        return (e, r);
    }
    let (u, ru) = scale_to(e, r, 2.0);
    (
        Guarded::Square(MARGIN, bx(u)),
        Range::new(MARGIN, MARGIN + ru.mag() * ru.mag()),
    )
}

/// `e` if it is bounded away from zero, else [`positive`]`(e)`.
fn nonzero(e: Guarded, r: Range) -> (Guarded, Range) {
    if r.away_from_zero() {
        (e, r)
    } else {
        positive(e, r)
    }
}

/// The guarded form of `e` and an interval enclosing its value.
fn guard(e: &Expr) -> (Guarded, Range) {
    let limit = |(g, r): (Guarded, Range)| scale_to(g, r, LIMIT);
    match e {
        Expr::Sym(i) => (Guarded::Sym(*i), Range::new(BOX[*i].0, BOX[*i].1)),
        Expr::Lit(v) => (Guarded::Lit(*v), Range::point(*v)),
        Expr::Const(i) => (Guarded::Const(*i), Range::point(CONSTS[*i].1)),
        Expr::Neg(a) => {
            let (a, r) = guard(a);
            (Guarded::Neg(bx(a)), Range::new(-r.hi, -r.lo))
        }
        Expr::Bin(op, a, b) => {
            let (a, ra) = guard(a);
            let (b, rb) = guard(b);
            let (b, rb) = if *op == Op2::Div {
                nonzero(b, rb)
            } else {
                (b, rb)
            };
            let r = match op {
                Op2::Add => Range::new(ra.lo + rb.lo, ra.hi + rb.hi),
                Op2::Sub => Range::new(ra.lo - rb.hi, ra.hi - rb.lo),
                Op2::Mul => ra.corners(rb, |x, y| x * y),
                Op2::Div => ra.corners(rb, |x, y| x / y),
            };
            limit((Guarded::Bin(*op, bx(a), bx(b)), r))
        }
        Expr::Call(f, a, form) => {
            let (a, ra) = guard(a);
            let (a, ra) = match f {
                F1::Tan => scale_to(a, ra, 1.0),
                F1::Asin | F1::Acos => scale_to(a, ra, 0.75),
                // `tanh` for round-off, not range: see the module documentation.
                F1::Exp | F1::Sinh | F1::Cosh | F1::Tanh => scale_to(a, ra, 2.0),
                F1::Ln | F1::Sqrt => positive(a, ra),
                F1::Recip => nonzero(a, ra),
                F1::Sin | F1::Cos | F1::Atan => (a, ra),
            };
            let r = f.range(ra);
            limit((Guarded::Call(*f, bx(a), *form), r))
        }
        Expr::Powi(a, n, form) => {
            let (a, ra) = guard(a);
            let (a, ra) = if *n < 0 {
                nonzero(a, ra)
            } else {
                // |a|^n ≤ LIMIT.
                let max = LIMIT.powf(1.0 / f64::from((*n).max(1)));
                scale_to(a, ra, max)
            };
            let r = if *n == 0 {
                Range::point(1.0)
            } else if *n > 0 && n % 2 == 0 && ra.lo < 0.0 && ra.hi > 0.0 {
                Range::new(0.0, ra.mag().powi(*n))
            } else {
                // Odd powers are increasing; the interval of a negative or even power is on one
                // side of zero, where the power is monotone.
                ra.map(|x| x.powi(*n))
            };
            limit((Guarded::Powi(bx(a), *n, *form), r))
        }
        Expr::Powf(a, b, form) => {
            let (a, ra) = guard(a);
            let (a, ra) = positive(a, ra);
            let (b, rb) = guard(b);
            let (b, rb) = scale_to(b, rb, 2.0);
            let r = ra.corners(rb, f64::powf);
            limit((Guarded::Powf(bx(a), bx(b), *form), r))
        }
        Expr::Atan2(y, x, form, negative) => {
            let (y, ry) = guard(y);
            let (x, rx) = guard(x);
            // Off the origin, and off the branch cut (the negative x axis), where the value jumps
            // by 2π: x ≥ MARGIN, or |x| ≥ MARGIN and |y| ≥ MARGIN.
            let (y, x) = if rx.lo >= MARGIN {
                (y, x)
            } else if rx.hi <= -MARGIN {
                (nonzero(y, ry).0, x)
            } else if *negative {
                (nonzero(y, ry).0, Guarded::Neg(bx(positive(x, rx).0)))
            } else {
                (y, positive(x, rx).0)
            };
            let pi = std::f64::consts::PI;
            (Guarded::Atan2(bx(y), bx(x), *form, ()), Range::new(-pi, pi))
        }
        Expr::Square(never, _) => match *never {},
    }
}

// ---------------------------------------------------------------------------------------------
// Rendering, compiling, and the oracle
// ---------------------------------------------------------------------------------------------

/// Renders `g` as Rust source, pushing the `let` bindings of [`Tree::Square`] onto `lets`.
fn render(g: &Guarded, lets: &mut Vec<String>) -> String {
    let call = |name: &str, form: Form, receiver: String, args: &[String]| match form {
        Form::Method => format!("{receiver}.{name}({})", args.join(", ")),
        Form::Path => {
            let all: Vec<String> = std::iter::once(receiver)
                .chain(args.iter().cloned())
                .collect();
            format!("f64::{name}({})", all.join(", "))
        }
    };
    match g {
        Guarded::Sym(i) => SYMS[*i].0.to_string(),
        Guarded::Lit(v) if v.is_sign_negative() => format!("({v:?})"),
        Guarded::Lit(v) => format!("{v:?}"),
        Guarded::Const(i) if i % 2 == 0 => format!("std::f64::consts::{}", CONSTS[*i].0),
        Guarded::Const(i) => format!("f64::consts::{}", CONSTS[*i].0),
        Guarded::Neg(a) => format!("(-{})", render(a, lets)),
        Guarded::Bin(op, a, b) => {
            let (a, b) = (render(a, lets), render(b, lets));
            format!("({a} {} {b})", op.token())
        }
        Guarded::Call(f, a, form) => call(f.name(), *form, render(a, lets), &[]),
        Guarded::Powi(a, n, form) => call("powi", *form, render(a, lets), &[n.to_string()]),
        Guarded::Powf(a, b, form) => {
            let a = render(a, lets);
            call("powf", *form, a, &[render(b, lets)])
        }
        Guarded::Atan2(y, x, form, ()) => {
            let y = render(y, lets);
            call("atan2", *form, y, &[render(x, lets)])
        }
        Guarded::Square(c, u) => {
            let u = render(u, lets);
            let name = format!("t{}", lets.len());
            lets.push(format!("let {name} = {u};"));
            format!("({c:?} + {name} * {name})")
        }
    }
}

/// The body `{ let t0 = …; …; expr }` of a discrete Lagrangian computing `g`.
fn source(g: &Guarded) -> String {
    let mut lets = Vec::new();
    let e = render(g, &mut lets);
    let mut out = String::from("{\n");
    for l in &lets {
        let _ = writeln!(out, "    {l}");
    }
    let _ = write!(out, "    {e}\n}}");
    out
}

fn has_sym(g: &Guarded) -> bool {
    match g {
        Guarded::Sym(_) => true,
        Guarded::Lit(_) | Guarded::Const(_) => false,
        Guarded::Neg(a)
        | Guarded::Call(_, a, _)
        | Guarded::Powi(a, _, _)
        | Guarded::Square(_, a) => has_sym(a),
        Guarded::Bin(_, a, b) | Guarded::Powf(a, b, _) | Guarded::Atan2(a, b, _, ()) => {
            has_sym(a) || has_sym(b)
        }
    }
}

/// The oracle: `g` on num-dual numbers (or plain `f64`), at `syms`.
fn value<T: DualNum<Primitive = f64> + Copy>(g: &Guarded, syms: &[T; 6]) -> T {
    let v = |e: &Guarded| value(e, syms);
    match g {
        Guarded::Sym(i) => syms[*i],
        Guarded::Lit(c) => T::from(*c),
        Guarded::Const(i) => T::from(CONSTS[*i].1),
        Guarded::Neg(a) => -v(a),
        Guarded::Bin(op, a, b) => {
            let (a, b) = (v(a), v(b));
            match op {
                Op2::Add => a + b,
                Op2::Sub => a - b,
                Op2::Mul => a * b,
                Op2::Div => a / b,
            }
        }
        Guarded::Call(f, a, _) => f.apply(v(a)),
        Guarded::Powi(a, n, _) => v(a).powi(*n),
        // num-dual's `powf` takes a primitive exponent; a dual one is `powd`.
        Guarded::Powf(a, b, _) if has_sym(b) => v(a).powd(v(b)),
        Guarded::Powf(a, b, _) => v(a).powf(value::<f64>(b, &[0.0; 6])),
        Guarded::Atan2(y, x, _, ()) => v(y).atan2(v(x)),
        Guarded::Square(c, u) => {
            let u = v(u);
            T::from(*c) + u * u
        }
    }
}

/// What the compiler made of a body: its value, gradient and Hessian at a point.
struct Compiled {
    value: f64,
    gradient: [f64; 6],
    /// `hessian[i][j] = ∂/∂s_j (∂f/∂s_i)`.
    hessian: [[f64; 6]; 6],
}

/// Parses and lowers `src`, differentiates the graph twice and evaluates at `at`. Returns the
/// values and, in the same shape, their scales: the largest magnitude among each value and the
/// intermediate values it is computed from.
/// The gradient comes from one forward pass per symbol or, with `reverse`, from one reverse
/// sweep ([`gradient`]); the Hessian is forward passes over the gradient either way.
fn compile(src: &str, at: &[f64; 6], reverse: bool) -> Result<(Compiled, Compiled), String> {
    let block: syn::Block = syn::parse_str(src).map_err(|e| format!("syn: {e}"))?;
    let (q0, q1) = (
        Ident::new("q0", Span::call_site()),
        Ident::new("q1", Span::call_site()),
    );
    let names = Names {
        q0: &q0,
        q1: &q1,
        coords: CoordName::scalars(["a".to_string(), "b".to_string()]),
        params: vec!["h".into(), "p".into()],
        dq: Vec::new(),
    };
    let cx = Ctxt::new();
    let mut g = Graph::default();
    let root = Lowering::new(&mut g, &cx, &names).body(&block);
    let root = cx
        .finish(root)
        .map_err(|e| format!("lowering rejected the body: {e}"))?;
    let syms: Vec<Sym> = SYMS.iter().map(|&(_, s)| s).collect();
    let first: Vec<_> = if reverse {
        gradient(&mut g, root, &syms)
    } else {
        syms.iter()
            .map(|&s| derivatives(&mut g, &[root], s)[0])
            .collect()
    };
    // second[j][i] = ∂/∂s_j of first[i].
    let second: Vec<Vec<_>> = SYMS
        .iter()
        .map(|&(_, s)| derivatives(&mut g, &first, s))
        .collect();
    let mut roots = vec![root];
    roots.extend(&first);
    roots.extend(second.iter().flatten());
    let sym = |s: Sym| {
        let i = SYMS.iter().position(|&(_, t)| t == s);
        at[i.expect("only the fuzzer's symbols appear")]
    };
    let cone = g.cone(&roots);
    let values = g.eval(&cone, &sym);
    // The cone is in topological order, so children are scaled before their parents.
    let mut scale: HashMap<NodeId, f64> = HashMap::new();
    for (&id, &v) in cone.iter().zip(&values) {
        let s = g
            .node(id)
            .children()
            .map(|c| scale[&c])
            .fold(v.abs(), f64::max);
        scale.insert(id, s);
    }
    let value: HashMap<NodeId, f64> = cone.iter().copied().zip(values).collect();
    let shaped = |m: &HashMap<NodeId, f64>| Compiled {
        value: m[&root],
        gradient: std::array::from_fn(|i| m[&first[i]]),
        hessian: std::array::from_fn(|i| std::array::from_fn(|j| m[&second[j][i]])),
    };
    Ok((shaped(&value), shaped(&scale)))
}

/// The oracle's value, gradient and Hessian: one hyper-dual evaluation per pair `(i, j)`, seeding
/// `ε₁` on `s_i` and `ε₂` on `s_j`.
fn reference(g: &Guarded, at: &[f64; 6]) -> Compiled {
    let mut out = Compiled {
        value: 0.0,
        gradient: [0.0; 6],
        hessian: [[0.0; 6]; 6],
    };
    for i in 0..6 {
        for j in 0..6 {
            let syms: [HyperDual64; 6] = std::array::from_fn(|k| {
                let seed = |on: usize| if k == on { 1.0 } else { 0.0 };
                HyperDual64::new(at[k], seed(i), seed(j), 0.0)
            });
            let r = value(g, &syms);
            if (i, j) == (0, 0) {
                out.value = r.re;
            }
            if i == j {
                out.gradient[i] = r.eps1;
            }
            out.hessian[i][j] = r.eps1eps2;
        }
    }
    out
}

/// Every mismatch beyond [`TOL`], and the largest differences seen, scaled by
/// `max(1, |a|, |b|)` and by `max(1, |a|, |b|, scale)`.
fn compare(got: &Compiled, scale: &Compiled, want: &Compiled) -> (Vec<String>, f64, f64) {
    let mut entries = vec![("f".to_string(), got.value, scale.value, want.value)];
    for (i, (si, _)) in SYMS.iter().enumerate() {
        let d = (got.gradient[i], scale.gradient[i], want.gradient[i]);
        entries.push((format!("∂f/∂{si}"), d.0, d.1, d.2));
        for (j, (sj, _)) in SYMS.iter().enumerate() {
            let d = (got.hessian[i][j], scale.hessian[i][j], want.hessian[i][j]);
            entries.push((format!("∂²f/∂{si}∂{sj}"), d.0, d.1, d.2));
        }
    }
    let (mut worst_strict, mut worst) = (0.0f64, 0.0f64);
    let mut failures = Vec::new();
    for (what, a, s, b) in entries {
        let strict = (a - b).abs() / 1f64.max(a.abs()).max(b.abs());
        let scaled = (a - b).abs() / 1f64.max(a.abs()).max(b.abs()).max(s);
        worst_strict = worst_strict.max(strict);
        worst = worst.max(scaled);
        if !(a.is_finite() && b.is_finite() && scaled <= TOL) {
            failures.push(format!(
                "{what}: compiled {a:e}, num-dual {b:e}, scale {s:e}, scaled difference {scaled:e}"
            ));
        }
    }
    (failures, worst_strict, worst)
}

/// Prints each new largest difference, by either scaling (shown with `--nocapture`): the margin
/// under [`TOL`] the tolerance is justified by.
fn report_worst(strict: f64, scaled: f64, src: &str, at: &[f64; 6]) {
    static WORST: std::sync::Mutex<(f64, f64)> = std::sync::Mutex::new((0.0, 0.0));
    let mut worst = WORST.lock().unwrap_or_else(|e| e.into_inner());
    if strict > worst.0 || scaled > worst.1 {
        *worst = (worst.0.max(strict), worst.1.max(scaled));
        eprintln!(
            "largest differences so far: {:e} by max(1, |a|, |b|), {:e} with the scale, at \
             {at:?}:\n{src}",
            worst.0, worst.1
        );
    }
}

fn config() -> ProptestConfig {
    ProptestConfig {
        // `ProptestConfig::default()` reads `PROPTEST_CASES`; never run fewer than CASES.
        cases: ProptestConfig::default().cases.max(CASES),
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// The compiler's value, gradient and Hessian of a random expression equal num-dual's, with
    /// the gradient by forward passes and by reverse accumulation (forward over reverse).
    #[test]
    fn derivatives_match_num_dual(e in expr(), at in point()) {
        let (g, _) = guard(&e);
        let src = source(&g);
        let want = reference(&g, &at);
        for reverse in [false, true] {
            let got = compile(&src, &at, reverse);
            prop_assert!(got.is_ok(), "{}\nbody:\n{src}", got.err().unwrap_or_default());
            let (got, scale) = got.expect("checked");
            let (failures, strict, scaled) = compare(&got, &scale, &want);
            report_worst(strict, scaled, &src, &at);
            prop_assert!(
                failures.is_empty(),
                "{} mismatches (reverse: {reverse}) at (q0.a, q0.b, q1.a, q1.b, h, p) = {at:?}:\n  {}\nbody:\n{src}",
                failures.len(),
                failures.join("\n  ")
            );
        }
    }
}

/// Counts each operation of the body language in `e`.
fn count(e: &Expr, counts: &mut std::collections::BTreeMap<String, usize>) {
    let mut add = |k: &str| *counts.entry(k.to_string()).or_default() += 1;
    match e {
        Expr::Sym(_) | Expr::Lit(_) | Expr::Const(_) => {}
        Expr::Neg(a) => {
            add("neg");
            count(a, counts);
        }
        Expr::Bin(op, a, b) => {
            add(op.token());
            count(a, counts);
            count(b, counts);
        }
        Expr::Call(f, a, form) => {
            add(f.name());
            add(&format!("{form:?}"));
            count(a, counts);
        }
        Expr::Powi(a, _, form) => {
            add("powi");
            add(&format!("{form:?}"));
            count(a, counts);
        }
        Expr::Powf(a, b, form) | Expr::Atan2(a, b, form, _) => {
            add(if matches!(e, Expr::Powf(..)) {
                "powf"
            } else {
                "atan2"
            });
            add(&format!("{form:?}"));
            count(a, counts);
            count(b, counts);
        }
        Expr::Square(never, _) => match *never {},
    }
}

/// [`CASES`] trees of the generator use every operation of the body language many times, in
/// both call forms.
#[test]
fn the_generator_covers_every_operation() {
    let mut runner = TestRunner::deterministic();
    let strategy = expr();
    let mut counts = std::collections::BTreeMap::new();
    for _ in 0..CASES {
        let e = strategy
            .new_tree(&mut runner)
            .expect("the strategy never rejects")
            .current();
        count(&e, &mut counts);
    }
    let ops = F1S.iter().map(|f| f.name()).chain([
        "powi", "powf", "atan2", "+", "-", "*", "/", "neg", "Method", "Path",
    ]);
    for op in ops {
        let n = counts.get(op).copied().unwrap_or(0);
        assert!(
            n >= 1000,
            "`{op}` appears {n} times in {CASES} trees: {counts:?}"
        );
    }
}

/// Guards keep every argument where its operation is well conditioned, whatever the raw tree.
#[test]
fn guarded_arguments_stay_in_their_domains() {
    let mut runner = TestRunner::deterministic();
    let strategy = (expr(), point());
    for _ in 0..CASES {
        let (e, at) = strategy
            .new_tree(&mut runner)
            .expect("the strategy never rejects")
            .current();
        let (g, range) = guard(&e);
        let v = value::<f64>(&g, &at);
        assert!(
            range.lo - 1e-9 <= v && v <= range.hi + 1e-9,
            "{v} outside {range:?}: {}",
            source(&g)
        );
        check_domains(&g, &at);
    }
}

fn check_domains(g: &Guarded, at: &[f64; 6]) {
    let v = |e: &Guarded| value::<f64>(e, at);
    // The guards decide on intervals whose ends may be off by an ulp.
    let m = MARGIN - 1e-12;
    let ok = match g {
        Guarded::Call(F1::Ln | F1::Sqrt, a, _) | Guarded::Powf(a, _, _) => v(a) >= m,
        Guarded::Call(F1::Recip, a, _) | Guarded::Bin(Op2::Div, _, a) => v(a).abs() >= m,
        Guarded::Atan2(y, x, _, ()) => v(x) >= m || (v(x) <= -m && v(y).abs() >= m),
        Guarded::Powi(a, n, _) if *n < 0 => v(a).abs() >= m,
        Guarded::Call(F1::Asin | F1::Acos, a, _) => v(a).abs() <= 0.75,
        Guarded::Call(F1::Tan, a, _) => v(a).abs() <= 1.0,
        _ => true,
    };
    assert!(ok, "argument out of its domain in {}", source(g));
    // Before a scaling guard: at most 4.5², a power or a product of two guarded values.
    assert!(v(g).abs() <= 20.25 + 1e-9, "{} = {}", source(g), v(g));
    match g {
        Guarded::Sym(_) | Guarded::Lit(_) | Guarded::Const(_) => {}
        Guarded::Neg(a)
        | Guarded::Call(_, a, _)
        | Guarded::Powi(a, _, _)
        | Guarded::Square(_, a) => check_domains(a, at),
        Guarded::Bin(_, a, b) | Guarded::Powf(a, b, _) | Guarded::Atan2(a, b, _, ()) => {
            check_domains(a, at);
            check_domains(b, at);
        }
    }
}
