//! Adapted coordinates of a system given as text whose symmetry is declared on the user's
//! coordinates (`coordinates(..), translate(..)`): the maps of the runtime's
//! `AdaptedCoordinates` (§2.2.1: `q_user = T q`, `p = Tᵀ p_user`), which the attribute emits as
//! associated functions of the type and a system given at run time provides as methods, with
//! the same sums and differences in the same order (so a state converted here is the compiled-in
//! system's bit for bit). Without a declared translation every map is the identity.

use dirac_compiler::text::UserComponent;
use dirac_runtime::nalgebra::SVector;
use dirac_runtime::UnreducedState;

use super::{Code, JitSystem};

impl Code {
    /// The user components, or `None` when the system's coordinates are the user's.
    fn components(&self) -> Option<&[UserComponent]> {
        self.system.adapted.as_deref()
    }

    /// The number of shape coordinates `S`.
    fn shape_len(&self) -> usize {
        self.system.shape.len()
    }

    /// `q = T⁻¹ q_user`: a translation's group coordinate is its first component `a[0]`, every
    /// other component `c` it moves becomes `r_c = c − a[0]`, other coordinates are unchanged.
    /// `q_user` and `q` have the system's `N` entries.
    pub fn to_adapted(&self, q_user: &[f64], q: &mut [f64]) {
        let Some(components) = self.components() else {
            q.copy_from_slice(q_user);
            return;
        };
        for (u, c) in components.iter().enumerate() {
            match *c {
                UserComponent::Var(a) => q[a] = q_user[u],
                UserComponent::Sum(g, r) => q[r] = q_user[u] - q_user[group_source(components, g)],
            }
        }
    }

    /// `q_user = T q`: `a[0] = g`, `c = g + r_c`.
    pub fn from_adapted(&self, q: &[f64], q_user: &mut [f64]) {
        let Some(components) = self.components() else {
            q_user.copy_from_slice(q);
            return;
        };
        for (u, c) in components.iter().enumerate() {
            q_user[u] = match *c {
                UserComponent::Var(a) => q[a],
                UserComponent::Sum(g, r) => q[g] + q[r],
            };
        }
    }

    /// `p = Tᵀ p_user`: a shape coordinate's momentum is its component's, a group coordinate's
    /// the sum of the momenta of every component its translation moves (the total momentum).
    pub fn momentum_to_adapted(&self, p_user: &[f64], p: &mut [f64]) {
        let Some(components) = self.components() else {
            p.copy_from_slice(p_user);
            return;
        };
        let s = self.shape_len();
        for (u, c) in components.iter().enumerate() {
            match *c {
                UserComponent::Var(a) if a < s => p[a] = p_user[u],
                UserComponent::Sum(_, r) => p[r] = p_user[u],
                UserComponent::Var(_) => {}
            }
        }
        for (a, pa) in p.iter_mut().enumerate().skip(s) {
            let mut moved = components.iter().enumerate().filter_map(|(u, c)| match *c {
                UserComponent::Var(g) | UserComponent::Sum(g, _) if g == a => Some(p_user[u]),
                _ => None,
            });
            // The emitted `p_user[m1] + p_user[m2] + …`, left to right.
            *pa = moved
                .next()
                .map_or(0.0, |first| moved.fold(first, |sum, v| sum + v));
        }
    }

    /// `p_user = T⁻ᵀ p`: a moved component's momentum is its shape coordinate's, the first
    /// component's `p_g − Σ_{c ≠ a[0]} p_{r_c}`.
    pub fn momentum_from_adapted(&self, p: &[f64], p_user: &mut [f64]) {
        let Some(components) = self.components() else {
            p_user.copy_from_slice(p);
            return;
        };
        let s = self.shape_len();
        for (u, c) in components.iter().enumerate() {
            p_user[u] = match *c {
                UserComponent::Sum(_, r) => p[r],
                UserComponent::Var(a) if a < s => p[a],
                UserComponent::Var(g) => components
                    .iter()
                    .filter_map(|c| match *c {
                        UserComponent::Sum(h, r) if h == g => Some(p[r]),
                        _ => None,
                    })
                    .fold(p[g], |rest, pr| rest - pr),
            };
        }
    }
}

/// The user component that carries group coordinate `g` (`a[0]`).
fn group_source(components: &[UserComponent], g: usize) -> usize {
    components
        .iter()
        .position(|c| *c == UserComponent::Var(g))
        .expect("every group coordinate is a user component")
}

impl<const S: usize, const K: usize, const N: usize, V> JitSystem<S, K, N, V> {
    /// `q = T⁻¹ q_user` ([`Code::to_adapted`]); the identity without a declared translation.
    pub fn to_adapted(&self, q_user: &SVector<f64, N>) -> SVector<f64, N> {
        let mut q = SVector::<f64, N>::zeros();
        self.code.to_adapted(q_user.as_slice(), q.as_mut_slice());
        q
    }

    /// `q_user = T q` ([`Code::from_adapted`]).
    pub fn from_adapted(&self, q: &SVector<f64, N>) -> SVector<f64, N> {
        let mut q_user = SVector::<f64, N>::zeros();
        self.code.from_adapted(q.as_slice(), q_user.as_mut_slice());
        q_user
    }

    /// `p = Tᵀ p_user` ([`Code::momentum_to_adapted`]).
    pub fn momentum_to_adapted(&self, p_user: &SVector<f64, N>) -> SVector<f64, N> {
        let mut p = SVector::<f64, N>::zeros();
        self.code
            .momentum_to_adapted(p_user.as_slice(), p.as_mut_slice());
        p
    }

    /// `p_user = T⁻ᵀ p` ([`Code::momentum_from_adapted`]).
    pub fn momentum_from_adapted(&self, p: &SVector<f64, N>) -> SVector<f64, N> {
        let mut p_user = SVector::<f64, N>::zeros();
        self.code
            .momentum_from_adapted(p.as_slice(), p_user.as_mut_slice());
        p_user
    }

    /// The state in adapted coordinates from a configuration and momentum in the user's.
    pub fn adapted_state(
        &self,
        q_user: &SVector<f64, N>,
        p_user: &SVector<f64, N>,
    ) -> UnreducedState<N> {
        UnreducedState {
            q: self.to_adapted(q_user),
            p: self.momentum_to_adapted(p_user),
        }
    }

    /// A state in the user's coordinates converted to adapted ones.
    pub fn to_adapted_state(&self, user: &UnreducedState<N>) -> UnreducedState<N> {
        self.adapted_state(&user.q, &user.p)
    }

    /// A state in adapted coordinates converted to the user's.
    pub fn from_adapted_state(&self, state: &UnreducedState<N>) -> UnreducedState<N> {
        UnreducedState {
            q: self.from_adapted(&state.q),
            p: self.momentum_from_adapted(&state.p),
        }
    }
}
