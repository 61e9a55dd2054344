//! The double spherical pendulum on an atlas of three charts (§6 of the paper), so that it runs
//! from the paper's own initial state for as long as asked.
//!
//! The paper's chart ([`DoubleSphericalPendulum`], chart [`PAPER`]) is singular when either link
//! is vertical (Remark 7.1): there the azimuth of that link is undefined. Two more charts cover
//! those configurations. In each, the group coordinate is the azimuth of one link, and the other
//! link's direction is measured in the first link's rotating frame by spherical angles whose pole
//! is a *horizontal* axis of that frame, so that they are regular when the other link passes the
//! vertical:
//!
//! * [`DspBob1Frame`] (chart [`BOB1_FRAME`]): group `θ1`, the azimuth of link 1; shape
//!   `(φ1, a2, b2)` with, in the frame `(e1', e2', ẑ)` rotated by `θ1`,
//!   `u2' = (sin a2 cos b2, cos a2, sin a2 sin b2)` (pole `e2'`). Singular where link 1 is
//!   vertical (`sin φ1 = 0`) or link 2 is along `±e2'` (`sin a2 = 0`).
//! * [`DspBob2Frame`] (chart [`BOB2_FRAME`]): the same with the links exchanged: group `θ2`, shape
//!   `(φ2, a1, b1)`, `u1'' = (sin a1 cos b1, cos a1, sin a1 sin b1)` in the frame rotated by `θ2`.
//!
//! Together they cover every configuration where the diagonal rotation acts freely, i.e. where
//! not both links are vertical: with link 1 vertical and link 2 not, [`DspBob2Frame`] is regular
//! (link 1's direction `±ẑ` is far from its pole `e2''`); symmetrically for link 2. Where both
//! links are vertical at once every chart is singular, and a step there fails with a typed error.
//!
//! The kinetic energy of each chart is derived from the Cartesian positions
//! `r1 = l1 u1`, `r2 = r1 + l2 u2`: a vector `v = R_z(θ) v'` moves as
//! `ṙ = R_z(θ) (v̇' + θ̇ ẑ × v')`, and `|R_z(θ) ·|` is `| · |`, so in the rotating frame
//! `|ṙ1|² = l1² |u̇1' + θ̇ ẑ × u1'|²` and `ṙ2' = ṙ1' + l2 (u̇2' + θ̇ ẑ × u2')` — in which `θ`
//! itself does not appear (G-invariance by construction). All three use the paper's midpoint
//! rule in their own coordinates.

use crate::chart_transition;
use crate::paper::DoubleSphericalPendulum;
use crate::prelude::*;
use crate::runtime::atlas::AtlasIntegrator;

/// The index of the paper's chart in [`DoubleSphericalPendulum::atlas`].
pub const PAPER: usize = 0;
/// The index of [`DspBob1Frame`] in [`DoubleSphericalPendulum::atlas`].
pub const BOB1_FRAME: usize = 1;
/// The index of [`DspBob2Frame`] in [`DoubleSphericalPendulum::atlas`].
pub const BOB2_FRAME: usize = 2;

