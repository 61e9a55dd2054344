//! Holonomic constraints (beyond the paper, which treats only `Δ_Q = TQ`): the attribute's
//! `constraints = |q| [φ_1, …, φ_m]` with `φ(q) = 0` on the motion.
//!
//! # The constrained discrete equations (RATTLE in position–momentum form)
//!
//! The discrete Hamilton–Pontryagin principle restricted to the constraint manifold
//! `C = φ⁻¹(0)` (Marsden & West §3.5; Leok & Ohsawa's discrete Dirac structure with
//! `Δ_Q = TC`) gives, with multipliers `λ_k` for the positions and `ν_{k+1}` for the momenta,
//!
//! ```text
//! p_k + D1 L_d(q_k, q_{k+1}) + f_d^− − Dφ(q_k)ᵀ λ_k = 0,   φ(q_{k+1}) = 0        (position step)
//! p_{k+1} = D2 L_d(q_k, q_{k+1}) + f_d^+ + Dφ(q_{k+1})ᵀ ν_{k+1}                  (momentum update)
//! Dφ(q_{k+1}) v_{k+1} = 0,   p_{k+1} = ∂L/∂v(q_{k+1}, v_{k+1})                  (projection)
//! ```
//!
//! The first line is SHAKE: it determines `q_{k+1}` and `λ_k` whatever representative of the
//! momentum modulo the annihilator of `TC` is carried. The last two lines are RATTLE's
//! projection: they choose the representative whose velocity (by the continuous Legendre map of
//! `L`) is tangent to `C`, so the momenta stay on the constraint's cotangent space and their
//! energies are those of the constrained motion. The projection is solved for
//! `(v_{k+1}, ν_{k+1})` by the same Newton driver (it is linear when `L` is quadratic in the
//! velocities): `R(v, ν) = (∂L/∂v(q_{k+1}, v) − Dφᵀν − p_{k+1}^SHAKE, Dφ v)`. This needs the
//! continuous Legendre map, so constraints are accepted on continuous Lagrangians.
//!
//! # Reduction
//!
//! A constraint invariant under the symmetry, `φ(x, g + c) = φ(x, g)`, has `∂φ/∂g = 0`: the
//! group directions are tangent to `C` and the constraint forces `Dφᵀλ` have no group
//! component. The reduced equations keep their group rows (and with them `μ`, exact, or the
//! forced Noether balance) and gain `−Dφ_x(x_k)ᵀ λ` in their shape rows and the rows
//! `φ(x_{k+1}) = 0`; the projection changes `w` only, by `Dφ_x(x_{k+1})ᵀ ν`.

use syn::ExprClosure;

use crate::ctxt::Ctxt;
use crate::ir::diff::derivatives;
use crate::ir::discretize::Continuous;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};
use crate::ir::reduce::{reduce, system, Side, Stepper};

/// The constraints of a system, whatever their kind, as the steps use them.
pub struct Constraints {
    /// Whether they are holonomic (`φ(q) = 0`) or nonholonomic (`A(q) v = 0`).
    pub holonomic: bool,
    /// `φ(q)` over `Q0` (holonomic; empty otherwise): the initial state's check.
    pub phi: Vec<NodeId>,
    /// `A(q)`, `m × N` over `Q0`: `Dφ` for holonomic constraints.
    pub a: Vec<Vec<NodeId>>,
    /// The position step's constraint rows over `Q0 = q_k`, `Q1 = q_{k+1}`: `φ(q_{k+1})`, or the
    /// discrete nonholonomic constraint `A((q_k + q_{k+1})/2) (q_{k+1} − q_k)/h`.
    pub rows: Vec<NodeId>,
}

/// The closure's argument names, exactly `n` plain names (or `name: Type`).
pub fn args(cx: &Ctxt, closure: &ExprClosure, n: usize, usage: &str) -> Option<Vec<syn::Ident>> {
    let names: Vec<Option<syn::Ident>> = closure
        .inputs
        .iter()
        .map(|input| match input {
            syn::Pat::Ident(p) if p.by_ref.is_none() && p.mutability.is_none() => {
                Some(p.ident.clone())
            }
            syn::Pat::Type(t) => match &*t.pat {
                syn::Pat::Ident(p) => Some(p.ident.clone()),
                _ => None,
            },
            _ => None,
        })
        .collect();
    if names.len() != n || names.iter().any(Option::is_none) {
        cx.error_spanned_by(&closure.inputs, usage);
        return None;
    }
    Some(names.into_iter().flatten().collect())
}

