//! An element-wise system given at run time: its sizes' names, smallest size, kind, controls and
//! families' depths are values (the constants hold placeholders), and the integrators read them
//! from the value — the same steps, bit for bit, as the system compiled in.

use std::ops::Range;

use super::{ElementIntegrator, ElementLagrangian, ElementState, Family, FamilyVisitor};
use crate::domain::{Bound, Relation};
use crate::driver::Drive;
use crate::error::StepError;
use crate::model::System;
use crate::newton::NewtonOptions;
use crate::stepper::{StepAt, Stepper};

/// A ring of `n` particles of mass `m` joined by nearest-neighbour springs with the potential
/// `V(d) = k d²/2 + β d⁴/4`, a continuous Lagrangian under the midpoint rule. One family of
/// elements, `for i in 0..n` reading `x[i]` and `x[(i + 1) % n]`: each element carries half the
/// kinetic energy of its two particles and the spring between them,
/// `L_d^e = h [m (v_0² + v_1²)/4 − V(x̄_1 − x̄_0)]` with `x̄ = (q0 + q1)/2`, `v = (q1 − q0)/h`.
#[derive(Clone, Debug)]
struct Ring {
    h: f64,
    m: f64,
    k: f64,
    beta: f64,
    n: usize,
}

impl Ring {
    fn elements(&self, visit: &mut dyn FnMut(&[i64], [i64; 2])) {
        let n = self.n as i64;
        for i in 0..n {
            visit(&[i], [i, (i + 1) % n]);
        }
    }

    /// The spring's stretch at the midpoint and the velocities.
    fn midpoint(&self, q0: &[f64; 2], q1: &[f64; 2]) -> (f64, [f64; 2]) {
        let d = 0.5 * (q0[1] + q1[1]) - 0.5 * (q0[0] + q1[0]);
        (d, [(q1[0] - q0[0]) / self.h, (q1[1] - q0[1]) / self.h])
    }

    fn potential(&self, d: f64) -> f64 {
        0.5 * self.k * d * d + 0.25 * self.beta * d.powi(4)
    }

    /// `V'(d)`.
    fn tension(&self, d: f64) -> f64 {
        self.k * d + self.beta * d.powi(3)
    }

    fn d1_d2(&self, q0: &[f64; 2], q1: &[f64; 2]) -> ([f64; 2], [f64; 2]) {
        let (d, v) = self.midpoint(q0, q1);
        let (p, t) = (0.5 * self.m, 0.5 * self.h * self.tension(d));
        ([-p * v[0] + t, -p * v[1] - t], [p * v[0] + t, p * v[1] - t])
    }

    #[allow(clippy::type_complexity)]
    fn d1_d2_d12(&self, q0: &[f64; 2], q1: &[f64; 2]) -> ([f64; 2], [f64; 2], [[f64; 2]; 2]) {
        let (d, _) = self.midpoint(q0, q1);
        let (d1, d2) = self.d1_d2(q0, q1);
        let diagonal = -0.5 * self.m / self.h;
        let s = 0.25 * self.h * (self.k + 3.0 * self.beta * d * d);
        (d1, d2, [[diagonal - s, s], [s, diagonal - s]])
    }

    fn value(&self, q0: &[f64; 2], q1: &[f64; 2]) -> f64 {
        let (d, v) = self.midpoint(q0, q1);
        self.h * (0.25 * self.m * (v[0] * v[0] + v[1] * v[1]) - self.potential(d))
    }

    fn energy(&self, q: &[f64; 2], v: &[f64; 2]) -> f64 {
        0.25 * self.m * (v[0] * v[0] + v[1] * v[1]) + self.potential(q[1] - q[0])
    }

    #[allow(clippy::type_complexity)]
    fn legendre(&self, v: &[f64; 2]) -> ([f64; 2], [[f64; 2]; 2]) {
        let p = 0.5 * self.m;
        ([p * v[0], p * v[1]], [[p, 0.0], [0.0, p]])
    }
}

/// The two stencil values of a ring element.
fn pair(q: &[f64]) -> &[f64; 2] {
    q.try_into().expect("a ring element reads two coordinates")
}

