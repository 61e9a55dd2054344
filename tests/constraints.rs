//! Holonomic constraints: the constrained discrete Lagrange–Dirac equations (RATTLE form),
//! unreduced and reduced, dense and sparse.

use dirac::prelude::*;
use dirac::runtime::{AdaptedCoordinates, DiscreteLagrangian};

/// A planar pendulum in Cartesian coordinates: the bob at `(x, y)` on a circle of radius `l`.
#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]
fn cartesian_pendulum(q: Config, v: Velocity, m: f64, l: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
}

/// The same pendulum in its angle: `(x, y) = (l sin θ, −l cos θ)`.
#[reduced_lagrangian(shape(theta), group(), rule = midpoint)]
fn angle_pendulum(q: Config, v: Velocity, m: f64, l: f64) -> f64 {
    0.5 * m * l * l * v.theta * v.theta + 9.81 * m * l * q.theta.cos()
}

/// A bead on a vertical cylinder of radius `r` under gravity along the axis `z`, with a spring
/// to the axis' plane of motion: translating `z` is a symmetry, and the constraint does not
/// read `z`, so the reduced constrained step keeps `p_z` exact.
#[reduced_lagrangian(shape(x, y), group(z), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - r * r])]
fn bead(q: Config, v: Velocity, m: f64, r: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) - 0.5 * (q.x - 0.3) * (q.x - 0.3)
}

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

fn pendulum_start(l: f64, theta: f64, omega: f64) -> UnreducedState<2> {
    let (x, y) = (l * theta.sin(), -l * theta.cos());
    let (vx, vy) = (l * omega * theta.cos(), l * omega * theta.sin());
    UnreducedState::new([x, y], [vx, vy])
}

#[test]
fn the_cartesian_pendulum_stays_on_its_circle_and_matches_the_angle_pendulum() {
    let (m, l, t_end) = (1.0, 1.3, 4.0);
    let run = |n: usize| {
        let sys = CartesianPendulum {
            h: t_end / n as f64,
            m,
            l,
        };
        let traj = ConstrainedIntegrator::new(sys, tight())
            .run(pendulum_start(l, 1.0, 0.0))
            .steps(n)
            .collect()
            .unwrap();
        // Every step on the circle, to round-off, and the velocity tangent to it (RATTLE).
        assert!(
            traj.max_constraint_residual() <= 1e-13 * l * l,
            "{:e}",
            traj.max_constraint_residual()
        );
        for s in &traj.states {
            let tangency = (s.q[0] * s.p[0] + s.q[1] * s.p[1]).abs();
            assert!(tangency <= 1e-12, "{tangency:e}");
        }
        let end = traj.last();
        end.q[1].atan2(end.q[0]) + std::f64::consts::FRAC_PI_2
    };
    let angle = |n: usize| {
        let sys = AnglePendulum {
            h: t_end / n as f64,
            m,
            l,
        };
        let traj = UnreducedIntegrator::new(sys, tight())
            .run(UnreducedState::new([1.0], [0.0]))
            .steps(n)
            .collect()
            .unwrap();
        traj.last().q[0]
    };
    // Both discretizations converge at order 2 to the same motion.
    let (c1, c2, c3) = (run(200), run(400), run(800));
    let order = ((c1 - c2) / (c2 - c3)).abs().log2();
    assert!((order - 2.0).abs() < 0.1, "order {order}");
    let reference = angle(6400);
    assert!(
        (c3 - reference).abs() < 5.0 * (c2 - c3).abs(),
        "{c3} {reference}"
    );
}

#[test]
fn the_initial_state_must_satisfy_the_constraints() {
    let sys = CartesianPendulum {
        h: 0.01,
        m: 1.0,
        l: 1.0,
    };
    let e = ConstrainedIntegrator::new(sys, tight())
        .run(UnreducedState::new([1.1, 0.0], [0.0, 0.0]))
        .steps(10)
        .collect()
        .unwrap_err();
    assert!(
        matches!(e.source, StepError::ConstraintViolated { .. }),
        "{e}"
    );
    assert_eq!(e.trajectory.step_count(), 0);
}

