//! Systems given as text against the same systems compiled in with `#[reduced_lagrangian]`: the
//! text is cut from the facade's own sources (the paper's systems, Kepler's), so both are
//! compiled from the same characters, and every step of every integrator must agree bit for bit
//! — the kernels perform the same operations in the same order as the emitted Rust.

use std::sync::Arc;

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, DoubleSphericalPendulumContinuous};
use dirac::prelude::*;
use dirac::systems::kepler::Kepler;
use dirac_jit::{compile, Code};

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

/// A continuous Lagrangian with its quadrature rule: `L_d` formed by the compiler, and the
/// Legendre map and energy from the same graph.
#[test]
fn a_continuous_lagrangian_steps_bit_for_bit() {
    let code = code(PAPER, "double_spherical_pendulum_continuous");
    let compiled = DoubleSphericalPendulumContinuous::paper();
    let jit = code
        .instantiate::<3, 1, 4>(&compiled.parameter_values())
        .unwrap();
    let (q, v) = (
        SVector::<f64, 4>::new(0.4, 0.1, 0.7, 0.2),
        SVector::<f64, 4>::new(0.3, -0.2, 0.1, 0.5),
    );
    assert_eq!(jit.legendre(&q, &v), Some(compiled.legendre(&q, &v)));
    assert_eq!(jit.energy(&q, &v), Some(compiled.energy(&q, &v)));
    let start = DoubleSphericalPendulum::paper_initial_state();
    same_runs(compiled, jit, start, 300);
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
    let b = ReducedIntegrator::plus(jit, opts)
        .run(start)
        .steps(500)
        .feedback(law)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "forced (+)");
    assert_ne!(a.last().mu, start.mu, "the torque changes μ");
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
    same_runs(compiled, jit, start, 100);
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
