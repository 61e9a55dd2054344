//! Diagnostics along computed trajectories.

use nalgebra::SVector;

use crate::integrate::Trajectory;
use crate::system::{join, DiscreteLagrangian};

/// The (+) discrete generalized energy, eq. (5.7):
/// `E_{d+}(q0, q0^+, q1, p1) = L_d(q0, q0^+) + ⟨p1, q1 − q0^+⟩`.
pub fn generalized_energy_plus<L, const S: usize, const K: usize, const N: usize>(
    system: &L,
    q0: &SVector<f64, N>,
    q0_plus: &SVector<f64, N>,
    q1: &SVector<f64, N>,
    p1: &SVector<f64, N>,
) -> f64
where
    L: DiscreteLagrangian<S, K, N>,
{
    system.lagrangian(q0, q0_plus) + p1.dot(&(q1 - q0_plus))
}

/// The discrete energy of each step along a trajectory, `(E_d)_k = E_{d+} = L_d(q_k, q_{k+1})`
/// (eq. (5.7) on solutions, where `q_k^+ = q_{k+1}`; §7.2.2).
pub fn trajectory_energies<L, const S: usize, const K: usize, const N: usize>(
    system: &L,
    trajectory: &Trajectory<S, K>,
) -> Vec<f64>
where
    L: DiscreteLagrangian<S, K, N>,
{
    trajectory
        .states
        .windows(2)
        .map(|pair| {
            let q0 = join::<S, K, N>(&pair[0].x, &pair[0].g);
            let q1 = join::<S, K, N>(&pair[1].x, &pair[1].g);
            system.lagrangian(&q0, &q1)
        })
        .collect()
}
