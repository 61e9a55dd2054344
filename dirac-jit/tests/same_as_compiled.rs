//! Systems given as text against the same systems compiled in with `#[reduced_lagrangian]`: the
//! text is cut from the facade's own sources (the paper's systems, Kepler's), so both are
//! compiled from the same characters, and every step of every integrator must agree bit for bit
//! — the kernels perform the same operations in the same order as the emitted Rust.

use std::sync::Arc;

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, DoubleSphericalPendulumContinuous};
use dirac::prelude::*;
use dirac::systems::kepler::Kepler;
use dirac_jit::{compile, Code, JitSystem};

/// The text of the function `name` of a source file, with its attribute and doc comments.
fn function(source: &str, name: &str) -> String {
    let file = syn::parse_file(source).expect("the facade's sources parse");
    for item in file.items {
        if let syn::Item::Fn(f) = &item {
            if f.sig.ident == name {
                let range = syn::spanned::Spanned::span(&item).byte_range();
                return source[range].to_owned();
            }
        }
    }
    panic!("no function `{name}`")
}

const PAPER: &str = include_str!("../../src/paper.rs");
const KEPLER: &str = include_str!("../../src/systems/kepler.rs");
const TODA: &str = include_str!("../../examples/common/toda.rs");

/// The compiled-in 200-particle Toda lattice of the examples (sparse backend).
#[path = "../../examples/common/toda.rs"]
mod toda;

fn code(source: &str, name: &str) -> Arc<Code> {
    compile(&function(source, name)).unwrap_or_else(|e| panic!("{name}:\n{e}"))
}

/// Equal state by state; else the first step that differs.
fn same<T: PartialEq + std::fmt::Debug>(a: &[T], b: &[T], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    if let Some(k) = (0..a.len()).find(|&k| a[k] != b[k]) {
        panic!("{what}: step {k} differs:\n{:?}\n{:?}", a[k], b[k]);
    }
}

