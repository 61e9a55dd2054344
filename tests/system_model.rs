//! The one system model: a function written once against `System` reads a flat system, one on
//! rotation groups and an element-wise one alike — names, parameters, the system at another
//! step and with other controls — and each family's integrators step the system that
//! `System::with_time_step` and `System::with_controls` form.

use dirac::prelude::*;
use dirac::systems::rotations::{Satellite, SatelliteConfig, SatelliteMomentum};

/// A forced oscillator on `r > 0` with a control `a`, of fixed size.
#[reduced_lagrangian(shape(r), group(), controls(a), domain(r > 0.0),
    force = |dq0, dq1| 0.5 * h * a * (dq0.r + dq1.r))]
fn pushed(q0: Config, q1: Config, h: f64, k: f64, a: f64) -> f64 {
    let dr = q1.r - q0.r;
    0.5 * dr * dr / h - 0.25 * h * k * (q0.r * q0.r + q1.r * q1.r)
}

/// A chain of `n` masses driven at its first by the control `a`, sized at run time.
#[reduced_lagrangian(coordinates(x[n]), controls(a),
    force = |dq0, dq1| 0.5 * h * a * (dq0.x[0] + dq1.x[0]))]
fn driven(q0: Config, q1: Config, h: f64, c: f64, a: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let d = q1.x[i] - q0.x[i];
        l += 0.5 * d * d / h;
    }
    for i in 0..n - 1 {
        let s = q0.x[i + 1] - q0.x[i];
        l -= 0.5 * h * c * s * s;
    }
    l
}

/// What a system says of itself, read through `System` only.
#[derive(Debug, PartialEq)]
struct Described {
    coordinates: Vec<String>,
    parameters: Vec<(String, f64)>,
    controls: Vec<String>,
    h: f64,
}

/// Written once, for every family.
fn describe<L: System>(sys: &L) -> Described {
    let own = |names: Vec<&str>| names.into_iter().map(str::to_owned).collect();
    Described {
        coordinates: own(sys.coordinate_names()),
        parameters: sys
            .parameter_names()
            .into_iter()
            .map(str::to_owned)
            .zip(sys.parameter_values())
            .collect(),
        controls: own(sys.control_names()),
        h: sys.time_step(),
    }
}

/// The same system at step `h` with the controls `u`: every other parameter unchanged.
fn at<L: System>(sys: &L, h: f64, u: &[f64]) -> Described {
    assert_eq!(u.len(), sys.control_count());
    describe(&sys.with_time_step(h).with_controls(u))
}

fn pairs(values: &[(&str, f64)]) -> Vec<(String, f64)> {
    values.iter().map(|&(n, v)| (n.to_owned(), v)).collect()
}

#[test]
fn one_function_reads_every_family() {
    let flat = Pushed {
        h: 0.1,
        k: 2.0,
        a: 0.0,
    };
    assert_eq!(
        describe(&flat),
        Described {
            coordinates: vec!["r".into()],
            parameters: pairs(&[("h", 0.1), ("k", 2.0), ("a", 0.0)]),
            controls: vec!["a".into()],
            h: 0.1,
        }
    );
    assert_eq!(
        at(&flat, 0.05, &[0.5]).parameters,
        pairs(&[("h", 0.05), ("k", 2.0), ("a", 0.5)])
    );
    assert_eq!(flat.domain().len(), 1);
    assert_eq!(flat.time_index(), None);

    let lie = Satellite {
        h: 0.1,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
        jw: 0.5,
        u: 0.0,
    };
    let described = describe(&lie);
    assert_eq!(described.coordinates, ["r", "phi"]);
    assert_eq!(described.controls, ["u"]);
    assert_eq!(
        at(&lie, 0.2, &[1.5]).parameters,
        pairs(&[
            ("h", 0.2),
            ("j1", 1.0),
            ("j2", 2.0),
            ("j3", 3.0),
            ("jw", 0.5),
            ("u", 1.5)
        ])
    );
    assert!(lie.domain().is_empty());

    let element = Driven {
        h: 0.1,
        c: 3.0,
        a: 0.0,
        n: 4,
    };
    assert_eq!(
        describe(&element),
        Described {
            coordinates: vec!["x".into()],
            parameters: pairs(&[("h", 0.1), ("c", 3.0), ("a", 0.0)]),
            controls: vec!["a".into()],
            h: 0.1,
        }
    );
    let moved = element.with_time_step(0.3).with_controls(&[2.0]);
    assert_eq!((moved.h, moved.a, moved.n), (0.3, 2.0, 4));
}

