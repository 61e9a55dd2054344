//! The derivatives that `#[reduced_lagrangian]` generates at compile time, checked against an
//! independent run-time oracle: forward-mode second-order dual numbers from `num-dual`.
//!
//! For each system the discrete Lagrangian `L_d(q0, q1)` is written a second time, by hand, as a
//! generic function over `num_dual::DualNum` (it never calls the generated code). The harness
//! builds the reduced Lagrangian of eq. (4.5),
//!
//! ```text
//! l(x0, x1, g1) = L_d((x0, 0), (x1, g1 + B (x1 − x0))),
//! ```
//!
//! on dual numbers in the variables `v = (x0, x1, g1)`, takes its gradient and Hessian with
//! `num_dual::hessian`, and compares every output of the generated `Reduced<Plus, ..>` methods with the
//! corresponding gradient / Hessian entry to `|a − b| ≤ 1e-12 · max(1, |a|, |b|)`.

use dirac::nalgebra::{SMatrix, SVector};
use dirac::paper::ChargedParticle;
use dirac::prelude::*;
use num_dual::{hessian, Dual2SVec64, DualNum};

// ---------------------------------------------------------------------------------------------
// The oracle harness.
// ---------------------------------------------------------------------------------------------

mod common;
use common::Rng;

const TOL: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOL * 1f64.max(a.abs()).max(b.abs())
}

/// Gradient and Hessian of `l(x0, x1, g1)` from `num-dual`, in the variables `v = (x0, x1, g1)`
/// (so `M = 2S + K`); `lag` is the reference discrete Lagrangian over `q = (x, g)`.
fn oracle<const S: usize, const K: usize, const N: usize, const M: usize>(
    b: &SMatrix<f64, K, S>,
    lag: &dyn Fn([Dual2SVec64<M>; N], [Dual2SVec64<M>; N]) -> Dual2SVec64<M>,
    x0: &SVector<f64, S>,
    z: &SVector<f64, N>,
) -> (f64, SVector<f64, M>, SMatrix<f64, M, M>) {
    assert_eq!(S + K, N);
    assert_eq!(2 * S + K, M);
    // v = (x0, x1, g1) = (x0, z).
    let v = SVector::<f64, M>::from_fn(|i, _| if i < S { x0[i] } else { z[i - S] });
    hessian(
        |v: SVector<Dual2SVec64<M>, M>| {
            let zero = Dual2SVec64::<M>::from(0.0);
            // q0 = (x0, g0 = 0): the reduced space fixes g0 = 0.
            let q0: [Dual2SVec64<M>; N] = std::array::from_fn(|i| if i < S { v[i] } else { zero });
            // q1 = (x1, g1 + B (x1 − x0)).
            let q1: [Dual2SVec64<M>; N] = std::array::from_fn(|i| {
                if i < S {
                    v[S + i]
                } else {
                    let j = i - S;
                    let mut g = v[2 * S + j];
                    for c in 0..S {
                        g += (v[S + c] - v[c]) * b[(j, c)];
                    }
                    g
                }
            });
            lag(q0, q1)
        },
        &v,
    )
}

