//! The two implementations of each kind of coordinate agree: the chart `φ_q(z)` the compiler
//! emits from its symbolic group (`dirac-compiler/src/ir/group/`) and the runtime's numeric one
//! (`dirac::runtime::groups`), which the integrators' chart coordinates, checks and momentum
//! maps read, for a system with one coordinate of every kind.

use dirac::lie::{cayley, rows, CoordinateKind, LieLagrangian};
use dirac::prelude::*;

/// One coordinate of every kind, each with a kinetic-like term (the scalar also in a field along
/// the direction, so the terms couple); `g` enters through `g1 − g0` only, as `group(g)` needs.
#[reduced_lagrangian(shape(s), group(g), rotation(r), direction(n), pose(x))]
fn every_kind(q0: Config, q1: Config, h: f64) -> f64 {
    let (ds, dg) = (q1.s - q0.s, q1.g - q0.g);
    let f = q0.r.transpose() * q1.r;
    let fx = q0.x.rotation.transpose() * q1.x.rotation;
    let dx = q1.x.translation - q0.x.translation;
    0.5 * (ds * ds + dg * dg + (q1.n - q0.n).norm_squared() + dx.norm_squared()) / h
        + ((Matrix3::identity() - f).trace() + (Matrix3::identity() - fx).trace()) / h
        - h * q0.s * q0.n.z
}

const P: usize = 32;
const N: usize = 13;

/// The stored point of the values `s`, `g`, `R`, `n`, `(R_x, x)`, built block by block by each
/// kind's runtime group.
fn point(values: &[Vec<f64>]) -> SVector<f64, P> {
    let mut q = SVector::<f64, P>::zeros();
    let mut at = 0;
    for ((name, kind), value) in EveryKind::COORDINATES.iter().zip(values) {
        let group = kind.group();
        let block = &mut q.as_mut_slice()[at..at + group.point_len()];
        group.point_from_value(name, value, block).unwrap();
        at += group.point_len();
    }
    q
}

/// The runtime's `φ_q(z)`, block by block.
fn retract_by_groups(q: &SVector<f64, P>, z: &SVector<f64, N>) -> SVector<f64, P> {
    let mut out = SVector::<f64, P>::zeros();
    let (mut at, mut c) = (0, 0);
    for (_, kind) in EveryKind::COORDINATES {
        let group = kind.group();
        let (np, nc) = (group.point_len(), group.chart_len());
        group.retract(
            &q.as_slice()[at..at + np],
            &z.as_slice()[c..c + nc],
            &mut out.as_mut_slice()[at..at + np],
        );
        at += np;
        c += nc;
    }
    out
}

#[test]
fn the_emitted_coordinates_are_the_runtime_kinds_by_name() {
    let kinds: Vec<CoordinateKind> = EveryKind::COORDINATES.iter().map(|c| c.1).collect();
    assert_eq!(
        kinds,
        [
            CoordinateKind::SCALAR,
            CoordinateKind::GROUP,
            CoordinateKind::ROTATION,
            CoordinateKind::DIRECTION,
            CoordinateKind::POSE,
        ]
    );
    let names: Vec<&str> = kinds.iter().map(|k| k.name()).collect();
    assert_eq!(names, ["shape", "group", "rotation", "direction", "pose"]);
    let (p, n): (usize, usize) = kinds
        .iter()
        .fold((0, 0), |(p, n), k| (p + k.point_len(), n + k.chart_len()));
    assert_eq!((p, n), (P, N));
}

/// `φ_q(z)` emitted from the compiler's groups equals the runtime's to a few ulps (the same
/// formulas, evaluated in another order: entries of size 1, tolerance 1e-14), the chart inverse
/// the integrators use recovers `z`, and the result passes every kind's manifold check.
#[test]
fn the_emitted_chart_is_the_runtime_chart_for_every_kind() {
    let sys = EveryKind { h: 0.1 };
    let pose: Vec<f64> = rows(&cayley(&Vector3::new(-0.3, 0.5, 0.1)))
        .into_iter()
        .chain([1.5, -0.5, 2.0])
        .collect();
    let q = point(&[
        vec![0.7],
        vec![-1.25],
        rows(&cayley(&Vector3::new(0.2, -0.7, 0.4))).to_vec(),
        Vector3::new(0.3, -0.4, 0.5).normalize().as_slice().to_vec(),
        pose,
    ]);
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    for scale in [0.0, 1e-3, 0.3] {
        let z = SVector::<f64, N>::from_fn(|i, _| scale * (0.9 - 0.23 * i as f64));
        let emitted = sys.retract(&q, &z);
        let numeric = retract_by_groups(&q, &z);
        assert!(
            (emitted - numeric).amax() < 1e-14,
            "scale {scale}: {}",
            (emitted - numeric).amax()
        );
        assert!((integ.chart_coordinates(&q, &emitted) - z).amax() < 1e-13);
        assert!(integ.manifold_defect(&emitted) < 1e-15);
        let state = LieState::from_row_major(emitted, SVector::<f64, N>::zeros());
        assert!(integ.check(&state).is_ok());
    }
}
