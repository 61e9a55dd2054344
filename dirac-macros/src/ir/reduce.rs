//! The paper's constructions on the graph: the reduced Lagrangians `l_{d+}` (eq. (4.5)) and
//! `l_{d−}` (eq. (4.7)), the residuals of the reduced (+) and (−) equations (4.6), (4.8) and of the
//! unreduced discrete Lagrange–Dirac equations (Definitions 2.7, 2.8), with exact Jacobians in
//! each stepper's unknowns and the explicit momentum updates. The (+) and (−) constructions are
//! one function each, parameterised by [`Side`].

use crate::ir::diff::derivatives;
use crate::ir::graph::{Graph, NodeId, Sym};

/// What a stepper needs, as graph nodes: a residual `R(z)` in the unknowns `z`, its Jacobian,
/// and the momentum update evaluated at the solution.
pub struct Stepper {
    pub residual: Vec<NodeId>,
    /// `∂R/∂z`, row-major.
    pub jacobian: Vec<Vec<NodeId>>,
    pub momentum: Vec<NodeId>,
}

/// A family of indexed symbols, e.g. `Sym::X0`.
type Coordinate = fn(usize) -> Sym;

/// Which reduced equations: (+), eq. (4.6), or (−), eq. (4.8) with the signs of Definition 2.8
/// (the runtime's `Plus`/`Minus`). The two differ only in what this type states: which group
/// coordinate is the unknown, which way the connection shifts it, where the group origin sits,
/// and the sign of `μ_k` in the momentum equations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Plus,
    Minus,
}

impl Side {
    /// The group unknown `u`: `g1` (that is `g_k^+`) for (+), `g0` (`g_{k+1}^−`) for (−).
    pub fn group(self) -> Coordinate {
        match self {
            Side::Plus => Sym::G1,
            Side::Minus => Sym::G0,
        }
    }
}

/// The reduced Lagrangian of `side`, built by substituting into the body's graph `l`:
///
/// * (+), eq. (4.5): `l_{d+}(x0, x1, g1) = L_d(x0, 0, x1, g1 + h_d^0(x0, x1))`;
/// * (−), eq. (4.7): `l_{d−}(x0, g0, x1) = L_d(x0, g0 + h_d^0(x1, x0), x1, 0)`,
///
/// with `h_d^0(x0, x1) = B (x1 − x0)`.
///
/// `alpha` chooses where the group origin sits: by G-invariance, with `G = u + h_d^0` the shifted
/// group unknown, `l_{d+} = L_d((x0, −α G), (x1, (1 − α) G))` and
/// `l_{d−} = L_d((x0, (1 − α) G), (x1, −α G))` for every `α`; the paper's formulas are `α = 0`.
/// The functions are equal, but their expressions are not: with `α = ½` a midpoint-rule
/// Lagrangian sees the group coordinate only through its increment, which is what lets
/// [`eliminate_group`] recognise affine momentum equations structurally.
pub fn reduced_lagrangian(
    g: &mut Graph,
    side: Side,
    l: NodeId,
    s: usize,
    b: &[Vec<NodeId>],
    alpha: f64,
) -> NodeId {
    // (+) shifts g1 by B (x1 − x0) and puts the group at q1; (−) shifts g0 by B (x0 − x1) and
    // puts it at q0.
    let (to, from): (Coordinate, Coordinate) = match side {
        Side::Plus => (Sym::X1, Sym::X0),
        Side::Minus => (Sym::X0, Sym::X1),
    };
    let (at_q0, at_q1) = match side {
        Side::Plus => (-alpha, 1.0 - alpha),
        Side::Minus => (1.0 - alpha, -alpha),
    };
    let u = side.group();
    g.substitute(l, &mut |g, sym| match sym {
        Sym::Q0(i) if i < s => g.var(Sym::X0(i)),
        Sym::Q0(i) => {
            let total = shifted(g, u(i - s), &b[i - s], to, from);
            let c = g.constant(at_q0);
            g.mul(c, total)
        }
        Sym::Q1(i) if i < s => g.var(Sym::X1(i)),
        Sym::Q1(i) => {
            let total = shifted(g, u(i - s), &b[i - s], to, from);
            let c = g.constant(at_q1);
            g.mul(c, total)
        }
        other => g.var(other),
    })
}