/// Compares every output of the generated code at `(x_k, z)` with the oracle; returns the largest
/// scaled error seen (`|a − b| / max(1, |a|, |b|)`), panicking with a precise report on failure.
#[allow(clippy::too_many_arguments)]
fn compare_at<Sys, const S: usize, const K: usize, const N: usize, const M: usize>(
    label: &str,
    sys: &Sys,
    b: &SMatrix<f64, K, S>,
    lag: &dyn Fn([Dual2SVec64<M>; N], [Dual2SVec64<M>; N]) -> Dual2SVec64<M>,
    lag_f64: &dyn Fn([f64; N], [f64; N]) -> f64,
    x0: &SVector<f64, S>,
    z: &SVector<f64, N>,
) -> f64
where
    Sys: Reduced<Plus, S, K, N, Linear = dirac::runtime::Lu<N>>,
{
    let (value, grad, hess) = oracle::<S, K, N, M>(b, lag, x0, z);
    let mut worst = 0f64;
    let mut check = |what: String, generated: f64, reference: f64| {
        let scaled = (generated - reference).abs() / 1f64.max(generated.abs()).max(reference.abs());
        worst = worst.max(scaled);
        assert!(
            close(generated, reference) && generated.is_finite(),
            "{label}: {what} disagrees at x_k = {:?}, z = {:?}: generated {generated:e}, num-dual {reference:e} \
             (scaled error {scaled:e})",
            x0.as_slice(),
            z.as_slice(),
        );
    };

    // The connection matrix the macro emitted.
    let emitted_b = sys.connection();
    for j in 0..K {
        for c in 0..S {
            check(format!("B[{j},{c}]"), emitted_b[(j, c)], b[(j, c)]);
        }
    }

    // Row r of R is ∂l/∂x0_r (r < S) or ∂l/∂g1_{r−S}; in v these sit at r and S + r.
    let out = |r: usize| if r < S { r } else { S + r };
    // Column c of ∂R/∂z is z_c, which sits at S + c in v.
    let col = |c: usize| S + c;

    // Momenta w_k, μ_k enter the residual R = (∂l/∂x0 + w_k, ∂l/∂g1 − μ_k) additively.
    let w_k = SVector::<f64, S>::from_fn(|i, _| 0.3 - 0.7 * z[i]);
    let mu_k = SVector::<f64, K>::from_fn(|j, _| 0.2 + 0.4 * z[S + j]);
    let offset = |r: usize| if r < S { w_k[r] } else { -mu_k[r - S] };
    let residual = sys.residual(x0, &w_k, &mu_k, z);
    let (residual_j, jac) = sys.residual_jacobian(x0, &w_k, &mu_k, z);
    let momentum = sys.momentum(x0, z);
    for r in 0..N {
        check(
            format!("plus_residual[{r}]"),
            residual[r],
            grad[out(r)] + offset(r),
        );
        check(
            format!("plus_residual_jacobian.0[{r}]"),
            residual_j[r],
            grad[out(r)] + offset(r),
        );
        for c in 0..N {
            check(
                format!("plus_residual_jacobian.1[({r},{c})]"),
                jac[(r, c)],
                hess[(out(r), col(c))],
            );
        }
    }
    for i in 0..S {
        check(format!("plus_momentum[{i}]"), momentum[i], grad[S + i]);
    }

    // Values: the reduced Lagrangian and L_d itself (the user's own function body).
    let x1 = z.fixed_rows::<S>(0).into_owned();
    let g1 = z.fixed_rows::<K>(S).into_owned();
    check(
        "reduced_lagrangian_plus".into(),
        sys.reduced_lagrangian(x0, &x1, &g1),
        value,
    );
    let q0: [f64; N] = std::array::from_fn(|i| if i < S { x0[i] } else { 0.3 * i as f64 });
    let q1: [f64; N] = std::array::from_fn(|i| z[i] - 0.2);
    check(
        "lagrangian".into(),
        sys.lagrangian(&SVector::from(q0), &SVector::from(q1)),
        lag_f64(q0, q1),
    );
    worst
}

/// Runs [`compare_at`] at `points` pseudo-random points, with fresh parameters from `make` each
/// time; returns the largest scaled error seen.
fn compare_system<Sys, const S: usize, const K: usize, const N: usize, const M: usize>(
    label: &str,
    seed: u64,
    points: usize,
    make: &dyn Fn(&mut Rng) -> Sys,
    reference: &dyn Fn(&Sys) -> Reference<'_, K, S, M, N>,
) -> f64
where
    Sys: Reduced<Plus, S, K, N, Linear = dirac::runtime::Lu<N>>,
{
    let mut rng = Rng(seed);
    let mut worst = 0f64;
    for _ in 0..points {
        let sys = make(&mut rng);
        let (b, lag, lag_f64) = reference(&sys);
        let x0 = rng.vector::<S>(-1.5, 1.5);
        let z = rng.vector::<N>(-1.5, 1.5);
        worst = worst.max(compare_at::<Sys, S, K, N, M>(
            label, &sys, &b, &*lag, &*lag_f64, &x0, &z,
        ));
    }
    println!("{label}: {points} points, worst scaled error {worst:.2e}");
    worst
}

type RefLagrangian<'a, const M: usize, const N: usize> =
    Box<dyn Fn([Dual2SVec64<M>; N], [Dual2SVec64<M>; N]) -> Dual2SVec64<M> + 'a>;
type RefLagrangianF64<'a, const N: usize> = Box<dyn Fn([f64; N], [f64; N]) -> f64 + 'a>;
/// A system's reference: the connection matrix `B` and `L_d` on dual numbers and on `f64`.
type Reference<'a, const K: usize, const S: usize, const M: usize, const N: usize> = (
    SMatrix<f64, K, S>,
    RefLagrangian<'a, M, N>,
    RefLagrangianF64<'a, N>,
);