/// A link frame's chart (module documentation): group `$th` the azimuth of the link `$own` whose
/// polar angle is `$phi`, shape `($phi, $a, $b)` with `($a, $b)` the spherical angles of the
/// other link `$other` about the pole `e2'` of the frame rotated by `$th`, and the midpoint rule
/// `L_d = h L((q0 + q1)/2, (q1 − q0)/h)`. The two link frames are the one Lagrangian with the
/// links exchanged; each is written from this one text, and the type it declares gets the
/// paper's parameters ([`DoubleSphericalPendulum::paper`]).
macro_rules! link_frame_chart {
    ($(#[$doc:meta])* $name:ident, $ty:ident: $coords:tt, frame of link 1) => {
        link_frame_chart!(@emit $(#[$doc])* $name, $ty: $coords, own = (u1, du1),
            other = (u2, du2), links = (u1, du1, u2, du2));
    };
    ($(#[$doc:meta])* $name:ident, $ty:ident: $coords:tt, frame of link 2) => {
        link_frame_chart!(@emit $(#[$doc])* $name, $ty: $coords, own = (u2, du2),
            other = (u1, du1), links = (u1, du1, u2, du2));
    };
    (
        @emit $(#[$doc:meta])* $name:ident, $ty:ident:
        (shape($phi:ident, $a:ident, $b:ident), group($th:ident)),
        own = ($own:ident, $down:ident), other = ($other:ident, $dother:ident),
        links = ($u1:ident, $du1:ident, $u2:ident, $du2:ident)
    ) => {
        $(#[$doc])*
        #[reduced_lagrangian(shape($phi, $a, $b), group($th))]
        #[allow(clippy::too_many_arguments)]
        pub fn $name(
            q0: Config,
            q1: Config,
            h: f64,
            m1: f64,
            m2: f64,
            l1: f64,
            l2: f64,
            g: f64,
        ) -> f64 {
            let (phi, a, b) = (
                0.5 * (q0.$phi + q1.$phi),
                0.5 * (q0.$a + q1.$a),
                0.5 * (q0.$b + q1.$b),
            );
            let (dphi, da, db, dth) = (
                (q1.$phi - q0.$phi) / h,
                (q1.$a - q0.$a) / h,
                (q1.$b - q0.$b) / h,
                (q1.$th - q0.$th) / h,
            );
            let (s, c) = (phi.sin(), phi.cos());
            let (sa, ca, sb, cb) = (a.sin(), a.cos(), b.sin(), b.cos());
            // Link directions in the frame rotated by the group angle, and their velocities
            // u̇ + θ̇ ẑ × u.
            let $own = [s, 0.0, c];
            let $other = [sa * cb, ca, sa * sb];
            let $down = [c * dphi, 0.0, -s * dphi];
            let $dother = [
                ca * cb * da - sa * sb * db,
                -sa * da,
                ca * sb * da + sa * cb * db,
            ];
            let v1 = [
                l1 * ($du1[0] - dth * $u1[1]),
                l1 * ($du1[1] + dth * $u1[0]),
                l1 * $du1[2],
            ];
            let v2 = [
                v1[0] + l2 * ($du2[0] - dth * $u2[1]),
                v1[1] + l2 * ($du2[1] + dth * $u2[0]),
                v1[2] + l2 * $du2[2],
            ];
            let kinetic = 0.5 * m1 * (v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2])
                + 0.5 * m2 * (v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]);
            let potential = g * (m1 * l1 * $u1[2] + m2 * (l1 * $u1[2] + l2 * $u2[2]));
            h * (kinetic - potential)
        }

        impl $ty {
            /// The paper's parameters (§7.2.2), as [`DoubleSphericalPendulum::paper`].
            pub fn paper() -> Self {
                pendulum_parameters!(Self, DoubleSphericalPendulum::paper())
            }
        }
    };
}

link_frame_chart!(
    /// The double spherical pendulum in the rotating frame of link 1 (module documentation):
    /// shape `(φ1, a2, b2)`, group `θ1`, midpoint rule `L_d = h L((q0 + q1)/2, (q1 − q0)/h)`.
    dsp_bob1_frame, DspBob1Frame: (shape(phi1, a2, b2), group(th1)), frame of link 1
);

link_frame_chart!(
    /// The double spherical pendulum in the rotating frame of link 2 (module documentation):
    /// shape `(φ2, a1, b1)`, group `θ2`, midpoint rule.
    dsp_bob2_frame, DspBob2Frame: (shape(phi2, a1, b1), group(th2)), frame of link 2
);

/// Paper chart → link-1 frame. With `θ1 = ϑ1 − ϑ2`, link 2 in the frame rotated by `θ1` is
/// `(sin φ2 cos 2ϑ2, sin φ2 sin 2ϑ2, cos φ2)`, whose angles about the pole `e2'` are `(a2, b2)`.
#[chart_transition(
    from(shape(phi1, vt2, phi2), group(vt1)),
    to(shape(phi1, a2, b2), group(th1))
)]
pub fn paper_to_bob1_frame(q: Config) -> (f64, f64, f64, f64) {
    let d = 2.0 * q.vt2;
    let u = [q.phi2.sin() * d.cos(), q.phi2.sin() * d.sin(), q.phi2.cos()];
    let a2 = (u[0] * u[0] + u[2] * u[2]).sqrt().atan2(u[1]);
    let b2 = u[2].atan2(u[0]);
    (q.phi1, a2, b2, q.vt1 - q.vt2)
}

/// Link-1 frame → paper chart: link 2's polar angle `φ2` and its azimuth `δ = θ2 − θ1` relative
/// to link 1; `ϑ2 = δ/2`, `ϑ1 = θ1 + δ/2`.
#[chart_transition(
    from(shape(phi1, a2, b2), group(th1)),
    to(shape(phi1, vt2, phi2), group(vt1))
)]
pub fn bob1_frame_to_paper(q: Config) -> (f64, f64, f64, f64) {
    let u = [q.a2.sin() * q.b2.cos(), q.a2.cos(), q.a2.sin() * q.b2.sin()];
    let phi2 = (u[0] * u[0] + u[1] * u[1]).sqrt().atan2(u[2]);
    let d = u[1].atan2(u[0]);
    (q.phi1, 0.5 * d, phi2, q.th1 + 0.5 * d)
}

