/// A chain of 20 links hanging from the origin in maximal coordinates: the end points
/// `(x[i], y[i])` of the links, one length constraint per link (20 constraints on 40
/// coordinates), gravity `gr`. Continuous, midpoint rule. Included as Rust by `tests/sizes.rs`
/// and compiled from its text by the JIT.
#[reduced_lagrangian(shape(x[20], y[20]), group(), rule = midpoint,
    constraints = |q| {
        let mut phi = [0.0; 20];
        phi[0] = q.x[0] * q.x[0] + q.y[0] * q.y[0] - l * l;
        for i in 1..20 {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
pub fn chain(q: Config, v: Velocity, m: f64, l: f64, gr: f64) -> f64 {
    let mut l_ = 0.0;
    for i in 0..20 {
        l_ += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    l_
}
