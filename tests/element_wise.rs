//! Element-wise systems with run-time sizes (`dirac::runtime::element`).

#[path = "common/child.rs"]
mod child;

use dirac::prelude::*;
use dirac::runtime::element::ElementIntegrator;

#[path = "../examples/common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, DampedTodaN, TodaN};

mod element_systems;
use element_systems::{DampedToda16, DrivenChain, DrivenChain5};

#[test]
fn one_build_runs_at_several_sizes() {
    for n in [3, 16, 200, 2000] {
        let sys = TodaN {
            m: 1.0,
            d: 1.0,
            h: 0.05,
            n,
        };
        let integ = ElementIntegrator::new(sys, NewtonOptions::default());
        let start = initial(&sys, 0.1, 0.3, 0.05);
        let mu0 = integ.momentum_map(&start).unwrap()[0];
        let traj = integ.run(start).steps(200).collect().unwrap();
        let last = traj.states.last().unwrap();
        let mu = integ.momentum_map(last).unwrap()[0];
        assert!(
            (mu - mu0).abs() <= 1e-13 * mu0.abs().max(1.0),
            "n = {n}: {mu} vs {mu0}"
        );
    }
}

/// The same lattice at n = 16 written with a literal size: unrolled, straight-line code.
#[reduced_lagrangian(coordinates(x[16]), translate(x), rule = midpoint)]
fn toda16(q: Config, v: Velocity, m: f64, d: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..16 {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..15 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + 16.0 * d - q.x[15] - d)).exp()
}

type V16 = SVector<f64, 16>;

fn s16(v: &DVector<f64>) -> V16 {
    V16::from_column_slice(v.as_slice())
}

#[test]
fn element_wise_code_equals_the_unrolled_code_at_n_16() {
    use dirac::runtime::adapted::AdaptedCoordinates;
    let (m, d, h) = (1.3, 0.9, 0.05);
    let el = TodaN { m, d, h, n: 16 };
    let un = Toda16 { m, d, h };
    let integ = ElementIntegrator::new(el, NewtonOptions::default());
    let start = initial(&el, 0.2, 0.4, 0.1);
    let q0 = start.q.clone();
    let q1 = &q0 + DVector::from_fn(16, |i, _| 0.01 * (i as f64).cos());
    // L_d: the sum of the element values against the unrolled body, in adapted coordinates.
    let (a0, a1) = (Toda16::to_adapted(&s16(&q0)), Toda16::to_adapted(&s16(&q1)));
    let (l_el, l_un) = (
        integ.discrete_lagrangian(&q0, &q1).unwrap(),
        un.lagrangian(&a0, &a1),
    );
    assert!(
        (l_el - l_un).abs() <= 1e-14 * l_un.abs(),
        "{l_el} vs {l_un}"
    );
    // The residual and the step Jacobian: R_user = T⁻ᵀ R_adapted, J_user = T⁻ᵀ J_adapted T⁻¹.
    let mut ws = integ.workspace();
    let (mut r, mut j) = (DVector::zeros(16), Vec::new());
    integ
        .residual_jacobian(&mut ws, &q0, &start.p, &q1, &mut r, &mut j)
        .unwrap();
    let pa = Toda16::momentum_to_adapted(&s16(&start.p));
    let (ra, ja) = un.unreduced_residual_jacobian(&a0, &pa, &a1);
    let r_un = Toda16::momentum_from_adapted(&ra);
    let t_inv = SMatrix::<f64, 16, 16>::from_fn(|i, k| {
        Toda16::to_adapted(&V16::from_fn(|j, _| f64::from(j == k)))[i]
    });
    let j_un = t_inv.transpose() * ja * t_inv;
    let (col_ptr, row_idx) = ws.pattern();
    let mut j_el = SMatrix::<f64, 16, 16>::zeros();
    for c in 0..16 {
        for p in col_ptr[c]..col_ptr[c + 1] {
            j_el[(row_idx[p], c)] = j[p];
        }
    }
    assert!(
        (s16(&r) - r_un).amax() <= 1e-14 * r_un.amax().max(1.0),
        "R: {:e}",
        (s16(&r) - r_un).amax()
    );
    assert!(
        (j_el - j_un).amax() <= 1e-13 * j_un.amax(),
        "J: {:e}",
        (j_el - j_un).amax()
    );
    // Trajectories: the element-wise step against the reduced (+) integrator of the unrolled code.
    let reduced = ReducedIntegrator::plus(un, NewtonOptions::default());
    let steps = 300;
    let el_traj = integ.run(start.clone()).steps(steps).collect().unwrap();
    let r0 = un.trivialize(&Toda16::adapted_state(&s16(&start.q), &s16(&start.p)));
    let red_traj = reduced.run(r0).steps(steps).collect().unwrap();
    let mut worst = 0.0f64;
    for k in 1..=steps {
        let s = &red_traj.states[k];
        let canonical = Toda16::from_adapted_state(&un.untrivialize(s));
        worst = worst
            .max((canonical.q - s16(&el_traj.states[k].q)).amax())
            .max((canonical.p - s16(&el_traj.states[k].p)).amax());
    }
    eprintln!("element-wise vs reduced (+), n = 16, {steps} steps: largest difference {worst:e}");
    assert!(
        worst <= 1e-10,
        "largest difference over {steps} steps: {worst:e}"
    );
    // The momentum map: exactly μ_0, as the reduced integrator keeps it.
    let mu0 = integ.momentum_map(&start).unwrap()[0];
    for s in &el_traj.states {
        assert!(
            (integ.momentum_map(s).unwrap()[0] - mu0).abs()
                <= 4.0 * f64::EPSILON * 16.0 * mu0.abs().max(1.0)
        );
    }
}