/// The largest step cap with a stop condition: the constrained trajectories grow as the run
/// proceeds, and stop after the third state as a run of three steps does.
#[test]
fn a_constrained_run_up_to_usize_max_steps_stops_on_its_condition() {
    let sys = Bead {
        h: 0.01,
        m: 1.2,
        r: 0.8,
    };
    let c0 = UnreducedState::new([0.8, 0.0, 0.0], [0.0, 0.5, 0.7]);
    let unreduced = ConstrainedIntegrator::new(sys, tight());
    let capped = unreduced
        .run(c0)
        .steps(usize::MAX)
        .stop(|k, _, _| k == 3)
        .collect()
        .unwrap();
    assert_eq!(
        capped.states,
        unreduced.run(c0).steps(3).collect().unwrap().states
    );
    let reduced = ReducedConstrainedIntegrator::plus(sys, tight());
    let s0 = sys.trivialize(&c0);
    let capped = reduced
        .run(s0)
        .steps(usize::MAX)
        .stop(|k, _, _| k == 3)
        .collect()
        .unwrap();
    assert_eq!(
        capped.states,
        reduced.run(s0).steps(3).collect().unwrap().states
    );
}

#[test]
fn reduced_and_unreduced_constrained_steps_agree_and_mu_is_exact() {
    let sys = Bead {
        h: 0.01,
        m: 1.2,
        r: 0.8,
    };
    let c0 = UnreducedState::new([0.8, 0.0, 0.0], [0.0, 0.5, 0.7]);
    let unr = ConstrainedIntegrator::new(sys, tight())
        .run(c0)
        .steps(1000)
        .collect()
        .unwrap();
    let s0 = sys.trivialize(&c0);
    for plus in [true, false] {
        let red = if plus {
            ReducedConstrainedIntegrator::plus(sys, tight())
                .run(s0)
                .steps(1000)
                .collect()
        } else {
            ReducedConstrainedIntegrator::minus(sys, tight())
                .run(s0)
                .steps(1000)
                .collect()
        }
        .unwrap();
        for (a, b) in red.states.iter().zip(&unr.states) {
            assert_eq!(a.mu, s0.mu, "μ is copied bit for bit");
            let a = sys.untrivialize(a);
            assert!(
                (a.q - b.q).amax() < 1e-10 && (a.p - b.p).amax() < 1e-10,
                "{a:?} {b:?}"
            );
        }
        assert!(red.max_constraint_residual() <= 1e-13);
    }
}

/// The chain of `benches/scaling/chain.rs.in` (6 links on a cart) in its absolute angles.
#[reduced_lagrangian(shape(theta[6]), group(c), rule = midpoint)]
fn angle_chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {
    let mut vx = v.c;
    let mut vy = 0.0;
    let mut y = 0.0;
    let mut t = 0.5 * mc * v.c * v.c;
    let mut u = 0.0;
    for i in 0..6 {
        let (s, c) = (q.theta[i].sin(), q.theta[i].cos());
        vx += l * c * v.theta[i];
        vy += l * s * v.theta[i];
        y -= l * c;
        t += 0.5 * m * (vx * vx + vy * vy);
        u += m * gr * y;
    }
    t - u
}

/// The same chain in maximal coordinates: the cart at `c`, the links' end points `(x_i, y_i)`,
/// one length constraint per link; the cart's translation moves `c` and every `x_i`. The step's
/// saddle-point systems have 13 + 6 = 19 unknowns: the sparse backend.
#[reduced_lagrangian(coordinates(c, x[6], y[6]), translate(c, x), rule = midpoint,
    constraints = |q| {
        let mut phi = [0.0; 6];
        phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
        for i in 1..6 {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
fn maximal_chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    let mut u = 0.0;
    for i in 0..6 {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]);
        u += m * gr * q.y[i];
    }
    t - u
}

