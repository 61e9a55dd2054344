//! The attribute keys, each spelled once (serde_derive's `symbol.rs`): the parsers match on
//! these and the messages print them; and the one parser of an attribute argument,
//! `key(...)` or `key = ...` ([`KeyArg`]), that all three attributes share.

use std::fmt::{self, Display};

use syn::parse::{Parse, ParseStream, Parser};
use syn::punctuated::Punctuated;
use syn::{Ident, Token};

use crate::ctxt::Ctxt;

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
/// `domain(r > 0.0, ..)`: bounds on coordinates, checked after every step.
pub const DOMAIN: Symbol = Symbol("domain");
/// `rule = midpoint`.
pub const MIDPOINT: Symbol = Symbol("midpoint");
/// `rule = trapezoid`.
pub const TRAPEZOID: Symbol = Symbol("trapezoid");
/// `rule = left`.
pub const LEFT: Symbol = Symbol("left");
/// `rule = right`.
pub const RIGHT: Symbol = Symbol("right");
/// `rotation(R, ..)`: coordinates in the rotation group `SO(3)` (a 3 × 3 matrix in the body).
pub const ROTATION: Symbol = Symbol("rotation");
/// `direction(n, ..)`: coordinates on the sphere `S²` (a unit 3-vector in the body).
pub const DIRECTION: Symbol = Symbol("direction");
/// `pose(X, ..)`: coordinates in the group of rigid motions `SE(3)` (a rotation and a
/// translation in the body).
pub const POSE: Symbol = Symbol("pose");
/// The keys that declare coordinates on a group other than the line: any of them makes the
/// attribute one of a system on groups (`crate::front::lie`), whose coordinate kinds are these and
/// `shape`, `group`.
pub const GROUP_COORDINATES: [Symbol; 3] = [ROTATION, DIRECTION, POSE];
/// `time(t)`: the group coordinate that is physical time, for adaptive steps.
pub const TIME: Symbol = Symbol("time");
/// `adapt = |q| g`: the step monitor of adaptive steps, `dt = g(q) dτ`.
pub const ADAPT: Symbol = Symbol("adapt");
/// `symmetry(R)` or `symmetry(n, .., axis = z)`: rotations that leave the Lagrangian invariant.
pub const SYMMETRY: Symbol = Symbol("symmetry");
/// `axis = x | y | z` inside `symmetry(..)`: the fixed axis of the rotations.
pub const AXIS: Symbol = Symbol("axis");
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
pub const KEYS: [Symbol; 16] = [
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
    TIME,
    ADAPT,
    DOMAIN,
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

/// One argument of an attribute: `key(...)` with its contents, or `key = value`. What the
/// contents and the value are depends on the attribute and the key, so [`KeyArg::parse_with`]
/// leaves both to its caller.
pub enum KeyArg<L, V> {
    /// `key(...)`, the contents parsed.
    List(Ident, L),
    /// `key = value`.
    Value(Ident, V),
}

impl<L, V> KeyArg<L, V> {
    /// The key as written.
    pub fn key(&self) -> &Ident {
        match self {
            KeyArg::List(key, _) | KeyArg::Value(key, _) => key,
        }
    }

    /// Parses a key, then `(...)` with `list(key, contents)` or `= ...` with
    /// `value(key, input)`; a key followed by neither is an error at the key, `neither(key)`
    /// its message. The first syntax error ends the attribute's parse (as syn does).
    pub fn parse_with(
        input: ParseStream,
        list: impl FnOnce(&Ident, ParseStream) -> syn::Result<L>,
        value: impl FnOnce(&Ident, ParseStream) -> syn::Result<V>,
        neither: impl FnOnce(&Ident) -> String,
    ) -> syn::Result<Self> {
        let key: Ident = input.parse()?;
        if input.peek(syn::token::Paren) {
            let content;
            syn::parenthesized!(content in input);
            let contents = list(&key, &content)?;
            Ok(KeyArg::List(key, contents))
        } else if input.peek(Token![=]) {
            input.parse::<Token![=]>()?;
            let value = value(&key, input)?;
            Ok(KeyArg::Value(key, value))
        } else {
            Err(syn::Error::new(key.span(), neither(&key)))
        }
    }
}

/// The message of a key followed by neither `(...)` nor `= ...`, for an attribute that accepts
/// `accepted`.
pub fn list_or_value(key: &Ident, accepted: &str) -> String {
    format!("expected `{key}(...)` or `{key} = ...`; accepted: {accepted}")
}

/// An attribute's comma-separated arguments, each parsed as `A` (a [`KeyArg`]); `None` after
/// the first syntax error, which is recorded in `cx`.
pub fn parse_args<A: Parse>(
    cx: &Ctxt,
    args: proc_macro2::TokenStream,
) -> Option<Punctuated<A, Token![,]>> {
    match Punctuated::<A, Token![,]>::parse_terminated.parse2(args) {
        Ok(args) => Some(args),
        Err(e) => {
            cx.syn_error(e);
            None
        }
    }
}