#[path = "../examples/common/membrane.rs"]
mod membrane;
use membrane::Membrane;

#[path = "../examples/common/cluster.rs"]
mod cluster;
use cluster::Cluster;

/// `h L((q0 + q1)/2, (q1 − q0)/h)` from the user's own function (the reference), against the
/// sum of the element values.
#[test]
fn pairs_and_grids_sum_to_the_users_function() {
    let c = Cluster {
        m: 1.0,
        eps: 1.0,
        sigma: 1.0,
        h: 0.002,
        n: 27,
    };
    let s = cluster::initial(&c, 1.15, 0.2);
    let q1 = &s.q + &s.p * (c.h / c.m);
    let integ = ElementIntegrator::new(c, NewtonOptions::default());
    let mid = (&s.q + &q1) * 0.5;
    let vel = (&q1 - &s.q) / c.h;
    let reference =
        c.h * cluster::cluster(c.config(&mid), c.config(&vel), c.m, c.eps, c.sigma, c.n);
    let summed = integ.discrete_lagrangian(&s.q, &q1).unwrap();
    assert!(
        (summed - reference).abs() <= 1e-12 * reference.abs(),
        "{summed} vs {reference}"
    );

    let w = Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: 0.5,
        delta: 0.1,
        h: 0.02,
        nx: 7,
        ny: 5,
    };
    let s = membrane::initial(&w, 0.3, 0.15, 1.0, 0.05);
    let q1 = &s.q + &s.p * 0.3;
    let integ = ElementIntegrator::new(w, NewtonOptions::default());
    let mid = (&s.q + &q1) * 0.5;
    let vel = (&q1 - &s.q) / w.h;
    let reference = w.h
        * membrane::membrane(
            w.config(&mid),
            w.config(&vel),
            w.rho,
            w.c2,
            w.beta,
            w.delta,
            w.nx,
            w.ny,
        );
    let summed = integ.discrete_lagrangian(&s.q, &q1).unwrap();
    assert!(
        (summed - reference).abs() <= 1e-12 * reference.abs(),
        "{summed} vs {reference}"
    );
    assert_eq!(
        w.vector(&w.config(&s.q)),
        s.q,
        "config and vector are inverse"
    );
}

