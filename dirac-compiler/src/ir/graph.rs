//! Hash-consed expression graph: equal subexpressions are one node, so common subexpressions are
//! shared by construction. The constructors fold constants and apply exact algebraic identities
//! (`x + 0`, `x · 1`, `x · 0`, `−(−x)`, `x − x`, …); they never reassociate, so the emitted code
//! rounds exactly as the expression the user wrote (up to these identities).
//!
//! One identity changes the rounding, always for the better: a difference of two sums with a
//! common term drops the term (`(a + b) − a = b`, [`Graph::sub`]). It is what keeps a chart
//! increment exact where a step's points are `x + z`: see [`Graph::sub`].

use rustc_hash::FxHashMap as HashMap;

/// Index of a node; children always have smaller indices than their parents, so index order is
/// a topological order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

/// The symbols an expression can read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sym {
    /// Coordinate `i` of `q0` (shape first, then group).
    Q0(usize),
    /// Coordinate `i` of `q1`.
    Q1(usize),
    /// Shape coordinate `i` of `x0` (reduced Lagrangian, eq. (4.5)).
    X0(usize),
    /// Shape coordinate `i` of `x1`.
    X1(usize),
    /// Group coordinate `j` of `g1` (reduced (+) Lagrangian).
    G1(usize),
    /// Group coordinate `j` of `g0` (reduced (−) Lagrangian, eq. (4.7)).
    G0(usize),
    /// Canonical momentum `p_k[i]` (unreduced equations, Definition 2.7).
    P(usize),
    /// Reduced shape momentum `w_k[i]` (eq. (4.6)).
    W(usize),
    /// Group momentum `μ_k[j]` (eq. (4.6)).
    Mu(usize),
    /// Scalar parameter `i`.
    Param(usize),
    /// Component `i` of the virtual displacement `δq0` in a force's virtual work (`δq` for a
    /// continuous Lagrangian); gone after differentiation ([`crate::ir::force`]).
    D0(usize),
    /// Component `i` of the virtual displacement `δq1` in a discrete force's virtual work.
    D1(usize),
    /// Lagrange multiplier `i` of the holonomic constraints ([`crate::ir::constraint`]).
    Lambda(usize),
    /// Entry `i` of the stored point `q_k` at the centre of a step's chart (rotation and
    /// direction coordinates, [`crate::ir::lie`]).
    Base(usize),
    /// Chart coordinate `j` of the point being varied: `q_k` in the residual, `q_{k+1}` in the
    /// momentum update (differentiated, then zero).
    Chart0(usize),
    /// Chart coordinate `j` of `q_{k+1}`: the step's unknown `z`.
    Chart1(usize),
    /// Entry `i` of the stored point of a rotation coordinate standing for the relative rotation
    /// `F = R0ᵀ R1` (`i` runs over the coordinate's 9 point entries, row by row): what
    /// `q0.R.transpose() * q1.R` lowers to ([`crate::ir::lie`] substitutes the step's own
    /// `cay(ξ0)ᵀ cay(z)`).
    Rel(usize),
}

/// Elementary functions of one argument, each Rust's `f64` method of the same name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fun {
    /// `sin`.
    Sin,
    /// `cos`.
    Cos,
    /// `tan`.
    Tan,
    /// `asin`.
    Asin,
    /// `acos`.
    Acos,
    /// `atan`.
    Atan,
    /// `exp`.
    Exp,
    /// `ln` (the natural logarithm).
    Ln,
    /// `sqrt`.
    Sqrt,
    /// `sinh`.
    Sinh,
    /// `cosh`.
    Cosh,
    /// `tanh`.
    Tanh,
    /// `recip`, `1 / x`.
    Recip,
}