#[test]
fn the_chain_in_maximal_coordinates_follows_the_chain_in_angles() {
    let t_end = 1.0;
    let theta0: Vec<f64> = (0..6).map(|i| 0.3 * ((i + 1) as f64).sin()).collect();
    // The end points of the links at rest.
    let mut points = Vec::new();
    let (mut x, mut y) = (0.0, 0.0);
    for th in &theta0 {
        x += th.sin();
        y -= th.cos();
        points.push((x, y));
    }
    let maximal = |n: usize| {
        let sys = MaximalChain {
            h: t_end / n as f64,
            mc: 1.0,
            m: 1.0,
            l: 1.0,
            gr: 9.81,
        };
        let mut q = [0.0; 13];
        for (i, (x, y)) in points.iter().enumerate() {
            q[1 + i] = *x;
            q[7 + i] = *y;
        }
        let user = UnreducedState::new(q, [0.0; 13]);
        let c0 = MaximalChain::to_adapted_state(&user);
        let traj = ConstrainedIntegrator::new(sys, tight())
            .run(c0)
            .steps(n)
            .collect()
            .unwrap();
        assert!(
            traj.max_constraint_residual() <= 1e-12,
            "{:e}",
            traj.max_constraint_residual()
        );
        let end = MaximalChain::from_adapted_state(traj.last());
        (end.q[6], end.q[12])
    };
    let angles = |n: usize| {
        let sys = AngleChain {
            h: t_end / n as f64,
            mc: 1.0,
            m: 1.0,
            l: 1.0,
            gr: 9.81,
        };
        let mut q = [0.0; 7];
        q[..6].copy_from_slice(&theta0);
        let traj = UnreducedIntegrator::new(sys, tight())
            .run(UnreducedState::new(q, [0.0; 7]))
            .steps(n)
            .collect()
            .unwrap();
        let end = traj.last();
        let (mut x, mut y) = (end.q[6], 0.0);
        for i in 0..6 {
            x += end.q[i].sin();
            y -= end.q[i].cos();
        }
        (x, y)
    };
    // The two discretizations differ by O(h²): halving h quarters their distance.
    let d = |n: usize| {
        let (a, b) = (maximal(n), angles(n));
        (a.0 - b.0).hypot(a.1 - b.1)
    };
    let (d1, d2) = (d(100), d(200));
    assert!(d2 < 0.35 * d1 && d1 < 1e-2, "{d1:e} {d2:e}");
}

/// The vertical rolling disk (radius `r`): heading `phi` (shape), position `(x, y)` and rolling
/// angle `psi` (group: the Lagrangian and the constraints do not read them); rolling without
/// slipping, `ẋ = r cos φ ψ̇`, `ẏ = r sin φ ψ̇`.
#[reduced_lagrangian(shape(phi), group(x, y, psi), rule = midpoint,
    nonholonomic = |q, v| [v.x - r * q.phi.cos() * v.psi, v.y - r * q.phi.sin() * v.psi])]
fn rolling_disk(_q: Config, v: Velocity, m: f64, i: f64, j: f64, r: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * i * v.phi * v.phi + 0.5 * j * v.psi * v.psi
}

fn disk_start(sys: &RollingDisk, omega: f64, spin: f64) -> UnreducedState<4> {
    // (phi, x, y, psi) = (0, 0, 0, 0), rolling at spin Ω while turning at ω.
    let (vx, vy) = (sys.r * spin, 0.0);
    UnreducedState::new(
        [0.0; 4],
        [sys.i * omega, sys.m * vx, sys.m * vy, sys.j * spin],
    )
}

#[test]
fn the_rolling_disk_converges_at_order_two_to_its_closed_form() {
    let (omega, spin, t_end) = (0.7, 2.0, 3.0);
    let error = |n: usize| {
        let sys = RollingDisk {
            h: t_end / n as f64,
            m: 1.0,
            i: 0.25,
            j: 0.5,
            r: 0.5,
        };
        let traj = ConstrainedIntegrator::new(sys, tight())
            .run(disk_start(&sys, omega, spin))
            .steps(n)
            .collect()
            .unwrap();
        let end = traj.last();
        // φ = ω t, ψ = Ω t, x = (rΩ/ω) sin φ, y = (rΩ/ω)(1 − cos φ).
        let phi = omega * t_end;
        let radius = sys.r * spin / omega;
        let exact = [
            phi,
            radius * phi.sin(),
            radius * (1.0 - phi.cos()),
            spin * t_end,
        ];
        (0..4)
            .map(|i| (end.q[i] - exact[i]).abs())
            .fold(0.0, f64::max)
    };
    let (e1, e2) = (error(100), error(200));
    let order = (e1 / e2).log2();
    assert!((order - 2.0).abs() < 0.15, "order {order} ({e1:e}, {e2:e})");
}

