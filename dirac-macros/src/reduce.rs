//! The paper's construction on the graph: the reduced Lagrangian `l_{d+}` (eq. (4.5)), the
//! residual of the reduced (+) equations (4.6) in the unknowns `z = (x_{k+1}, g_k^+)`, its exact
//! Jacobian, and the momentum update.

use crate::diff::derivatives;
use crate::graph::{Graph, NodeId, Sym};

/// Everything the (+) stepper needs, as graph nodes.
pub struct ReducedPlus {
    /// `R(z) = (∂l_{d+}/∂x0 + w_k, ∂l_{d+}/∂g1 − μ_k)`, length `N = S + K`: the third and fourth
    /// lines of eq. (4.6) (the third simplified with the fourth, see `dirac_runtime::ReducedPlus`).
    pub residual: Vec<NodeId>,
    /// `∂R/∂z`, row-major `N × N`, with `z = (x1, g1)`.
    pub jacobian: Vec<Vec<NodeId>>,
    /// `w_{k+1} = ∂l_{d+}/∂x1`, length `S`.
    pub momentum: Vec<NodeId>,
}

/// `l_{d+}(x0, x1, g1) = L_d(x0, 0, x1, g1 + h_d^0(x0, x1))` with `h_d^0(x0, x1) = B (x1 − x0)`,
/// eq. (4.5), built by substituting into the body's graph `l`.
pub fn reduced_lagrangian_plus(g: &mut Graph, l: NodeId, s: usize, b: &[Vec<NodeId>]) -> NodeId {
    g.substitute(l, &mut |g, sym| match sym {
        Sym::Q0(i) if i < s => g.var(Sym::X0(i)),
        // The reduced space fixes g0 = 0 (identification (3.10)).
        Sym::Q0(_) => g.constant(0.0),
        Sym::Q1(i) if i < s => g.var(Sym::X1(i)),
        Sym::Q1(i) => {
            let j = i - s;
            let mut v = g.var(Sym::G1(j));
            for (col, &bji) in b[j].iter().enumerate() {
                let x1 = g.var(Sym::X1(col));
                let x0 = g.var(Sym::X0(col));
                let dx = g.sub(x1, x0);
                let term = g.mul(bji, dx);
                v = g.add(v, term);
            }
            v
        }
        other => g.var(other),
    })
}

/// Differentiates `l_{d+}` for the (+) stepper of eq. (4.6): the residual, its Jacobian in the
/// unknowns `z = (x_{k+1}, g_k^+)`, and the momentum update.
pub fn plus_system(g: &mut Graph, l_plus: NodeId, s: usize, k: usize) -> ReducedPlus {
    let first = |g: &mut Graph, sym: Sym| derivatives(g, &[l_plus], sym)[0];
    let mut residual: Vec<NodeId> = (0..s)
        .map(|i| {
            let d = first(g, Sym::X0(i));
            let w = g.var(Sym::W(i));
            g.add(d, w)
        })
        .collect();
    residual.extend((0..k).map(|j| {
        let d = first(g, Sym::G1(j));
        let mu = g.var(Sym::Mu(j));
        g.sub(d, mu)
    }));
    let momentum = (0..s).map(|i| first(g, Sym::X1(i))).collect();
    let unknowns: Vec<Sym> = (0..s).map(Sym::X1).chain((0..k).map(Sym::G1)).collect();
    // Forward mode: one pass per unknown gives one column of the Jacobian.
    let columns: Vec<Vec<NodeId>> = unknowns
        .iter()
        .map(|&z| derivatives(g, &residual, z))
        .collect();
    let n = s + k;
    let jacobian = (0..n)
        .map(|r| (0..n).map(|c| columns[c][r]).collect())
        .collect();
    ReducedPlus {
        residual,
        jacobian,
        momentum,
    }
}
