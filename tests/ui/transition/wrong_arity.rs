// The body returns two coordinates where the new chart has three.
use dirac::prelude::*;

#[chart_transition(from(shape(a, b), group(g)), to(shape(c, d), group(h)))]
fn swap(q: Config) -> (f64, f64) {
    (q.b, q.a)
}

fn main() {}
