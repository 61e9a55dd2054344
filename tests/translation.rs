//! A symmetry declared on the user's own coordinates (`coordinates(...)`, `translate(...)`) and
//! indexed coordinates (`x[3]`, `q.x[i]`).
//!
//! The compiler builds adapted coordinates (the trivialization `Q = Σ × G` of §2.2.1:
//! `g = x[0]`, `r_c = c − x[0]`) and reduces by the translation of `g` with `B = 0`; the user's
//! states are mapped with `AdaptedCoordinates` (`q = T⁻¹ q_user`, `p = Tᵀ p_user`).

use dirac::prelude::*;

/// The periodic Toda lattice, n = 6, in the particles' own positions: midpoint rule.
#[reduced_lagrangian(coordinates(x[6]), translate(x), rule = midpoint)]
fn toda(q: Config, v: Velocity, m: f64, a: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..6 {
        l += 0.5 * m * v.x[i] * v.x[i] - a * (q.x[i] - q.x[(i + 1) % 6]).exp();
    }
    l
}

/// The same lattice with no symmetry declared (K = 0): the unreduced baseline in the user's
/// coordinates, knowing nothing of adapted coordinates.
#[reduced_lagrangian(shape(x[6]), group(), rule = midpoint)]
fn toda_user(q: Config, v: Velocity, m: f64, a: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..6 {
        l += 0.5 * m * v.x[i] * v.x[i] - a * (q.x[i] - q.x[(i + 1) % 6]).exp();
    }
    l
}

/// The same lattice written by hand in the adapted coordinates the compiler builds:
/// `x[0] = g`, `x[i] = g + r[i − 1]`.
#[reduced_lagrangian(shape(r[5]), group(g), rule = midpoint)]
fn toda_adapted(q: Config, v: Velocity, m: f64, a: f64) -> f64 {
    let (mut x, mut u) = ([q.g; 6], [v.g; 6]);
    for i in 1..6 {
        x[i] = q.g + q.r[i - 1];
        u[i] = v.g + v.r[i - 1];
    }
    let mut l = 0.0;
    for i in 0..6 {
        l += 0.5 * m * u[i] * u[i] - a * (x[i] - x[(i + 1) % 6]).exp();
    }
    l
}

const H: f64 = 0.05;
const STEPS: usize = 400;

fn toda_initial() -> UnreducedState<6> {
    // Positions and momenta of the six particles; total momentum 0.37.
    UnreducedState::new(
        [0.0, 0.9, 2.1, 2.8, 4.2, 5.0],
        [0.5, -0.3, 0.8, -0.6, 0.1, -0.13],
    )
}

/// Newton is run to round-off (tolerances 1e-14), so the trajectories below differ by the
/// rounding of two different evaluations of the same equations — `c` read directly against
/// `g + r_c` — amplified over the run, not by Newton's stopping error.
fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