impl Fun {
    /// The name of the `f64` method, as written in a body.
    pub fn name(self) -> &'static str {
        match self {
            Fun::Sin => "sin",
            Fun::Cos => "cos",
            Fun::Tan => "tan",
            Fun::Asin => "asin",
            Fun::Acos => "acos",
            Fun::Atan => "atan",
            Fun::Exp => "exp",
            Fun::Ln => "ln",
            Fun::Sqrt => "sqrt",
            Fun::Sinh => "sinh",
            Fun::Cosh => "cosh",
            Fun::Tanh => "tanh",
            Fun::Recip => "recip",
        }
    }

    /// The function a method name in a body calls, if it is one of these.
    pub fn from_name(name: &str) -> Option<Fun> {
        Some(match name {
            "sin" => Fun::Sin,
            "cos" => Fun::Cos,
            "tan" => Fun::Tan,
            "asin" => Fun::Asin,
            "acos" => Fun::Acos,
            "atan" => Fun::Atan,
            "exp" => Fun::Exp,
            "ln" => Fun::Ln,
            "sqrt" => Fun::Sqrt,
            "sinh" => Fun::Sinh,
            "cosh" => Fun::Cosh,
            "tanh" => Fun::Tanh,
            "recip" => Fun::Recip,
            _ => return None,
        })
    }

    /// The value at `v`, by Rust's `f64` method.
    pub fn eval(self, v: f64) -> f64 {
        match self {
            Fun::Sin => v.sin(),
            Fun::Cos => v.cos(),
            Fun::Tan => v.tan(),
            Fun::Asin => v.asin(),
            Fun::Acos => v.acos(),
            Fun::Atan => v.atan(),
            Fun::Exp => v.exp(),
            Fun::Ln => v.ln(),
            Fun::Sqrt => v.sqrt(),
            Fun::Sinh => v.sinh(),
            Fun::Cosh => v.cosh(),
            Fun::Tanh => v.tanh(),
            Fun::Recip => v.recip(),
        }
    }
}

/// A node of the graph. Constants are stored by bit pattern so nodes can be hashed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    Const(u64),
    Var(Sym),
    Neg(NodeId),
    Add(NodeId, NodeId),
    Sub(NodeId, NodeId),
    Mul(NodeId, NodeId),
    Div(NodeId, NodeId),
    Fun(Fun, NodeId),
    Powi(NodeId, i32),
    Powf(NodeId, NodeId),
    Atan2(NodeId, NodeId),
}

impl Node {
    /// The children of this node.
    pub fn children(&self) -> impl Iterator<Item = NodeId> {
        let (a, b) = match *self {
            Node::Const(_) | Node::Var(_) => (None, None),
            Node::Neg(a) | Node::Fun(_, a) | Node::Powi(a, _) => (Some(a), None),
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Powf(a, b)
            | Node::Atan2(a, b) => (Some(a), Some(b)),
        };
        a.into_iter().chain(b)
    }
}

/// The arena.
#[derive(Default)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, NodeId>,
}

impl Graph {
    pub fn node(&self, id: NodeId) -> Node {
        self.nodes[id.0 as usize]
    }

    fn intern(&mut self, node: Node) -> NodeId {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(node);
        self.index.insert(node, id);
        id
    }

    pub fn constant(&mut self, v: f64) -> NodeId {
        // One zero: −0.0 and 0.0 behave alike in every expression built here except 1/±0, which
        // never survives as a finite result anyway.
        let v = if v == 0.0 { 0.0 } else { v };
        self.intern(Node::Const(v.to_bits()))
    }

    pub fn var(&mut self, sym: Sym) -> NodeId {
        self.intern(Node::Var(sym))
    }

    /// The constant value of a node, if it is one.
    pub fn as_const(&self, id: NodeId) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    pub fn neg(&mut self, a: NodeId) -> NodeId {
        if let Some(v) = self.as_const(a) {
            return self.constant(-v);
        }
        if let Node::Neg(inner) = self.node(a) {
            return inner;
        }
        self.intern(Node::Neg(a))
    }

