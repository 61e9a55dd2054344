//! Element-wise systems given as text against the same systems compiled in: the examples'
//! Toda lattice (with and without damping), membrane (a 2-D grid with periodic stencils) and
//! chain of links with a constraint per link, and the tests' driven chain (discrete forces and a
//! control), each at sizes chosen at run time. Every step of every integrator is the same, bit
//! for bit: the kernels perform the compiled-in kernels' operations in their order, and the
//! elements are visited in the emitted loops' order.

use std::sync::Arc;

use dirac::prelude::*;
use dirac::runtime::element::{
    ElementConstrainedIntegrator, ElementIntegrator, ElementLagrangian, ElementState,
};
use dirac::runtime::nalgebra::DVector;
use dirac_jit::{compile_element, ElementCode, JitElement};

use super::{function, same};

#[path = "../../../examples/common/toda_n.rs"]
#[allow(dead_code)]
mod toda_n;

#[path = "../../../examples/common/membrane.rs"]
#[allow(dead_code)]
mod membrane;

#[path = "../../../examples/common/link_chain.rs"]
mod link_chain;

#[path = "../../../tests/element_systems/mod.rs"]
mod element_systems;

fn element_code(source: &str, name: &str) -> Arc<ElementCode> {
    compile_element(&function(source, name)).unwrap_or_else(|e| panic!("{name}:\n{e}"))
}

/// Both sides and the triple jump of both systems from `start`, state by state.
fn same_element_runs<L: ElementLagrangian>(
    compiled: L,
    jit: JitElement,
    start: &ElementState,
    steps: usize,
) {
    assert_eq!(compiled.dim(), jit.dim());
    assert_eq!(compiled.sizes(), jit.sizes());
    assert_eq!(compiled.translations(), jit.translations());
    assert_eq!(compiled.size_names(), jit.size_names());
    assert_eq!(
        (
            compiled.min_size(),
            compiled.continuous(),
            compiled.forced()
        ),
        (jit.min_size(), jit.continuous(), jit.forced())
    );
    let opts = NewtonOptions::default();
    let a = ElementIntegrator::new(compiled.clone(), opts)
        .run(start.clone())
        .steps(steps)
        .collect()
        .unwrap();
    let b = ElementIntegrator::new(jit.clone(), opts)
        .run(start.clone())
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "(+)");
    let a = ElementIntegrator::minus(compiled.clone(), opts)
        .run(start.clone())
        .steps(steps)
        .collect()
        .unwrap();
    let b = ElementIntegrator::minus(jit.clone(), opts)
        .run(start.clone())
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "(−)");
    let a = Composition::new(
        ElementIntegrator::new(compiled, opts),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(start.clone())
    .steps(steps / 10)
    .collect()
    .unwrap();
    let b = Composition::new(
        ElementIntegrator::new(jit, opts),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(start.clone())
    .steps(steps / 10)
    .collect()
    .unwrap();
    same(&a.states, &b.states, "triple jump");
}

const TODA_N: &str = include_str!("../../../examples/common/toda_n.rs");

#[test]
fn the_toda_lattice_sized_at_run_time_steps_bit_for_bit() {
    let code = element_code(TODA_N, "toda_n");
    assert_eq!(code.system().sizes, ["n"]);
    for n in [8, 64] {
        let compiled = toda_n::TodaN {
            m: 1.0,
            d: 1.0,
            h: 0.05,
            n,
        };
        let jit = code
            .instantiate_named(&[("m", 1.0), ("d", 1.0), ("h", 0.05)], &[("n", n)])
            .unwrap();
        let start = toda_n::initial(&compiled, 0.1, 0.2, 0.05);
        let opts = NewtonOptions::default();
        let (ea, eb) = (
            ElementIntegrator::new(compiled, opts),
            ElementIntegrator::new(jit.clone(), opts),
        );
        let q1 = &start.q + &start.p * 0.01;
        assert_eq!(
            ea.energy(&start.q, &q1).unwrap(),
            eb.energy(&start.q, &q1).unwrap()
        );
        same_element_runs(compiled, jit, &start, 200);
    }
}

#[test]
fn a_damped_lattice_steps_bit_for_bit_with_the_same_sensitivities() {
    let code = element_code(TODA_N, "damped_toda_n");
    let compiled = toda_n::DampedTodaN {
        m: 1.0,
        d: 1.0,
        c: 0.2,
        h: 0.05,
        n: 16,
    };
    let jit = code
        .instantiate(&compiled.parameter_values(), &[16])
        .unwrap();
    assert!(jit.forced());
    let start = toda_n::initial(
        &toda_n::TodaN {
            m: 1.0,
            d: 1.0,
            h: 0.05,
            n: 16,
        },
        0.1,
        0.2,
        0.05,
    );
    same_element_runs(compiled, jit.clone(), &start, 200);
    let opts = NewtonOptions::default();
    let (_, _, mut a) = ElementIntegrator::new(compiled, opts)
        .step_sensitivity(0, &start, &[])
        .unwrap();
    let (_, _, mut b) = ElementIntegrator::new(jit, opts)
        .step_sensitivity(0, &start, &[])
        .unwrap();
    assert_eq!(a.to_dense(), b.to_dense(), "the step's sensitivity");
}

#[test]
fn a_driven_chain_steps_bit_for_bit_under_feedback() {
    let text = function(
        include_str!("../../../tests/element_systems/mod.rs"),
        "driven_chain",
    );
    let code = compile_element(&text).unwrap();
    assert_eq!(code.system().controls, [2]);
    let compiled = element_systems::DrivenChain {
        h: 0.05,
        c: 0.3,
        a: 0.7,
        n: 9,
    };
    let jit = code
        .instantiate(&compiled.parameter_values(), &[9])
        .unwrap();
    // The one system model says the same of both.
    assert_eq!(jit.control_count(), 1);
    assert_eq!(jit.control_names(), compiled.control_names());
    assert_eq!(jit.coordinate_names(), compiled.coordinate_names());
    assert_eq!(jit.parameter_names(), compiled.parameter_names());
    let start = ElementState::new(
        DVector::from_fn(9, |i, _| 0.1 * (i as f64).sin()),
        DVector::from_fn(9, |i, _| 0.2 * (i as f64).cos()),
    );
    same_element_runs(compiled, jit.clone(), &start, 200);
    let law = |k: usize, _: f64, s: &ElementState, u: &mut [f64]| {
        u[0] = 0.7 * (0.05 * k as f64).cos() - 0.5 * s.q[0];
    };
    let opts = NewtonOptions::default();
    let a = ElementIntegrator::new(compiled, opts)
        .run(start.clone())
        .steps(200)
        .feedback(law)
        .collect()
        .unwrap();
    let b = ElementIntegrator::new(jit.clone(), opts)
        .run(start.clone())
        .steps(200)
        .feedback(law)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "under feedback");
    let (_, _, mut a) = ElementIntegrator::new(compiled, opts)
        .step_sensitivity(0, &start, &[0.4])
        .unwrap();
    let (_, _, mut b) = ElementIntegrator::new(jit, opts)
        .step_sensitivity(0, &start, &[0.4])
        .unwrap();
    let (a, b) = (a.to_dense(), b.to_dense());
    assert_eq!(a, b, "the step's sensitivity to the state and the control");
    assert!(a.control.iter().any(|&v| v != 0.0));
}

