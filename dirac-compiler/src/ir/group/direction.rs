//! `direction(n)`: the sphere `S²`, stored as a frame `[e1 e2 n]` row by row (the direction its
//! third column), with the chart `φ(a, b)` the sphere's retraction `n' ∝ n + a e1 + b e2` and
//! the frame carried along, so `dφ(0)(a, b) = a e1 + b e2` and a momentum in the chart is the
//! momentum's components on `(e1, e2)`. A continuous Lagrangian reads the chord velocity
//! `(n1 − n0)/h`.

use proc_macro2::TokenStream;
use quote::quote;
use syn::Ident;

use super::rotation::{matrix_at, times_right, write_rows, Rotation};
use super::{Group, KindSpec, Paths, Rotated, Step};
use crate::front::layout::Reading;
use crate::ir::graph::{Fun, Graph, NodeId};

/// `direction(n)`.
pub struct Direction;

/// A direction's next frame from the carried one `f`: the point
/// `n' = (n + a e1 + b e2)/|n + a e1 + b e2|` (the sphere's retraction, so `|n'| = 1` to
/// round-off at every step whatever the frame's own round-off), `e1'` the carried first column
/// made orthogonal to `n'` and normalized, `e2' = n' × e1'`. To first order in round-off this is
/// `f` itself; it keeps the frame orthonormal over any number of steps.
fn orthonormal(
    g: &mut Graph,
    f: [[NodeId; 3]; 3],
    n: [NodeId; 3],
    ab: [NodeId; 2],
    e1: [NodeId; 3],
    e2: [NodeId; 3],
) -> [[NodeId; 3]; 3] {
    let unit = |g: &mut Graph, v: [NodeId; 3]| {
        let sq: Vec<NodeId> = v.iter().map(|&x| g.mul(x, x)).collect();
        let s01 = g.add(sq[0], sq[1]);
        let s = g.add(s01, sq[2]);
        let norm = g.fun(Fun::Sqrt, s);
        v.map(|x| g.div(x, norm))
    };
    let w: [NodeId; 3] = std::array::from_fn(|i| {
        let t1 = g.mul(ab[0], e1[i]);
        let t2 = g.mul(ab[1], e2[i]);
        let s = g.add(n[i], t1);
        g.add(s, t2)
    });
    let n1 = unit(g, w);
    let t = [f[0][0], f[1][0], f[2][0]];
    let tn: Vec<NodeId> = (0..3).map(|i| g.mul(t[i], n1[i])).collect();
    let s01 = g.add(tn[0], tn[1]);
    let dot = g.add(s01, tn[2]);
    let perp: [NodeId; 3] = std::array::from_fn(|i| {
        let d = g.mul(dot, n1[i]);
        g.sub(t[i], d)
    });
    let u1 = unit(g, perp);
    let cross = |g: &mut Graph, i: usize, j: usize| {
        let x = g.mul(n1[i], u1[j]);
        let y = g.mul(n1[j], u1[i]);
        g.sub(x, y)
    };
    let u2 = [cross(g, 1, 2), cross(g, 2, 0), cross(g, 0, 1)];
    std::array::from_fn(|i| [u1[i], u2[i], n1[i]])
}

/// The column `j` of a frame stored row by row.
fn column(point: &[NodeId], j: usize) -> [NodeId; 3] {
    [point[j], point[3 + j], point[6 + j]]
}

/// 9 point entries (the frame), a 2-entry chart, the 3 components of `ṅ`; a force on `ṅ` is a
/// vector in space.
static SPEC: KindSpec = KindSpec::new(crate::symbol::DIRECTION, 9, 2, 3).spatial_at(&[0]);

impl Group for Direction {
    fn spec(&self) -> &KindSpec {
        &SPEC
    }

    fn reads(&self, point: usize) -> Option<Reading> {
        Some(Reading::Entries(
            3,
            1,
            vec![point + 2, point + 5, point + 8],
        ))
    }

    fn reads_velocity(&self, velocity: usize) -> Reading {
        Reading::block(3, 1, velocity)
    }