/// The assembled Jacobian against central differences of the assembled residual (grid and
/// pairs: stencils with wrap-around and with every pair).
#[test]
fn the_assembled_jacobian_is_the_derivative_of_the_residual() {
    fn check<L: dirac::runtime::element::ElementLagrangian>(
        integ: &ElementIntegrator<L>,
        s: &ElementState,
        z: &DVector<f64>,
    ) {
        let n = s.q.len();
        let mut ws = integ.workspace();
        let (mut r, mut j) = (DVector::zeros(n), Vec::new());
        integ
            .residual_jacobian(&mut ws, &s.q, &s.p, z, &mut r, &mut j)
            .unwrap();
        let (col_ptr, row_idx) = ws.pattern();
        let (col_ptr, row_idx) = (col_ptr.to_vec(), row_idx.to_vec());
        let mut worst = 0.0f64;
        let mut scale = 0.0f64;
        for c in 0..n {
            let eps = 1e-6;
            let (mut zp, mut zm) = (z.clone(), z.clone());
            zp[c] += eps;
            zm[c] -= eps;
            let (mut rp, mut rm, mut jj) = (DVector::zeros(n), DVector::zeros(n), Vec::new());
            integ
                .residual_jacobian(&mut ws, &s.q, &s.p, &zp, &mut rp, &mut jj)
                .unwrap();
            integ
                .residual_jacobian(&mut ws, &s.q, &s.p, &zm, &mut rm, &mut jj)
                .unwrap();
            let fd = (rp - rm) / (2.0 * eps);
            let mut column = DVector::zeros(n);
            for p in col_ptr[c]..col_ptr[c + 1] {
                column[row_idx[p]] = j[p];
            }
            worst = worst.max((fd - &column).amax());
            scale = scale.max(column.amax());
        }
        assert!(worst <= 1e-6 * scale, "{worst:e} against {scale:e}");
    }
    let w = Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: 0.5,
        delta: 0.1,
        h: 0.02,
        nx: 6,
        ny: 4,
    };
    let s = membrane::initial(&w, 0.3, 0.15, 1.0, 0.05);
    let z = &s.q + &s.p * 0.3;
    check(&ElementIntegrator::new(w, NewtonOptions::default()), &s, &z);
    let c = Cluster {
        m: 1.0,
        eps: 1.0,
        sigma: 1.0,
        h: 0.002,
        n: 8,
    };
    let s = cluster::initial(&c, 1.15, 0.2);
    let z = &s.q + &s.p * c.h;
    check(&ElementIntegrator::new(c, NewtonOptions::default()), &s, &z);
}

/// Parallel assembly is the serial one bit for bit, on 1 and 2 threads.
#[test]
fn parallel_assembly_is_the_serial_one_bit_for_bit() {
    let w = Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: 0.5,
        delta: 0.05,
        h: 0.01,
        nx: 40,
        ny: 36,
    };
    let s = membrane::initial(&w, 0.3, 0.4, 1.0, 0.05);
    let run = |parallel: Parallel, threads: usize| {
        let integ = ElementIntegrator::new(w, NewtonOptions::default()).with_parallel(parallel);
        let pool = dirac::runtime::ensemble::rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            assert_eq!(
                integ.workspace().is_parallel(),
                parallel == Parallel::Always
            );
            integ.run(s.clone()).steps(8).collect().unwrap()
        })
    };
    let serial = run(Parallel::Never, 1);
    for threads in [1, 2, 3] {
        let parallel = run(Parallel::Always, threads);
        for (a, b) in serial.states.iter().zip(&parallel.states) {
            assert!(
                a.q.iter()
                    .zip(b.q.iter())
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "q differs on {threads} threads"
            );
            assert!(
                a.p.iter()
                    .zip(b.p.iter())
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "p differs on {threads} threads"
            );
        }
    }
}