/// Reduced (+) and (−) and unreduced runs of `jit` and `compiled` from `start`, state by state.
fn same_runs<L, J, const S: usize, const K: usize, const N: usize>(
    compiled: L,
    jit: J,
    start: ReducedState<S, K>,
    steps: usize,
) where
    L: Reduced<Plus, S, K, N> + Reduced<Minus, S, K, N> + Unreduced<S, K, N> + Clone,
    J: Reduced<Plus, S, K, N> + Reduced<Minus, S, K, N> + Unreduced<S, K, N> + Clone,
{
    let opts = NewtonOptions::default();
    let a = ReducedIntegrator::plus(compiled.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::plus(jit.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "(+)");
    let a = ReducedIntegrator::minus(compiled.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::minus(jit.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "(−)");
    let unreduced = <L as DiscreteLagrangian<S, K, N>>::untrivialize(&compiled, &start);
    let a = UnreducedIntegrator::new(compiled, opts)
        .run(unreduced)
        .steps(steps)
        .collect()
        .unwrap();
    let b = UnreducedIntegrator::new(jit, opts)
        .run(unreduced)
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "unreduced");
}

#[test]
fn the_charged_particle_steps_bit_for_bit() {
    let code = code(PAPER, "charged_particle");
    let compiled = ChargedParticle::paper(200);
    let jit = code
        .instantiate::<3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    let (q0, q1) = (
        SVector::<f64, 4>::new(0.1, -0.2, 0.3, 0.4),
        SVector::<f64, 4>::new(0.15, -0.1, 0.35, 0.5),
    );
    assert_eq!(jit.lagrangian(&q0, &q1), compiled.lagrangian(&q0, &q1));
    same_runs(compiled, jit, ChargedParticle::paper_initial_state(), 200);
}

#[test]
fn the_double_spherical_pendulum_steps_bit_for_bit() {
    let code = code(PAPER, "double_spherical_pendulum");
    let compiled = DoubleSphericalPendulum::paper();
    let jit = code
        .instantiate::<3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    same_runs(
        compiled,
        jit,
        DoubleSphericalPendulum::paper_initial_state(),
        500,
    );
}

#[test]
fn keplers_problem_steps_bit_for_bit() {
    let code = code(KEPLER, "kepler");
    let compiled = Kepler::unit(0.01);
    let start = compiled.periapsis_state(1.0, 0.5);
    let jit = code
        .instantiate::<1, 1, 2>(&compiled.parameter_values())
        .unwrap();
    same_runs(compiled, jit, start, 1000);
}

/// The declared domain (`domain(r > 0.0)` in Kepler's text) is checked after every step as the
/// compiled-in one is: at a step too coarse for the periapsis passage (e = 0.9, h = 0.2) both
/// stop with the same typed error at the same step, the same states kept.
#[test]
fn a_domain_given_as_text_is_checked_as_the_one_compiled_in() {
    let code = code(KEPLER, "kepler");
    let compiled = Kepler::unit(0.2);
    let start = compiled.periapsis_state(1.0, 0.9);
    let jit = code
        .instantiate::<1, 1, 2>(&compiled.parameter_values())
        .unwrap();
    assert_eq!(jit.domain(), compiled.domain());
    // The one system model says the same of both.
    assert_eq!(jit.coordinate_names(), compiled.coordinate_names());
    assert_eq!(jit.parameter_names(), compiled.parameter_names());
    assert_eq!(jit.time_index(), compiled.time_index());
    let opts = NewtonOptions::default();
    let a = ReducedIntegrator::plus(compiled, opts)
        .run(start)
        .steps(50)
        .collect()
        .unwrap_err();
    let b = ReducedIntegrator::plus(jit.clone(), opts)
        .run(start)
        .steps(50)
        .collect()
        .unwrap_err();
    assert!(
        matches!(&b.source, StepError::OutOfDomain { step: 5, coordinate, value, .. }
            if coordinate == "r" && *value < 0.0),
        "{:?}",
        b.source
    );
    assert_eq!(a.source, b.source);
    same(
        &a.trajectory.states,
        &b.trajectory.states,
        "(+) up to the domain",
    );
    let unreduced = jit.untrivialize(&start);
    let e = UnreducedIntegrator::new(jit, opts)
        .run(unreduced)
        .steps(50)
        .collect()
        .unwrap_err();
    assert!(
        matches!(e.source, StepError::OutOfDomain { step: 5, .. }),
        "{:?}",
        e.source
    );
}

/// The paper's double spherical pendulum as a continuous Lagrangian, compiled in and given as
/// the same text, and a point `(q, v)` to compare them at.
fn continuous_pendulum() -> (
    DoubleSphericalPendulumContinuous,
    JitSystem<3, 1, 4>,
    (SVector<f64, 4>, SVector<f64, 4>),
) {
    let compiled = DoubleSphericalPendulumContinuous::paper();
    let jit = code(PAPER, "double_spherical_pendulum_continuous")
        .instantiate::<3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    let point = (
        SVector::<f64, 4>::new(0.4, 0.1, 0.7, 0.2),
        SVector::<f64, 4>::new(0.3, -0.2, 0.1, 0.5),
    );
    (compiled, jit, point)
}

/// A continuous Lagrangian with its quadrature rule: `L_d` formed by the compiler, and the
/// Legendre map and energy from the same graph.
#[test]
fn a_continuous_lagrangian_steps_bit_for_bit() {
    let (compiled, jit, (q, v)) = continuous_pendulum();
    assert_eq!(jit.legendre(&q, &v), Some(compiled.legendre(&q, &v)));
    assert_eq!(jit.energy(&q, &v), Some(compiled.energy(&q, &v)));
    let start = DoubleSphericalPendulum::paper_initial_state();
    same_runs(compiled, jit.clone(), start, 300);
    // `ContinuousLagrangian`: the Legendre map's Jacobian, the state from a velocity, and the
    // energies of a trajectory at its nodes (the inverse Legendre map) and midpoints.
    same_continuous(&compiled, &jit, &q, &v);
    let opts = NewtonOptions::default();
    let (a, b) = (
        ReducedIntegrator::plus(compiled, opts),
        ReducedIntegrator::plus(jit.clone(), opts),
    );
    let (ta, tb) = (
        a.run(start).steps(200).collect().unwrap(),
        b.run(start).steps(200).collect().unwrap(),
    );
    assert_eq!(a.energies(&ta).unwrap(), b.energies(&tb).unwrap());
    // A discrete Lagrangian has no L(q, v): an error, not a number.
    let discrete = self::code(PAPER, "double_spherical_pendulum");
    let discrete = discrete
        .instantiate::<3, 1, 4>(&DoubleSphericalPendulum::paper().parameter_values())
        .unwrap();
    let integ = ReducedIntegrator::plus(discrete, opts);
    let traj = integ.run(start).steps(3).collect().unwrap();
    assert!(integ.energies(&traj).is_err());
}

/// `ContinuousLagrangian` of both systems at `(q, v)`: `L` to round-off (the text's `L` is the
/// compiler's straight line, the compiled-in one the user's function), the rest bit for bit.
fn same_continuous<L, J, const S: usize, const K: usize, const N: usize>(
    compiled: &L,
    jit: &J,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) where
    L: ContinuousLagrangian<N> + DiscreteLagrangian<S, K, N>,
    J: ContinuousLagrangian<N> + DiscreteLagrangian<S, K, N>,
{
    let (a, b) = (
        compiled.continuous_lagrangian(q, v),
        jit.continuous_lagrangian(q, v),
    );
    assert!((a - b).abs() <= 1e-14 * a.abs().max(1.0), "L: {a} vs {b}");
    assert_eq!(
        ContinuousLagrangian::legendre(compiled, q, v),
        ContinuousLagrangian::legendre(jit, q, v)
    );
    assert_eq!(
        ContinuousLagrangian::energy(compiled, q, v),
        ContinuousLagrangian::energy(jit, q, v)
    );
    assert_eq!(
        compiled.unreduced_state(*q, *v).unwrap(),
        jit.unreduced_state(*q, *v).unwrap()
    );
    let p = ContinuousLagrangian::legendre(compiled, q, v);
    let guess = v.map(|x| 1.1 * x);
    assert_eq!(
        compiled.velocity(0, q, &p, guess).unwrap(),
        jit.velocity(0, q, &p, guess).unwrap()
    );
}

#[path = "../../examples/common/forced.rs"]
#[allow(dead_code)]
mod forced;

/// Forces with a group component and a control set by a feedback law before every step: the
/// forced discrete Noether balance `μ_{k+1} = μ_k + f_{d,g}^− + f_{d,g}^+` and the controls go
/// through the same kernels.
#[test]
fn forces_and_a_feedback_control_step_bit_for_bit() {
    let code = code(include_str!("../../examples/common/forced.rs"), "turntable");
    assert!(code.system().forced);
    assert_eq!(code.system().controls, [4]);
    let compiled = forced::Turntable {
        h: 0.01,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.2,
        tau: 0.0,
    };
    // The continuous Lagrangian does not take `h`: it is the last parameter.
    assert_eq!(code.system().parameters, ["i0", "m", "l", "c", "tau", "h"]);
    let jit = code
        .instantiate_named::<1, 1, 2>(&[
            ("h", 0.01),
            ("i0", 0.7),
            ("m", 1.3),
            ("l", 0.9),
            ("c", 0.2),
            ("tau", 0.0),
        ])
        .unwrap();
    assert_eq!(jit.parameter_values(), compiled.parameter_values());
    let start = ReducedState::new([0.4], [0.2], [0.3], [0.0]);
    let law = |_: usize, _: f64, s: &ReducedState<1, 1>, u: &mut [f64]| u[0] = -0.5 * s.x[0];
    let opts = NewtonOptions::default();
    let a = ReducedIntegrator::plus(compiled, opts)
        .run(start)
        .steps(500)
        .feedback(law)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::plus(jit.clone(), opts)
        .run(start)
        .steps(500)
        .feedback(law)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "forced (+)");
    assert_ne!(a.last().mu, start.mu, "the torque changes μ");
    // The steps' sensitivities to the state and the control, both sides and unreduced: the
    // same partial derivatives, the same solves.
    let a = ReducedIntegrator::plus(compiled, opts).step_sensitivity(0, &start, &[0.3]);
    let b = ReducedIntegrator::plus(jit.clone(), opts).step_sensitivity(0, &start, &[0.3]);
    assert_eq!(a.unwrap(), b.unwrap(), "(+) sensitivity");
    let a = ReducedIntegrator::minus(compiled, opts).step_sensitivity(0, &start, &[0.3]);
    let b = ReducedIntegrator::minus(jit.clone(), opts).step_sensitivity(0, &start, &[0.3]);
    assert_eq!(a.unwrap(), b.unwrap(), "(−) sensitivity");
    let unreduced = compiled.untrivialize(&start);
    let a = UnreducedIntegrator::new(compiled, opts)
        .step_sensitivity(0, &unreduced, &[0.3])
        .unwrap();
    let b = UnreducedIntegrator::new(jit.clone(), opts)
        .step_sensitivity(0, &unreduced, &[0.3])
        .unwrap();
    assert_eq!(a, b, "unreduced sensitivity");
    assert!(
        a.2.control.iter().any(|&v| v != 0.0),
        "the control moves the step"
    );
    // A forced system has no Hessian form of its step map: an error, not NaN.
    let e = UnreducedIntegrator::new(jit, opts)
        .step_jacobian(0, &unreduced, &a.0)
        .unwrap_err();
    assert!(matches!(e, StepError::NonFinite { .. }), "{e}");
}

