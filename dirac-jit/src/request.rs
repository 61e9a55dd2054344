//! One run request for a system given as text, whatever its family: which equations (the
//! runtime's one vocabulary, [`Equations`]), which order, how many steps (up to which time, of
//! which sizes), and Newton's options —
//! what a front end (the Python package's classes, a command line) reads from its user, checked
//! against the compiled system in one place before the run is dispatched to its family's
//! integrators.

use std::sync::Arc;

use dirac_runtime::{Equations, Form, NewtonOptions};

use crate::{Compiled, Error};

/// The orders a run takes by [`Scheme::Compositions`]: 2 (the integrator itself), 4 (the triple
/// jump) and 6 (Kahan–Li's composition), the symmetric compositions of the integrator of order 2.
pub const ORDERS: [u32; 3] = [2, 4, 6];

/// How a run reaches its order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scheme {
    /// The system's integrator of order 2, or its symmetric compositions of order 4 and 6
    /// ([`ORDERS`]); the keyword "composition".
    #[default]
    Compositions,
    /// The Gauss–Legendre variational integrator of the order, any even order from 2 to 32
    /// (`dirac_runtime::gauss`), for a system on vector spaces with a continuous Lagrangian
    /// `L(q, v)` without constraints; the keyword "gauss".
    Gauss,
}

impl Scheme {
    /// The scheme a front end's keyword names: "composition" or "gauss".
    pub fn from_keyword(word: &str) -> Option<Self> {
        match word {
            "composition" => Some(Scheme::Compositions),
            "gauss" => Some(Scheme::Gauss),
            _ => None,
        }
    }
}

/// What a run of a system given as text is asked for, apart from the parameters and the start.
///
/// ```
/// use dirac_jit::{compile_any, RunRequest};
/// use dirac_runtime::{Form, Variant};
///
/// let kepler = compile_any(
///     "#[reduced_lagrangian(shape(r), group(phi))]
///      fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
///          let (dr, dphi) = (q1.r - q0.r, q1.phi - q0.phi);
///          let r = 0.5 * (q0.r + q1.r);
///          0.5 / h * (dr * dr + r * r * dphi * dphi) + h / r
///      }",
/// )?;
/// // "minus": the reduced (−) equations, the family's own form on the other side.
/// let request = RunRequest::from_keywords(&kepler, "minus", "composition", 4, 100, Some(1e-12))?;
/// assert_eq!((request.equations.form, request.equations.side), (Form::Reduced, Variant::Minus));
/// assert_eq!((request.order, request.steps, request.newton.abs_tol), (4, 100, 1e-12));
/// // Mistakes are typed errors that say what is accepted.
/// let e = RunRequest::from_keywords(&kepler, "plus", "composition", 3, 100, None).unwrap_err();
/// assert!(e.to_string().contains("accepted 2"), "{e}");
/// // Gauss–Legendre at higher order needs `L(q, v)`; this text is a discrete Lagrangian.
/// let e = RunRequest::from_keywords(&kepler, "plus", "gauss", 8, 100, None).unwrap_err();
/// assert!(e.to_string().contains("continuous Lagrangian"), "{e}");
/// # Ok::<(), dirac_jit::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RunRequest {
    /// Which equations: their form (reduced or unreduced) and side (+ or −).
    pub equations: Equations,
    /// 2, 4 or 6 ([`ORDERS`]) by compositions, any even order from 2 to 32 by Gauss–Legendre.
    pub order: u32,
    /// How the order is reached.
    pub scheme: Scheme,
    /// The number of steps: with [`Self::end_time`], at most this many.
    pub steps: usize,
    /// Up to this time, reached exactly (the run API's `end_time`:
    /// the last step shortened to land on it), or `None` for `steps` steps of the system's own
    /// size.
    pub end_time: Option<f64>,
    /// The size of each step, `h_0, h_1, …` (the run API's `StepSizes`), or `None` for every
    /// step of the system's own size; set through [`Self::with_schedule`], which checks it.
    pub schedule: Option<Arc<[f64]>>,
    /// Newton's options for each step.
    pub newton: NewtonOptions,
}

impl Compiled {
    /// The form of the equations the family integrates as its own, of which "plus" and "minus"
    /// name the sides ([`Equations::from_keyword`]): reduced for a system on vector spaces (the
    /// paper's eqs. (4.6) and (4.8)), unreduced on rotation groups and element-wise.
    pub fn own_form(&self) -> Form {
        match self {
            Compiled::Flat(_) => Form::Reduced,
            Compiled::Lie(_) | Compiled::Element(_) => Form::Unreduced,
        }
    }

