//! Systems on rotation groups given as text at sizes chosen at run time ([`DynJitLie`], run by
//! `LieIntegratorOf<_, Dyn, Dyn>`) against the same systems compiled in at fixed sizes: eight
//! rigid bodies on a chain of springs (the text of `texts/eight_bodies.rs`, compiled in here
//! from the same characters), beyond any fixed-size instance a front end dispatches, and the
//! small systems of the facade.

use std::sync::Arc;

use dirac::prelude::*;
use dirac::runtime::lie::{cayley, LieIntegratorOf, LieStateOf, ReducedLieIntegratorOf};
use dirac::runtime::nalgebra::{DVector, Dyn, Matrix3, Vector3};
use dirac::systems::rotations::{DspOnSpheres, HeavyTop};
use dirac_jit::{compile_lie, DynJitLie, LieCode};

#[path = "texts/eight_bodies.rs"]
mod eight_bodies;

use eight_bodies::{EightBodies, EightBodiesConfig, EightBodiesMomentum};

const EIGHT_BODIES: &str = include_str!("texts/eight_bodies.rs");
const ROTATIONS: &str = include_str!("../../src/systems/rotations.rs");

/// The text of the function `name` of a source file, with its attribute and doc comments.
fn function(source: &str, name: &str) -> String {
    let file = syn::parse_file(source).expect("the sources parse");
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

fn lie_code(source: &str, name: &str) -> Arc<LieCode> {
    compile_lie(&function(source, name)).unwrap_or_else(|e| panic!("{name}:\n{e}"))
}

/// The attitudes and body momenta of the eight bodies' start.
fn eight_start() -> (Vec<Matrix3<f64>>, Vec<Vector3<f64>>) {
    let rotations = (1..=8)
        .map(|i| cayley(&Vector3::new(0.1 * f64::from(i), -0.2, 0.05 * f64::from(i))))
        .collect();
    let momenta = (1..=8)
        .map(|i| Vector3::new(0.3, 1.0 - 0.1 * f64::from(i), -0.2 * f64::from(i)))
        .collect();
    (rotations, momenta)
}

/// The compiled-in system's start.
fn compiled_start(sys: &EightBodies) -> LieState<72, 24> {
    let (r, m) = eight_start();
    sys.state(
        &EightBodiesConfig {
            r1: r[0],
            r2: r[1],
            r3: r[2],
            r4: r[3],
            r5: r[4],
            r6: r[5],
            r7: r[6],
            r8: r[7],
        },
        &EightBodiesMomentum {
            r1: m[0],
            r2: m[1],
            r3: m[2],
            r4: m[3],
            r5: m[4],
            r6: m[5],
            r7: m[6],
            r8: m[7],
        },
    )
}

/// The start given at run time, from the coordinates as the text names them.
fn dyn_start(sys: &DynJitLie) -> LieStateOf<Dyn, Dyn> {
    let (r, m) = eight_start();
    let rows: Vec<Vec<f64>> = r
        .iter()
        .map(|r| r.transpose().as_slice().to_vec())
        .collect();
    let q: Vec<&[f64]> = rows.iter().map(Vec::as_slice).collect();
    let p: Vec<&[f64]> = m.iter().map(|m| m.as_slice()).collect();
    sys.state(&q, &p).unwrap()
}

/// `a` and `b` equal entry by entry, state by state; else the first state that differs.
fn same_states<const P: usize, const N: usize>(
    a: &[LieState<P, N>],
    b: &[LieStateOf<Dyn, Dyn>],
    what: &str,
) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (k, (a, b)) in a.iter().zip(b).enumerate() {
        assert!(
            a.q.as_slice() == b.q.as_slice() && a.p.as_slice() == b.p.as_slice(),
            "{what}: step {k} differs:\n{a:?}\n{b:?}"
        );
    }
}

/// The largest difference between `a` and `b` over every state, relative to the state's size.
fn relative_gap<const P: usize, const N: usize>(
    a: &[LieState<P, N>],
    b: &[LieStateOf<Dyn, Dyn>],
) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(a, b)| {
            let gap =
                a.q.iter()
                    .zip(b.q.iter())
                    .chain(a.p.iter().zip(b.p.iter()))
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max);
            gap / a.p.amax().max(1.0)
        })
        .fold(0.0, f64::max)
}

