//! States of the reduced and the unreduced descriptions, and what their constructors accept.

use nalgebra::{DVector, SVector};

/// A vector of components as a state's constructors take it: every state constructor and
/// [`crate::ContinuousLagrangian::reduced_state`] / [`unreduced_state`](crate::ContinuousLagrangian::unreduced_state)
/// accept arrays and nalgebra vectors alike, and a state sized at run time
/// ([`crate::ElementState`]) accepts slices and `Vec`s too — whatever carries the size the
/// state needs (a fixed size is checked by the compiler, so slices, whose length is known only
/// at run time, are not accepted there).
pub trait IntoVector<V> {
    /// The components as `V`.
    fn into_vector(self) -> V;
}

impl<const N: usize> IntoVector<SVector<f64, N>> for [f64; N] {
    fn into_vector(self) -> SVector<f64, N> {
        SVector::from(self)
    }
}

impl<const N: usize> IntoVector<SVector<f64, N>> for &[f64; N] {
    fn into_vector(self) -> SVector<f64, N> {
        SVector::from(*self)
    }
}

impl<const N: usize> IntoVector<SVector<f64, N>> for SVector<f64, N> {
    fn into_vector(self) -> SVector<f64, N> {
        self
    }
}

impl<const N: usize> IntoVector<SVector<f64, N>> for &SVector<f64, N> {
    fn into_vector(self) -> SVector<f64, N> {
        *self
    }
}

impl IntoVector<DVector<f64>> for DVector<f64> {
    fn into_vector(self) -> DVector<f64> {
        self
    }
}

impl IntoVector<DVector<f64>> for &DVector<f64> {
    fn into_vector(self) -> DVector<f64> {
        self.clone()
    }
}

impl IntoVector<DVector<f64>> for Vec<f64> {
    fn into_vector(self) -> DVector<f64> {
        DVector::from_vec(self)
    }
}

impl IntoVector<DVector<f64>> for &[f64] {
    fn into_vector(self) -> DVector<f64> {
        DVector::from_column_slice(self)
    }
}

impl<const N: usize> IntoVector<DVector<f64>> for [f64; N] {
    fn into_vector(self) -> DVector<f64> {
        DVector::from_column_slice(&self)
    }
}

impl<const N: usize> IntoVector<DVector<f64>> for &[f64; N] {
    fn into_vector(self) -> DVector<f64> {
        DVector::from_column_slice(self)
    }
}

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
    /// The state `(x, w, μ, g)`, each given as an array or an nalgebra vector ([`IntoVector`]).
    pub fn new(
        x: impl IntoVector<SVector<f64, S>>,
        w: impl IntoVector<SVector<f64, S>>,
        mu: impl IntoVector<SVector<f64, K>>,
        g: impl IntoVector<SVector<f64, K>>,
    ) -> Self {
        Self {
            x: x.into_vector(),
            w: w.into_vector(),
            mu: mu.into_vector(),
            g: g.into_vector(),
        }
    }

    /// True when every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        all_finite(&[
            self.x.as_slice(),
            self.w.as_slice(),
            self.mu.as_slice(),
            self.g.as_slice(),
        ])
    }
}

/// Whether every component of `parts` is finite, what every state's `is_finite` asks. `v · 0`
/// is 0 for finite `v` and NaN otherwise: one branch-free sum instead of a short-circuiting test
/// per component (this runs on every step).
#[inline]
pub(crate) fn all_finite(parts: &[&[f64]]) -> bool {
    let mut zero = 0.0;
    for part in parts {
        for v in *part {
            zero += v * 0.0;
        }
    }
    zero == 0.0
}

/// The constructor `$new(q, p)` (each given as whatever [`IntoVector`] takes to the vector
/// types `$q` and `$p`) and `is_finite` of a state `(q, p)`: the unreduced state, the state on
/// rotation groups and the state sized at run time.
macro_rules! qp_state {
    ($(#[$doc:meta])* $new:ident($q:ty, $p:ty)) => {
        $(#[$doc])*
        pub fn $new(
            q: impl crate::state::IntoVector<$q>,
            p: impl crate::state::IntoVector<$p>,
        ) -> Self {
            Self {
                q: crate::state::IntoVector::into_vector(q),
                p: crate::state::IntoVector::into_vector(p),
            }
        }

        /// Whether every component is finite.
        pub fn is_finite(&self) -> bool {
            crate::state::all_finite(&[self.q.as_slice(), self.p.as_slice()])
        }
    };
}
pub(crate) use qp_state;

/// A point `(q, p) ∈ T*Q ≃ Q × Q*` with `q = (x, g)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnreducedState<const N: usize> {
    /// Configuration `q = (x, g)`.
    pub q: SVector<f64, N>,
    /// Canonical momentum `p = (p_x, p_g)`.
    pub p: SVector<f64, N>,
}

impl<const N: usize> UnreducedState<N> {
    qp_state!(
        /// The state `(q, p)` with `q = (x, g)` and `p = (p_x, p_g)` in the order of the system's
        /// coordinates ([`crate::DiscreteLagrangian::SHAPE`], then
        /// [`crate::DiscreteLagrangian::GROUP`]), each given as an array or an nalgebra vector
        /// ([`IntoVector`]).
        new(SVector<f64, N>, SVector<f64, N>)
    );
}
