use dirac::prelude::*;

// Two group coordinates; `a` enters through its difference, `b` also through `q1.b` alone.
// The error names `b` and only `b`.
#[reduced_lagrangian(shape(x), group(a, b))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, da, db) = (q1.x - q0.x, q1.a - q0.a, q1.b - q0.b);
    0.5 * m / h * (dx * dx + da * da + db * db) + h * (q1.b * 0.5).sin()
}

fn main() {}
