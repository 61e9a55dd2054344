//! States of the reduced and the canonical (unreduced) descriptions.

use nalgebra::SVector;

/// A point of the reduced phase space with its reconstructed group coordinate:
/// shape `x ∈ Σ`, reduced momenta `w ∈ Σ*`, `μ ∈ g*` (eq. (3.6)), and the absolute group
/// coordinate `g ∈ G`, which the reduced equations do not need but reconstruction recovers
/// (last line of eq. (4.6)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReducedState<const S: usize, const K: usize> {
    /// Shape coordinates `x`.
    pub x: SVector<f64, S>,
    /// Reduced shape momenta `w = p_x + Bᵀ p_g`.
    pub w: SVector<f64, S>,
    /// Group momenta `μ = J(q, p) = p_g`.
    pub mu: SVector<f64, K>,
    /// Absolute group coordinate `g`.
    pub g: SVector<f64, K>,
}

impl<const S: usize, const K: usize> ReducedState<S, K> {
    /// Builds a state from slices; panics only if a slice has the wrong length, which is a
    /// programming error caught at the first run.
    pub fn new(x: [f64; S], w: [f64; S], mu: [f64; K], g: [f64; K]) -> Self {
        Self {
            x: SVector::from(x),
            w: SVector::from(w),
            mu: SVector::from(mu),
            g: SVector::from(g),
        }
    }

    /// True when every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        // `v · 0` is 0 for finite `v` and NaN otherwise: one branch-free sum instead of a
        // short-circuiting test per component (this runs on every step).
        let parts = [
            self.x.as_slice(),
            self.w.as_slice(),
            self.mu.as_slice(),
            self.g.as_slice(),
        ];
        let mut zero = 0.0;
        for part in parts {
            for v in part {
                zero += v * 0.0;
            }
        }
        zero == 0.0
    }
}

/// A point `(q, p) ∈ T*Q ≃ Q × Q*` with `q = (x, g)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CanonicalState<const N: usize> {
    /// Configuration `q = (x, g)`.
    pub q: SVector<f64, N>,
    /// Canonical momentum `p = (p_x, p_g)`.
    pub p: SVector<f64, N>,
}

impl<const N: usize> CanonicalState<N> {
    /// Builds a state from arrays `q = (x, g)` and `p = (p_x, p_g)`.
    pub fn new(q: [f64; N], p: [f64; N]) -> Self {
        Self {
            q: SVector::from(q),
            p: SVector::from(p),
        }
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.q.iter().chain(self.p.iter()).all(|v| v.is_finite())
    }
}
