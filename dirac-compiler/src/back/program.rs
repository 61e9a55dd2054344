//! Graph → straight-line program as data: the second back end of the compiler, beside
//! the Rust tokens of the attribute's code generator. A [`Program`] is the same straight line the Rust back end
//! emits (each live operation once, in the graph's topological order, leaves read where they are
//! used, constants inlined), so a run-time code generator that translates it operation by
//! operation rounds exactly as the compiled-in system does.

use rustc_hash::FxHashMap as HashMap;

pub use crate::ir::graph::Fun;
use crate::ir::graph::{Graph, Node, NodeId, Sym};

/// What a leaf of a [`Program`] reads. Which argument of a function each leaf is depends on the
/// function; the names follow the paper and the runtime's traits (`dirac_runtime::system`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Leaf {
    /// `q0[i]`: the first point of `L_d`, or `q_k` in the unreduced step.
    Q0(usize),
    /// `q1[i]`: the second point of `L_d`, or the unknown `z = q_{k+1}` of the unreduced step.
    Q1(usize),
    /// `x0[i]`: the shape at the start of a reduced step, `x_k`.
    X0(usize),
    /// `x1[i]`: the shape unknown `x_{k+1}` of a reduced step (`z[i]`).
    X1(usize),
    /// The group unknown `u[j]` of a reduced step: `g_k^+` for (+), `g_{k+1}^−` for (−)
    /// (`z[S + j]`).
    U(usize),
    /// The canonical momentum `p_k[i]` of the unreduced step.
    P(usize),
    /// The reduced shape momentum `w_k[i]`.
    W(usize),
    /// The group momentum `μ_k[j]`.
    Mu(usize),
    /// Parameter `i`, in declaration order.
    Param(usize),
    /// The Lagrange multiplier `λ_k[j]` of a constrained position step, or `ν_{k+1}[j]` of its
    /// projection (the unknowns after the configuration or velocity: `z[N + j]`).
    Lambda(usize),
    /// Entry `i` of the stored point `q_k` at the centre of the chart of a step on rotation
    /// groups (rotations and directions 9 entries each, row by row).
    Base(usize),
    /// Chart coordinate `j` of the next point of a step on rotation groups: the step's unknown
    /// `z`, `q_{k+1} = φ_{q_k}(z)`.
    Chart(usize),
}

/// One operation of a [`Program`]; operands are indices of earlier operations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// Reads a leaf.
    Leaf(Leaf),
    /// A constant.
    Const(f64),
    /// `−a`.
    Neg(u32),
    /// `a + b`.
    Add(u32, u32),
    /// `a − b`.
    Sub(u32, u32),
    /// `a · b`.
    Mul(u32, u32),
    /// `a / b`.
    Div(u32, u32),
    /// `f(a)`, with Rust's `f64` method of that name.
    Fun(Fun, u32),
    /// `a.powi(n)`.
    Powi(u32, i32),
    /// `a.powf(b)`.
    Powf(u32, u32),
    /// `y.atan2(x)`.
    Atan2(u32, u32),
}

/// A straight-line function: operations in evaluation order, and the operations whose values it
/// returns, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    /// The operations; each reads only earlier ones.
    pub ops: Vec<Op>,
    /// The returned values, as indices into [`Self::ops`].
    pub outputs: Vec<u32>,
}

impl Program {
    /// The operations that are arithmetic or function calls (not leaves or constants): the size
    /// of the straight line.
    pub fn operations(&self) -> usize {
        self.ops
            .iter()
            .filter(|op| !matches!(op, Op::Leaf(_) | Op::Const(_)))
            .count()
    }

    /// The leaves the program reads.
    pub fn leaves(&self) -> impl Iterator<Item = Leaf> + '_ {
        self.ops.iter().filter_map(|op| match op {
            Op::Leaf(l) => Some(*l),
            _ => None,
        })
    }

    /// Evaluates the program with `leaf` reading the leaves: a reference for tests of code
    /// generated from it, with Rust's own `f64` operations.
    pub fn eval(&self, leaf: &dyn Fn(Leaf) -> f64) -> Vec<f64> {
        let mut v: Vec<f64> = Vec::with_capacity(self.ops.len());
        for op in &self.ops {
            let a = |i: u32| v[i as usize];
            let x = match *op {
                Op::Leaf(l) => leaf(l),
                Op::Const(c) => c,
                Op::Neg(x) => -a(x),
                Op::Add(x, y) => a(x) + a(y),
                Op::Sub(x, y) => a(x) - a(y),
                Op::Mul(x, y) => a(x) * a(y),
                Op::Div(x, y) => a(x) / a(y),
                Op::Fun(f, x) => f.eval(a(x)),
                Op::Powi(x, n) => a(x).powi(n),
                Op::Powf(x, y) => a(x).powf(a(y)),
                Op::Atan2(y, x) => a(y).atan2(a(x)),
            };
            v.push(x);
        }
        self.outputs.iter().map(|&o| v[o as usize]).collect()
    }
}

/// The program computing `outputs` of `g`, every symbol read as [`leaf`] maps it. A symbol the
/// map does not know is a bug of the compiler (a function reading what its kind cannot read).
pub(crate) fn program(g: &Graph, outputs: &[NodeId]) -> Program {
    let mut index: HashMap<NodeId, u32> = HashMap::default();
    let mut ops = Vec::new();
    for id in g.cone(outputs) {
        let i = |n: NodeId| index[&n];
        let op = match g.node(id) {
            Node::Const(bits) => Op::Const(f64::from_bits(bits)),
            Node::Var(sym) => Op::Leaf(leaf(sym)),
            Node::Neg(a) => Op::Neg(i(a)),
            Node::Add(a, b) => Op::Add(i(a), i(b)),
            Node::Sub(a, b) => Op::Sub(i(a), i(b)),
            Node::Mul(a, b) => Op::Mul(i(a), i(b)),
            Node::Div(a, b) => Op::Div(i(a), i(b)),
            Node::Fun(f, a) => Op::Fun(f, i(a)),
            Node::Powi(a, n) => Op::Powi(i(a), n),
            Node::Powf(a, b) => Op::Powf(i(a), i(b)),
            Node::Atan2(y, x) => Op::Atan2(i(y), i(x)),
        };
        index.insert(id, ops.len() as u32);
        ops.push(op);
    }
    Program {
        outputs: outputs.iter().map(|o| index[o]).collect(),
        ops,
    }
}

/// The leaf a symbol of the compiled functions is: both reduced group unknowns are `U`.
fn leaf(sym: Sym) -> Leaf {
    match sym {
        Sym::Q0(i) => Leaf::Q0(i),
        Sym::Q1(i) => Leaf::Q1(i),
        Sym::X0(i) => Leaf::X0(i),
        Sym::X1(i) => Leaf::X1(i),
        Sym::G0(j) | Sym::G1(j) => Leaf::U(j),
        Sym::P(i) => Leaf::P(i),
        Sym::W(i) => Leaf::W(i),
        Sym::Mu(j) => Leaf::Mu(j),
        Sym::Param(i) => Leaf::Param(i),
        Sym::Lambda(j) => Leaf::Lambda(j),
        Sym::Base(i) => Leaf::Base(i),
        Sym::Chart1(j) => Leaf::Chart(j),
        other => unreachable!("the compiled functions do not read {other:?}"),
    }
}