/// The step-map Jacobian from the second derivatives of `L_d` (a system without forces), and
/// the composed one of the triple jump: the same as compiled in.
#[test]
fn step_map_jacobians_are_the_compiled_in_ones() {
    let code = code(PAPER, "double_spherical_pendulum");
    let compiled = DoubleSphericalPendulum::paper();
    let jit = code
        .instantiate::<3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    let start = compiled.untrivialize(&DoubleSphericalPendulum::paper_initial_state());
    let opts = NewtonOptions::default();
    let (a, b) = (
        UnreducedIntegrator::new(compiled, opts),
        UnreducedIntegrator::new(jit, opts),
    );
    let next = a.run(start).steps(1).collect().unwrap().states[1];
    assert_eq!(
        a.step_jacobian(0, &start, &next).unwrap(),
        b.step_jacobian(0, &start, &next).unwrap()
    );
    let (a, b) = (
        Composition::new(a, CompositionMethod::TRIPLE_JUMP),
        Composition::new(b, CompositionMethod::TRIPLE_JUMP),
    );
    let (sa, ma) = a.step_with_jacobian(0, &start).unwrap();
    let (sb, mb) = b.step_with_jacobian(0, &start).unwrap();
    assert_eq!((sa, &ma), (sb, &mb));
    assert!(ma.symplecticity_defect() < 1e-10);
}

