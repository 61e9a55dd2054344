use dirac::prelude::*;

// A continuous Lagrangian `L(q, v)` with a quadrature rule whose body has one mistake (a macro
// call). The emitted type still implements the system traits and `ContinuousLagrangian`, so the
// Legendre map, the energy and the integrators in `main` add no follow-on errors: the only
// diagnostic is the macro call.
#[reduced_lagrangian(shape(x), group(theta), rule = midpoint)]
fn rotor(q: Config, v: Velocity, m: f64, k: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.theta * v.theta) - 0.5 * k * q.x * q.x + dbg!(0.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sys = Rotor { h: 0.1, m: 1.0, k: 2.0 };
    let (q, v) = (SVector::from([1.0, 0.0]), SVector::from([0.0, 1.0]));
    let p = sys.legendre(&q, &v);
    let (_, jacobian) = sys.legendre_jacobian(&q, &v);
    let e = sys.energy(&q, &v);
    let initial = sys.reduced_state::<1, 1>(q, v)?;
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(initial).steps(10).collect()?;
    let energies = reduced_continuous_energies(&sys, &traj)?;
    println!("{p} {jacobian} {e} {} {}", energies.nodes[0], Rotor::RULE);
    Ok(())
}
