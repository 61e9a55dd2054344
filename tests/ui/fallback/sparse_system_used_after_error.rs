use dirac::prelude::*;

// A system above the dense size (17 shape coordinates: the sparse backend) whose body has one
// mistake (an unsupported method). The emitted type and its traits still exist with the
// signatures of the sparse backend, so `main` adds no follow-on errors: the only diagnostic is
// the unsupported method.
#[reduced_lagrangian(shape(x[17]), group(theta))]
fn chain(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let mut l = 0.5 * m / h * (q1.theta - q0.theta) * (q1.theta - q0.theta);
    for i in 0..17 {
        l += 0.5 * m / h * (q1.x[i] - q0.x[i]) * (q1.x[i] - q0.x[i]);
    }
    l - h * q0.x[0].floor()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sys = Chain { h: 0.1, m: 1.0 };
    assert_eq!(Chain::SHAPE_DIM, 17);
    let initial = ReducedState::new([0.0; 17], [0.0; 17], [1.0], [0.0]);
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(initial).steps(10).collect()?;
    let back = ReducedIntegrator::minus(sys, NewtonOptions::default()).run(initial).steps(10).collect()?;
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(sys.untrivialize(&initial)).steps(10).collect()?;
    let l = chain(ChainConfig::default(), ChainConfig::default(), sys.h, sys.m);
    println!(
        "{} {} {} {l} {}",
        traj.last().x[0],
        back.last().x[0],
        unreduced.states.len(),
        sys.lagrangian(&SVector::zeros(), &SVector::zeros())
    );
    Ok(())
}