/// The shift of the membrane and the translations of the cluster: their momentum maps stay at
/// their initial values to round-off, and the energy stays bounded.
#[test]
fn momentum_maps_are_exact_on_grids_and_pairs() {
    let w = Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: 0.5,
        delta: 0.1,
        h: 0.02,
        nx: 16,
        ny: 12,
    };
    let integ = ElementIntegrator::new(w, NewtonOptions::default());
    let s = membrane::initial(&w, 0.3, 0.3, 1.0, 0.05);
    let mu0 = integ.momentum_map(&s).unwrap();
    let traj = integ.run(s).steps(300).collect().unwrap();
    let energies: Vec<f64> = traj
        .states
        .windows(2)
        .map(|p| integ.energy(&p[0].q, &p[1].q).unwrap())
        .collect();
    let (lo, hi) = energies
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    assert!(
        (hi - lo) <= 1e-2 * hi.abs(),
        "energy spread {:e} of {hi}",
        hi - lo
    );
    for st in &traj.states {
        let mu = integ.momentum_map(st).unwrap();
        assert!((mu[0] - mu0[0]).abs() <= 1e-13, "{mu:?} vs {mu0:?}");
    }
    let c = Cluster {
        m: 1.0,
        eps: 1.0,
        sigma: 1.0,
        h: 0.002,
        n: 27,
    };
    let integ = ElementIntegrator::new(c, NewtonOptions::default());
    let s = cluster::initial(&c, 1.15, 0.2);
    let mu0 = integ.momentum_map(&s).unwrap();
    assert_eq!(mu0.len(), 3);
    let traj = integ.run(s).steps(200).collect().unwrap();
    for st in &traj.states {
        let mu = integ.momentum_map(st).unwrap();
        for a in 0..3 {
            assert!((mu[a] - mu0[a]).abs() <= 1e-13, "{mu:?} vs {mu0:?}");
        }
    }
}

/// Sizes below the stencils' smallest, and states of the wrong length, are typed errors before
/// any step; the initial state is kept.
#[test]
fn sizes_and_states_that_do_not_fit_are_typed_errors() {
    assert_eq!(
        <TodaN as dirac::runtime::element::ElementLagrangian>::MIN_SIZE,
        1
    );
    let sys = TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 10,
    };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    let short = ElementState::new(DVector::zeros(9), DVector::zeros(9));
    let err = integ.run(short).steps(5).collect().unwrap_err();
    assert!(matches!(err.source, StepError::InvalidSize { .. }), "{err}");
    assert_eq!(err.trajectory.states.len(), 1);
    let empty = TodaN { n: 0, ..sys };
    let err = ElementIntegrator::new(empty, NewtonOptions::default())
        .run(ElementState::new(DVector::zeros(0), DVector::zeros(0)))
        .steps(5)
        .collect()
        .unwrap_err();
    assert!(matches!(err.source, StepError::InvalidSize { .. }), "{err}");
    assert!(err.source.to_string().contains("size `n` = 0"), "{err}");
}