/// Implements the element functions of [`Family`] (width 2) by [`Ring`]'s (the family's system
/// holds it in field `ring`).
macro_rules! ring_family {
    () => {
        fn width(&self) -> usize {
            2
        }

        fn elements(&self, visit: &mut dyn FnMut(&[i64], &[i64])) {
            self.0
                .ring
                .elements(&mut |indices, stencil| visit(indices, &stencil))
        }

        fn d1_d2(&self, _: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) {
            let (d1, d2) = self.0.ring.d1_d2(pair(q0), pair(q1));
            out[..2].copy_from_slice(&d1);
            out[2..4].copy_from_slice(&d2);
        }

        fn d1_d2_d12(&self, _: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) {
            let (d1, d2, d12) = self.0.ring.d1_d2_d12(pair(q0), pair(q1));
            out[..2].copy_from_slice(&d1);
            out[2..4].copy_from_slice(&d2);
            out[4..6].copy_from_slice(&d12[0]);
            out[6..8].copy_from_slice(&d12[1]);
        }

        fn value(&self, _: &[i64], q0: &[f64], q1: &[f64]) -> f64 {
            self.0.ring.value(pair(q0), pair(q1))
        }

        fn energy(&self, _: &[i64], q: &[f64], v: &[f64]) -> f64 {
            self.0.ring.energy(pair(q), pair(v))
        }

        fn legendre(&self, _: &[i64], _: &[f64], v: &[f64], out: &mut [f64]) {
            let (p, m) = self.0.ring.legendre(pair(v));
            out[..2].copy_from_slice(&p);
            out[2..4].copy_from_slice(&m[0]);
            out[4..6].copy_from_slice(&m[1]);
        }
    };
}

/// Implements the parameters of [`System`] by [`Ring`]'s (field `ring`); the control is the
/// stiffness `k`.
macro_rules! ring_model {
    () => {
        fn with_controls(&self, u: &[f64]) -> Self {
            let mut system = self.clone();
            system.ring.k = u[0];
            system
        }

        fn time_step(&self) -> f64 {
            self.ring.h
        }

        fn with_time_step(&self, h: f64) -> Self {
            let mut system = self.clone();
            system.ring.h = h;
            system
        }

        fn parameter_values(&self) -> Vec<f64> {
            vec![self.ring.m, self.ring.k, self.ring.beta]
        }

        fn coordinate_names(&self) -> Vec<&str> {
            vec!["x"]
        }
    };
}

/// Implements the run-time parts of [`ElementLagrangian`] by [`Ring`]'s (field `ring`).
macro_rules! ring_system {
    () => {
        fn sizes(&self) -> Vec<usize> {
            vec![self.ring.n]
        }

        fn dim(&self) -> usize {
            self.ring.n
        }

        fn translations(&self) -> Vec<Vec<Range<usize>>> {
            vec![vec![0..self.ring.n]]
        }
    };
}

/// The ring compiled in: everything in the constants.
#[derive(Clone, Debug)]
struct Compiled {
    ring: Ring,
}

struct CompiledSprings<'a>(&'a Compiled);

impl Family for CompiledSprings<'_> {
    fn depth(&self) -> usize {
        1
    }

    ring_family!();
}

impl System for Compiled {
    const PARAMETERS: &'static [&'static str] = &["m", "k", "beta"];
    const CONTROLS: &'static [&'static str] = &["k"];
    ring_model!();
}

impl ElementLagrangian for Compiled {
    const SIZES: &'static [&'static str] = &["n"];
    const MIN_SIZE: usize = 2;
    const CONTINUOUS: bool = true;

    fn families<V: FamilyVisitor>(&self, visitor: &mut V) {
        visitor.family(&CompiledSprings(self));
    }

    ring_system!();
}

/// The ring given at run time: the constants say nothing (or what would fail if read), the
/// value says everything.
#[derive(Clone, Debug)]
struct Given {
    ring: Ring,
    names: Vec<String>,
    min_size: usize,
    continuous: bool,
    controls: usize,
    depth: usize,
    domain: Vec<Bound>,
    time: Option<usize>,
}

impl Given {
    fn new(ring: Ring) -> Self {
        Given {
            ring,
            names: vec!["n".into()],
            min_size: 2,
            continuous: true,
            controls: 1,
            depth: 1,
            domain: Vec::new(),
            time: None,
        }
    }
}

struct GivenSprings<'a>(&'a Given);

impl Family for GivenSprings<'_> {
    fn depth(&self) -> usize {
        self.0.depth
    }

    fn force(&self) -> bool {
        false
    }

    ring_family!();
}

impl System for Given {
    // Placeholders: no names, no controls.
    const PARAMETERS: &'static [&'static str] = &[];

    fn parameter_names(&self) -> Vec<&str> {
        vec!["m", "k", "beta"]
    }

    fn control_count(&self) -> usize {
        self.controls
    }

    fn control_names(&self) -> Vec<&str> {
        vec!["k"]
    }

    fn domain(&self) -> &[Bound] {
        &self.domain
    }

    fn time_index(&self) -> Option<usize> {
        self.time
    }

    ring_model!();
}