    pub fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x + y),
            (Some(0.0), _) => return b,
            (_, Some(0.0)) => return a,
            _ => {}
        }
        // x + (−x) = 0 and c·x + (−c)·x = 0, exactly: the two terms are exact negatives.
        if self.is_negation_of(a, b) {
            return self.constant(0.0);
        }
        // a + (−b) = a − b, exactly.
        if let Node::Neg(nb) = self.node(b) {
            return self.sub(a, nb);
        }
        if let Node::Neg(na) = self.node(a) {
            return self.sub(b, na);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(a, b))
    }

    /// Whether `b` is structurally the exact negation of `a`: `−a`, or `(−c)·x` for `a = c·x`.
    fn is_negation_of(&self, a: NodeId, b: NodeId) -> bool {
        if self.node(b) == Node::Neg(a) || self.node(a) == Node::Neg(b) {
            return true;
        }
        let scaled = |n: NodeId| match self.node(n) {
            Node::Mul(p, q) => match (self.as_const(p), self.as_const(q)) {
                (Some(c), None) => Some((c, q)),
                (None, Some(c)) => Some((c, p)),
                _ => None,
            },
            _ => None,
        };
        matches!((scaled(a), scaled(b)), (Some((ca, xa)), Some((cb, xb))) if xa == xb && ca == -cb)
    }

    /// `a − b`, with `x − 0 = x`, `0 − x = −x`, `x − x = 0`, `a − (−b) = a + b`, and a common term
    /// of two sums cancelled:
    ///
    /// ```text
    /// (a + b) − a = b,     a − (a + b) = −b,     (a + b) − (a + c) = b − c.
    /// ```
    ///
    /// These hold in real arithmetic. In floating point they remove a cancellation: `a + b`
    /// rounds at `|a|`, so `(a + b) − a` evaluated as written is `b` with an error up to
    /// `ε |a|`, and `b` is exact. This is where they apply: in a step on charts
    /// ([`crate::ir::lie`]) the next point of a translation is `φ_x(z) = x + z` (a scalar's, a
    /// pose's position), so in the chart Lagrangian `L̃(ξ, z) = L_d(φ_x(ξ), φ_x(z))` the body's
    /// `q1.x − q0.x` is `(x + z) − (x + ξ)`, which is `z − ξ` (and `z` once `ξ = 0`, the centre
    /// of the chart where the residual, its Jacobian, the momentum update and the
    /// sensitivities are evaluated). Computed as written, the residual `m (x1 − x0)/h − p_k`
    /// would have a floor of `ε |x| m/h` — the position's size, not the momentum's — and Newton
    /// would stop converging once the body is far enough from the origin; with the increment
    /// itself it is at the round-off of the momenta, wherever the body is. The same holds for
    /// the velocity `(x1 − x0)/h` of a continuous Lagrangian ([`crate::ir::group::Step::chord`])
    /// and for a force that reads the difference.
    pub fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x - y),
            (Some(0.0), _) => return self.neg(b),
            (_, Some(0.0)) => return a,
            _ => {}
        }
        if a == b {
            return self.constant(0.0);
        }
        if let Node::Neg(nb) = self.node(b) {
            return self.add(a, nb);
        }
        if let Some(d) = self.common_term_cancelled(a, b) {
            return d;
        }
        self.intern(Node::Sub(a, b))
    }

    /// The two terms of a sum node.
    fn terms(&self, id: NodeId) -> Option<[NodeId; 2]> {
        match self.node(id) {
            Node::Add(p, q) => Some([p, q]),
            _ => None,
        }
    }

    /// `a − b` with the common term of `a` and `b` cancelled, if one is a sum containing the
    /// other or both are sums sharing a term ([`Self::sub`]).
    fn common_term_cancelled(&mut self, a: NodeId, b: NodeId) -> Option<NodeId> {
        match (self.terms(a), self.terms(b)) {
            (Some([p, q]), _) if p == b => Some(q),
            (Some([p, q]), _) if q == b => Some(p),
            (_, Some([r, s])) if r == a => Some(self.neg(s)),
            (_, Some([r, s])) if s == a => Some(self.neg(r)),
            (Some([p, q]), Some([r, s])) => {
                let (x, y) = if p == r {
                    (q, s)
                } else if p == s {
                    (q, r)
                } else if q == r {
                    (p, s)
                } else if q == s {
                    (p, r)
                } else {
                    return None;
                };
                Some(self.sub(x, y))
            }
            _ => None,
        }
    }

    pub fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x * y),
            (Some(0.0), _) => return a,
            (_, Some(0.0)) => return b,
            (Some(1.0), _) => return b,
            (_, Some(1.0)) => return a,
            (Some(-1.0), _) => return self.neg(b),
            (_, Some(-1.0)) => return self.neg(a),
            _ => {}
        }
        // (−a)·b = −(a·b) exactly; pulling signs out lets more products share a node.
        if let Node::Neg(na) = self.node(a) {
            let p = self.mul(na, b);
            return self.neg(p);
        }
        if let Node::Neg(nb) = self.node(b) {
            let p = self.mul(a, nb);
            return self.neg(p);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Mul(a, b))
    }

    pub fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x / y),
            (Some(0.0), _) => return a,
            (_, Some(1.0)) => return a,
            (_, Some(-1.0)) => return self.neg(a),
            _ => {}
        }
        if let Node::Neg(na) = self.node(a) {
            let q = self.div(na, b);
            return self.neg(q);
        }
        self.intern(Node::Div(a, b))
    }

    pub fn fun(&mut self, f: Fun, a: NodeId) -> NodeId {
        if let Some(v) = self.as_const(a) {
            return self.constant(f.eval(v));
        }
        self.intern(Node::Fun(f, a))
    }

    pub fn powi(&mut self, a: NodeId, n: i32) -> NodeId {
        if let Some(v) = self.as_const(a) {
            return self.constant(v.powi(n));
        }
        match n {
            0 => self.constant(1.0),
            1 => a,
            _ => self.intern(Node::Powi(a, n)),
        }
    }

    pub fn powf(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x.powf(y)),
            (_, Some(1.0)) => return a,
            _ => {}
        }
        self.intern(Node::Powf(a, b))
    }

    pub fn atan2(&mut self, y: NodeId, x: NodeId) -> NodeId {
        if let (Some(a), Some(b)) = (self.as_const(y), self.as_const(x)) {
            return self.constant(a.atan2(b));
        }
        self.intern(Node::Atan2(y, x))
    }

    /// Rebuilds `root` with each symbol replaced by `map(sym)`; nodes are re-simplified, so
    /// substituting constants folds.
    pub fn substitute(
        &mut self,
        root: NodeId,
        map: &mut dyn FnMut(&mut Graph, Sym) -> NodeId,
    ) -> NodeId {
        let mut memo: HashMap<NodeId, NodeId> = HashMap::default();
        for id in self.cone(&[root]) {
            let new = match self.node(id) {
                Node::Const(_) => id,
                Node::Var(sym) => map(self, sym),
                other => self.rebuild(other, &memo),
            };
            memo.insert(id, new);
        }
        memo[&root]
    }

    /// Rebuilds an operation node with its children looked up in `memo`.
    pub fn rebuild(&mut self, node: Node, memo: &HashMap<NodeId, NodeId>) -> NodeId {
        let m = |id: NodeId| memo[&id];
        match node {
            Node::Const(_) | Node::Var(_) => unreachable!("leaves are not rebuilt"),
            Node::Neg(a) => self.neg(m(a)),
            Node::Add(a, b) => self.add(m(a), m(b)),
            Node::Sub(a, b) => self.sub(m(a), m(b)),
            Node::Mul(a, b) => self.mul(m(a), m(b)),
            Node::Div(a, b) => self.div(m(a), m(b)),
            Node::Fun(f, a) => self.fun(f, m(a)),
            Node::Powi(a, n) => self.powi(m(a), n),
            Node::Powf(a, b) => self.powf(m(a), m(b)),
            Node::Atan2(a, b) => self.atan2(m(a), m(b)),
        }
    }

    /// Every node the roots depend on, in topological (index) order.
    pub fn cone(&self, roots: &[NodeId]) -> Vec<NodeId> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack: Vec<NodeId> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id.0 as usize], true) {
                continue;
            }
            stack.extend(self.node(id).children());
        }
        (0..self.nodes.len() as u32)
            .map(NodeId)
            .filter(|id| seen[id.0 as usize])
            .collect()
    }

    /// The symbols the roots read.
    pub fn symbols(&self, roots: &[NodeId]) -> Vec<Sym> {
        self.cone(roots)
            .into_iter()
            .filter_map(|id| match self.node(id) {
                Node::Var(s) => Some(s),
                _ => None,
            })
            .collect()
    }

    /// Evaluates nodes numerically (compile-time checks and the compiler's own tests).
    #[allow(dead_code)]
    pub fn eval(&self, roots: &[NodeId], sym: &dyn Fn(Sym) -> f64) -> Vec<f64> {
        let mut value: HashMap<NodeId, f64> = HashMap::default();
        for id in self.cone(roots) {
            let v = |n: NodeId| value[&n];
            let x = match self.node(id) {
                Node::Const(bits) => f64::from_bits(bits),
                Node::Var(s) => sym(s),
                Node::Neg(a) => -v(a),
                Node::Add(a, b) => v(a) + v(b),
                Node::Sub(a, b) => v(a) - v(b),
                Node::Mul(a, b) => v(a) * v(b),
                Node::Div(a, b) => v(a) / v(b),
                Node::Fun(f, a) => f.eval(v(a)),
                Node::Powi(a, n) => v(a).powi(n),
                Node::Powf(a, b) => v(a).powf(v(b)),
                Node::Atan2(a, b) => v(a).atan2(v(b)),
            };
            value.insert(id, x);
        }
        roots.iter().map(|r| value[r]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(a + b) − a`, `a − (a + b)` and `(a + b) − (a + c)` drop the common term `a`, whichever
    /// side of each sum it is on, and then evaluate to `b`, `−b` and `b − c` exactly, where
    /// the expressions as written round `b` at `|a|`.
    #[test]
    fn a_common_term_of_a_difference_of_sums_cancels() {
        let mut g = Graph::default();
        let (a, b, c) = (
            g.var(Sym::Base(0)),
            g.var(Sym::Chart1(0)),
            g.var(Sym::Chart0(0)),
        );
        let (ab, ba, ac, ca) = (g.add(a, b), g.add(b, a), g.add(a, c), g.add(c, a));
        assert_eq!(g.sub(ab, a), b);
        assert_eq!(g.sub(ba, a), b);
        let minus_b = g.neg(b);
        assert_eq!(g.sub(a, ab), minus_b);
        let b_minus_c = g.sub(b, c);
        for (x, y) in [(ab, ac), (ab, ca), (ba, ac), (ba, ca)] {
            assert_eq!(g.sub(x, y), b_minus_c);
        }
        // Far from the origin: b loses its low bits in a + b, and keeps them here.
        let value = |s: Sym| match s {
            Sym::Base(_) => 1.0e8,
            Sym::Chart1(_) => 0.1 + 1e-9,
            _ => 0.03,
        };
        let roots = [g.sub(ab, a), g.sub(ab, ac)];
        let got = g.eval(&roots, &value);
        assert_eq!(got, [0.1 + 1e-9, (0.1 + 1e-9) - 0.03]);
        let as_written = (1.0e8 + (0.1 + 1e-9)) - 1.0e8;
        assert_ne!(as_written, 0.1 + 1e-9);
        // (a + b) − (b + d) = a − d; sums without a common term are left as written.
        let d = g.var(Sym::Base(1));
        let (bd, cd) = (g.add(b, d), g.add(c, d));
        let a_minus_d = g.sub(a, d);
        assert_eq!(g.sub(ab, bd), a_minus_d);
        let unrelated = g.sub(ab, cd);
        assert_eq!(g.node(unrelated), Node::Sub(ab, cd));
    }
}
