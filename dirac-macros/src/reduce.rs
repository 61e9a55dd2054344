//! The paper's constructions on the graph: the reduced Lagrangians `l_{d+}` (eq. (4.5)) and
//! `l_{d−}` (eq. (4.7)), the residuals of the reduced (+) and (−) equations (4.6), (4.8) and of the
//! unreduced discrete Lagrange–Dirac equations (Definitions 2.7, 2.8), with exact Jacobians in
//! each stepper's unknowns and the explicit momentum updates.

use crate::diff::derivatives;
use crate::graph::{Graph, NodeId, Sym};

/// What a stepper needs, as graph nodes: a residual `R(z)` in the unknowns `z`, its Jacobian,
/// and the momentum update evaluated at the solution.
pub struct Stepper {
    pub residual: Vec<NodeId>,
    /// `∂R/∂z`, row-major.
    pub jacobian: Vec<Vec<NodeId>>,
    pub momentum: Vec<NodeId>,
}

/// `l_{d+}(x0, x1, g1) = L_d(x0, 0, x1, g1 + h_d^0(x0, x1))` with `h_d^0(x0, x1) = B (x1 − x0)`,
/// eq. (4.5), built by substituting into the body's graph `l`.
pub fn reduced_lagrangian_plus(g: &mut Graph, l: NodeId, s: usize, b: &[Vec<NodeId>]) -> NodeId {
    g.substitute(l, &mut |g, sym| match sym {
        Sym::Q0(i) if i < s => g.var(Sym::X0(i)),
        // The (+) reduced space fixes g0 = 0 (identification (3.10)).
        Sym::Q0(_) => g.constant(0.0),
        Sym::Q1(i) if i < s => g.var(Sym::X1(i)),
        Sym::Q1(i) => shifted(g, Sym::G1(i - s), &b[i - s], Sym::X1, Sym::X0),
        other => g.var(other),
    })
}

/// `l_{d−}(x0, g0, x1) = L_d(x0, g0 + h_d^0(x1, x0), x1, 0)` with `h_d^0(x1, x0) = B (x0 − x1)`,
/// eq. (4.7).
pub fn reduced_lagrangian_minus(g: &mut Graph, l: NodeId, s: usize, b: &[Vec<NodeId>]) -> NodeId {
    g.substitute(l, &mut |g, sym| match sym {
        Sym::Q0(i) if i < s => g.var(Sym::X0(i)),
        Sym::Q0(i) => shifted(g, Sym::G0(i - s), &b[i - s], Sym::X0, Sym::X1),
        Sym::Q1(i) if i < s => g.var(Sym::X1(i)),
        // The (−) reduced space fixes g1 = 0 (Remark 3.5).
        Sym::Q1(_) => g.constant(0.0),
        other => g.var(other),
    })
}

/// `group + Σ_i b_i (to_i − from_i)`: a group coordinate shifted by `h_d^0`.
fn shifted(
    g: &mut Graph,
    group: Sym,
    b_row: &[NodeId],
    to: fn(usize) -> Sym,
    from: fn(usize) -> Sym,
) -> NodeId {
    let mut v = g.var(group);
    for (i, &bji) in b_row.iter().enumerate() {
        let t = g.var(to(i));
        let f = g.var(from(i));
        let d = g.sub(t, f);
        let term = g.mul(bji, d);
        v = g.add(v, term);
    }
    v
}

/// The (+) stepper of eq. (4.6): `R(z) = (∂l_{d+}/∂x0 + w_k, ∂l_{d+}/∂g1 − μ_k)` in
/// `z = (x_{k+1}, g_k^+)`, momentum update `w_{k+1} = ∂l_{d+}/∂x1`.
pub fn plus_stepper(g: &mut Graph, l_plus: NodeId, s: usize, k: usize) -> Stepper {
    let mut residual = Vec::with_capacity(s + k);
    for i in 0..s {
        residual.push(first_plus(g, l_plus, Sym::X0(i), Sym::W(i)));
    }
    for j in 0..k {
        let d = first(g, l_plus, Sym::G1(j));
        let mu = g.var(Sym::Mu(j));
        residual.push(g.sub(d, mu));
    }
    let unknowns: Vec<Sym> = (0..s).map(Sym::X1).chain((0..k).map(Sym::G1)).collect();
    let momentum: Vec<Sym> = (0..s).map(Sym::X1).collect();
    finish(g, l_plus, residual, &unknowns, &momentum)
}

/// The (−) stepper: `R(z) = (∂l_{d−}/∂x0 + w_k, ∂l_{d−}/∂g0 + μ_k)` in `z = (x_{k+1}, g_{k+1}^−)`,
/// momentum update `w_{k+1} = ∂l_{d−}/∂x1` (the signs of Definition 2.8; see
/// `dirac_runtime::ReducedMinus` for the derivation and the paper's sign discrepancy).
pub fn minus_stepper(g: &mut Graph, l_minus: NodeId, s: usize, k: usize) -> Stepper {
    let mut residual = Vec::with_capacity(s + k);
    for i in 0..s {
        residual.push(first_plus(g, l_minus, Sym::X0(i), Sym::W(i)));
    }
    for j in 0..k {
        residual.push(first_plus(g, l_minus, Sym::G0(j), Sym::Mu(j)));
    }
    let unknowns: Vec<Sym> = (0..s).map(Sym::X1).chain((0..k).map(Sym::G0)).collect();
    let momentum: Vec<Sym> = (0..s).map(Sym::X1).collect();
    finish(g, l_minus, residual, &unknowns, &momentum)
}

/// The unreduced stepper of Definitions 2.7/2.8: `R(q1) = D1 L_d(q_k, q1) + p_k` in
/// `z = q_{k+1}`, momentum update `p_{k+1} = D2 L_d(q_k, q_{k+1})`.
pub fn unreduced_stepper(g: &mut Graph, l: NodeId, n: usize) -> Stepper {
    let residual = (0..n)
        .map(|i| first_plus(g, l, Sym::Q0(i), Sym::P(i)))
        .collect();
    let unknowns: Vec<Sym> = (0..n).map(Sym::Q1).collect();
    finish(g, l, residual, &unknowns, &unknowns)
}

fn first(g: &mut Graph, l: NodeId, var: Sym) -> NodeId {
    derivatives(g, &[l], var)[0]
}

/// `∂l/∂var + leaf`.
fn first_plus(g: &mut Graph, l: NodeId, var: Sym, leaf: Sym) -> NodeId {
    let d = first(g, l, var);
    let v = g.var(leaf);
    g.add(d, v)
}

/// Jacobian columns by forward mode (one pass per unknown) and the momentum update.
fn finish(
    g: &mut Graph,
    l: NodeId,
    residual: Vec<NodeId>,
    unknowns: &[Sym],
    momentum: &[Sym],
) -> Stepper {
    let columns: Vec<Vec<NodeId>> = unknowns
        .iter()
        .map(|&z| derivatives(g, &residual, z))
        .collect();
    let jacobian = (0..residual.len())
        .map(|r| (0..unknowns.len()).map(|c| columns[c][r]).collect())
        .collect();
    let momentum = momentum.iter().map(|&v| first(g, l, v)).collect();
    Stepper {
        residual,
        jacobian,
        momentum,
    }
}
