//! `rule = ...`: the quadrature rule that forms a discrete Lagrangian `L_d` from a continuous
//! `L(q, v)` (see [`crate::ir::discretize`]).

use syn::Ident;

use crate::symbol;

/// What `rule = ...` accepts, for error messages.
pub const RULES: &str = "`rule = midpoint`, `rule = trapezoid`, `rule = left` or `rule = right`";

/// A quadrature rule forming `L_d` from `L`, with `v = (q1 − q0)/h`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// `h L((q0 + q1)/2, v)`.
    Midpoint,
    /// `h/2 (L(q0, v) + L(q1, v))`.
    Trapezoid,
    /// `h L(q0, v)`.
    Left,
    /// `h L(q1, v)`.
    Right,
}

impl Rule {
    /// The rule `id` names, if any.
    pub fn from_ident(id: &Ident) -> Option<Rule> {
        [
            (symbol::MIDPOINT, Rule::Midpoint),
            (symbol::TRAPEZOID, Rule::Trapezoid),
            (symbol::LEFT, Rule::Left),
            (symbol::RIGHT, Rule::Right),
        ]
        .into_iter()
        .find_map(|(word, rule)| (*id == word).then_some(rule))
    }

    /// The rule and its formula, for documentation and messages.
    pub fn describe(self) -> &'static str {
        match self {
            Rule::Midpoint => "the midpoint rule L_d(q0, q1) = h L((q0 + q1)/2, (q1 − q0)/h)",
            Rule::Trapezoid => {
                "the trapezoidal rule L_d(q0, q1) = h/2 (L(q0, (q1 − q0)/h) + L(q1, (q1 − q0)/h))"
            }
            Rule::Left => "the left-point rule L_d(q0, q1) = h L(q0, (q1 − q0)/h)",
            Rule::Right => "the right-point rule L_d(q0, q1) = h L(q1, (q1 − q0)/h)",
        }
    }
}
