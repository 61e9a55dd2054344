//! Forces (beyond the paper, which treats only conservative systems): the attribute's
//! `force = |dq| W` (continuous) or `force = |dq0, dq1| W` (discrete) is the virtual work of the
//! forces, linear in the virtual displacements; its derivatives in them are the forces.
//!
//! # The forced discrete equations
//!
//! The discrete Lagrange–d'Alembert principle (Marsden & West, "Discrete mechanics and
//! variational integrators", §3.2) adds to the variation of the discrete action the virtual work
//! of the discrete forces, `δ Σ L_d(q_k, q_{k+1}) + Σ [⟨f_d^−(q_k, q_{k+1}), δq_k⟩ +
//! ⟨f_d^+(q_k, q_{k+1}), δq_{k+1}⟩] = 0`, which in position–momentum form is the forced discrete
//! Lagrange–Dirac step
//!
//! ```text
//! p_k     = −D1 L_d(q_k, q_{k+1}) − f_d^−(q_k, q_{k+1})
//! p_{k+1} =  D2 L_d(q_k, q_{k+1}) + f_d^+(q_k, q_{k+1}).
//! ```
//!
//! A discrete body states `W = ⟨f_d^−, dq0⟩ + ⟨f_d^+, dq1⟩`, so `f_d^− = ∂W/∂dq0` and
//! `f_d^+ = ∂W/∂dq1`. A continuous body states `W = ⟨F(q, v), dq⟩`, and the declared rule forms
//! the discrete forces by applying its own quadrature to the continuous virtual work
//! `∫ ⟨F(q, q̇), δq⟩ dt` with `δq` interpolated linearly over the step (`v = (q1 − q0)/h`):
//!
//! ```text
//! midpoint   f_d^− = f_d^+ = (h/2) F((q0 + q1)/2, v)
//! trapezoid  f_d^− = (h/2) F(q0, v),  f_d^+ = (h/2) F(q1, v)
//! left       f_d^− = h F(q0, v),      f_d^+ = 0
//! right      f_d^− = 0,               f_d^+ = h F(q1, v)
//! ```
//!
//! The reduced forced equations and the forced discrete Noether balance are derived in
//! [`crate::ir::reduce`]. Controls are parameters (`controls(u)`); the forces read them like any
//! other parameter.

use std::ops::Not;

use syn::spanned::Spanned;
use syn::{ExprClosure, Pat};

use crate::ctxt::Ctxt;
use crate::front::rule::Rule;
use crate::ir::diff::derivatives;
use crate::ir::discretize::{at_point, difference_quotients, midpoint};
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};

/// The discrete forces `f_d^−(q0, q1)` and `f_d^+(q0, q1)`, one node per configuration
/// component, over `Sym::Q0`, `Sym::Q1` and the parameters.
#[derive(Clone, Debug)]
pub struct Forces {
    pub minus: Vec<NodeId>,
    pub plus: Vec<NodeId>,
}

/// How the virtual work is read: a continuous force `F(q, v)` formed into `f_d^±` by `rule`
/// with the time step `h`, or the discrete forces directly.
#[derive(Clone, Copy)]
pub enum Form {
    Continuous { rule: Rule, h: NodeId },
    Discrete,
}

/// Lowers `force = |..| W` and differentiates `W` in its virtual displacements; `None` after
/// errors, all recorded in `cx`. `names` are the body's names (configurations, coordinates,
/// parameters); `n` is the configuration dimension.
pub fn lower(
    cx: &Ctxt,
    g: &mut Graph,
    closure: &ExprClosure,
    names: Names,
    n: usize,
    form: Form,
) -> Option<Forces> {
    let parts = lower_parts(cx, g, closure, names, n, matches!(form, Form::Discrete))?;
    Some(match form {
        Form::Discrete => Forces {
            minus: parts[0].clone(),
            plus: parts[1].clone(),
        },
        Form::Continuous { rule, h } => discretize(g, &parts[0], n, h, rule),
    })
}