#[test]
fn a_membrane_on_a_periodic_grid_steps_bit_for_bit() {
    let code = element_code(
        include_str!("../../../examples/common/membrane.rs"),
        "membrane",
    );
    assert_eq!(code.system().sizes, ["nx", "ny"]);
    let compiled = membrane::Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: 0.5,
        delta: 0.1,
        h: 0.02,
        nx: 9,
        ny: 7,
    };
    let jit = code
        .instantiate(&compiled.parameter_values(), &[9, 7])
        .unwrap();
    let start = membrane::initial(&compiled, 0.3, 0.2, 1.0, 0.1);
    same_element_runs(compiled, jit, &start, 100);
}

#[test]
fn a_chain_of_links_with_a_constraint_per_link_steps_bit_for_bit() {
    let code = element_code(
        include_str!("../../../examples/common/link_chain.rs"),
        "link_chain",
    );
    let n = 6;
    let compiled = link_chain::LinkChain {
        mc: 1.0,
        m: 0.5,
        l: 0.4,
        gr: 9.81,
        h: 0.01,
        n,
    };
    let jit = code
        .instantiate(&compiled.parameter_values(), &[n])
        .unwrap();
    assert!(jit.constrained());
    assert_eq!(jit.constraint_count(), compiled.constraint_count());
    let start = link_chain::hanging(n, 0.4);
    let opts = NewtonOptions::default();
    for plus in [true, false] {
        let (a, b) = if plus {
            (
                ElementConstrainedIntegrator::new(compiled, opts),
                ElementConstrainedIntegrator::new(jit.clone(), opts),
            )
        } else {
            (
                ElementConstrainedIntegrator::minus(compiled, opts),
                ElementConstrainedIntegrator::minus(jit.clone(), opts),
            )
        };
        let a = a.run(start.clone()).steps(200).collect().unwrap();
        let b = b.run(start.clone()).steps(200).collect().unwrap();
        same(&a.states, &b.states, "constrained states");
        same(
            &a.records,
            &b.records,
            "multipliers and constraint residuals",
        );
        assert!(b.max_constraint_residual() < 1e-9);
    }
}

#[test]
fn wrong_sizes_and_kinds_are_errors() {
    let code = element_code(TODA_N, "toda_n");
    let e = code.instantiate(&[1.0, 1.0, 0.05], &[]).unwrap_err();
    assert!(e.to_string().contains("0 sizes for 1 (n)"), "{e}");
    let e = code
        .instantiate_named(&[("m", 1.0), ("d", 1.0), ("h", 0.05)], &[("m", 3)])
        .unwrap_err();
    assert!(e.to_string().contains("no parameter `m`"), "{e}");
    // Below the smallest size the stencils fit in: the integrator says so before any step, as
    // for the compiled-in system.
    let tiny = code.instantiate(&[1.0, 1.0, 0.05], &[0]).unwrap();
    let start = ElementState::new(DVector::zeros(0), DVector::zeros(0));
    let err = ElementIntegrator::new(tiny, NewtonOptions::default())
        .run(start.clone())
        .steps(1)
        .collect()
        .unwrap_err();
    let compiled = toda_n::TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 0,
    };
    let expected = ElementIntegrator::new(compiled, NewtonOptions::default())
        .run(start)
        .steps(1)
        .collect()
        .unwrap_err();
    assert_eq!(err.to_string(), expected.to_string());
    // The other kinds of text, each way.
    let e = dirac_jit::compile(&function(TODA_N, "toda_n")).unwrap_err();
    assert!(e.to_string().contains("compile_element"), "{e}");
    let e = compile_element(
        "#[reduced_lagrangian(shape(x), group())]\n\
         fn f(q0: Config, q1: Config, h: f64) -> f64 { (q1.x - q0.x) * (q1.x - q0.x) / h }",
    )
    .unwrap_err();
    assert!(e.to_string().contains("not an element-wise system"), "{e}");
    assert!(matches!(
        dirac_jit::compile_any(&function(TODA_N, "toda_n")),
        Ok(dirac_jit::Compiled::Element(_))
    ));
}