    /// Whether the system runs the constrained integrators (which compose no further than
    /// order 2).
    fn constrained(&self) -> bool {
        match self {
            Compiled::Flat(code) => code.system().constrained.is_some(),
            Compiled::Lie(_) => false,
            Compiled::Element(code) => code.system().constraints.is_some(),
        }
    }
}

impl RunRequest {
    /// The request of `steps` steps of `equations` at order 2 with Newton's default options.
    pub fn new(equations: Equations, steps: usize) -> Self {
        RunRequest {
            equations,
            order: 2,
            scheme: Scheme::Compositions,
            steps,
            end_time: None,
            schedule: None,
            newton: NewtonOptions::default(),
        }
    }

    /// The request ending at the time `t` (or not, `None`), at most [`Self::steps`] steps; a
    /// time that is not a positive finite number (a run starts at 0) is refused.
    pub fn with_end_time(mut self, t: Option<f64>) -> Result<Self, Error> {
        if let Some(t) = t {
            if !(t.is_finite() && t > 0.0) {
                return Err(request(format!(
                    "end_time = {t}: a run starts at time 0 and ends at a positive finite time"
                )));
            }
        }
        self.end_time = t;
        Ok(self)
    }

    /// The request stepping through the sizes `schedule` (or each step of the system's own size,
    /// `None`): step `k` has size `schedule[k]`, by the run API's `StepSizes` (the last step
    /// shortened to land on [`Self::end_time`] when one is given). Every size is a positive
    /// finite number and there is one for each of the [`Self::steps`] the run may take; anything
    /// else is refused, saying what is accepted.
    pub fn with_schedule(mut self, schedule: Option<Vec<f64>>) -> Result<Self, Error> {
        if let Some(sizes) = &schedule {
            if let Some((k, h)) = sizes
                .iter()
                .enumerate()
                .find(|(_, h)| !(h.is_finite() && **h > 0.0))
            {
                return Err(request(format!(
                    "schedule[{k}] = {h}: each step size is a positive finite number"
                )));
            }
            if sizes.len() < self.steps {
                return Err(request(format!(
                    "schedule: {} step sizes for {} steps; give one size for each step (steps                      at most the schedule's length)",
                    sizes.len(),
                    self.steps
                )));
            }
        }
        self.schedule = schedule.map(Arc::from);
        Ok(self)
    }

    /// The request a front end's keywords make for `system`: the equations named by `method`
    /// ("plus", "minus", "reduced", "unreduced"), the scheme named by `scheme` ("composition",
    /// "gauss"), the `order`, the `steps` and, when given, the absolute tolerance `tol` of
    /// Newton's residual; checked against the system ([`Self::check`]).
    pub fn from_keywords(
        system: &Compiled,
        method: &str,
        scheme: &str,
        order: u32,
        steps: usize,
        tol: Option<f64>,
    ) -> Result<Self, Error> {
        let equations = Equations::from_keyword(method, system.own_form()).ok_or_else(|| {
            let accepted = match system {
                Compiled::Element(_) => {
                    "\"plus\", \"minus\", \"unreduced\" (an element-wise system declares no \
                     reduction)"
                }
                _ => "\"plus\", \"minus\", \"reduced\", \"unreduced\"",
            };
            request(format!("unknown method `{method}`; accepted: {accepted}"))
        })?;
        let scheme = Scheme::from_keyword(scheme).ok_or_else(|| {
            request(format!(
                "unknown scheme `{scheme}`; accepted: \"composition\" (order 2, 4, 6), \"gauss\" \
                 (Gauss–Legendre, any even order 2 to 32)"
            ))
        })?;
        let mut newton = NewtonOptions::default();
        if let Some(tol) = tol {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(request(format!(
                    "tol = {tol}: Newton's absolute tolerance is a positive finite number"
                )));
            }
            newton.abs_tol = tol;
        }
        let r = RunRequest {
            equations,
            order,
            scheme,
            steps,
            end_time: None,
            schedule: None,
            newton,
        };
        r.check(system)?;
        Ok(r)
    }

    /// Whether `system` can run this request: the order one of [`ORDERS`] (2 for a system with
    /// constraints), or by Gauss–Legendre an even order from 2 to 32 of a system on vector
    /// spaces with stage derivatives (a continuous Lagrangian without constraints, at most
    /// [`crate::MAX_DISPATCHED`] coordinates); reduced equations only for a system that has them
    /// (one on rotation groups declares its `symmetry(..)`; an element-wise system declares no
    /// reduction).
    pub fn check(&self, system: &Compiled) -> Result<(), Error> {
        if self.scheme == Scheme::Gauss {
            let most = 2 * dirac_runtime::gauss::MAX_STAGES as u32;
            if !self.order.is_multiple_of(2) || !(2..=most).contains(&self.order) {
                return Err(request(format!(
                    "order {}: a Gauss–Legendre run takes an even order from 2 to {most}",
                    self.order
                )));
            }
            let Compiled::Flat(code) = system else {
                return Err(request(
                    "scheme \"gauss\": Gauss–Legendre runs a system on vector spaces (one on \
                     rotation groups or element-wise runs order 2, or 4 and 6 by compositions)",
                ));
            };
            if !code.has_stages() {
                return Err(request(format!(
                    "scheme \"gauss\": the system `{}` has no stage derivatives; Gauss–Legendre \
                     needs a continuous Lagrangian `fn l(q: Config, v: Velocity, ..)` with a \
                     `rule`, on at most 16 coordinates and without constraints",
                    code.system().name
                )));
            }
            if !code.fixed_size() {
                return Err(request(format!(
                    "scheme \"gauss\": at most {} coordinates from a system given as text",
                    crate::MAX_DISPATCHED
                )));
            }
            return Ok(());
        }
        if !ORDERS.contains(&self.order) {
            return Err(request(format!(
                "order {}: accepted 2 (the integrator itself), 4 (triple jump), 6 (Kahan–Li)",
                self.order
            )));
        }
        if self.order != 2 && system.constrained() {
            return Err(request(format!(
                "order {}: a system with constraints runs the constrained integrators \
                 themselves (order 2)",
                self.order
            )));
        }
        if self.equations.form == Form::Reduced {
            match system {
                Compiled::Lie(code) if code.system().symmetry.is_none() => {
                    return Err(request(
                        "method \"reduced\": the system declares no symmetry (`symmetry(..)`)",
                    ))
                }
                Compiled::Element(_) => {
                    return Err(request(
                        "method \"reduced\": an element-wise system declares no reduction",
                    ))
                }
                _ => {}
            }
        }
        Ok(())
    }
}

