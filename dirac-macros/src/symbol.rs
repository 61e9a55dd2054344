//! The attribute keys, each spelled once (serde_derive's `symbol.rs`): the parsers match on
//! these and the messages print them.

use std::fmt::{self, Display};

use syn::Ident;

/// An attribute key or keyword value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Symbol(pub &'static str);

/// `shape(x, y[3], ...)`: the shape coordinates.
pub const SHAPE: Symbol = Symbol("shape");
/// `group(theta, ...)`: the group coordinates.
pub const GROUP: Symbol = Symbol("group");
/// `coordinates(x[4], ...)`: the user's own coordinates.
pub const COORDINATES: Symbol = Symbol("coordinates");
/// `translate(x, ...)`: one declared translation.
pub const TRANSLATE: Symbol = Symbol("translate");
/// `connection = [[..], ..]`: the connection matrix `B`.
pub const CONNECTION: Symbol = Symbol("connection");
/// `step = h`: the time-step parameter.
pub const STEP: Symbol = Symbol("step");
/// `name = Type`: the emitted type.
pub const NAME: Symbol = Symbol("name");
/// `rule = midpoint`: the quadrature rule of a continuous Lagrangian.
pub const RULE: Symbol = Symbol("rule");
/// `ranges(h = (lo, hi), ..)`: the invariance check's sampling ranges.
pub const RANGES: Symbol = Symbol("ranges");
/// `controls(u, ..)`: the parameters a control law sets before every step.
pub const CONTROLS: Symbol = Symbol("controls");
/// `force = |dq| ..` or `force = |dq0, dq1| ..`: the virtual work of the forces.
pub const FORCE: Symbol = Symbol("force");
/// `constraints = |q| [φ_1, ..]`: holonomic constraints `φ(q) = 0`.
pub const CONSTRAINTS: Symbol = Symbol("constraints");
/// `nonholonomic = |q, v| [A_1(q) v, ..]`: nonholonomic constraints `A(q) v = 0`.
pub const NONHOLONOMIC: Symbol = Symbol("nonholonomic");
/// `rule = midpoint`.
pub const MIDPOINT: Symbol = Symbol("midpoint");
/// `rule = trapezoid`.
pub const TRAPEZOID: Symbol = Symbol("trapezoid");
/// `rule = left`.
pub const LEFT: Symbol = Symbol("left");
/// `rule = right`.
pub const RIGHT: Symbol = Symbol("right");
/// `#[chart_transition(from(..))]`: the old chart.
pub const FROM: Symbol = Symbol("from");
/// `#[chart_transition(to(..))]`: the new chart.
pub const TO: Symbol = Symbol("to");

impl PartialEq<Symbol> for Ident {
    fn eq(&self, word: &Symbol) -> bool {
        self == word.0
    }
}

impl PartialEq<Symbol> for &Ident {
    fn eq(&self, word: &Symbol) -> bool {
        *self == word.0
    }
}

/// The keys of `#[reduced_lagrangian(...)]`.
pub const KEYS: [Symbol; 13] = [
    SHAPE,
    GROUP,
    COORDINATES,
    TRANSLATE,
    CONNECTION,
    STEP,
    NAME,
    RULE,
    RANGES,
    CONTROLS,
    FORCE,
    CONSTRAINTS,
    NONHOLONOMIC,
];

/// The key `ident` spells, if it is one of [`KEYS`].
pub fn key(ident: &Ident) -> Option<Symbol> {
    KEYS.iter().copied().find(|k| ident == k)
}

impl PartialEq<Symbol> for String {
    fn eq(&self, word: &Symbol) -> bool {
        self == word.0
    }
}

impl PartialEq<Symbol> for str {
    fn eq(&self, word: &Symbol) -> bool {
        self == word.0
    }
}

impl Display for Symbol {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}
