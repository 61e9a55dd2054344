//! The Lie group variational step of a system on groups (`dirac::runtime::lie`), on the graph:
//! the chart `φ_{q_k}(z)` centred at the current point (each coordinate's own,
//! [`crate::ir::group`]: scalars `x + z`, rotations `R cay(z)`, directions by the sphere's
//! retraction with their frame carried along, poses `(R cay(ξ), x + v)`), the residual
//! `R(z) = D1 L_d(q_k, φ(z)) · dφ_{q_k}(0) + p_k` with its exact Jacobian in `z`, and the
//! momentum update `p_{k+1} = D2 L_d(q_k, φ(z)) · dφ_{φ(z)}(0)`.
//!
//! Both are derivatives at the centre of a chart (`φ_q(ξ)` at `ξ = 0`), taken on the graph: for a
//! rotation `dφ(0) η = R η̂`, for a direction `dφ(0)(a, b) = a e1 + b e2`.

use crate::front::rule::Rule;
use crate::ir::diff::derivatives;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::group::{cayley, product, Step};
use crate::ir::reduce::{firsts, Mode, Stepper};

mod check;
mod partials;
mod spec;

pub use check::{check_rotations, check_skew, check_translations};
pub use partials::{partials, LiePartials};
pub use spec::LieSpec;

/// `L_d` from a continuous `L(q, v)` by `rule`, with the velocity of each coordinate over the
/// step ([`crate::ir::group::Group::velocity`]): a scalar's `(x1 − x0)/h`, a direction's chord
/// `(n1 − n0)/h`, a rotation's body angular velocity `Ω = cay⁻¹(F)/h` of its relative rotation
/// `F = R0ᵀ R1` ([`Sym::Rel`]), a pose's `Ω` and spatial `(x1 − x0)/h`.
///
/// * trapezoid: `L_d = h/2 (L(q0, v) + L(q1, v))`, symmetric (`v` changes sign with `h` and
///   with the order of the points), so of order 2;
/// * left, right: `h L(q0, v)`, `h L(q1, v)`, of order 1.
///
/// The lowered `L` reads the configuration as `Q0` and the velocity as `Q1` (indexed by the
/// coordinates' velocity offsets).
pub fn discretize(g: &mut Graph, spec: &LieSpec, l: NodeId, rule: Rule, h: NodeId) -> NodeId {
    let v = velocities(g, spec, h);
    match rule {
        Rule::Left => {
            let l0 = at_end(g, l, 0, &v);
            g.mul(h, l0)
        }
        Rule::Right => {
            let l1 = at_end(g, l, 1, &v);
            g.mul(h, l1)
        }
        Rule::Trapezoid | Rule::Midpoint => {
            let (l0, l1) = (at_end(g, l, 0, &v), at_end(g, l, 1, &v));
            let sum = g.add(l0, l1);
            let half = g.constant(0.5);
            let hh = g.mul(half, h);
            g.mul(hh, sum)
        }
    }
}

/// The discrete forces `(f_d^−, f_d^+)` of a continuous force `F(q, v)` (one node per
/// displacement symbol) by the rule's own quadrature of the virtual work, as for ordinary
/// coordinates: trapezoid `(h/2) F(q0, v)`, `(h/2) F(q1, v)`; left `h F(q0, v)`, 0; right 0,
/// `h F(q1, v)`.
pub fn discretize_force(
    g: &mut Graph,
    spec: &LieSpec,
    f: &[NodeId],
    rule: Rule,
    h: NodeId,
) -> (Vec<NodeId>, Vec<NodeId>) {
    let v = velocities(g, spec, h);
    let zero = g.constant(0.0);
    let half = g.constant(0.5);
    let half_h = g.mul(half, h);
    let scaled = |g: &mut Graph, end: usize, w: NodeId| -> Vec<NodeId> {
        f.iter()
            .map(|&fi| {
                let at = at_end(g, fi, end, &v);
                g.mul(w, at)
            })
            .collect()
    };
    match rule {
        Rule::Left => (scaled(g, 0, h), vec![zero; f.len()]),
        Rule::Right => (vec![zero; f.len()], scaled(g, 1, h)),
        Rule::Trapezoid | Rule::Midpoint => (scaled(g, 0, half_h), scaled(g, 1, half_h)),
    }
}

