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