/// `T::from(v)` for literals in the reference Lagrangians.
fn c<T: DualNum<Primitive = f64>>(v: f64) -> T {
    T::from(v)
}

// ---------------------------------------------------------------------------------------------
// The charged particle of the paper (§7.1), `dirac::paper::ChargedParticle`.
// ---------------------------------------------------------------------------------------------

/// `L_d = ½ m/h |Δq|² + ½/h (½ b0 (−q0_y Δx + q0_x Δy) + Δθ)²`, written independently of the
/// macro over `q = (x, y, z, θ)`.
fn charged_particle_ref<T: DualNum<Primitive = f64> + Copy>(
    q0: [T; 4],
    q1: [T; 4],
    h: T,
    m: T,
    b0: T,
) -> T {
    let (dx, dy, dz) = (q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]);
    let a_dot_dq = c::<T>(0.5) * b0 * (-q0[1] * dx + q0[0] * dy);
    let s = a_dot_dq + (q1[3] - q0[3]);
    c::<T>(0.5) * m / h * (dx * dx + dy * dy + dz * dz) + c::<T>(0.5) / h * s * s
}

#[test]
fn charged_particle_matches_num_dual() {
    let worst = compare_system::<ChargedParticle, 3, 1, 4, 7>(
        "ChargedParticle",
        0xC4A2_6ED0,
        40,
        &|rng| ChargedParticle {
            h: rng.uniform(0.05, 1.0),
            m: rng.uniform(0.5, 2.0),
            b0: rng.uniform(-2.0, 2.0),
        },
        &|s| {
            let (h, m, b0) = (s.h, s.m, s.b0);
            (
                SMatrix::zeros(),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h.into(), m.into(), b0.into())),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h, m, b0)),
            )
        },
    );
    assert!(worst <= TOL);
}

#[test]
fn charged_particle_paper_parameters_match_num_dual() {
    // The paper's run itself (m = 1, B0 = 1, T/N with N = 100).
    compare_system::<ChargedParticle, 3, 1, 4, 7>(
        "ChargedParticle::paper(100)",
        7,
        20,
        &|_| ChargedParticle::paper(100),
        &|s| {
            let (h, m, b0) = (s.h, s.m, s.b0);
            (
                SMatrix::zeros(),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h.into(), m.into(), b0.into())),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h, m, b0)),
            )
        },
    );
}

// ---------------------------------------------------------------------------------------------
// The same body with a nonzero connection `B = [0.3, −0.7, b]`, `b` a parameter.
// ---------------------------------------------------------------------------------------------

#[reduced_lagrangian(shape(x, y, z), group(theta), connection = [[0.3, -0.7, b]])]
fn connected_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64, b: f64) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
    let s = a_dot_dq + (q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
}

#[test]
fn connected_particle_matches_num_dual() {
    let worst = compare_system::<ConnectedParticle, 3, 1, 4, 7>(
        "ConnectedParticle",
        0x0C0_EEC7,
        40,
        &|rng| ConnectedParticle {
            h: rng.uniform(0.05, 1.0),
            m: rng.uniform(0.5, 2.0),
            b0: rng.uniform(-2.0, 2.0),
            b: rng.uniform(-1.5, 1.5),
        },
        &|s| {
            let (h, m, b0) = (s.h, s.m, s.b0);
            (
                SMatrix::from_row_slice(&[0.3, -0.7, s.b]),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h.into(), m.into(), b0.into())),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h, m, b0)),
            )
        },
    );
    assert!(worst <= TOL);
}

// ---------------------------------------------------------------------------------------------
// K = 2: one shape coordinate `s`, two group coordinates `(gx, gy)` translated by R².
// ---------------------------------------------------------------------------------------------

/// A particle on the plane `(gx, gy)` whose mass and a velocity coupling depend on the shape
/// variable `s`, midpoint-evaluated; G-invariant (group coordinates only as differences).
#[reduced_lagrangian(shape(s), group(gx, gy))]
fn planar_shape(q0: Config, q1: Config, h: f64, m: f64, k: f64) -> f64 {
    let ds = (q1.s - q0.s) / h;
    let (vx, vy) = ((q1.gx - q0.gx) / h, (q1.gy - q0.gy) / h);
    let sm = 0.5 * (q0.s + q1.s);
    let r = 1.0 + 0.5 * sm.sin().powi(2);
    let coupling = 0.3 * sm.cos() * vx * ds + 0.2 * (sm.tanh() * vy).atan();
    let kinetic = 0.5 * m * ds * ds + 0.5 * r * (vx * vx + vy * vy) + coupling;
    let potential =
        k * (1.0 - sm.cos()) + 0.1 * (1.0 + sm * sm).ln() * (0.1 * vx * vy).exp().sqrt();
    h * (kinetic - potential)
}

