///A configuration of [`ChargedParticle`]: shape coordinates (`x`, `y`, `z`) then group coordinates (`theta`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChargedParticleConfig {
    ///The coordinate `x`.
    pub x: f64,
    ///The coordinate `y`.
    pub y: f64,
    ///The coordinate `z`.
    pub z: f64,
    ///The coordinate `theta`.
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
    ///The parameter `h` of [`charged_particle`].
    pub h: f64,
    ///The parameter `m` of [`charged_particle`].
    pub m: f64,
    ///The parameter `b0` of [`charged_particle`].
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
    /// Number of shape coordinates `S` (the first const parameter of the system
    /// traits, and the length of `ReducedState::x`).
    pub const SHAPE_DIM: usize = 3usize;
    /// Number of group coordinates `K` (the second const parameter of the system
    /// traits, and the length of `ReducedState::mu`).
    pub const GROUP_DIM: usize = 1usize;
    /// Number of configuration coordinates `N = S + K` (the third const
    /// parameter of the system traits, and the length of `UnreducedState::q`).
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
impl ::dirac::runtime::System for ChargedParticle {
    const PARAMETERS: &'static [&'static str] = &["h", "m", "b0"];
    const CONTROLS: &'static [&'static str] = &[];
    fn parameter_values(&self) -> ::std::vec::Vec<f64> {
        ::std::vec![self.h, self.m, self.b0]
    }
    fn time_step(&self) -> f64 {
        self.h
    }
    fn with_time_step(&self, h: f64) -> Self {
        let mut system = *self;
        system.h = h;
        system
    }
    #[allow(unused_variables, reason = "a system without controls ignores `u`")]
    fn with_controls(&self, u: &[f64]) -> Self {
        *self
    }
    fn coordinate_names(&self) -> ::std::vec::Vec<&str> {
        ::std::vec!["x", "y", "z", "theta"]
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
impl ::dirac::runtime::DiscreteLagrangian<3usize, 1usize, 4usize> for ChargedParticle {
    const SHAPE: [&'static str; 3usize] = ["x", "y", "z"];
    const GROUP: [&'static str; 1usize] = ["theta"];
    const FORCED: bool = false;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = x1[0usize];
        let __x0_0: f64 = x0[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = x1[1usize];
        let __x0_1: f64 = x0[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = x1[2usize];
        let __x0_2: f64 = x0[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __g1_0: f64 = u[0usize];
        let __t52: f64 = __t49 + __g1_0;
        let __t53: f64 = __t39 * __t39;
        let __t54: f64 = __t42 * __t42;
        let __t55: f64 = __t53 + __t54;
        let __t56: f64 = __t45 * __t45;
        let __t57: f64 = __t55 + __t56;
        let __t58: f64 = __t25 * __t57;
        let __t59: f64 = __t32 * __t52;
        let __t60: f64 = __t52 * __t59;
        let __t61: f64 = __t58 + __t60;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __g1_0: f64 = z[3usize];
        let __t52: f64 = __t49 + __g1_0;
        let __t59: f64 = __t32 * __t52;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __t70: f64 = __t59 * __t65;
        let __t71: f64 = __t52 * __t69;
        let __t72: f64 = __t70 + __t71;
        let __t73: f64 = __t68 + __t72;
        let __w_0: f64 = w_k[0usize];
        let __t75: f64 = __t73 + __w_0;
        let __t76: f64 = -__x0_0;
        let __t77: f64 = __t76 - __t39;
        let __t78: f64 = __t11 * __t77;
        let __t79: f64 = -__t42;
        let __t80: f64 = __t79 - __t42;
        let __t81: f64 = __t25 * __t80;
        let __t82: f64 = __t32 * __t78;
        let __t83: f64 = __t59 * __t78;
        let __t84: f64 = __t52 * __t82;
        let __t85: f64 = __t83 + __t84;
        let __t86: f64 = __t81 + __t85;
        let __w_1: f64 = w_k[1usize];
        let __t88: f64 = __t86 + __w_1;
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __t94: f64 = __t59 + __t59;
        let __mu_0: f64 = mu_k[0usize];
        let __t96: f64 = __t94 - __mu_0;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __g1_0: f64 = z[3usize];
        let __t52: f64 = __t49 + __g1_0;
        let __t59: f64 = __t32 * __t52;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __t70: f64 = __t59 * __t65;
        let __t71: f64 = __t52 * __t69;
        let __t72: f64 = __t70 + __t71;
        let __t73: f64 = __t68 + __t72;
        let __w_0: f64 = w_k[0usize];
        let __t75: f64 = __t73 + __w_0;
        let __t76: f64 = -__x0_0;
        let __t77: f64 = __t76 - __t39;
        let __t78: f64 = __t11 * __t77;
        let __t79: f64 = -__t42;
        let __t80: f64 = __t79 - __t42;
        let __t81: f64 = __t25 * __t80;
        let __t82: f64 = __t32 * __t78;
        let __t83: f64 = __t59 * __t78;
        let __t84: f64 = __t52 * __t82;
        let __t85: f64 = __t83 + __t84;
        let __t86: f64 = __t81 + __t85;
        let __w_1: f64 = w_k[1usize];
        let __t88: f64 = __t86 + __w_1;
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __t94: f64 = __t59 + __t59;
        let __mu_0: f64 = mu_k[0usize];
        let __t96: f64 = __t94 - __mu_0;
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t32 * __t97;
        let __t100: f64 = -__t99;
        let __t102: f64 = __t25 * (-2f64);
        let __t103: f64 = __t65 * __t99;
        let __t104: f64 = -__t103;
        let __t105: f64 = __t69 * __t97;
        let __t107: f64 = __t104 - __t105;
        let __t108: f64 = __t102 + __t107;
        let __t110: f64 = __t11 * __t32;
        let __t112: f64 = __t78 * __t99;
        let __t113: f64 = -__t112;
        let __t114: f64 = __t11 * __t59;
        let __t116: f64 = __t113 - __t114;
        let __t117: f64 = __t82 * __t97;
        let __t118: f64 = -__t117;
        let __t119: f64 = __t52 * __t110;
        let __t121: f64 = __t118 - __t119;
        let __t122: f64 = __t116 + __t121;
        let __t123: f64 = __t100 - __t99;
        let __t124: f64 = __t11 * __x0_0;
        let __t125: f64 = __t32 * __t124;
        let __t126: f64 = __t65 * __t125;
        let __t127: f64 = __t114 + __t126;
        let __t128: f64 = __t69 * __t124;
        let __t129: f64 = __t119 + __t128;
        let __t130: f64 = __t127 + __t129;
        let __t131: f64 = __t78 * __t125;
        let __t132: f64 = __t82 * __t124;
        let __t133: f64 = __t131 + __t132;
        let __t134: f64 = __t102 + __t133;
        let __t135: f64 = __t125 + __t125;
        let __t136: f64 = __t69 + __t69;
        let __t137: f64 = __t82 + __t82;
        let __t138: f64 = __t32 + __t32;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __g1_0: f64 = z[3usize];
        let __t52: f64 = __t49 + __g1_0;
        let __t59: f64 = __t32 * __t52;
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t32 * __t97;
        let __t124: f64 = __t11 * __x0_0;
        let __t125: f64 = __t32 * __t124;
        let __t139: f64 = __t39 + __t39;
        let __t140: f64 = __t25 * __t139;
        let __t141: f64 = __t59 * __t97;
        let __t142: f64 = -__t141;
        let __t143: f64 = __t52 * __t99;
        let __t145: f64 = __t142 - __t143;
        let __t146: f64 = __t140 + __t145;
        let __t147: f64 = __t42 + __t42;
        let __t148: f64 = __t25 * __t147;
        let __t149: f64 = __t59 * __t124;
        let __t150: f64 = __t52 * __t125;
        let __t151: f64 = __t149 + __t150;
        let __t152: f64 = __t148 + __t151;
        let __t153: f64 = __t45 + __t45;
        let __t154: f64 = __t25 * __t153;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __g1_0: f64 = z[3usize];
        let __t52: f64 = __t49 + __g1_0;
        let __t59: f64 = __t32 * __t52;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __t70: f64 = __t59 * __t65;
        let __t71: f64 = __t52 * __t69;
        let __t72: f64 = __t70 + __t71;
        let __t73: f64 = __t68 + __t72;
        let __w_0: f64 = w_k[0usize];
        let __t75: f64 = __t73 + __w_0;
        let __t76: f64 = -__x0_0;
        let __t77: f64 = __t76 - __t39;
        let __t78: f64 = __t11 * __t77;
        let __t79: f64 = -__t42;
        let __t80: f64 = __t79 - __t42;
        let __t81: f64 = __t25 * __t80;
        let __t82: f64 = __t32 * __t78;
        let __t83: f64 = __t59 * __t78;
        let __t84: f64 = __t52 * __t82;
        let __t85: f64 = __t83 + __t84;
        let __t86: f64 = __t81 + __t85;
        let __w_1: f64 = w_k[1usize];
        let __t88: f64 = __t86 + __w_1;
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __t94: f64 = __t59 + __t59;
        let __mu_0: f64 = mu_k[0usize];
        let __t96: f64 = __t94 - __mu_0;
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t32 * __t97;
        let __t124: f64 = __t11 * __x0_0;
        let __t125: f64 = __t32 * __t124;
        let __t139: f64 = __t39 + __t39;
        let __t140: f64 = __t25 * __t139;
        let __t141: f64 = __t59 * __t97;
        let __t142: f64 = -__t141;
        let __t143: f64 = __t52 * __t99;
        let __t145: f64 = __t142 - __t143;
        let __t146: f64 = __t140 + __t145;
        let __t147: f64 = __t42 + __t42;
        let __t148: f64 = __t25 * __t147;
        let __t149: f64 = __t59 * __t124;
        let __t150: f64 = __t52 * __t125;
        let __t151: f64 = __t149 + __t150;
        let __t152: f64 = __t148 + __t151;
        let __t153: f64 = __t45 + __t45;
        let __t154: f64 = __t25 * __t153;
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
            let __p2: f64 = self.b0;
            let __t11: f64 = 0.5f64 * __p2;
            let __p1: f64 = self.m;
            let __t23: f64 = 0.5f64 * __p1;
            let __p0: f64 = self.h;
            let __t25: f64 = __t23 / __p0;
            let __t32: f64 = 0.5f64 / __p0;
            let __x1_0: f64 = z[0usize];
            let __x0_0: f64 = x_k[0usize];
            let __t39: f64 = __x1_0 - __x0_0;
            let __x1_1: f64 = z[1usize];
            let __x0_1: f64 = x_k[1usize];
            let __t42: f64 = __x1_1 - __x0_1;
            let __x1_2: f64 = z[2usize];
            let __x0_2: f64 = x_k[2usize];
            let __t45: f64 = __x1_2 - __x0_2;
            let __t46: f64 = __t39 * __x0_1;
            let __t47: f64 = __x0_0 * __t42;
            let __t48: f64 = __t47 - __t46;
            let __t49: f64 = __t11 * __t48;
            let __t64: f64 = __x0_1 + __t42;
            let __t65: f64 = __t11 * __t64;
            let __t66: f64 = -__t39;
            let __t67: f64 = __t66 - __t39;
            let __t68: f64 = __t25 * __t67;
            let __t69: f64 = __t32 * __t65;
            let __w_0: f64 = w_k[0usize];
            let __t76: f64 = -__x0_0;
            let __t77: f64 = __t76 - __t39;
            let __t78: f64 = __t11 * __t77;
            let __t79: f64 = -__t42;
            let __t80: f64 = __t79 - __t42;
            let __t81: f64 = __t25 * __t80;
            let __t82: f64 = __t32 * __t78;
            let __w_1: f64 = w_k[1usize];
            let __t89: f64 = -__t45;
            let __t90: f64 = __t89 - __t45;
            let __t91: f64 = __t25 * __t90;
            let __w_2: f64 = w_k[2usize];
            let __t93: f64 = __t91 + __w_2;
            let __mu_0: f64 = mu_k[0usize];
            let __t138: f64 = __t32 + __t32;
            let __t405: f64 = __t32 * __t49;
            let __t406: f64 = __t405 + __t405;
            let __t407: f64 = __t406 - __mu_0;
            let __t409: f64 = __t407 / __t138;
            let __t411: f64 = __t49 - __t409;
            let __t412: f64 = __t32 * __t411;
            let __t413: f64 = __t65 * __t412;
            let __t414: f64 = __t69 * __t411;
            let __t415: f64 = __t413 + __t414;
            let __t416: f64 = __t68 + __t415;
            let __t417: f64 = __w_0 + __t416;
            let __t418: f64 = __t78 * __t412;
            let __t419: f64 = __t82 * __t411;
            let __t420: f64 = __t418 + __t419;
            let __t421: f64 = __t81 + __t420;
            let __t422: f64 = __w_1 + __t421;
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
            let __p2: f64 = self.b0;
            let __t11: f64 = 0.5f64 * __p2;
            let __p1: f64 = self.m;
            let __t23: f64 = 0.5f64 * __p1;
            let __p0: f64 = self.h;
            let __t25: f64 = __t23 / __p0;
            let __t32: f64 = 0.5f64 / __p0;
            let __x1_0: f64 = z[0usize];
            let __x0_0: f64 = x_k[0usize];
            let __t39: f64 = __x1_0 - __x0_0;
            let __x1_1: f64 = z[1usize];
            let __x0_1: f64 = x_k[1usize];
            let __t42: f64 = __x1_1 - __x0_1;
            let __x1_2: f64 = z[2usize];
            let __x0_2: f64 = x_k[2usize];
            let __t45: f64 = __x1_2 - __x0_2;
            let __t46: f64 = __t39 * __x0_1;
            let __t47: f64 = __x0_0 * __t42;
            let __t48: f64 = __t47 - __t46;
            let __t49: f64 = __t11 * __t48;
            let __t64: f64 = __x0_1 + __t42;
            let __t65: f64 = __t11 * __t64;
            let __t66: f64 = -__t39;
            let __t67: f64 = __t66 - __t39;
            let __t68: f64 = __t25 * __t67;
            let __t69: f64 = __t32 * __t65;
            let __w_0: f64 = w_k[0usize];
            let __t76: f64 = -__x0_0;
            let __t77: f64 = __t76 - __t39;
            let __t78: f64 = __t11 * __t77;
            let __t79: f64 = -__t42;
            let __t80: f64 = __t79 - __t42;
            let __t81: f64 = __t25 * __t80;
            let __t82: f64 = __t32 * __t78;
            let __w_1: f64 = w_k[1usize];
            let __t89: f64 = -__t45;
            let __t90: f64 = __t89 - __t45;
            let __t91: f64 = __t25 * __t90;
            let __w_2: f64 = w_k[2usize];
            let __t93: f64 = __t91 + __w_2;
            let __mu_0: f64 = mu_k[0usize];
            let __t97: f64 = __t11 * __x0_1;
            let __t98: f64 = -__t97;
            let __t99: f64 = __t32 * __t97;
            let __t100: f64 = -__t99;
            let __t102: f64 = __t25 * (-2f64);
            let __t110: f64 = __t11 * __t32;
            let __t123: f64 = __t100 - __t99;
            let __t124: f64 = __t11 * __x0_0;
            let __t125: f64 = __t32 * __t124;
            let __t135: f64 = __t125 + __t125;
            let __t138: f64 = __t32 + __t32;
            let __t405: f64 = __t32 * __t49;
            let __t406: f64 = __t405 + __t405;
            let __t407: f64 = __t406 - __mu_0;
            let __t409: f64 = __t407 / __t138;
            let __t411: f64 = __t49 - __t409;
            let __t412: f64 = __t32 * __t411;
            let __t413: f64 = __t65 * __t412;
            let __t414: f64 = __t69 * __t411;
            let __t415: f64 = __t413 + __t414;
            let __t416: f64 = __t68 + __t415;
            let __t417: f64 = __w_0 + __t416;
            let __t418: f64 = __t78 * __t412;
            let __t419: f64 = __t82 * __t411;
            let __t420: f64 = __t418 + __t419;
            let __t421: f64 = __t81 + __t420;
            let __t422: f64 = __w_1 + __t421;
            let __t423: f64 = __t123 / __t138;
            let __t424: f64 = __t98 - __t423;
            let __t425: f64 = __t32 * __t424;
            let __t426: f64 = __t65 * __t425;
            let __t427: f64 = __t69 * __t424;
            let __t428: f64 = __t426 + __t427;
            let __t429: f64 = __t102 + __t428;
            let __t430: f64 = __t11 * __t412;
            let __t432: f64 = __t78 * __t425;
            let __t433: f64 = __t432 - __t430;
            let __t434: f64 = __t110 * __t411;
            let __t436: f64 = __t82 * __t424;
            let __t437: f64 = __t436 - __t434;
            let __t438: f64 = __t433 + __t437;
            let __t439: f64 = __t135 / __t138;
            let __t440: f64 = __t124 - __t439;
            let __t441: f64 = __t32 * __t440;
            let __t442: f64 = __t65 * __t441;
            let __t443: f64 = __t430 + __t442;
            let __t444: f64 = __t69 * __t440;
            let __t445: f64 = __t434 + __t444;
            let __t446: f64 = __t443 + __t445;
            let __t447: f64 = __t78 * __t441;
            let __t448: f64 = __t82 * __t440;
            let __t449: f64 = __t447 + __t448;
            let __t450: f64 = __t102 + __t449;
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
            let __p2: f64 = self.b0;
            let __t11: f64 = 0.5f64 * __p2;
            let __p0: f64 = self.h;
            let __t32: f64 = 0.5f64 / __p0;
            let __x1_0: f64 = z[0usize];
            let __x0_0: f64 = x_k[0usize];
            let __t39: f64 = __x1_0 - __x0_0;
            let __x1_1: f64 = z[1usize];
            let __x0_1: f64 = x_k[1usize];
            let __t42: f64 = __x1_1 - __x0_1;
            let __t46: f64 = __t39 * __x0_1;
            let __t47: f64 = __x0_0 * __t42;
            let __t48: f64 = __t47 - __t46;
            let __t49: f64 = __t11 * __t48;
            let __mu_0: f64 = mu_k[0usize];
            let __t138: f64 = __t32 + __t32;
            let __t405: f64 = __t32 * __t49;
            let __t406: f64 = __t405 + __t405;
            let __t407: f64 = __t406 - __mu_0;
            let __t409: f64 = __t407 / __t138;
            let __t410: f64 = -__t409;
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
        let __p0: f64 = self.h;
        let __t32: f64 = 0.5f64 / __p0;
        let __t138: f64 = __t32 + __t32;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = x1[0usize];
        let __x0_0: f64 = x0[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = x1[1usize];
        let __x0_1: f64 = x0[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = x1[2usize];
        let __x0_2: f64 = x0[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __t53: f64 = __t39 * __t39;
        let __t54: f64 = __t42 * __t42;
        let __t55: f64 = __t53 + __t54;
        let __t56: f64 = __t45 * __t45;
        let __t57: f64 = __t55 + __t56;
        let __t58: f64 = __t25 * __t57;
        let __g0_0: f64 = u[0usize];
        let __t201: f64 = __t49 - __g0_0;
        let __t202: f64 = __t32 * __t201;
        let __t203: f64 = __t201 * __t202;
        let __t204: f64 = __t58 + __t203;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __w_0: f64 = w_k[0usize];
        let __t76: f64 = -__x0_0;
        let __t77: f64 = __t76 - __t39;
        let __t78: f64 = __t11 * __t77;
        let __t79: f64 = -__t42;
        let __t80: f64 = __t79 - __t42;
        let __t81: f64 = __t25 * __t80;
        let __t82: f64 = __t32 * __t78;
        let __w_1: f64 = w_k[1usize];
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __mu_0: f64 = mu_k[0usize];
        let __g0_0: f64 = z[3usize];
        let __t201: f64 = __t49 - __g0_0;
        let __t202: f64 = __t32 * __t201;
        let __t205: f64 = __t65 * __t202;
        let __t206: f64 = __t69 * __t201;
        let __t207: f64 = __t205 + __t206;
        let __t208: f64 = __t68 + __t207;
        let __t209: f64 = __w_0 + __t208;
        let __t210: f64 = __t78 * __t202;
        let __t211: f64 = __t82 * __t201;
        let __t212: f64 = __t210 + __t211;
        let __t213: f64 = __t81 + __t212;
        let __t214: f64 = __w_1 + __t213;
        let __t216: f64 = -__t202;
        let __t217: f64 = __t216 - __t202;
        let __t218: f64 = __mu_0 + __t217;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __w_0: f64 = w_k[0usize];
        let __t76: f64 = -__x0_0;
        let __t77: f64 = __t76 - __t39;
        let __t78: f64 = __t11 * __t77;
        let __t79: f64 = -__t42;
        let __t80: f64 = __t79 - __t42;
        let __t81: f64 = __t25 * __t80;
        let __t82: f64 = __t32 * __t78;
        let __w_1: f64 = w_k[1usize];
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __mu_0: f64 = mu_k[0usize];
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t32 * __t97;
        let __t102: f64 = __t25 * (-2f64);
        let __t103: f64 = __t65 * __t99;
        let __t104: f64 = -__t103;
        let __t105: f64 = __t69 * __t97;
        let __t107: f64 = __t104 - __t105;
        let __t108: f64 = __t102 + __t107;
        let __t110: f64 = __t11 * __t32;
        let __t112: f64 = __t78 * __t99;
        let __t117: f64 = __t82 * __t97;
        let __t124: f64 = __t11 * __x0_0;
        let __t125: f64 = __t32 * __t124;
        let __t126: f64 = __t65 * __t125;
        let __t128: f64 = __t69 * __t124;
        let __t131: f64 = __t78 * __t125;
        let __t132: f64 = __t82 * __t124;
        let __t133: f64 = __t131 + __t132;
        let __t134: f64 = __t102 + __t133;
        let __t138: f64 = __t32 + __t32;
        let __g0_0: f64 = z[3usize];
        let __t201: f64 = __t49 - __g0_0;
        let __t202: f64 = __t32 * __t201;
        let __t205: f64 = __t65 * __t202;
        let __t206: f64 = __t69 * __t201;
        let __t207: f64 = __t205 + __t206;
        let __t208: f64 = __t68 + __t207;
        let __t209: f64 = __w_0 + __t208;
        let __t210: f64 = __t78 * __t202;
        let __t211: f64 = __t82 * __t201;
        let __t212: f64 = __t210 + __t211;
        let __t213: f64 = __t81 + __t212;
        let __t214: f64 = __w_1 + __t213;
        let __t216: f64 = -__t202;
        let __t217: f64 = __t216 - __t202;
        let __t218: f64 = __mu_0 + __t217;
        let __t219: f64 = __t11 * __t202;
        let __t220: f64 = -__t219;
        let __t221: f64 = __t220 - __t112;
        let __t222: f64 = __t110 * __t201;
        let __t223: f64 = -__t222;
        let __t224: f64 = __t223 - __t117;
        let __t225: f64 = __t221 + __t224;
        let __t226: f64 = __t99 + __t99;
        let __t227: f64 = __t126 + __t219;
        let __t228: f64 = __t128 + __t222;
        let __t229: f64 = __t227 + __t228;
        let __t230: f64 = -__t125;
        let __t231: f64 = __t230 - __t125;
        let __t232: f64 = -__t69;
        let __t233: f64 = __t232 - __t69;
        let __t234: f64 = -__t82;
        let __t235: f64 = __t234 - __t82;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t32 * __t97;
        let __t124: f64 = __t11 * __x0_0;
        let __t125: f64 = __t32 * __t124;
        let __t139: f64 = __t39 + __t39;
        let __t140: f64 = __t25 * __t139;
        let __t147: f64 = __t42 + __t42;
        let __t148: f64 = __t25 * __t147;
        let __t153: f64 = __t45 + __t45;
        let __t154: f64 = __t25 * __t153;
        let __g0_0: f64 = z[3usize];
        let __t201: f64 = __t49 - __g0_0;
        let __t202: f64 = __t32 * __t201;
        let __t236: f64 = __t97 * __t202;
        let __t237: f64 = -__t236;
        let __t238: f64 = __t99 * __t201;
        let __t240: f64 = __t237 - __t238;
        let __t241: f64 = __t140 + __t240;
        let __t242: f64 = __t124 * __t202;
        let __t243: f64 = __t125 * __t201;
        let __t244: f64 = __t242 + __t243;
        let __t245: f64 = __t148 + __t244;
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
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __x1_0: f64 = z[0usize];
        let __x0_0: f64 = x_k[0usize];
        let __t39: f64 = __x1_0 - __x0_0;
        let __x1_1: f64 = z[1usize];
        let __x0_1: f64 = x_k[1usize];
        let __t42: f64 = __x1_1 - __x0_1;
        let __x1_2: f64 = z[2usize];
        let __x0_2: f64 = x_k[2usize];
        let __t45: f64 = __x1_2 - __x0_2;
        let __t46: f64 = __t39 * __x0_1;
        let __t47: f64 = __x0_0 * __t42;
        let __t48: f64 = __t47 - __t46;
        let __t49: f64 = __t11 * __t48;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __w_0: f64 = w_k[0usize];
        let __t76: f64 = -__x0_0;
        let __t77: f64 = __t76 - __t39;
        let __t78: f64 = __t11 * __t77;
        let __t79: f64 = -__t42;
        let __t80: f64 = __t79 - __t42;
        let __t81: f64 = __t25 * __t80;
        let __t82: f64 = __t32 * __t78;
        let __w_1: f64 = w_k[1usize];
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __mu_0: f64 = mu_k[0usize];
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t32 * __t97;
        let __t124: f64 = __t11 * __x0_0;
        let __t125: f64 = __t32 * __t124;
        let __t139: f64 = __t39 + __t39;
        let __t140: f64 = __t25 * __t139;
        let __t147: f64 = __t42 + __t42;
        let __t148: f64 = __t25 * __t147;
        let __t153: f64 = __t45 + __t45;
        let __t154: f64 = __t25 * __t153;
        let __g0_0: f64 = z[3usize];
        let __t201: f64 = __t49 - __g0_0;
        let __t202: f64 = __t32 * __t201;
        let __t205: f64 = __t65 * __t202;
        let __t206: f64 = __t69 * __t201;
        let __t207: f64 = __t205 + __t206;
        let __t208: f64 = __t68 + __t207;
        let __t209: f64 = __w_0 + __t208;
        let __t210: f64 = __t78 * __t202;
        let __t211: f64 = __t82 * __t201;
        let __t212: f64 = __t210 + __t211;
        let __t213: f64 = __t81 + __t212;
        let __t214: f64 = __w_1 + __t213;
        let __t216: f64 = -__t202;
        let __t217: f64 = __t216 - __t202;
        let __t218: f64 = __mu_0 + __t217;
        let __t236: f64 = __t97 * __t202;
        let __t237: f64 = -__t236;
        let __t238: f64 = __t99 * __t201;
        let __t240: f64 = __t237 - __t238;
        let __t241: f64 = __t140 + __t240;
        let __t242: f64 = __t124 * __t202;
        let __t243: f64 = __t125 * __t201;
        let __t244: f64 = __t242 + __t243;
        let __t245: f64 = __t148 + __t244;
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
            let __p2: f64 = self.b0;
            let __t11: f64 = 0.5f64 * __p2;
            let __p1: f64 = self.m;
            let __t23: f64 = 0.5f64 * __p1;
            let __p0: f64 = self.h;
            let __t25: f64 = __t23 / __p0;
            let __t32: f64 = 0.5f64 / __p0;
            let __x1_0: f64 = z[0usize];
            let __x0_0: f64 = x_k[0usize];
            let __t39: f64 = __x1_0 - __x0_0;
            let __x1_1: f64 = z[1usize];
            let __x0_1: f64 = x_k[1usize];
            let __t42: f64 = __x1_1 - __x0_1;
            let __x1_2: f64 = z[2usize];
            let __x0_2: f64 = x_k[2usize];
            let __t45: f64 = __x1_2 - __x0_2;
            let __t46: f64 = __t39 * __x0_1;
            let __t47: f64 = __x0_0 * __t42;
            let __t48: f64 = __t47 - __t46;
            let __t49: f64 = __t11 * __t48;
            let __t64: f64 = __x0_1 + __t42;
            let __t65: f64 = __t11 * __t64;
            let __t66: f64 = -__t39;
            let __t67: f64 = __t66 - __t39;
            let __t68: f64 = __t25 * __t67;
            let __t69: f64 = __t32 * __t65;
            let __w_0: f64 = w_k[0usize];
            let __t76: f64 = -__x0_0;
            let __t77: f64 = __t76 - __t39;
            let __t78: f64 = __t11 * __t77;
            let __t79: f64 = -__t42;
            let __t80: f64 = __t79 - __t42;
            let __t81: f64 = __t25 * __t80;
            let __t82: f64 = __t32 * __t78;
            let __w_1: f64 = w_k[1usize];
            let __t89: f64 = -__t45;
            let __t90: f64 = __t89 - __t45;
            let __t91: f64 = __t25 * __t90;
            let __w_2: f64 = w_k[2usize];
            let __t93: f64 = __t91 + __w_2;
            let __mu_0: f64 = mu_k[0usize];
            let __t138: f64 = __t32 + __t32;
            let __t405: f64 = __t32 * __t49;
            let __t500: f64 = -__t405;
            let __t501: f64 = __t500 - __t405;
            let __t502: f64 = __mu_0 + __t501;
            let __t504: f64 = __t502 / __t138;
            let __t506: f64 = __t49 + __t504;
            let __t507: f64 = __t32 * __t506;
            let __t508: f64 = __t65 * __t507;
            let __t509: f64 = __t69 * __t506;
            let __t510: f64 = __t508 + __t509;
            let __t511: f64 = __t68 + __t510;
            let __t512: f64 = __w_0 + __t511;
            let __t513: f64 = __t78 * __t507;
            let __t514: f64 = __t82 * __t506;
            let __t515: f64 = __t513 + __t514;
            let __t516: f64 = __t81 + __t515;
            let __t517: f64 = __w_1 + __t516;
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
            let __p2: f64 = self.b0;
            let __t11: f64 = 0.5f64 * __p2;
            let __p1: f64 = self.m;
            let __t23: f64 = 0.5f64 * __p1;
            let __p0: f64 = self.h;
            let __t25: f64 = __t23 / __p0;
            let __t32: f64 = 0.5f64 / __p0;
            let __x1_0: f64 = z[0usize];
            let __x0_0: f64 = x_k[0usize];
            let __t39: f64 = __x1_0 - __x0_0;
            let __x1_1: f64 = z[1usize];
            let __x0_1: f64 = x_k[1usize];
            let __t42: f64 = __x1_1 - __x0_1;
            let __x1_2: f64 = z[2usize];
            let __x0_2: f64 = x_k[2usize];
            let __t45: f64 = __x1_2 - __x0_2;
            let __t46: f64 = __t39 * __x0_1;
            let __t47: f64 = __x0_0 * __t42;
            let __t48: f64 = __t47 - __t46;
            let __t49: f64 = __t11 * __t48;
            let __t64: f64 = __x0_1 + __t42;
            let __t65: f64 = __t11 * __t64;
            let __t66: f64 = -__t39;
            let __t67: f64 = __t66 - __t39;
            let __t68: f64 = __t25 * __t67;
            let __t69: f64 = __t32 * __t65;
            let __w_0: f64 = w_k[0usize];
            let __t76: f64 = -__x0_0;
            let __t77: f64 = __t76 - __t39;
            let __t78: f64 = __t11 * __t77;
            let __t79: f64 = -__t42;
            let __t80: f64 = __t79 - __t42;
            let __t81: f64 = __t25 * __t80;
            let __t82: f64 = __t32 * __t78;
            let __w_1: f64 = w_k[1usize];
            let __t89: f64 = -__t45;
            let __t90: f64 = __t89 - __t45;
            let __t91: f64 = __t25 * __t90;
            let __w_2: f64 = w_k[2usize];
            let __t93: f64 = __t91 + __w_2;
            let __mu_0: f64 = mu_k[0usize];
            let __t97: f64 = __t11 * __x0_1;
            let __t99: f64 = __t32 * __t97;
            let __t102: f64 = __t25 * (-2f64);
            let __t110: f64 = __t11 * __t32;
            let __t124: f64 = __t11 * __x0_0;
            let __t125: f64 = __t32 * __t124;
            let __t138: f64 = __t32 + __t32;
            let __t226: f64 = __t99 + __t99;
            let __t230: f64 = -__t125;
            let __t231: f64 = __t230 - __t125;
            let __t405: f64 = __t32 * __t49;
            let __t500: f64 = -__t405;
            let __t501: f64 = __t500 - __t405;
            let __t502: f64 = __mu_0 + __t501;
            let __t504: f64 = __t502 / __t138;
            let __t506: f64 = __t49 + __t504;
            let __t507: f64 = __t32 * __t506;
            let __t508: f64 = __t65 * __t507;
            let __t509: f64 = __t69 * __t506;
            let __t510: f64 = __t508 + __t509;
            let __t511: f64 = __t68 + __t510;
            let __t512: f64 = __w_0 + __t511;
            let __t513: f64 = __t78 * __t507;
            let __t514: f64 = __t82 * __t506;
            let __t515: f64 = __t513 + __t514;
            let __t516: f64 = __t81 + __t515;
            let __t517: f64 = __w_1 + __t516;
            let __t518: f64 = __t226 / __t138;
            let __t519: f64 = __t518 - __t97;
            let __t520: f64 = __t32 * __t519;
            let __t521: f64 = __t65 * __t520;
            let __t522: f64 = __t69 * __t519;
            let __t523: f64 = __t521 + __t522;
            let __t524: f64 = __t102 + __t523;
            let __t525: f64 = __t11 * __t507;
            let __t527: f64 = __t78 * __t520;
            let __t528: f64 = __t527 - __t525;
            let __t529: f64 = __t110 * __t506;
            let __t531: f64 = __t82 * __t519;
            let __t532: f64 = __t531 - __t529;
            let __t533: f64 = __t528 + __t532;
            let __t534: f64 = __t231 / __t138;
            let __t535: f64 = __t124 + __t534;
            let __t536: f64 = __t32 * __t535;
            let __t537: f64 = __t65 * __t536;
            let __t538: f64 = __t525 + __t537;
            let __t539: f64 = __t69 * __t535;
            let __t540: f64 = __t529 + __t539;
            let __t541: f64 = __t538 + __t540;
            let __t542: f64 = __t78 * __t536;
            let __t543: f64 = __t82 * __t535;
            let __t544: f64 = __t542 + __t543;
            let __t545: f64 = __t102 + __t544;
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
            let __p2: f64 = self.b0;
            let __t11: f64 = 0.5f64 * __p2;
            let __p0: f64 = self.h;
            let __t32: f64 = 0.5f64 / __p0;
            let __x1_0: f64 = z[0usize];
            let __x0_0: f64 = x_k[0usize];
            let __t39: f64 = __x1_0 - __x0_0;
            let __x1_1: f64 = z[1usize];
            let __x0_1: f64 = x_k[1usize];
            let __t42: f64 = __x1_1 - __x0_1;
            let __t46: f64 = __t39 * __x0_1;
            let __t47: f64 = __x0_0 * __t42;
            let __t48: f64 = __t47 - __t46;
            let __t49: f64 = __t11 * __t48;
            let __mu_0: f64 = mu_k[0usize];
            let __t138: f64 = __t32 + __t32;
            let __t405: f64 = __t32 * __t49;
            let __t500: f64 = -__t405;
            let __t501: f64 = __t500 - __t405;
            let __t502: f64 = __mu_0 + __t501;
            let __t504: f64 = __t502 / __t138;
            let __t505: f64 = -__t504;
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
        let __p0: f64 = self.h;
        let __t32: f64 = 0.5f64 / __p0;
        let __t138: f64 = __t32 + __t32;
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
        let __q1_0: f64 = z[0usize];
        let __q0_0: f64 = q_k[0usize];
        let __t2: f64 = __q1_0 - __q0_0;
        let __q1_1: f64 = z[1usize];
        let __q0_1: f64 = q_k[1usize];
        let __t5: f64 = __q1_1 - __q0_1;
        let __q1_2: f64 = z[2usize];
        let __q0_2: f64 = q_k[2usize];
        let __t8: f64 = __q1_2 - __q0_2;
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __t13: f64 = __t2 * __q0_1;
        let __t15: f64 = __q0_0 * __t5;
        let __t16: f64 = __t15 - __t13;
        let __t17: f64 = __t11 * __t16;
        let __q1_3: f64 = z[3usize];
        let __q0_3: f64 = q_k[3usize];
        let __t20: f64 = __q1_3 - __q0_3;
        let __t21: f64 = __t17 + __t20;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __t33: f64 = __t21 * __t32;
        let __t286: f64 = __q0_1 + __t5;
        let __t287: f64 = __t11 * __t286;
        let __t288: f64 = -__t2;
        let __t289: f64 = __t288 - __t2;
        let __t290: f64 = __t25 * __t289;
        let __t291: f64 = __t32 * __t287;
        let __t292: f64 = __t33 * __t287;
        let __t293: f64 = __t21 * __t291;
        let __t294: f64 = __t292 + __t293;
        let __t295: f64 = __t290 + __t294;
        let __p_0: f64 = p_k[0usize];
        let __t297: f64 = __t295 + __p_0;
        let __t298: f64 = -__q0_0;
        let __t299: f64 = __t298 - __t2;
        let __t300: f64 = __t11 * __t299;
        let __t301: f64 = -__t5;
        let __t302: f64 = __t301 - __t5;
        let __t303: f64 = __t25 * __t302;
        let __t304: f64 = __t32 * __t300;
        let __t305: f64 = __t33 * __t300;
        let __t306: f64 = __t21 * __t304;
        let __t307: f64 = __t305 + __t306;
        let __t308: f64 = __t303 + __t307;
        let __p_1: f64 = p_k[1usize];
        let __t310: f64 = __t308 + __p_1;
        let __t311: f64 = -__t8;
        let __t312: f64 = __t311 - __t8;
        let __t313: f64 = __t25 * __t312;
        let __p_2: f64 = p_k[2usize];
        let __t315: f64 = __t313 + __p_2;
        let __t316: f64 = -__t33;
        let __t317: f64 = __t316 - __t33;
        let __p_3: f64 = p_k[3usize];
        let __t319: f64 = __t317 + __p_3;
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
        let __q1_0: f64 = z[0usize];
        let __q0_0: f64 = q_k[0usize];
        let __t2: f64 = __q1_0 - __q0_0;
        let __q1_1: f64 = z[1usize];
        let __q0_1: f64 = q_k[1usize];
        let __t5: f64 = __q1_1 - __q0_1;
        let __q1_2: f64 = z[2usize];
        let __q0_2: f64 = q_k[2usize];
        let __t8: f64 = __q1_2 - __q0_2;
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __t13: f64 = __t2 * __q0_1;
        let __t15: f64 = __q0_0 * __t5;
        let __t16: f64 = __t15 - __t13;
        let __t17: f64 = __t11 * __t16;
        let __q1_3: f64 = z[3usize];
        let __q0_3: f64 = q_k[3usize];
        let __t20: f64 = __q1_3 - __q0_3;
        let __t21: f64 = __t17 + __t20;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __t33: f64 = __t21 * __t32;
        let __t102: f64 = __t25 * (-2f64);
        let __t110: f64 = __t11 * __t32;
        let __t215: f64 = -__t32;
        let __t286: f64 = __q0_1 + __t5;
        let __t287: f64 = __t11 * __t286;
        let __t288: f64 = -__t2;
        let __t289: f64 = __t288 - __t2;
        let __t290: f64 = __t25 * __t289;
        let __t291: f64 = __t32 * __t287;
        let __t292: f64 = __t33 * __t287;
        let __t293: f64 = __t21 * __t291;
        let __t294: f64 = __t292 + __t293;
        let __t295: f64 = __t290 + __t294;
        let __p_0: f64 = p_k[0usize];
        let __t297: f64 = __t295 + __p_0;
        let __t298: f64 = -__q0_0;
        let __t299: f64 = __t298 - __t2;
        let __t300: f64 = __t11 * __t299;
        let __t301: f64 = -__t5;
        let __t302: f64 = __t301 - __t5;
        let __t303: f64 = __t25 * __t302;
        let __t304: f64 = __t32 * __t300;
        let __t305: f64 = __t33 * __t300;
        let __t306: f64 = __t21 * __t304;
        let __t307: f64 = __t305 + __t306;
        let __t308: f64 = __t303 + __t307;
        let __p_1: f64 = p_k[1usize];
        let __t310: f64 = __t308 + __p_1;
        let __t311: f64 = -__t8;
        let __t312: f64 = __t311 - __t8;
        let __t313: f64 = __t25 * __t312;
        let __p_2: f64 = p_k[2usize];
        let __t315: f64 = __t313 + __p_2;
        let __t316: f64 = -__t33;
        let __t317: f64 = __t316 - __t33;
        let __p_3: f64 = p_k[3usize];
        let __t319: f64 = __t317 + __p_3;
        let __t320: f64 = __q0_1 * __t11;
        let __t322: f64 = __t32 * __t320;
        let __t324: f64 = __t287 * __t322;
        let __t325: f64 = -__t324;
        let __t326: f64 = __t291 * __t320;
        let __t328: f64 = __t325 - __t326;
        let __t329: f64 = __t102 + __t328;
        let __t330: f64 = __t300 * __t322;
        let __t331: f64 = -__t330;
        let __t332: f64 = __t11 * __t33;
        let __t334: f64 = __t331 - __t332;
        let __t335: f64 = __t304 * __t320;
        let __t336: f64 = -__t335;
        let __t337: f64 = __t21 * __t110;
        let __t339: f64 = __t336 - __t337;
        let __t340: f64 = __t334 + __t339;
        let __t341: f64 = __t322 + __t322;
        let __t342: f64 = __q0_0 * __t11;
        let __t343: f64 = __t32 * __t342;
        let __t344: f64 = __t287 * __t343;
        let __t345: f64 = __t332 + __t344;
        let __t346: f64 = __t291 * __t342;
        let __t347: f64 = __t337 + __t346;
        let __t348: f64 = __t345 + __t347;
        let __t349: f64 = __t300 * __t343;
        let __t350: f64 = __t304 * __t342;
        let __t351: f64 = __t349 + __t350;
        let __t352: f64 = __t102 + __t351;
        let __t353: f64 = -__t343;
        let __t354: f64 = __t353 - __t343;
        let __t355: f64 = __t291 + __t291;
        let __t356: f64 = __t304 + __t304;
        let __t357: f64 = __t215 - __t32;
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
        let __q1_0: f64 = z[0usize];
        let __q0_0: f64 = q_k[0usize];
        let __t2: f64 = __q1_0 - __q0_0;
        let __q1_1: f64 = z[1usize];
        let __q0_1: f64 = q_k[1usize];
        let __t5: f64 = __q1_1 - __q0_1;
        let __q1_2: f64 = z[2usize];
        let __q0_2: f64 = q_k[2usize];
        let __t8: f64 = __q1_2 - __q0_2;
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __t13: f64 = __t2 * __q0_1;
        let __t15: f64 = __q0_0 * __t5;
        let __t16: f64 = __t15 - __t13;
        let __t17: f64 = __t11 * __t16;
        let __q1_3: f64 = z[3usize];
        let __q0_3: f64 = q_k[3usize];
        let __t20: f64 = __q1_3 - __q0_3;
        let __t21: f64 = __t17 + __t20;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __t33: f64 = __t21 * __t32;
        let __t320: f64 = __q0_1 * __t11;
        let __t322: f64 = __t32 * __t320;
        let __t342: f64 = __q0_0 * __t11;
        let __t343: f64 = __t32 * __t342;
        let __t358: f64 = __t2 + __t2;
        let __t359: f64 = __t25 * __t358;
        let __t360: f64 = __t33 * __t320;
        let __t361: f64 = -__t360;
        let __t362: f64 = __t21 * __t322;
        let __t364: f64 = __t361 - __t362;
        let __t365: f64 = __t359 + __t364;
        let __t366: f64 = __t5 + __t5;
        let __t367: f64 = __t25 * __t366;
        let __t368: f64 = __t33 * __t342;
        let __t369: f64 = __t21 * __t343;
        let __t370: f64 = __t368 + __t369;
        let __t371: f64 = __t367 + __t370;
        let __t372: f64 = __t8 + __t8;
        let __t373: f64 = __t25 * __t372;
        let __t374: f64 = __t33 + __t33;
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
        let __q1_0: f64 = q1[0usize];
        let __q0_0: f64 = q0[0usize];
        let __t2: f64 = __q1_0 - __q0_0;
        let __q1_1: f64 = q1[1usize];
        let __q0_1: f64 = q0[1usize];
        let __t5: f64 = __q1_1 - __q0_1;
        let __p2: f64 = self.b0;
        let __t11: f64 = 0.5f64 * __p2;
        let __t13: f64 = __t2 * __q0_1;
        let __t15: f64 = __q0_0 * __t5;
        let __t16: f64 = __t15 - __t13;
        let __t17: f64 = __t11 * __t16;
        let __q1_3: f64 = q1[3usize];
        let __q0_3: f64 = q0[3usize];
        let __t20: f64 = __q1_3 - __q0_3;
        let __t21: f64 = __t17 + __t20;
        let __p1: f64 = self.m;
        let __t23: f64 = 0.5f64 * __p1;
        let __p0: f64 = self.h;
        let __t25: f64 = __t23 / __p0;
        let __t32: f64 = 0.5f64 / __p0;
        let __t33: f64 = __t21 * __t32;
        let __t102: f64 = __t25 * (-2f64);
        let __t110: f64 = __t11 * __t32;
        let __t138: f64 = __t32 + __t32;
        let __t215: f64 = -__t32;
        let __t286: f64 = __q0_1 + __t5;
        let __t287: f64 = __t11 * __t286;
        let __t291: f64 = __t32 * __t287;
        let __t298: f64 = -__q0_0;
        let __t299: f64 = __t298 - __t2;
        let __t300: f64 = __t11 * __t299;
        let __t304: f64 = __t32 * __t300;
        let __t320: f64 = __q0_1 * __t11;
        let __t322: f64 = __t32 * __t320;
        let __t323: f64 = -__t322;
        let __t324: f64 = __t287 * __t322;
        let __t325: f64 = -__t324;
        let __t326: f64 = __t291 * __t320;
        let __t328: f64 = __t325 - __t326;
        let __t329: f64 = __t102 + __t328;
        let __t330: f64 = __t300 * __t322;
        let __t331: f64 = -__t330;
        let __t332: f64 = __t11 * __t33;
        let __t334: f64 = __t331 - __t332;
        let __t335: f64 = __t304 * __t320;
        let __t336: f64 = -__t335;
        let __t337: f64 = __t21 * __t110;
        let __t339: f64 = __t336 - __t337;
        let __t340: f64 = __t334 + __t339;
        let __t341: f64 = __t322 + __t322;
        let __t342: f64 = __q0_0 * __t11;
        let __t343: f64 = __t32 * __t342;
        let __t344: f64 = __t287 * __t343;
        let __t345: f64 = __t332 + __t344;
        let __t346: f64 = __t291 * __t342;
        let __t347: f64 = __t337 + __t346;
        let __t348: f64 = __t345 + __t347;
        let __t349: f64 = __t300 * __t343;
        let __t350: f64 = __t304 * __t342;
        let __t351: f64 = __t349 + __t350;
        let __t352: f64 = __t102 + __t351;
        let __t353: f64 = -__t343;
        let __t354: f64 = __t353 - __t343;
        let __t355: f64 = __t291 + __t291;
        let __t356: f64 = __t304 + __t304;
        let __t357: f64 = __t215 - __t32;
        let __t376: f64 = __t25 * 2f64;
        let __t377: f64 = __t287 * __t291;
        let __t378: f64 = __t377 + __t377;
        let __t379: f64 = __t376 + __t378;
        let __t380: f64 = __t291 * __t300;
        let __t381: f64 = __t287 * __t304;
        let __t382: f64 = __t380 + __t381;
        let __t383: f64 = -__t291;
        let __t384: f64 = __t383 - __t291;
        let __t385: f64 = __t300 * __t304;
        let __t386: f64 = __t385 + __t385;
        let __t387: f64 = __t376 + __t386;
        let __t388: f64 = -__t304;
        let __t389: f64 = __t388 - __t304;
        let __t390: f64 = __t320 * __t322;
        let __t392: f64 = __t390 + __t390;
        let __t393: f64 = __t376 + __t392;
        let __t394: f64 = __t322 * __t342;
        let __t395: f64 = -__t394;
        let __t396: f64 = __t320 * __t343;
        let __t397: f64 = -__t396;
        let __t398: f64 = __t395 - __t396;
        let __t399: f64 = __t323 - __t322;
        let __t400: f64 = __t397 - __t394;
        let __t401: f64 = __t342 * __t343;
        let __t402: f64 = __t401 + __t401;
        let __t403: f64 = __t376 + __t402;
        let __t404: f64 = __t343 + __t343;
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
