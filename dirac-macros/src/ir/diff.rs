//! Forward-mode differentiation on the graph, done at compile time.
//!
//! One pass per seed symbol propagates tangents through the cone of the requested outputs in
//! topological order — the rule `num-dual`'s dual numbers apply at run time, unrolled here into
//! new graph nodes. Applying the pass to first-derivative nodes gives second derivatives
//! (forward over forward). Tangents that are structurally zero stay the constant 0 and fold
//! away, so they never reach the emitted code.

use std::collections::HashMap;

use crate::ir::graph::{Fun, Graph, Node, NodeId, Sym};

/// `∂ root / ∂ seed` for each root.
pub fn derivatives(g: &mut Graph, roots: &[NodeId], seed: Sym) -> Vec<NodeId> {
    let zero = g.constant(0.0);
    let one = g.constant(1.0);
    let mut tangent: HashMap<NodeId, NodeId> = HashMap::new();
    for id in g.cone(roots) {
        let t = |n: NodeId| tangent[&n];
        let dt = match g.node(id) {
            Node::Const(_) => zero,
            Node::Var(s) => {
                if s == seed {
                    one
                } else {
                    zero
                }
            }
            Node::Neg(a) => g.neg(t(a)),
            Node::Add(a, b) => g.add(t(a), t(b)),
            Node::Sub(a, b) => g.sub(t(a), t(b)),
            Node::Mul(a, b) => {
                let l = g.mul(t(a), b);
                let r = g.mul(a, t(b));
                g.add(l, r)
            }
            Node::Div(a, b) => {
                // d(a/b) = (da − (a/b) db) / b, reusing the quotient node itself.
                let q_db = g.mul(id, t(b));
                let num = g.sub(t(a), q_db);
                g.div(num, b)
            }
            Node::Fun(f, a) => {
                let da = t(a);
                if g.as_const(da) == Some(0.0) {
                    zero
                } else {
                    let d = fun_derivative(g, f, a, id);
                    g.mul(d, da)
                }
            }
            Node::Powi(a, n) => {
                let da = t(a);
                if g.as_const(da) == Some(0.0) {
                    zero
                } else {
                    let c = g.constant(f64::from(n));
                    let p = g.powi(a, n - 1);
                    let cp = g.mul(c, p);
                    g.mul(cp, da)
                }
            }
            Node::Powf(a, b) => {
                // d(a^b) = b a^(b−1) da + a^b ln(a) db; each term only when its tangent is not
                // structurally zero, so a constant exponent never brings ln(a) in.
                let (da, db) = (t(a), t(b));
                let mut sum = zero;
                if g.as_const(da) != Some(0.0) {
                    let b1 = g.sub(b, one);
                    let p = g.powf(a, b1);
                    let bp = g.mul(b, p);
                    let term = g.mul(bp, da);
                    sum = g.add(sum, term);
                }
                if g.as_const(db) != Some(0.0) {
                    let ln = g.fun(Fun::Ln, a);
                    let pl = g.mul(id, ln);
                    let term = g.mul(pl, db);
                    sum = g.add(sum, term);
                }
                sum
            }
            Node::Atan2(y, x) => {
                // d atan2(y, x) = (x dy − y dx) / (x² + y²).
                let (dy, dx) = (t(y), t(x));
                let xdy = g.mul(x, dy);
                let ydx = g.mul(y, dx);
                let num = g.sub(xdy, ydx);
                if g.as_const(num) == Some(0.0) {
                    zero
                } else {
                    let xx = g.mul(x, x);
                    let yy = g.mul(y, y);
                    let den = g.add(xx, yy);
                    g.div(num, den)
                }
            }
        };
        tangent.insert(id, dt);
    }
    roots.iter().map(|r| tangent[r]).collect()
}

