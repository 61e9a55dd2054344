/// A cart `c` carrying 11 damped oscillators `x[i]` (positions relative to the cart), pushed by
/// a constant force `f` and damped by `b`: the cart's translation is a symmetry of `L`, and
/// the forces change its momentum by their impulse. Continuous, midpoint rule. Included as Rust
/// by `tests/sizes.rs` and compiled from its text by the JIT.
#[reduced_lagrangian(shape(x[11]), group(c), rule = midpoint,
    force = |dq| {
        let mut w = f * dq.c;
        for i in 0..11 {
            w -= b * v.x[i] * dq.x[i];
        }
        w
    })]
pub fn forced(q: Config, v: Velocity, m: f64, k: f64, b: f64, f: f64) -> f64 {
    let mut l = 0.5 * v.c * v.c;
    for i in 0..11 {
        l += 0.5 * m * (v.c + v.x[i]) * (v.c + v.x[i]) - k * (1.0 - q.x[i].cos());
    }
    l
}