/// Each coordinate's velocity over the step, by velocity symbol.
fn velocities(g: &mut Graph, spec: &LieSpec, h: NodeId) -> Vec<NodeId> {
    let inv_h = {
        let one = g.constant(1.0);
        g.div(one, h)
    };
    let mut velocity = Vec::with_capacity(spec.velocity_len());
    for c in &spec.coords {
        let block = |g: &mut Graph, sym: fn(usize) -> Sym| -> Vec<NodeId> {
            (c.point..c.point + c.kind.point_len())
                .map(|i| g.var(sym(i)))
                .collect()
        };
        let (q0, q1) = (block(g, Sym::Q0), block(g, Sym::Q1));
        let rel: Vec<NodeId> = match c.kind.rotation() {
            Some(at) => (0..9).map(|i| g.var(Sym::Rel(c.point + at + i))).collect(),
            None => Vec::new(),
        };
        let step = Step {
            q0: &q0,
            q1: &q1,
            rel: &rel,
            inv_h,
        };
        velocity.extend(c.kind.velocity(g, &step));
    }
    velocity
}

/// `node` over `q = Q0` and the velocity symbols `Q1`, at the end `end` of the step (`q0` or
/// `q1`) with the velocities `v`.
fn at_end(g: &mut Graph, node: NodeId, end: usize, v: &[NodeId]) -> NodeId {
    g.substitute(node, &mut |g, sym| match sym {
        Sym::Q0(i) if end == 1 => g.var(Sym::Q1(i)),
        Sym::Q1(i) => v[i],
        other => g.var(other),
    })
}

/// A covector in velocity components (a force in displacement symbols, a momentum `∂L/∂v`) as
/// a covector of the chart at `point` ([`crate::ir::group::Group::covector`]): a rotation's and
/// a scalar's components as they are, a direction's `(F·e1, F·e2)` with the frame of `point`.
fn to_chart(g: &mut Graph, spec: &LieSpec, f: &[NodeId], point: &[NodeId]) -> Vec<NodeId> {
    let mut out = Vec::with_capacity(spec.n());
    for c in &spec.coords {
        let (p, v) = (c.point, c.velocity);
        let f = &f[v..v + c.kind.velocity_len()];
        out.extend(c.kind.covector(g, f, &point[p..p + c.kind.point_len()]));
    }
    out
}

/// What a system on groups compiles to.
pub struct LieCode {
    /// `L_d` over the points `Q0`, `Q1` and the relative rotations `Rel`.
    pub lagrangian: NodeId,
    /// `φ_{q_k}(z)`: the next point, `P` entries.
    pub retract: Vec<NodeId>,
    /// The residual, its Jacobian in `z` and the momentum update.
    pub stepper: Stepper,
    /// The partial derivatives for the step's sensitivities (dense systems only).
    pub partials: Option<LiePartials>,
    /// The reduced step of a system reduced by every rotation of one rotation coordinate.
    pub reduced: Option<Stepper>,
    /// Whether the forces act on a coordinate the declared symmetry rotates (then its momentum
    /// obeys a forced balance rather than being constant).
    pub symmetry_forced: bool,
    /// Adaptive steps: the monitor and the state on the level set ([`adaptive`]).
    pub adapt: Option<LieAdaptive>,
}

/// What adaptive steps add to a system on rotation groups, over the configuration `Q0` and the
/// physical velocity `Q1` (the velocity symbols of the continuous Lagrangian).
pub struct LieAdaptive {
    /// The index of the time coordinate among the coordinates.
    pub coord: usize,
    /// The monitor `g(q)`.
    pub monitor: NodeId,
    /// The momentum of the state at `(q, v)` on the level set, in the chart (`N` entries): the
    /// physical momenta `∂L/∂v` — a rotation's body momentum `∂L/∂Ω`, a direction's `∂L/∂ṅ`
    /// in its frame's tangent basis `(e1, e2)`, a scalar's `∂L/∂ẋ` — and on the time
    /// coordinate `p_t = −E = L − ⟨∂L/∂v, v⟩`.
    pub momentum: Vec<NodeId>,
}