/// Lowers `constraints = |q| [..]` (holonomic) or `nonholonomic = |q, v| [..]`; `None` after
/// errors, all recorded in `cx`. `h` is the time step's leaf.
pub fn lower(
    cx: &Ctxt,
    g: &mut Graph,
    closure: &ExprClosure,
    names: Names,
    continuous: bool,
    holonomic: bool,
    h: NodeId,
) -> Option<Constraints> {
    if !continuous {
        cx.error_spanned_by(
            closure,
            "constraints are accepted on a continuous Lagrangian `fn l(q: Config, v: Velocity, ..)` with a rule: \
             the momenta are kept on the constraint with its Legendre map (RATTLE)",
        );
        return None;
    }
    let n = names
        .coords
        .iter()
        .map(|c| c.len.unwrap_or(1))
        .sum::<usize>();
    let (usage, arity) = if holonomic {
        (
            "the constraints take the configuration alone: `constraints = |q| [<φ_1>, ...]`",
            1,
        )
    } else {
        (
            "nonholonomic constraints take the configuration and the velocity, and are linear in the velocity: \
             `nonholonomic = |q, v| [<A_1(q) v>, ...]`",
            2,
        )
    };
    let arg = args(cx, closure, arity, usage)?;
    let unused = syn::Ident::new("__dirac_no_velocity", proc_macro2::Span::call_site());
    let names = Names {
        q0: &arg[0],
        q1: arg.get(1).unwrap_or(&unused),
        ..names
    };
    let values = Lowering::new(g, cx, &names).scalars_expr(&closure.body, "the constraints")?;
    if values.is_empty() {
        cx.error_spanned_by(
            &closure.body,
            "no constraint: list at least one, `[<φ_1>, ...]`",
        );
        return None;
    }
    if holonomic {
        let a = jacobian(g, &values, Sym::Q0, n);
        let rows = values
            .iter()
            .map(|&p| {
                g.substitute(p, &mut |g, sym| match sym {
                    Sym::Q0(i) => g.var(Sym::Q1(i)),
                    other => g.var(other),
                })
            })
            .collect();
        return Some(Constraints {
            holonomic,
            phi: values,
            a,
            rows,
        });
    }
    // Nonholonomic: linear in v, so A(q) = ∂(A v)/∂v does not read v and A(q) 0 = 0.
    let a = jacobian(g, &values, Sym::Q1, n);
    let flat: Vec<NodeId> = a.iter().flatten().copied().collect();
    let reads_v = g.symbols(&flat).iter().any(|s| matches!(s, Sym::Q1(_)));
    let at_rest: Vec<NodeId> = values
        .iter()
        .map(|&p| {
            g.substitute(p, &mut |g, sym| match sym {
                Sym::Q1(_) => g.constant(0.0),
                other => g.var(other),
            })
        })
        .collect();
    if reads_v || at_rest.iter().any(|&p| g.as_const(p) != Some(0.0)) {
        cx.error_spanned_by(
            &closure.body,
            "nonholonomic constraints must be linear in the velocity, `A(q) v`: each a sum of terms `a(q) * v.x` \
             (an affine term or a product of velocities is not accepted)",
        );
        return None;
    }
    // The discrete constraint at the midpoint (McLachlan & Perlmutter): A(q_{k+1/2}) (q_{k+1} − q_k)/h.
    let half = g.constant(0.5);
    let rows = values
        .iter()
        .map(|&p| {
            g.substitute(p, &mut |g, sym| match sym {
                Sym::Q0(i) => {
                    let (a, b) = (g.var(Sym::Q0(i)), g.var(Sym::Q1(i)));
                    let s = g.add(a, b);
                    g.mul(half, s)
                }
                Sym::Q1(i) => {
                    let (a, b) = (g.var(Sym::Q0(i)), g.var(Sym::Q1(i)));
                    let d = g.sub(b, a);
                    g.div(d, h)
                }
                other => g.var(other),
            })
        })
        .collect();
    Some(Constraints {
        holonomic,
        phi: Vec::new(),
        a,
        rows,
    })
}

