//! `rotation(R)`: the rotation group `SO(3)`, stored as `R` row by row, with the
//! left-trivialized (body-frame) Cayley chart `φ_R(ξ) = R cay(ξ)`, so `dφ_R(0) η = R η̂` and a
//! momentum in the chart is the body momentum `Π` (`⟨P, R η̂⟩ = Π·η`). A continuous Lagrangian
//! reads the body angular velocity `Ω = cay⁻¹(R0ᵀ R1)/h`.

use proc_macro2::TokenStream;
use quote::quote;
use syn::Ident;

use super::{Group, KindSpec, Paths, Rotated, Step};
use crate::front::layout::Reading;
use crate::ir::graph::{Graph, NodeId};

/// `rotation(R)`.
pub struct Rotation;

/// `cay(x) = I + α x̂ + (α/2)(x xᵀ − |x|² I)`, `α = 4/(4 + |x|²)`, row by row.
pub fn cayley(g: &mut Graph, x: [NodeId; 3]) -> [[NodeId; 3]; 3] {
    let one = g.constant(1.0);
    let squares: Vec<NodeId> = x.iter().map(|&v| g.mul(v, v)).collect();
    let s01 = g.add(squares[0], squares[1]);
    let n2 = g.add(s01, squares[2]);
    let four = g.constant(4.0);
    let den = g.add(four, n2);
    let alpha = g.div(four, den);
    let half = g.constant(0.5);
    let beta = g.mul(half, alpha);
    let bn2 = g.mul(beta, n2);
    let diag = g.sub(one, bn2);
    let hat = [
        [None, Some((2, -1.0)), Some((1, 1.0))],
        [Some((2, 1.0)), None, Some((0, -1.0))],
        [Some((1, -1.0)), Some((0, 1.0)), None],
    ];
    let mut m = [[one; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let xx = g.mul(x[i], x[j]);
            let outer = g.mul(beta, xx);
            let mut e = if i == j { g.add(diag, outer) } else { outer };
            if let Some((k, sign)) = hat[i][j] {
                let t = g.mul(alpha, x[k]);
                e = if sign > 0.0 { g.add(e, t) } else { g.sub(e, t) };
            }
            m[i][j] = e;
        }
    }
    m
}

/// `a b` of 3 × 3 matrices (`a` transposed first if `ta`).
pub fn product(
    g: &mut Graph,
    a: &[[NodeId; 3]; 3],
    ta: bool,
    b: &[[NodeId; 3]; 3],
) -> [[NodeId; 3]; 3] {
    let mut m = *a;
    for (i, row) in m.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            let terms: Vec<NodeId> = (0..3)
                .map(|k| {
                    let x = if ta { a[k][i] } else { a[i][k] };
                    g.mul(x, b[k][j])
                })
                .collect();
            let s01 = g.add(terms[0], terms[1]);
            *e = g.add(s01, terms[2]);
        }
    }
    m
}

/// `cay(x)` in plain arithmetic, row by row (for the sample configurations).
pub fn cayley_value(x: [f64; 3]) -> [[f64; 3]; 3] {
    let n2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    let alpha = 4.0 / (4.0 + n2);
    let hat = [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]];
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let diag = if i == j { 1.0 - 0.5 * alpha * n2 } else { 0.0 };
            m[i][j] = diag + alpha * hat[i][j] + 0.5 * alpha * x[i] * x[j];
        }
    }
    m
}

/// The stored matrix (`P` nodes, row by row) times `m` on the right.
pub(super) fn times_right(
    g: &mut Graph,
    base: &[NodeId],
    m: &[[NodeId; 3]; 3],
) -> [[NodeId; 3]; 3] {
    let one = g.constant(1.0);
    let mut f = [[one; 3]; 3];
    for (i, row) in f.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            let terms: Vec<NodeId> = (0..3).map(|k| g.mul(base[3 * i + k], m[k][j])).collect();
            let s01 = g.add(terms[0], terms[1]);
            *e = g.add(s01, terms[2]);
        }
    }
    f
}

/// `Ω = cay⁻¹(F)/h` of the relative rotation `F = R0ᵀ R1` (its 9 symbols), with the inverse
/// Cayley map `cay⁻¹(F) = 2 vee(F − Fᵀ)/(1 + tr F)` (exact: for `F = cay(ξ)`,
/// `vee(F − Fᵀ) = 2α ξ` and `1 + tr F = 4α` with `α = 4/(4 + |ξ|²)`; smooth wherever
/// `tr F > −1`, i.e. for every rotation by less than π).
pub(super) fn angular_velocity(g: &mut Graph, rel: &[NodeId], inv_h: NodeId) -> Vec<NodeId> {
    let f = |i: usize, j: usize| rel[3 * i + j];
    let one = g.constant(1.0);
    let t01 = g.add(f(0, 0), f(1, 1));
    let trace = g.add(t01, f(2, 2));
    let den = g.add(one, trace);
    let two = g.constant(2.0);
    [((2, 1), (1, 2)), ((0, 2), (2, 0)), ((1, 0), (0, 1))]
        .into_iter()
        .map(|(a, b)| {
            let d = g.sub(f(a.0, a.1), f(b.0, b.1));
            let num = g.mul(two, d);
            let xi = g.div(num, den);
            g.mul(xi, inv_h)
        })
        .collect()
}