/// Paper chart → link-2 frame. With `θ2 = ϑ1 + ϑ2`, link 1 in the frame rotated by `θ2` is
/// `(sin φ1 cos 2ϑ2, −sin φ1 sin 2ϑ2, cos φ1)`.
#[chart_transition(
    from(shape(phi1, vt2, phi2), group(vt1)),
    to(shape(phi2, a1, b1), group(th2))
)]
pub fn paper_to_bob2_frame(q: Config) -> (f64, f64, f64, f64) {
    let d = -2.0 * q.vt2;
    let u = [q.phi1.sin() * d.cos(), q.phi1.sin() * d.sin(), q.phi1.cos()];
    let a1 = (u[0] * u[0] + u[2] * u[2]).sqrt().atan2(u[1]);
    let b1 = u[2].atan2(u[0]);
    (q.phi2, a1, b1, q.vt1 + q.vt2)
}

/// Link-2 frame → paper chart: `δ = θ1 − θ2`, `ϑ2 = −δ/2`, `ϑ1 = θ2 + δ/2`.
#[chart_transition(
    from(shape(phi2, a1, b1), group(th2)),
    to(shape(phi1, vt2, phi2), group(vt1))
)]
pub fn bob2_frame_to_paper(q: Config) -> (f64, f64, f64, f64) {
    let u = [q.a1.sin() * q.b1.cos(), q.a1.cos(), q.a1.sin() * q.b1.sin()];
    let phi1 = (u[0] * u[0] + u[1] * u[1]).sqrt().atan2(u[2]);
    let d = u[1].atan2(u[0]);
    (phi1, -0.5 * d, q.phi2, q.th2 + 0.5 * d)
}

/// Link-1 frame → link-2 frame: `δ` the azimuth of link 2 relative to link 1, `θ2 = θ1 + δ`,
/// and link 1 seen from the frame rotated by `θ2` is `R_z(−δ) u1'`.
#[chart_transition(
    from(shape(phi1, a2, b2), group(th1)),
    to(shape(phi2, a1, b1), group(th2))
)]
pub fn bob1_frame_to_bob2_frame(q: Config) -> (f64, f64, f64, f64) {
    let u2 = [q.a2.sin() * q.b2.cos(), q.a2.cos(), q.a2.sin() * q.b2.sin()];
    let phi2 = (u2[0] * u2[0] + u2[1] * u2[1]).sqrt().atan2(u2[2]);
    let d = u2[1].atan2(u2[0]);
    let s1 = q.phi1.sin();
    let u1 = [s1 * d.cos(), -s1 * d.sin(), q.phi1.cos()];
    let a1 = (u1[0] * u1[0] + u1[2] * u1[2]).sqrt().atan2(u1[1]);
    let b1 = u1[2].atan2(u1[0]);
    (phi2, a1, b1, q.th1 + d)
}

