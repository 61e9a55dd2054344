//! The middle: the body lowered to a hash-consed expression graph ([`lower`], [`graph`]),
//! a continuous `L` discretized by its rule ([`discretize`]), the forces from their virtual work
//! ([`force`]), the compile-time invariance check
//! ([`check`]), forward-mode and reverse-mode derivatives ([`diff`]), the paper's constructions ([`reduce`]),
//! all of it driven for a system by [`compile`] and for a chart transition by [`transition`].
//! Imports only the front end ([`crate::front`]); emits no code.

pub mod adapt;
pub mod check;
pub mod compile;
pub mod constraint;
pub mod diff;
pub mod discretize;
pub mod element;
pub mod force;
pub mod graph;
pub mod group;
pub mod lie;
pub mod lower;
pub mod reduce;
pub mod transition;
