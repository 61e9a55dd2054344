//! The paper's constructions on the graph: the reduced Lagrangians `l_{d+}` (eq. (4.5)) and
//! `l_{d−}` (eq. (4.7)), the residuals of the reduced (+) and (−) equations (4.6), (4.8) and of the
//! unreduced discrete Lagrange–Dirac equations (Definitions 2.7, 2.8), with exact Jacobians in
//! each stepper's unknowns and the explicit momentum updates. The (+) and (−) constructions are
//! one function each, parameterised by [`Side`].

use crate::ir::diff::{derivatives, gradient, symmetric_jacobian};
use crate::ir::graph::{Graph, NodeId, Sym};

/// What a stepper needs, as graph nodes: a residual `R(z)` in the unknowns `z`, its Jacobian,
/// and the momentum update evaluated at the solution.
pub struct Stepper {
    pub residual: Vec<NodeId>,
    /// `∂R/∂z`, row-major.
    pub jacobian: Vec<Vec<NodeId>>,
    pub momentum: Vec<NodeId>,
    /// The group impulse `μ_{k+1} − μ_k = f_{d,g}^− + f_{d,g}^+` of a reduced stepper (the forced
    /// discrete Noether balance, see [`reduced_stepper`]); empty when no force has a group
    /// component (then `μ` is conserved exactly) and for the unreduced stepper.
    pub impulse: Vec<NodeId>,
}

/// The discrete forces `f_d^−`, `f_d^+` of a stepper, over its own symbols (for a reduced
/// stepper: substituted like its Lagrangian, see [`reduce`]).
pub struct StepForces<'a> {
    pub minus: &'a [NodeId],
    pub plus: &'a [NodeId],
}

/// How first derivatives of the Lagrangian are built (second derivatives are forward passes over
/// them either way).
///
/// * `Forward`: one forward pass per coordinate ([`derivatives`]); the paper's systems use it,
///   and their generated code is the same text as before reverse accumulation existed;
/// * `Reverse`: one backward sweep for the whole gradient ([`gradient`]), the Jacobian then
///   forward over reverse, and the symmetric Hessian blocks of `L_d` one triangle each. On a
///   densely coupled Lagrangian (a chain of links whose velocities accumulate) forward mode
///   re-derives every accumulated term once per coordinate: `O(n²)` operations for the residual
///   and `O(n³)` for its Jacobian, against `O(n)` and `O(n²)` here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Forward,
    Reverse,
}

