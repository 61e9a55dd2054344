//! The examples of the attributes' own documentation (`dirac-macros/docs/*.md`, shown on
//! `reduced_lagrangian` and `chart_transition`), compiled and run: the proc-macro crate cannot
//! run them as doctests, since they need the `dirac` crate.

use dirac::prelude::*;

/// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
#[reduced_lagrangian(shape(x, y, z), group(theta))]
fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
    let s = a_dot_dq + (q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
}

/// A particle on a line coupled to a free rotor; midpoint rule.
#[reduced_lagrangian(shape(x), group(theta), rule = midpoint)]
fn rotor(q: Config, v: Velocity, m: f64, k: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.theta * v.theta) - 0.5 * k * q.x * q.x
}

/// A shear of the shape coordinates, and a group coordinate shifted by a function of them.
#[chart_transition(from(shape(x, y), group(theta)), to(shape(u, v), group(phi)))]
fn shear(q: Config) -> (f64, f64, f64) {
    (q.x + 0.5 * q.y, q.y, q.theta + q.x * q.y)
}

#[test]
fn the_discrete_example_runs() -> Result<(), Box<dyn std::error::Error>> {
    let sys = ChargedParticle {
        h: 0.2,
        m: 1.0,
        b0: 1.0,
    };
    let initial = ReducedState::new([0.0; 3], [1.0, 0.0, 1.0], [1.0], [0.0]);
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(100)
        .collect()?;
    assert_eq!(traj.step_count(), 100);
    // The emitted dimensions name the state's sizes.
    let _: ReducedState<{ ChargedParticle::SHAPE_DIM }, { ChargedParticle::GROUP_DIM }> =
        *traj.last();
    assert_eq!(ChargedParticle::CONFIG_DIM, 4);
    Ok(())
}

#[test]
fn the_continuous_example_runs() -> Result<(), Box<dyn std::error::Error>> {
    let sys = Rotor {
        h: 0.1,
        m: 1.0,
        k: 2.0,
    };
    let (q, v) = (SVector::from([1.0, 0.0]), SVector::from([0.0, 1.0]));
    // E = ½ m |v|² + ½ k x² = 0.5 + 1.0, exactly in floating point.
    assert_eq!(sys.energy(&q, &v), 1.5);
    let initial = sys.reduced_state::<1, 1>(q, v)?;
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(10)
        .collect()?;
    assert_eq!(traj.last().mu, initial.mu);
    Ok(())
}

#[test]
fn the_transition_example_runs() {
    let q = SVector::<f64, 3>::from([1.0, 2.0, 0.5]);
    let moved = Shear.map(&q);
    assert_eq!(moved, SVector::from([2.0, 2.0, 2.5]));
    let (value, jacobian) = Shear.map_jacobian(&q);
    assert_eq!(value, moved);
    // ∂phi/∂x = y = 2, ∂phi/∂y = x = 1, ∂phi/∂theta = 1.
    assert_eq!(jacobian.row(2).transpose(), SVector::from([2.0, 1.0, 1.0]));
    assert_eq!(Shear::FROM, ["x", "y", "theta"]);
}