/// Link-2 frame → link-1 frame (the previous map with the links exchanged).
#[chart_transition(
    from(shape(phi2, a1, b1), group(th2)),
    to(shape(phi1, a2, b2), group(th1))
)]
pub fn bob2_frame_to_bob1_frame(q: Config) -> (f64, f64, f64, f64) {
    let u1 = [q.a1.sin() * q.b1.cos(), q.a1.cos(), q.a1.sin() * q.b1.sin()];
    let phi1 = (u1[0] * u1[0] + u1[1] * u1[1]).sqrt().atan2(u1[2]);
    let d = u1[1].atan2(u1[0]);
    let s2 = q.phi2.sin();
    let u2 = [s2 * d.cos(), -s2 * d.sin(), q.phi2.cos()];
    let a2 = (u2[0] * u2[0] + u2[2] * u2[2]).sqrt().atan2(u2[1]);
    let b2 = u2[2].atan2(u2[0]);
    (phi1, a2, b2, q.th2 + d)
}

/// The distance of a state of chart `chart` to that chart's singular set, measured as the
/// smallest `|sin|` of the polar angles that must stay away from their poles: `min(|sin φ1|,
/// |sin φ2|)` in the paper's chart, `min(|sin φ1|, |sin a2|)` and `min(|sin φ2|, |sin a1|)` in the
/// link frames. 1 is best, 0 is on the singular set.
pub fn chart_quality(chart: usize, state: &ReducedState<3, 1>) -> f64 {
    let x = &state.x;
    match chart {
        PAPER => x[0].sin().abs().min(x[2].sin().abs()),
        _ => x[0].sin().abs().min(x[1].sin().abs()),
    }
}

/// The threshold of [`chart_quality`] below which [`DoubleSphericalPendulum::atlas`] changes
/// chart: `|sin| < 0.3`, a link within ≈ 17° of its chart's pole.
///
/// Measured on the paper's run (`tests/atlas_long_run.rs`): at 0.1 and 0.05 the close passages
/// near the link frames' poles cost energy accuracy (a 3% excursion of `T + V` at 0.1, a drift of
/// half the spread over 10⁶ steps at 0.05); at 0.3 every step stays well inside a chart. The
/// paper's initial state itself has `|sin φ2| = sin 3 ≈ 0.14`, so at 0.3 the atlas leaves the
/// paper's chart after the first step.
pub const SWITCH_BELOW: f64 = 0.3;

/// The Hamiltonian `H(q, p) = ½ pᵀ M(q)⁻¹ p + V(q)` of a midpoint-rule chart, read off its
/// discrete Lagrangian: with `T` quadratic in the velocities, at `q0 = q1 = q` the Hessian blocks
/// of `L_d` are `D22 = M/h − (h/4) V''` and `D12 = −M/h − (h/4) V''`, so
/// `M(q) = (h/2)(D22 − D12)`, and `V(q) = −L_d(q, q)/h`. `H` is intrinsic to `T*Q`, so it takes
/// the same value at the same physical state in every chart: the physical energy `T + V` at the
/// nodes, continuous across a change of chart. `None` where `M` is singular (the chart's
/// singular set).
pub fn hamiltonian<L>(system: &L, state: &ReducedState<3, 1>) -> Option<f64>
where
    L: crate::LagrangianHessian<3, 1, 4>,
{
    let canonical = system.untrivialize(state);
    let q = canonical.q;
    let h = system.time_step();
    let (_, d12, d22) = system.lagrangian_hessian(&q, &q);
    let m = 0.5 * h * (d22 - d12);
    let v = -system.lagrangian(&q, &q) / h;
    let velocity = m.lu().solve(&canonical.p)?;
    Some(0.5 * canonical.p.dot(&velocity) + v)
}

/// The three charts of one pendulum, with the same parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DspCharts {
    /// The paper's chart, [`PAPER`].
    pub paper: DoubleSphericalPendulum,
    /// The link-1 frame, [`BOB1_FRAME`].
    pub bob1: DspBob1Frame,
    /// The link-2 frame, [`BOB2_FRAME`].
    pub bob2: DspBob2Frame,
}

