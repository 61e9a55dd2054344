//! A system on rotation groups given at run time: its coordinates, parameters, controls and
//! symmetry are values (the constants hold placeholders), and the integrators read them from the
//! value — the same steps, bit for bit, as the system compiled in.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::{
    cayley, matrix_at, rows, vee, CoordinateKind, LieIntegrator, LieLagrangian, LieState,
    LieSymmetric, ReducedLieIntegrator, ReducedLieTrajectory, RotationSymmetry,
};
use crate::domain::{Bound, Relation};
use crate::error::StepError;
use crate::linalg::Lu;
use crate::model::System;
use crate::newton::NewtonOptions;
use crate::stepper::{StepAt, Stepper};

/// The free rigid body, `L_d = tr((I − F) J_d)/h` with `F = R0ᵀ R1` and
/// `J_d = ½ tr(J) I − J`: `h Π_k = vee(F J_d − J_d Fᵀ)`, `h Π_{k+1} = vee(J_d F − Fᵀ J_d)`.
#[derive(Clone, Debug)]
struct Body {
    h: f64,
    inertia: Vector3<f64>,
}

impl Body {
    fn j_d(&self) -> Matrix3<f64> {
        let j = Matrix3::from_diagonal(&self.inertia);
        Matrix3::identity() * (0.5 * j.trace()) - j
    }

    fn lagrangian(&self, q0: &SVector<f64, 9>, q1: &SVector<f64, 9>) -> f64 {
        let f = matrix_at(q0.as_slice(), 0).transpose() * matrix_at(q1.as_slice(), 0);
        ((Matrix3::identity() - f) * self.j_d()).trace() / self.h
    }

    fn retract(&self, q: &SVector<f64, 9>, z: &SVector<f64, 3>) -> SVector<f64, 9> {
        let r = matrix_at(q.as_slice(), 0) * cayley(&Vector3::new(z[0], z[1], z[2]));
        SVector::from(rows(&r))
    }

    fn residual(&self, p: &SVector<f64, 3>, z: &SVector<f64, 3>) -> SVector<f64, 3> {
        let (f, j_d) = (cayley(&Vector3::new(z[0], z[1], z[2])), self.j_d());
        p - vee(&(f * j_d - j_d * f.transpose())) / self.h
    }

    /// The Jacobian by central differences: enough for Newton in a test.
    fn residual_jacobian(
        &self,
        p: &SVector<f64, 3>,
        z: &SVector<f64, 3>,
    ) -> (SVector<f64, 3>, SMatrix<f64, 3, 3>) {
        let d = 1e-6;
        let j = SMatrix::<f64, 3, 3>::from_fn(|_, _| 0.0);
        let j = (0..3).fold(j, |mut j, c| {
            let e = SVector::<f64, 3>::ith(c, d);
            let column = (self.residual(p, &(z + e)) - self.residual(p, &(z - e))) / (2.0 * d);
            j.set_column(c, &column);
            j
        });
        (self.residual(p, z), j)
    }

    fn momentum(&self, z: &SVector<f64, 3>) -> SVector<f64, 3> {
        let (f, j_d) = (cayley(&Vector3::new(z[0], z[1], z[2])), self.j_d());
        vee(&(j_d * f - f.transpose() * j_d)) / self.h
    }
}

/// Implements the parameters of [`System`] by [`Body`]'s (field `body`).
macro_rules! body_model {
    () => {
        fn time_step(&self) -> f64 {
            self.body.h
        }

        fn with_time_step(&self, h: f64) -> Self {
            let mut system = self.clone();
            system.body.h = h;
            system
        }

        fn parameter_values(&self) -> Vec<f64> {
            self.body.inertia.iter().copied().collect()
        }
    };
}

/// Implements the step functions of [`LieLagrangian`] by [`Body`]'s (field `body`).
macro_rules! body_steps {
    () => {
        type Linear = Lu<3>;

        fn linear_solver(&self) -> Lu<3> {
            Lu::empty()
        }

        fn lagrangian(&self, q0: &SVector<f64, 9>, q1: &SVector<f64, 9>) -> f64 {
            self.body.lagrangian(q0, q1)
        }

        fn retract(&self, q: &SVector<f64, 9>, z: &SVector<f64, 3>) -> SVector<f64, 9> {
            self.body.retract(q, z)
        }

        fn residual(
            &self,
            _q: &SVector<f64, 9>,
            p: &SVector<f64, 3>,
            z: &SVector<f64, 3>,
        ) -> SVector<f64, 3> {
            self.body.residual(p, z)
        }

        fn residual_jacobian(
            &self,
            _q: &SVector<f64, 9>,
            p: &SVector<f64, 3>,
            z: &SVector<f64, 3>,
        ) -> (SVector<f64, 3>, SMatrix<f64, 3, 3>) {
            self.body.residual_jacobian(p, z)
        }

        fn momentum(
            &self,
            _q: &SVector<f64, 9>,
            _p: &SVector<f64, 3>,
            z: &SVector<f64, 3>,
        ) -> SVector<f64, 3> {
            self.body.momentum(z)
        }
    };
}

