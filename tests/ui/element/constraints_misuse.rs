use dirac::prelude::*;

// A constraint that is not invariant under the declared translation.
#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        for i in 0..n {
            phi[i] = q.x[i] * q.x[i] - 1.0;
        }
        phi
    })]
fn anchored(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    l
}

// A constraint that escapes the coordinates for every size.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        for i in 0..n {
            phi[i] = q.x[i + n] - q.x[i];
        }
        phi
    })]
fn escaping(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    l
}

// A row that is not an affine index.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        for i in 0..n {
            phi[i * i] = q.x[i] - 1.0;
        }
        phi
    })]
fn squared_row(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    l
}

// Something other than a row assigned.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        let mut other = 0.0;
        for i in 0..n {
            other = q.x[i] - 1.0;
        }
        phi
    })]
fn not_a_row(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    l
}

// Without the constraint vector.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint, constraints = |q| [q.x[0]])]
fn array(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    l
}

// A discrete Lagrangian.
#[reduced_lagrangian(coordinates(x[n]),
    constraints = |q| {
        let mut phi = vec![0.0; n];
        for i in 0..n {
            phi[i] = q.x[i] - 1.0;
        }
        phi
    })]
fn discrete(q0: Config, q1: Config, h: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * (q1.x[i] - q0.x[i]) * (q1.x[i] - q0.x[i]) / h;
    }
    l
}

fn main() {}