/// The monitor and the level-set momentum of adaptive steps ([`LieAdaptive`]) from the user's
/// continuous `L` (before the time transformation): `L₂` has momenta `∂L/∂v (q, q'/t')` and
/// `∂L₂/∂t' = −E + (t'/g − 1)`, so the state with the fictitious velocity `(g v, t' = g)` of a
/// physical velocity `v` has the physical momenta and `p_t = −E(q, v)`, on the level set
/// `K₂ = 0` where the transformed flow is the physical one.
pub fn adaptive(
    g: &mut Graph,
    spec: &LieSpec,
    coord: usize,
    monitor: NodeId,
    l: NodeId,
) -> LieAdaptive {
    let d: Vec<NodeId> = (0..spec.velocity_len())
        .map(|v| derivatives(g, &[l], Sym::Q1(v))[0])
        .collect();
    let mut power = g.constant(0.0);
    for (v, &dv) in d.iter().enumerate() {
        let rate = g.var(Sym::Q1(v));
        let term = g.mul(dv, rate);
        power = g.add(power, term);
    }
    let minus_energy = g.sub(l, power);
    let point: Vec<NodeId> = (0..spec.p()).map(|i| g.var(Sym::Q0(i))).collect();
    let mut momentum = to_chart(g, spec, &d, &point);
    momentum[spec.coords[coord].chart] = minus_energy;
    LieAdaptive {
        coord,
        monitor,
        momentum,
    }
}

