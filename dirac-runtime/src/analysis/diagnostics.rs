//! The paper's geometry as diagnostics: the reduced discrete Dirac differentials and membership
//! in the reduced discrete Dirac structures (§3–4), the reduced discrete generalized energies and
//! the reduced discrete action (§5). Along a computed trajectory both routes — Dirac structure
//! and variational principle — must agree with the stepper to round-off.
//!
//! All formulas are the paper's, specialised to the linear connection
//! `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)`, for which `h_d^0(x0, x1) = B (x1 − x0)`,
//! `h_{d,Σ} = B`, `h*_{d,Σ} = Bᵀ`, `h_{d,Q}((x, 0)) = −B x` and `h_d((0, g), 0) = g`.

use nalgebra::SVector;

use crate::error::StepError;
use crate::newton::inf_norm;
use crate::reduced::Trajectory;
use crate::system::{join, DiscreteLagrangian, Minus, Plus, Reduced, Side, Variant};

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

/// First partials of the reduced Lagrangian of side `D` at `(x0, x1)` and the group unknown `u`,
/// read from the emitted code: `(∂l/∂x0, ∂l/∂u, ∂l/∂x1)`. At zero momenta the step residual is
/// `(∂l/∂x0, ∂l/∂u)` on either side, and the momentum update is `∂l/∂x1`.
fn partials<D, L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x0: &SVector<f64, S>,
    x1: &SVector<f64, S>,
    u: &SVector<f64, K>,
) -> (SVector<f64, S>, SVector<f64, K>, SVector<f64, S>)
where
    D: Side,
    L: Reduced<D, S, K, N>,
{
    let z = join::<S, K, N>(x1, u);
    let f = sys.residual(x0, &SVector::zeros(), &SVector::zeros(), &z);
    let d_x0 = f.fixed_rows::<S>(0).into_owned();
    let d_u = f.fixed_rows::<K>(S).into_owned();
    (d_x0, d_u, sys.momentum(x0, &z))
}

/// The pairing `⟨w − Bᵀμ, Δx⟩ + ⟨μ, Δg⟩` of a reduced momentum `(w, μ)` with the displacement
/// `(Δx, Δg) = (x − x_v, g − g_v − h_d^0(x_s, x_v))` of a configuration `(x, g)` from a step's
/// variables `(x_v, g_v)` taken from the shape point `x_s` (`h_d^0` of eq. (2.5)): the canonical
/// pairing `⟨p, Δq⟩` through the trivialization (3.7). Both reduced generalized energies (Lemmas
/// 5.1 and 5.4) add it to the reduced Lagrangian.
fn pairing<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    (w, mu): (&SVector<f64, S>, &SVector<f64, K>),
    (x, g): (&SVector<f64, S>, &SVector<f64, K>),
    x_s: &SVector<f64, S>,
    (x_v, g_v): (&SVector<f64, S>, &SVector<f64, K>),
) -> f64
where
    L: DiscreteLagrangian<S, K, N>,
{
    let b = sys.connection();
    let (dx, dg) = (x - x_v, g - g_v - sys.h_d0(x_s, x_v));
    (w - b.transpose() * mu).dot(&dx) + mu.dot(&dg)
}

/// The reduced (+) discrete Dirac differential at `(x0, x1, g1)`, Proposition 4.3: a point of
/// `Σ × (Σ* × g*) × Q* × (Σ × g)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiracDifferentialPlus<const S: usize, const K: usize> {
    /// `x0`.
    pub x0: SVector<f64, S>,
    /// `∂L_d/∂x1 + h*_{d,Σ}(∂L_d/∂g1) = ∂l_{d+}/∂x1`.
    pub w: SVector<f64, S>,
    /// `∂L_d/∂g1 = ∂l_{d+}/∂g1`.
    pub mu: SVector<f64, K>,
    /// `−∂L_d/∂q0 = (−∂l_{d+}/∂x0 − Bᵀ ∂l_{d+}/∂g1, ∂l_{d+}/∂g1)` (Lemma 4.5), shape part.
    pub p_x: SVector<f64, S>,
    /// Group part of `−∂L_d/∂q0`.
    pub p_g: SVector<f64, K>,
    /// `x1`.
    pub x1: SVector<f64, S>,
    /// `g1 + h_{d,Q}(x0, 0) = g1 − B x0`.
    pub xi: SVector<f64, K>,
}

