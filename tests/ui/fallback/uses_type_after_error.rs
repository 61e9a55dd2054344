use dirac::prelude::*;

// The Lagrangian is rejected (an absolute group coordinate), but the emitted type, its traits
// and the configuration struct still exist with the right signatures: the only diagnostic is
// the invariance error, none from `main`.
#[reduced_lagrangian(shape(x), group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dg * dg) - h * q0.theta.sin()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sys = Particle { h: 0.1, m: 1.0 };
    assert_eq!(Particle::CONFIG_DIM, 2);
    let l = particle(
        ParticleConfig::default(),
        ParticleConfig { x: 1.0, theta: 0.5 },
        sys.h,
        sys.m,
    );
    let initial = ReducedState::new([0.0], [1.0], [0.0], [l]);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let traj = integ.run(initial).steps(10).collect()?;
    println!(
        "{} {}",
        traj.last().x,
        sys.lagrangian(&SVector::zeros(), &SVector::zeros())
    );
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let _ = unreduced.system();
    Ok(())
}
