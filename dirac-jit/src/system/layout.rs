//! Where each program of a system on vector spaces reads its inputs: the layouts that map a
//! leaf of the compiler's graph (a parameter, a coordinate of `q_k`, `x_{k+1}`, a multiplier, ...)
//! to the argument array and index the machine code loads it from.

use dirac_compiler::program::Leaf;

/// `L_d`, the connection, the Legendre map and the energy: `q0` (or `q`) in `a`, `q1` (or `v`)
/// in `b`.
pub(crate) fn ld_layout(leaf: Leaf) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::Q0(i) => (1, i),
        Leaf::Q1(i) => (2, i),
        other => unreachable!("L_d does not read {other:?}"),
    }
}

/// The monitor `g(x)` of adaptive steps: the shape `x` (`S` entries) in `a`.
pub(super) fn monitor_layout(leaf: Leaf, s: usize) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::Q0(i) if i < s => (1, i),
        other => unreachable!("the monitor reads the shape and the parameters, not {other:?}"),
    }
}

/// `l_{d±}(x0, x1, u)`: `x0`, `x1`, `u` in `a`, `b`, `c`.
pub(super) fn reduced_lagrangian_layout(leaf: Leaf) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::X0(i) => (1, i),
        Leaf::X1(i) => (2, i),
        Leaf::U(j) => (3, j),
        other => unreachable!("a reduced Lagrangian does not read {other:?}"),
    }
}

/// A reduced step of a system of `s` shape and `n` coordinates: `x_k`, `w_k`, `μ_k` in `a`,
/// `b`, `c`, the unknowns `z = (x_{k+1}, u)` in `d`. A constrained step reads its state the same
/// way (the projection reads the shape of `q_{k+1}` as `Q0`) and its unknowns `(x_{k+1}, u, λ)`
/// or `(v, ν)` in `d`.
pub(super) fn reduced_layout(leaf: Leaf, s: usize, n: usize) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::X0(i) => (1, i),
        Leaf::Q0(i) if i < s => (1, i),
        Leaf::W(i) => (2, i),
        Leaf::Mu(j) => (3, j),
        Leaf::X1(i) | Leaf::Q1(i) => (4, i),
        Leaf::U(j) => (4, s + j),
        Leaf::Lambda(j) => (4, n + j),
        other => unreachable!("a reduced step does not read {other:?}"),
    }
}

/// An unreduced step: `q_k`, `p_k`, the unknown `z` in `a`, `b`, `c`.
pub(super) fn unreduced_layout(leaf: Leaf) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::Q0(i) => (1, i),
        Leaf::P(i) => (2, i),
        Leaf::Q1(i) => (3, i),
        other => unreachable!("an unreduced step does not read {other:?}"),
    }
}
