use dirac::prelude::*;

// A chart transition whose body has one mistake (an unsupported method). The emitted type
// still implements `ChartTransition` with the right dimensions, so the map, its Jacobian and
// the constants used in `main` add no follow-on errors: the only diagnostic is the method.
#[chart_transition(from(shape(x, y), group(theta)), to(shape(u, v), group(phi)))]
fn shear(q: Config) -> (f64, f64, f64) {
    (q.x + 0.5 * q.y, q.y.floor(), q.theta + q.x)
}

fn main() {
    let t = Shear;
    let q = SVector::<f64, 3>::from([1.0, 2.0, 0.5]);
    let moved = t.map(&q);
    let (_, jacobian) = t.map_jacobian(&q);
    let state = UnreducedState::new([1.0, 2.0, 0.5], [0.0, 0.0, 1.0]);
    let lifted = ChartTransition::<2, 1, 3>::lift(&t, &state);
    println!("{moved} {jacobian} {:?} {:?} {:?}", lifted.is_some(), Shear::FROM, Shear::TO);
}
