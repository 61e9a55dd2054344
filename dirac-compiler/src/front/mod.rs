//! The front end: what the user wrote, parsed and checked against itself — the attribute
//! grammar ([`attr`]), the coordinate layout ([`layout`]), the function signature
//! ([`signature`]), the sampling ranges ([`ranges`]), the coordinate bounds ([`domain`]), the
//! quadrature rule ([`rule`]) and the chart-transition attribute ([`transition`]). Nothing here
//! reads the body or emits code.

pub mod attr;
pub mod domain;
pub mod element;
pub mod layout;
pub mod lie;
pub mod ranges;
pub mod rule;
pub mod signature;
pub mod transition;

pub use attr::{parse_spec, Spec};