/// Conjugate gradients on the membrane's symmetric step Jacobian give the sparse LU's
/// trajectory; a Jacobian that is not symmetric (a gyroscopic coupling) falls back to the LU.
#[test]
fn conjugate_gradients_match_the_lu_and_fall_back_when_not_symmetric() {
    use dirac::runtime::element::StepSolver;
    let w = Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: 0.5,
        delta: 0.1,
        h: 0.02,
        nx: 12,
        ny: 10,
    };
    let s = membrane::initial(&w, 0.3, 0.3, 1.0, 0.05);
    let run = |linear| {
        let integ = ElementIntegrator::new(w, NewtonOptions::default()).with_solver(linear);
        assert_eq!(
            integ.workspace().linear_solver(),
            if linear == StepSolver::Iterative {
                "conjugate gradients (Jacobi)"
            } else {
                "sparse LU"
            }
        );
        integ.run(s.clone()).steps(50).collect().unwrap()
    };
    let (cg, lu) = (run(StepSolver::Iterative), run(StepSolver::Direct));
    let worst = cg
        .states
        .iter()
        .zip(&lu.states)
        .map(|(a, b)| (&a.q - &b.q).amax().max((&a.p - &b.p).amax()))
        .fold(0.0, f64::max);
    assert!(worst <= 1e-11, "CG against LU: {worst:e}");

    let sys = Gyro {
        m: 1.0,
        b: 0.7,
        h: 0.05,
        n: 8,
    };
    let integ =
        ElementIntegrator::new(sys, NewtonOptions::default()).with_solver(StepSolver::Iterative);
    let start = ElementState::new(
        DVector::from_fn(8, |i, _| (i as f64).sin()),
        DVector::from_fn(8, |i, _| 0.2 * (i as f64).cos()),
    );
    let mut ws = integ.workspace();
    assert_eq!(ws.linear_solver(), "conjugate gradients (Jacobi)");
    let mut next = start.clone();
    integ
        .step_into(
            &mut ws,
            StepAt::new(0, integ.time_step()),
            &start,
            &mut next,
        )
        .unwrap();
    assert_eq!(
        ws.linear_solver(),
        "sparse LU",
        "a non-symmetric Jacobian falls back"
    );
    let direct =
        ElementIntegrator::new(sys, NewtonOptions::default()).with_solver(StepSolver::Direct);
    let (reference, _) = direct.step(0, &start).unwrap();
    assert!((reference.q - next.q).amax() < 1e-13);
}

/// A ring with a gyroscopic (magnetic-like) coupling: `D_1 D_2 L_d` is not symmetric.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint)]
fn gyro(q: Config, v: Velocity, m: f64, b: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let j = (i + 1) % n;
        l += 0.5 * m * v.x[i] * v.x[i] + b * (q.x[i] * v.x[j] - q.x[j] * v.x[i])
            - 0.5 * (q.x[j] - q.x[i]).powi(2);
    }
    l
}

/// The methods of an element integrator that take states or vectors, on vectors of the wrong
/// length (or a workspace of another system): typed errors, not a panic (index out of bounds,
/// a failed assertion) or a silent NaN.
#[test]
fn methods_on_vectors_of_the_wrong_length_are_typed_errors() {
    use std::panic::{catch_unwind, AssertUnwindSafe};
    let sys = TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 10,
    };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    let good = initial(&sys, 0.1, 0.3, 0.05);
    let short = ElementState::new(DVector::zeros(4), DVector::zeros(4));
    let mut ws = integ.workspace();
    let other = ElementIntegrator::new(TodaN { n: 12, ..sys }, NewtonOptions::default());
    let mut other_ws = other.workspace();
    let (mut r, mut j) = (DVector::zeros(10), Vec::new());
    let outcome = |what: &str, f: &mut dyn FnMut() -> String| {
        let got = catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| "a panic".to_string());
        assert!(got.contains("InvalidSize"), "{what}: {got}");
    };
    outcome("momentum_map", &mut || {
        format!("{:?}", integ.momentum_map(&short))
    });
    outcome("energy", &mut || {
        format!("{:?}", integ.energy(&short.q, &good.q))
    });
    outcome("discrete_lagrangian", &mut || {
        format!("{:?}", integ.discrete_lagrangian(&good.q, &short.q))
    });
    outcome("residual_jacobian", &mut || {
        format!(
            "{:?}",
            integ.residual_jacobian(&mut ws, &short.q, &good.p, &good.q, &mut r, &mut j)
        )
    });
    outcome("residual_jacobian, another system's workspace", &mut || {
        format!(
            "{:?}",
            integ.residual_jacobian(&mut other_ws, &good.q, &good.p, &good.q, &mut r, &mut j)
        )
    });
}