/// `∂ root / ∂ v` for each `v` in `wrt`, by reverse accumulation: one backward sweep over the
/// cone of `root` gives the adjoint `∂ root / ∂ n` of every node `n` that depends on a symbol of
/// `wrt`, built as graph nodes, and the gradient is the adjoints of the symbols. Subexpressions
/// shared by many symbols' derivatives (the adjoint of an accumulated sum, say) are built once,
/// where one forward pass per symbol re-derives them per symbol. Symbols the root does not read
/// get the constant 0.
///
/// **Factored adjoints.** An adjoint reaching a node along a single path is kept as a product
/// `b · f` of the adjoint `b` where the path started (a node with several contributions, or the
/// root) and the product `f` of the local partial derivatives along the path, which involves the
/// primal values only: through `m = l · s` and then `p = m · ω`, `s` gets `b · (ω · l)` instead
/// of `(b · ω) · l`. The sweep costs the same (one multiplication per edge, one more where a
/// factor meets a sum), but `f` is primal: a forward pass over the gradient (the Jacobian's
/// columns) differentiates one product `b · f` instead of the chain, and where `f` does not
/// depend on the seed (most columns of a dense Jacobian) that is one multiplication. The
/// contributions to a node are summed in decreasing parent order, so the result is
/// deterministic, and the adjoint of a node does not depend on which symbols are asked for.
pub fn gradient(g: &mut Graph, root: NodeId, wrt: &[Sym]) -> Vec<NodeId> {
    let zero = g.constant(0.0);
    let one = g.constant(1.0);
    let cone = g.cone(&[root]);
    // Nodes that depend on a symbol of `wrt`: only they carry (nonzero) adjoints.
    let mut active: HashMap<NodeId, bool> = HashMap::with_capacity(cone.len());
    let mut leaf: HashMap<Sym, NodeId> = HashMap::new();
    for &id in &cone {
        let node = g.node(id);
        let a = match node {
            Node::Const(_) => false,
            Node::Var(s) => {
                leaf.insert(s, id);
                wrt.contains(&s)
            }
            _ => node.children().any(|c| active[&c]),
        };
        active.insert(id, a);
    }
    // Contributions `(b, f)`, each worth `b · f`.
    let mut parts: HashMap<NodeId, Vec<(NodeId, NodeId)>> = HashMap::new();
    if active[&root] {
        parts.insert(root, vec![(one, one)]);
    }
    let mut adjoint: HashMap<NodeId, NodeId> = HashMap::new();
    for &id in cone.iter().rev() {
        let Some(contributions) = parts.remove(&id) else {
            continue;
        };
        let (b, f) = if let [single] = contributions[..] {
            single
        } else {
            let mut sum = zero;
            for (b, f) in contributions {
                let c = g.mul(b, f);
                sum = if sum == zero { c } else { g.add(sum, c) };
            }
            (sum, one)
        };
        if matches!(g.node(id), Node::Var(_)) {
            let a = g.mul(b, f);
            adjoint.insert(id, a);
            continue;
        }
        if g.as_const(b) == Some(0.0) || g.as_const(f) == Some(0.0) {
            continue;
        }
        let mut push = |g: &Graph, child: NodeId, f: NodeId| {
            if active[&child] && g.as_const(f) != Some(0.0) {
                parts.entry(child).or_default().push((b, f));
            }
        };
        let is_active = |n: NodeId| active[&n];
        match g.node(id) {
            Node::Const(_) | Node::Var(_) => {}
            Node::Neg(x) => {
                let c = g.neg(f);
                push(g, x, c);
            }
            Node::Add(x, y) => {
                push(g, x, f);
                push(g, y, f);
            }
            Node::Sub(x, y) => {
                push(g, x, f);
                if is_active(y) {
                    let c = g.neg(f);
                    push(g, y, c);
                }
            }
            Node::Mul(x, y) if x == y => {
                // x·x: the two contributions b·(f·x) as one, b·(f·x + f·x) (exact: doubling is).
                let fx = g.mul(f, x);
                let c = g.add(fx, fx);
                push(g, x, c);
            }
            Node::Mul(x, y) => {
                if is_active(x) {
                    let c = g.mul(f, y);
                    push(g, x, c);
                }
                if is_active(y) {
                    let c = g.mul(f, x);
                    push(g, y, c);
                }
            }
            Node::Div(x, y) => {
                // ∂(x/y)/∂x = 1/y, ∂(x/y)/∂y = −(x/y)/y: with t = f/y, x gets t and y gets −t·(x/y).
                let t = g.div(f, y);
                push(g, x, t);
                if is_active(y) {
                    let ty = g.mul(t, id);
                    let c = g.neg(ty);
                    push(g, y, c);
                }
            }
            Node::Fun(fun, x) => {
                let d = fun_derivative(g, fun, x, id);
                let c = g.mul(d, f);
                push(g, x, c);
            }
            Node::Powi(x, n) => {
                let c = g.constant(f64::from(n));
                let p = g.powi(x, n - 1);
                let cp = g.mul(c, p);
                let c = g.mul(cp, f);
                push(g, x, c);
            }
            Node::Powf(x, y) => {
                if is_active(x) {
                    let y1 = g.sub(y, one);
                    let p = g.powf(x, y1);
                    let yp = g.mul(y, p);
                    let c = g.mul(yp, f);
                    push(g, x, c);
                }
                if is_active(y) {
                    let ln = g.fun(Fun::Ln, x);
                    let pl = g.mul(id, ln);
                    let c = g.mul(pl, f);
                    push(g, y, c);
                }
            }
            Node::Atan2(y, x) => {
                // ∂ atan2(y, x) = (x dy − y dx) / (x² + y²).
                let xx = g.mul(x, x);
                let yy = g.mul(y, y);
                let den = g.add(xx, yy);
                if is_active(y) {
                    let fx = g.mul(f, x);
                    let c = g.div(fx, den);
                    push(g, y, c);
                }
                if is_active(x) {
                    let fy = g.mul(f, y);
                    let q = g.div(fy, den);
                    let c = g.neg(q);
                    push(g, x, c);
                }
            }
        }
    }
    wrt.iter()
        .map(|s| {
            leaf.get(s)
                .and_then(|id| adjoint.get(id))
                .copied()
                .unwrap_or(zero)
        })
        .collect()
}

