//! The continuous front end: a Lagrangian `L(q, v)` and a quadrature rule
//! become the discrete Lagrangian `L_d(q0, q1)` on the expression graph, so everything
//! downstream (reduction, differentiation, emission) is unchanged; and the Legendre map
//! `p = ∂L/∂v`, its Jacobian `∂²L/∂v²` and the energy `E = ⟨∂L/∂v, v⟩ − L` are differentiated
//! here, forward mode, on the graph ([`crate::back::continuous`] emits them).
//!
//! While lowering a continuous body, `Sym::Q0(i)` stands for `q_i` and `Sym::Q1(i)` for `v_i`;
//! [`discretize`] substitutes the rule's quadrature point and difference quotient for them.

use crate::front::rule::Rule;
use crate::ir::diff::{derivatives, symmetric_jacobian};
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::reduce::{firsts, Mode};

/// `L_d(q0, q1)` from `l` (over `q = Q0`, `v = Q1`) by `rule`, with the time step `h`.
///
/// The nodes are built in the order a hand-written rule reads — `0.5 * (q0 + q1)`,
/// `(q1 − q0) / h`, `h * L` — so that, the graph being hash-consed, a continuous Lagrangian and
/// the same rule written out by hand give the same graph and the same code, bit for bit.
pub fn discretize(g: &mut Graph, l: NodeId, n: usize, h: NodeId, rule: Rule) -> NodeId {
    let half = g.constant(0.5);
    let v = difference_quotients(g, n, h);
    let at = |g: &mut Graph, point: &dyn Fn(&mut Graph, usize) -> NodeId| at_point(g, l, point, &v);
    match rule {
        Rule::Midpoint => {
            let l_mid = at(g, &|g, i| midpoint(g, i, half));
            g.mul(h, l_mid)
        }
        Rule::Left => {
            let l0 = at(g, &|g, i| g.var(Sym::Q0(i)));
            g.mul(h, l0)
        }
        Rule::Right => {
            let l1 = at(g, &|g, i| g.var(Sym::Q1(i)));
            g.mul(h, l1)
        }
        Rule::Trapezoid => {
            let l0 = at(g, &|g, i| g.var(Sym::Q0(i)));
            let l1 = at(g, &|g, i| g.var(Sym::Q1(i)));
            let half_h = g.mul(half, h);
            let sum = g.add(l0, l1);
            g.mul(half_h, sum)
        }
    }
}

/// The difference quotients `(q1 − q0)/h` of the `n` coordinates: the velocity every rule reads
/// (of a Lagrangian and of a force alike).
pub fn difference_quotients(g: &mut Graph, n: usize, h: NodeId) -> Vec<NodeId> {
    (0..n)
        .map(|i| {
            let (a, b) = (g.var(Sym::Q0(i)), g.var(Sym::Q1(i)));
            let d = g.sub(b, a);
            g.div(d, h)
        })
        .collect()
}

/// `node` (over `q = Q0`, `v = Q1`) at the configuration `point(i)` and the velocities `v`.
pub fn at_point(
    g: &mut Graph,
    node: NodeId,
    point: &dyn Fn(&mut Graph, usize) -> NodeId,
    v: &[NodeId],
) -> NodeId {
    g.substitute(node, &mut |g, sym| match sym {
        Sym::Q0(i) => point(g, i),
        Sym::Q1(i) => v[i],
        other => g.var(other),
    })
}

/// The midpoint `0.5 * (q0_i + q1_i)`, with `half` the constant `0.5`.
pub fn midpoint(g: &mut Graph, i: usize, half: NodeId) -> NodeId {
    let (a, b) = (g.var(Sym::Q0(i)), g.var(Sym::Q1(i)));
    let s = g.add(a, b);
    g.mul(half, s)
}

/// The Legendre map, its Jacobian and the energy of `l` (over `q = Q0`, `v = Q1`).
pub struct Continuous {
    pub rule: Rule,
    /// `L(q, v)` itself.
    pub lagrangian: NodeId,
    /// `∂L/∂v_i`.
    pub legendre: Vec<NodeId>,
    /// `∂²L/∂v_i∂v_j`, row `i`.
    pub hessian: Vec<Vec<NodeId>>,
    /// `⟨∂L/∂v, v⟩ − L`.
    pub energy: NodeId,
    /// The derivatives a Gauss–Legendre step evaluates at its stages ([`stage`]), for a system
    /// on the dense backend without constraints; `None` otherwise.
    pub stage: Option<Stage>,
}

