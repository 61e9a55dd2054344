use dirac::prelude::*;

#[reduced_lagrangian(coordinates(x[2], y[2]), translate(x, y), translate(y), rule = midpoint)]
fn pair(q: Config, v: Velocity, m: f64) -> f64 {
    let (dx, dy) = (q.x[1] - q.x[0], q.y[1] - q.y[0]);
    0.5 * m * (v.x[0] * v.x[0] + v.x[1] * v.x[1] + v.y[0] * v.y[0] + v.y[1] * v.y[1])
        - (dx * dx + dy * dy)
}

fn main() {}