/// A system of 200 coordinates: the text gets the attribute's sparse backend — the Jacobian's
/// structural nonzeros, factored by the same sparse LU (same ordering, same pivots) — and steps
/// bit for bit as the compiled-in lattice, reduced on both sides and unreduced.
#[test]
fn the_200_particle_lattice_steps_bit_for_bit_on_the_sparse_backend() {
    let code = code(TODA, "toda");
    let pattern = code.system().plus.stepper.pattern.as_ref().expect("sparse");
    assert_eq!(pattern.col_ptr.len(), toda::N + 1);
    let compiled = toda::Toda {
        m: 1.0,
        d: 1.0,
        h: 0.05,
    };
    let jit = code
        .instantiate_sparse_named::<199, 1, 200>(&[("m", 1.0), ("d", 1.0), ("h", 0.05)])
        .unwrap();
    let start = toda::initial(&compiled, 0.1, 0.3, 0.05);
    same_runs(compiled, jit.clone(), start, 100);
    // The lattice's translation is declared on the user's coordinates: the adapted coordinates
    // of a user state are the compiled-in system's, and back.
    let q_user = SVector::<f64, 200>::from_fn(|i, _| i as f64 + 0.1 * (i as f64).sin());
    let p_user = SVector::<f64, 200>::from_fn(|i, _| 0.2 * (i as f64).cos());
    type T = toda::Toda;
    assert_eq!(
        jit.to_adapted(&q_user),
        <T as AdaptedCoordinates<200>>::to_adapted(&q_user)
    );
    assert_eq!(
        jit.momentum_to_adapted(&p_user),
        <T as AdaptedCoordinates<200>>::momentum_to_adapted(&p_user)
    );
    let state = jit.adapted_state(&q_user, &p_user);
    assert_eq!(
        jit.from_adapted_state(&state),
        <T as AdaptedCoordinates<200>>::from_adapted_state(&state)
    );
    // The inverse Legendre map on the sparse pattern of ∂²L/∂v².
    let unreduced = compiled.untrivialize(&start);
    let v = unreduced.p.map(|p| 0.9 * p);
    same_continuous(&compiled, &jit, &unreduced.q, &v);
    // The dense backend is refused at this size, and the sparse one below it.
    let e = code
        .instantiate::<199, 1, 200>(&[1.0, 1.0, 0.05])
        .unwrap_err();
    assert!(e.to_string().contains("instantiate_sparse"), "{e}");
    let kepler = self::code(KEPLER, "kepler");
    let e = kepler
        .instantiate_sparse::<1, 1, 2>(&[0.01, 1.0])
        .unwrap_err();
    assert!(e.to_string().contains("with `instantiate`"), "{e}");
}

