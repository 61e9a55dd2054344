/// A cart `c` carrying 29 pendulum-like oscillators `x[i]` (positions relative to the cart,
/// restoring force `k sin x`, neighbours coupled by springs `κ`): 30 coordinates, the cart's
/// translation a symmetry whose momentum (the total momentum) is conserved. Continuous, midpoint
/// rule. Included as Rust by `tests/sizes.rs` and compiled from its text by the JIT.
#[reduced_lagrangian(shape(x[29]), group(c), rule = midpoint)]
pub fn cart(q: Config, v: Velocity, mc: f64, m: f64, k: f64, kappa: f64) -> f64 {
    let mut l = 0.5 * mc * v.c * v.c;
    for i in 0..29 {
        l += 0.5 * m * (v.c + v.x[i]) * (v.c + v.x[i]) - k * (1.0 - q.x[i].cos());
    }
    for i in 0..28 {
        l -= 0.5 * kappa * (q.x[i + 1] - q.x[i]) * (q.x[i + 1] - q.x[i]);
    }
    l
}