/// Lowers `force = |..| W` and differentiates `W` in its `n` virtual displacements of each
/// argument: `[∂W/∂dq]` (`discrete` false: `|dq|`) or `[∂W/∂dq0, ∂W/∂dq1]`, with `W` checked
/// to be linear in them; `None` after errors, all recorded in `cx`.
pub fn lower_parts(
    cx: &Ctxt,
    g: &mut Graph,
    closure: &ExprClosure,
    names: Names,
    n: usize,
    discrete: bool,
) -> Option<Vec<Vec<NodeId>>> {
    let expected = if discrete { 2 } else { 1 };
    let dq = closure_args(cx, closure, expected)?;
    let names = Names { dq, ..names };
    let w = Lowering::new(g, cx, &names).scalar_expr(&closure.body, "the virtual work")?;
    parts_of(cx, g, w, n, expected, &closure.body)
}

/// The forces of the lowered virtual work `w`: its derivatives in the `n` virtual displacements
/// of each of its `expected` arguments, with `w` checked to be linear in them (errors at `at`).
pub fn parts_of(
    cx: &Ctxt,
    g: &mut Graph,
    w: NodeId,
    n: usize,
    expected: usize,
    at: &dyn quote::ToTokens,
) -> Option<Vec<Vec<NodeId>>> {
    let displacement: [fn(usize) -> Sym; 2] = [Sym::D0, Sym::D1];
    let parts: Vec<Vec<NodeId>> = displacement[..expected]
        .iter()
        .map(|&d| (0..n).map(|i| derivatives(g, &[w], d(i))[0]).collect())
        .collect();
    let all: Vec<NodeId> = parts.iter().flatten().copied().collect();
    let is_displacement = |s: &Sym| matches!(s, Sym::D0(_) | Sym::D1(_));
    if g.symbols(&all).iter().any(is_displacement) {
        cx.error_spanned_by(
            at.to_token_stream(),
            "the virtual work must be linear in the virtual displacements: write it as `⟨F, dq⟩`, a sum of terms \
             `F_i * dq.x` whose factors `F_i` do not read `dq` (a force may depend on the configurations, the \
             velocities and the parameters, not on the virtual displacement)",
        );
        return None;
    }
    if !vanishes_without_displacement(g, w) {
        cx.error_spanned_by(
            at.to_token_stream(),
            "every term of the virtual work must be multiplied by a virtual displacement: at `dq = 0` it is not \
             zero, so a term such as `c * v.x` lacks its `* dq.x`",
        );
        return None;
    }
    Some(parts)
}

/// The closure's argument names, `expected` of them, each a plain name or `name: Config`.
pub fn closure_args(cx: &Ctxt, closure: &ExprClosure, expected: usize) -> Option<Vec<syn::Ident>> {
    let accepted = "accepted: `force = |dq| <virtual work>` for a continuous Lagrangian, \
                    `force = |dq0, dq1| <virtual work>` for a discrete one";
    let mut ok = true;
    if let Some(m) = &closure.capture {
        cx.error_spanned_by(m, format!("`move` has no meaning here; {accepted}"));
        ok = false;
    }
    if let Some(a) = &closure.asyncness {
        cx.error_spanned_by(
            a,
            format!("an `async` closure is not a virtual work; {accepted}"),
        );
        ok = false;
    }
    if let syn::ReturnType::Type(_, ty) = &closure.output {
        cx.error_spanned_by(
            ty,
            format!("the virtual work is an f64; leave out the return type; {accepted}"),
        );
        ok = false;
    }
    if closure.inputs.len() != expected {
        let what = if expected == 1 {
            "a continuous Lagrangian's force takes one virtual displacement, `|dq|`, and the rule forms the discrete forces"
        } else {
            "a discrete Lagrangian's force takes the virtual displacements of both configurations, `|dq0, dq1|`: \
             `W = ⟨f_d^−, dq0⟩ + ⟨f_d^+, dq1⟩`"
        };
        let at = closure
            .inputs
            .first()
            .map_or_else(|| closure.or1_token.span(), |_| closure.inputs.span());
        cx.error_at(
            at,
            format!("{what}; found {} argument(s)", closure.inputs.len()),
        );
        return None;
    }
    let mut names = Vec::new();
    for input in &closure.inputs {
        let (pat, ty) = match input {
            Pat::Type(t) => (&*t.pat, Some(&*t.ty)),
            other => (other, None),
        };
        if let Some(ty) = ty {
            let is_config =
                matches!(ty, syn::Type::Path(p) if p.qself.is_none() && p.path.is_ident("Config"));
            if !is_config {
                cx.error_spanned_by(
                    ty,
                    "a virtual displacement has the type of a configuration: write `dq` or `dq: Config`",
                );
                ok = false;
            }
        }
        match pat {
            Pat::Ident(p) if p.by_ref.is_none() && p.mutability.is_none() && p.subpat.is_none() => {
                names.push(p.ident.clone())
            }
            other => {
                cx.error_spanned_by(
                    other,
                    format!("expected a plain name for the virtual displacement; {accepted}"),
                );
                ok = false;
            }
        }
    }
    ok.then_some(names)
}