/// `f'(a)` for `node = f(a)`.
fn fun_derivative(g: &mut Graph, f: Fun, a: NodeId, node: NodeId) -> NodeId {
    let one = g.constant(1.0);
    match f {
        Fun::Sin => g.fun(Fun::Cos, a),
        Fun::Cos => {
            let s = g.fun(Fun::Sin, a);
            g.neg(s)
        }
        Fun::Tan => {
            let t2 = g.mul(node, node);
            g.add(one, t2)
        }
        Fun::Asin | Fun::Acos => {
            let a2 = g.mul(a, a);
            let r = g.sub(one, a2);
            let s = g.fun(Fun::Sqrt, r);
            let d = g.div(one, s);
            if f == Fun::Asin {
                d
            } else {
                g.neg(d)
            }
        }
        Fun::Atan => {
            let a2 = g.mul(a, a);
            let den = g.add(one, a2);
            g.div(one, den)
        }
        Fun::Exp => node,
        Fun::Ln => g.div(one, a),
        Fun::Sqrt => {
            let two = g.constant(2.0);
            let den = g.mul(two, node);
            g.div(one, den)
        }
        Fun::Sinh => g.fun(Fun::Cosh, a),
        Fun::Cosh => g.fun(Fun::Sinh, a),
        Fun::Tanh => {
            let t2 = g.mul(node, node);
            g.sub(one, t2)
        }
        Fun::Recip => {
            let r2 = g.mul(node, node);
            g.neg(r2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn central_difference(g: &Graph, root: NodeId, at: f64) -> f64 {
        let h = 1e-6;
        let f = |x: f64| g.eval(&[root], &|_| x)[0];
        (f(at + h) - f(at - h)) / (2.0 * h)
    }

    #[test]
    fn every_elementary_rule_matches_a_central_difference() {
        type Op = fn(&mut Graph, NodeId) -> NodeId;
        let ops: Vec<(&str, Op)> = vec![
            ("sin", |g, x| g.fun(Fun::Sin, x)),
            ("cos", |g, x| g.fun(Fun::Cos, x)),
            ("tan", |g, x| g.fun(Fun::Tan, x)),
            ("asin", |g, x| g.fun(Fun::Asin, x)),
            ("acos", |g, x| g.fun(Fun::Acos, x)),
            ("atan", |g, x| g.fun(Fun::Atan, x)),
            ("exp", |g, x| g.fun(Fun::Exp, x)),
            ("ln", |g, x| g.fun(Fun::Ln, x)),
            ("sqrt", |g, x| g.fun(Fun::Sqrt, x)),
            ("sinh", |g, x| g.fun(Fun::Sinh, x)),
            ("cosh", |g, x| g.fun(Fun::Cosh, x)),
            ("tanh", |g, x| g.fun(Fun::Tanh, x)),
            ("recip", |g, x| g.fun(Fun::Recip, x)),
            ("powi", |g, x| g.powi(x, 3)),
            ("powf const", |g, x| {
                let c = g.constant(2.5);
                g.powf(x, c)
            }),
            ("powf var", |g, x| g.powf(x, x)),
            ("atan2", |g, x| {
                let y = g.fun(Fun::Sin, x);
                g.atan2(y, x)
            }),
            ("div", |g, x| {
                let s = g.fun(Fun::Exp, x);
                g.div(s, x)
            }),
        ];
        for (name, op) in ops {
            let mut g = Graph::default();
            let x = g.var(Sym::Param(0));
            let root = op(&mut g, x);
            let d = derivatives(&mut g, &[root], Sym::Param(0))[0];
            let at = 0.4;
            let exact = g.eval(&[d], &|_| at)[0];
            let fd = central_difference(&g, root, at);
            assert!(
                (exact - fd).abs() < 1e-7 * (1.0 + fd.abs()),
                "{name}: {exact} vs {fd}"
            );
        }
    }

    #[test]
    fn reverse_accumulation_matches_forward_passes() {
        // f(x, y) = sin(x·y) / (1 + y²) + atan2(y, x)·exp(x) + x^2.5 + ln(y)·x³ − √(x + y)·tanh(x),
        // every rule with both children active, a square and a parameter the gradient skips.
        let mut g = Graph::default();
        let (x, y, p) = (g.var(Sym::X0(0)), g.var(Sym::X1(0)), g.var(Sym::Param(0)));
        let one = g.constant(1.0);
        let xy = g.mul(x, y);
        let s = g.fun(Fun::Sin, xy);
        let yy = g.mul(y, y);
        let den = g.add(one, yy);
        let a = g.div(s, den);
        let at = g.atan2(y, x);
        let e = g.fun(Fun::Exp, x);
        let b = g.mul(at, e);
        let c25 = g.constant(2.5);
        let c = g.powf(x, c25);
        let ln = g.fun(Fun::Ln, y);
        let x3 = g.powi(x, 3);
        let d = g.mul(ln, x3);
        let xpy = g.add(x, y);
        let r = g.fun(Fun::Sqrt, xpy);
        let t = g.fun(Fun::Tanh, x);
        let rt = g.mul(r, t);
        let py = g.powf(y, x);
        let np = g.neg(p);
        let pp = g.mul(np, py);
        let mut f = g.add(a, b);
        for term in [c, d, pp] {
            f = g.add(f, term);
        }
        let f = g.sub(f, rt);
        let wrt = [Sym::X0(0), Sym::X1(0), Sym::G1(0)];
        let reverse = gradient(&mut g, f, &wrt);
        assert_eq!(g.as_const(reverse[2]), Some(0.0));
        let forward: Vec<NodeId> = wrt
            .iter()
            .map(|&v| derivatives(&mut g, &[f], v)[0])
            .collect();
        let at = |s: Sym| match s {
            Sym::X0(_) => 0.7,
            Sym::X1(_) => 1.3,
            _ => -0.4,
        };
        let (rv, fv) = (g.eval(&reverse, &at), g.eval(&forward, &at));
        for (r, f) in rv.iter().zip(&fv) {
            assert!((r - f).abs() <= 1e-14 * (1.0 + f.abs()), "{rv:?} vs {fv:?}");
        }
    }

    #[test]
    fn structural_zeros_fold_away() {
        let mut g = Graph::default();
        let x = g.var(Sym::X0(0));
        let y = g.var(Sym::X1(0));
        let s = g.fun(Fun::Sin, x);
        let root = g.mul(s, y);
        let d = derivatives(&mut g, &[root], Sym::G1(0))[0];
        assert_eq!(g.as_const(d), Some(0.0));
        // d/dx (sin x · y) = cos x · y: one product, no multiplication by one.
        let d = derivatives(&mut g, &[root], Sym::X0(0))[0];
        let c = g.fun(Fun::Cos, x);
        assert_eq!(g.node(d), Node::Mul(y.min(c), y.max(c)));
    }
}