    /// The frame times the shortest-arc rotation taking `e3` to `u = (a, b, 1)/√(1 + a² + b²)`,
    /// made orthonormal ([`orthonormal`]).
    fn chart(&self, g: &mut Graph, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId> {
        let one = g.constant(1.0);
        let (a, bb) = (xi[0], xi[1]);
        let (a2, b2) = (g.mul(a, a), g.mul(bb, bb));
        let s1 = g.add(one, a2);
        let s2 = g.add(s1, b2);
        let r = g.fun(Fun::Sqrt, s2);
        let s = g.div(one, r);
        let (ux, uy, uz) = (g.mul(a, s), g.mul(bb, s), s);
        let d = g.add(one, uz);
        let uxux = g.mul(ux, ux);
        let uyuy = g.mul(uy, uy);
        let uxuy = g.mul(ux, uy);
        let (t00, t11, t01) = (g.div(uxux, d), g.div(uyuy, d), g.div(uxuy, d));
        let m00 = g.sub(one, t00);
        let m11 = g.sub(one, t11);
        let m01 = g.neg(t01);
        let (nux, nuy) = (g.neg(ux), g.neg(uy));
        let m = [[m00, m01, ux], [m01, m11, uy], [nux, nuy, uz]];
        let f = times_right(g, base, &m);
        let f = orthonormal(
            g,
            f,
            column(base, 2),
            [xi[0], xi[1]],
            column(base, 0),
            column(base, 1),
        );
        f.into_iter().flatten().collect()
    }

    /// The chord `(n1 − n0)/h`.
    fn velocity(&self, g: &mut Graph, step: &Step) -> Vec<NodeId> {
        step.chord(g, [2, 5, 8])
    }

    /// `(F·e1, F·e2)` with the frame of `point`.
    fn covector(&self, g: &mut Graph, f: &[NodeId], point: &[NodeId]) -> Vec<NodeId> {
        (0..2)
            .map(|j| {
                let e: Vec<NodeId> = column(point, j).to_vec();
                let terms: Vec<NodeId> = (0..3).map(|k| g.mul(f[k], e[k])).collect();
                let s01 = g.add(terms[0], terms[1]);
                g.add(s01, terms[2])
            })
            .collect()
    }

    fn rotated(&self) -> Rotated {
        Rotated::AboutAxis(|id| {
            format!(
                "every rotation of a direction leaves only the rotations about it; \
                 `symmetry(..)` without an axis acts on one rotation coordinate (`R ↦ g R`), \
                 and `{id}` is a direction: declare the rotations about a fixed axis, \
                 `symmetry({id}, axis = z)`"
            )
        })
    }

    /// The frame is a rotation matrix: sampled as one.
    fn sample(&self, t: f64, at: usize) -> [Vec<f64>; 2] {
        Rotation.sample(t, at)
    }

    /// `[e1 e2 n] ↦ g [e1 e2 n]`, as a rotation.
    fn rotate(&self, g: &[[f64; 3]; 3], point: &mut [f64]) {
        Rotation.rotate(g, point);
    }

    fn config_field(&self, paths: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        let na = &paths.na;
        (
            quote!(#na::Vector3<f64>),
            format!("The direction `{name}` (a unit vector)."),
        )
    }

    fn read_point(&self, paths: &Paths, _: &Ident, at: usize) -> TokenStream {
        let na = &paths.na;
        let (n0, n1, n2) = (at + 2, at + 5, at + 8);
        quote!(#na::Vector3::new(q[#n0], q[#n1], q[#n2]))
    }

    fn write_point(&self, paths: &Paths, name: &Ident, at: usize) -> TokenStream {
        let rt = &paths.rt;
        write_rows(paths, &quote!(#rt::lie::direction_frame(&self.#name)), at)
    }

    fn momentum_field(&self, paths: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        let na = &paths.na;
        (
            quote!(#na::Vector3<f64>),
            format!(
                "The momentum of `{name}`: a vector tangent to the sphere at `{name}` (its component along `{name}` is dropped)."
            ),
        )
    }

    fn read_chart(&self, paths: &Paths, _: &Ident, at: usize, ch: usize) -> TokenStream {
        let (frame, c1) = (matrix_at(paths, at), ch + 1);
        quote! {
            {
                let f = #frame;
                f.column(0) * p[#ch] + f.column(1) * p[#c1]
            }
        }
    }

    fn write_chart(&self, paths: &Paths, name: &Ident, at: usize, ch: usize) -> TokenStream {
        let (frame, c1) = (matrix_at(paths, at), ch + 1);
        quote! {
            let f = #frame;
            p[#ch] = f.column(0).dot(&self.#name);
            p[#c1] = f.column(1).dot(&self.#name);
        }
    }

    fn velocity_field(&self, paths: &Paths, name: &Ident, _: &Ident) -> (TokenStream, String) {
        let na = &paths.na;
        (
            quote!(#na::Vector3<f64>),
            format!("The velocity of `{name}`."),
        )
    }

    fn velocity_entries(&self, v: &TokenStream) -> Vec<TokenStream> {
        (0..3_usize).map(|k| quote!(#v[#k])).collect()
    }
}