/// The periodic Toda lattice with n = 10⁸ under a 4 GB address-space limit (`ulimit -v`, in a
/// child process so that an abort ends the child, not the harness): the input check sees that
/// the run's workspace does not fit before allocating it, and returns a typed error with the
/// bytes needed, where the stencils' check used to collect every element and abort.
#[cfg(target_os = "linux")]
#[test]
fn a_lattice_too_large_for_memory_is_a_typed_error_before_any_allocation() {
    const NAME: &str = "a_lattice_too_large_for_memory_is_a_typed_error_before_any_allocation";
    if !child::in_child(NAME, Some(4000000), "typed error:") {
        return;
    }
    let sys = TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 100_000_000,
    };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    // At rest at the origin: zeroed vectors, which the allocator hands out untouched.
    let n = sys.n;
    let start = ElementState::new(DVector::zeros(n), DVector::zeros(n));
    let err = integ
        .run(start)
        .steps(1)
        .observe(|_, _, _, _| {})
        .stream()
        .unwrap_err();
    let message = err.source.to_string();
    assert_eq!(err.trajectory.step_count, 0);
    assert!(
        message.contains("bytes") && message.contains("memory"),
        "{message}"
    );
    println!("typed error: {message}");
}

/// `q` after 8 units of time from a strongly displaced lattice by `method` with `steps` macro
/// steps at `n = 16`, run-time sized, and the same for the unrolled code (in the user's
/// coordinates).
fn composed_toda(method: CompositionMethod, steps: usize) -> (DVector<f64>, V16) {
    use dirac::runtime::adapted::AdaptedCoordinates;
    let (m, d, h) = (1.0, 0.9, 8.0 / steps as f64);
    let el = TodaN { m, d, h, n: 16 };
    let un = Toda16 { m, d, h };
    let start = initial(&el, 0.6, 1.2, 0.1);
    let options = NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    };
    let composed = Composition::new(ElementIntegrator::new(el, options), method);
    let last = composed.run(start.clone()).steps(steps).collect().unwrap();
    let reduced = Composition::new(ReducedIntegrator::plus(un, options), method);
    let r0 = un.trivialize(&Toda16::adapted_state(&s16(&start.q), &s16(&start.p)));
    let traj = reduced.run(r0).steps(steps).collect().unwrap();
    let canonical = Toda16::from_adapted_state(&un.untrivialize(traj.last()));
    (last.last().q.clone(), canonical.q)
}

#[test]
fn compositions_of_order_four_and_six_at_run_time_sizes_equal_the_unrolled_code() {
    for (method, order) in [
        (CompositionMethod::TRIPLE_JUMP, 4.0),
        (CompositionMethod::KAHAN_LI_6, 6.0),
    ] {
        // The same trajectory as the unrolled code's composition.
        let (el, un) = composed_toda(method, 20);
        let gap = (s16(&el) - un).amax();
        assert!(gap < 1e-12, "{gap:e}");
        // The order, against a run with four times as many steps.
        let reference = composed_toda(method, 640).0;
        let e: Vec<f64> = [20, 40, 80]
            .iter()
            .map(|&n| (composed_toda(method, n).0 - &reference).amax())
            .collect();
        let observed = (e[1] / e[2]).log2();
        assert!(
            (observed - order).abs() < 0.5,
            "order {observed} from {e:?}"
        );
    }
}

