//! The back end: graph → straight-line Rust ([`emit`]) and → a straight-line program as data
//! ([`program`]), the backend choice by size ([`backend`]), the one table of trait impls
//! rendered with real or stub bodies ([`impls`]), the items around them ([`items`],
//! [`adapted`]), and the bodies of a system ([`system`]), of a continuous Lagrangian
//! ([`continuous`]) and of a chart transition ([`transition`]). Every emitted item carries the
//! lint allowances of [`lints`].

pub mod adapted;
pub mod backend;
pub mod constrained;
pub mod continuous;
pub mod element;
pub mod emit;
pub mod impls;
pub mod items;
pub mod lie;
pub mod lints;
pub mod program;
pub mod system;
pub mod transition;
