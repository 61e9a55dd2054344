//! The compile-time checks of a system on rotation groups, on sample configurations: declared
//! translations and rotations are symmetries of `L_d` and its forces, and every `vee` reads a
//! skew-symmetric matrix.

use super::LieSpec;
use crate::front::lie::SymmetryKind;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::group::cayley_value;

/// How a sample configuration is moved before the body is evaluated again.
#[derive(Clone, Copy)]
enum Move<'a> {
    /// As it is.
    None,
    /// The scalar at point entry `.0` translated by `.1` in both configurations.
    Shift(usize, f64),
    /// The coordinates whose points start at the entries `.1` moved by the rotation `.0` in both
    /// configurations ([`crate::ir::group::Group::rotate`]; their relative rotations unchanged),
    /// then a pose's position translated by `.2` (a rigid motion; zero for rotations).
    Rotate([[f64; 3]; 3], &'a [usize], [f64; 3]),
}

/// Values of the symbols at sample configuration `t`: each coordinate's sample points
/// ([`crate::ir::group::Group::sample`]) with the relative rotations `R0ᵀ R1` consistent with
/// them, velocities arbitrary, parameters positive; then moved by `moved`.
fn sampler(spec: &LieSpec, t: f64, moved: Move) -> impl Fn(Sym) -> f64 {
    let mut point = [vec![0.0; spec.p()], vec![0.0; spec.p()]];
    let mut rel = vec![0.0; spec.p()];
    for c in &spec.coords {
        let (p, len) = (c.point, c.kind.point_len());
        let [mut q0, mut q1] = c.kind.sample(t, p);
        if let Some(at) = c.kind.rotation() {
            for i in 0..3 {
                for j in 0..3 {
                    rel[p + at + 3 * i + j] = (0..3)
                        .map(|k| q0[at + 3 * k + i] * q1[at + 3 * k + j])
                        .sum();
                }
            }
        }
        match moved {
            Move::Shift(at, by) if at == p => {
                q0[0] += by;
                q1[0] += by;
            }
            Move::Rotate(g, at, a) if at.contains(&p) => {
                c.kind.rotate(&g, &mut q0);
                c.kind.rotate(&g, &mut q1);
                if len == 12 {
                    // A pose: the position, after the rotation, translated.
                    for i in 0..3 {
                        q0[9 + i] += a[i];
                        q1[9 + i] += a[i];
                    }
                }
            }
            _ => {}
        }
        point[0][p..p + len].copy_from_slice(&q0);
        point[1][p..p + len].copy_from_slice(&q1);
    }
    move |sym: Sym| match sym {
        Sym::Q0(i) => point[0].get(i).copied().unwrap_or(0.7 - 0.1 * i as f64),
        // A continuous Lagrangian reads its velocities as Q1: any values serve.
        Sym::Q1(i) => point[1].get(i).copied().unwrap_or(0.5 + 0.1 * i as f64),
        Sym::Rel(i) => rel[i],
        Sym::Param(i) => 0.9 + 0.07 * i as f64 + 0.1 * t,
        _ => 0.3 + 0.05 * t,
    }
}

/// Whether two sampled values differ beyond round-off (`1e-9` relative).
fn differ(a: f64, b: f64) -> bool {
    (a - b).abs() > 1e-9 * a.abs().max(b.abs()).max(1.0)
}

/// The rotation the checks move configurations by: a generic rotation for `SO(3)`, one by
/// 0.83 rad about the axis for rotations about an axis.
fn sample_rotation(kind: SymmetryKind) -> [[f64; 3]; 3] {
    match kind {
        SymmetryKind::Rotations | SymmetryKind::RigidMotions => cayley_value([0.7, -0.4, 1.1]),
        SymmetryKind::Axis(k) => {
            let (c, s) = (0.83_f64.cos(), 0.83_f64.sin());
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            let mut m = [[0.0; 3]; 3];
            m[k][k] = 1.0;
            (m[a][a], m[a][b], m[b][a], m[b][b]) = (c, -s, s, c);
            m
        }
    }
}