/// Instantiation checks the dimensions and the parameters against the text's.
#[test]
fn wrong_dimensions_and_parameters_are_errors() {
    let code = code(KEPLER, "kepler");
    let e = code.instantiate::<2, 0, 2>(&[0.01, 1.0]).unwrap_err();
    assert!(e.to_string().contains("1 shape and 1 group"), "{e}");
    let e = code.instantiate::<1, 1, 2>(&[0.01]).unwrap_err();
    assert!(e.to_string().contains("1 values for 2 parameters"), "{e}");
    let e = code.instantiate::<1, 1, 2>(&[0.01, f64::NAN]).unwrap_err();
    assert!(e.to_string().contains("`k` = NaN is not finite"), "{e}");
    let e = code
        .instantiate_named::<1, 1, 2>(&[("h", 0.01), ("kk", 1.0)])
        .unwrap_err();
    assert!(e.to_string().contains("no parameter `kk`"), "{e}");
    let e = compile("#[reduced_lagrangian(shape(r), group(phi))] fn f(q0: Config, q1: Config, h: f64) -> f64 { q0.s }")
        .unwrap_err();
    assert!(e.to_string().contains("unknown coordinate `s`"), "{e}");
}

/// Compiles `$item` in with the attribute and keeps its text as `$text`: both come from the same
/// tokens.
macro_rules! compiled_and_text {
    ($text:ident: $($item:tt)*) => {
        $($item)*
        const $text: &str = stringify!($($item)*);
    };
}

compiled_and_text!(BEAD:
    /// A bead on a vertical cylinder, free along its axis `z` (the symmetry, which the
    /// constraint does not read), with a spring in the plane.
    #[reduced_lagrangian(shape(x, y), group(z), rule = midpoint,
        constraints = |q| [q.x * q.x + q.y * q.y - r * r])]
    fn bead(q: Config, v: Velocity, m: f64, r: f64) -> f64 {
        0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) - 0.5 * (q.x - 0.3) * (q.x - 0.3)
    }
);

compiled_and_text!(SLEIGH:
    /// The Chaplygin sleigh: its knife edge, at distance `a` behind the centre of mass, cannot
    /// slip sideways (a nonholonomic constraint whose force has a group component: `μ` moves).
    #[reduced_lagrangian(shape(theta), group(x, y), rule = midpoint,
        nonholonomic = |q, v| [-q.theta.sin() * v.x + q.theta.cos() * v.y - a * v.theta])]
    fn sleigh(_q: Config, v: Velocity, m: f64, i: f64, a: f64) -> f64 {
        0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * i * v.theta * v.theta
    }
);

#[path = "../../examples/common/cartesian_dsp.rs"]
#[allow(dead_code)]
mod cartesian_dsp;

use dirac::runtime::constrained::Form;

/// Constrained runs of form `F` of `compiled` and `jit` from `start`: every state and every
/// step's multipliers `(λ, ν)` equal.
fn same_constrained<
    F,
    L,
    J,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>(
    compiled: L,
    jit: J,
    start: F::State,
    steps: usize,
    what: &str,
) where
    F: Form<S, K, N>,
    L: Constrained<F, S, K, N, M, Z>,
    J: Constrained<F, S, K, N, M, Z>,
{
    let opts = NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    };
    let a = ConstrainedStepper::<L, F, S, K, N, M, Z>::new(compiled, opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    let b = ConstrainedStepper::<J, F, S, K, N, M, Z>::new(jit, opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, what);
    let multipliers = |t: &ConstrainedTrajectory<F::State, M>| {
        t.records
            .iter()
            .map(|s| (s.lambda, s.nu))
            .collect::<Vec<_>>()
    };
    same(&multipliers(&a), &multipliers(&b), what);
}

/// The paper's double spherical pendulum in Cartesian positions with its two rods as holonomic
/// constraints (`M = 2`): `φ` and every unreduced constrained step bit for bit.
#[test]
fn holonomic_constraints_step_bit_for_bit() {
    let code = code(
        include_str!("../../examples/common/cartesian_dsp.rs"),
        "cartesian_dsp",
    );
    let (compiled, start) = cartesian_dsp::cartesian_initial(0.01);
    let jit = code
        .instantiate_constrained::<6, 0, 6, 2, 8>(&compiled.parameter_values())
        .unwrap();
    assert!(jit.holonomic());
    let q = SVector::<f64, 6>::new(0.3, -0.2, -0.9, 0.1, 0.4, -1.7);
    assert_eq!(jit.constraint(&q), compiled.constraint(&q));
    same_constrained::<UnreducedForm, _, _, 6, 0, 6, 2, 8>(
        compiled,
        jit.clone(),
        start,
        500,
        "rods",
    );
    // The energies of a constrained trajectory, through the inverse Legendre map.
    let opts = NewtonOptions::default();
    let (a, b) = (
        ConstrainedIntegrator::new(compiled, opts),
        ConstrainedIntegrator::new(jit, opts),
    );
    let (ta, tb) = (
        a.run(start).steps(100).collect().unwrap(),
        b.run(start).steps(100).collect().unwrap(),
    );
    assert_eq!(a.energies(&ta).unwrap(), b.energies(&tb).unwrap());
}

