// The new shape coordinate depends on the old group coordinate: the symmetry would not act by
// translation in the new chart.
use dirac::prelude::*;

#[chart_transition(from(shape(r), group(theta)), to(shape(x), group(phi)))]
fn polar_to_cartesian(q: Config) -> (f64, f64) {
    (q.r * q.theta.cos(), q.theta)
}

fn main() {}