/// Whether `W` is zero with every virtual displacement zero, at a few points (`NaN`s skipped: a
/// point outside the force's domain says nothing).
fn vanishes_without_displacement(g: &mut Graph, w: NodeId) -> bool {
    let at_zero = g.substitute(w, &mut |g, sym| match sym {
        Sym::D0(_) | Sym::D1(_) => g.constant(0.0),
        other => g.var(other),
    });
    if g.as_const(at_zero) == Some(0.0) {
        return true;
    }
    [0.37, -0.81, 1.3].iter().all(|&c| {
        let v = g.eval(&[at_zero], &|sym| match sym {
            Sym::Q0(i) => c + 0.11 * i as f64,
            Sym::Q1(i) => 0.7 * c - 0.13 * i as f64,
            // Parameters are sampled positive, as the invariance check does.
            Sym::Param(i) => 0.9 + 0.07 * i as f64 + 0.1 * c.abs(),
            _ => c,
        })[0];
        // Written so that NaN passes: outside the force's domain the point says nothing.
        (v.abs() > 1e-12).not()
    })
}

/// `f_d^±` from a continuous force `F(q, v)` (over `Q0 = q`, `Q1 = v`) by `rule` (see the
/// module documentation for the formulas and their derivation).
pub fn discretize(g: &mut Graph, f: &[NodeId], n: usize, h: NodeId, rule: Rule) -> Forces {
    let half = g.constant(0.5);
    let v = difference_quotients(g, n, h);
    // F at the configuration `point(i)` and the difference quotient, scaled by `weight`.
    let at = |g: &mut Graph, point: &dyn Fn(&mut Graph, usize) -> NodeId, weight: NodeId| {
        f.iter()
            .map(|&fi| {
                let value = at_point(g, fi, point, &v);
                g.mul(weight, value)
            })
            .collect::<Vec<NodeId>>()
    };
    let q0 = |g: &mut Graph, i: usize| g.var(Sym::Q0(i));
    let q1 = |g: &mut Graph, i: usize| g.var(Sym::Q1(i));
    let half_h = g.mul(half, h);
    let zero = g.constant(0.0);
    match rule {
        Rule::Midpoint => {
            let f_mid = at(g, &|g, i| midpoint(g, i, half), half_h);
            Forces {
                minus: f_mid.clone(),
                plus: f_mid,
            }
        }
        Rule::Trapezoid => Forces {
            minus: at(g, &q0, half_h),
            plus: at(g, &q1, half_h),
        },
        Rule::Left => Forces {
            minus: at(g, &q0, h),
            plus: vec![zero; n],
        },
        Rule::Right => Forces {
            minus: vec![zero; n],
            plus: at(g, &q1, h),
        },
    }
}