/// The group origins [`eliminate_group`] tries, in order: the paper's (`α = 0`), the midpoint,
/// and the other end.
pub const GROUP_ORIGINS: [f64; 3] = [0.0, 0.5, 1.0];

/// `group + Σ_i b_i (to_i − from_i)`: a group coordinate shifted by `h_d^0`.
fn shifted(
    g: &mut Graph,
    group: Sym,
    b_row: &[NodeId],
    to: Coordinate,
    from: Coordinate,
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

/// The reduced stepper of `side` on its reduced Lagrangian `l`, in the unknowns
/// `z = (x_{k+1}, u)`:
///
/// * (+), eq. (4.6): `R(z) = (∂l_{d+}/∂x0 + w_k, ∂l_{d+}/∂g1 − μ_k)`, `u = g_k^+`;
/// * (−): `R(z) = (∂l_{d−}/∂x0 + w_k, ∂l_{d−}/∂g0 + μ_k)`, `u = g_{k+1}^−` (the signs of
///   Definition 2.8; see `dirac_runtime::Minus` for the derivation and the paper's sign
///   discrepancy);
///
/// momentum update `w_{k+1} = ∂l/∂x1` on both sides.
pub fn reduced_stepper(g: &mut Graph, side: Side, l: NodeId, s: usize, k: usize) -> Stepper {
    let u = side.group();
    let mut residual = Vec::with_capacity(s + k);
    for i in 0..s {
        residual.push(first_plus(g, l, Sym::X0(i), Sym::W(i)));
    }
    for j in 0..k {
        let d = first(g, l, u(j));
        let mu = g.var(Sym::Mu(j));
        residual.push(match side {
            Side::Plus => g.sub(d, mu),
            Side::Minus => g.add(d, mu),
        });
    }
    let unknowns: Vec<Sym> = (0..s).map(Sym::X1).chain((0..k).map(u)).collect();
    let momentum: Vec<Sym> = (0..s).map(Sym::X1).collect();
    finish(g, l, residual, &unknowns, &momentum)
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

/// A stepper whose group equations were solved in closed form: Newton runs on the shape
/// unknowns `x_{k+1}` only.
pub struct Eliminated {
    /// The shape equations with the group unknowns substituted, length `S`.
    pub residual: Vec<NodeId>,
    /// Their exact Jacobian in `x_{k+1}` (`S × S`), including the dependence through the
    /// eliminated group unknowns.
    pub jacobian: Vec<Vec<NodeId>>,
    /// The group unknowns as functions of `(x_k, w_k, μ_k, x_{k+1})`, length `K`.
    pub group: Vec<NodeId>,
    /// The block `A = ∂R_g/∂g` that the closed form inverts (`K × K`, free of the group
    /// unknowns): a degenerate `A` (e.g. where the symmetry action is not free) no longer shows
    /// in the shape Jacobian, so the runtime estimates its conditioning from this.
    pub block: Vec<Vec<NodeId>>,
}

/// Momentum-level elimination (beyond the paper: its conclusion names discrete Routh reduction
/// as future work). The last `K` rows of a reduced stepper's residual are the momentum
/// equations (`∂l_{d+}/∂g1 = μ_k` for (+), `∂l_{d−}/∂g0 = −μ_k` for (−)). When their Jacobian in
/// the group unknowns does not involve the group unknowns — structurally, in the hash-consed
/// graph — they are affine in them: `R_g(x1, g) = R_g(x1, 0) + A(x1) g`. Then
/// `g = −A⁻¹ R_g(x1, 0)` in closed form (Cramer's rule, `K ≤ 3`), substituted into the shape
/// equations, which are differentiated again for their exact Jacobian. This holds whenever the
/// group coordinates are cyclic and `L_d` is quadratic in their increments (both paper examples).
/// Returns `None` when the equations are not affine, `K > 3`, or `A` is structurally singular;
/// the general path is used then.
pub fn eliminate_group(
    g: &mut Graph,
    side: Side,
    st: &Stepper,
    s: usize,
    k: usize,
) -> Option<Eliminated> {
    let group = side.group();
    if k == 0 || k > 3 {
        return None;
    }
    let is_group = |sym: Sym| (0..k).any(|j| group(j) == sym);
    let a: Vec<Vec<NodeId>> = (0..k)
        .map(|i| (0..k).map(|j| st.jacobian[s + i][s + j]).collect())
        .collect();
    let a_flat: Vec<NodeId> = a.iter().flatten().copied().collect();
    if g.symbols(&a_flat).into_iter().any(is_group) {
        return None;
    }
    let minus_r0: Vec<NodeId> = (0..k)
        .map(|i| {
            let r0 = g.substitute(st.residual[s + i], &mut |g, sym| {
                if is_group(sym) {
                    g.constant(0.0)
                } else {
                    g.var(sym)
                }
            });
            g.neg(r0)
        })
        .collect();
    let solution = cramer(g, &a, &minus_r0)?;
    let residual: Vec<NodeId> = (0..s)
        .map(|i| {
            g.substitute(
                st.residual[i],
                &mut |g, sym| match (0..k).find(|&j| group(j) == sym) {
                    Some(j) => solution[j],
                    None => g.var(sym),
                },
            )
        })
        .collect();
    let columns: Vec<Vec<NodeId>> = (0..s)
        .map(|c| derivatives(g, &residual, Sym::X1(c)))
        .collect();
    let jacobian = (0..s)
        .map(|r| (0..s).map(|c| columns[c][r]).collect())
        .collect();
    Some(Eliminated {
        residual,
        jacobian,
        group: solution,
        block: a,
    })
}

/// Solves `A x = b` symbolically by Cramer's rule (`A` is `K × K`, `K ≤ 3`); `None` when
/// `det A` is structurally zero.
fn cramer(g: &mut Graph, a: &[Vec<NodeId>], b: &[NodeId]) -> Option<Vec<NodeId>> {
    let det_a = det(g, a);
    if g.as_const(det_a) == Some(0.0) {
        return None;
    }
    let n = a.len();
    Some(
        (0..n)
            .map(|j| {
                let aj: Vec<Vec<NodeId>> = (0..n)
                    .map(|r| {
                        (0..n)
                            .map(|c| if c == j { b[r] } else { a[r][c] })
                            .collect()
                    })
                    .collect();
                let d = det(g, &aj);
                g.div(d, det_a)
            })
            .collect(),
    )
}

/// Determinant by Laplace expansion along the first row (small matrices only).
fn det(g: &mut Graph, a: &[Vec<NodeId>]) -> NodeId {
    match a.len() {
        1 => a[0][0],
        2 => {
            let p = g.mul(a[0][0], a[1][1]);
            let q = g.mul(a[0][1], a[1][0]);
            g.sub(p, q)
        }
        n => {
            let mut sum = g.constant(0.0);
            for c in 0..n {
                let minor: Vec<Vec<NodeId>> = (1..n)
                    .map(|r| (0..n).filter(|&j| j != c).map(|j| a[r][j]).collect())
                    .collect();
                let m = det(g, &minor);
                let term = g.mul(a[0][c], m);
                sum = if c % 2 == 0 {
                    g.add(sum, term)
                } else {
                    g.sub(sum, term)
                };
            }
            sum
        }
    }
}

/// The Hessian blocks of `L_d(q0, q1)`: `(D11, D12, D22)` with `D12[i][j] = ∂²L_d/∂q0_i∂q1_j`,
/// for the step-map Jacobian (implicit-function theorem on Definition 2.7's equations).
pub fn lagrangian_hessian(g: &mut Graph, l: NodeId, n: usize) -> [Vec<Vec<NodeId>>; 3] {
    let d1: Vec<NodeId> = (0..n).map(|i| first(g, l, Sym::Q0(i))).collect();
    let d2: Vec<NodeId> = (0..n).map(|i| first(g, l, Sym::Q1(i))).collect();
    let block = |g: &mut Graph, rows: &[NodeId], var: fn(usize) -> Sym| -> Vec<Vec<NodeId>> {
        let columns: Vec<Vec<NodeId>> = (0..n).map(|c| derivatives(g, rows, var(c))).collect();
        (0..n)
            .map(|r| (0..n).map(|c| columns[c][r]).collect())
            .collect()
    };
    [
        block(g, &d1, Sym::Q0),
        block(g, &d1, Sym::Q1),
        block(g, &d2, Sym::Q1),
    ]
}