#[test]
fn the_reduced_rolling_disk_follows_the_discrete_nonholonomic_momentum_equation() {
    let sys = RollingDisk {
        h: 0.01,
        m: 1.0,
        i: 0.25,
        j: 0.5,
        r: 0.5,
    };
    let c0 = disk_start(&sys, 0.7, 2.0);
    let unr = ConstrainedIntegrator::new(sys, tight())
        .run(c0)
        .steps(500)
        .collect()
        .unwrap();
    let red = ReducedConstrainedIntegrator::plus(sys, tight())
        .run(sys.trivialize(&c0))
        .steps(500)
        .collect()
        .unwrap();
    for (a, b) in red.states.iter().zip(&unr.states) {
        let a = sys.untrivialize(a);
        assert!(
            (a.q - b.q).amax() < 1e-10 && (a.p - b.p).amax() < 1e-10,
            "{a:?} {b:?}"
        );
    }
    // μ = (p_x, p_y, p_ψ) is not conserved (the symmetry is not horizontal): it turns with the
    // heading, by the group component of the constraint impulses.
    let (first, last) = (red.states[0].mu, red.last().mu);
    assert!((first - last).amax() > 1e-2);
}

#[path = "../examples/common/cartesian_dsp.rs"]
mod cartesian;

#[test]
fn the_cartesian_double_spherical_pendulum_agrees_with_the_atlas_run() {
    use dirac::paper::atlas::PAPER;
    use dirac::paper::DoubleSphericalPendulum;
    let t_end: f64 = 10.0;
    let distance = |h: f64| {
        let n = (t_end / h).round() as usize;
        let (sys, c0) = cartesian::cartesian_initial(h);
        let mut worst: f64 = 0.0;
        let summary = ConstrainedIntegrator::new(sys, NewtonOptions::default())
            .run(c0)
            .steps(n)
            .observe(|_, _, s, _| worst = worst.max(cartesian::sys_residual(&sys, s)))
            .stream()
            .unwrap();
        assert!(worst <= 1e-13, "|phi|/l^2 = {worst:e}");
        let paper = DoubleSphericalPendulum {
            h,
            ..DoubleSphericalPendulum::paper()
        };
        let atlas = paper
            .atlas(NewtonOptions::default())
            .run((PAPER, DoubleSphericalPendulum::paper_initial_state()))
            .steps(n)
            .observe(|_, _, _, _| {})
            .stream()
            .unwrap();
        let (chart, state) = atlas.last;
        let (_, r2) = paper.charts().bob_positions(chart, &state);
        let c = &summary.last.q;
        ((c[3] - r2[0]).powi(2) + (c[4] - r2[1]).powi(2) + (c[5] - r2[2]).powi(2)).sqrt()
    };
    // The two discretizations of the same motion approach each other as h².
    let (d1, d2) = (distance(0.02), distance(0.01));
    let ratio = d1 / d2;
    assert!(
        (3.5..4.5).contains(&ratio) && d1 < 1.0,
        "{d1:e} {d2:e} ratio {ratio}"
    );
}

/// The Cartesian pendulum with air drag: forces and constraints together.
#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
    force = |dq| -c * (v.x * dq.x + v.y * dq.y),
    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]
fn damped_pendulum(q: Config, v: Velocity, m: f64, l: f64, c: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
}

#[test]
fn forces_and_constraints_together() {
    let (m, l, c) = (1.0, 1.3, 0.4);
    let sys = DampedPendulum { h: 0.01, m, l, c };
    let traj = ConstrainedIntegrator::new(sys, tight())
        .run(pendulum_start(l, 1.0, 0.0))
        .steps(2000)
        .collect()
        .unwrap();
    assert!(traj.max_constraint_residual() <= 1e-13 * l * l);
    // The energy decays, step after step (midpoint drag dissipates), and the velocity stays
    // tangent to the circle.
    let energy =
        |s: &UnreducedState<2>| 0.5 * (s.p[0] * s.p[0] + s.p[1] * s.p[1]) / m + 9.81 * m * s.q[1];
    for pair in traj.states.windows(2) {
        assert!(energy(&pair[1]) <= energy(&pair[0]) + 1e-12);
        assert!((pair[1].q[0] * pair[1].p[0] + pair[1].q[1] * pair[1].p[1]).abs() < 1e-12);
    }
    // With c = 0 the same system is the conservative pendulum, bit for bit.
    let free = CartesianPendulum { h: 0.01, m, l };
    let a = ConstrainedIntegrator::new(DampedPendulum { c: 0.0, ..sys }, tight())
        .run(pendulum_start(l, 1.0, 0.0))
        .steps(200)
        .collect()
        .unwrap();
    let b = ConstrainedIntegrator::new(free, tight())
        .run(pendulum_start(l, 1.0, 0.0))
        .steps(200)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
}