/// `∂values_j/∂var(i)`, row `j`.
fn jacobian(g: &mut Graph, values: &[NodeId], var: fn(usize) -> Sym, n: usize) -> Vec<Vec<NodeId>> {
    let columns: Vec<Vec<NodeId>> = (0..n).map(|i| derivatives(g, values, var(i))).collect();
    (0..values.len())
        .map(|j| (0..n).map(|i| columns[i][j]).collect())
        .collect()
}

/// The constrained steppers of one system.
pub struct ConstrainedCode {
    /// Number of constraints `m`.
    pub m: usize,
    /// Whether the constraints are holonomic.
    pub holonomic: bool,
    /// `φ(q)` over `Q0` (holonomic; empty otherwise).
    pub phi: Vec<NodeId>,
    /// The unreduced position step in `z = (q_{k+1}, λ)`.
    pub position: Stepper,
    /// The unreduced projection in `y = (v_{k+1}, ν)`; its update is the projected `p_{k+1}`.
    pub projection: Stepper,
    /// Each reduced side's position step in `z = (x_{k+1}, u, λ)` (its impulse: the change of
    /// `μ` by forces and constraint forces) and projection in `y = (v, ν)` (updates: the
    /// projected `(w_{k+1}, μ_{k+1})`).
    pub plus: (Stepper, Stepper),
    pub minus: (Stepper, Stepper),
}

/// `Σ_j λ_j a[j][i]` for each `i`: the constraint force `Aᵀλ`.
fn force(g: &mut Graph, a: &[Vec<NodeId>], n: usize) -> Vec<NodeId> {
    (0..n)
        .map(|i| {
            let mut f = g.constant(0.0);
            for (j, row) in a.iter().enumerate() {
                let l = g.var(Sym::Lambda(j));
                let t = g.mul(l, row[i]);
                f = g.add(f, t);
            }
            f
        })
        .collect()
}

/// `Σ_i a[j][i] v_i` (`v_i` is `Q1(i)`), one row per constraint.
fn tangency(g: &mut Graph, a: &[Vec<NodeId>]) -> Vec<NodeId> {
    a.iter()
        .map(|row| {
            let mut r = g.constant(0.0);
            for (i, &aji) in row.iter().enumerate() {
                let v = g.var(Sym::Q1(i));
                let t = g.mul(aji, v);
                r = g.add(r, t);
            }
            r
        })
        .collect()
}

