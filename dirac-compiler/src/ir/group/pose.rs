//! `pose(X)`: the group of rigid motions `SE(3) = SO(3) ⋉ ℝ³`, stored as the rotation `R` row by
//! row (body → space) then the position `x`, with the chart
//!
//! ```text
//! φ_(R, x)(ξ, v) = (R cay(ξ), x + v)
//! ```
//!
//! (the rotation left-trivialized, in the body frame as `rotation(R)`; the translation in
//! space), so `dφ(0)(η, ζ) = (R η̂, ζ)`, `φ` is centred and inverse by sign
//! (`φ_{φ_q(z)}(−z) = q`: `cay(−ξ) = cay(ξ)ᵀ`), and a momentum in the chart is `(Π, p)`: the
//! body angular momentum and the spatial linear momentum. The body reads `q0.X.rotation` (a
//! 3 × 3 matrix) and `q0.X.translation` (a 3-vector); a continuous Lagrangian reads
//! `v.X.angular`, the body angular velocity `Ω = cay⁻¹(R0ᵀ R1)/h`, and `v.X.linear`, the
//! spatial velocity `(x1 − x0)/h`; a force reads `dq.X.angular` (`η`, `δR = R η̂`) and
//! `dq.X.linear` (`δx`).

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::Ident;

use super::rotation::{
    angular_velocity, cayley, matrix_at, rotate_rows, sample_rotations, times_right, write_rows,
};
use super::{Group, KindSpec, Paths, Rotated, Step};
use crate::front::layout::Reading;
use crate::ir::graph::{Graph, NodeId};

/// `pose(X)`.
pub struct Pose;

/// The emitted types: `<Name>Pose` (a configuration's pose), `<Name>PoseMomentum` and
/// `<Name>PoseVelocity`.
fn types(ty: &Ident) -> [Ident; 3] {
    [
        format_ident!("{}Pose", ty),
        format_ident!("{}PoseMomentum", ty),
        format_ident!("{}PoseVelocity", ty),
    ]
}

/// `R` (9) then `x` (3), the chart `(ξ, v)` and the velocity `(Ω, ẋ)` (6 each); `R` at 0, the
/// spatial velocity `ẋ` at 3.
static SPEC: KindSpec = KindSpec::new(crate::symbol::POSE, 12, 6, 6)
    .rotation_at(0)
    .spatial_at(&[3]);

impl Group for Pose {
    fn spec(&self) -> &KindSpec {
        &SPEC
    }

    fn reads(&self, point: usize) -> Option<Reading> {
        Some(Reading::Parts(vec![
            ("rotation", Reading::block(3, 3, point)),
            ("translation", Reading::block(3, 1, point + 9)),
        ]))
    }

    fn reads_velocity(&self, velocity: usize) -> Reading {
        Reading::Parts(vec![
            ("angular", Reading::block(3, 1, velocity)),
            ("linear", Reading::block(3, 1, velocity + 3)),
        ])
    }

    fn chart(&self, g: &mut Graph, base: &[NodeId], xi: &[NodeId]) -> Vec<NodeId> {
        let m = cayley(g, [xi[0], xi[1], xi[2]]);
        let mut out: Vec<NodeId> = times_right(g, base, &m).into_iter().flatten().collect();
        out.extend((0..3).map(|i| g.add(base[9 + i], xi[3 + i])));
        out
    }

    /// `(Ω, ẋ)`: the rotation's body angular velocity, the position's chord.
    fn velocity(&self, g: &mut Graph, step: &Step) -> Vec<NodeId> {
        let mut v = angular_velocity(g, step.rel, step.inv_h);
        v.extend(step.chord(g, 9..12));
        v
    }

    fn rotated(&self) -> Rotated {
        Rotated::Rigid(|id| {
            format!(
                "`{id}` is a pose, reduced by every rigid motion `(A, a)·({id}) = (A R, A x + a)`: declare \
                 `symmetry({id})` alone, without an axis"
            )
        })
    }

    fn sample(&self, t: f64, at: usize) -> [Vec<f64>; 2] {
        let k = at as f64;
        let [r0, r1] = sample_rotations(t, at);
        let mut q0: Vec<f64> = r0.into_iter().flatten().collect();
        let mut q1: Vec<f64> = r1.into_iter().flatten().collect();
        q0.extend([0.4 + 0.1 * t, -0.3 + 0.05 * k, 0.8 - 0.2 * t]);
        q1.extend([-0.6 + 0.2 * t, 0.1 - 0.03 * k, 0.5 + 0.1 * t]);
        [q0, q1]
    }

    /// `(R, x) ↦ (g R, g x)`.
    fn rotate(&self, g: &[[f64; 3]; 3], point: &mut [f64]) {
        rotate_rows(g, &mut point[..9]);
        let x: [f64; 3] = std::array::from_fn(|i| point[9 + i]);
        for i in 0..3 {
            point[9 + i] = (0..3).map(|k| g[i][k] * x[k]).sum();
        }
    }

