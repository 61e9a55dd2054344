//! The partial derivatives of a step of a system on rotation groups, for its sensitivities.

use super::{chart, to_chart, LieSpec};
use crate::ir::diff::derivatives;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::group::{cayley, product};
use crate::ir::reduce::{firsts, Mode};

/// The partial derivatives of one step for its sensitivities, in the charts at the nominal
/// points: the step from `q' = φ_{q_k}(δ)` with the momentum `p` (in the chart at `q'`) to
/// `q'_{k+1} = φ_{q_{k+1}}(w)`, `q_{k+1} = φ_{q_k}(z̄)` the nominal step, solves
///
/// ```text
/// R̃(w; δ, p, u) = ∂/∂ξ L_d(φ_{q'}(ξ), q'_{k+1})|_0 + p + f_d^−      = 0
/// O(w; δ, u)     = ∂/∂η L_d(q', φ_{q'_{k+1}}(η))|_0 + f_d^+          (= p_{k+1})
/// ```
///
/// with every relative rotation `cay(ξ)ᵀ cay(δ)ᵀ cay(z̄) cay(w)` (resp.
/// `cay(δ)ᵀ cay(z̄) cay(w) cay(η)`), so that no product of stored rotations enters. The
/// implicit-function theorem at `δ = 0`, `w = 0` gives the derivatives of `(w, p_{k+1})` in
/// `(δ, p, u)` (the runtime's `LieIntegrator::sensitivity`). `δ` is `Sym::X0`, `w` is `Sym::X1`.
pub struct LiePartials {
    /// `∂R̃/∂w`, `∂R̃/∂δ`, `∂R̃/∂u`, `∂O/∂w`, `∂O/∂δ`, `∂O/∂u`, row-major.
    pub blocks: [Vec<Vec<NodeId>>; 6],
}

/// The [`LiePartials`] of `L_d` with its forces, `controls` the indices of the control
/// parameters.
pub fn partials(
    g: &mut Graph,
    spec: &LieSpec,
    l: NodeId,
    forces: Option<&(Vec<NodeId>, Vec<NodeId>)>,
    controls: &[usize],
    mode: Mode,
) -> LiePartials {
    let (p, n) = (spec.p(), spec.n());
    let base: Vec<NodeId> = (0..p).map(|i| g.var(Sym::Base(i))).collect();
    let var = |g: &mut Graph, f: fn(usize) -> Sym| -> Vec<NodeId> {
        (0..n).map(|j| g.var(f(j))).collect()
    };
    let (zbar, delta, w, xi) = (
        var(g, Sym::Chart1),
        var(g, Sym::X0),
        var(g, Sym::X1),
        var(g, Sym::Chart0),
    );
    let start = chart(g, spec, &base, &delta);
    let nominal = chart(g, spec, &base, &zbar);
    let next = chart(g, spec, &nominal, &w);
    // The relative rotations: (varied start)ᵀ next, start ᵀ (varied next), start ᵀ next.
    let mut rel = [vec![None; p], vec![None; p], vec![None; p]];
    for (point, q) in spec.rotations() {
        let at = |v: &[NodeId]| [v[q], v[q + 1], v[q + 2]];
        let (cd, cz, cw, cx) = (
            cayley(g, at(&delta)),
            cayley(g, at(&zbar)),
            cayley(g, at(&w)),
            cayley(g, at(&xi)),
        );
        let zw = product(g, &cz, false, &cw);
        let dzw = product(g, &cd, true, &zw);
        let residual = product(g, &cx, true, &dzw);
        let momentum = product(g, &dzw, false, &cx);
        for (slot, m) in rel.iter_mut().zip([residual, momentum, dzw]) {
            for i in 0..3 {
                for j in 0..3 {
                    slot[point + 3 * i + j] = Some(m[i][j]);
                }
            }
        }
    }
    let vary: Vec<Sym> = (0..n).map(Sym::Chart0).collect();
    let zero_vary = |g: &mut Graph, d: NodeId| {
        g.substitute(d, &mut |g, sym| match sym {
            Sym::Chart0(_) => g.constant(0.0),
            other => g.var(other),
        })
    };
    let substituted =
        |g: &mut Graph, node: NodeId, q0: &[NodeId], q1: &[NodeId], rel: &[Option<NodeId>]| {
            g.substitute(node, &mut |g, sym| match sym {
                Sym::Q0(i) => q0[i],
                Sym::Q1(i) => q1[i],
                Sym::Rel(i) => rel[i].expect("Rel reads a rotation coordinate"),
                other => g.var(other),
            })
        };
    let varied_start = chart(g, spec, &start, &xi);
    let l0 = substituted(g, l, &varied_start, &next, &rel[0]);
    let mut residual: Vec<NodeId> = firsts(g, mode, l0, &vary)
        .into_iter()
        .enumerate()
        .map(|(j, d)| {
            let d = zero_vary(g, d);
            let pj = g.var(Sym::P(j));
            g.add(d, pj)
        })
        .collect();
    let varied_next = chart(g, spec, &next, &xi);
    let l1 = substituted(g, l, &start, &varied_next, &rel[1]);
    let mut output: Vec<NodeId> = firsts(g, mode, l1, &vary)
        .into_iter()
        .map(|d| zero_vary(g, d))
        .collect();
    if let Some((minus, plus)) = forces {
        let at_step = |g: &mut Graph, f: &[NodeId]| -> Vec<NodeId> {
            f.iter()
                .map(|&fi| substituted(g, fi, &start, &next, &rel[2]))
                .collect()
        };
        let (minus, plus) = (at_step(g, minus), at_step(g, plus));
        let minus = to_chart(g, spec, &minus, &start);
        let plus = to_chart(g, spec, &plus, &next);
        for (r, f) in residual.iter_mut().zip(minus) {
            *r = g.add(*r, f);
        }
        for (o, f) in output.iter_mut().zip(plus) {
            *o = g.add(*o, f);
        }
    }
    let nominal_point = |g: &mut Graph, d: NodeId| {
        g.substitute(d, &mut |g, sym| match sym {
            Sym::X0(_) | Sym::X1(_) => g.constant(0.0),
            other => g.var(other),
        })
    };
    let jacobian = |g: &mut Graph, rows: &[NodeId], by: &[Sym]| -> Vec<Vec<NodeId>> {
        let columns: Vec<Vec<NodeId>> = by.iter().map(|&s| derivatives(g, rows, s)).collect();
        (0..rows.len())
            .map(|r| {
                (0..by.len())
                    .map(|c| nominal_point(g, columns[c][r]))
                    .collect()
            })
            .collect()
    };
    let by_w: Vec<Sym> = (0..n).map(Sym::X1).collect();
    let by_delta: Vec<Sym> = (0..n).map(Sym::X0).collect();
    let by_u: Vec<Sym> = controls.iter().map(|&i| Sym::Param(i)).collect();
    LiePartials {
        blocks: [
            jacobian(g, &residual, &by_w),
            jacobian(g, &residual, &by_delta),
            jacobian(g, &residual, &by_u),
            jacobian(g, &output, &by_w),
            jacobian(g, &output, &by_delta),
            jacobian(g, &output, &by_u),
        ],
    }
}