/// The sample rotations `(R0, R1)` of a coordinate at point offset `at`.
pub(super) fn sample_rotations(t: f64, at: usize) -> [[[f64; 3]; 3]; 2] {
    let k = at as f64;
    [
        cayley_value([0.3 + t, -0.5 + 0.1 * k, 0.2 * t + 0.1]),
        cayley_value([-0.2, 0.4 + 0.3 * t, 0.6 - 0.05 * k]),
    ]
}

/// `g m` of a matrix stored row by row in `point`.
pub(super) fn rotate_rows(g: &[[f64; 3]; 3], point: &mut [f64]) {
    let m: [f64; 9] = std::array::from_fn(|i| point[i]);
    for i in 0..3 {
        for j in 0..3 {
            point[3 * i + j] = (0..3).map(|k| g[i][k] * m[3 * k + j]).sum();
        }
    }
}

/// `Matrix3::new(q[at], .., q[at + 8])`.
pub(super) fn matrix_at(paths: &Paths, at: usize) -> TokenStream {
    let na = &paths.na;
    let rows: Vec<usize> = (at..at + 9).collect();
    quote!(#na::Matrix3::new( #( q[#rows] ),* ))
}

/// Statements writing the matrix `m` row by row into `q` from `at`.
pub(super) fn write_rows(paths: &Paths, m: &TokenStream, at: usize) -> TokenStream {
    let rt = &paths.rt;
    quote! {
        for (i, v) in #rt::lie::rows(&#m).into_iter().enumerate() {
            q[#at + i] = v;
        }
    }
}

/// `R` row by row (9), the 3-entry chart `ξ` and body angular velocity `Ω`.
static SPEC: KindSpec = KindSpec::new(crate::symbol::ROTATION, 9, 3, 3).rotation_at(0);

impl Group for Rotation {
    fn spec(&self) -> &KindSpec {
        &SPEC
    }

    fn reads(&self, point: usize) -> Option<Reading> {
        Some(Reading::block(3, 3, point))
    }

    fn reads_velocity(&self, velocity: usize) -> Reading {
        Reading::block(3, 1, velocity)
    }

    fn chart(&self, g: &mut Graph, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId> {
        let m = cayley(g, [xi[0], xi[1], xi[2]]);
        times_right(g, base, &m).into_iter().flatten().collect()
    }

    fn velocity(&self, g: &mut Graph, step: &Step) -> Vec<NodeId> {
        angular_velocity(g, step.rel, step.inv_h)
    }

    fn rotated(&self) -> Rotated {
        Rotated::Every
    }

    fn sample(&self, t: f64, at: usize) -> [Vec<f64>; 2] {
        sample_rotations(t, at).map(|r| r.into_iter().flatten().collect())
    }

    fn rotate(&self, g: &[[f64; 3]; 3], point: &mut [f64]) {
        rotate_rows(g, point);
    }

    fn config_field(&self, paths: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        let na = &paths.na;
        (
            quote!(#na::Matrix3<f64>),
            format!("The rotation `{name}` (a rotation matrix)."),
        )
    }

    fn read_point(&self, paths: &Paths, _: &Ident, at: usize) -> TokenStream {
        matrix_at(paths, at)
    }

    fn write_point(&self, paths: &Paths, name: &Ident, at: usize) -> TokenStream {
        write_rows(paths, &quote!(self.#name), at)
    }

    fn momentum_field(&self, paths: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        let na = &paths.na;
        (
            quote!(#na::Vector3<f64>),
            format!(
                "The discrete body momentum `Π` of `{name}` (left-trivialized: `⟨P, {name} η̂⟩ = Π·η`): \
                 the discrete Legendre momentum a step reads, not `JΩ` (see `dirac::lie`; from an \
                 angular velocity: `LieLagrangian::discrete_legendre_state`)."
            ),
        )
    }

    fn read_chart(&self, paths: &Paths, _: &Ident, _at: usize, ch: usize) -> TokenStream {
        let na = &paths.na;
        let (c1, c2) = (ch + 1, ch + 2);
        quote!(#na::Vector3::new(p[#ch], p[#c1], p[#c2]))
    }

    fn write_chart(&self, _: &Paths, name: &Ident, _at: usize, ch: usize) -> TokenStream {
        let (c1, c2) = (ch + 1, ch + 2);
        quote! { p[#ch] = self.#name.x; p[#c1] = self.#name.y; p[#c2] = self.#name.z; }
    }

    fn velocity_field(&self, paths: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        let na = &paths.na;
        (
            quote!(#na::Vector3<f64>),
            format!("The body angular velocity `Ω` of `{name}` (`Ṙ = R Ω̂`)."),
        )
    }

    fn velocity_entries(&self, v: &TokenStream) -> Vec<TokenStream> {
        (0..3_usize).map(|k| quote!(#v[#k])).collect()
    }
}
