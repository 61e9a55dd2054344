//! Eight rigid bodies on a chain of springs: body `i` and body `i + 1` are joined by a spring
//! between the body-fixed points `a` of the one and `b` of the other. 24 chart coordinates, so
//! the compiled-in system runs on the sparse backend. The text of this function is both the
//! compiled-in system (by the attribute) and the system given at run time (the dirac-jit
//! tests, the Python package and the command line read it), so the two are the same characters.
//!
//! `L_d = Σ_i s_i tr((I − F_i) J_d)/h − (h/2) (V(q0) + V(q1))` with `F_i = R_i0ᵀ R_i1`, the body
//! `i` scaled by `s_i = 1 + i/4`, and `V = (k/2) Σ_i |R_i a − R_{i+1} b|²`. Rotating every body
//! together leaves it unchanged, so the spatial angular momentum `Σ R_i Π_i` is conserved.

use dirac::prelude::*;
use dirac::runtime::nalgebra::{Matrix3, Vector3};

/// Eight rigid bodies, each joined to the next by a spring between body-fixed points.
#[reduced_lagrangian(rotation(r1, r2, r3, r4, r5, r6, r7, r8))]
pub fn eight_bodies(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.5));
    let one = Matrix3::identity();
    let a = Vector3::new(0.5, 0.1, 0.0);
    let b = Vector3::new(-0.5, 0.0, 0.1);
    let kinetic = ((one - q0.r1.transpose() * q1.r1) * jd).trace()
        + ((one - q0.r2.transpose() * q1.r2) * jd).trace() * 1.25
        + ((one - q0.r3.transpose() * q1.r3) * jd).trace() * 1.5
        + ((one - q0.r4.transpose() * q1.r4) * jd).trace() * 1.75
        + ((one - q0.r5.transpose() * q1.r5) * jd).trace() * 2.0
        + ((one - q0.r6.transpose() * q1.r6) * jd).trace() * 2.25
        + ((one - q0.r7.transpose() * q1.r7) * jd).trace() * 2.5
        + ((one - q0.r8.transpose() * q1.r8) * jd).trace() * 2.75;
    let d0 = [
        q0.r1 * a - q0.r2 * b,
        q0.r2 * a - q0.r3 * b,
        q0.r3 * a - q0.r4 * b,
        q0.r4 * a - q0.r5 * b,
        q0.r5 * a - q0.r6 * b,
        q0.r6 * a - q0.r7 * b,
        q0.r7 * a - q0.r8 * b,
    ];
    let d1 = [
        q1.r1 * a - q1.r2 * b,
        q1.r2 * a - q1.r3 * b,
        q1.r3 * a - q1.r4 * b,
        q1.r4 * a - q1.r5 * b,
        q1.r5 * a - q1.r6 * b,
        q1.r6 * a - q1.r7 * b,
        q1.r7 * a - q1.r8 * b,
    ];
    let v0 = d0[0].dot(&d0[0])
        + d0[1].dot(&d0[1])
        + d0[2].dot(&d0[2])
        + d0[3].dot(&d0[3])
        + d0[4].dot(&d0[4])
        + d0[5].dot(&d0[5])
        + d0[6].dot(&d0[6]);
    let v1 = d1[0].dot(&d1[0])
        + d1[1].dot(&d1[1])
        + d1[2].dot(&d1[2])
        + d1[3].dot(&d1[3])
        + d1[4].dot(&d1[4])
        + d1[5].dot(&d1[5])
        + d1[6].dot(&d1[6]);
    kinetic / h - 0.25 * h * k * (v0 + v1)
}