/// `‖a − b‖∞ / max(‖b‖∞, 1)`.
fn rel<const N: usize>(a: &SVector<f64, N>, b: &SVector<f64, N>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

#[test]
fn names_and_dimensions_of_the_adapted_coordinates() {
    assert_eq!((Toda::SHAPE_DIM, Toda::GROUP_DIM), (5, 1));
    assert_eq!(
        <Toda as DiscreteLagrangian<5, 1, 6>>::SHAPE,
        [
            "x[1] - x[0]",
            "x[2] - x[0]",
            "x[3] - x[0]",
            "x[4] - x[0]",
            "x[5] - x[0]"
        ]
    );
    assert_eq!(<Toda as DiscreteLagrangian<5, 1, 6>>::GROUP, ["x[0]"]);
    assert_eq!(
        <TodaUser as DiscreteLagrangian<6, 0, 6>>::SHAPE,
        ["x[0]", "x[1]", "x[2]", "x[3]", "x[4]", "x[5]"]
    );
    // The configuration struct stays in the user's coordinates.
    let c = TodaConfig {
        x: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
    };
    assert_eq!(c.to_vector(), SVector::from([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]));
    assert_eq!(TodaConfig::from_vector(&c.to_vector()), c);
    assert_eq!(
        Toda::to_adapted(&c.to_vector()),
        SVector::from([1.0, 2.0, 3.0, 4.0, 5.0, 1.0])
    );
}

/// The user's function, called with the user's configurations, is the Lagrangian the system
/// evaluates on adapted vectors.
#[test]
fn the_user_function_reads_user_coordinates() {
    let sys = Toda {
        m: 1.3,
        a: 0.7,
        h: H,
    };
    let q = toda_initial().q;
    let v = SVector::from([0.2, -0.1, 0.4, 0.0, 0.3, -0.5]);
    let direct = toda(
        TodaConfig::from_vector(&q),
        TodaConfig::from_vector(&v),
        1.3,
        0.7,
    );
    let through = sys.continuous_lagrangian(&Toda::to_adapted(&q), &Toda::to_adapted(&v));
    assert!(
        (direct - through).abs() <= 1e-14 * direct.abs(),
        "{direct} vs {through}"
    );
}

/// (a) Reduced (+) in adapted coordinates, mapped back to the user's coordinates, against the
/// unreduced integrator — both the system's own (in adapted coordinates) and a K = 0 system in
/// the user's coordinates — from the same user state. μ is the total momentum, bit for bit
/// constant.
#[test]
fn toda_reduced_equals_unreduced_in_user_coordinates() {
    let sys = Toda {
        m: 1.3,
        a: 0.7,
        h: H,
    };
    let user = TodaUser {
        m: 1.3,
        a: 0.7,
        h: H,
    };
    let start = Toda::to_adapted_state(&toda_initial());
    let total: f64 = toda_initial().p.iter().sum();
    assert_eq!(start.p[5], total);
    let reduced = ReducedIntegrator::plus(sys, tight())
        .run(sys.trivialize(&start))
        .steps(STEPS)
        .collect()
        .unwrap();
    let own = UnreducedIntegrator::new(sys, tight())
        .run(start)
        .steps(STEPS)
        .collect()
        .unwrap();
    let baseline = UnreducedIntegrator::new(user, tight())
        .run(toda_initial())
        .steps(STEPS)
        .collect()
        .unwrap();
    let (mut worst_own, mut worst_user) = (0.0_f64, 0.0_f64);
    for k in 0..=STEPS {
        let r = &reduced.states[k];
        assert_eq!(r.mu, reduced.states[0].mu, "μ at step {k}");
        assert_eq!(r.mu[0], total);
        let back = Toda::from_adapted_state(&sys.untrivialize(r));
        let own_back = Toda::from_adapted_state(&own.states[k]);
        let b = &baseline.states[k];
        worst_own = worst_own
            .max(rel(&back.q, &own_back.q))
            .max(rel(&back.p, &own_back.p));
        worst_user = worst_user.max(rel(&back.q, &b.q)).max(rel(&back.p, &b.p));
        if k == 1 {
            // One step: only round-off separates them (measured 3e-16 and 2.4e-15).
            assert!(
                worst_own < 1e-14 && worst_user < 1e-14,
                "{worst_own:e} {worst_user:e}"
            );
        }
    }
    eprintln!(
        "Toda, {STEPS} steps: max relative |reduced − unreduced| = {worst_own:e} (same system), \
         {worst_user:e} (K = 0 system in user coordinates)"
    );
    // Round-off, grown by the run: one step agrees to a few ulps (asserted above); every step
    // then stops Newton at a residual below ~1e-13 (abs_tol + rel_tol·ρ) and evaluates
    // differently rounded sums (g + r_c against c), and nearby Toda trajectories separate
    // linearly in time. Measured after 400 steps: 1.6e-12 and 1.4e-12; a real mismatch of the
    // conversions or of the reduction would be O(h) = O(1e-2) within the first steps.
    assert!(worst_own < 1e-11, "{worst_own:e}");
    assert!(worst_user < 1e-11, "{worst_user:e}");
    // The motion is not trivial: the particles moved.
    let last = Toda::from_adapted_state(&sys.untrivialize(reduced.last()));
    assert!(rel(&last.q, &toda_initial().q) > 0.1);
}

/// (b) The hand-written adapted Lagrangian builds the same expression graph (`q.g + q.r[i]`
/// is the node the compiler forms for `q.x[i + 1]`), hence the same code and the same steps, bit
/// for bit.
#[test]
fn toda_by_hand_in_adapted_coordinates_takes_the_same_steps() {
    let sys = Toda {
        m: 1.3,
        a: 0.7,
        h: H,
    };
    let hand = TodaAdapted {
        m: 1.3,
        a: 0.7,
        h: H,
    };
    let start = sys.trivialize(&Toda::to_adapted_state(&toda_initial()));
    let a = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(start)
        .steps(STEPS)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::plus(hand, NewtonOptions::default())
        .run(start)
        .steps(STEPS)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
    assert_eq!(Toda::GENERATED, TodaAdapted::GENERATED);
}

/// Three bodies in space with softened gravity, one translation per axis (K = 3), discrete
/// Lagrangian by the midpoint rule written out.
#[reduced_lagrangian(
    coordinates(x[3], y[3], z[3]),
    translate(x),
    translate(y),
    translate(z)
)]
fn three_body(q0: Config, q1: Config, h: f64, m0: f64, m1: f64, m2: f64, eps: f64) -> f64 {
    let m = [m0, m1, m2];
    let mut l = 0.0;
    for i in 0..3 {
        let (vx, vy, vz) = (
            (q1.x[i] - q0.x[i]) / h,
            (q1.y[i] - q0.y[i]) / h,
            (q1.z[i] - q0.z[i]) / h,
        );
        l += 0.5 * m[i] * (vx * vx + vy * vy + vz * vz);
    }
    for i in 0..3 {
        for j in (i + 1)..3 {
            let dx = 0.5 * (q0.x[i] + q1.x[i]) - 0.5 * (q0.x[j] + q1.x[j]);
            let dy = 0.5 * (q0.y[i] + q1.y[i]) - 0.5 * (q0.y[j] + q1.y[j]);
            let dz = 0.5 * (q0.z[i] + q1.z[i]) - 0.5 * (q0.z[j] + q1.z[j]);
            l += m[i] * m[j] / (dx * dx + dy * dy + dz * dz + eps * eps).sqrt();
        }
    }
    h * l
}