/// The body compiled in: everything in the constants.
#[derive(Clone, Debug)]
struct Compiled {
    body: Body,
}

impl System for Compiled {
    const PARAMETERS: &'static [&'static str] = &["j1", "j2", "j3"];

    fn with_controls(&self, _u: &[f64]) -> Self {
        self.clone()
    }

    fn coordinate_names(&self) -> Vec<&str> {
        vec!["attitude"]
    }

    body_model!();
}

impl LieLagrangian<9, 3> for Compiled {
    const COORDINATES: &'static [(&'static str, CoordinateKind)] =
        &[("attitude", CoordinateKind::ROTATION)];
    body_steps!();
}

impl LieSymmetric<9, 3> for Compiled {
    const SYMMETRY: RotationSymmetry<'static> = RotationSymmetry::Rotations { coordinate: 0 };
    const SYMMETRY_FORCED: bool = false;
}

/// The body given at run time: the constants say nothing (or what would fail if read), the
/// value says everything.
#[derive(Clone, Debug)]
struct Given {
    body: Body,
    coordinates: Vec<(String, CoordinateKind)>,
    parameters: Vec<String>,
    controls: usize,
    /// `None`: every rotation of coordinate 0; otherwise the rotations about z of these.
    axis: Option<Vec<usize>>,
    domain: Vec<Bound>,
}

impl Given {
    fn new(body: Body) -> Self {
        Given {
            body,
            coordinates: vec![("attitude".into(), CoordinateKind::ROTATION)],
            parameters: ["j1", "j2", "j3"].map(String::from).to_vec(),
            controls: 1,
            axis: None,
            domain: Vec::new(),
        }
    }
}

impl System for Given {
    const PARAMETERS: &'static [&'static str] = &[];

    fn parameter_names(&self) -> Vec<&str> {
        self.parameters.iter().map(String::as_str).collect()
    }

    fn control_count(&self) -> usize {
        self.controls
    }

    fn with_controls(&self, _u: &[f64]) -> Self {
        self.clone()
    }

    fn coordinate_names(&self) -> Vec<&str> {
        self.coordinates
            .iter()
            .map(|(name, _)| name.as_str())
            .collect()
    }

    fn domain(&self) -> &[Bound] {
        &self.domain
    }

    body_model!();
}

impl LieLagrangian<9, 3> for Given {
    const COORDINATES: &'static [(&'static str, CoordinateKind)] = &[];

    fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)> {
        self.coordinates
            .get(i)
            .map(|(name, kind)| (name.as_str(), *kind))
    }

    body_steps!();
}

impl LieSymmetric<9, 3> for Given {
    // A coordinate no system has: reading it instead of the value panics.
    const SYMMETRY: RotationSymmetry<'static> = RotationSymmetry::Rotations {
        coordinate: usize::MAX,
    };
    const SYMMETRY_FORCED: bool = true;

    fn symmetry(&self) -> RotationSymmetry<'_> {
        match &self.axis {
            None => RotationSymmetry::Rotations { coordinate: 0 },
            Some(coordinates) => RotationSymmetry::Axis {
                axis: 2,
                coordinates,
            },
        }
    }

    fn symmetry_forced(&self) -> bool {
        false
    }
}

fn body() -> Body {
    Body {
        h: 0.05,
        inertia: Vector3::new(1.0, 2.0, 3.5),
    }
}

fn initial() -> LieState<9, 3> {
    let r = cayley(&Vector3::new(0.2, -0.1, 0.4));
    LieState::from_row_major(rows(&r), [0.3, 1.1, -0.4])
}

fn run<I: Stepper>(integrator: &I, state: I::State, steps: usize) -> Vec<I::State>
where
    I::State: Clone,
{
    integrator.check(&state).expect("a valid initial state");
    let mut workspace = integrator.workspace();
    let mut states = vec![state];
    for k in 0..steps {
        let (next, _) = integrator
            .step_in(&mut workspace, k, &states[k])
            .expect("the step converges");
        states.push(next);
    }
    states
}