#[test]
fn a_damping_force_at_run_time_sizes_is_the_unrolled_forced_step() {
    use dirac::runtime::adapted::AdaptedCoordinates;
    let (m, d, c, h) = (1.3, 0.9, 0.2, 0.05);
    let el = DampedTodaN { m, d, c, h, n: 16 };
    let un = DampedToda16 { m, d, c, h };
    let toda = TodaN { m, d, h, n: 16 };
    let start = initial(&toda, 0.2, 0.4, 0.1);
    let integ = ElementIntegrator::new(el, NewtonOptions::default());
    let steps = 300;
    let traj = integ.run(start.clone()).steps(steps).collect().unwrap();
    let reduced = ReducedIntegrator::plus(un, NewtonOptions::default());
    let r0 = un.trivialize(&DampedToda16::adapted_state(&s16(&start.q), &s16(&start.p)));
    let red = reduced.run(r0).steps(steps).collect().unwrap();
    let mut worst = 0.0f64;
    for k in 0..=steps {
        let canonical = DampedToda16::from_adapted_state(&un.untrivialize(&red.states[k]));
        worst = worst
            .max((canonical.q - s16(&traj.states[k].q)).amax())
            .max((canonical.p - s16(&traj.states[k].p)).amax());
    }
    assert!(
        worst <= 1e-10,
        "largest difference over {steps} steps: {worst:e}"
    );
    // The forced Noether balance of the translation, step by step: μ_{k+1} − μ_k is the
    // impulse of the damping, −c h Σ_i v_i with v = (q_{k+1} − q_k)/h, exactly as the
    // unrolled reduced step keeps μ.
    let mu: Vec<f64> = traj
        .states
        .iter()
        .map(|s| integ.momentum_map(s).unwrap()[0])
        .collect();
    for k in 0..steps {
        let impulse = -c * (&traj.states[k + 1].q - &traj.states[k].q).sum();
        let gap = (mu[k + 1] - mu[k] - impulse).abs();
        assert!(gap <= 1e-14, "step {k}: {gap:e}");
        assert!((mu[k] - red.states[k].mu[0]).abs() <= 1e-12, "step {k}");
    }
    assert!(
        mu[steps] < 0.5 * mu[0],
        "the damping takes the momentum: {} -> {}",
        mu[0],
        mu[steps]
    );
}

#[test]
fn discrete_forces_and_controls_at_run_time_sizes_are_the_unrolled_forced_step() {
    let (h, c, a) = (0.05, 0.3, 0.7);
    let el = DrivenChain { h, c, a, n: 5 };
    let un = DrivenChain5 { h, c, a };
    let q0 = DVector::from_fn(5, |i, _| 0.1 * (i as f64).sin());
    let p0 = DVector::from_fn(5, |i, _| 0.2 * (i as f64).cos());
    let start = ElementState::new(q0.clone(), p0.clone());
    // The drive set before every step by a feedback law on the first particle's position.
    let drive = |x0: f64, k: usize| a * (0.05 * k as f64).cos() - 0.5 * x0;
    let integ = ElementIntegrator::new(el, NewtonOptions::default());
    assert_eq!(integ.control_dim(), 1);
    let traj = integ
        .run(start.clone())
        .steps(200)
        .feedback(|k: usize, _, s: &ElementState, u: &mut [f64]| u[0] = drive(s.q[0], k))
        .collect()
        .unwrap();
    let fixed = UnreducedIntegrator::new(un, NewtonOptions::default())
        .run(UnreducedState::new(
            SVector::<f64, 5>::from_column_slice(q0.as_slice()),
            SVector::<f64, 5>::from_column_slice(p0.as_slice()),
        ))
        .steps(200)
        .feedback(|k: usize, _, s: &UnreducedState<5>, u: &mut [f64]| u[0] = drive(s.q[0], k))
        .collect()
        .unwrap();
    let worst = traj
        .states
        .iter()
        .zip(&fixed.states)
        .map(|(e, f)| {
            (SVector::<f64, 5>::from_column_slice(e.q.as_slice()) - f.q)
                .amax()
                .max((SVector::<f64, 5>::from_column_slice(e.p.as_slice()) - f.p).amax())
        })
        .fold(0.0, f64::max);
    assert!(worst <= 1e-12, "{worst:e}");
    // The drive moves the chain, unlike the same run without controls (the system's own `a`).
    let free = integ.run(start.clone()).steps(200).collect().unwrap();
    assert!((free.last().q[0] - traj.last().q[0]).abs() > 0.01);
    // Controls of the wrong number, or not finite, are typed errors with their step.
    let mut ws = integ.workspace();
    let err = integ
        .step_with(
            &mut ws,
            StepAt::new(3, h).with_controls(&[1.0, 2.0]),
            &start,
        )
        .unwrap_err();
    assert!(
        matches!(
            err,
            StepError::InvalidControls {
                step: 3,
                expected: 1,
                found: 2
            }
        ),
        "{err}"
    );
    let err = integ
        .step_with(
            &mut ws,
            StepAt::new(4, h).with_controls(&[f64::NAN]),
            &start,
        )
        .unwrap_err();
    assert!(matches!(err, StepError::NonFinite { step: 4, .. }), "{err}");
}