const BODIES: ThreeBody = ThreeBody {
    h: 0.01,
    m0: 1.0,
    m1: 0.8,
    m2: 1.2,
    eps: 0.05,
};

fn three_body_initial() -> UnreducedState<9> {
    UnreducedState::new(
        [1.0, -0.5, -0.4, 0.0, 0.9, -0.8, 0.1, -0.2, 0.15],
        [0.1, 0.5, -0.3, 0.7, -0.2, -0.4, 0.05, 0.3, -0.1],
    )
}

/// (c) μ = (P_x, P_y, P_z), the total linear momentum, is conserved bit for bit by the reduced
/// stepper; mapped back, its trajectory is the unreduced one; the unreduced stepper conserves the
/// total momentum only to its Newton tolerance.
#[test]
fn three_bodies_conserve_total_momentum_and_agree_with_unreduced() {
    let sys = BODIES;
    assert_eq!((ThreeBody::SHAPE_DIM, ThreeBody::GROUP_DIM), (6, 3));
    assert_eq!(
        <ThreeBody as DiscreteLagrangian<6, 3, 9>>::SHAPE,
        [
            "x[1] - x[0]",
            "x[2] - x[0]",
            "y[1] - y[0]",
            "y[2] - y[0]",
            "z[1] - z[0]",
            "z[2] - z[0]"
        ]
    );
    assert_eq!(
        <ThreeBody as DiscreteLagrangian<6, 3, 9>>::GROUP,
        ["x[0]", "y[0]", "z[0]"]
    );
    let start = ThreeBody::to_adapted_state(&three_body_initial());
    let p = three_body_initial().p;
    let total = [p[0] + p[1] + p[2], p[3] + p[4] + p[5], p[6] + p[7] + p[8]];
    assert_eq!(
        start.p.fixed_rows::<3>(6).into_owned(),
        SVector::from(total)
    );
    let steps = 500;
    let reduced = ReducedIntegrator::plus(sys, tight())
        .run(sys.trivialize(&start))
        .steps(steps)
        .collect()
        .unwrap();
    let unreduced = UnreducedIntegrator::new(sys, tight())
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    let (mut worst, mut drift) = (0.0_f64, 0.0_f64);
    for k in 0..=steps {
        let r = &reduced.states[k];
        assert_eq!(r.mu, SVector::from(total), "μ at step {k}");
        let back = ThreeBody::from_adapted_state(&sys.untrivialize(r));
        let u = ThreeBody::from_adapted_state(&unreduced.states[k]);
        worst = worst.max(rel(&back.q, &u.q)).max(rel(&back.p, &u.p));
        let pu = &unreduced.states[k].p;
        drift = drift.max((pu.fixed_rows::<3>(6) - SVector::from(total)).amax());
    }
    eprintln!(
        "three bodies, {steps} steps: max relative |reduced − unreduced| = {worst:e}; \
         unreduced total-momentum drift {drift:e}"
    );
    assert!(worst < 1e-11, "{worst:e}");
    assert!(drift < 1e-11, "{drift:e}");
}

