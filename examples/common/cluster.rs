//! A Lennard-Jones cluster of `n` particles in 3-D with pair interactions, its size chosen at run
//! time; the symmetry is the common translation (K = 3), whose momentum is conserved exactly.
//! Shared by `examples/cluster.rs` and `tests/element_wise.rs` (included with `#[path]`).

use dirac::prelude::*;

/// `L = Σ_i m/2 |v_i|² − Σ_{i<j} 4ε ((σ/r_ij)¹² − (σ/r_ij)⁶)`.
#[reduced_lagrangian(
    coordinates(x[n], y[n], z[n]),
    translate(x),
    translate(y),
    translate(z),
    rule = midpoint
)]
pub fn cluster(q: Config, v: Velocity, m: f64, eps: f64, sigma: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i] + v.z[i] * v.z[i]);
    }
    for i in 0..n {
        for j in i + 1..n {
            let dx = q.x[i] - q.x[j];
            let dy = q.y[i] - q.y[j];
            let dz = q.z[i] - q.z[j];
            let s2 = sigma * sigma / (dx * dx + dy * dy + dz * dz);
            let s6 = s2 * s2 * s2;
            l -= 4.0 * eps * (s6 * s6 - s6);
        }
    }
    l
}

/// The same cluster with each point stored as three consecutive entries of one array, read with
/// strided indices; the loops over the components are unrolled by the compiler.
#[reduced_lagrangian(coordinates(x[3 * n]), rule = midpoint)]
pub fn strided_cluster(q: Config, v: Velocity, m: f64, eps: f64, sigma: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        for d in 0..3 {
            l += 0.5 * m * v.x[3 * i + d] * v.x[3 * i + d];
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            let mut r2 = 0.0;
            for d in 0..3 {
                r2 += (q.x[3 * i + d] - q.x[3 * j + d]).powi(2);
            }
            let s2 = sigma * sigma / r2;
            let s6 = s2 * s2 * s2;
            l -= 4.0 * eps * (s6 * s6 - s6);
        }
    }
    l
}

/// `n` particles on a jittered cubic lattice of spacing `a` (slightly above the pair minimum
/// `2^{1/6} σ`), with small deterministic velocities and a common drift.
pub fn initial(sys: &Cluster, a: f64, speed: f64) -> ElementState {
    let n = sys.n;
    let side = (n as f64).cbrt().ceil() as usize;
    let mut q = DVector::zeros(3 * n);
    let mut p = DVector::zeros(3 * n);
    for k in 0..n {
        let (i, j, l) = (k % side, (k / side) % side, k / (side * side));
        let jitter = |s: f64| 0.03 * a * (s * (k as f64 + 1.0)).sin();
        q[k] = i as f64 * a + jitter(1.3);
        q[n + k] = j as f64 * a + jitter(2.1);
        q[2 * n + k] = l as f64 * a + jitter(3.7);
        p[k] = sys.m * (speed * (0.7 * k as f64).sin() + 0.01);
        p[n + k] = sys.m * speed * (1.1 * k as f64).cos();
        p[2 * n + k] = sys.m * speed * (1.9 * k as f64).sin();
    }
    ElementState::new(q, p)
}