#[test]
fn the_provided_methods_say_the_constants() {
    let compiled = Compiled { body: body() };
    assert_eq!(
        compiled.coordinate(0),
        Some(("attitude", CoordinateKind::ROTATION))
    );
    assert_eq!(compiled.coordinate(1), None);
    assert_eq!(compiled.parameter_names(), ["j1", "j2", "j3"]);
    assert_eq!(compiled.control_count(), 0);
    assert_eq!(compiled.time_index(), None);
    assert_eq!(
        compiled.symmetry(),
        RotationSymmetry::Rotations { coordinate: 0 }
    );
    assert!(!compiled.symmetry_forced());
    let given = Given::new(body());
    assert_eq!(given.parameter_names(), ["j1", "j2", "j3"]);
}

/// A domain the rotation integrators cannot check is refused before any step, not ignored.
#[test]
fn a_declared_domain_is_refused_not_ignored() {
    let options = NewtonOptions::default();
    assert!(LieIntegrator::new(Given::new(body()), options)
        .check(&initial())
        .is_ok());
    let bounded = Given {
        domain: vec![Bound::new(0, Relation::Above, -2.0)],
        ..Given::new(body())
    };
    let refused = LieIntegrator::new(bounded, options).check(&initial());
    assert!(
        matches!(refused, Err(StepError::Unsupported { what }) if what.contains("domain")),
        "{refused:?}"
    );
}

#[test]
fn a_system_given_at_run_time_steps_as_the_one_compiled_in() {
    let options = NewtonOptions::default();
    let compiled = LieIntegrator::new(Compiled { body: body() }, options);
    let given = LieIntegrator::new(Given::new(body()), options);
    let (a, b) = (run(&compiled, initial(), 40), run(&given, initial(), 40));
    assert_eq!(a, b);
    // The layout of the point comes from the value: an empty one would give π = 0.
    let pi = given.spatial_momentum(&b[0]);
    assert!(pi.norm() > 1.0);
    for state in &b {
        assert!((given.spatial_momentum(state) - pi).amax() < 1e-12);
        assert!(given.manifold_defect(&state.q) < 1e-13);
    }
    assert_eq!(
        given.chart_coordinates(&b[0].q, &b[1].q),
        compiled.chart_coordinates(&a[0].q, &a[1].q)
    );

    // The controls: the value's count.
    assert_eq!((compiled.control_dim(), given.control_dim()), (0, 1));
    let mut workspace = given.workspace();
    assert!(given
        .step_with(
            &mut workspace,
            StepAt::new(0, 0.05).with_controls(&[0.0]),
            &b[0]
        )
        .is_ok());
    assert!(matches!(
        compiled.step_with(
            &mut compiled.workspace(),
            StepAt::new(0, 0.05).with_controls(&[0.0]),
            &a[0],
        ),
        Err(StepError::InvalidControls {
            expected: 0,
            found: 1,
            ..
        })
    ));

    // The checks name the value's coordinate.
    let mut off = initial();
    off.q[0] += 1e-3;
    match given.check(&off) {
        Err(StepError::OffManifold { reason }) => assert!(reason.contains("`attitude`")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_symmetry_given_at_run_time_reduces_as_the_one_compiled_in() {
    let options = NewtonOptions::default();
    let compiled = ReducedLieIntegrator::new(Compiled { body: body() }, options);
    let given = ReducedLieIntegrator::new(Given::new(body()), options);
    let start = compiled.reduce(&initial());
    assert_eq!(given.reduce(&initial()), start);
    let (a, b) = (run(&compiled, start, 40), run(&given, start, 40));
    assert_eq!(a, b);

    // The rotations about z of the coordinates the value lists.
    let mut axis = Given::new(body());
    axis.axis = Some(vec![0]);
    let axis = ReducedLieIntegrator::new(axis, options);
    let start = axis.reduce(&initial());
    let pi = axis.unreduced().spatial_momentum(&initial());
    assert_eq!(start.mu, Vector3::new(0.0, 0.0, start.mu.z));
    assert!((start.mu.z - pi.z).abs() < 1e-14);
    let states = run(&axis, start, 40);
    for state in &states {
        assert_eq!(state.mu, start.mu);
        assert!((axis.momentum_map(&state.unreduced()).unwrap().z - pi.z).abs() < 1e-12);
    }
    let trajectory = ReducedLieTrajectory {
        h: 0.05,
        times: (0..states.len()).map(|k| 0.05 * k as f64).collect(),
        step_sizes: vec![0.05; states.len() - 1],
        states,
        stats: Vec::new(),
    };
    let residuals = axis.dirac_residuals(&trajectory);
    assert_eq!(residuals.len(), 40);
    assert!(residuals.iter().all(|r| *r < 1e-9), "{residuals:?}");
}