/// The first derivatives `∂l/∂v` for `v` in `vars`, in `mode`.
pub fn firsts(g: &mut Graph, mode: Mode, l: NodeId, vars: &[Sym]) -> Vec<NodeId> {
    match mode {
        Mode::Forward => vars.iter().map(|&v| first(g, l, v)).collect(),
        Mode::Reverse => gradient(g, l, vars),
    }
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
///
/// The same substitution takes any expression in `(q0, q1)` to the reduced variables of `side`:
/// G-invariant discrete forces too, whose values at `(q_k, q_{k+1})` are their values at the
/// reduced arguments for the same reason.
pub fn reduce(
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
///
/// # With forces: the reduced forced equations and the forced discrete Noether balance
///
/// Let the discrete forces be G-invariant (they depend on the group only through differences;
/// the compiler checks it as it checks `L_d`), and write them `f^± = (f_x^±, f_g^±)`, reduced by
/// the same substitution as `l` ([`reduce`]). The forced step
/// `p_k = −D1 L_d − f^−`, `p_{k+1} = D2 L_d + f^+` ([`crate::ir::force`]) with the chain rule of
/// `L_d(q0, q1) = l(x0, x1, u)` (for (+), `u = g1 − g0 − B (x1 − x0)`: `∂L_d/∂x0 = ∂l/∂x0 + Bᵀ ∂l/∂u`,
/// `∂L_d/∂g0 = −∂l/∂u`, `∂L_d/∂x1 = ∂l/∂x1 − Bᵀ ∂l/∂u`, `∂L_d/∂g1 = ∂l/∂u`) and the
/// trivialization (3.6) `w = p_x + Bᵀ p_g`, `μ = p_g` gives
///
/// ```text
/// w_k      = −∂l/∂x0 − f̃_x^−           f̃_x := f_x + Bᵀ f_g   (a force trivializes as a momentum)
/// μ_k      =  ∂l/∂u − f_g^−             ((−): μ_k = −∂l/∂u − f_g^−)
/// w_{k+1}  =  ∂l/∂x1 + f̃_x^+
/// μ_{k+1}  =  ∂l/∂u + f_g^+ = μ_k + f_g^− + f_g^+      (both sides)
/// ```
///
/// so the residual gains `f̃_x^−` in its shape rows and `∓ f_g^−` in its group rows, the momentum
/// update gains `f̃_x^+`, and `μ` obeys the **forced discrete Noether balance**
/// `μ_{k+1} − μ_k = f_g^− + f_g^+` (the discrete counterpart of `dJ/dt = ⟨F, ξ_Q⟩`). The runtime
/// applies the balance explicitly, so it holds to round-off at every step; with no group force
/// `impulse` is empty and `μ` stays bit for bit constant. The (−) side is the same computation
/// with `u = g0 − g1 + B (x1 − x0)`.
#[allow(clippy::too_many_arguments)]
pub fn reduced_stepper(
    g: &mut Graph,
    side: Side,
    l: NodeId,
    forces: Option<StepForces>,
    b: &[Vec<NodeId>],
    s: usize,
    k: usize,
    mode: Mode,
) -> Stepper {
    let u = side.group();
    // Reverse mode: the residual's derivatives from one sweep, the momentum update's from
    // another (each gradient expands the sums of adjoints only its own entries use).
    let grad = (mode == Mode::Reverse).then(|| {
        let rows: Vec<Sym> = (0..s).map(Sym::X0).chain((0..k).map(u)).collect();
        let mut d = gradient(g, l, &rows);
        let momentum: Vec<Sym> = (0..s).map(Sym::X1).collect();
        d.extend(gradient(g, l, &momentum));
        d
    });
    // f̃_x = f_x + Bᵀ f_g: the shape part of a force in the trivialization (3.6).
    let trivialized = |g: &mut Graph, f: &[NodeId], i: usize| {
        let mut v = f[i];
        for (j, row) in b.iter().enumerate() {
            let t = g.mul(row[i], f[s + j]);
            v = g.add(v, t);
        }
        v
    };
    let mut residual = Vec::with_capacity(s + k);
    for i in 0..s {
        let r = match &grad {
            Some(d) => {
                let w = g.var(Sym::W(i));
                g.add(d[i], w)
            }
            None => first_plus(g, l, Sym::X0(i), Sym::W(i)),
        };
        residual.push(match &forces {
            Some(f) => {
                let fx = trivialized(g, f.minus, i);
                g.add(r, fx)
            }
            None => r,
        });
    }
    for j in 0..k {
        let d = match &grad {
            Some(d) => d[s + j],
            None => first(g, l, u(j)),
        };
        let mut mu = g.var(Sym::Mu(j));
        if let Some(f) = &forces {
            mu = g.add(mu, f.minus[s + j]);
        }
        residual.push(match side {
            Side::Plus => g.sub(d, mu),
            Side::Minus => g.add(d, mu),
        });
    }
    let unknowns: Vec<Sym> = (0..s).map(Sym::X1).chain((0..k).map(u)).collect();
    // Built after the Jacobian, so a system without forces keeps its node numbers (and the
    // emitted code its names).
    finish(g, residual, &unknowns, |g| {
        let momentum: Vec<NodeId> = (0..s)
            .map(|i| {
                let m = match &grad {
                    Some(d) => d[s + k + i],
                    None => first(g, l, Sym::X1(i)),
                };
                match &forces {
                    Some(f) => {
                        let fx = trivialized(g, f.plus, i);
                        g.add(m, fx)
                    }
                    None => m,
                }
            })
            .collect();
        let mut impulse = Vec::new();
        if let Some(f) = &forces {
            let parts: Vec<NodeId> = (0..k)
                .map(|j| g.add(f.minus[s + j], f.plus[s + j]))
                .collect();
            if parts.iter().any(|&p| g.as_const(p) != Some(0.0)) {
                impulse = parts;
            }
        }
        (momentum, impulse)
    })
}

/// The unreduced stepper of Definitions 2.7/2.8: `R(q1) = D1 L_d(q_k, q1) + p_k` in
/// `z = q_{k+1}`, momentum update `p_{k+1} = D2 L_d(q_k, q_{k+1})`; with forces
/// `R(q1) = D1 L_d + p_k + f_d^−` and `p_{k+1} = D2 L_d + f_d^+` ([`crate::ir::force`]).
pub fn unreduced_stepper(
    g: &mut Graph,
    l: NodeId,
    forces: Option<StepForces>,
    n: usize,
    mode: Mode,
) -> Stepper {
    let grad = (mode == Mode::Reverse).then(|| {
        let mut d = gradient(g, l, &(0..n).map(Sym::Q0).collect::<Vec<_>>());
        d.extend(gradient(g, l, &(0..n).map(Sym::Q1).collect::<Vec<_>>()));
        d
    });
    let with = |g: &mut Graph, v: NodeId, f: Option<&[NodeId]>, i: usize| match f {
        Some(f) => g.add(v, f[i]),
        None => v,
    };
    let residual = (0..n)
        .map(|i| {
            let r = match &grad {
                Some(d) => {
                    let p = g.var(Sym::P(i));
                    g.add(d[i], p)
                }
                None => first_plus(g, l, Sym::Q0(i), Sym::P(i)),
            };
            with(g, r, forces.as_ref().map(|f| f.minus), i)
        })
        .collect();
    let unknowns: Vec<Sym> = (0..n).map(Sym::Q1).collect();
    finish(g, residual, &unknowns, |g| {
        let momentum = (0..n)
            .map(|i| {
                let m = match &grad {
                    Some(d) => d[n + i],
                    None => first(g, l, Sym::Q1(i)),
                };
                with(g, m, forces.as_ref().map(|f| f.plus), i)
            })
            .collect();
        (momentum, Vec::new())
    })
}

/// The partial derivatives of one step that its sensitivities need (implicit-function theorem
/// on `R(z; y, u) = 0`, see `dirac_runtime::sensitivity`), row-major: the residual and the
/// explicit updates `o` (the momentum update, then the group impulse for a reduced stepper) in
/// the step's data `y` (`x_k` reduced, `q_k` unreduced), its unknowns `z` and its controls `u`.
pub struct Partials {
    pub r_y: Vec<Vec<NodeId>>,
    pub r_u: Vec<Vec<NodeId>>,
    pub o_y: Vec<Vec<NodeId>>,
    pub o_z: Vec<Vec<NodeId>>,
    pub o_u: Vec<Vec<NodeId>>,
}

/// The [`Partials`] of `st`; `outputs` are its explicit updates.
pub fn partials(
    g: &mut Graph,
    st: &Stepper,
    outputs: &[NodeId],
    data: &[Sym],
    unknowns: &[Sym],
    controls: &[Sym],
) -> Partials {
    let jacobian = |g: &mut Graph, rows: &[NodeId], vars: &[Sym]| -> Vec<Vec<NodeId>> {
        let columns: Vec<Vec<NodeId>> = vars.iter().map(|&v| derivatives(g, rows, v)).collect();
        (0..rows.len())
            .map(|r| (0..vars.len()).map(|c| columns[c][r]).collect())
            .collect()
    };
    Partials {
        r_y: jacobian(g, &st.residual, data),
        r_u: jacobian(g, &st.residual, controls),
        o_y: jacobian(g, outputs, data),
        o_z: jacobian(g, outputs, unknowns),
        o_u: jacobian(g, outputs, controls),
    }
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

/// A stepper from its residual in `unknowns` and its explicit updates (Jacobian by forward
/// mode, one pass per unknown).
pub fn system(
    g: &mut Graph,
    residual: Vec<NodeId>,
    unknowns: &[Sym],
    momentum: Vec<NodeId>,
    impulse: Vec<NodeId>,
) -> Stepper {
    finish(g, residual, unknowns, |_| (momentum, impulse))
}

/// Jacobian columns by forward mode (one pass per unknown), then the momentum update and the
/// group impulse from `updates`.
fn finish(
    g: &mut Graph,
    residual: Vec<NodeId>,
    unknowns: &[Sym],
    updates: impl FnOnce(&mut Graph) -> (Vec<NodeId>, Vec<NodeId>),
) -> Stepper {
    let columns: Vec<Vec<NodeId>> = unknowns
        .iter()
        .map(|&z| derivatives(g, &residual, z))
        .collect();
    let jacobian = (0..residual.len())
        .map(|r| (0..unknowns.len()).map(|c| columns[c][r]).collect())
        .collect();
    let (momentum, impulse) = updates(g);
    Stepper {
        residual,
        jacobian,
        momentum,
        impulse,
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
/// for the step-map Jacobian (implicit-function theorem on Definition 2.7's equations). In
/// reverse mode the symmetric blocks `D11`, `D22` are built one triangle each (column `c` is a
/// forward pass over the rows `r ≥ c` only) and mirrored.
pub fn lagrangian_hessian(g: &mut Graph, l: NodeId, n: usize, mode: Mode) -> [Vec<Vec<NodeId>>; 3] {
    let d1 = &firsts(g, mode, l, &(0..n).map(Sym::Q0).collect::<Vec<_>>());
    let d2 = &firsts(g, mode, l, &(0..n).map(Sym::Q1).collect::<Vec<_>>());
    let block = |g: &mut Graph, rows: &[NodeId], var: fn(usize) -> Sym| -> Vec<Vec<NodeId>> {
        let columns: Vec<Vec<NodeId>> = (0..n).map(|c| derivatives(g, rows, var(c))).collect();
        (0..n)
            .map(|r| (0..n).map(|c| columns[c][r]).collect())
            .collect()
    };
    let symmetric = |g: &mut Graph, rows: &[NodeId], var: fn(usize) -> Sym| match mode {
        Mode::Forward => block(g, rows, var),
        Mode::Reverse => symmetric_jacobian(g, rows, var),
    };
    [
        symmetric(g, d1, Sym::Q0),
        block(g, d1, Sym::Q1),
        symmetric(g, d2, Sym::Q1),
    ]
}