    fn config_field(&self, _: &Paths, name: &Ident, ty: &Ident) -> (TokenStream, String) {
        let pose = &types(ty)[0];
        (
            quote!(#pose),
            format!("The pose `{name}`: its rotation (body → space) and its position."),
        )
    }

    fn read_point(&self, paths: &Paths, ty: &Ident, at: usize) -> TokenStream {
        let na = &paths.na;
        let pose = &types(ty)[0];
        let rotation = matrix_at(paths, at);
        let (x, y, z) = (at + 9, at + 10, at + 11);
        quote! {
            #pose {
                rotation: #rotation,
                translation: #na::Vector3::new(q[#x], q[#y], q[#z]),
            }
        }
    }

    fn write_point(&self, paths: &Paths, name: &Ident, at: usize) -> TokenStream {
        let rotation = write_rows(paths, &quote!(self.#name.rotation), at);
        let x = at + 9;
        quote! {
            #rotation
            for (i, v) in self.#name.translation.iter().enumerate() {
                q[#x + i] = *v;
            }
        }
    }

    fn momentum_field(&self, _: &Paths, name: &Ident, ty: &Ident) -> (TokenStream, String) {
        let momentum = &types(ty)[1];
        (
            quote!(#momentum),
            format!(
                "The momentum of `{name}`: the discrete body angular momentum `Π` and the spatial linear \
                 momentum `p` (`⟨(Π, p), (η, δx)⟩ = Π·η + p·δx` for `δR = R η̂`)."
            ),
        )
    }

    fn read_chart(&self, paths: &Paths, ty: &Ident, _at: usize, ch: usize) -> TokenStream {
        let na = &paths.na;
        let momentum = &types(ty)[1];
        let a: Vec<usize> = (ch..ch + 3).collect();
        let l: Vec<usize> = (ch + 3..ch + 6).collect();
        quote! {
            #momentum {
                angular: #na::Vector3::new( #( p[#a] ),* ),
                linear: #na::Vector3::new( #( p[#l] ),* ),
            }
        }
    }

    fn write_chart(&self, _: &Paths, name: &Ident, _at: usize, ch: usize) -> TokenStream {
        let l = ch + 3;
        quote! {
            for i in 0..3 {
                p[#ch + i] = self.#name.angular[i];
                p[#l + i] = self.#name.linear[i];
            }
        }
    }

    fn velocity_field(&self, _: &Paths, name: &Ident, ty: &Ident) -> (TokenStream, String) {
        let velocity = &types(ty)[2];
        (
            quote!(#velocity),
            format!(
                "The velocity of `{name}`: its body angular velocity `Ω` (`Ṙ = R Ω̂`) and its spatial \
                 velocity `ẋ`."
            ),
        )
    }

    fn velocity_entries(&self, v: &TokenStream) -> Vec<TokenStream> {
        let angular = (0..3_usize).map(|k| quote!(#v.angular[#k]));
        angular
            .chain((0..3_usize).map(|k| quote!(#v.linear[#k])))
            .collect()
    }

    fn items(
        &self,
        paths: &Paths,
        ty: &Ident,
        vis: &syn::Visibility,
        continuous: bool,
    ) -> TokenStream {
        let na = &paths.na;
        let [pose, momentum, velocity] = types(ty);
        let doc_pose =
            format!("A pose of [`{ty}`]: a rigid motion, stored as `rotation` then `translation`.");
        let doc_momentum = format!(
            "The momentum of a pose of [`{ty}`], in its chart `(ξ, v) ↦ (R cay(ξ), x + v)`."
        );
        let velocity_item = continuous.then(|| {
            let doc = format!(
                "The velocity of a pose of [`{ty}`], as its continuous Lagrangian reads it."
            );
            quote! {
                #[doc = #doc]
                #[derive(Clone, Copy, Debug, Default, PartialEq)]
                #vis struct #velocity {
                    /// The body angular velocity `Ω` (`Ṙ = R Ω̂`).
                    pub angular: #na::Vector3<f64>,
                    /// The spatial velocity `ẋ`.
                    pub linear: #na::Vector3<f64>,
                }
            }
        });
        quote! {
            #[doc = #doc_pose]
            #[derive(Clone, Copy, Debug, PartialEq)]
            #vis struct #pose {
                /// The rotation `R` (body → space).
                pub rotation: #na::Matrix3<f64>,
                /// The position `x`.
                pub translation: #na::Vector3<f64>,
            }

            #[doc = #doc_momentum]
            #[derive(Clone, Copy, Debug, PartialEq)]
            #vis struct #momentum {
                /// The discrete body angular momentum `Π` (left-trivialized, as a rotation's).
                pub angular: #na::Vector3<f64>,
                /// The spatial linear momentum `p`.
                pub linear: #na::Vector3<f64>,
            }

            #velocity_item
        }
    }
}