/// Eight bodies (a stored point of 72 entries, 24 chart coordinates): the system given as text
/// at run-time sizes takes every step of the compiled-in one bit for bit, (+) and (−), over 300
/// steps — both factor the step Jacobian on the compiler's sparsity pattern with the same
/// ordering and pivots, and the kernels perform the emitted Rust's operations in its order — and
/// keeps the spatial angular momentum to round-off.
#[test]
fn eight_bodies_at_run_time_sizes_step_bit_for_bit_as_compiled_in() {
    let compiled = EightBodies { h: 0.01, k: 3.0 };
    let code = lie_code(EIGHT_BODIES, "eight_bodies");
    assert_eq!(
        (code.system().point_len(), code.system().chart_len()),
        (72, 24)
    );
    let given = code.instantiate_dyn(&compiled.parameter_values()).unwrap();
    let s0 = compiled_start(&compiled);
    let d0 = dyn_start(&given);
    assert_eq!(s0.q.as_slice(), d0.q.as_slice(), "the start's point");
    assert_eq!(s0.p.as_slice(), d0.p.as_slice(), "the start's momenta");
    let opts = NewtonOptions::default();
    let steps = 300;
    let a = LieIntegrator::new(compiled, opts)
        .run(s0)
        .steps(steps)
        .collect()
        .unwrap();
    let integ = LieIntegratorOf::new(given.clone(), opts);
    let b = integ.run(d0.clone()).steps(steps).collect().unwrap();
    same_states(&a.states, &b.states, "(+)");
    assert_eq!(a.stats, b.stats, "(+) Newton statistics");
    // The bodies move: the last attitudes are far from the first.
    assert!((a.last().q - s0.q).amax() > 0.1);
    // The spatial angular momentum, kept to round-off.
    let pi0 = integ.spatial_momentum(&b.states[0]);
    let drift = b
        .states
        .iter()
        .map(|s| (integ.spatial_momentum(s) - pi0).amax())
        .fold(0.0, f64::max);
    assert!(drift < 1e-13 * pi0.amax().max(1.0), "π drifts by {drift:e}");
    let a = LieIntegrator::minus(compiled, opts)
        .run(s0)
        .steps(steps)
        .collect()
        .unwrap();
    let b = LieIntegratorOf::minus(given, opts)
        .run(d0)
        .steps(steps)
        .collect()
        .unwrap();
    same_states(&a.states, &b.states, "(−)");
}

/// The small systems of the facade, at run-time sizes: the heavy top (dense kernels, the step
/// Jacobian factored by the run-time-sized dense LU where the compiled-in step uses the
/// fixed-size one — another order of operations, so agreement to 1e-12 relative and not bit for
/// bit), reduced or not, and the pendulum on `S² × S²` (over 200 steps: its motion is chaotic
/// and amplifies round-off).
#[test]
fn small_systems_at_run_time_sizes_agree_with_the_compiled_in_ones() {
    let opts = NewtonOptions::default();
    let top = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.0,
        j3: 0.5,
        mgl: 2.0,
    };
    let code = lie_code(ROTATIONS, "heavy_top");
    let given = code.instantiate_dyn(&top.parameter_values()).unwrap();
    let r = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.8, -0.6, 0.0, 0.6, 0.8);
    let s0 = LieState::<9, 3>::from_row_major(
        SVector::<f64, 9>::from_iterator(r.transpose().iter().copied()),
        [0.2, -0.1, 3.0],
    );
    let d0 = given
        .state(&[r.transpose().as_slice()], &[&[0.2, -0.1, 3.0]])
        .unwrap();
    assert_eq!(s0.q.as_slice(), d0.q.as_slice());
    let a = LieIntegrator::new(top, opts)
        .run(s0)
        .steps(500)
        .collect()
        .unwrap();
    let b = LieIntegratorOf::new(given, opts)
        .run(d0.clone())
        .steps(500)
        .collect()
        .unwrap();
    let gap = relative_gap(&a.states, &b.states);
    assert!(gap < 1e-12, "heavy top: {gap:e}");
    let integ = ReducedLieIntegrator::new(top, opts);
    let a = integ.run(integ.reduce(&s0)).steps(500).collect().unwrap();
    let reduced = code
        .instantiate_dyn_reduced(&top.parameter_values())
        .unwrap();
    let dyn_integ = ReducedLieIntegratorOf::new(reduced, opts);
    let b = dyn_integ
        .run(dyn_integ.reduce(&d0))
        .steps(500)
        .collect()
        .unwrap();
    assert_eq!(a.last().mu, b.last().mu, "μ, copied from step to step");
    let gap = a
        .states
        .iter()
        .zip(&b.states)
        .map(|(a, b)| (a.p - DVector::from_column_slice(b.p.as_slice())).amax())
        .fold(0.0, f64::max);
    assert!(gap < 1e-12, "reduced heavy top: {gap:e}");

    let dsp = DspOnSpheres::paper(0.01);
    let code = lie_code(ROTATIONS, "dsp_on_spheres");
    let given = code.instantiate_dyn(&dsp.parameter_values()).unwrap();
    let s0 = dsp.paper_initial_state();
    let d0 = LieStateOf {
        q: DVector::from_column_slice(s0.q.as_slice()),
        p: DVector::from_column_slice(s0.p.as_slice()),
    };
    // The double pendulum amplifies round-off (its motion is chaotic): 200 steps, each solved
    // to near round-off (the two factorizations otherwise accept different solutions within
    // Newton's default tolerance, 1e-12 of the momenta).
    let opts = NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..opts
    };
    let a = LieIntegrator::new(dsp, opts)
        .run(s0)
        .steps(200)
        .collect()
        .unwrap();
    let b = LieIntegratorOf::new(given, opts)
        .run(d0)
        .steps(200)
        .collect()
        .unwrap();
    let gap = relative_gap(&a.states, &b.states);
    assert!(gap < 1e-12, "pendulum on S² × S²: {gap:e}");
}

/// A state of other sizes than the system's is a typed error before any step, not a panic.
#[test]
fn a_state_of_the_wrong_size_is_refused() {
    let code = lie_code(EIGHT_BODIES, "eight_bodies");
    let given = code.instantiate_dyn(&[0.01, 3.0]).unwrap();
    let mut s0 = dyn_start(&given);
    s0.p = DVector::zeros(23);
    let e = LieIntegratorOf::new(given, NewtonOptions::default())
        .run(s0)
        .steps(3)
        .collect()
        .unwrap_err();
    let why = e.source.to_string();
    assert!(why.contains("24"), "{why}");
}
