//! Differentiation on the graph, done at compile time.
//!
//! Forward mode ([`derivatives`]): one pass per seed symbol propagates tangents through the cone
//! of the requested outputs in topological order — the rule `num-dual`'s dual numbers apply at
//! run time, unrolled here into new graph nodes. Applying the pass to first-derivative nodes
//! gives second derivatives (forward over forward). Tangents that are structurally zero stay the
//! constant 0 and fold away, so they never reach the emitted code.
//!
//! Reverse mode ([`gradient`]): one backward sweep gives a whole gradient; forward passes over it
//! give second derivatives (forward over reverse), symmetric ones one triangle at a time
//! ([`symmetric_jacobian`]).

use rustc_hash::FxHashMap as HashMap;

use crate::ir::graph::{Fun, Graph, Node, NodeId, Sym};

/// `∂ root / ∂ seed` for each root.
pub fn derivatives(g: &mut Graph, roots: &[NodeId], seed: Sym) -> Vec<NodeId> {
    let zero = g.constant(0.0);
    let one = g.constant(1.0);
    let mut tangent: HashMap<NodeId, NodeId> = HashMap::default();
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
/// `b · f` of the adjoint `b` where the path started (a sum of several contributions, or the
/// root's 1) and the product `f` of the local partial derivatives along the path, which involves
/// the primal values only: through `m = l · s` and then `p = m · ω`, `s` gets `b · (ω · l)`
/// instead of `(b · ω) · l`. The sweep costs the same (one multiplication per edge), but `f` is
/// primal: a forward pass over the gradient (a Jacobian column) differentiates one product `b · f`
/// instead of the chain, and where `f` does not depend on the seed (most columns of a dense
/// Jacobian) that is one multiplication.
///
/// **Expanded leaves.** A sum of contributions `Σ bₖ · fₖ` that only one entry of the gradient
/// uses (counted over this call's entries, so a caller asks separately for the entries it
/// differentiates again) is expanded into that entry, recursively, and contributions with the
/// same `b` are merged, `b · (f₁ + f₂)`. On a chain of links the adjoint of a link's angle and
/// of its angular velocity are such sums; expanded, the residual row of link `i` is
/// `Aᵢ · Pᵢ + Bᵢ · Qᵢ + ..` over the few accumulated adjoints `Aᵢ, Bᵢ` (of the velocity sums
/// through link `i`) with primal coefficients, and a Jacobian column costs a multiplication and
/// an addition per accumulated adjoint per row instead of re-deriving the intermediate sums.
///
/// The contributions to a node are summed in the order they arrive (decreasing parent order), so
/// the result is deterministic, and the adjoint of a node does not depend on which symbols are
/// asked for. These regroupings change the rounding of the derivatives (not of the body's own
/// value), as any other order of the chain rule would.
pub fn gradient(g: &mut Graph, root: NodeId, wrt: &[Sym]) -> Vec<NodeId> {
    let zero = g.constant(0.0);
    let one = g.constant(1.0);
    let cone = g.cone(&[root]);
    // Nodes that depend on a symbol of `wrt`: only they carry (nonzero) adjoints.
    let mut active: HashMap<NodeId, bool> =
        HashMap::with_capacity_and_hasher(cone.len(), Default::default());
    let mut leaf: HashMap<Sym, NodeId> = HashMap::default();
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
    let mut parts: HashMap<NodeId, Vec<(NodeId, NodeId)>> = HashMap::default();
    if active[&root] {
        parts.insert(root, vec![(one, one)]);
    }
    // The contributions reaching each leaf; the contributions a sum of adjoints was formed from,
    // by the sum's node; and how many lists (those, and the leaves') each adjoint appears in.
    let mut leaf_terms: HashMap<NodeId, Vec<(NodeId, NodeId)>> = HashMap::default();
    let mut terms: HashMap<NodeId, Vec<(NodeId, NodeId)>> = HashMap::default();
    let mut uses: HashMap<NodeId, usize> = HashMap::default();
    for &id in cone.iter().rev() {
        let Some(contributions) = parts.remove(&id) else {
            continue;
        };
        let contributions = merge(g, contributions);
        if matches!(g.node(id), Node::Var(_)) {
            leaf_terms.insert(id, contributions);
            continue;
        }
        let (b, f) = if let [single] = contributions[..] {
            single
        } else {
            let sum = total(g, &contributions);
            for &(b, _) in &contributions {
                *uses.entry(b).or_default() += 1;
            }
            terms.entry(sum).or_insert(contributions);
            (sum, one)
        };
        if g.as_const(b) == Some(0.0) || g.as_const(f) == Some(0.0) {
            continue;
        }
        let mut pushed: Vec<(NodeId, NodeId)> = Vec::with_capacity(2);
        let mut push = |_: &Graph, child: NodeId, f: NodeId| pushed.push((child, f));
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
        for (child, f) in pushed {
            if !active[&child] || g.as_const(f) == Some(0.0) {
                continue;
            }
            // A factor that varies with the symbols, on the root's adjoint 1, is an adjoint of
            // its own (a term of a sum, say): it becomes the contribution's `b`, so that the
            // factors further down multiply it rather than it being buried inside them.
            let c = if b == one && varies(g, f, &mut active) {
                (f, one)
            } else {
                (b, f)
            };
            parts.entry(child).or_default().push(c);
        }
    }
    // The leaves: sums of adjoints used by this leaf alone are expanded into it (see above).
    for list in leaf_terms.values() {
        for &(b, _) in list {
            *uses.entry(b).or_default() += 1;
        }
    }
    wrt.iter()
        .map(|s| {
            let Some(list) = leaf.get(s).and_then(|id| leaf_terms.get(id)) else {
                return zero;
            };
            let mut list = list.clone();
            while let Some(at) = list
                .iter()
                .position(|(b, _)| uses.get(b) == Some(&1) && terms.contains_key(b))
            {
                let (b, f) = list.remove(at);
                for &(inner, fi) in &terms[&b] {
                    let ff = g.mul(fi, f);
                    list.push((inner, ff));
                }
            }
            let list = merge(g, list);
            total(g, &list)
        })
        .collect()
}

/// Whether `n` depends on a symbol the gradient is taken in; `active` holds the answer for the
/// cone and is extended, memoised, to the nodes the sweep builds. With an explicit stack: a
/// graph is as deep as the longest chain of the text (a sum of 10⁵ terms, a chain of `let`s).
fn varies(g: &Graph, n: NodeId, active: &mut HashMap<NodeId, bool>) -> bool {
    if let Some(&a) = active.get(&n) {
        return a;
    }
    // A node is answered once its children are: pushed again behind them on first sight.
    let mut pending = vec![(n, false)];
    while let Some((id, expanded)) = pending.pop() {
        if active.contains_key(&id) {
            continue;
        }
        let node = g.node(id);
        if matches!(node, Node::Const(_) | Node::Var(_)) {
            active.insert(id, false);
        } else if expanded {
            let a = node
                .children()
                .any(|c| active.get(&c).copied().unwrap_or(false));
            active.insert(id, a);
        } else {
            pending.push((id, true));
            pending.extend(
                node.children()
                    .filter(|c| !active.contains_key(c))
                    .map(|c| (c, false)),
            );
        }
    }
    active[&n]
}

/// Contributions with the same adjoint `b` as one, `b · (f₁ + f₂ + ..)`, in order of first
/// appearance.
fn merge(g: &mut Graph, list: Vec<(NodeId, NodeId)>) -> Vec<(NodeId, NodeId)> {
    let mut out: Vec<(NodeId, NodeId)> = Vec::with_capacity(list.len());
    for (b, f) in list {
        match out.iter_mut().find(|(ob, _)| *ob == b) {
            Some(slot) => slot.1 = g.add(slot.1, f),
            None => out.push((b, f)),
        }
    }
    out
}

/// `Σ b · f` over the contributions, in order.
fn total(g: &mut Graph, list: &[(NodeId, NodeId)]) -> NodeId {
    let mut sum: Option<NodeId> = None;
    for &(b, f) in list {
        let c = g.mul(b, f);
        sum = Some(match sum {
            Some(s) => g.add(s, c),
            None => c,
        });
    }
    sum.unwrap_or_else(|| g.constant(0.0))
}

/// The symmetric matrix `∂ rows[r] / ∂ var(c)` (rows the gradient of one function in the
/// symbols `var(0..n)`), built one triangle at a time: column `c` is a forward pass over the rows
/// `r ≥ c` only, and the upper triangle mirrors the lower.
pub fn symmetric_jacobian(
    g: &mut Graph,
    rows: &[NodeId],
    var: fn(usize) -> Sym,
) -> Vec<Vec<NodeId>> {
    let n = rows.len();
    // lower[c][r − c] = ∂rows[r]/∂var(c) for r ≥ c.
    let lower: Vec<Vec<NodeId>> = (0..n).map(|c| derivatives(g, &rows[c..], var(c))).collect();
    (0..n)
        .map(|r| {
            (0..n)
                .map(|c| {
                    let (hi, lo) = (r.max(c), r.min(c));
                    lower[lo][hi - lo]
                })
                .collect()
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
