//! The Lie group variational step of a system on rotation groups (`dirac::runtime::lie`), on
//! the graph: the chart `φ_{q_k}(z)` centred at the current point (scalars `x + z`, rotations
//! `R cay(z)`, directions by the sphere's retraction with their frame carried along), the residual
//! `R(z) = D1 L_d(q_k, φ(z)) · dφ_{q_k}(0) + p_k` with its exact Jacobian in `z`, and the
//! momentum update `p_{k+1} = D2 L_d(q_k, φ(z)) · dφ_{φ(z)}(0)`.
//!
//! Both are derivatives at the centre of a chart (`φ_q(ξ)` at `ξ = 0`), taken on the graph: for a
//! rotation `dφ(0) η = R η̂`, for a direction `dφ(0)(a, b) = a e1 + b e2`.

use crate::ast::lie::{Kind, LieSpec};
use crate::ast::rule::Rule;
use crate::ir::diff::derivatives;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::reduce::{firsts, Mode, Stepper};

mod check;
mod partials;

pub use check::{check_rotations, check_skew, check_translations};
pub use partials::{partials, LiePartials};

/// `L_d` from a continuous `L(q, v)` by `rule`, with the velocity of each coordinate over the
/// step: a scalar's `(x1 − x0)/h`, a direction's chord `(n1 − n0)/h`, and a rotation's body
/// angular velocity `Ω = cay⁻¹(F)/h`, `F = R0ᵀ R1` (the relative rotation, [`Sym::Rel`]), with
/// the inverse Cayley map `cay⁻¹(F) = 2 vee(F − Fᵀ)/(1 + tr F)` (exact: for `F = cay(ξ)`,
/// `vee(F − Fᵀ) = 2α ξ` and `1 + tr F = 4α` with `α = 4/(4 + |ξ|²)`; smooth wherever
/// `tr F > −1`, i.e. for every rotation by less than π).
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
    let mut velocity = vec![None; spec.velocity_len()];
    let inv_h = {
        let one = g.constant(1.0);
        g.div(one, h)
    };
    for c in &spec.coords {
        let (p, v) = (c.point, c.velocity);
        let rate = |g: &mut Graph, i: usize| {
            let (a, b) = (g.var(Sym::Q1(i)), g.var(Sym::Q0(i)));
            let d = g.sub(a, b);
            g.mul(d, inv_h)
        };
        match c.kind {
            Kind::Scalar => velocity[v] = Some(rate(g, p)),
            Kind::Direction => {
                for (k, i) in [p + 2, p + 5, p + 8].into_iter().enumerate() {
                    velocity[v + k] = Some(rate(g, i));
                }
            }
            Kind::Rotation => {
                let f = |g: &mut Graph, i: usize, j: usize| g.var(Sym::Rel(p + 3 * i + j));
                let diagonal: Vec<NodeId> = (0..3).map(|i| f(g, i, i)).collect();
                let one = g.constant(1.0);
                let t01 = g.add(diagonal[0], diagonal[1]);
                let trace = g.add(t01, diagonal[2]);
                let den = g.add(one, trace);
                let two = g.constant(2.0);
                for (k, (a, b)) in [((2, 1), (1, 2)), ((0, 2), (2, 0)), ((1, 0), (0, 1))]
                    .into_iter()
                    .enumerate()
                {
                    let (x, y) = (f(g, a.0, a.1), f(g, b.0, b.1));
                    let d = g.sub(x, y);
                    let num = g.mul(two, d);
                    let xi = g.div(num, den);
                    velocity[v + k] = Some(g.mul(xi, inv_h));
                }
            }
        }
    }
    velocity
        .into_iter()
        .map(|v| v.expect("every velocity symbol is formed"))
        .collect()
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

/// A force in displacement symbols as a covector of the chart at `point`: a rotation's and a
/// scalar's components as they are, a direction's `(F·e1, F·e2)` with the frame of `point`.
fn to_chart(g: &mut Graph, spec: &LieSpec, f: &[NodeId], point: &[NodeId]) -> Vec<NodeId> {
    let mut out = Vec::with_capacity(spec.n());
    for c in &spec.coords {
        let (p, v) = (c.point, c.velocity);
        match c.kind {
            Kind::Scalar => out.push(f[v]),
            Kind::Rotation => out.extend_from_slice(&f[v..v + 3]),
            Kind::Direction => {
                for column in 0..2 {
                    let terms: Vec<NodeId> = (0..3)
                        .map(|k| g.mul(f[v + k], point[p + 3 * k + column]))
                        .collect();
                    let s01 = g.add(terms[0], terms[1]);
                    out.push(g.add(s01, terms[2]));
                }
            }
        }
    }
    out
}