fn planar_shape_ref<T: DualNum<Primitive = f64> + Copy>(
    q0: [T; 3],
    q1: [T; 3],
    h: T,
    m: T,
    k: T,
) -> T {
    let one = c::<T>(1.0);
    let half = c::<T>(0.5);
    let ds = (q1[0] - q0[0]) / h;
    let vx = (q1[1] - q0[1]) / h;
    let vy = (q1[2] - q0[2]) / h;
    let sm = half * (q0[0] + q1[0]);
    let r = one + half * sm.sin() * sm.sin();
    let coupling = c::<T>(0.3) * sm.cos() * vx * ds + c::<T>(0.2) * (sm.tanh() * vy).atan();
    let kinetic = half * m * ds * ds + half * r * (vx * vx + vy * vy) + coupling;
    let potential =
        k * (one - sm.cos()) + c::<T>(0.1) * (one + sm * sm).ln() * (c::<T>(0.05) * vx * vy).exp();
    h * (kinetic - potential)
}

#[test]
fn two_group_coordinates_match_num_dual() {
    let worst = compare_system::<PlanarShape, 1, 2, 3, 4>(
        "PlanarShape",
        0x0026_0AF5,
        40,
        &|rng| PlanarShape {
            h: rng.uniform(0.5, 1.5),
            m: rng.uniform(0.5, 2.0),
            k: rng.uniform(-1.0, 1.0),
        },
        &|s| {
            let (h, m, k) = (s.h, s.m, s.k);
            (
                SMatrix::zeros(),
                Box::new(move |q0, q1| planar_shape_ref(q0, q1, h.into(), m.into(), k.into())),
                Box::new(move |q0, q1| planar_shape_ref(q0, q1, h, m, k)),
            )
        },
    );
    assert!(worst <= TOL);
}

// ---------------------------------------------------------------------------------------------
// K = 2 with a 2 × 2 connection depending on a parameter.
// ---------------------------------------------------------------------------------------------

#[reduced_lagrangian(shape(a, b), group(u, w), connection = [[0.5, -1.0], [beta, 0.25 * beta]])]
fn connected_pair(q0: Config, q1: Config, h: f64, beta: f64) -> f64 {
    let (da, db) = (q1.a - q0.a, q1.b - q0.b);
    let (du, dw) = (q1.u - q0.u, q1.w - q0.w);
    let inertia = 2.0 + (q0.a * q1.b).cos();
    let cross = f64::atan2(du + 0.5 * da, 1.5 + dw * dw) * db;
    0.5 / h * (da * da + inertia * db * db + du * du + dw * dw) + cross / h
        - h * (q0.a * q0.a + q1.b * q1.b)
}

fn connected_pair_ref<T: DualNum<Primitive = f64> + Copy>(q0: [T; 4], q1: [T; 4], h: T) -> T {
    let da = q1[0] - q0[0];
    let db = q1[1] - q0[1];
    let du = q1[2] - q0[2];
    let dw = q1[3] - q0[3];
    let inertia = c::<T>(2.0) + (q0[0] * q1[1]).cos();
    // atan2(y, x) = atan(y / x) for x > 0, which holds here (x = 1.5 + dw²).
    let cross = ((du + c::<T>(0.5) * da) / (c::<T>(1.5) + dw * dw)).atan() * db;
    c::<T>(0.5) / h * (da * da + inertia * db * db + du * du + dw * dw) + cross / h
        - h * (q0[0] * q0[0] + q1[1] * q1[1])
}

#[test]
fn connected_two_group_coordinates_match_num_dual() {
    let worst = compare_system::<ConnectedPair, 2, 2, 4, 6>(
        "ConnectedPair",
        0xBE7A,
        40,
        &|rng| ConnectedPair {
            h: rng.uniform(0.2, 1.5),
            beta: rng.uniform(-1.0, 1.0),
        },
        &|s| {
            let h = s.h;
            (
                SMatrix::from_row_slice(&[0.5, -1.0, s.beta, 0.25 * s.beta]),
                Box::new(move |q0, q1| connected_pair_ref(q0, q1, h.into())),
                Box::new(move |q0, q1| connected_pair_ref(q0, q1, h)),
            )
        },
    );
    assert!(worst <= TOL);
}