/// A holonomic constraint invariant under the symmetry: the reduced constrained steps of both
/// sides keep `μ` exact, and all three forms step bit for bit.
#[test]
fn reduced_constrained_steps_bit_for_bit() {
    let code = compile(BEAD).unwrap();
    let compiled = Bead {
        h: 0.01,
        m: 1.2,
        r: 0.8,
    };
    let jit = code
        .instantiate_constrained::<2, 1, 3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    let c0 = UnreducedState::new([0.8, 0.0, 0.0], [0.0, 0.5, 0.7]);
    let s0 = compiled.trivialize(&c0);
    same_constrained::<UnreducedForm, _, _, 2, 1, 3, 1, 4>(
        compiled,
        jit.clone(),
        c0,
        300,
        "bead, unreduced",
    );
    same_constrained::<Plus, _, _, 2, 1, 3, 1, 4>(compiled, jit.clone(), s0, 300, "bead, (+)");
    same_constrained::<Minus, _, _, 2, 1, 3, 1, 4>(compiled, jit.clone(), s0, 300, "bead, (−)");
    let run = ReducedConstrainedIntegrator::plus(jit, NewtonOptions::default())
        .run(s0)
        .steps(300)
        .collect()
        .unwrap();
    assert!(run.states.iter().all(|s| s.mu == s0.mu), "μ exact");
}

/// Nonholonomic constraints (`A(q) v = 0` at the step's midpoint) with a group component:
/// `μ` moves by the constraint impulse, through the same kernels as the compiled-in system.
#[test]
fn nonholonomic_constraints_step_bit_for_bit() {
    let code = compile(SLEIGH).unwrap();
    let compiled = Sleigh {
        h: 0.01,
        m: 1.0,
        i: 0.3,
        a: 0.4,
    };
    let jit = code
        .instantiate_constrained::<1, 2, 3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    assert!(!jit.holonomic());
    // A start whose velocity satisfies the constraint.
    let (theta, vx, vtheta) = (0.3_f64, 1.0, 0.5);
    let vy = (compiled.a * vtheta + theta.sin() * vx) / theta.cos();
    let c0 = UnreducedState::new(
        [theta, 0.0, 0.0],
        [compiled.i * vtheta, compiled.m * vx, compiled.m * vy],
    );
    let s0 = compiled.trivialize(&c0);
    same_constrained::<UnreducedForm, _, _, 1, 2, 3, 1, 4>(
        compiled,
        jit.clone(),
        c0,
        300,
        "sleigh, unreduced",
    );
    same_constrained::<Plus, _, _, 1, 2, 3, 1, 4>(compiled, jit.clone(), s0, 300, "sleigh, (+)");
    same_constrained::<Minus, _, _, 1, 2, 3, 1, 4>(compiled, jit.clone(), s0, 300, "sleigh, (−)");
    let run = ReducedConstrainedIntegrator::plus(jit, NewtonOptions::default())
        .run(s0)
        .steps(100)
        .collect()
        .unwrap();
    assert_ne!(
        run.last().mu,
        s0.mu,
        "the knife edge's force turns the momentum"
    );
}

/// Constraints asked for where the text has none, or another number of them, or a backend
/// that is not the one of the solves' size: typed errors.
#[test]
fn wrong_constraints_are_errors() {
    let bead = compile(BEAD).unwrap();
    let e = bead
        .instantiate_constrained::<2, 1, 3, 2, 5>(&[0.01, 1.2, 0.8])
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("has 1 constraints; it was asked for with M = 2"),
        "{e}"
    );
    let e = bead
        .instantiate_constrained::<2, 1, 3, 1, 5>(&[0.01, 1.2, 0.8])
        .unwrap_err();
    assert!(e.to_string().contains("Z = 5"), "{e}");
    let e = bead
        .instantiate_constrained_sparse::<2, 1, 3, 1, 4>(&[0.01, 1.2, 0.8])
        .unwrap_err();
    assert!(e.to_string().contains("`instantiate_constrained`"), "{e}");
    let kepler = code(KEPLER, "kepler");
    let e = kepler
        .instantiate_constrained::<1, 1, 2, 1, 3>(&[0.01, 1.0])
        .unwrap_err();
    assert!(e.to_string().contains("has 0 constraints"), "{e}");
    // The unconstrained steps of a constrained system are there too, as for a compiled-in one.
    assert!(bead.instantiate::<2, 1, 3>(&[0.01, 1.2, 0.8]).is_ok());
}

