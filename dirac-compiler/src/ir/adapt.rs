//! Adaptive steps: the Poincaré time transformation of a continuous Lagrangian, made
//! variational with physical time as a coordinate (`time(t), adapt = |q| g`).
//!
//! With the fictitious time `τ`, `dt = g(q) dτ` (Sundman, Poincaré; Hairer 1997), the
//! Hamiltonian of an autonomous system becomes, in the extended phase space `(q, t, p, p_t)`,
//! `K = g(q) (H(q, p) + p_t)`, whose flow on the level set `K = 0` is the physical flow
//! reparametrized, with `t' = g(q)` and `p_t = −H`. `K` is degenerate in `p_t`, so it has no
//! Lagrangian; its regularization
//!
//! ```text
//! K₂ = g (H + p_t) + (c/2) g (H + p_t)²        (c = 1)
//! ```
//!
//! has the same level set, invariant and with the same flow on it (the added term vanishes there
//! with its gradient), `p_t` conserved (`K₂` does not read `t`), and is regular. Its Legendre
//! transform, maximizing over `p_t` then over `p`, is
//!
//! ```text
//! L₂(q, t, q', t') = t' L(q, q'/t') + (t' − g(q))² / (2 c g(q)),
//! ```
//!
//! the physical Lagrangian made homogeneous in the extended velocity, plus a term that vanishes
//! on the solutions (`t' = g`) and pins the step. Its momenta are the physical ones,
//! `∂L₂/∂q' = ∂L/∂v (q, q'/t')`, and `∂L₂/∂t' = −E + (t'/g − 1)/c` (`= −E` on the level set).
//! Discretized by the rule at the fictitious step `ε` (the attribute's step parameter), e.g. the
//! midpoint rule, `L_d = Δt L(q̄, Δq/Δt) + (Δt − ε g(q̄))²/(2 ε g(q̄))`: a step of the physical
//! discrete Lagrangian with its own size `Δt`, chosen by the dynamics so that `Δt ≈ ε g`. The
//! result is an ordinary discrete Lagrangian on `(q, t)`: every integrator applies unchanged, and
//! since `L₂` does not read `t` (a group coordinate), the reduced integrators keep `p_t = −E`
//! (with every other momentum of a symmetry the monitor respects) bit for bit, and reconstruct
//! physical time as that group coordinate.

use crate::ctxt::Ctxt;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};

/// The time-transformed Lagrangian `L₂` and the lowered monitor `g` (over `Q0`).
pub struct Adapted {
    pub lagrangian: NodeId,
    pub monitor: NodeId,
}

/// Where the time coordinate is: its configuration entry (`Q0`, `Q1` of a discrete Lagrangian)
/// and its velocity entry (`Q1` of a continuous one). The same on flat coordinates; on rotation
/// groups a rotation's 9 entries carry 3 velocities, so they differ.
#[derive(Clone, Copy)]
pub struct TimeAt {
    pub point: usize,
    pub velocity: usize,
}

/// The declared time coordinate: its name as written, the monitor `|q| g(q)` and where it is.
pub struct Declared<'a> {
    pub name: &'a syn::Ident,
    pub monitor: &'a syn::ExprClosure,
    pub at: TimeAt,
}

/// Lowers the monitor (`|q| g(q)`) and transforms the continuous Lagrangian `l` (over
/// `q = Q0`, `v = Q1`) with the declared time coordinate `time`; `is_group(i)`
/// tells whether configuration entry `i` belongs to a group coordinate. `None` after errors,
/// all recorded in `cx`: a monitor that reads a group coordinate (it would break that symmetry
/// and make the step depend on the origin of time), and a Lagrangian that reads the time
/// coordinate or its rate (the system must be autonomous).
pub fn transform(
    cx: &Ctxt,
    g: &mut Graph,
    l: NodeId,
    time: &Declared,
    names: Names,
    is_group: &dyn Fn(usize) -> bool,
) -> Option<Adapted> {
    let (closure, name) = (time.monitor, time.name);
    let arg = crate::ir::constraint::args(
        cx,
        closure,
        1,
        "the monitor takes the configuration alone: `adapt = |q| <g(q)>`",
    )?;
    let unused = syn::Ident::new("__dirac_no_velocity", proc_macro2::Span::call_site());
    let names = Names {
        q0: &arg[0],
        q1: &unused,
        ..names
    };
    let monitor = Lowering::new(g, cx, &names).scalar_expr(&closure.body, "the monitor")?;
    if g.symbols(&[monitor])
        .iter()
        .any(|sym| matches!(sym, Sym::Q0(i) if is_group(*i)))
    {
        monitor_reads_group(cx, closure);
        return None;
    }
    if reads_time(g, &[l], time.at) {
        cx.error_spanned_by(
            name,
            format!(
                "the Lagrangian reads the time coordinate `{}` or its rate: adaptive steps transform an autonomous \
                 Lagrangian, whose energy is conserved; leave `{0}` out of the body",
                name
            ),
        );
        return None;
    }
    let time = time.at.velocity;
    // L₂ = t' L(q, v/t') + (t' − g)² / (2 g).
    let rate = g.var(Sym::Q1(time));
    let scaled = g.substitute(l, &mut |g, sym| match sym {
        Sym::Q1(i) if i != time => {
            let v = g.var(Sym::Q1(i));
            g.div(v, rate)
        }
        other => g.var(other),
    });
    let homogeneous = g.mul(rate, scaled);
    let gap = g.sub(rate, monitor);
    let gap2 = g.mul(gap, gap);
    let two = g.constant(2.0);
    let den = g.mul(two, monitor);
    let pin = g.div(gap2, den);
    Some(Adapted {
        lagrangian: g.add(homogeneous, pin),
        monitor,
    })
}