impl DspCharts {
    /// The physical energy `T + V` ([`hamiltonian`]) of a state of chart `chart`.
    pub fn energy(&self, chart: usize, state: &ReducedState<3, 1>) -> Option<f64> {
        match chart {
            PAPER => hamiltonian(&self.paper, state),
            BOB1_FRAME => hamiltonian(&self.bob1, state),
            _ => hamiltonian(&self.bob2, state),
        }
    }

    /// The Cartesian positions `(r1, r2)` of the bobs at a state of chart `chart`, in the frame
    /// of the paper's chart (pivot at the origin, `z` up).
    pub fn bob_positions(&self, chart: usize, state: &ReducedState<3, 1>) -> ([f64; 3], [f64; 3]) {
        let (l1, l2) = (self.paper.l1, self.paper.l2);
        let (x, theta) = (&state.x, state.g[0]);
        // Link directions in the frame rotated by θ (the group coordinate of a link frame).
        let sph = |a: f64, b: f64| [a.sin() * b.cos(), a.cos(), a.sin() * b.sin()];
        let (u1, u2) = match chart {
            PAPER => {
                let q = SVector::<f64, 4>::new(x[0], x[1], x[2], theta);
                return self.paper.bob_positions(&q);
            }
            BOB1_FRAME => ([x[0].sin(), 0.0, x[0].cos()], sph(x[1], x[2])),
            _ => (sph(x[1], x[2]), [x[0].sin(), 0.0, x[0].cos()]),
        };
        let rot = |u: [f64; 3]| {
            let (s, c) = theta.sin_cos();
            [c * u[0] - s * u[1], s * u[0] + c * u[1], u[2]]
        };
        let (u1, u2) = (rot(u1), rot(u2));
        let r1 = [l1 * u1[0], l1 * u1[1], l1 * u1[2]];
        let r2 = [r1[0] + l2 * u2[0], r1[1] + l2 * u2[1], r1[2] + l2 * u2[2]];
        (r1, r2)
    }
}

impl DoubleSphericalPendulum {
    /// The same pendulum in all three charts.
    pub fn charts(&self) -> DspCharts {
        DspCharts {
            paper: *self,
            bob1: pendulum_parameters!(DspBob1Frame, self),
            bob2: pendulum_parameters!(DspBob2Frame, self),
        }
    }

    /// The atlas integrator: the reduced (+) stepper of eq. (4.6) in each of the three charts
    /// (indices [`PAPER`], [`BOB1_FRAME`], [`BOB2_FRAME`]), all six transitions, and the
    /// distance to the singular set ([`chart_quality`]) as the switching indicator, below
    /// [`SWITCH_BELOW`].
    pub fn atlas(&self, options: NewtonOptions) -> AtlasIntegrator<'static, 3, 1, 4> {
        let charts = self.charts();
        AtlasIntegrator::new()
            .chart(
                "paper (φ1, ϑ2, φ2; ϑ1)",
                ReducedIntegrator::plus(charts.paper, options),
            )
            .chart(
                "link-1 frame (φ1, a2, b2; θ1)",
                ReducedIntegrator::plus(charts.bob1, options),
            )
            .chart(
                "link-2 frame (φ2, a1, b1; θ2)",
                ReducedIntegrator::plus(charts.bob2, options),
            )
            .transition(PAPER, BOB1_FRAME, PaperToBob1Frame)
            .transition(BOB1_FRAME, PAPER, Bob1FrameToPaper)
            .transition(PAPER, BOB2_FRAME, PaperToBob2Frame)
            .transition(BOB2_FRAME, PAPER, Bob2FrameToPaper)
            .transition(BOB1_FRAME, BOB2_FRAME, Bob1FrameToBob2Frame)
            .transition(BOB2_FRAME, BOB1_FRAME, Bob2FrameToBob1Frame)
            .with_quality(SWITCH_BELOW, chart_quality)
    }
}