/// What a system on rotation groups compiles to.
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
    let zero = g.constant(0.0);
    let mut momentum = vec![zero; spec.n()];
    for (i, c) in spec.coords.iter().enumerate() {
        let (p, ch, v) = (c.point, c.chart, c.velocity);
        match c.kind {
            Kind::Scalar if i == coord => momentum[ch] = minus_energy,
            Kind::Scalar => momentum[ch] = d[v],
            Kind::Rotation => momentum[ch..ch + 3].copy_from_slice(&d[v..v + 3]),
            Kind::Direction => {
                for a in 0..2 {
                    let mut sum = g.constant(0.0);
                    for k in 0..3 {
                        let e = g.var(Sym::Q0(p + 3 * k + a));
                        let term = g.mul(e, d[v + k]);
                        sum = g.add(sum, term);
                    }
                    momentum[ch + a] = sum;
                }
            }
        }
    }
    LieAdaptive {
        coord,
        monitor,
        momentum,
    }
}

/// `cay(x) = I + α x̂ + (α/2)(x xᵀ − |x|² I)`, `α = 4/(4 + |x|²)`, row by row.
fn cayley(g: &mut Graph, x: [NodeId; 3]) -> [[NodeId; 3]; 3] {
    let one = g.constant(1.0);
    let squares: Vec<NodeId> = x.iter().map(|&v| g.mul(v, v)).collect();
    let s01 = g.add(squares[0], squares[1]);
    let n2 = g.add(s01, squares[2]);
    let four = g.constant(4.0);
    let den = g.add(four, n2);
    let alpha = g.div(four, den);
    let half = g.constant(0.5);
    let beta = g.mul(half, alpha);
    let bn2 = g.mul(beta, n2);
    let diag = g.sub(one, bn2);
    let hat = [
        [None, Some((2, -1.0)), Some((1, 1.0))],
        [Some((2, 1.0)), None, Some((0, -1.0))],
        [Some((1, -1.0)), Some((0, 1.0)), None],
    ];
    let mut m = [[one; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let xx = g.mul(x[i], x[j]);
            let outer = g.mul(beta, xx);
            let mut e = if i == j { g.add(diag, outer) } else { outer };
            if let Some((k, sign)) = hat[i][j] {
                let t = g.mul(alpha, x[k]);
                e = if sign > 0.0 { g.add(e, t) } else { g.sub(e, t) };
            }
            m[i][j] = e;
        }
    }
    m
}

/// `a b` of 3 × 3 matrices (`a` transposed first if `ta`).
fn product(
    g: &mut Graph,
    a: &[[NodeId; 3]; 3],
    ta: bool,
    b: &[[NodeId; 3]; 3],
) -> [[NodeId; 3]; 3] {
    let mut m = *a;
    for (i, row) in m.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            let terms: Vec<NodeId> = (0..3)
                .map(|k| {
                    let x = if ta { a[k][i] } else { a[i][k] };
                    g.mul(x, b[k][j])
                })
                .collect();
            let s01 = g.add(terms[0], terms[1]);
            *e = g.add(s01, terms[2]);
        }
    }
    m
}

/// `φ_q(ξ)` at the point `base` (`P` nodes) and chart coordinates `xi` (`N` nodes).
pub fn chart(g: &mut Graph, spec: &LieSpec, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId> {
    let mut out = Vec::with_capacity(base.len());
    for c in &spec.coords {
        let (p, q) = (c.point, c.chart);
        let b = |i: usize, j: usize| base[p + 3 * i + j];
        let one = g.constant(1.0);
        // The rotation each kind multiplies its stored matrix by, on the right.
        let m: [[NodeId; 3]; 3] = match c.kind {
            Kind::Scalar => {
                out.push(g.add(base[p], xi[q]));
                continue;
            }
            Kind::Rotation => cayley(g, [xi[q], xi[q + 1], xi[q + 2]]),
            Kind::Direction => {
                // The shortest-arc rotation taking e3 to u = (a, b, 1)/√(1 + a² + b²).
                let (a, bb) = (xi[q], xi[q + 1]);
                let (a2, b2) = (g.mul(a, a), g.mul(bb, bb));
                let s1 = g.add(one, a2);
                let s2 = g.add(s1, b2);
                let r = g.fun(crate::ir::graph::Fun::Sqrt, s2);
                let s = g.div(one, r);
                let (ux, uy, uz) = (g.mul(a, s), g.mul(bb, s), s);
                let d = g.add(one, uz);
                let uxux = g.mul(ux, ux);
                let uyuy = g.mul(uy, uy);
                let uxuy = g.mul(ux, uy);
                let (t00, t11, t01) = (g.div(uxux, d), g.div(uyuy, d), g.div(uxuy, d));
                let m00 = g.sub(one, t00);
                let m11 = g.sub(one, t11);
                let m01 = g.neg(t01);
                let (nux, nuy) = (g.neg(ux), g.neg(uy));
                [[m00, m01, ux], [m01, m11, uy], [nux, nuy, uz]]
            }
        };
        let mut f = [[one; 3]; 3];
        for (i, row) in f.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                let terms: Vec<NodeId> = (0..3).map(|k| g.mul(b(i, k), m[k][j])).collect();
                let s01 = g.add(terms[0], terms[1]);
                *e = g.add(s01, terms[2]);
            }
        }
        if c.kind == Kind::Direction {
            f = orthonormal(
                g,
                f,
                [b(0, 2), b(1, 2), b(2, 2)],
                [xi[q], xi[q + 1]],
                [b(0, 0), b(1, 0), b(2, 0)],
                [b(0, 1), b(1, 1), b(2, 1)],
            );
        }
        out.extend(f.iter().flatten());
    }
    out
}