/// The force of a continuous `F(q, v)` (one node per component, over `q = Q0`, `v = Q1`) in the
/// fictitious time of [`transform`]: the virtual work `F·δq dt` of a physical path whose time is
/// varied too, `δq_phys = δq − q̇ δt`, is `(t' F·δq − (F·q') δt) dτ` with `q̇ = q'/t'`, so
///
/// ```text
/// F_τ = (t' F(q, q'/t'),  −F(q, q'/t')·q')        (the last entry on the time coordinate)
/// ```
///
/// — on the time coordinate the power the force delivers, so that `p_t = −E` changes by the
/// work done (the forced Noether balance of the time translation). A force that reads the time
/// or its rate, or acts on the time coordinate itself, is an error at the closure.
pub fn transform_force(
    cx: &Ctxt,
    g: &mut Graph,
    f: &[NodeId],
    time: TimeAt,
    closure: &syn::ExprClosure,
) -> Option<Vec<NodeId>> {
    if reads_time(g, f, time) || g.as_const(f[time.velocity]) != Some(0.0) {
        cx.error_spanned_by(
            closure,
            "with adaptive steps the force may not read the time coordinate or act on it: the time \
             transformation gives it its own component, the power the force delivers",
        );
        return None;
    }
    let time = time.velocity;
    let rate = g.var(Sym::Q1(time));
    let scaled: Vec<NodeId> = f
        .iter()
        .map(|&fi| {
            g.substitute(fi, &mut |g, sym| match sym {
                Sym::Q1(i) if i != time => {
                    let v = g.var(Sym::Q1(i));
                    g.div(v, rate)
                }
                other => g.var(other),
            })
        })
        .collect();
    let mut out: Vec<NodeId> = scaled.iter().map(|&fi| g.mul(rate, fi)).collect();
    let mut power = g.constant(0.0);
    for (i, &fi) in scaled.iter().enumerate() {
        if i != time {
            let v = g.var(Sym::Q1(i));
            let term = g.mul(fi, v);
            power = g.add(power, term);
        }
    }
    out[time] = g.neg(power);
    Some(out)
}

/// Whether `nodes` read the time coordinate or its rate.
fn reads_time(g: &Graph, nodes: &[NodeId], time: TimeAt) -> bool {
    g.symbols(nodes).iter().any(|sym| {
        matches!(sym, Sym::Q0(i) if *i == time.point)
            || matches!(sym, Sym::Q1(i) if *i == time.velocity)
    })
}

/// The error of a monitor that reads a group coordinate.
pub fn monitor_reads_group(cx: &Ctxt, closure: &syn::ExprClosure) {
    cx.error_spanned_by(
        &closure.body,
        "the monitor reads a group coordinate: it must be a function of the shape coordinates, so that the \
         symmetry of each group coordinate (time included) is kept and its momentum with it",
    );
}

/// Whether `monitor` (over `Q0` with `s` shape and `k` group coordinates, and parameters)
/// changes when the group coordinates are translated: sampled at three configurations and two
/// translations of each group coordinate (to `1e-9` relative), for layouts whose coordinates
/// are sums of adapted ones.
pub fn varies_with_group(g: &Graph, monitor: NodeId, s: usize, k: usize) -> bool {
    (0..3).any(|sample| {
        let t = f64::from(sample);
        let value = |shift: Option<(usize, f64)>| {
            g.eval(&[monitor], &|sym| match sym {
                Sym::Q0(i) => {
                    let by = shift.filter(|&(at, _)| at == i).map_or(0.0, |(_, a)| a);
                    0.4 + 0.13 * i as f64 + 0.21 * t + by
                }
                Sym::Param(i) => 0.9 + 0.07 * i as f64 + 0.1 * t,
                _ => 0.3 + 0.05 * t,
            })[0]
        };
        let at = value(None);
        (s..s + k).any(|j| {
            [0.37, -1.3].iter().any(|&a| {
                let moved = value(Some((j, a)));
                (moved - at).abs() > 1e-9 * at.abs().max(moved.abs()).max(1.0)
                    || moved.is_nan() != at.is_nan()
            })
        })
    })
}