/// What a variational partitioned Runge–Kutta step reads at a stage `(Q_i, V_i)`: the force
/// `f = ∂L/∂q + F(q, v)` (the Lagrangian's and the declared forces'), the momentum
/// `p = ∂L/∂v` ([`Continuous::legendre`]) and their Jacobians in `q` and `v`
/// (`∂p/∂v` is [`Continuous::hessian`]), all over `q = Q0`, `v = Q1` and the parameters.
pub struct Stage {
    /// `f_i = ∂L/∂q_i + F_i`.
    pub force: Vec<NodeId>,
    /// `∂f_i/∂q_j`, row `i`.
    pub force_q: Vec<Vec<NodeId>>,
    /// `∂f_i/∂v_j`, row `i`.
    pub force_v: Vec<Vec<NodeId>>,
    /// `∂p_i/∂q_j`, row `i`.
    pub momentum_q: Vec<Vec<NodeId>>,
}

/// The stage derivatives of `c` (its Lagrangian over `q = Q0`, `v = Q1`, `n` coordinates) with
/// the continuous forces `forces` (`F_i(q, v)`, when declared): `∂L/∂q` by `mode`, then one
/// forward pass per coordinate and velocity for the Jacobians.
pub fn stage(
    g: &mut Graph,
    c: &Continuous,
    forces: Option<&[NodeId]>,
    n: usize,
    mode: Mode,
) -> Stage {
    let vars: Vec<Sym> = (0..n).map(Sym::Q0).collect();
    let mut force = firsts(g, mode, c.lagrangian, &vars);
    if let Some(forces) = forces {
        for (f, &extra) in force.iter_mut().zip(forces) {
            *f = g.add(*f, extra);
        }
    }
    let both: Vec<NodeId> = force.iter().chain(&c.legendre).copied().collect();
    // Column j of ∂(f, p)/∂q and of ∂f/∂v.
    let by_q: Vec<Vec<NodeId>> = (0..n).map(|j| derivatives(g, &both, Sym::Q0(j))).collect();
    let by_v: Vec<Vec<NodeId>> = (0..n).map(|j| derivatives(g, &force, Sym::Q1(j))).collect();
    let rows = |columns: &[Vec<NodeId>], offset: usize| -> Vec<Vec<NodeId>> {
        (0..n)
            .map(|i| (0..n).map(|j| columns[j][offset + i]).collect())
            .collect()
    };
    Stage {
        force_q: rows(&by_q, 0),
        momentum_q: rows(&by_q, n),
        force_v: rows(&by_v, 0),
        force,
    }
}

/// In `mode` (see [`Mode`]): forward passes, or the Legendre map by reverse accumulation and its
/// symmetric Jacobian one triangle at a time.
pub fn continuous(g: &mut Graph, l: NodeId, n: usize, rule: Rule, mode: Mode) -> Continuous {
    let vars: Vec<Sym> = (0..n).map(Sym::Q1).collect();
    let legendre = firsts(g, mode, l, &vars);
    let hessian = match mode {
        Mode::Forward => {
            let columns: Vec<Vec<NodeId>> = (0..n)
                .map(|j| derivatives(g, &legendre, Sym::Q1(j)))
                .collect();
            (0..n)
                .map(|i| (0..n).map(|j| columns[j][i]).collect())
                .collect()
        }
        Mode::Reverse => symmetric_jacobian(g, &legendre, Sym::Q1),
    };
    let mut pv = g.constant(0.0);
    for (i, &p) in legendre.iter().enumerate() {
        let v = g.var(Sym::Q1(i));
        let term = g.mul(p, v);
        pv = g.add(pv, term);
    }
    let energy = g.sub(pv, l);
    Continuous {
        rule,
        lagrangian: l,
        legendre,
        hessian,
        energy,
        stage: None,
    }
}
