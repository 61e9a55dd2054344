//! Diagnostics along computed trajectories.

use crate::integrate::Trajectory;
use crate::system::{join, DiscreteLagrangian};

/// The discrete energy of each step along a trajectory, `(E_d)_k = L_d(q_k, q_{k+1})`: the
/// generalized energy (5.7) on solutions, where `q_k^+ = q_{k+1}` (§7.2.2; see
/// [`DiscreteLagrangian::generalized_energy_plus`]).
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