/// Particles in 3-D joined pairwise by springs of rest length 1, each point stored as three
/// consecutive entries of one array and read with strided indices.
#[reduced_lagrangian(coordinates(x[3 * n]), rule = midpoint)]
fn strided_springs(q: Config, v: Velocity, k: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        for d in 0..3 {
            l += 0.5 * v.x[3 * i + d] * v.x[3 * i + d];
        }
        for j in i + 1..n {
            let mut r2 = 0.0;
            for d in 0..3 {
                r2 += (q.x[3 * j + d] - q.x[3 * i + d]).powi(2);
            }
            l -= 0.5 * k * (r2.sqrt() - 1.0).powi(2);
        }
    }
    l
}

/// The same particles with one array per component.
#[reduced_lagrangian(coordinates(x[n], y[n], z[n]), rule = midpoint)]
fn component_springs(q: Config, v: Velocity, k: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * (v.x[i] * v.x[i] + v.y[i] * v.y[i] + v.z[i] * v.z[i]);
        for j in i + 1..n {
            let r2 =
                (q.x[j] - q.x[i]).powi(2) + (q.y[j] - q.y[i]).powi(2) + (q.z[j] - q.z[i]).powi(2);
            l -= 0.5 * k * (r2.sqrt() - 1.0).powi(2);
        }
    }
    l
}

#[test]
fn strided_indices_are_three_arrays() {
    let n = 7;
    let point = |i: usize| {
        let t = i as f64;
        [t.cos() * 1.3, (1.7 * t).sin(), 0.4 * t]
    };
    let velocity = |i: usize| {
        let t = i as f64;
        [0.2 * (2.0 * t).sin(), -0.1 * t.cos(), 0.05 * t]
    };
    // Strided: x[3 i + d]; by component: x[i], y[i], z[i] (offsets 0, n, 2n).
    let strided = |f: &dyn Fn(usize) -> [f64; 3]| DVector::from_fn(3 * n, |a, _| f(a / 3)[a % 3]);
    let by_component =
        |f: &dyn Fn(usize) -> [f64; 3]| DVector::from_fn(3 * n, |a, _| f(a % n)[a / n]);
    let s = ElementIntegrator::new(
        StridedSprings { k: 2.0, h: 0.02, n },
        NewtonOptions::default(),
    );
    let c = ElementIntegrator::new(
        ComponentSprings { k: 2.0, h: 0.02, n },
        NewtonOptions::default(),
    );
    assert!(
        StridedSprings::GENERATED.contains("famil"),
        "{}",
        StridedSprings::GENERATED
    );
    let a = s
        .run(ElementState::new(strided(&point), strided(&velocity)))
        .steps(300)
        .collect()
        .unwrap();
    let b = c
        .run(ElementState::new(
            by_component(&point),
            by_component(&velocity),
        ))
        .steps(300)
        .collect()
        .unwrap();
    let mut worst = 0.0f64;
    for (x, y) in a.states.iter().zip(&b.states) {
        for i in 0..n {
            for d in 0..3 {
                worst = worst
                    .max((x.q[3 * i + d] - y.q[d * n + i]).abs())
                    .max((x.p[3 * i + d] - y.p[d * n + i]).abs());
            }
        }
    }
    assert!(worst <= 1e-12, "{worst:e}");
    // The particles moved: the run is not trivial.
    assert!((&a.last().q - &a.states[0].q).amax() > 0.05);
}