/// Bits apart of two f64.
fn ulps(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    let key = |v: f64| {
        let bits = v.to_bits() as i64;
        if bits < 0 {
            i64::MIN - bits
        } else {
            bits
        }
    };
    key(a).abs_diff(key(b))
}

/// SplitMix64: deterministic test values.
fn values(seed: u64, n: usize) -> Vec<f64> {
    let mut state = seed;
    (0..n)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            4.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 2.0
        })
        .collect()
}

/// (d) The conversions are inverse to each other: exactly on dyadic values (every sum and
/// difference is exact), and on arbitrary values to the rounding of one sum and one difference.
#[test]
fn conversions_round_trip() {
    // Dyadic values: every operation exact, so the round trips are exact.
    let q = SVector::<f64, 9>::from([1.5, -0.25, 3.0, 0.125, 2.0, -1.0, 0.5, 0.75, -2.5]);
    let p = SVector::<f64, 9>::from([0.5, 1.25, -3.0, 2.0, -0.125, 1.0, 0.25, -0.75, 4.0]);
    assert_eq!(ThreeBody::from_adapted(&ThreeBody::to_adapted(&q)), q);
    assert_eq!(ThreeBody::to_adapted(&ThreeBody::from_adapted(&q)), q);
    assert_eq!(
        ThreeBody::momentum_from_adapted(&ThreeBody::momentum_to_adapted(&p)),
        p
    );
    assert_eq!(
        ThreeBody::momentum_to_adapted(&ThreeBody::momentum_from_adapted(&p)),
        p
    );
    // ⟨p, q⟩ is invariant: p_user · q_user = (Tᵀ p_user) · (T⁻¹ q_user).
    let (qa, pa) = (
        ThreeBody::to_adapted(&q),
        ThreeBody::momentum_to_adapted(&p),
    );
    assert_eq!(p.dot(&q), pa.dot(&qa));
    // Without a declared translation every map is the identity, bit for bit.
    let q6 = SVector::<f64, 6>::from_column_slice(&values(7, 6));
    assert_eq!(TodaUser::to_adapted(&q6), q6);
    assert_eq!(TodaUser::momentum_from_adapted(&q6), q6);

    // Arbitrary values: positions. c' = fl(a0 + fl(c − a0)) and r' = fl(fl(g + r) − g) are
    // each within 1 ulp of the larger magnitude involved (one rounding of a sum bounded by it,
    // seen through one more rounding); measured, not assumed.
    let mut worst_q = 0_u64;
    for seed in 0..2000 {
        let v = SVector::<f64, 9>::from_column_slice(&values(seed, 9));
        for (back, scale) in [
            (ThreeBody::from_adapted(&ThreeBody::to_adapted(&v)), &v),
            (ThreeBody::to_adapted(&ThreeBody::from_adapted(&v)), &v),
        ] {
            for i in 0..9 {
                let err = (back[i] - scale[i]).abs();
                let bound = f64::EPSILON * scale.amax();
                assert!(
                    err <= bound,
                    "seed {seed}, component {i}: {err:e} > {bound:e}"
                );
                worst_q = worst_q.max(ulps(back[i], scale[i]));
            }
        }
    }
    // Momenta: p_g sums three momenta and the way back subtracts two of them again, so the
    // error is that of a three-term sum: within 2 ulps of max |p|.
    let mut worst_p = 0.0_f64;
    for seed in 0..2000 {
        let v = SVector::<f64, 9>::from_column_slice(&values(10_000 + seed, 9));
        let back = ThreeBody::momentum_from_adapted(&ThreeBody::momentum_to_adapted(&v));
        let err = (back - v).amax() / (f64::EPSILON * v.amax());
        worst_p = worst_p.max(err);
        assert!(err <= 2.0, "seed {seed}: {err} ulps of max |p|");
    }
    eprintln!(
        "round trips on 2000 random vectors: positions worst {worst_q} ulps of the component, \
         momenta worst {worst_p} ulps of max |p|"
    );
}

/// An indexed shape coordinate and three named ones: the same leaves, the same graph, the same
/// code, the same steps.
#[reduced_lagrangian(shape(x[3]), group(c))]
fn indexed(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let mut l = 0.5 / h * (q1.c - q0.c + q0.x[0] * (q1.x[1] - q0.x[1])).powi(2);
    for i in 0..3 {
        l += 0.5 / h * (q1.x[i] - q0.x[i]).powi(2) - h * k * q0.x[i] * q0.x[(i + 1) % 3];
    }
    l - h * q0.x[2].powi(4)
}

