//! The steps: the one stepping abstraction ([`stepper`]) and the integrators that implement it —
//! the flat family's reduced ([`reduced`], eqs. (4.6)/(4.8)) and unreduced ([`unreduced`])
//! steps, with constraints ([`constrained`]), on rotation groups ([`lie`]) and element-wise
//! ([`element`]); symmetric compositions of a self-adjoint step ([`compose`]), the atlas of
//! charts ([`atlas`], §6), the Gauss–Legendre variational integrators of any even order
//! ([`gauss`]) and adaptive steps by the Poincaré time transformation ([`adaptive`]). Each is
//! re-exported at the crate root under its own name.

pub mod adaptive;
pub mod atlas;
pub mod compose;
pub mod constrained;
pub mod element;
pub mod gauss;
pub mod lie;
pub mod reduced;
pub mod stepper;
pub mod unreduced;