/// The constrained steppers from the unconstrained ones (see the module documentation).
#[allow(clippy::too_many_arguments)] // one call site
pub fn construct(
    g: &mut Graph,
    c: Constraints,
    unreduced: &Stepper,
    plus: &Stepper,
    minus: &Stepper,
    continuous: &Continuous,
    b: &[Vec<NodeId>],
    s: usize,
    k: usize,
) -> ConstrainedCode {
    let n = s + k;
    let m = c.a.len();
    let lambdas: Vec<Sym> = (0..m).map(Sym::Lambda).collect();
    let q_unknowns: Vec<Sym> = (0..n).map(Sym::Q1).chain(lambdas.clone()).collect();
    // Unreduced position step: R − Aᵀ(q_k) λ, and the constraint rows.
    let f = force(g, &c.a, n);
    let mut residual: Vec<NodeId> = (0..n).map(|i| g.sub(unreduced.residual[i], f[i])).collect();
    residual.extend_from_slice(&c.rows);
    let position = system(
        g,
        residual,
        &q_unknowns,
        unreduced.momentum.clone(),
        Vec::new(),
    );
    // Unreduced projection: data q_{k+1} (Q0) and the momentum p̃ (P); unknowns v (Q1), ν.
    let projection = {
        let mut rows: Vec<NodeId> = (0..n)
            .map(|i| {
                let p = g.var(Sym::P(i));
                let r = g.sub(continuous.legendre[i], f[i]);
                g.sub(r, p)
            })
            .collect();
        rows.extend(tangency(g, &c.a));
        system(
            g,
            rows,
            &q_unknowns,
            continuous.legendre.clone(),
            Vec::new(),
        )
    };
    let reduced = |g: &mut Graph, side: Side, st: &Stepper| {
        let red = |g: &mut Graph, node: NodeId| reduce(g, side, node, s, b, 0.0);
        // The constraint force f^− = −A(q_k)ᵀ λ, in the reduced variables, trivialized.
        let a_r: Vec<Vec<NodeId>> =
            c.a.iter()
                .map(|row| row.iter().map(|&e| red(g, e)).collect())
                .collect();
        let f_r = force(g, &a_r, n);
        let mut residual = Vec::with_capacity(n + m);
        for i in 0..s {
            let mut fx = f_r[i];
            for (j, row) in b.iter().enumerate() {
                let t = g.mul(row[i], f_r[s + j]);
                fx = g.add(fx, t);
            }
            residual.push(g.sub(st.residual[i], fx));
        }
        // Group rows: ∂l/∂u ∓ (μ_k + f_g^−) with f_g^− = −(Aᵀλ)_g.
        for j in 0..k {
            residual.push(match side {
                Side::Plus => g.add(st.residual[s + j], f_r[s + j]),
                Side::Minus => g.sub(st.residual[s + j], f_r[s + j]),
            });
        }
        for &row in &c.rows {
            residual.push(red(g, row));
        }
        // μ_{k+1} − μ_k = the forces' group impulse − (Aᵀλ)_g.
        let mut impulse: Vec<NodeId> = (0..k)
            .map(|j| {
                let force = st
                    .impulse
                    .get(j)
                    .copied()
                    .unwrap_or_else(|| g.constant(0.0));
                g.sub(force, f_r[s + j])
            })
            .collect();
        if impulse.iter().all(|&p| g.as_const(p) == Some(0.0)) {
            impulse.clear();
        }
        let unknowns: Vec<Sym> = (0..s)
            .map(Sym::X1)
            .chain((0..k).map(side.group()))
            .chain(lambdas.clone())
            .collect();
        let position = system(g, residual, &unknowns, st.momentum.clone(), impulse);
        // Projection at x_{k+1} (Q0 shape, group 0), data w̃_{k+1} (W) and μ_{k+1} (Mu).
        let at_x = |g: &mut Graph, node: NodeId| {
            g.substitute(node, &mut |g, sym| match sym {
                Sym::Q0(i) if i >= s => g.constant(0.0),
                other => g.var(other),
            })
        };
        let a_p: Vec<Vec<NodeId>> =
            c.a.iter()
                .map(|row| row.iter().map(|&e| at_x(g, e)).collect())
                .collect();
        let f_p = force(g, &a_p, n);
        let legendre: Vec<NodeId> = continuous.legendre.iter().map(|&l| at_x(g, l)).collect();
        let mu: Vec<NodeId> = (0..k).map(|j| g.var(Sym::Mu(j))).collect();
        let bt = |g: &mut Graph, v: &[NodeId], i: usize| {
            let mut r = g.constant(0.0);
            for (j, row) in b.iter().enumerate() {
                let t = g.mul(row[i], v[j]);
                r = g.add(r, t);
            }
            r
        };
        let mut rows = Vec::with_capacity(n + m);
        for i in 0..s {
            let w = g.var(Sym::W(i));
            let bt_mu = bt(g, &mu, i);
            let p_x = g.sub(w, bt_mu);
            let r = g.sub(legendre[i], f_p[i]);
            rows.push(g.sub(r, p_x));
        }
        for j in 0..k {
            let r = g.sub(legendre[s + j], f_p[s + j]);
            rows.push(g.sub(r, mu[j]));
        }
        rows.extend(tangency(g, &a_p));
        // μ' = μ + (Aᵀν)_g: copied when the constraints have no group component.
        let group_free = (0..k).all(|j| g.as_const(f_p[s + j]) == Some(0.0));
        let mu_new: Vec<NodeId> = if group_free {
            mu.clone()
        } else {
            legendre[s..].to_vec()
        };
        let mut projected: Vec<NodeId> = (0..s)
            .map(|i| {
                let t = bt(g, &mu_new, i);
                g.add(legendre[i], t)
            })
            .collect();
        projected.extend(mu_new);
        let projection = system(g, rows, &q_unknowns, projected, Vec::new());
        (position, projection)
    };
    let plus = reduced(g, Side::Plus, plus);
    let minus = reduced(g, Side::Minus, minus);
    ConstrainedCode {
        m,
        holonomic: c.holonomic,
        phi: c.phi,
        position,
        projection,
        plus,
        minus,
    }
}