#[reduced_lagrangian(shape(x0, x1, x2), group(c))]
fn named(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let mut l = 0.5 / h * (q1.c - q0.c + q0.x0 * (q1.x1 - q0.x1)).powi(2);
    l += 0.5 / h * (q1.x0 - q0.x0).powi(2) - h * k * q0.x0 * q0.x1;
    l += 0.5 / h * (q1.x1 - q0.x1).powi(2) - h * k * q0.x1 * q0.x2;
    l += 0.5 / h * (q1.x2 - q0.x2).powi(2) - h * k * q0.x2 * q0.x0;
    l - h * q0.x2.powi(4)
}

/// (e) `shape(x[3]), group(c)` and `shape(x0, x1, x2), group(c)`: bit-for-bit the same steps,
/// with (+), (−) and the unreduced stepper.
#[test]
fn indexed_coordinates_take_the_same_steps_as_named_ones() {
    let (a, b) = (Indexed { h: 0.02, k: 0.6 }, Named { h: 0.02, k: 0.6 });
    assert_eq!(
        <Indexed as DiscreteLagrangian<3, 1, 4>>::SHAPE,
        ["x[0]", "x[1]", "x[2]"]
    );
    assert_eq!(Indexed::GENERATED, Named::GENERATED);
    let start = ReducedState::new([0.3, -0.2, 0.5], [0.1, 0.4, -0.2], [0.7], [0.0]);
    let opts = NewtonOptions::default();
    let pa = ReducedIntegrator::plus(a, opts)
        .run(start)
        .steps(300)
        .collect()
        .unwrap();
    let pb = ReducedIntegrator::plus(b, opts)
        .run(start)
        .steps(300)
        .collect()
        .unwrap();
    assert_eq!(pa.states, pb.states);
    let ma = ReducedIntegrator::minus(a, opts)
        .run(start)
        .steps(300)
        .collect()
        .unwrap();
    let mb = ReducedIntegrator::minus(b, opts)
        .run(start)
        .steps(300)
        .collect()
        .unwrap();
    assert_eq!(ma.states, mb.states);
    let c = a.untrivialize(&start);
    let ua = UnreducedIntegrator::new(a, opts)
        .run(c)
        .steps(300)
        .collect()
        .unwrap();
    let ub = UnreducedIntegrator::new(b, opts)
        .run(c)
        .steps(300)
        .collect()
        .unwrap();
    assert_eq!(ua.states, ub.states);
    // The configuration structs agree field by field.
    let q = SVector::from([1.0, 2.0, 3.0, 4.0]);
    let (ia, nb) = (IndexedConfig::from_vector(&q), NamedConfig::from_vector(&q));
    assert_eq!(ia.x, [nb.x0, nb.x1, nb.x2]);
    assert_eq!(ia.c, nb.c);
    assert_eq!(
        indexed(ia, ia, 0.02, 0.6).to_bits(),
        named(nb, nb, 0.02, 0.6).to_bits()
    );
}

/// A loop of 1000 iterations unrolls, and an array coordinate longer than 32 gets a `Default`.
#[reduced_lagrangian(shape(x[40]), group())]
fn long_chain(q0: Config, q1: Config, h: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..40 {
        l += 0.5 / h * (q1.x[i] - q0.x[i]).powi(2);
    }
    // 1000 iterations, each adding the same small spring term for one pair of components.
    for j in 0..1000 {
        l -= 1e-3 * h * (q0.x[j % 40] - q0.x[(j + 1) % 40]).powi(2);
    }
    l
}

#[test]
fn long_loops_and_long_arrays() {
    let c = LongChainConfig::default();
    assert_eq!(c.x, [0.0; 40]);
    let sys = LongChain { h: 0.1 };
    let q0 = SVector::<f64, 40>::from_fn(|i, _| i as f64 * 0.1);
    let q1 = SVector::<f64, 40>::from_fn(|i, _| i as f64 * 0.1 + 0.01);
    let l = sys.lagrangian(&q0, &q1);
    // Kinetic 40 · ½ /0.1 · 1e-4 = 0.02; the springs: 1000 terms, 975 of (0.1)² and 25 of the
    // closing pair (3.9)² (j % 40 = 39 for 25 values of j).
    let expected = 0.02 - 1e-3 * 0.1 * (975.0 * 0.01 + 25.0 * 3.9 * 3.9);
    assert!((l - expected).abs() < 1e-12, "{l} vs {expected}");
}