/// Checks that `L_d` and its forces are invariant under the declared rotations
/// ([`crate::front::lie::Symmetry`]): with every listed rotation and direction rotated by the same
/// `g` in both configurations, `L_d(g q0, g q1) = L_d(q0, q1)` and the virtual work is unchanged
/// — a rotation's torque `τ` (paired with the body-frame `η`) and a scalar's force the same, a
/// direction's force rotated with it, `f(g q) = g f(q)` — at three sample configurations (to
/// `1e-9` relative). A body or force that is not is a compile error at the symmetry's first
/// coordinate. The monitor of adaptive steps, `g(q)`, must be invariant too (or the momentum of
/// the symmetry is not kept): an error at its closure otherwise.
pub fn check_rotations(
    cx: &crate::ctxt::Ctxt,
    g: &Graph,
    spec: &LieSpec,
    l: NodeId,
    forces: Option<&(Vec<NodeId>, Vec<NodeId>)>,
    monitor: Option<(NodeId, &syn::ExprClosure)>,
) {
    let Some(symmetry) = &spec.symmetry else {
        return;
    };
    let rotation = sample_rotation(symmetry.kind);
    // A rigid motion also translates: by a sample vector.
    let shift = match symmetry.kind {
        SymmetryKind::RigidMotions => [0.9, -1.7, 0.6],
        _ => [0.0; 3],
    };
    let points: Vec<usize> = symmetry
        .coords
        .iter()
        .map(|(i, _)| spec.coords[*i].point)
        .collect();
    let what = match symmetry.kind {
        SymmetryKind::Rotations => format!("the rotations `{0} ↦ g {0}`", symmetry.coords[0].1),
        SymmetryKind::RigidMotions => {
            format!("the rigid motions `{0} ↦ (A, a)·{0}`", symmetry.coords[0].1)
        }
        SymmetryKind::Axis(k) => {
            let names: Vec<String> = symmetry
                .coords
                .iter()
                .map(|(_, n)| format!("`{n}`"))
                .collect();
            let together = if names.len() > 1 { " together" } else { "" };
            format!(
                "the rotations about the {}-axis of {}{together}",
                ["x", "y", "z"][k],
                names.join(", ")
            )
        }
    };
    let first = &symmetry.coords[0].1;
    let hint = match symmetry.kind {
        SymmetryKind::Rotations => format!(
            "a body in empty space reads its rotation only through `q0.{first}.transpose() * q1.{first}` and \
             body-frame vectors; a potential (gravity, a field along an axis) leaves the rotations about that \
             axis: declare `symmetry({first}, axis = z)`"
        ),
        SymmetryKind::RigidMotions => format!(
            "a body in empty space reads its pose only through the relative pose `(q0.{first}.rotation.transpose() * \
             q1.{first}.rotation, q0.{first}.rotation.transpose() * (q1.{first}.translation - q0.{first}.translation))` \
             and body-frame vectors; a potential (gravity) breaks it"
        ),
        SymmetryKind::Axis(_) => "a field along another axis, or a coordinate that the body compares with a \
             listed one but the list leaves out, breaks it; list every rotation and direction the rotations move"
            .to_string(),
    };
    let varies = |node: NodeId| {
        (0..3).any(|sample| {
            let t = sample as f64;
            let at = g.eval(&[node], &sampler(spec, t, Move::None))[0];
            let moved = g.eval(
                &[node],
                &sampler(spec, t, Move::Rotate(rotation, &points, shift)),
            )[0];
            differ(at, moved)
        })
    };
    if let Some((_, closure)) = monitor.filter(|&(m, _)| varies(m)) {
        cx.error_spanned_by(
            &closure.body,
            format!(
                "the monitor is not invariant under {what}: the step size would depend on the orientation the \
                 symmetry moves, and its momentum would not be kept; read what the rotations leave unchanged \
                 (for rotations about the z-axis, e.g. `q.{first}[(2, 2)]` or a direction's `z` component)"
            ),
        );
        return;
    }
    let lagrangian_varies = varies(l);
    let at = &symmetry.coords[0].1;
    let moved = match symmetry.kind {
        SymmetryKind::RigidMotions => "both configurations are moved by the same rigid motion",
        _ => "they are rotated by the same rotation in both configurations",
    };
    if lagrangian_varies {
        cx.error_spanned_by(
            at,
            format!(
                "the discrete Lagrangian is not invariant under {what}: its value changes when {moved}; {hint}"
            ),
        );
        return;
    }
    let Some((minus, plus)) = forces else {
        return;
    };
    // Each force node's expected value after the move: a direction's components mix by `g`.
    let force_varies = (0..3).any(|sample| {
        let t = sample as f64;
        [minus, plus].iter().any(|f| {
            let before = g.eval(f, &sampler(spec, t, Move::None));
            let after = g.eval(f, &sampler(spec, t, Move::Rotate(rotation, &points, shift)));
            spec.coords.iter().any(|c| {
                let v = c.velocity;
                let moved = points.contains(&c.point);
                (0..c.kind.velocity_len()).any(|i| {
                    // A 3-vector in space turns with the configuration; body-frame torques and
                    // scalar forces do not.
                    let turned = c
                        .kind
                        .spatial()
                        .iter()
                        .find(|&&s| moved && (s..s + 3).contains(&i));
                    let expected = match turned {
                        Some(&s) => (0..3).map(|k| rotation[i - s][k] * before[v + s + k]).sum(),
                        None => before[v + i],
                    };
                    differ(expected, after[v + i])
                })
            })
        })
    });
    if force_varies {
        cx.error_spanned_by(
            at,
            format!(
                "the force is not invariant under {what}: its virtual work changes when the configurations \
                 and the displacements are rotated together, so the momentum of the symmetry would not obey \
                 its balance; write torques in the body frame (`tau.dot(&dq.{first})`) and forces on \
                 directions with vectors that turn with them"
            ),
        );
    }
}