impl ElementLagrangian for Given {
    // Placeholders: no names, a smallest size no system allows, a discrete Lagrangian (no
    // energy), forces and constraints, no controls.
    const SIZES: &'static [&'static str] = &[];
    const MIN_SIZE: usize = usize::MAX;
    const CONTINUOUS: bool = false;
    const FORCED: bool = true;
    const CONSTRAINED: bool = true;

    fn size_names(&self) -> Vec<&str> {
        self.names.iter().map(String::as_str).collect()
    }

    fn min_size(&self) -> usize {
        self.min_size
    }

    fn continuous(&self) -> bool {
        self.continuous
    }

    fn forced(&self) -> bool {
        false
    }

    fn constrained(&self) -> bool {
        false
    }

    fn families<V: FamilyVisitor>(&self, visitor: &mut V) {
        visitor.family(&GivenSprings(self));
    }

    ring_system!();
}

fn ring(n: usize) -> Ring {
    Ring {
        h: 0.05,
        m: 1.3,
        k: 2.0,
        beta: 0.7,
        n,
    }
}

/// A stretched ring moving as a whole: `μ = Σ p ≠ 0`.
fn initial(n: usize) -> ElementState {
    let q: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64 * 1.7).sin()).collect();
    let p: Vec<f64> = (0..n).map(|i| 0.3 + 0.5 * (i as f64 * 0.9).cos()).collect();
    ElementState::new(q, p)
}

/// Visits the families and records their shapes: `(width, depth, force)`.
struct Shapes(Vec<(usize, usize, bool)>);

impl FamilyVisitor for Shapes {
    fn family<F: Family>(&mut self, family: &F) {
        self.0
            .push((family.width(), family.depth(), family.force()));
    }
}

#[test]
fn the_provided_methods_say_the_constants() {
    let compiled = Compiled { ring: ring(5) };
    assert_eq!(compiled.size_names(), ["n"]);
    assert_eq!(compiled.min_size(), 2);
    assert!(compiled.continuous());
    assert!(!compiled.forced());
    assert_eq!(compiled.control_count(), 1);
    assert!(!compiled.constrained());
    let mut shapes = Shapes(Vec::new());
    compiled.families(&mut shapes);
    assert_eq!(shapes.0, [(2, 1, false)]);

    let given = Given::new(ring(5));
    assert_eq!(given.size_names(), ["n"]);
    assert_eq!(given.min_size(), 2);
    assert!(given.continuous() && !given.forced() && !given.constrained());
    assert_eq!(given.control_count(), 1);
    let mut shapes = Shapes(Vec::new());
    given.families(&mut shapes);
    assert_eq!(shapes.0, [(2, 1, false)]);
}

/// A domain or a time coordinate the element-wise integrators cannot honour is refused before
/// any step, not ignored.
#[test]
fn a_declared_domain_or_time_coordinate_is_refused_not_ignored() {
    let options = NewtonOptions::default();
    let plain = ElementIntegrator::new(Given::new(ring(5)), options);
    assert!(plain.check(&initial(5)).is_ok());
    let bounded = Given {
        domain: vec![Bound::new(0, Relation::Above, -1.0)],
        ..Given::new(ring(5))
    };
    let refused = ElementIntegrator::new(bounded, options).check(&initial(5));
    assert!(
        matches!(refused, Err(StepError::Unsupported { what }) if what.contains("domain")),
        "{refused:?}"
    );
    let timed = Given {
        time: Some(0),
        ..Given::new(ring(5))
    };
    let refused = ElementIntegrator::minus(timed, options).check(&initial(5));
    assert!(
        matches!(refused, Err(StepError::Unsupported { what }) if what.contains("adaptive")),
        "{refused:?}"
    );
}

