//! Coordinates on the real line: `shape(x)` ([`Scalar`]) and `group(x)` ([`Translation`]).

use super::{CoordinateKind, Group};

/// An ordinary real coordinate: `shape(x)`.
///
/// * point: `x` (1 entry); chart: `ξ` with `φ_x(ξ) = x + ξ`, inverted by a sign;
/// * momentum: its momentum `p`;
/// * spatial momentum: none (a scalar is not moved by rigid motions of space);
/// * value: the number (shape `()`), momentum value `p`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Scalar;

impl Group for Scalar {
    fn name(&self) -> &'static str {
        "shape"
    }

    fn point_len(&self) -> usize {
        1
    }

    fn chart_len(&self) -> usize {
        1
    }

    fn point_suffixes(&self) -> &'static [&'static str] {
        &[""]
    }

    fn chart_suffixes(&self) -> &'static [&'static str] {
        &[""]
    }

    fn retract(&self, q: &[f64], z: &[f64], out: &mut [f64]) {
        out[0] = q[0] + z[0];
    }

    fn chart_inverse(&self, base: &[f64], point: &[f64], z: &mut [f64]) {
        z[0] = point[0] - base[0];
    }

    /// `r` itself: a scalar's momentum map (under translations of it) is its momentum.
    fn carry_residual(&self, _q: &[f64], _q_next: &[f64], r: &[f64], p_next: &mut [f64]) {
        p_next[0] += r[0];
    }

    fn value_shape(&self) -> &'static [usize] {
        &[]
    }

    fn momentum_shape(&self) -> &'static [usize] {
        &[]
    }

    fn point_from_value(&self, _name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String> {
        q[0] = value[0];
        Ok(())
    }

    fn value(&self, q: &[f64], out: &mut Vec<f64>) {
        out.push(q[0]);
    }

    fn momentum_from_value(&self, _q: &[f64], value: &[f64], p: &mut [f64]) {
        p[0] = value[0];
    }

    fn momentum_value(&self, _q: &[f64], p: &[f64], out: &mut Vec<f64>) {
        out.push(p[0]);
    }
}

impl CoordinateKind {
    /// An ordinary real coordinate (`shape(x)`): one entry of the point, one of the chart.
    pub const SCALAR: CoordinateKind = CoordinateKind(&Scalar);
    /// [`Self::SCALAR`] by its keyword, the name the code `#[reduced_lagrangian]` emits.
    pub const SHAPE: CoordinateKind = CoordinateKind::SCALAR;
    /// A real coordinate whose translations are a symmetry (`group(x)`, checked at compile
    /// time): its momentum `μ` obeys the discrete Noether balance explicitly,
    /// `μ_{k+1} = μ_k + f_d^− + f_d^+` — copied bit for bit without forces.
    pub const GROUP: CoordinateKind = CoordinateKind(&Translation);
}

/// A real coordinate whose translations are a symmetry (`group(x)`, checked at compile time):
/// a [`Scalar`] in everything but its momentum update, which is the discrete Noether balance
/// `μ_{k+1} = μ_k + f_d^− + f_d^+` emitted explicitly — copied bit for bit without forces, so
/// Newton's residual is not carried into it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Translation;

impl Group for Translation {
    fn name(&self) -> &'static str {
        "group"
    }

    fn point_len(&self) -> usize {
        1
    }

    fn chart_len(&self) -> usize {
        1
    }

    fn point_suffixes(&self) -> &'static [&'static str] {
        Scalar.point_suffixes()
    }

    fn chart_suffixes(&self) -> &'static [&'static str] {
        Scalar.chart_suffixes()
    }

    fn retract(&self, q: &[f64], z: &[f64], out: &mut [f64]) {
        Scalar.retract(q, z, out);
    }

    fn chart_inverse(&self, base: &[f64], point: &[f64], z: &mut [f64]) {
        Scalar.chart_inverse(base, point, z);
    }

    /// Nothing: its momentum is the explicit Noether balance, exact as it is.
    fn carry_residual(&self, _q: &[f64], _q_next: &[f64], _r: &[f64], _p_next: &mut [f64]) {}

    fn value_shape(&self) -> &'static [usize] {
        Scalar.value_shape()
    }

    fn momentum_shape(&self) -> &'static [usize] {
        Scalar.momentum_shape()
    }

    fn point_from_value(&self, name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String> {
        Scalar.point_from_value(name, value, q)
    }

    fn value(&self, q: &[f64], out: &mut Vec<f64>) {
        Scalar.value(q, out);
    }

    fn momentum_from_value(&self, q: &[f64], value: &[f64], p: &mut [f64]) {
        Scalar.momentum_from_value(q, value, p);
    }

    fn momentum_value(&self, q: &[f64], p: &[f64], out: &mut Vec<f64>) {
        Scalar.momentum_value(q, p, out);
    }
}