/// Each family's step at another size and with controls is the step of the system
/// `with_time_step` and `with_controls` form, bit for bit: the one way a step forms its system.
#[test]
fn a_step_with_its_own_size_and_controls_steps_the_system_formed_by_the_model() {
    let options = NewtonOptions::default();
    let (h, u) = (0.05, [0.7]);

    let flat = Pushed {
        h: 0.1,
        k: 2.0,
        a: 0.0,
    };
    let start = UnreducedState::new([1.0], [0.2]);
    let integ = UnreducedIntegrator::new(flat, options);
    let (own, _) = integ
        .step_with(
            &mut integ.workspace(),
            StepAt::new(0, h).with_controls(&u),
            &start,
        )
        .unwrap();
    let formed = UnreducedIntegrator::new(flat.with_time_step(h).with_controls(&u), options);
    assert_eq!(own, formed.step(0, &start).unwrap().0);

    let lie = Satellite {
        h: 0.1,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
        jw: 0.5,
        u: 0.0,
    };
    let start = lie.state(
        &SatelliteConfig {
            r: Matrix3::identity(),
            phi: 0.0,
        },
        &SatelliteMomentum {
            r: Vector3::new(0.1, 0.2, 0.3),
            phi: 0.4,
        },
    );
    let integ = LieIntegrator::new(lie, options);
    let (own, _) = integ
        .step_with(
            &mut integ.workspace(),
            StepAt::new(0, h).with_controls(&u),
            &start,
        )
        .unwrap();
    let formed = LieIntegrator::new(lie.with_time_step(h).with_controls(&u), options);
    assert_eq!(own, formed.step(0, &start).unwrap().0);

    let element = Driven {
        h: 0.1,
        c: 3.0,
        a: 0.0,
        n: 4,
    };
    let start = ElementState::new(vec![0.0, 0.1, 0.2, 0.3], vec![0.1; 4]);
    let integ = ElementIntegrator::new(element, options);
    let (own, _) = integ
        .step_with(
            &mut integ.workspace(),
            StepAt::new(0, h).with_controls(&u),
            &start,
        )
        .unwrap();
    let formed = ElementIntegrator::new(element.with_time_step(h).with_controls(&u), options);
    assert_eq!(own, formed.step(0, &start).unwrap().0);
}

/// The one check of a control vector, for every family: the wrong number of controls is the
/// same typed error at the step it was given for.
#[test]
fn every_family_refuses_the_wrong_number_of_controls_alike() {
    let options = NewtonOptions::default();
    let expected = |e: StepError| {
        assert!(
            matches!(
                e,
                StepError::InvalidControls {
                    step: 3,
                    expected: 1,
                    found: 2
                }
            ),
            "{e:?}"
        );
    };
    let flat = UnreducedIntegrator::new(
        Pushed {
            h: 0.1,
            k: 2.0,
            a: 0.0,
        },
        options,
    );
    let start = UnreducedState::new([1.0], [0.2]);
    expected(
        flat.step_with(
            &mut flat.workspace(),
            StepAt::new(3, 0.1).with_controls(&[1.0, 2.0]),
            &start,
        )
        .unwrap_err(),
    );
    let element = ElementIntegrator::new(
        Driven {
            h: 0.1,
            c: 3.0,
            a: 0.0,
            n: 4,
        },
        options,
    );
    let start = ElementState::new(vec![0.0; 4], vec![0.1; 4]);
    expected(
        element
            .step_with(
                &mut element.workspace(),
                StepAt::new(3, 0.1).with_controls(&[1.0, 2.0]),
                &start,
            )
            .unwrap_err(),
    );
}

/// The one vocabulary of equations: every keyword names equations whose keyword names them
/// again, for a family whose own equations are reduced (on vector spaces) and one whose own are
/// unreduced (on rotation groups, element-wise); "plus" and "minus" name the family's own form,
/// and the other form's word its (+) side (in its own form a synonym of "plus").
#[test]
fn every_keyword_names_equations_that_name_them_back() {
    for own in [Form::Reduced, Form::Unreduced] {
        for word in Equations::KEYWORDS {
            let equations = Equations::from_keyword(word, own).expect("a keyword");
            let again = Equations::from_keyword(equations.keyword(own), own);
            assert_eq!(again, Some(equations), "{word} in {own:?}");
        }
        let minus = Equations::from_keyword("minus", own).unwrap();
        assert_eq!((minus.form, minus.side), (own, Variant::Minus));
        assert_eq!(minus.keyword(own), "minus");
    }
    let unreduced = Equations::from_keyword("unreduced", Form::Reduced).unwrap();
    assert_eq!(unreduced.keyword(Form::Reduced), "unreduced");
    assert_eq!(Equations::from_keyword("Plus", Form::Reduced), None);
}
