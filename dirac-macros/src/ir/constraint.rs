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
use crate::ir::reduce::{system, Side, Stepper};

/// Lowers `constraints = |q| [..]`: the values `φ_j` over `Sym::Q0` and the parameters.
pub fn lower(
    cx: &Ctxt,
    g: &mut Graph,
    closure: &ExprClosure,
    names: Names,
    continuous: bool,
) -> Option<Vec<NodeId>> {
    if !continuous {
        cx.error_spanned_by(
            closure,
            "constraints are accepted on a continuous Lagrangian `fn l(q: Config, v: Velocity, ..)` with a rule: \
             the momenta are kept on the constraint's cotangent space with its Legendre map (RATTLE)",
        );
        return None;
    }
    let arg = match closure.inputs.iter().collect::<Vec<_>>().as_slice() {
        [syn::Pat::Ident(p)] if p.by_ref.is_none() && p.mutability.is_none() => p.ident.clone(),
        [syn::Pat::Type(t)] if matches!(&*t.pat, syn::Pat::Ident(_)) => {
            let syn::Pat::Ident(p) = &*t.pat else {
                unreachable!("matched above")
            };
            p.ident.clone()
        }
        _ => {
            cx.error_spanned_by(
                &closure.inputs,
                "the constraints take the configuration alone: `constraints = |q| [<φ_1>, ...]`",
            );
            return None;
        }
    };
    let unused = syn::Ident::new("__dirac_no_velocity", proc_macro2::Span::call_site());
    let names = Names {
        q0: &arg,
        q1: &unused,
        ..names
    };
    let phi = Lowering::new(g, cx, &names).scalars_expr(&closure.body, "the constraints")?;
    if phi.is_empty() {
        cx.error_spanned_by(
            &closure.body,
            "no constraint: list at least one, `[<φ_1>, ...]`",
        );
        return None;
    }
    Some(phi)
}

/// The constrained steppers of one system.
pub struct ConstrainedCode {
    /// Number of constraints `m`.
    pub m: usize,
    /// `φ(q)` over `Q0`.
    pub phi: Vec<NodeId>,
    /// The unreduced position step in `z = (q_{k+1}, λ)`.
    pub position: Stepper,
    /// The unreduced projection in `y = (v_{k+1}, ν)`; its update is the projected `p_{k+1}`.
    pub projection: Stepper,
    /// Each reduced side's position step in `z = (x_{k+1}, u, λ)` and projection in
    /// `y = (v, ν)` (update: the projected `w_{k+1}`).
    pub plus: (Stepper, Stepper),
    pub minus: (Stepper, Stepper),
}

/// `Σ_j λ_j ∂φ_j/∂var(i)` for each `i < n`: the constraint force.
fn constraint_force(g: &mut Graph, phi: &[NodeId], var: fn(usize) -> Sym, n: usize) -> Vec<NodeId> {
    let columns: Vec<Vec<NodeId>> = (0..n).map(|i| derivatives(g, phi, var(i))).collect();
    (0..n)
        .map(|i| {
            let mut f = g.constant(0.0);
            for (j, &d) in columns[i].iter().enumerate() {
                let l = g.var(Sym::Lambda(j));
                let t = g.mul(l, d);
                f = g.add(f, t);
            }
            f
        })
        .collect()
}

/// `φ` with `from(i)` replaced by `to(i)` (and the group coordinates of `Q0` by 0 when
/// `reduced`: a G-invariant constraint does not read them).
fn substituted(
    g: &mut Graph,
    phi: &[NodeId],
    s: usize,
    reduced: bool,
    to: fn(usize) -> Sym,
) -> Vec<NodeId> {
    phi.iter()
        .map(|&p| {
            g.substitute(p, &mut |g, sym| match sym {
                Sym::Q0(i) if reduced && i >= s => g.constant(0.0),
                Sym::Q0(i) => g.var(to(i)),
                other => g.var(other),
            })
        })
        .collect()
}