/// Checks that `L_d` is invariant under the translations of each `group(..)` coordinate:
/// `L_d(q0 + a e_g, q1 + a e_g) = L_d(q0, q1)` at three sample configurations and two shifts
/// `a` (to `1e-9` relative). A body that is not is a compile error at the coordinate's name.
pub fn check_translations(cx: &crate::ctxt::Ctxt, g: &Graph, spec: &LieSpec, l: NodeId) {
    for c in spec.coords.iter().filter(|c| c.group()) {
        let varies = (0..3).any(|sample| {
            let t = sample as f64;
            let at = g.eval(&[l], &sampler(spec, t, Move::None))[0];
            [0.37, -1.3].iter().any(|&a| {
                let moved = g.eval(&[l], &sampler(spec, t, Move::Shift(c.point, a)))[0];
                differ(at, moved)
            })
        });
        if varies {
            cx.error_spanned_by(
                &c.name,
                format!(
                    "the discrete Lagrangian is not invariant under translations of `{}`: its value changes when `{0}` \
                     is shifted by the same amount in both configurations; declare it in `shape(..)`, or make the \
                     body depend on `{0}` only through `q1.{0} - q0.{0}`",
                    c.name
                ),
            );
        }
    }
}

/// Checks that every `vee(&m)` of the body reads a skew-symmetric `m` (an element of `so(3)`):
/// `m + mᵀ` at three sample configurations — rotations, frames of directions and relative
/// rotations consistent with each other, scalars and velocities arbitrary, parameters
/// positive — must vanish to round-off. The runtime's `vee` takes the skew part of any matrix;
/// a body that hands it a matrix with a symmetric part has almost always mistaken one matrix for
/// another (`vee(&f)` for `vee(&(f − fᵀ))/2`), so that is a compile error at the argument.
pub fn check_skew(
    cx: &crate::ctxt::Ctxt,
    g: &Graph,
    spec: &LieSpec,
    checks: &[(Vec<NodeId>, proc_macro2::Span)],
) {
    for sample in 0..3 {
        let t = sample as f64;
        let value = sampler(spec, t, Move::None);
        for (entries, span) in checks {
            let values = g.eval(entries, &value);
            let scale = values.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
            if let Some(v) = values.iter().find(|v| v.abs() > 1e-9 * scale) {
                cx.error_at(
                    *span,
                    format!(
                        "`vee` needs a skew-symmetric matrix (an element of so(3)), but this one has a symmetric part \
                         (an entry of `m + mᵀ` is {v:.3e} at a sample configuration): write the skew part you mean, \
                         e.g. `vee(&(m - m.transpose())) * 0.5`"
                    ),
                );
                return;
            }
        }
    }
}