/// A direction's next frame from the carried one `f`: the point
/// `n' = (n + a e1 + b e2)/|n + a e1 + b e2|` (the sphere's retraction, so `|n'| = 1` to
/// round-off at every step whatever the frame's own round-off), `e1'` the carried first column
/// made orthogonal to `n'` and normalized, `e2' = n' × e1'`. To first order in round-off this is
/// `f` itself; it keeps the frame orthonormal over any number of steps.
fn orthonormal(
    g: &mut Graph,
    f: [[NodeId; 3]; 3],
    n: [NodeId; 3],
    ab: [NodeId; 2],
    e1: [NodeId; 3],
    e2: [NodeId; 3],
) -> [[NodeId; 3]; 3] {
    let unit = |g: &mut Graph, v: [NodeId; 3]| {
        let sq: Vec<NodeId> = v.iter().map(|&x| g.mul(x, x)).collect();
        let s01 = g.add(sq[0], sq[1]);
        let s = g.add(s01, sq[2]);
        let norm = g.fun(crate::ir::graph::Fun::Sqrt, s);
        v.map(|x| g.div(x, norm))
    };
    let w: [NodeId; 3] = std::array::from_fn(|i| {
        let t1 = g.mul(ab[0], e1[i]);
        let t2 = g.mul(ab[1], e2[i]);
        let s = g.add(n[i], t1);
        g.add(s, t2)
    });
    let n1 = unit(g, w);
    let t = [f[0][0], f[1][0], f[2][0]];
    let tn: Vec<NodeId> = (0..3).map(|i| g.mul(t[i], n1[i])).collect();
    let s01 = g.add(tn[0], tn[1]);
    let dot = g.add(s01, tn[2]);
    let perp: [NodeId; 3] = std::array::from_fn(|i| {
        let d = g.mul(dot, n1[i]);
        g.sub(t[i], d)
    });
    let u1 = unit(g, perp);
    let cross = |g: &mut Graph, i: usize, j: usize| {
        let x = g.mul(n1[i], u1[j]);
        let y = g.mul(n1[j], u1[i]);
        g.sub(x, y)
    };
    let u2 = [cross(g, 1, 2), cross(g, 2, 0), cross(g, 0, 1)];
    std::array::from_fn(|i| [u1[i], u2[i], n1[i]])
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
    for c in spec.coords.iter().filter(|c| c.kind == Kind::Rotation) {
        let q = c.chart;
        let cz = cayley(g, [z[q], z[q + 1], z[q + 2]]);
        let cx = cayley(g, [xi[q], xi[q + 1], xi[q + 2]]);
        let f0 = product(g, &cx, true, &cz);
        let f1 = product(g, &cz, false, &cx);
        for i in 0..3 {
            for j in 0..3 {
                rel_residual[c.point + 3 * i + j] = Some(f0[i][j]);
                rel_momentum[c.point + 3 * i + j] = Some(f1[i][j]);
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
        for c in spec.coords.iter().filter(|c| c.kind == Kind::Rotation) {
            let q = c.chart;
            let cz = cayley(g, [z[q], z[q + 1], z[q + 2]]);
            for (i, row) in cz.iter().enumerate() {
                for (j, &e) in row.iter().enumerate() {
                    rel_step[c.point + 3 * i + j] = Some(e);
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
    for c in spec.coords.iter().filter(|c| c.group) {
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