fn request(reason: impl Into<String>) -> Error {
    Error::Request {
        reason: reason.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dirac_runtime::Variant;

    const KEPLER: &str = "#[reduced_lagrangian(shape(r), group(phi))]
        fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
            let (dr, dphi) = (q1.r - q0.r, q1.phi - q0.phi);
            let r = 0.5 * (q0.r + q1.r);
            0.5 / h * (dr * dr + r * r * dphi * dphi) + h / r
        }";
    const BODY: &str = "#[reduced_lagrangian(rotation(r))]
        fn body(q0: Config, q1: Config, h: f64) -> f64 {
            let f = q0.r.transpose() * q1.r;
            (Matrix3::identity() - f).trace() / h
        }";
    const CHAIN: &str = "#[reduced_lagrangian(coordinates(x[n]), rule = midpoint)]
        fn chain(q: Config, v: Velocity, n: usize) -> f64 {
            let mut l = 0.0;
            for i in 0..n { l += 0.5 * v.x[i] * v.x[i]; }
            l
        }";
    const ROD: &str = "#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
            constraints = |q| [q.x * q.x + q.y * q.y - 1.0])]
        fn rod(q: Config, v: Velocity) -> f64 { 0.5 * (v.x * v.x + v.y * v.y) - q.y }";

    const CONTINUOUS: &str = "#[reduced_lagrangian(shape(r), group(phi), rule = midpoint)]
        fn kepler(q: Config, v: Velocity) -> f64 {
            0.5 * (v.r * v.r + q.r * q.r * v.phi * v.phi) + 1.0 / q.r
        }";

    fn compiled(text: &str) -> Compiled {
        crate::compile_any(text).expect("the test system compiles")
    }

    fn refused(system: &Compiled, method: &str, order: u32, tol: Option<f64>) -> String {
        match RunRequest::from_keywords(system, method, "composition", order, 10, tol) {
            Err(Error::Request { reason }) => reason,
            other => panic!("{method}, order {order}, tol {tol:?}: {other:?}"),
        }
    }

    #[test]
    fn the_words_name_each_familys_equations() {
        let (flat, lie, element) = (compiled(KEPLER), compiled(BODY), compiled(CHAIN));
        let words = |system: &Compiled, word: &str| {
            let e = RunRequest::from_keywords(system, word, "composition", 2, 10, None)
                .expect("accepted")
                .equations;
            (e.form, e.side)
        };
        use Form::{Reduced, Unreduced};
        use Variant::{Minus, Plus};
        assert_eq!(words(&flat, "plus"), (Reduced, Plus));
        assert_eq!(words(&flat, "minus"), (Reduced, Minus));
        assert_eq!(words(&flat, "reduced"), (Reduced, Plus));
        assert_eq!(words(&flat, "unreduced"), (Unreduced, Plus));
        assert_eq!(words(&lie, "minus"), (Unreduced, Minus));
        assert_eq!(words(&lie, "unreduced"), (Unreduced, Plus));
        assert_eq!(words(&element, "plus"), (Unreduced, Plus));
        assert_eq!(words(&element, "unreduced"), (Unreduced, Plus));
    }

    #[test]
    fn what_a_system_cannot_run_is_a_typed_error_saying_what_is_accepted() {
        let (flat, lie, element) = (compiled(KEPLER), compiled(BODY), compiled(CHAIN));
        assert!(refused(&flat, "sideways", 2, None).contains("\"unreduced\""));
        assert!(refused(&element, "sideways", 2, None).contains("no reduction"));
        assert!(refused(&element, "reduced", 2, None).contains("no reduction"));
        assert!(refused(&lie, "reduced", 2, None).contains("declares no symmetry"));
        assert!(refused(&flat, "plus", 3, None).contains("accepted 2"));
        assert!(refused(&compiled(ROD), "unreduced", 4, None).contains("constrained"));
        for tol in [0.0, -1e-12, f64::NAN, f64::INFINITY] {
            assert!(refused(&flat, "plus", 2, Some(tol)).contains("positive finite"));
        }
        // Gauss–Legendre: an even order up to 32 of a continuous Lagrangian without constraints.
        let continuous = compiled(CONTINUOUS);
        let gauss = |system: &Compiled, order: u32| match RunRequest::from_keywords(
            system, "plus", "gauss", order, 10, None,
        ) {
            Err(Error::Request { reason }) => reason,
            Ok(r) => panic!("accepted: {r:?}"),
            Err(other) => panic!("{other:?}"),
        };
        for order in [2, 8, 32] {
            let r = RunRequest::from_keywords(&continuous, "minus", "gauss", order, 10, None)
                .expect("an even order up to 32");
            assert_eq!((r.scheme, r.order), (Scheme::Gauss, order));
        }
        for order in [0, 7, 34] {
            assert!(gauss(&continuous, order).contains("even order from 2 to 32"));
        }
        assert!(gauss(&flat, 8).contains("continuous Lagrangian"));
        assert!(gauss(&compiled(ROD), 4).contains("without constraints"));
        assert!(gauss(&lie, 4).contains("vector spaces"));
        assert!(gauss(&element, 4).contains("vector spaces"));
        match RunRequest::from_keywords(&continuous, "plus", "runge", 4, 10, None) {
            Err(Error::Request { reason }) => assert!(reason.contains("\"gauss\"")),
            other => panic!("{other:?}"),
        }
        let r = RunRequest::from_keywords(
            &compiled(ROD),
            "unreduced",
            "composition",
            2,
            10,
            Some(1e-13),
        )
        .expect("order 2 with constraints");
        assert_eq!(r.newton.abs_tol, 1e-13);
        for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            match r.clone().with_end_time(Some(t)) {
                Err(Error::Request { reason }) => assert!(reason.contains("positive finite")),
                other => panic!("end_time {t}: {other:?}"),
            }
        }
        assert_eq!(
            r.clone().with_end_time(Some(0.5)).map(|r| r.end_time).ok(),
            Some(Some(0.5))
        );
    }

    #[test]
    fn a_schedule_is_one_positive_finite_size_for_each_step() {
        let r = RunRequest::from_keywords(&compiled(KEPLER), "plus", "composition", 2, 3, None)
            .expect("valid");
        for (sizes, says) in [
            (vec![0.1, 0.0, 0.1], "schedule[1] = 0"),
            (vec![0.1, 0.1, -0.2], "schedule[2] = -0.2"),
            (vec![f64::NAN, 0.1, 0.1], "schedule[0] = NaN"),
            (vec![0.1, f64::INFINITY, 0.1], "schedule[1] = inf"),
            (vec![0.1, 0.1], "2 step sizes for 3 steps"),
            (vec![], "0 step sizes for 3 steps"),
        ] {
            match r.clone().with_schedule(Some(sizes.clone())) {
                Err(Error::Request { reason }) => assert!(reason.contains(says), "{reason}"),
                other => panic!("{sizes:?}: {other:?}"),
            }
        }
        let given = r
            .clone()
            .with_schedule(Some(vec![0.1, 0.05, 0.05, 0.2]))
            .expect("four sizes for three steps");
        assert_eq!(given.schedule.as_deref(), Some(&[0.1, 0.05, 0.05, 0.2][..]));
        assert_eq!(r.with_schedule(None).map(|r| r.schedule).ok(), Some(None));
    }
}