/// The constrained steppers from the unconstrained ones (see the module documentation).
#[allow(clippy::too_many_arguments)] // one call site
pub fn construct(
    g: &mut Graph,
    phi: Vec<NodeId>,
    unreduced: &Stepper,
    plus: &Stepper,
    minus: &Stepper,
    continuous: &Continuous,
    b: &[Vec<NodeId>],
    s: usize,
    k: usize,
) -> ConstrainedCode {
    let n = s + k;
    let m = phi.len();
    let lambdas: Vec<Sym> = (0..m).map(Sym::Lambda).collect();
    // Unreduced position step.
    let force = constraint_force(g, &phi, Sym::Q0, n);
    let mut residual: Vec<NodeId> = (0..n)
        .map(|i| g.sub(unreduced.residual[i], force[i]))
        .collect();
    residual.extend(substituted(g, &phi, s, false, Sym::Q1));
    let unknowns: Vec<Sym> = (0..n).map(Sym::Q1).chain(lambdas.clone()).collect();
    let position = system(
        g,
        residual,
        &unknowns,
        unreduced.momentum.clone(),
        Vec::new(),
    );
    // Unreduced projection: data q_{k+1} (Q0) and the SHAKE momentum (P); unknowns v (Q1), ν.
    let projection = {
        let mut rows: Vec<NodeId> = (0..n)
            .map(|i| {
                let p = g.var(Sym::P(i));
                let r = g.sub(continuous.legendre[i], force[i]);
                g.sub(r, p)
            })
            .collect();
        rows.extend(tangency(g, &phi, Sym::Q0, n));
        system(g, rows, &unknowns, continuous.legendre.clone(), Vec::new())
    };
    let reduced = |g: &mut Graph, side: Side, st: &Stepper| {
        let phi0 = substituted(g, &phi, s, true, Sym::X0);
        let force = constraint_force(g, &phi0, Sym::X0, s);
        let mut residual: Vec<NodeId> = (0..s).map(|i| g.sub(st.residual[i], force[i])).collect();
        residual.extend_from_slice(&st.residual[s..]);
        residual.extend(substituted(g, &phi, s, true, Sym::X1));
        let unknowns: Vec<Sym> = (0..s)
            .map(Sym::X1)
            .chain((0..k).map(side.group()))
            .chain(lambdas.clone())
            .collect();
        let position = system(
            g,
            residual,
            &unknowns,
            st.momentum.clone(),
            st.impulse.clone(),
        );
        // Projection at x_{k+1} (Q0 shape, group 0), data w_{k+1} (W), μ_{k+1} (Mu).
        let phi_x = substituted(g, &phi, s, true, Sym::Q0);
        let force = constraint_force(g, &phi_x, Sym::Q0, s);
        let legendre: Vec<NodeId> = continuous
            .legendre
            .iter()
            .map(|&l| {
                g.substitute(l, &mut |g, sym| match sym {
                    Sym::Q0(i) if i >= s => g.constant(0.0),
                    other => g.var(other),
                })
            })
            .collect();
        // p_x = w − Bᵀ μ; the projected w' = p'_x + Bᵀ μ.
        let bt_mu: Vec<NodeId> = (0..s)
            .map(|i| {
                let mut v = g.constant(0.0);
                for (j, row) in b.iter().enumerate() {
                    let mu = g.var(Sym::Mu(j));
                    let t = g.mul(row[i], mu);
                    v = g.add(v, t);
                }
                v
            })
            .collect();
        let mut rows: Vec<NodeId> = (0..s)
            .map(|i| {
                let w = g.var(Sym::W(i));
                let p_x = g.sub(w, bt_mu[i]);
                let r = g.sub(legendre[i], force[i]);
                g.sub(r, p_x)
            })
            .collect();
        for j in 0..k {
            let mu = g.var(Sym::Mu(j));
            rows.push(g.sub(legendre[s + j], mu));
        }
        rows.extend(tangency(g, &phi_x, Sym::Q0, s));
        let projected: Vec<NodeId> = (0..s).map(|i| g.add(legendre[i], bt_mu[i])).collect();
        let unknowns: Vec<Sym> = (0..n).map(Sym::Q1).chain(lambdas.clone()).collect();
        let projection = system(g, rows, &unknowns, projected, Vec::new());
        (position, projection)
    };
    let plus = reduced(g, Side::Plus, plus);
    let minus = reduced(g, Side::Minus, minus);
    ConstrainedCode {
        m,
        phi,
        position,
        projection,
        plus,
        minus,
    }
}

/// `Dφ v = Σ_i ∂φ_j/∂var(i) · v_i` (`v_i` is `Q1(i)`), one row per constraint.
fn tangency(g: &mut Graph, phi: &[NodeId], var: fn(usize) -> Sym, n: usize) -> Vec<NodeId> {
    let columns: Vec<Vec<NodeId>> = (0..n).map(|i| derivatives(g, phi, var(i))).collect();
    (0..phi.len())
        .map(|j| {
            let mut r = g.constant(0.0);
            for (i, column) in columns.iter().enumerate() {
                let v = g.var(Sym::Q1(i));
                let t = g.mul(column[j], v);
                r = g.add(r, t);
            }
            r
        })
        .collect()
}