compiled_and_text!(CHAIN:
    /// A cart carrying a chain of 6 links in maximal coordinates, one length constraint per
    /// link: 13 coordinates (the dense backend for the unconstrained steps), 19 unknowns in each
    /// constrained solve (the sparse backend).
    #[reduced_lagrangian(shape(c, x[6], y[6]), group(), rule = midpoint,
        constraints = |q| {
            let mut phi = [0.0; 6];
            phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
            for i in 1..6 {
                let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
                phi[i] = dx * dx + dy * dy - l * l;
            }
            phi
        })]
    fn chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {
        let mut t = 0.5 * mc * v.c * v.c;
        for i in 0..6 {
            t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
        }
        t
    }
);

/// Constrained solves of more than 16 unknowns: the sparse backend on the saddle-point
/// Jacobians' structural nonzeros, bit for bit as the compiled-in chain's.
#[test]
fn constrained_solves_on_the_sparse_backend_step_bit_for_bit() {
    let code = compile(CHAIN).unwrap();
    let c = code.system().constrained.as_ref().unwrap();
    assert!(c.unreduced.position.pattern.is_some() && c.unreduced.projection.pattern.is_some());
    let compiled = Chain {
        h: 0.01,
        mc: 1.0,
        m: 1.0,
        l: 1.0,
        gr: 9.81,
    };
    let values = compiled.parameter_values();
    let jit = code
        .instantiate_constrained_sparse::<13, 0, 13, 6, 19>(&values)
        .unwrap();
    // The links at θ_i = 0.3 sin(i + 1) from the vertical, at rest.
    let mut q = SVector::<f64, 13>::zeros();
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..6 {
        let th = 0.3 * ((i + 1) as f64).sin();
        x += th.sin();
        y -= th.cos();
        q[1 + i] = x;
        q[7 + i] = y;
    }
    let start = UnreducedState {
        q,
        p: SVector::zeros(),
    };
    same_constrained::<UnreducedForm, _, _, 13, 0, 13, 6, 19>(compiled, jit, start, 200, "chain");
    let e = code
        .instantiate_constrained::<13, 0, 13, 6, 19>(&values)
        .unwrap_err();
    assert!(
        e.to_string().contains("`instantiate_constrained_sparse`"),
        "{e}"
    );
    assert!(code.instantiate::<13, 0, 13>(&values).is_ok());
}

compiled_and_text!(ADAPTIVE_KEPLER:
    /// Kepler's problem with adaptive steps: physical time `t` a group coordinate, the step
    /// monitor `r^{3/2}` (the regularized Poincaré transformation of the midpoint Lagrangian).
    #[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r * q.r.sqrt(), rule = midpoint)]
    fn adaptive_kepler(q: Config, v: Velocity, k: f64) -> f64 {
        0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
    }
);

/// Adaptive steps: the time coordinate and the monitor come from the text, and every
/// integrator steps in fictitious time bit for bit as the compiled-in system — the first step's
/// guess from the motion in fictitious time included — with physical time reconstructed.
#[test]
fn adaptive_steps_step_bit_for_bit() {
    let code = compile(ADAPTIVE_KEPLER).unwrap();
    assert_eq!(code.system().adaptive.as_ref().map(|a| a.time), Some(1));
    let compiled = AdaptiveKepler { k: 1.0, h: 0.05 };
    let jit = code
        .instantiate::<1, 2, 3>(&compiled.parameter_values())
        .unwrap();
    assert_eq!(jit.time_index(), Some(1));
    let x = SVector::<f64, 1>::new(0.3);
    assert_eq!(jit.monitor(&x), compiled.monitor(&x));
    // An orbit of eccentricity 0.9 from periapsis, its state from the physical velocity.
    let (e, r0) = (0.9_f64, 0.1_f64);
    let omega = (1.0 + e).sqrt() / r0.powf(1.5);
    let start = compiled
        .reduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
        .unwrap();
    let unreduced = compiled.untrivialize(&start);
    assert_eq!(
        jit.adaptive_increment(&unreduced.q, &unreduced.p, 0.05),
        compiled.adaptive_increment(&unreduced.q, &unreduced.p, 0.05)
    );
    // The level set p_t = −E: the same defect, and a start off it refused as compiled in.
    assert_eq!(
        jit.level_set_defect(&unreduced.q, &unreduced.p),
        compiled.level_set_defect(&unreduced.q, &unreduced.p)
    );
    let mut off = start;
    off.mu[1] *= 0.9;
    let refused = ReducedIntegrator::plus(jit.clone(), NewtonOptions::default())
        .run(off)
        .steps(10)
        .collect()
        .unwrap_err();
    assert!(
        matches!(&refused.source, StepError::OffManifold { reason } if reason.contains("level set")),
        "{:?}",
        refused.source
    );
    same_runs(compiled, jit.clone(), start, 400);
    let run = ReducedIntegrator::plus(jit, NewtonOptions::default())
        .run(start)
        .steps(400)
        .collect()
        .unwrap();
    let times = run.times;
    assert!(
        times
            .windows(2)
            .any(|w| w[1] - w[0] > 10.0 * (times[1] - times[0])),
        "the steps lengthen away from periapsis"
    );
}