/// The reduced (−) discrete Dirac differential at `(x0, g0, x1)`, Proposition 4.4: a point of
/// `(Σ* × g*) × Σ × (Σ × g) × Q*`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiracDifferentialMinus<const S: usize, const K: usize> {
    /// `−∂L_d/∂x0 − h*_{d,Σ}(∂L_d/∂g0) = −∂l_{d−}/∂x0` (Lemma 4.7).
    pub w: SVector<f64, S>,
    /// `−∂L_d/∂g0 = −∂l_{d−}/∂g0`.
    pub mu: SVector<f64, K>,
    /// `x1`.
    pub x1: SVector<f64, S>,
    /// `−x0`.
    pub minus_x0: SVector<f64, S>,
    /// `−g0 − h_{d,Q}(x1, 0) = −g0 + B x1`.
    pub xi: SVector<f64, K>,
    /// `−∂L_d/∂q1 = (−∂l_{d−}/∂x1 − Bᵀ ∂l_{d−}/∂g0, ∂l_{d−}/∂g0)`, shape part.
    pub p_x: SVector<f64, S>,
    /// Group part of `−∂L_d/∂q1`.
    pub p_g: SVector<f64, K>,
}

/// The reduced (+) discrete Dirac differential `[D̂⁺ L_d](x0, x1, g1)`, Proposition 4.3.
pub fn dirac_differential_plus<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x0: &SVector<f64, S>,
    x1: &SVector<f64, S>,
    g1: &SVector<f64, K>,
) -> DiracDifferentialPlus<S, K>
where
    L: Reduced<Plus, S, K, N>,
{
    let b = sys.connection();
    let (d_x0, d_g1, d_x1) = partials::<Plus, L, S, K, N>(sys, x0, x1, g1);
    DiracDifferentialPlus {
        x0: *x0,
        w: d_x1,
        mu: d_g1,
        p_x: -d_x0 - b.transpose() * d_g1,
        p_g: d_g1,
        x1: *x1,
        xi: g1 - b * x0,
    }
}

/// The reduced (−) discrete Dirac differential `[D̂⁻ L_d](x0, g0, x1)`, Proposition 4.4.
pub fn dirac_differential_minus<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x0: &SVector<f64, S>,
    g0: &SVector<f64, K>,
    x1: &SVector<f64, S>,
) -> DiracDifferentialMinus<S, K>
where
    L: Reduced<Minus, S, K, N>,
{
    let b = sys.connection();
    let (d_x0, d_g0, d_x1) = partials::<Minus, L, S, K, N>(sys, x0, x1, g0);
    DiracDifferentialMinus {
        w: -d_x0,
        mu: -d_g0,
        x1: *x1,
        minus_x0: -x0,
        xi: -g0 + b * x1,
        p_x: -d_x1 - b.transpose() * d_g0,
        p_g: d_g0,
    }
}

