///A configuration of [`ChargedParticle`]: shape coordinates (`x`, `y`, `z`) then group coordinates (`theta`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChargedParticleConfig {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub theta: f64,
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
impl ChargedParticleConfig {
    /// Reads `q = (x, g)` in configuration order.
    pub fn from_vector(q: &::dirac::nalgebra::SVector<f64, 4usize>) -> Self {
        Self {
            x: q[0usize],
            y: q[1usize],
            z: q[2usize],
            theta: q[3usize],
        }
    }
    /// Writes `q = (x, g)` in configuration order.
    pub fn to_vector(&self) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        ::dirac::nalgebra::SVector::<
            f64,
            4usize,
        >::from([self.x, self.y, self.z, self.theta])
    }
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
#[automatically_derived]
impl ::dirac::runtime::AdaptedCoordinates<4usize> for ChargedParticle {
    #[inline]
    fn to_adapted(
        q_user: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        *q_user
    }
    #[inline]
    fn from_adapted(
        q: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        *q
    }
    #[inline]
    fn momentum_to_adapted(
        p_user: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        *p_user
    }
    #[inline]
    fn momentum_from_adapted(
        p: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        *p
    }
}
/// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
#[allow(
    clippy::too_many_arguments,
    reason = "the attribute takes the Lagrangian's parameters as `f64` arguments"
)]
#[allow(
    clippy::many_single_char_names,
    reason = "parameters keep the physical symbols (h, m, g, l)"
)]
pub fn charged_particle(
    q0: ChargedParticleConfig,
    q1: ChargedParticleConfig,
    h: f64,
    m: f64,
    b0: f64,
) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
    let s = a_dot_dq + (q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
}
/// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
/**

The parameters of [`charged_particle`]; emitted by `#[reduced_lagrangian]`, which implements the `dirac` system traits for it.*/
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChargedParticle {
    pub h: f64,
    pub m: f64,
    pub b0: f64,
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
impl ChargedParticle {
    /// Number of shape coordinates `S`.
    pub const SHAPE_DIM: usize = 3usize;
    /// Number of group coordinates `K`.
    pub const GROUP_DIM: usize = 1usize;
    /// Number of configuration coordinates `N = S + K`.
    pub const CONFIG_DIM: usize = 4usize;
    ///Generated straight-line code: reduced (+) stepper: 42 operations for the residual, 77 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; reduced (−) stepper: 43 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; unreduced stepper: 44 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 34 for the momentum update. Momentum-level elimination: (+) group unknowns in closed form, Newton on the shape unknowns: 45 operations for the residual, 81 for the residual with its Jacobian (5 nonzero entries), 14 for the momentum update (the third count is the closed form); used by default: yes; (−) group unknowns in closed form, Newton on the shape unknowns: 46 operations for the residual, 81 for the residual with its Jacobian (5 nonzero entries), 15 for the momentum update (the third count is the closed form); used by default: yes.
    pub const GENERATED: &'static str = "Generated straight-line code: reduced (+) stepper: 42 operations for the residual, 77 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; reduced (−) stepper: 43 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; unreduced stepper: 44 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 34 for the momentum update. Momentum-level elimination: (+) group unknowns in closed form, Newton on the shape unknowns: 45 operations for the residual, 81 for the residual with its Jacobian (5 nonzero entries), 14 for the momentum update (the third count is the closed form); used by default: yes; (−) group unknowns in closed form, Newton on the shape unknowns: 46 operations for the residual, 81 for the residual with its Jacobian (5 nonzero entries), 15 for the momentum update (the third count is the closed form); used by default: yes.";
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
#[automatically_derived]
impl ::dirac::runtime::DiscreteLagrangian<3usize, 1usize, 4usize> for ChargedParticle {
    const SHAPE: [&'static str; 3usize] = ["x", "y", "z"];
    const GROUP: [&'static str; 1usize] = ["theta"];
    const PARAMETERS: &'static [&'static str] = &["h", "m", "b0"];
    fn lagrangian(
        &self,
        q0: &::dirac::nalgebra::SVector<f64, 4usize>,
        q1: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> f64 {
        charged_particle(
            ChargedParticleConfig::from_vector(q0),
            ChargedParticleConfig::from_vector(q1),
            self.h,
            self.m,
            self.b0,
        )
    }
    fn connection(&self) -> ::dirac::nalgebra::SMatrix<f64, 1usize, 3usize> {
        ::dirac::nalgebra::SMatrix::<
            f64,
            1usize,
            3usize,
        >::from_row_slice(&[0f64, 0f64, 0f64])
    }
    fn time_step(&self) -> f64 {
        self.h
    }
    fn with_time_step(&self, h: f64) -> Self {
        let mut system = *self;
        system.h = h;
        system
    }
    fn parameter_values(&self) -> ::std::vec::Vec<f64> {
        ::std::vec![self.h, self.m, self.b0]
    }
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
#[automatically_derived]
impl ::dirac::runtime::Reduced<::dirac::runtime::Plus, 3usize, 1usize, 4usize>
for ChargedParticle {
    type Linear = ::dirac::runtime::Lu<4usize>;
    fn linear_solver(&self) -> ::dirac::runtime::Lu<4usize> {
        ::dirac::runtime::Lu::empty()
    }
    #[allow(unused_variables)]
    fn reduced_lagrangian(
        &self,
        x0: &::dirac::nalgebra::SVector<f64, 3usize>,
        x1: &::dirac::nalgebra::SVector<f64, 3usize>,
        u: &::dirac::nalgebra::SVector<f64, 1usize>,
    ) -> f64 {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __g1_0,
            __t52,
            __t53,
            __t54,
            __t55,
            __t56,
            __t57,
            __t58,
            __t59,
            __t60,
            __t61,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = x1[0usize];
        __x0_0 = x0[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = x1[1usize];
        __x0_1 = x0[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = x1[2usize];
        __x0_2 = x0[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __g1_0 = u[0usize];
        __t52 = __t49 + __g1_0;
        __t53 = __t39 * __t39;
        __t54 = __t42 * __t42;
        __t55 = __t53 + __t54;
        __t56 = __t45 * __t45;
        __t57 = __t55 + __t56;
        __t58 = __t25 * __t57;
        __t59 = __t32 * __t52;
        __t60 = __t52 * __t59;
        __t61 = __t58 + __t60;
        __t61
    }
    #[inline]
    fn residual(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __g1_0,
            __t52,
            __t59,
            __t64,
            __t65,
            __t66,
            __t67,
            __t68,
            __t69,
            __t70,
            __t71,
            __t72,
            __t73,
            __w_0,
            __t75,
            __t76,
            __t77,
            __t78,
            __t79,
            __t80,
            __t81,
            __t82,
            __t83,
            __t84,
            __t85,
            __t86,
            __w_1,
            __t88,
            __t89,
            __t90,
            __t91,
            __w_2,
            __t93,
            __t94,
            __mu_0,
            __t96,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __g1_0 = z[3usize];
        __t52 = __t49 + __g1_0;
        __t59 = __t32 * __t52;
        __t64 = __x0_1 + __t42;
        __t65 = __t11 * __t64;
        __t66 = -__t39;
        __t67 = __t66 - __t39;
        __t68 = __t25 * __t67;
        __t69 = __t32 * __t65;
        __t70 = __t59 * __t65;
        __t71 = __t52 * __t69;
        __t72 = __t70 + __t71;
        __t73 = __t68 + __t72;
        __w_0 = w_k[0usize];
        __t75 = __t73 + __w_0;
        __t76 = -__x0_0;
        __t77 = __t76 - __t39;
        __t78 = __t11 * __t77;
        __t79 = -__t42;
        __t80 = __t79 - __t42;
        __t81 = __t25 * __t80;
        __t82 = __t32 * __t78;
        __t83 = __t59 * __t78;
        __t84 = __t52 * __t82;
        __t85 = __t83 + __t84;
        __t86 = __t81 + __t85;
        __w_1 = w_k[1usize];
        __t88 = __t86 + __w_1;
        __t89 = -__t45;
        __t90 = __t89 - __t45;
        __t91 = __t25 * __t90;
        __w_2 = w_k[2usize];
        __t93 = __t91 + __w_2;
        __t94 = __t59 + __t59;
        __mu_0 = mu_k[0usize];
        __t96 = __t94 - __mu_0;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t75, __t88, __t93, __t96])
    }
    #[inline]
    fn residual_jacobian(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> (
        ::dirac::nalgebra::SVector<f64, 4usize>,
        ::dirac::nalgebra::SMatrix<f64, 4usize, 4usize>,
    ) {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __g1_0,
            __t52,
            __t59,
            __t64,
            __t65,
            __t66,
            __t67,
            __t68,
            __t69,
            __t70,
            __t71,
            __t72,
            __t73,
            __w_0,
            __t75,
            __t76,
            __t77,
            __t78,
            __t79,
            __t80,
            __t81,
            __t82,
            __t83,
            __t84,
            __t85,
            __t86,
            __w_1,
            __t88,
            __t89,
            __t90,
            __t91,
            __w_2,
            __t93,
            __t94,
            __mu_0,
            __t96,
            __t97,
            __t99,
            __t100,
            __t102,
            __t103,
            __t104,
            __t105,
            __t107,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __g1_0 = z[3usize];
        __t52 = __t49 + __g1_0;
        __t59 = __t32 * __t52;
        __t64 = __x0_1 + __t42;
        __t65 = __t11 * __t64;
        __t66 = -__t39;
        __t67 = __t66 - __t39;
        __t68 = __t25 * __t67;
        __t69 = __t32 * __t65;
        __t70 = __t59 * __t65;
        __t71 = __t52 * __t69;
        __t72 = __t70 + __t71;
        __t73 = __t68 + __t72;
        __w_0 = w_k[0usize];
        __t75 = __t73 + __w_0;
        __t76 = -__x0_0;
        __t77 = __t76 - __t39;
        __t78 = __t11 * __t77;
        __t79 = -__t42;
        __t80 = __t79 - __t42;
        __t81 = __t25 * __t80;
        __t82 = __t32 * __t78;
        __t83 = __t59 * __t78;
        __t84 = __t52 * __t82;
        __t85 = __t83 + __t84;
        __t86 = __t81 + __t85;
        __w_1 = w_k[1usize];
        __t88 = __t86 + __w_1;
        __t89 = -__t45;
        __t90 = __t89 - __t45;
        __t91 = __t25 * __t90;
        __w_2 = w_k[2usize];
        __t93 = __t91 + __w_2;
        __t94 = __t59 + __t59;
        __mu_0 = mu_k[0usize];
        __t96 = __t94 - __mu_0;
        __t97 = __t11 * __x0_1;
        __t99 = __t32 * __t97;
        __t100 = -__t99;
        __t102 = __t25 * (-2f64);
        __t103 = __t65 * __t99;
        __t104 = -__t103;
        __t105 = __t69 * __t97;
        __t107 = __t104 - __t105;
        let (
            __t108,
            __t110,
            __t112,
            __t113,
            __t114,
            __t116,
            __t117,
            __t118,
            __t119,
            __t121,
            __t122,
            __t123,
            __t124,
            __t125,
            __t126,
            __t127,
            __t128,
            __t129,
            __t130,
            __t131,
            __t132,
            __t133,
            __t134,
            __t135,
            __t136,
            __t137,
            __t138,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __t108 = __t102 + __t107;
        __t110 = __t11 * __t32;
        __t112 = __t78 * __t99;
        __t113 = -__t112;
        __t114 = __t11 * __t59;
        __t116 = __t113 - __t114;
        __t117 = __t82 * __t97;
        __t118 = -__t117;
        __t119 = __t52 * __t110;
        __t121 = __t118 - __t119;
        __t122 = __t116 + __t121;
        __t123 = __t100 - __t99;
        __t124 = __t11 * __x0_0;
        __t125 = __t32 * __t124;
        __t126 = __t65 * __t125;
        __t127 = __t114 + __t126;
        __t128 = __t69 * __t124;
        __t129 = __t119 + __t128;
        __t130 = __t127 + __t129;
        __t131 = __t78 * __t125;
        __t132 = __t82 * __t124;
        __t133 = __t131 + __t132;
        __t134 = __t102 + __t133;
        __t135 = __t125 + __t125;
        __t136 = __t69 + __t69;
        __t137 = __t82 + __t82;
        __t138 = __t32 + __t32;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t75, __t88, __t93, __t96]),
            {
                let mut __jac = ::dirac::nalgebra::SMatrix::<
                    f64,
                    4usize,
                    4usize,
                >::zeros();
                __jac[(0usize, 0usize)] = __t108;
                __jac[(0usize, 1usize)] = __t130;
                __jac[(0usize, 3usize)] = __t136;
                __jac[(1usize, 0usize)] = __t122;
                __jac[(1usize, 1usize)] = __t134;
                __jac[(1usize, 3usize)] = __t137;
                __jac[(2usize, 2usize)] = __t102;
                __jac[(3usize, 0usize)] = __t123;
                __jac[(3usize, 1usize)] = __t135;
                __jac[(3usize, 3usize)] = __t138;
                __jac
            },
        )
    }
    #[inline]
    fn momentum(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 3usize> {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __g1_0,
            __t52,
            __t59,
            __t97,
            __t99,
            __t124,
            __t125,
            __t139,
            __t140,
            __t141,
            __t142,
            __t143,
            __t145,
            __t146,
            __t147,
            __t148,
            __t149,
            __t150,
            __t151,
            __t152,
            __t153,
            __t154,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __g1_0 = z[3usize];
        __t52 = __t49 + __g1_0;
        __t59 = __t32 * __t52;
        __t97 = __t11 * __x0_1;
        __t99 = __t32 * __t97;
        __t124 = __t11 * __x0_0;
        __t125 = __t32 * __t124;
        __t139 = __t39 + __t39;
        __t140 = __t25 * __t139;
        __t141 = __t59 * __t97;
        __t142 = -__t141;
        __t143 = __t52 * __t99;
        __t145 = __t142 - __t143;
        __t146 = __t140 + __t145;
        __t147 = __t42 + __t42;
        __t148 = __t25 * __t147;
        __t149 = __t59 * __t124;
        __t150 = __t52 * __t125;
        __t151 = __t149 + __t150;
        __t152 = __t148 + __t151;
        __t153 = __t45 + __t45;
        __t154 = __t25 * __t153;
        ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t146, __t152, __t154])
    }
    #[inline]
    #[allow(unused_variables)]
    fn residual_momentum(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> (
        ::dirac::nalgebra::SVector<f64, 4usize>,
        ::dirac::nalgebra::SVector<f64, 3usize>,
    ) {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __g1_0,
            __t52,
            __t59,
            __t64,
            __t65,
            __t66,
            __t67,
            __t68,
            __t69,
            __t70,
            __t71,
            __t72,
            __t73,
            __w_0,
            __t75,
            __t76,
            __t77,
            __t78,
            __t79,
            __t80,
            __t81,
            __t82,
            __t83,
            __t84,
            __t85,
            __t86,
            __w_1,
            __t88,
            __t89,
            __t90,
            __t91,
            __w_2,
            __t93,
            __t94,
            __mu_0,
            __t96,
            __t97,
            __t99,
            __t124,
            __t125,
            __t139,
            __t140,
            __t141,
            __t142,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __g1_0 = z[3usize];
        __t52 = __t49 + __g1_0;
        __t59 = __t32 * __t52;
        __t64 = __x0_1 + __t42;
        __t65 = __t11 * __t64;
        __t66 = -__t39;
        __t67 = __t66 - __t39;
        __t68 = __t25 * __t67;
        __t69 = __t32 * __t65;
        __t70 = __t59 * __t65;
        __t71 = __t52 * __t69;
        __t72 = __t70 + __t71;
        __t73 = __t68 + __t72;
        __w_0 = w_k[0usize];
        __t75 = __t73 + __w_0;
        __t76 = -__x0_0;
        __t77 = __t76 - __t39;
        __t78 = __t11 * __t77;
        __t79 = -__t42;
        __t80 = __t79 - __t42;
        __t81 = __t25 * __t80;
        __t82 = __t32 * __t78;
        __t83 = __t59 * __t78;
        __t84 = __t52 * __t82;
        __t85 = __t83 + __t84;
        __t86 = __t81 + __t85;
        __w_1 = w_k[1usize];
        __t88 = __t86 + __w_1;
        __t89 = -__t45;
        __t90 = __t89 - __t45;
        __t91 = __t25 * __t90;
        __w_2 = w_k[2usize];
        __t93 = __t91 + __w_2;
        __t94 = __t59 + __t59;
        __mu_0 = mu_k[0usize];
        __t96 = __t94 - __mu_0;
        __t97 = __t11 * __x0_1;
        __t99 = __t32 * __t97;
        __t124 = __t11 * __x0_0;
        __t125 = __t32 * __t124;
        __t139 = __t39 + __t39;
        __t140 = __t25 * __t139;
        __t141 = __t59 * __t97;
        __t142 = -__t141;
        let (
            __t143,
            __t145,
            __t146,
            __t147,
            __t148,
            __t149,
            __t150,
            __t151,
            __t152,
            __t153,
            __t154,
        ): (f64, f64, f64, f64, f64, f64, f64, f64, f64, f64, f64);
        __t143 = __t52 * __t99;
        __t145 = __t142 - __t143;
        __t146 = __t140 + __t145;
        __t147 = __t42 + __t42;
        __t148 = __t25 * __t147;
        __t149 = __t59 * __t124;
        __t150 = __t52 * __t125;
        __t151 = __t149 + __t150;
        __t152 = __t148 + __t151;
        __t153 = __t45 + __t45;
        __t154 = __t25 * __t153;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t75, __t88, __t93, __t96]),
            ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t146, __t152, __t154]),
        )
    }
    const ELIMINATES_GROUP: bool = true;
    const ELIMINATION_PAYS: bool = true;
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_residual(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<::dirac::nalgebra::SVector<f64, 3usize>> {
        ::core::option::Option::Some({
            let (
                __p2,
                __t11,
                __p1,
                __t23,
                __p0,
                __t25,
                __t32,
                __x1_0,
                __x0_0,
                __t39,
                __x1_1,
                __x0_1,
                __t42,
                __x1_2,
                __x0_2,
                __t45,
                __t46,
                __t47,
                __t48,
                __t49,
                __t64,
                __t65,
                __t66,
                __t67,
                __t68,
                __t69,
                __w_0,
                __t76,
                __t77,
                __t78,
                __t79,
                __t80,
                __t81,
                __t82,
                __w_1,
                __t89,
                __t90,
                __t91,
                __w_2,
                __t93,
                __mu_0,
                __t138,
                __t405,
                __t406,
                __t407,
                __t409,
                __t411,
                __t412,
                __t413,
                __t414,
                __t415,
                __t416,
                __t417,
                __t418,
                __t419,
                __t420,
                __t421,
                __t422,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __p2 = self.b0;
            __t11 = 0.5f64 * __p2;
            __p1 = self.m;
            __t23 = 0.5f64 * __p1;
            __p0 = self.h;
            __t25 = __t23 / __p0;
            __t32 = 0.5f64 / __p0;
            __x1_0 = z[0usize];
            __x0_0 = x_k[0usize];
            __t39 = __x1_0 - __x0_0;
            __x1_1 = z[1usize];
            __x0_1 = x_k[1usize];
            __t42 = __x1_1 - __x0_1;
            __x1_2 = z[2usize];
            __x0_2 = x_k[2usize];
            __t45 = __x1_2 - __x0_2;
            __t46 = __t39 * __x0_1;
            __t47 = __x0_0 * __t42;
            __t48 = __t47 - __t46;
            __t49 = __t11 * __t48;
            __t64 = __x0_1 + __t42;
            __t65 = __t11 * __t64;
            __t66 = -__t39;
            __t67 = __t66 - __t39;
            __t68 = __t25 * __t67;
            __t69 = __t32 * __t65;
            __w_0 = w_k[0usize];
            __t76 = -__x0_0;
            __t77 = __t76 - __t39;
            __t78 = __t11 * __t77;
            __t79 = -__t42;
            __t80 = __t79 - __t42;
            __t81 = __t25 * __t80;
            __t82 = __t32 * __t78;
            __w_1 = w_k[1usize];
            __t89 = -__t45;
            __t90 = __t89 - __t45;
            __t91 = __t25 * __t90;
            __w_2 = w_k[2usize];
            __t93 = __t91 + __w_2;
            __mu_0 = mu_k[0usize];
            __t138 = __t32 + __t32;
            __t405 = __t32 * __t49;
            __t406 = __t405 + __t405;
            __t407 = __t406 - __mu_0;
            __t409 = __t407 / __t138;
            __t411 = __t49 - __t409;
            __t412 = __t32 * __t411;
            __t413 = __t65 * __t412;
            __t414 = __t69 * __t411;
            __t415 = __t413 + __t414;
            __t416 = __t68 + __t415;
            __t417 = __w_0 + __t416;
            __t418 = __t78 * __t412;
            __t419 = __t82 * __t411;
            __t420 = __t418 + __t419;
            __t421 = __t81 + __t420;
            __t422 = __w_1 + __t421;
            ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t417, __t422, __t93])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_residual_jacobian(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<
        (
            ::dirac::nalgebra::SVector<f64, 3usize>,
            ::dirac::nalgebra::SMatrix<f64, 3usize, 3usize>,
        ),
    > {
        ::core::option::Option::Some({
            let (
                __p2,
                __t11,
                __p1,
                __t23,
                __p0,
                __t25,
                __t32,
                __x1_0,
                __x0_0,
                __t39,
                __x1_1,
                __x0_1,
                __t42,
                __x1_2,
                __x0_2,
                __t45,
                __t46,
                __t47,
                __t48,
                __t49,
                __t64,
                __t65,
                __t66,
                __t67,
                __t68,
                __t69,
                __w_0,
                __t76,
                __t77,
                __t78,
                __t79,
                __t80,
                __t81,
                __t82,
                __w_1,
                __t89,
                __t90,
                __t91,
                __w_2,
                __t93,
                __mu_0,
                __t97,
                __t98,
                __t99,
                __t100,
                __t102,
                __t110,
                __t123,
                __t124,
                __t125,
                __t135,
                __t138,
                __t405,
                __t406,
                __t407,
                __t409,
                __t411,
                __t412,
                __t413,
                __t414,
                __t415,
                __t416,
                __t417,
                __t418,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __p2 = self.b0;
            __t11 = 0.5f64 * __p2;
            __p1 = self.m;
            __t23 = 0.5f64 * __p1;
            __p0 = self.h;
            __t25 = __t23 / __p0;
            __t32 = 0.5f64 / __p0;
            __x1_0 = z[0usize];
            __x0_0 = x_k[0usize];
            __t39 = __x1_0 - __x0_0;
            __x1_1 = z[1usize];
            __x0_1 = x_k[1usize];
            __t42 = __x1_1 - __x0_1;
            __x1_2 = z[2usize];
            __x0_2 = x_k[2usize];
            __t45 = __x1_2 - __x0_2;
            __t46 = __t39 * __x0_1;
            __t47 = __x0_0 * __t42;
            __t48 = __t47 - __t46;
            __t49 = __t11 * __t48;
            __t64 = __x0_1 + __t42;
            __t65 = __t11 * __t64;
            __t66 = -__t39;
            __t67 = __t66 - __t39;
            __t68 = __t25 * __t67;
            __t69 = __t32 * __t65;
            __w_0 = w_k[0usize];
            __t76 = -__x0_0;
            __t77 = __t76 - __t39;
            __t78 = __t11 * __t77;
            __t79 = -__t42;
            __t80 = __t79 - __t42;
            __t81 = __t25 * __t80;
            __t82 = __t32 * __t78;
            __w_1 = w_k[1usize];
            __t89 = -__t45;
            __t90 = __t89 - __t45;
            __t91 = __t25 * __t90;
            __w_2 = w_k[2usize];
            __t93 = __t91 + __w_2;
            __mu_0 = mu_k[0usize];
            __t97 = __t11 * __x0_1;
            __t98 = -__t97;
            __t99 = __t32 * __t97;
            __t100 = -__t99;
            __t102 = __t25 * (-2f64);
            __t110 = __t11 * __t32;
            __t123 = __t100 - __t99;
            __t124 = __t11 * __x0_0;
            __t125 = __t32 * __t124;
            __t135 = __t125 + __t125;
            __t138 = __t32 + __t32;
            __t405 = __t32 * __t49;
            __t406 = __t405 + __t405;
            __t407 = __t406 - __mu_0;
            __t409 = __t407 / __t138;
            __t411 = __t49 - __t409;
            __t412 = __t32 * __t411;
            __t413 = __t65 * __t412;
            __t414 = __t69 * __t411;
            __t415 = __t413 + __t414;
            __t416 = __t68 + __t415;
            __t417 = __w_0 + __t416;
            __t418 = __t78 * __t412;
            let (
                __t419,
                __t420,
                __t421,
                __t422,
                __t423,
                __t424,
                __t425,
                __t426,
                __t427,
                __t428,
                __t429,
                __t430,
                __t432,
                __t433,
                __t434,
                __t436,
                __t437,
                __t438,
                __t439,
                __t440,
                __t441,
                __t442,
                __t443,
                __t444,
                __t445,
                __t446,
                __t447,
                __t448,
                __t449,
                __t450,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __t419 = __t82 * __t411;
            __t420 = __t418 + __t419;
            __t421 = __t81 + __t420;
            __t422 = __w_1 + __t421;
            __t423 = __t123 / __t138;
            __t424 = __t98 - __t423;
            __t425 = __t32 * __t424;
            __t426 = __t65 * __t425;
            __t427 = __t69 * __t424;
            __t428 = __t426 + __t427;
            __t429 = __t102 + __t428;
            __t430 = __t11 * __t412;
            __t432 = __t78 * __t425;
            __t433 = __t432 - __t430;
            __t434 = __t110 * __t411;
            __t436 = __t82 * __t424;
            __t437 = __t436 - __t434;
            __t438 = __t433 + __t437;
            __t439 = __t135 / __t138;
            __t440 = __t124 - __t439;
            __t441 = __t32 * __t440;
            __t442 = __t65 * __t441;
            __t443 = __t430 + __t442;
            __t444 = __t69 * __t440;
            __t445 = __t434 + __t444;
            __t446 = __t443 + __t445;
            __t447 = __t78 * __t441;
            __t448 = __t82 * __t440;
            __t449 = __t447 + __t448;
            __t450 = __t102 + __t449;
            (
                ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t417, __t422, __t93]),
                {
                    let mut __jac = ::dirac::nalgebra::SMatrix::<
                        f64,
                        3usize,
                        3usize,
                    >::zeros();
                    __jac[(0usize, 0usize)] = __t429;
                    __jac[(0usize, 1usize)] = __t446;
                    __jac[(1usize, 0usize)] = __t438;
                    __jac[(1usize, 1usize)] = __t450;
                    __jac[(2usize, 2usize)] = __t102;
                    __jac
                },
            )
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_group(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<::dirac::nalgebra::SVector<f64, 1usize>> {
        ::core::option::Option::Some({
            let (
                __p2,
                __t11,
                __p0,
                __t32,
                __x1_0,
                __x0_0,
                __t39,
                __x1_1,
                __x0_1,
                __t42,
                __t46,
                __t47,
                __t48,
                __t49,
                __mu_0,
                __t138,
                __t405,
                __t406,
                __t407,
                __t409,
                __t410,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __p2 = self.b0;
            __t11 = 0.5f64 * __p2;
            __p0 = self.h;
            __t32 = 0.5f64 / __p0;
            __x1_0 = z[0usize];
            __x0_0 = x_k[0usize];
            __t39 = __x1_0 - __x0_0;
            __x1_1 = z[1usize];
            __x0_1 = x_k[1usize];
            __t42 = __x1_1 - __x0_1;
            __t46 = __t39 * __x0_1;
            __t47 = __x0_0 * __t42;
            __t48 = __t47 - __t46;
            __t49 = __t11 * __t48;
            __mu_0 = mu_k[0usize];
            __t138 = __t32 + __t32;
            __t405 = __t32 * __t49;
            __t406 = __t405 + __t405;
            __t407 = __t406 - __mu_0;
            __t409 = __t407 / __t138;
            __t410 = -__t409;
            ::dirac::nalgebra::SVector::<f64, 1usize>::from([__t410])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_group_block(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<::dirac::nalgebra::SMatrix<f64, 1usize, 1usize>> {
        let (__p0, __t32, __t138): (f64, f64, f64);
        __p0 = self.h;
        __t32 = 0.5f64 / __p0;
        __t138 = __t32 + __t32;
        ::core::option::Option::Some(
            ::dirac::nalgebra::SMatrix::<f64, 1usize, 1usize>::from_row_slice(&[__t138]),
        )
    }
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
#[automatically_derived]
impl ::dirac::runtime::Reduced<::dirac::runtime::Minus, 3usize, 1usize, 4usize>
for ChargedParticle {
    type Linear = ::dirac::runtime::Lu<4usize>;
    fn linear_solver(&self) -> ::dirac::runtime::Lu<4usize> {
        ::dirac::runtime::Lu::empty()
    }
    #[allow(unused_variables)]
    fn reduced_lagrangian(
        &self,
        x0: &::dirac::nalgebra::SVector<f64, 3usize>,
        x1: &::dirac::nalgebra::SVector<f64, 3usize>,
        u: &::dirac::nalgebra::SVector<f64, 1usize>,
    ) -> f64 {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __t53,
            __t54,
            __t55,
            __t56,
            __t57,
            __t58,
            __g0_0,
            __t201,
            __t202,
            __t203,
            __t204,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = x1[0usize];
        __x0_0 = x0[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = x1[1usize];
        __x0_1 = x0[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = x1[2usize];
        __x0_2 = x0[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __t53 = __t39 * __t39;
        __t54 = __t42 * __t42;
        __t55 = __t53 + __t54;
        __t56 = __t45 * __t45;
        __t57 = __t55 + __t56;
        __t58 = __t25 * __t57;
        __g0_0 = u[0usize];
        __t201 = __t49 - __g0_0;
        __t202 = __t32 * __t201;
        __t203 = __t201 * __t202;
        __t204 = __t58 + __t203;
        __t204
    }
    #[inline]
    fn residual(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __t64,
            __t65,
            __t66,
            __t67,
            __t68,
            __t69,
            __w_0,
            __t76,
            __t77,
            __t78,
            __t79,
            __t80,
            __t81,
            __t82,
            __w_1,
            __t89,
            __t90,
            __t91,
            __w_2,
            __t93,
            __mu_0,
            __g0_0,
            __t201,
            __t202,
            __t205,
            __t206,
            __t207,
            __t208,
            __t209,
            __t210,
            __t211,
            __t212,
            __t213,
            __t214,
            __t216,
            __t217,
            __t218,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __t64 = __x0_1 + __t42;
        __t65 = __t11 * __t64;
        __t66 = -__t39;
        __t67 = __t66 - __t39;
        __t68 = __t25 * __t67;
        __t69 = __t32 * __t65;
        __w_0 = w_k[0usize];
        __t76 = -__x0_0;
        __t77 = __t76 - __t39;
        __t78 = __t11 * __t77;
        __t79 = -__t42;
        __t80 = __t79 - __t42;
        __t81 = __t25 * __t80;
        __t82 = __t32 * __t78;
        __w_1 = w_k[1usize];
        __t89 = -__t45;
        __t90 = __t89 - __t45;
        __t91 = __t25 * __t90;
        __w_2 = w_k[2usize];
        __t93 = __t91 + __w_2;
        __mu_0 = mu_k[0usize];
        __g0_0 = z[3usize];
        __t201 = __t49 - __g0_0;
        __t202 = __t32 * __t201;
        __t205 = __t65 * __t202;
        __t206 = __t69 * __t201;
        __t207 = __t205 + __t206;
        __t208 = __t68 + __t207;
        __t209 = __w_0 + __t208;
        __t210 = __t78 * __t202;
        __t211 = __t82 * __t201;
        __t212 = __t210 + __t211;
        __t213 = __t81 + __t212;
        __t214 = __w_1 + __t213;
        __t216 = -__t202;
        __t217 = __t216 - __t202;
        __t218 = __mu_0 + __t217;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t209, __t214, __t93, __t218])
    }
    #[inline]
    fn residual_jacobian(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> (
        ::dirac::nalgebra::SVector<f64, 4usize>,
        ::dirac::nalgebra::SMatrix<f64, 4usize, 4usize>,
    ) {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __t64,
            __t65,
            __t66,
            __t67,
            __t68,
            __t69,
            __w_0,
            __t76,
            __t77,
            __t78,
            __t79,
            __t80,
            __t81,
            __t82,
            __w_1,
            __t89,
            __t90,
            __t91,
            __w_2,
            __t93,
            __mu_0,
            __t97,
            __t99,
            __t102,
            __t103,
            __t104,
            __t105,
            __t107,
            __t108,
            __t110,
            __t112,
            __t117,
            __t124,
            __t125,
            __t126,
            __t128,
            __t131,
            __t132,
            __t133,
            __t134,
            __t138,
            __g0_0,
            __t201,
            __t202,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __t64 = __x0_1 + __t42;
        __t65 = __t11 * __t64;
        __t66 = -__t39;
        __t67 = __t66 - __t39;
        __t68 = __t25 * __t67;
        __t69 = __t32 * __t65;
        __w_0 = w_k[0usize];
        __t76 = -__x0_0;
        __t77 = __t76 - __t39;
        __t78 = __t11 * __t77;
        __t79 = -__t42;
        __t80 = __t79 - __t42;
        __t81 = __t25 * __t80;
        __t82 = __t32 * __t78;
        __w_1 = w_k[1usize];
        __t89 = -__t45;
        __t90 = __t89 - __t45;
        __t91 = __t25 * __t90;
        __w_2 = w_k[2usize];
        __t93 = __t91 + __w_2;
        __mu_0 = mu_k[0usize];
        __t97 = __t11 * __x0_1;
        __t99 = __t32 * __t97;
        __t102 = __t25 * (-2f64);
        __t103 = __t65 * __t99;
        __t104 = -__t103;
        __t105 = __t69 * __t97;
        __t107 = __t104 - __t105;
        __t108 = __t102 + __t107;
        __t110 = __t11 * __t32;
        __t112 = __t78 * __t99;
        __t117 = __t82 * __t97;
        __t124 = __t11 * __x0_0;
        __t125 = __t32 * __t124;
        __t126 = __t65 * __t125;
        __t128 = __t69 * __t124;
        __t131 = __t78 * __t125;
        __t132 = __t82 * __t124;
        __t133 = __t131 + __t132;
        __t134 = __t102 + __t133;
        __t138 = __t32 + __t32;
        __g0_0 = z[3usize];
        __t201 = __t49 - __g0_0;
        __t202 = __t32 * __t201;
        let (
            __t205,
            __t206,
            __t207,
            __t208,
            __t209,
            __t210,
            __t211,
            __t212,
            __t213,
            __t214,
            __t216,
            __t217,
            __t218,
            __t219,
            __t220,
            __t221,
            __t222,
            __t223,
            __t224,
            __t225,
            __t226,
            __t227,
            __t228,
            __t229,
            __t230,
            __t231,
            __t232,
            __t233,
            __t234,
            __t235,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __t205 = __t65 * __t202;
        __t206 = __t69 * __t201;
        __t207 = __t205 + __t206;
        __t208 = __t68 + __t207;
        __t209 = __w_0 + __t208;
        __t210 = __t78 * __t202;
        __t211 = __t82 * __t201;
        __t212 = __t210 + __t211;
        __t213 = __t81 + __t212;
        __t214 = __w_1 + __t213;
        __t216 = -__t202;
        __t217 = __t216 - __t202;
        __t218 = __mu_0 + __t217;
        __t219 = __t11 * __t202;
        __t220 = -__t219;
        __t221 = __t220 - __t112;
        __t222 = __t110 * __t201;
        __t223 = -__t222;
        __t224 = __t223 - __t117;
        __t225 = __t221 + __t224;
        __t226 = __t99 + __t99;
        __t227 = __t126 + __t219;
        __t228 = __t128 + __t222;
        __t229 = __t227 + __t228;
        __t230 = -__t125;
        __t231 = __t230 - __t125;
        __t232 = -__t69;
        __t233 = __t232 - __t69;
        __t234 = -__t82;
        __t235 = __t234 - __t82;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t209, __t214, __t93, __t218]),
            {
                let mut __jac = ::dirac::nalgebra::SMatrix::<
                    f64,
                    4usize,
                    4usize,
                >::zeros();
                __jac[(0usize, 0usize)] = __t108;
                __jac[(0usize, 1usize)] = __t229;
                __jac[(0usize, 3usize)] = __t233;
                __jac[(1usize, 0usize)] = __t225;
                __jac[(1usize, 1usize)] = __t134;
                __jac[(1usize, 3usize)] = __t235;
                __jac[(2usize, 2usize)] = __t102;
                __jac[(3usize, 0usize)] = __t226;
                __jac[(3usize, 1usize)] = __t231;
                __jac[(3usize, 3usize)] = __t138;
                __jac
            },
        )
    }
    #[inline]
    fn momentum(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 3usize> {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __t97,
            __t99,
            __t124,
            __t125,
            __t139,
            __t140,
            __t147,
            __t148,
            __t153,
            __t154,
            __g0_0,
            __t201,
            __t202,
            __t236,
            __t237,
            __t238,
            __t240,
            __t241,
            __t242,
            __t243,
            __t244,
            __t245,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __t97 = __t11 * __x0_1;
        __t99 = __t32 * __t97;
        __t124 = __t11 * __x0_0;
        __t125 = __t32 * __t124;
        __t139 = __t39 + __t39;
        __t140 = __t25 * __t139;
        __t147 = __t42 + __t42;
        __t148 = __t25 * __t147;
        __t153 = __t45 + __t45;
        __t154 = __t25 * __t153;
        __g0_0 = z[3usize];
        __t201 = __t49 - __g0_0;
        __t202 = __t32 * __t201;
        __t236 = __t97 * __t202;
        __t237 = -__t236;
        __t238 = __t99 * __t201;
        __t240 = __t237 - __t238;
        __t241 = __t140 + __t240;
        __t242 = __t124 * __t202;
        __t243 = __t125 * __t201;
        __t244 = __t242 + __t243;
        __t245 = __t148 + __t244;
        ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t241, __t245, __t154])
    }
    #[inline]
    #[allow(unused_variables)]
    fn residual_momentum(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> (
        ::dirac::nalgebra::SVector<f64, 4usize>,
        ::dirac::nalgebra::SVector<f64, 3usize>,
    ) {
        let (
            __p2,
            __t11,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __x1_0,
            __x0_0,
            __t39,
            __x1_1,
            __x0_1,
            __t42,
            __x1_2,
            __x0_2,
            __t45,
            __t46,
            __t47,
            __t48,
            __t49,
            __t64,
            __t65,
            __t66,
            __t67,
            __t68,
            __t69,
            __w_0,
            __t76,
            __t77,
            __t78,
            __t79,
            __t80,
            __t81,
            __t82,
            __w_1,
            __t89,
            __t90,
            __t91,
            __w_2,
            __t93,
            __mu_0,
            __t97,
            __t99,
            __t124,
            __t125,
            __t139,
            __t140,
            __t147,
            __t148,
            __t153,
            __t154,
            __g0_0,
            __t201,
            __t202,
            __t205,
            __t206,
            __t207,
            __t208,
            __t209,
            __t210,
            __t211,
            __t212,
            __t213,
            __t214,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __x1_0 = z[0usize];
        __x0_0 = x_k[0usize];
        __t39 = __x1_0 - __x0_0;
        __x1_1 = z[1usize];
        __x0_1 = x_k[1usize];
        __t42 = __x1_1 - __x0_1;
        __x1_2 = z[2usize];
        __x0_2 = x_k[2usize];
        __t45 = __x1_2 - __x0_2;
        __t46 = __t39 * __x0_1;
        __t47 = __x0_0 * __t42;
        __t48 = __t47 - __t46;
        __t49 = __t11 * __t48;
        __t64 = __x0_1 + __t42;
        __t65 = __t11 * __t64;
        __t66 = -__t39;
        __t67 = __t66 - __t39;
        __t68 = __t25 * __t67;
        __t69 = __t32 * __t65;
        __w_0 = w_k[0usize];
        __t76 = -__x0_0;
        __t77 = __t76 - __t39;
        __t78 = __t11 * __t77;
        __t79 = -__t42;
        __t80 = __t79 - __t42;
        __t81 = __t25 * __t80;
        __t82 = __t32 * __t78;
        __w_1 = w_k[1usize];
        __t89 = -__t45;
        __t90 = __t89 - __t45;
        __t91 = __t25 * __t90;
        __w_2 = w_k[2usize];
        __t93 = __t91 + __w_2;
        __mu_0 = mu_k[0usize];
        __t97 = __t11 * __x0_1;
        __t99 = __t32 * __t97;
        __t124 = __t11 * __x0_0;
        __t125 = __t32 * __t124;
        __t139 = __t39 + __t39;
        __t140 = __t25 * __t139;
        __t147 = __t42 + __t42;
        __t148 = __t25 * __t147;
        __t153 = __t45 + __t45;
        __t154 = __t25 * __t153;
        __g0_0 = z[3usize];
        __t201 = __t49 - __g0_0;
        __t202 = __t32 * __t201;
        __t205 = __t65 * __t202;
        __t206 = __t69 * __t201;
        __t207 = __t205 + __t206;
        __t208 = __t68 + __t207;
        __t209 = __w_0 + __t208;
        __t210 = __t78 * __t202;
        __t211 = __t82 * __t201;
        __t212 = __t210 + __t211;
        __t213 = __t81 + __t212;
        __t214 = __w_1 + __t213;
        let (
            __t216,
            __t217,
            __t218,
            __t236,
            __t237,
            __t238,
            __t240,
            __t241,
            __t242,
            __t243,
            __t244,
            __t245,
        ): (f64, f64, f64, f64, f64, f64, f64, f64, f64, f64, f64, f64);
        __t216 = -__t202;
        __t217 = __t216 - __t202;
        __t218 = __mu_0 + __t217;
        __t236 = __t97 * __t202;
        __t237 = -__t236;
        __t238 = __t99 * __t201;
        __t240 = __t237 - __t238;
        __t241 = __t140 + __t240;
        __t242 = __t124 * __t202;
        __t243 = __t125 * __t201;
        __t244 = __t242 + __t243;
        __t245 = __t148 + __t244;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t209, __t214, __t93, __t218]),
            ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t241, __t245, __t154]),
        )
    }
    const ELIMINATES_GROUP: bool = true;
    const ELIMINATION_PAYS: bool = true;
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_residual(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<::dirac::nalgebra::SVector<f64, 3usize>> {
        ::core::option::Option::Some({
            let (
                __p2,
                __t11,
                __p1,
                __t23,
                __p0,
                __t25,
                __t32,
                __x1_0,
                __x0_0,
                __t39,
                __x1_1,
                __x0_1,
                __t42,
                __x1_2,
                __x0_2,
                __t45,
                __t46,
                __t47,
                __t48,
                __t49,
                __t64,
                __t65,
                __t66,
                __t67,
                __t68,
                __t69,
                __w_0,
                __t76,
                __t77,
                __t78,
                __t79,
                __t80,
                __t81,
                __t82,
                __w_1,
                __t89,
                __t90,
                __t91,
                __w_2,
                __t93,
                __mu_0,
                __t138,
                __t405,
                __t500,
                __t501,
                __t502,
                __t504,
                __t506,
                __t507,
                __t508,
                __t509,
                __t510,
                __t511,
                __t512,
                __t513,
                __t514,
                __t515,
                __t516,
                __t517,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __p2 = self.b0;
            __t11 = 0.5f64 * __p2;
            __p1 = self.m;
            __t23 = 0.5f64 * __p1;
            __p0 = self.h;
            __t25 = __t23 / __p0;
            __t32 = 0.5f64 / __p0;
            __x1_0 = z[0usize];
            __x0_0 = x_k[0usize];
            __t39 = __x1_0 - __x0_0;
            __x1_1 = z[1usize];
            __x0_1 = x_k[1usize];
            __t42 = __x1_1 - __x0_1;
            __x1_2 = z[2usize];
            __x0_2 = x_k[2usize];
            __t45 = __x1_2 - __x0_2;
            __t46 = __t39 * __x0_1;
            __t47 = __x0_0 * __t42;
            __t48 = __t47 - __t46;
            __t49 = __t11 * __t48;
            __t64 = __x0_1 + __t42;
            __t65 = __t11 * __t64;
            __t66 = -__t39;
            __t67 = __t66 - __t39;
            __t68 = __t25 * __t67;
            __t69 = __t32 * __t65;
            __w_0 = w_k[0usize];
            __t76 = -__x0_0;
            __t77 = __t76 - __t39;
            __t78 = __t11 * __t77;
            __t79 = -__t42;
            __t80 = __t79 - __t42;
            __t81 = __t25 * __t80;
            __t82 = __t32 * __t78;
            __w_1 = w_k[1usize];
            __t89 = -__t45;
            __t90 = __t89 - __t45;
            __t91 = __t25 * __t90;
            __w_2 = w_k[2usize];
            __t93 = __t91 + __w_2;
            __mu_0 = mu_k[0usize];
            __t138 = __t32 + __t32;
            __t405 = __t32 * __t49;
            __t500 = -__t405;
            __t501 = __t500 - __t405;
            __t502 = __mu_0 + __t501;
            __t504 = __t502 / __t138;
            __t506 = __t49 + __t504;
            __t507 = __t32 * __t506;
            __t508 = __t65 * __t507;
            __t509 = __t69 * __t506;
            __t510 = __t508 + __t509;
            __t511 = __t68 + __t510;
            __t512 = __w_0 + __t511;
            __t513 = __t78 * __t507;
            __t514 = __t82 * __t506;
            __t515 = __t513 + __t514;
            __t516 = __t81 + __t515;
            __t517 = __w_1 + __t516;
            ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t512, __t517, __t93])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_residual_jacobian(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<
        (
            ::dirac::nalgebra::SVector<f64, 3usize>,
            ::dirac::nalgebra::SMatrix<f64, 3usize, 3usize>,
        ),
    > {
        ::core::option::Option::Some({
            let (
                __p2,
                __t11,
                __p1,
                __t23,
                __p0,
                __t25,
                __t32,
                __x1_0,
                __x0_0,
                __t39,
                __x1_1,
                __x0_1,
                __t42,
                __x1_2,
                __x0_2,
                __t45,
                __t46,
                __t47,
                __t48,
                __t49,
                __t64,
                __t65,
                __t66,
                __t67,
                __t68,
                __t69,
                __w_0,
                __t76,
                __t77,
                __t78,
                __t79,
                __t80,
                __t81,
                __t82,
                __w_1,
                __t89,
                __t90,
                __t91,
                __w_2,
                __t93,
                __mu_0,
                __t97,
                __t99,
                __t102,
                __t110,
                __t124,
                __t125,
                __t138,
                __t226,
                __t230,
                __t231,
                __t405,
                __t500,
                __t501,
                __t502,
                __t504,
                __t506,
                __t507,
                __t508,
                __t509,
                __t510,
                __t511,
                __t512,
                __t513,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __p2 = self.b0;
            __t11 = 0.5f64 * __p2;
            __p1 = self.m;
            __t23 = 0.5f64 * __p1;
            __p0 = self.h;
            __t25 = __t23 / __p0;
            __t32 = 0.5f64 / __p0;
            __x1_0 = z[0usize];
            __x0_0 = x_k[0usize];
            __t39 = __x1_0 - __x0_0;
            __x1_1 = z[1usize];
            __x0_1 = x_k[1usize];
            __t42 = __x1_1 - __x0_1;
            __x1_2 = z[2usize];
            __x0_2 = x_k[2usize];
            __t45 = __x1_2 - __x0_2;
            __t46 = __t39 * __x0_1;
            __t47 = __x0_0 * __t42;
            __t48 = __t47 - __t46;
            __t49 = __t11 * __t48;
            __t64 = __x0_1 + __t42;
            __t65 = __t11 * __t64;
            __t66 = -__t39;
            __t67 = __t66 - __t39;
            __t68 = __t25 * __t67;
            __t69 = __t32 * __t65;
            __w_0 = w_k[0usize];
            __t76 = -__x0_0;
            __t77 = __t76 - __t39;
            __t78 = __t11 * __t77;
            __t79 = -__t42;
            __t80 = __t79 - __t42;
            __t81 = __t25 * __t80;
            __t82 = __t32 * __t78;
            __w_1 = w_k[1usize];
            __t89 = -__t45;
            __t90 = __t89 - __t45;
            __t91 = __t25 * __t90;
            __w_2 = w_k[2usize];
            __t93 = __t91 + __w_2;
            __mu_0 = mu_k[0usize];
            __t97 = __t11 * __x0_1;
            __t99 = __t32 * __t97;
            __t102 = __t25 * (-2f64);
            __t110 = __t11 * __t32;
            __t124 = __t11 * __x0_0;
            __t125 = __t32 * __t124;
            __t138 = __t32 + __t32;
            __t226 = __t99 + __t99;
            __t230 = -__t125;
            __t231 = __t230 - __t125;
            __t405 = __t32 * __t49;
            __t500 = -__t405;
            __t501 = __t500 - __t405;
            __t502 = __mu_0 + __t501;
            __t504 = __t502 / __t138;
            __t506 = __t49 + __t504;
            __t507 = __t32 * __t506;
            __t508 = __t65 * __t507;
            __t509 = __t69 * __t506;
            __t510 = __t508 + __t509;
            __t511 = __t68 + __t510;
            __t512 = __w_0 + __t511;
            __t513 = __t78 * __t507;
            let (
                __t514,
                __t515,
                __t516,
                __t517,
                __t518,
                __t519,
                __t520,
                __t521,
                __t522,
                __t523,
                __t524,
                __t525,
                __t527,
                __t528,
                __t529,
                __t531,
                __t532,
                __t533,
                __t534,
                __t535,
                __t536,
                __t537,
                __t538,
                __t539,
                __t540,
                __t541,
                __t542,
                __t543,
                __t544,
                __t545,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __t514 = __t82 * __t506;
            __t515 = __t513 + __t514;
            __t516 = __t81 + __t515;
            __t517 = __w_1 + __t516;
            __t518 = __t226 / __t138;
            __t519 = __t518 - __t97;
            __t520 = __t32 * __t519;
            __t521 = __t65 * __t520;
            __t522 = __t69 * __t519;
            __t523 = __t521 + __t522;
            __t524 = __t102 + __t523;
            __t525 = __t11 * __t507;
            __t527 = __t78 * __t520;
            __t528 = __t527 - __t525;
            __t529 = __t110 * __t506;
            __t531 = __t82 * __t519;
            __t532 = __t531 - __t529;
            __t533 = __t528 + __t532;
            __t534 = __t231 / __t138;
            __t535 = __t124 + __t534;
            __t536 = __t32 * __t535;
            __t537 = __t65 * __t536;
            __t538 = __t525 + __t537;
            __t539 = __t69 * __t535;
            __t540 = __t529 + __t539;
            __t541 = __t538 + __t540;
            __t542 = __t78 * __t536;
            __t543 = __t82 * __t535;
            __t544 = __t542 + __t543;
            __t545 = __t102 + __t544;
            (
                ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t512, __t517, __t93]),
                {
                    let mut __jac = ::dirac::nalgebra::SMatrix::<
                        f64,
                        3usize,
                        3usize,
                    >::zeros();
                    __jac[(0usize, 0usize)] = __t524;
                    __jac[(0usize, 1usize)] = __t541;
                    __jac[(1usize, 0usize)] = __t533;
                    __jac[(1usize, 1usize)] = __t545;
                    __jac[(2usize, 2usize)] = __t102;
                    __jac
                },
            )
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_group(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<::dirac::nalgebra::SVector<f64, 1usize>> {
        ::core::option::Option::Some({
            let (
                __p2,
                __t11,
                __p0,
                __t32,
                __x1_0,
                __x0_0,
                __t39,
                __x1_1,
                __x0_1,
                __t42,
                __t46,
                __t47,
                __t48,
                __t49,
                __mu_0,
                __t138,
                __t405,
                __t500,
                __t501,
                __t502,
                __t504,
                __t505,
            ): (
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
                f64,
            );
            __p2 = self.b0;
            __t11 = 0.5f64 * __p2;
            __p0 = self.h;
            __t32 = 0.5f64 / __p0;
            __x1_0 = z[0usize];
            __x0_0 = x_k[0usize];
            __t39 = __x1_0 - __x0_0;
            __x1_1 = z[1usize];
            __x0_1 = x_k[1usize];
            __t42 = __x1_1 - __x0_1;
            __t46 = __t39 * __x0_1;
            __t47 = __x0_0 * __t42;
            __t48 = __t47 - __t46;
            __t49 = __t11 * __t48;
            __mu_0 = mu_k[0usize];
            __t138 = __t32 + __t32;
            __t405 = __t32 * __t49;
            __t500 = -__t405;
            __t501 = __t500 - __t405;
            __t502 = __mu_0 + __t501;
            __t504 = __t502 / __t138;
            __t505 = -__t504;
            ::dirac::nalgebra::SVector::<f64, 1usize>::from([__t505])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn eliminated_group_block(
        &self,
        x_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        w_k: &::dirac::nalgebra::SVector<f64, 3usize>,
        mu_k: &::dirac::nalgebra::SVector<f64, 1usize>,
        z: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> ::core::option::Option<::dirac::nalgebra::SMatrix<f64, 1usize, 1usize>> {
        let (__p0, __t32, __t138): (f64, f64, f64);
        __p0 = self.h;
        __t32 = 0.5f64 / __p0;
        __t138 = __t32 + __t32;
        ::core::option::Option::Some(
            ::dirac::nalgebra::SMatrix::<f64, 1usize, 1usize>::from_row_slice(&[__t138]),
        )
    }
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
#[automatically_derived]
impl ::dirac::runtime::Unreduced<3usize, 1usize, 4usize> for ChargedParticle {
    type UnreducedLinear = ::dirac::runtime::Lu<4usize>;
    fn unreduced_linear_solver(&self) -> ::dirac::runtime::Lu<4usize> {
        ::dirac::runtime::Lu::empty()
    }
    #[inline]
    fn unreduced_residual(
        &self,
        q_k: &::dirac::nalgebra::SVector<f64, 4usize>,
        p_k: &::dirac::nalgebra::SVector<f64, 4usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        let (
            __q1_0,
            __q0_0,
            __t2,
            __q1_1,
            __q0_1,
            __t5,
            __q1_2,
            __q0_2,
            __t8,
            __p2,
            __t11,
            __t13,
            __t15,
            __t16,
            __t17,
            __q1_3,
            __q0_3,
            __t20,
            __t21,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __t33,
            __t286,
            __t287,
            __t288,
            __t289,
            __t290,
            __t291,
            __t292,
            __t293,
            __t294,
            __t295,
            __p_0,
            __t297,
            __t298,
            __t299,
            __t300,
            __t301,
            __t302,
            __t303,
            __t304,
            __t305,
            __t306,
            __t307,
            __t308,
            __p_1,
            __t310,
            __t311,
            __t312,
            __t313,
            __p_2,
            __t315,
            __t316,
            __t317,
            __p_3,
            __t319,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __q1_0 = z[0usize];
        __q0_0 = q_k[0usize];
        __t2 = __q1_0 - __q0_0;
        __q1_1 = z[1usize];
        __q0_1 = q_k[1usize];
        __t5 = __q1_1 - __q0_1;
        __q1_2 = z[2usize];
        __q0_2 = q_k[2usize];
        __t8 = __q1_2 - __q0_2;
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __t13 = __t2 * __q0_1;
        __t15 = __q0_0 * __t5;
        __t16 = __t15 - __t13;
        __t17 = __t11 * __t16;
        __q1_3 = z[3usize];
        __q0_3 = q_k[3usize];
        __t20 = __q1_3 - __q0_3;
        __t21 = __t17 + __t20;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __t33 = __t21 * __t32;
        __t286 = __q0_1 + __t5;
        __t287 = __t11 * __t286;
        __t288 = -__t2;
        __t289 = __t288 - __t2;
        __t290 = __t25 * __t289;
        __t291 = __t32 * __t287;
        __t292 = __t33 * __t287;
        __t293 = __t21 * __t291;
        __t294 = __t292 + __t293;
        __t295 = __t290 + __t294;
        __p_0 = p_k[0usize];
        __t297 = __t295 + __p_0;
        __t298 = -__q0_0;
        __t299 = __t298 - __t2;
        __t300 = __t11 * __t299;
        __t301 = -__t5;
        __t302 = __t301 - __t5;
        __t303 = __t25 * __t302;
        __t304 = __t32 * __t300;
        __t305 = __t33 * __t300;
        __t306 = __t21 * __t304;
        __t307 = __t305 + __t306;
        __t308 = __t303 + __t307;
        __p_1 = p_k[1usize];
        __t310 = __t308 + __p_1;
        __t311 = -__t8;
        __t312 = __t311 - __t8;
        __t313 = __t25 * __t312;
        __p_2 = p_k[2usize];
        __t315 = __t313 + __p_2;
        __t316 = -__t33;
        __t317 = __t316 - __t33;
        __p_3 = p_k[3usize];
        __t319 = __t317 + __p_3;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t297, __t310, __t315, __t319])
    }
    #[inline]
    fn unreduced_residual_jacobian(
        &self,
        q_k: &::dirac::nalgebra::SVector<f64, 4usize>,
        p_k: &::dirac::nalgebra::SVector<f64, 4usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> (
        ::dirac::nalgebra::SVector<f64, 4usize>,
        ::dirac::nalgebra::SMatrix<f64, 4usize, 4usize>,
    ) {
        let (
            __q1_0,
            __q0_0,
            __t2,
            __q1_1,
            __q0_1,
            __t5,
            __q1_2,
            __q0_2,
            __t8,
            __p2,
            __t11,
            __t13,
            __t15,
            __t16,
            __t17,
            __q1_3,
            __q0_3,
            __t20,
            __t21,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __t33,
            __t102,
            __t110,
            __t215,
            __t286,
            __t287,
            __t288,
            __t289,
            __t290,
            __t291,
            __t292,
            __t293,
            __t294,
            __t295,
            __p_0,
            __t297,
            __t298,
            __t299,
            __t300,
            __t301,
            __t302,
            __t303,
            __t304,
            __t305,
            __t306,
            __t307,
            __t308,
            __p_1,
            __t310,
            __t311,
            __t312,
            __t313,
            __p_2,
            __t315,
            __t316,
            __t317,
            __p_3,
            __t319,
            __t320,
            __t322,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __q1_0 = z[0usize];
        __q0_0 = q_k[0usize];
        __t2 = __q1_0 - __q0_0;
        __q1_1 = z[1usize];
        __q0_1 = q_k[1usize];
        __t5 = __q1_1 - __q0_1;
        __q1_2 = z[2usize];
        __q0_2 = q_k[2usize];
        __t8 = __q1_2 - __q0_2;
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __t13 = __t2 * __q0_1;
        __t15 = __q0_0 * __t5;
        __t16 = __t15 - __t13;
        __t17 = __t11 * __t16;
        __q1_3 = z[3usize];
        __q0_3 = q_k[3usize];
        __t20 = __q1_3 - __q0_3;
        __t21 = __t17 + __t20;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __t33 = __t21 * __t32;
        __t102 = __t25 * (-2f64);
        __t110 = __t11 * __t32;
        __t215 = -__t32;
        __t286 = __q0_1 + __t5;
        __t287 = __t11 * __t286;
        __t288 = -__t2;
        __t289 = __t288 - __t2;
        __t290 = __t25 * __t289;
        __t291 = __t32 * __t287;
        __t292 = __t33 * __t287;
        __t293 = __t21 * __t291;
        __t294 = __t292 + __t293;
        __t295 = __t290 + __t294;
        __p_0 = p_k[0usize];
        __t297 = __t295 + __p_0;
        __t298 = -__q0_0;
        __t299 = __t298 - __t2;
        __t300 = __t11 * __t299;
        __t301 = -__t5;
        __t302 = __t301 - __t5;
        __t303 = __t25 * __t302;
        __t304 = __t32 * __t300;
        __t305 = __t33 * __t300;
        __t306 = __t21 * __t304;
        __t307 = __t305 + __t306;
        __t308 = __t303 + __t307;
        __p_1 = p_k[1usize];
        __t310 = __t308 + __p_1;
        __t311 = -__t8;
        __t312 = __t311 - __t8;
        __t313 = __t25 * __t312;
        __p_2 = p_k[2usize];
        __t315 = __t313 + __p_2;
        __t316 = -__t33;
        __t317 = __t316 - __t33;
        __p_3 = p_k[3usize];
        __t319 = __t317 + __p_3;
        __t320 = __q0_1 * __t11;
        __t322 = __t32 * __t320;
        let (
            __t324,
            __t325,
            __t326,
            __t328,
            __t329,
            __t330,
            __t331,
            __t332,
            __t334,
            __t335,
            __t336,
            __t337,
            __t339,
            __t340,
            __t341,
            __t342,
            __t343,
            __t344,
            __t345,
            __t346,
            __t347,
            __t348,
            __t349,
            __t350,
            __t351,
            __t352,
            __t353,
            __t354,
            __t355,
            __t356,
            __t357,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __t324 = __t287 * __t322;
        __t325 = -__t324;
        __t326 = __t291 * __t320;
        __t328 = __t325 - __t326;
        __t329 = __t102 + __t328;
        __t330 = __t300 * __t322;
        __t331 = -__t330;
        __t332 = __t11 * __t33;
        __t334 = __t331 - __t332;
        __t335 = __t304 * __t320;
        __t336 = -__t335;
        __t337 = __t21 * __t110;
        __t339 = __t336 - __t337;
        __t340 = __t334 + __t339;
        __t341 = __t322 + __t322;
        __t342 = __q0_0 * __t11;
        __t343 = __t32 * __t342;
        __t344 = __t287 * __t343;
        __t345 = __t332 + __t344;
        __t346 = __t291 * __t342;
        __t347 = __t337 + __t346;
        __t348 = __t345 + __t347;
        __t349 = __t300 * __t343;
        __t350 = __t304 * __t342;
        __t351 = __t349 + __t350;
        __t352 = __t102 + __t351;
        __t353 = -__t343;
        __t354 = __t353 - __t343;
        __t355 = __t291 + __t291;
        __t356 = __t304 + __t304;
        __t357 = __t215 - __t32;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t297, __t310, __t315, __t319]),
            {
                let mut __jac = ::dirac::nalgebra::SMatrix::<
                    f64,
                    4usize,
                    4usize,
                >::zeros();
                __jac[(0usize, 0usize)] = __t329;
                __jac[(0usize, 1usize)] = __t348;
                __jac[(0usize, 3usize)] = __t355;
                __jac[(1usize, 0usize)] = __t340;
                __jac[(1usize, 1usize)] = __t352;
                __jac[(1usize, 3usize)] = __t356;
                __jac[(2usize, 2usize)] = __t102;
                __jac[(3usize, 0usize)] = __t341;
                __jac[(3usize, 1usize)] = __t354;
                __jac[(3usize, 3usize)] = __t357;
                __jac
            },
        )
    }
    #[inline]
    fn unreduced_momentum(
        &self,
        q_k: &::dirac::nalgebra::SVector<f64, 4usize>,
        z: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> ::dirac::nalgebra::SVector<f64, 4usize> {
        let (
            __q1_0,
            __q0_0,
            __t2,
            __q1_1,
            __q0_1,
            __t5,
            __q1_2,
            __q0_2,
            __t8,
            __p2,
            __t11,
            __t13,
            __t15,
            __t16,
            __t17,
            __q1_3,
            __q0_3,
            __t20,
            __t21,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __t33,
            __t320,
            __t322,
            __t342,
            __t343,
            __t358,
            __t359,
            __t360,
            __t361,
            __t362,
            __t364,
            __t365,
            __t366,
            __t367,
            __t368,
            __t369,
            __t370,
            __t371,
            __t372,
            __t373,
            __t374,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __q1_0 = z[0usize];
        __q0_0 = q_k[0usize];
        __t2 = __q1_0 - __q0_0;
        __q1_1 = z[1usize];
        __q0_1 = q_k[1usize];
        __t5 = __q1_1 - __q0_1;
        __q1_2 = z[2usize];
        __q0_2 = q_k[2usize];
        __t8 = __q1_2 - __q0_2;
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __t13 = __t2 * __q0_1;
        __t15 = __q0_0 * __t5;
        __t16 = __t15 - __t13;
        __t17 = __t11 * __t16;
        __q1_3 = z[3usize];
        __q0_3 = q_k[3usize];
        __t20 = __q1_3 - __q0_3;
        __t21 = __t17 + __t20;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __t33 = __t21 * __t32;
        __t320 = __q0_1 * __t11;
        __t322 = __t32 * __t320;
        __t342 = __q0_0 * __t11;
        __t343 = __t32 * __t342;
        __t358 = __t2 + __t2;
        __t359 = __t25 * __t358;
        __t360 = __t33 * __t320;
        __t361 = -__t360;
        __t362 = __t21 * __t322;
        __t364 = __t361 - __t362;
        __t365 = __t359 + __t364;
        __t366 = __t5 + __t5;
        __t367 = __t25 * __t366;
        __t368 = __t33 * __t342;
        __t369 = __t21 * __t343;
        __t370 = __t368 + __t369;
        __t371 = __t367 + __t370;
        __t372 = __t8 + __t8;
        __t373 = __t25 * __t372;
        __t374 = __t33 + __t33;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t365, __t371, __t373, __t374])
    }
}
#[allow(
    clippy::approx_constant,
    reason = "constants folded at compile time (2π = 6.283185307179586) are printed in full, not named"
)]
#[allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    reason = "folded constants are printed with every digit f64 round-trips, without separators"
)]
#[allow(
    clippy::many_single_char_names,
    clippy::similar_names,
    reason = "generated locals and arguments follow the paper's symbols (x_k, w_k, mu_k, z)"
)]
#[allow(
    clippy::too_many_lines,
    clippy::let_and_return,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::unnecessary_cast,
    clippy::float_cmp,
    clippy::suboptimal_flops,
    clippy::imprecise_flops,
    reason = "straight-line code emitted one operation per line, rounding exactly as the user's expression"
)]
#[allow(
    clippy::must_use_candidate,
    clippy::missing_const_for_fn,
    clippy::return_self_not_must_use,
    reason = "accessors of the emitted types; their results are plain values"
)]
#[automatically_derived]
impl ::dirac::runtime::LagrangianHessian<3usize, 1usize, 4usize> for ChargedParticle {
    #[allow(unused_variables)]
    fn lagrangian_hessian(
        &self,
        q0: &::dirac::nalgebra::SVector<f64, 4usize>,
        q1: &::dirac::nalgebra::SVector<f64, 4usize>,
    ) -> (
        ::dirac::nalgebra::SMatrix<f64, 4usize, 4usize>,
        ::dirac::nalgebra::SMatrix<f64, 4usize, 4usize>,
        ::dirac::nalgebra::SMatrix<f64, 4usize, 4usize>,
    ) {
        let (
            __q1_0,
            __q0_0,
            __t2,
            __q1_1,
            __q0_1,
            __t5,
            __p2,
            __t11,
            __t13,
            __t15,
            __t16,
            __t17,
            __q1_3,
            __q0_3,
            __t20,
            __t21,
            __p1,
            __t23,
            __p0,
            __t25,
            __t32,
            __t33,
            __t102,
            __t110,
            __t138,
            __t215,
            __t286,
            __t287,
            __t291,
            __t298,
            __t299,
            __t300,
            __t304,
            __t320,
            __t322,
            __t323,
            __t324,
            __t325,
            __t326,
            __t328,
            __t329,
            __t330,
            __t331,
            __t332,
            __t334,
            __t335,
            __t336,
            __t337,
            __t339,
            __t340,
            __t341,
            __t342,
            __t343,
            __t344,
            __t345,
            __t346,
            __t347,
            __t348,
            __t349,
            __t350,
            __t351,
            __t352,
            __t353,
            __t354,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __q1_0 = q1[0usize];
        __q0_0 = q0[0usize];
        __t2 = __q1_0 - __q0_0;
        __q1_1 = q1[1usize];
        __q0_1 = q0[1usize];
        __t5 = __q1_1 - __q0_1;
        __p2 = self.b0;
        __t11 = 0.5f64 * __p2;
        __t13 = __t2 * __q0_1;
        __t15 = __q0_0 * __t5;
        __t16 = __t15 - __t13;
        __t17 = __t11 * __t16;
        __q1_3 = q1[3usize];
        __q0_3 = q0[3usize];
        __t20 = __q1_3 - __q0_3;
        __t21 = __t17 + __t20;
        __p1 = self.m;
        __t23 = 0.5f64 * __p1;
        __p0 = self.h;
        __t25 = __t23 / __p0;
        __t32 = 0.5f64 / __p0;
        __t33 = __t21 * __t32;
        __t102 = __t25 * (-2f64);
        __t110 = __t11 * __t32;
        __t138 = __t32 + __t32;
        __t215 = -__t32;
        __t286 = __q0_1 + __t5;
        __t287 = __t11 * __t286;
        __t291 = __t32 * __t287;
        __t298 = -__q0_0;
        __t299 = __t298 - __t2;
        __t300 = __t11 * __t299;
        __t304 = __t32 * __t300;
        __t320 = __q0_1 * __t11;
        __t322 = __t32 * __t320;
        __t323 = -__t322;
        __t324 = __t287 * __t322;
        __t325 = -__t324;
        __t326 = __t291 * __t320;
        __t328 = __t325 - __t326;
        __t329 = __t102 + __t328;
        __t330 = __t300 * __t322;
        __t331 = -__t330;
        __t332 = __t11 * __t33;
        __t334 = __t331 - __t332;
        __t335 = __t304 * __t320;
        __t336 = -__t335;
        __t337 = __t21 * __t110;
        __t339 = __t336 - __t337;
        __t340 = __t334 + __t339;
        __t341 = __t322 + __t322;
        __t342 = __q0_0 * __t11;
        __t343 = __t32 * __t342;
        __t344 = __t287 * __t343;
        __t345 = __t332 + __t344;
        __t346 = __t291 * __t342;
        __t347 = __t337 + __t346;
        __t348 = __t345 + __t347;
        __t349 = __t300 * __t343;
        __t350 = __t304 * __t342;
        __t351 = __t349 + __t350;
        __t352 = __t102 + __t351;
        __t353 = -__t343;
        __t354 = __t353 - __t343;
        let (
            __t355,
            __t356,
            __t357,
            __t376,
            __t377,
            __t378,
            __t379,
            __t380,
            __t381,
            __t382,
            __t383,
            __t384,
            __t385,
            __t386,
            __t387,
            __t388,
            __t389,
            __t390,
            __t392,
            __t393,
            __t394,
            __t395,
            __t396,
            __t397,
            __t398,
            __t399,
            __t400,
            __t401,
            __t402,
            __t403,
            __t404,
        ): (
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
            f64,
        );
        __t355 = __t291 + __t291;
        __t356 = __t304 + __t304;
        __t357 = __t215 - __t32;
        __t376 = __t25 * 2f64;
        __t377 = __t287 * __t291;
        __t378 = __t377 + __t377;
        __t379 = __t376 + __t378;
        __t380 = __t291 * __t300;
        __t381 = __t287 * __t304;
        __t382 = __t380 + __t381;
        __t383 = -__t291;
        __t384 = __t383 - __t291;
        __t385 = __t300 * __t304;
        __t386 = __t385 + __t385;
        __t387 = __t376 + __t386;
        __t388 = -__t304;
        __t389 = __t388 - __t304;
        __t390 = __t320 * __t322;
        __t392 = __t390 + __t390;
        __t393 = __t376 + __t392;
        __t394 = __t322 * __t342;
        __t395 = -__t394;
        __t396 = __t320 * __t343;
        __t397 = -__t396;
        __t398 = __t395 - __t396;
        __t399 = __t323 - __t322;
        __t400 = __t397 - __t394;
        __t401 = __t342 * __t343;
        __t402 = __t401 + __t401;
        __t403 = __t376 + __t402;
        __t404 = __t343 + __t343;
        (
            ::dirac::nalgebra::SMatrix::<
                f64,
                4usize,
                4usize,
            >::from_row_slice(
                &[
                    __t379,
                    __t382,
                    0f64,
                    __t384,
                    __t382,
                    __t387,
                    0f64,
                    __t389,
                    0f64,
                    0f64,
                    __t376,
                    0f64,
                    __t384,
                    __t389,
                    0f64,
                    __t138,
                ],
            ),
            ::dirac::nalgebra::SMatrix::<
                f64,
                4usize,
                4usize,
            >::from_row_slice(
                &[
                    __t329,
                    __t348,
                    0f64,
                    __t355,
                    __t340,
                    __t352,
                    0f64,
                    __t356,
                    0f64,
                    0f64,
                    __t102,
                    0f64,
                    __t341,
                    __t354,
                    0f64,
                    __t357,
                ],
            ),
            ::dirac::nalgebra::SMatrix::<
                f64,
                4usize,
                4usize,
            >::from_row_slice(
                &[
                    __t393,
                    __t400,
                    0f64,
                    __t399,
                    __t398,
                    __t403,
                    0f64,
                    __t404,
                    0f64,
                    0f64,
                    __t376,
                    0f64,
                    __t399,
                    __t404,
                    0f64,
                    __t138,
                ],
            ),
        )
    }
}