#[test]
fn a_system_given_at_run_time_steps_as_the_one_compiled_in() {
    let (n, steps) = (6, 40);
    let options = NewtonOptions::default();
    type Side<L> = fn(L, NewtonOptions) -> ElementIntegrator<L>;
    let sides: [(Side<Compiled>, Side<Given>); 2] = [
        (ElementIntegrator::new, ElementIntegrator::new),
        (ElementIntegrator::minus, ElementIntegrator::minus),
    ];
    for (compiled_side, given_side) in sides {
        let compiled = compiled_side(Compiled { ring: ring(n) }, options);
        let given = given_side(Given::new(ring(n)), options);
        assert_eq!(compiled.variant(), given.variant());
        given.check(&initial(n)).expect("a valid initial state");
        let a = compiled.run(initial(n)).steps(steps).collect().unwrap();
        let b = given.run(initial(n)).steps(steps).collect().unwrap();
        assert_eq!(a, b);
        // The ring moves: Newton iterated, and the momentum map is kept exact.
        assert_ne!(b.states[steps].q, b.states[0].q);
        let mu = given.momentum_map(&b.states[0]).unwrap();
        assert!(mu[0].abs() > 1.0);
        for state in &b.states {
            assert!((given.momentum_map(state).unwrap()[0] - mu[0]).abs() < 1e-12);
        }
        // A continuous Lagrangian, from the value: the same energies, node and midpoint (the
        // node energies solve the Legendre map, which a force family has no share of).
        assert_eq!(given.energies(&b).unwrap(), compiled.energies(&a).unwrap());
        assert_eq!(
            given.discrete_lagrangian(&b.states[0].q, &b.states[1].q),
            compiled.discrete_lagrangian(&a.states[0].q, &a.states[1].q)
        );
    }
}

#[test]
fn the_smallest_size_and_the_controls_are_the_values() {
    let n = 6;
    let options = NewtonOptions::default();
    let compiled = ElementIntegrator::new(Compiled { ring: ring(n) }, options);
    let given = ElementIntegrator::new(Given::new(ring(n)), options);

    // The controls: the value's count, and a controlled step as compiled in.
    assert_eq!((compiled.control_dim(), given.control_dim()), (1, 1));
    let start = initial(n);
    let at = |u| StepAt::new(0, 0.05).with_controls(u);
    let (a, _) = compiled
        .step_with(&mut compiled.workspace(), at(&[3.0]), &start)
        .unwrap();
    let (b, _) = given
        .step_with(&mut given.workspace(), at(&[3.0]), &start)
        .unwrap();
    assert_eq!(a, b);
    let (free, _) = given.step_in(&mut given.workspace(), 0, &start).unwrap();
    assert_ne!(free, b);
    assert!(matches!(
        given.step_with(&mut given.workspace(), at(&[3.0, 1.0]), &start),
        Err(StepError::InvalidControls {
            expected: 1,
            found: 2,
            ..
        })
    ));
    // A step's sensitivity checks the controls against the value's count too (before it finds
    // that the hand-written family has no step partials).
    assert!(matches!(
        given.sensitivity(0, &start, &b, &[3.0, 1.0]),
        Err(StepError::InvalidControls {
            expected: 1,
            found: 2,
            ..
        })
    ));
    let mut none = Given::new(ring(n));
    none.controls = 0;
    let none = ElementIntegrator::new(none, options);
    assert_eq!(none.control_dim(), 0);
    assert!(matches!(
        none.step_with(&mut none.workspace(), at(&[3.0]), &start),
        Err(StepError::InvalidControls {
            expected: 0,
            found: 1,
            ..
        })
    ));

    // The smallest size: the value's, named by the value's names.
    let one = ElementIntegrator::new(Given::new(ring(1)), options);
    match one.check(&initial(1)) {
        Err(StepError::InvalidSize { reason }) => {
            assert!(reason.contains("`n` = 1"), "{reason}");
            assert!(reason.contains("(2)"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let mut larger = Given::new(ring(n));
    larger.min_size = n + 1;
    larger.names = vec!["particles".into()];
    match ElementIntegrator::new(larger, options).check(&start) {
        Err(StepError::InvalidSize { reason }) => {
            assert!(reason.contains("`particles` = 6"), "{reason}");
        }
        other => panic!("{other:?}"),
    }

    // The kind: a discrete Lagrangian has no energy, whatever the constant says.
    let mut discrete = Given::new(ring(n));
    discrete.continuous = false;
    let discrete = ElementIntegrator::new(discrete, options);
    assert!(matches!(
        discrete.energy(&start.q, &b.q),
        Err(StepError::Unsupported { .. })
    ));
    assert!(given.energy(&start.q, &b.q).is_ok());
    // A family that is not a force has no impulse, whatever its constant says (on an orbit of
    // one coordinate, the springs' `D_1 L_d^e + D_2 L_d^e` do not cancel).
    let (q0, q1, first) = (start.q.as_slice(), b.q.as_slice(), 0..1);
    assert_eq!(super::sums::impulse(given.system(), &[first], q0, q1), 0.0);
}