/// For each step `k` of a reduced trajectory, how far `([X̂_d^k], [D̂^± L_d]) ∈ [D̂^{d±}]` is
/// from holding: the ∞-norm of the difference between the Dirac differential at the step's
/// solution and the point of the reduced Dirac structure that the discrete vector field
/// `[X̂_d^k] = (x_k, w_k, μ_k, q_{k+1}, w_{k+1}, μ_{k+1})` determines (Propositions 3.8 and
/// 4.3 for (+), 3.10 and 4.4 for (−)). Its momentum components are the step equations
/// themselves, so along a computed trajectory it is of the order of the Newton residual the
/// step was accepted with (`StepStats::residual`); a larger value means the stepper and the
/// geometry disagree.
pub fn dirac_membership_residuals<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    trajectory: &Trajectory<S, K>,
) -> Vec<f64>
where
    L: Reduced<Plus, S, K, N> + Reduced<Minus, S, K, N>,
{
    let b = sys.connection();
    let bt = b.transpose();
    let steps = trajectory.states.windows(2).zip(&trajectory.group_unknowns);
    match trajectory.variant {
        Variant::Plus => steps
            .map(|(pair, u)| {
                let (s0, s1) = (&pair[0], &pair[1]);
                // [X̂] = (x_k, w_k, μ_k, q_{k+1} = (x_{k+1}, g_{k+1} − g_k), w_{k+1}, μ_{k+1}) must pair
                // with (x_k, w_{k+1}, μ_{k+1}, (w_k − Bᵀμ_k, μ_k), x_{k+1}, (g_{k+1} − g_k) − B x_{k+1}).
                let d = dirac_differential_plus(sys, &s0.x, &s1.x, u);
                let g_rel = s1.g - s0.g;
                max_difference(&[
                    (d.x0.as_slice(), s0.x.as_slice()),
                    (d.w.as_slice(), s1.w.as_slice()),
                    (d.mu.as_slice(), s1.mu.as_slice()),
                    (d.p_x.as_slice(), (s0.w - bt * s0.mu).as_slice()),
                    (d.p_g.as_slice(), s0.mu.as_slice()),
                    (d.x1.as_slice(), s1.x.as_slice()),
                    (d.xi.as_slice(), (g_rel - b * s1.x).as_slice()),
                ])
            })
            .collect(),
        Variant::Minus => steps
            .map(|(pair, u)| {
                let (s0, s1) = (&pair[0], &pair[1]);
                // [X̂] = (q_k = (x_k, g_k − g_{k+1}), w_k, μ_k, x_{k+1}, w_{k+1}, μ_{k+1}) must pair with
                // (w_k, μ_k, x_{k+1}, −x_k, −(g_k − g_{k+1}) + B x_k, (−w_{k+1} + Bᵀμ_{k+1}, −μ_{k+1})).
                let d = dirac_differential_minus(sys, &s0.x, u, &s1.x);
                let g_rel = s0.g - s1.g;
                max_difference(&[
                    (d.w.as_slice(), s0.w.as_slice()),
                    (d.mu.as_slice(), s0.mu.as_slice()),
                    (d.x1.as_slice(), s1.x.as_slice()),
                    (d.minus_x0.as_slice(), (-s0.x).as_slice()),
                    (d.xi.as_slice(), (-g_rel + b * s0.x).as_slice()),
                    (d.p_x.as_slice(), (-s1.w + bt * s1.mu).as_slice()),
                    (d.p_g.as_slice(), (-s1.mu).as_slice()),
                ])
            })
            .collect(),
    }
}

/// The largest `|a_i − b_i|` over pairs of equally long slices.
fn max_difference(pairs: &[(&[f64], &[f64])]) -> f64 {
    pairs
        .iter()
        .flat_map(|(a, b)| a.iter().zip(*b))
        .fold(0.0, |worst, (a, b)| worst.max((a - b).abs()))
}

/// The reduced (+) discrete generalized energy, Lemma 5.1:
/// `e_{d+}(x0, x0^+, g0^+, q1, w1, μ1) = l_{d+}(x0, x0^+, g0^+) + ⟨w1 − Bᵀμ1, x1 − x0^+⟩
///  + ⟨μ1, g1 − g0^+ − B (x0^+ − x0)⟩`, with `q1 = (x1, g1)` relative to `g0` (identification (5.3)).
#[allow(clippy::too_many_arguments)]
pub fn reduced_energy_plus<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x0: &SVector<f64, S>,
    x0_plus: &SVector<f64, S>,
    g0_plus: &SVector<f64, K>,
    x1: &SVector<f64, S>,
    g1: &SVector<f64, K>,
    w1: &SVector<f64, S>,
    mu1: &SVector<f64, K>,
) -> f64
where
    L: Reduced<Plus, S, K, N>,
{
    Reduced::<Plus, S, K, N>::reduced_lagrangian(sys, x0, x0_plus, g0_plus)
        + pairing(sys, (w1, mu1), (x1, g1), x0, (x0_plus, g0_plus))
}