/// `φ_q(ξ)` at the point `base` (`P` nodes) and chart coordinates `xi` (`N` nodes): each
/// coordinate's chart ([`crate::ir::group::Group::chart`]) on its blocks.
pub fn chart(g: &mut Graph, spec: &LieSpec, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId> {
    let mut out = Vec::with_capacity(base.len());
    for c in &spec.coords {
        let (p, q) = (c.point, c.chart);
        let block = &base[p..p + c.kind.point_len()];
        out.extend(c.kind.chart(g, block, &xi[q..q + c.kind.chart_len()]));
    }
    out
}

/// The step's code from `L_d` (the lowered body, over the points `Q0`, `Q1` and the relative
/// rotations `Rel`): with `ξ` the chart coordinate of the point being varied,
///
/// ```text
/// R_j(z)   = ∂/∂ξ_j L_d(φ_{q_k}(ξ), φ_{q_k}(z))|_{ξ=0} + p_k,j        F = cay(ξ)ᵀ cay(z)
/// p_{k+1,j} = ∂/∂ξ_j L_d(q_k, φ_{φ_{q_k}(z)}(ξ))|_{ξ=0}               F = cay(z) cay(ξ)
/// ```
///
/// where `F` is the value of each relative rotation `R0ᵀ R1` (exact for rotations, with no
/// round-off from the stored matrices: `R_kᵀ R_k = I` is used, not computed).
///
/// With `reduced = Some(at)` — the rotation stored at point entry `at` is acted on by every
/// rotation `R ↦ g R` and `L_d` is invariant — the step is the reduced one: `R_k` is replaced by
/// the identity (`L_d(R_k, R_{k+1}) = L_d(I, R_kᵀ R_{k+1})`, the reduced Lagrangian
/// `l_d(F, ..) = L_d(I, .., F, ..)`), so the residual and the momentum update read the relative
/// rotation `F_k = cay(z)` alone; the retraction `R_{k+1} = R_k cay(z)` is then the
/// reconstruction.
pub fn compile(
    g: &mut Graph,
    spec: &LieSpec,
    l: NodeId,
    forces: Option<&(Vec<NodeId>, Vec<NodeId>)>,
    mode: Mode,
    reduced: Option<usize>,
) -> LieCode {
    let (p, n) = (spec.p(), spec.n());
    let stored: Vec<NodeId> = (0..p).map(|i| g.var(Sym::Base(i))).collect();
    let base: Vec<NodeId> = (0..p)
        .map(|i| match reduced {
            Some(at) if (at..at + 9).contains(&i) => {
                let (r, c) = ((i - at) / 3, (i - at) % 3);
                g.constant(if r == c { 1.0 } else { 0.0 })
            }
            _ => stored[i],
        })
        .collect();
    let z: Vec<NodeId> = (0..n).map(|j| g.var(Sym::Chart1(j))).collect();
    let xi: Vec<NodeId> = (0..n).map(|j| g.var(Sym::Chart0(j))).collect();
    let vary: Vec<Sym> = (0..n).map(Sym::Chart0).collect();
    let retract = chart(g, spec, &stored, &z);
    let next = chart(g, spec, &base, &z);
    // The relative rotation of each rotation coordinate, for the residual and the momentum.
    let mut rel_residual = vec![None; p];
    let mut rel_momentum = vec![None; p];
    for (at, q) in spec.rotations() {
        let cz = cayley(g, [z[q], z[q + 1], z[q + 2]]);
        let cx = cayley(g, [xi[q], xi[q + 1], xi[q + 2]]);
        let f0 = product(g, &cx, true, &cz);
        let f1 = product(g, &cz, false, &cx);
        for i in 0..3 {
            for j in 0..3 {
                rel_residual[at + 3 * i + j] = Some(f0[i][j]);
                rel_momentum[at + 3 * i + j] = Some(f1[i][j]);
            }
        }
    }
    let at_zero = |g: &mut Graph, d: NodeId| {
        g.substitute(d, &mut |g, sym| match sym {
            Sym::Chart0(_) => g.constant(0.0),
            other => g.var(other),
        })
    };
    // The residual: q_k varied along its chart.
    let varied = chart(g, spec, &base, &xi);
    let l0 = g.substitute(l, &mut |g, sym| match sym {
        Sym::Q0(i) => varied[i],
        Sym::Q1(i) => next[i],
        Sym::Rel(i) => rel_residual[i].expect("Rel reads a rotation coordinate"),
        other => g.var(other),
    });
    let residual: Vec<NodeId> = firsts(g, mode, l0, &vary)
        .into_iter()
        .enumerate()
        .map(|(j, d)| {
            let d = at_zero(g, d);
            let pj = g.var(Sym::P(j));
            g.add(d, pj)
        })
        .collect();
    // The momentum update: q_{k+1} varied along its own chart.
    let varied = chart(g, spec, &next, &xi);
    let l1 = g.substitute(l, &mut |g, sym| match sym {
        Sym::Q0(i) => base[i],
        Sym::Q1(i) => varied[i],
        Sym::Rel(i) => rel_momentum[i].expect("Rel reads a rotation coordinate"),
        other => g.var(other),
    });
    let mut momentum: Vec<NodeId> = firsts(g, mode, l1, &vary)
        .into_iter()
        .map(|d| at_zero(g, d))
        .collect();
    // The forced step: p_k = −D1 L_d − f_d^−, p_{k+1} = D2 L_d + f_d^+, each force a covector
    // of its point's chart, at (q_k, q_{k+1}) with the relative rotations cay(z).
    let mut residual = residual;
    let mut impulse = None;
    if let Some((minus, plus)) = forces {
        let mut rel_step = vec![None; p];
        for (at, q) in spec.rotations() {
            let cz = cayley(g, [z[q], z[q + 1], z[q + 2]]);
            for (i, row) in cz.iter().enumerate() {
                for (j, &e) in row.iter().enumerate() {
                    rel_step[at + 3 * i + j] = Some(e);
                }
            }
        }
        let at_step = |g: &mut Graph, f: &[NodeId]| -> Vec<NodeId> {
            f.iter()
                .map(|&fi| {
                    g.substitute(fi, &mut |g, sym| match sym {
                        Sym::Q0(i) => base[i],
                        Sym::Q1(i) => next[i],
                        Sym::Rel(i) => rel_step[i].expect("Rel reads a rotation coordinate"),
                        other => g.var(other),
                    })
                })
                .collect()
        };
        let (minus, plus) = (at_step(g, minus), at_step(g, plus));
        let minus = to_chart(g, spec, &minus, &base);
        let plus = to_chart(g, spec, &plus, &next);
        for (r, &f) in residual.iter_mut().zip(&minus) {
            *r = g.add(*r, f);
        }
        for (m, &f) in momentum.iter_mut().zip(&plus) {
            *m = g.add(*m, f);
        }
        impulse = Some((minus, plus));
    }
    // A group coordinate's momentum: the explicit discrete Noether balance
    // μ_{k+1} = μ_k + f_d^− + f_d^+ (copied without forces), which L_d's invariance makes equal
    // to D2 L_d + f_d^+ on every solution of the step, and exact in floating point.
    for c in spec.coords.iter().filter(|c| c.group()) {
        let j = c.chart;
        let mut mu = g.var(Sym::P(j));
        if let Some((minus, plus)) = &impulse {
            let f = g.add(minus[j], plus[j]);
            mu = g.add(mu, f);
        }
        momentum[j] = mu;
    }
    let columns: Vec<Vec<NodeId>> = (0..n)
        .map(|c| derivatives(g, &residual, Sym::Chart1(c)))
        .collect();
    let jacobian = (0..n)
        .map(|r| (0..n).map(|c| columns[c][r]).collect())
        .collect();
    LieCode {
        partials: None,
        reduced: None,
        symmetry_forced: false,
        adapt: None,
        lagrangian: l,
        retract,
        stepper: Stepper {
            residual,
            jacobian,
            momentum,
            impulse: Vec::new(),
        },
    }
}