// ---------------------------------------------------------------------------------------------
// Seven coordinates, densely coupled: first derivatives by reverse accumulation.
// ---------------------------------------------------------------------------------------------

/// Six links on a cart (midpoint rule written out), with a connection: at seven coordinates the
/// attribute takes the gradient of `L_d` by reverse accumulation and the Jacobian forward over
/// it (`dirac-compiler`'s `REVERSE_FROM`), with the accumulated adjoints of the velocity sums
/// expanded into each row. Every link's velocity feeds every later link's energy, so every
/// Jacobian entry is nonzero.
#[reduced_lagrangian(shape(th[6]), group(c), connection = [[0.1, 0.0, -0.2, 0.0, 0.3, b]])]
fn link_chain(q0: Config, q1: Config, h: f64, m: f64, gr: f64, b: f64) -> f64 {
    let mut vx = (q1.c - q0.c) / h;
    let mut vy = 0.0;
    let mut y = 0.0;
    let mut t = 0.5 * vx * vx;
    let mut u = 0.0;
    for i in 0..6 {
        let a = 0.5 * (q0.th[i] + q1.th[i]);
        let w = (q1.th[i] - q0.th[i]) / h;
        let (s, c) = (a.sin(), a.cos());
        vx += c * w;
        vy += s * w;
        y -= c;
        t += 0.5 * m * (vx * vx + vy * vy);
        u += m * gr * y + 0.1 * (a * w).tanh() / (1.0 + a * a).sqrt();
    }
    h * (t - u)
}

fn link_chain_ref<T: DualNum<Primitive = f64> + Copy>(
    q0: [T; 7],
    q1: [T; 7],
    h: T,
    m: T,
    gr: T,
) -> T {
    let half = c::<T>(0.5);
    let mut vx = (q1[6] - q0[6]) / h;
    let mut vy = c::<T>(0.0);
    let mut y = c::<T>(0.0);
    let mut t = half * vx * vx;
    let mut u = c::<T>(0.0);
    for i in 0..6 {
        let a = half * (q0[i] + q1[i]);
        let w = (q1[i] - q0[i]) / h;
        vx += a.cos() * w;
        vy += a.sin() * w;
        y -= a.cos();
        t += half * m * (vx * vx + vy * vy);
        u += m * gr * y + c::<T>(0.1) * (a * w).tanh() / (c::<T>(1.0) + a * a).sqrt();
    }
    h * (t - u)
}

#[test]
fn a_densely_coupled_chain_matches_num_dual() {
    let worst = compare_system::<LinkChain, 6, 1, 7, 13>(
        "LinkChain",
        0x0C4A_1175,
        20,
        &|rng| LinkChain {
            h: rng.uniform(0.2, 1.0),
            m: rng.uniform(0.5, 2.0),
            gr: rng.uniform(-1.0, 10.0),
            b: rng.uniform(-0.5, 0.5),
        },
        &|s| {
            let (h, m, gr) = (s.h, s.m, s.gr);
            (
                SMatrix::from_row_slice(&[0.1, 0.0, -0.2, 0.0, 0.3, s.b]),
                Box::new(move |q0, q1| link_chain_ref(q0, q1, h.into(), m.into(), gr.into())),
                Box::new(move |q0, q1| link_chain_ref(q0, q1, h, m, gr)),
            )
        },
    );
    assert!(worst <= TOL);
}

// ---------------------------------------------------------------------------------------------
// The comparison can fail.
// ---------------------------------------------------------------------------------------------

/// A reference that differs from the macro's Lagrangian by a term that changes the Hessian only
/// slightly must be rejected: the harness is not vacuous.
#[test]
#[should_panic(expected = "disagrees")]
fn a_perturbed_reference_is_caught() {
    compare_system::<ChargedParticle, 3, 1, 4, 7>(
        "ChargedParticle (perturbed reference)",
        1,
        5,
        &|_| ChargedParticle {
            h: 0.3,
            m: 1.0,
            b0: 1.0,
        },
        &|s| {
            let (h, m, b0) = (s.h, s.m, s.b0);
            (
                SMatrix::zeros(),
                Box::new(move |q0, q1| {
                    let eps = Dual2SVec64::<7>::from(1e-9);
                    charged_particle_ref(q0, q1, h.into(), m.into(), b0.into())
                        + eps * q1[0] * q1[0]
                }),
                Box::new(move |q0, q1| charged_particle_ref(q0, q1, h, m, b0)),
            )
        },
    );
}