/// The Gauss–Legendre integrators of a text: its stage derivatives compiled on first use, the
/// unreduced and both reduced steps state by state as the compiled-in system's, at orders 2 to 8,
/// adaptive steps included; a text without stage derivatives refused.
#[test]
fn gauss_legendre_steps_bit_for_bit() {
    let (compiled, jit, (q, v)) = continuous_pendulum();
    assert_eq!(jit.stage(&q, &v), compiled.stage(&q, &v));
    assert_eq!(jit.stage_jacobian(&q, &v), compiled.stage_jacobian(&q, &v));
    let start = DoubleSphericalPendulum::paper_initial_state();
    let opts = NewtonOptions::default();
    // The integrator `$new(system, stages, options)` of both systems, state by state.
    macro_rules! same_steps {
        ($new:path, $s:expr, $start:expr, $what:literal) => {{
            let a = $new(compiled, $s, opts).unwrap();
            let b = $new(jit.clone(), $s, opts).unwrap();
            let (ta, tb) = (
                a.run($start).steps(100).collect().unwrap(),
                b.run($start).steps(100).collect().unwrap(),
            );
            same(&ta.states, &tb.states, $what);
        }};
    }
    for s in [1, 4] {
        same_steps!(
            GaussIntegrator::new,
            s,
            compiled.untrivialize(&start),
            "Gauss, unreduced"
        );
        same_steps!(ReducedGaussIntegrator::plus, s, start, "Gauss, reduced (+)");
        same_steps!(
            ReducedGaussIntegrator::minus,
            s,
            start,
            "Gauss, reduced (−)"
        );
    }
    // Adaptive steps at order 8.
    let code = compile(ADAPTIVE_KEPLER).unwrap();
    let compiled = AdaptiveKepler { k: 1.0, h: 0.2 };
    let jit = code
        .instantiate::<1, 2, 3>(&compiled.parameter_values())
        .unwrap();
    let (e, r0) = (0.9_f64, 0.1_f64);
    let start = compiled
        .unreduced_state([r0, 0.0, 0.0], [0.0, (1.0 + e).sqrt() / r0.powf(1.5), 1.0])
        .unwrap();
    let (ta, tb) = (
        GaussIntegrator::new(compiled, 4, opts)
            .unwrap()
            .run(start)
            .steps(200)
            .collect()
            .unwrap(),
        GaussIntegrator::new(jit, 4, opts)
            .unwrap()
            .run(start)
            .steps(200)
            .collect()
            .unwrap(),
    );
    same(&ta.states, &tb.states, "Gauss, adaptive");
    // A discrete Lagrangian has no stage derivatives: NaN, which the step refuses as a typed
    // error (the run requests refuse it before running).
    let discrete = self::code(PAPER, "double_spherical_pendulum");
    assert!(!discrete.has_stages());
    let discrete = discrete
        .instantiate::<3, 1, 4>(&DoubleSphericalPendulum::paper().parameter_values())
        .unwrap();
    let failure = GaussIntegrator::new(discrete, 2, opts)
        .unwrap()
        .run(
            DoubleSphericalPendulum::paper()
                .untrivialize(&DoubleSphericalPendulum::paper_initial_state()),
        )
        .steps(3)
        .collect()
        .unwrap_err();
    assert_eq!(failure.source.step(), 0, "{:?}", failure.source);
}

/// Systems on rotation groups.
#[path = "same_as_compiled/lie.rs"]
mod lie;

/// Element-wise systems sized at run time.
#[path = "same_as_compiled/element.rs"]
mod element;