/// The reduced (−) discrete generalized energy as printed in Lemma 5.4:
/// `e_{d−}(x1^−, g1^−, x1, w0, μ0, q0) = l_{d−}(x1^−, g1^−, x1) + ⟨w0 − Bᵀμ0, x0 − x1^−⟩
///  + ⟨μ0, g0 − g1^− − B (x1^− − x1)⟩`, with `q0 = (x0, g0)` relative to `g1`.
///
/// It follows the (−) action (2.12), whose momenta have the opposite sign to Definition 2.8
/// (see [`Minus`]): along a trajectory of the (−) stepper it is stationary when evaluated
/// with `(−w_k, −μ_k)`.
#[allow(clippy::too_many_arguments)]
pub fn reduced_energy_minus<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x1_minus: &SVector<f64, S>,
    g1_minus: &SVector<f64, K>,
    x1: &SVector<f64, S>,
    w0: &SVector<f64, S>,
    mu0: &SVector<f64, K>,
    x0: &SVector<f64, S>,
    g0: &SVector<f64, K>,
) -> f64
where
    L: Reduced<Minus, S, K, N>,
{
    Reduced::<Minus, S, K, N>::reduced_lagrangian(sys, x1_minus, x1, g1_minus)
        + pairing(sys, (w0, mu0), (x0, g0), x1, (x1_minus, g1_minus))
}

/// The variables of the reduced (+) discrete action `Σ_k e_{d+}` (Theorem 5.2): configurations
/// `(x_k, g_k)` for `k = 0..=n`, and for each step `k < n` the variables
/// `(x_k^+, g_k^+, w_{k+1}, μ_{k+1})`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedActionPlus<const S: usize, const K: usize> {
    /// Shape coordinates `x_k`, `k = 0..=n`.
    pub x: Vec<SVector<f64, S>>,
    /// Group coordinates `g_k`, `k = 0..=n`.
    pub g: Vec<SVector<f64, K>>,
    /// `x_k^+`, `k < n`.
    pub x_plus: Vec<SVector<f64, S>>,
    /// `g_k^+`, `k < n` (the group unknown of the (+) step).
    pub g_plus: Vec<SVector<f64, K>>,
    /// Reduced momenta `w_{k+1}`, `k < n`.
    pub w: Vec<SVector<f64, S>>,
    /// Momentum values `μ_{k+1}`, `k < n`.
    pub mu: Vec<SVector<f64, K>>,
}

impl<const S: usize, const K: usize> ReducedActionPlus<S, K> {
    /// The action's variables along a trajectory of the (+) stepper: `x_k^+ = x_{k+1}`, the
    /// solved `g_k^+`, and the computed momenta. A trajectory of the (−) stepper (Theorem 5.2 is
    /// the (+) principle) is [`StepError::Unsupported`]; one without states or whose group
    /// unknowns do not number its steps (not made by `integrate`) is [`StepError::InvalidSize`].
    pub fn from_trajectory(trajectory: &Trajectory<S, K>) -> Result<Self, StepError> {
        if trajectory.variant != Variant::Plus {
            return Err(StepError::Unsupported {
                what: "the (+) action's variables of a trajectory of the (-) stepper \
                       (Theorem 5.2 is the (+) principle)",
            });
        }
        let states = &trajectory.states;
        let Some(later) = states.get(1..) else {
            return Err(StepError::InvalidSize {
                reason: "the trajectory holds no state".to_string(),
            });
        };
        if trajectory.group_unknowns.len() != later.len() {
            return Err(StepError::InvalidSize {
                reason: format!(
                    "the trajectory has {} steps but {} group unknowns",
                    later.len(),
                    trajectory.group_unknowns.len()
                ),
            });
        }
        Ok(Self {
            x: states.iter().map(|s| s.x).collect(),
            g: states.iter().map(|s| s.g).collect(),
            x_plus: later.iter().map(|s| s.x).collect(),
            g_plus: trajectory.group_unknowns.clone(),
            w: later.iter().map(|s| s.w).collect(),
            mu: later.iter().map(|s| s.mu).collect(),
        })
    }

