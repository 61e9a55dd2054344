//! The domain a system declares (`domain(r > 0.0)` in its attribute): bounds on coordinates
//! outside of which a state has no meaning, checked after every step.
//!
//! A step of a variational integrator solves `D2 L_d(q_{k−1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0`
//! for `q_{k+1}` (Definition 2.7; eqs. (4.6)/(4.8) reduced), and these equations do not know
//! where the Lagrangian is defined: Kepler's problem in polar coordinates
//! (`L = ½ (ṙ² + r² φ̇²) + k/r`) has a solution with `r < 0` as readily as one with `r > 0`, and
//! at a step too coarse for the periapsis passage Newton finds it. Nothing in the step can tell
//! the two apart. A declared domain can: every integrator on vector spaces tests the state after
//! each step against it (and the initial state before the first) and stops the run with
//! [`StepError::OutOfDomain`], naming the coordinate and its value, the states computed before
//! it kept.
//!
//! The bounds are data — a coordinate's index in `q = (x, g)`, a relation and a number — so a
//! system given as text declares them with the same key and is checked the same way.

use crate::error::StepError;

/// How a coordinate relates to a bound's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Relation {
    /// `q > value`.
    Above,
    /// `q >= value`.
    AtLeast,
    /// `q < value`.
    Below,
    /// `q <= value`.
    AtMost,
}

impl Relation {
    /// The operator as written in the attribute: `>`, `>=`, `<` or `<=`.
    pub fn operator(self) -> &'static str {
        match self {
            Relation::Above => ">",
            Relation::AtLeast => ">=",
            Relation::Below => "<",
            Relation::AtMost => "<=",
        }
    }
}

/// One bound of a declared domain: coordinate `coordinate` of `q = (x, g)` (shape coordinates
/// first, then group coordinates, as [`crate::DiscreteLagrangian::SHAPE`] and
/// [`crate::DiscreteLagrangian::GROUP`] list them) stands in `relation` to `value`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// The coordinate's index in `q = (x, g)`.
    pub coordinate: usize,
    /// How it relates to `value`.
    pub relation: Relation,
    /// The bound.
    pub value: f64,
}

impl Bound {
    /// The bound `q[coordinate] relation value`.
    pub const fn new(coordinate: usize, relation: Relation, value: f64) -> Self {
        Self {
            coordinate,
            relation,
            value,
        }
    }

    /// Whether `x` satisfies the bound (a NaN never does).
    pub fn holds(&self, x: f64) -> bool {
        match self.relation {
            Relation::Above => x > self.value,
            Relation::AtLeast => x >= self.value,
            Relation::Below => x < self.value,
            Relation::AtMost => x <= self.value,
        }
    }
}

/// The first bound of `bounds` that the configuration `q` (read by index) violates, as the typed
/// error of the state after step `step` (`initial`: the initial state). `names` gives a
/// coordinate's name, and is only called when a bound is violated.
pub(crate) fn check(
    bounds: &[Bound],
    step: usize,
    initial: bool,
    q: impl Fn(usize) -> Option<f64>,
    names: impl Fn(usize) -> String,
) -> Result<(), StepError> {
    for bound in bounds {
        let Some(value) = q(bound.coordinate) else {
            return Err(StepError::InvalidSize {
                reason: format!(
                    "the domain bounds coordinate {}, the configuration has fewer coordinates",
                    bound.coordinate
                ),
            });
        };
        if !bound.holds(value) {
            return Err(StepError::OutOfDomain {
                step,
                initial,
                coordinate: names(bound.coordinate),
                value,
                bound: format!("{} {}", bound.relation.operator(), bound.value),
            });
        }
    }
    Ok(())
}

/// [`check`] for a system on vector spaces, whose configuration is `q = (x, g)` read by `q`.
pub(crate) fn check_system<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    step: usize,
    initial: bool,
    q: impl Fn(usize) -> Option<f64>,
) -> Result<(), StepError>
where
    L: crate::DiscreteLagrangian<S, K, N>,
{
    let bounds = sys.domain();
    if bounds.is_empty() {
        return Ok(());
    }
    check(bounds, step, initial, q, |i| {
        if i < S {
            sys.shape_names().get(i).map(|s| s.to_string())
        } else {
            sys.group_names().get(i - S).map(|s| s.to_string())
        }
        .unwrap_or_else(|| format!("q[{i}]"))
    })
}

#[cfg(test)]
mod tests {
    use super::{check, Bound, Relation};
    use crate::StepError;

    #[test]
    fn each_relation_holds_where_it_should_and_a_nan_never_does() {
        let cases = [
            (Relation::Above, [false, false, true]),
            (Relation::AtLeast, [false, true, true]),
            (Relation::Below, [true, false, false]),
            (Relation::AtMost, [true, true, false]),
        ];
        for (relation, expected) in cases {
            let bound = Bound::new(0, relation, 1.0);
            let got = [0.5, 1.0, 1.5].map(|x| bound.holds(x));
            assert_eq!(got, expected, "{relation:?}");
            assert!(!bound.holds(f64::NAN), "{relation:?}");
        }
    }

    #[test]
    fn a_violated_bound_names_its_coordinate_value_and_step() {
        let bounds = [
            Bound::new(0, Relation::Above, 0.0),
            Bound::new(1, Relation::AtMost, 2.0),
        ];
        let q = [0.5, 3.0];
        let error = check(
            &bounds,
            7,
            false,
            |i| q.get(i).copied(),
            |i| ["r", "z"][i].into(),
        )
        .unwrap_err();
        assert_eq!(
            error,
            StepError::OutOfDomain {
                step: 7,
                initial: false,
                coordinate: "z".into(),
                value: 3.0,
                bound: "<= 2".into()
            }
        );
        let message = error.to_string();
        assert!(
            message.contains("step 7") && message.contains("z = 3"),
            "{message}"
        );
        assert!(check(
            &bounds,
            0,
            true,
            |i| [1.0, 2.0].get(i).copied(),
            |_| String::new()
        )
        .is_ok());
    }
}