    /// `Σ_k e_{d+}(x_k, x_k^+, g_k^+, q_{k+1} − g_k, w_{k+1}, μ_{k+1})`, eq. (5.8).
    pub fn action<L, const N: usize>(&self, sys: &L) -> f64
    where
        L: Reduced<Plus, S, K, N>,
    {
        (0..self.x_plus.len())
            .map(|k| {
                let g_rel = self.g[k + 1] - self.g[k];
                reduced_energy_plus(
                    sys,
                    &self.x[k],
                    &self.x_plus[k],
                    &self.g_plus[k],
                    &self.x[k + 1],
                    &g_rel,
                    &self.w[k],
                    &self.mu[k],
                )
            })
            .sum()
    }

    /// The gradient of [`Self::action`] with respect to the interior variables — `x_k, g_k` for
    /// `0 < k < n` and every `x_k^+, g_k^+, w_{k+1}, μ_{k+1}` — in the layout of `Self`, with the
    /// fixed endpoints' entries zero. By Theorem 5.2 and Proposition 5.3 it vanishes exactly on
    /// solutions of eq. (4.6):
    ///
    /// ```text
    /// ∂/∂x_k     = ∂l/∂x0(k) + Bᵀμ_{k+1} + w_k − Bᵀμ_k      ∂/∂g_k = μ_k − μ_{k+1}
    /// ∂/∂x_k^+   = ∂l/∂x1(k) − w_{k+1}                       ∂/∂g_k^+ = ∂l/∂g1(k) − μ_{k+1}
    /// ∂/∂w_{k+1} = x_{k+1} − x_k^+
    /// ∂/∂μ_{k+1} = (g_{k+1} − g_k) − g_k^+ − B (x_{k+1} − x_k)
    /// ```
    pub fn gradient<L, const N: usize>(&self, sys: &L) -> Self
    where
        L: Reduced<Plus, S, K, N>,
    {
        let b = sys.connection();
        let bt = b.transpose();
        let n = self.x_plus.len();
        let mut grad = Self {
            x: vec![SVector::zeros(); n + 1],
            g: vec![SVector::zeros(); n + 1],
            x_plus: vec![SVector::zeros(); n],
            g_plus: vec![SVector::zeros(); n],
            w: vec![SVector::zeros(); n],
            mu: vec![SVector::zeros(); n],
        };
        for k in 0..n {
            let (d_x0, d_g1, d_x1) =
                partials::<Plus, L, S, K, N>(sys, &self.x[k], &self.x_plus[k], &self.g_plus[k]);
            if k > 0 {
                grad.x[k] += d_x0 + bt * self.mu[k];
                grad.g[k] -= self.mu[k];
            }
            if k + 1 < n {
                grad.x[k + 1] += self.w[k] - bt * self.mu[k];
                grad.g[k + 1] += self.mu[k];
            }
            grad.x_plus[k] = d_x1 - self.w[k];
            grad.g_plus[k] = d_g1 - self.mu[k];
            grad.w[k] = self.x[k + 1] - self.x_plus[k];
            grad.mu[k] =
                (self.g[k + 1] - self.g[k]) - self.g_plus[k] - sys.h_d0(&self.x[k], &self.x[k + 1]);
        }
        grad
    }

    /// The largest entry in absolute value.
    pub fn max_abs(&self) -> f64 {
        let v = |xs: &[SVector<f64, S>]| xs.iter().map(inf_norm).fold(0.0, f64::max);
        let k = |xs: &[SVector<f64, K>]| xs.iter().map(inf_norm).fold(0.0, f64::max);
        v(&self.x)
            .max(k(&self.g))
            .max(v(&self.x_plus))
            .max(k(&self.g_plus))
            .max(v(&self.w))
            .max(k(&self.mu))
    }
}
