///A configuration of [`ChargedParticle`]: shape coordinates (`x`, `y`, `z`) then group coordinates (`theta`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChargedParticleConfig {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub theta: f64,
}
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
/// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
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
impl ChargedParticle {
    /// Number of shape coordinates `S`.
    pub const SHAPE_DIM: usize = 3usize;
    /// Number of group coordinates `K`.
    pub const GROUP_DIM: usize = 1usize;
    /// Number of configuration coordinates `N = S + K`.
    pub const CONFIG_DIM: usize = 4usize;
    ///Generated straight-line code: reduced (+) stepper: 42 operations for the residual, 77 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; reduced (−) stepper: 43 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; unreduced stepper: 44 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 34 for the momentum update. Momentum-level elimination: (+) group unknowns solved in closed form, (−) group unknowns solved in closed form.
    pub const GENERATED: &'static str = "Generated straight-line code: reduced (+) stepper: 42 operations for the residual, 77 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; reduced (−) stepper: 43 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 32 for the momentum update; unreduced stepper: 44 operations for the residual, 80 for the residual with its Jacobian (10 nonzero entries), 34 for the momentum update. Momentum-level elimination: (+) group unknowns solved in closed form, (−) group unknowns solved in closed form.";
}
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
    fn parameter_values(&self) -> ::std::vec::Vec<f64> {
        ::std::vec![self.h, self.m, self.b0]
    }
}
impl ::dirac::runtime::ReducedPlus<3usize, 1usize, 4usize> for ChargedParticle {
    fn reduced_lagrangian_plus(
        &self,
        x0: &::dirac::nalgebra::SVector<f64, 3usize>,
        x1: &::dirac::nalgebra::SVector<f64, 3usize>,
        g1: &::dirac::nalgebra::SVector<f64, 1usize>,
    ) -> f64 {
        let g1 = g1
            + <Self as ::dirac::runtime::DiscreteLagrangian<
                3usize,
                1usize,
                4usize,
            >>::connection(self) * (x1 - x0);
        let q0 = ::dirac::runtime::system::join::<
            3usize,
            1usize,
            4usize,
        >(x0, &::dirac::nalgebra::SVector::<f64, 1usize>::repeat(0f64));
        let q1 = ::dirac::runtime::system::join::<3usize, 1usize, 4usize>(x1, &g1);
        <Self as ::dirac::runtime::DiscreteLagrangian<
            3usize,
            1usize,
            4usize,
        >>::lagrangian(self, &q0, &q1)
    }
    #[inline]
    fn plus_residual(
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
    fn plus_residual_jacobian(
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
        let mut __jac = ::dirac::nalgebra::SMatrix::<f64, 4usize, 4usize>::zeros();
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
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t75, __t88, __t93, __t96]),
            __jac,
        )
    }
    #[inline]
    fn plus_momentum(
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
    const PLUS_ELIMINATES_GROUP: bool = true;
    #[inline]
    #[allow(unused_variables)]
    fn plus_eliminated_residual(
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
            let __t294: f64 = __t32 * __t49;
            let __t295: f64 = __t294 + __t294;
            let __t296: f64 = __t295 - __mu_0;
            let __t298: f64 = __t296 / __t138;
            let __t300: f64 = __t49 - __t298;
            let __t301: f64 = __t32 * __t300;
            let __t302: f64 = __t65 * __t301;
            let __t303: f64 = __t69 * __t300;
            let __t304: f64 = __t302 + __t303;
            let __t305: f64 = __t68 + __t304;
            let __t306: f64 = __w_0 + __t305;
            let __t307: f64 = __t78 * __t301;
            let __t308: f64 = __t82 * __t300;
            let __t309: f64 = __t307 + __t308;
            let __t310: f64 = __t81 + __t309;
            let __t311: f64 = __w_1 + __t310;
            ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t306, __t311, __t93])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn plus_eliminated_residual_jacobian(
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
            let __t294: f64 = __t32 * __t49;
            let __t295: f64 = __t294 + __t294;
            let __t296: f64 = __t295 - __mu_0;
            let __t298: f64 = __t296 / __t138;
            let __t300: f64 = __t49 - __t298;
            let __t301: f64 = __t32 * __t300;
            let __t302: f64 = __t65 * __t301;
            let __t303: f64 = __t69 * __t300;
            let __t304: f64 = __t302 + __t303;
            let __t305: f64 = __t68 + __t304;
            let __t306: f64 = __w_0 + __t305;
            let __t307: f64 = __t78 * __t301;
            let __t308: f64 = __t82 * __t300;
            let __t309: f64 = __t307 + __t308;
            let __t310: f64 = __t81 + __t309;
            let __t311: f64 = __w_1 + __t310;
            let __t312: f64 = __t123 / __t138;
            let __t313: f64 = __t98 - __t312;
            let __t314: f64 = __t32 * __t313;
            let __t315: f64 = __t65 * __t314;
            let __t316: f64 = __t69 * __t313;
            let __t317: f64 = __t315 + __t316;
            let __t318: f64 = __t102 + __t317;
            let __t319: f64 = __t11 * __t301;
            let __t321: f64 = __t78 * __t314;
            let __t322: f64 = __t321 - __t319;
            let __t323: f64 = __t110 * __t300;
            let __t325: f64 = __t82 * __t313;
            let __t326: f64 = __t325 - __t323;
            let __t327: f64 = __t322 + __t326;
            let __t328: f64 = __t135 / __t138;
            let __t329: f64 = __t124 - __t328;
            let __t330: f64 = __t32 * __t329;
            let __t331: f64 = __t65 * __t330;
            let __t332: f64 = __t319 + __t331;
            let __t333: f64 = __t69 * __t329;
            let __t334: f64 = __t323 + __t333;
            let __t335: f64 = __t332 + __t334;
            let __t336: f64 = __t78 * __t330;
            let __t337: f64 = __t82 * __t329;
            let __t338: f64 = __t336 + __t337;
            let __t339: f64 = __t102 + __t338;
            let mut __jac = ::dirac::nalgebra::SMatrix::<f64, 3usize, 3usize>::zeros();
            __jac[(0usize, 0usize)] = __t318;
            __jac[(0usize, 1usize)] = __t335;
            __jac[(1usize, 0usize)] = __t327;
            __jac[(1usize, 1usize)] = __t339;
            __jac[(2usize, 2usize)] = __t102;
            (
                ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t306, __t311, __t93]),
                __jac,
            )
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn plus_eliminated_group(
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
            let __t294: f64 = __t32 * __t49;
            let __t295: f64 = __t294 + __t294;
            let __t296: f64 = __t295 - __mu_0;
            let __t298: f64 = __t296 / __t138;
            let __t299: f64 = -__t298;
            ::dirac::nalgebra::SVector::<f64, 1usize>::from([__t299])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn plus_eliminated_group_block(
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
impl ::dirac::runtime::ReducedMinus<3usize, 1usize, 4usize> for ChargedParticle {
    fn reduced_lagrangian_minus(
        &self,
        x0: &::dirac::nalgebra::SVector<f64, 3usize>,
        g0: &::dirac::nalgebra::SVector<f64, 1usize>,
        x1: &::dirac::nalgebra::SVector<f64, 3usize>,
    ) -> f64 {
        let g0 = g0
            + <Self as ::dirac::runtime::DiscreteLagrangian<
                3usize,
                1usize,
                4usize,
            >>::connection(self) * (x0 - x1);
        let q0 = ::dirac::runtime::system::join::<3usize, 1usize, 4usize>(x0, &g0);
        let q1 = ::dirac::runtime::system::join::<
            3usize,
            1usize,
            4usize,
        >(x1, &::dirac::nalgebra::SVector::<f64, 1usize>::repeat(0f64));
        <Self as ::dirac::runtime::DiscreteLagrangian<
            3usize,
            1usize,
            4usize,
        >>::lagrangian(self, &q0, &q1)
    }
    #[inline]
    fn minus_residual(
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
        let __t160: f64 = __t49 - __g0_0;
        let __t161: f64 = __t32 * __t160;
        let __t164: f64 = __t65 * __t161;
        let __t165: f64 = __t69 * __t160;
        let __t166: f64 = __t164 + __t165;
        let __t167: f64 = __t68 + __t166;
        let __t168: f64 = __w_0 + __t167;
        let __t169: f64 = __t78 * __t161;
        let __t170: f64 = __t82 * __t160;
        let __t171: f64 = __t169 + __t170;
        let __t172: f64 = __t81 + __t171;
        let __t173: f64 = __w_1 + __t172;
        let __t175: f64 = -__t161;
        let __t176: f64 = __t175 - __t161;
        let __t177: f64 = __mu_0 + __t176;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t168, __t173, __t93, __t177])
    }
    #[inline]
    fn minus_residual_jacobian(
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
        let __t160: f64 = __t49 - __g0_0;
        let __t161: f64 = __t32 * __t160;
        let __t164: f64 = __t65 * __t161;
        let __t165: f64 = __t69 * __t160;
        let __t166: f64 = __t164 + __t165;
        let __t167: f64 = __t68 + __t166;
        let __t168: f64 = __w_0 + __t167;
        let __t169: f64 = __t78 * __t161;
        let __t170: f64 = __t82 * __t160;
        let __t171: f64 = __t169 + __t170;
        let __t172: f64 = __t81 + __t171;
        let __t173: f64 = __w_1 + __t172;
        let __t175: f64 = -__t161;
        let __t176: f64 = __t175 - __t161;
        let __t177: f64 = __mu_0 + __t176;
        let __t178: f64 = __t11 * __t161;
        let __t179: f64 = -__t178;
        let __t180: f64 = __t179 - __t112;
        let __t181: f64 = __t110 * __t160;
        let __t182: f64 = -__t181;
        let __t183: f64 = __t182 - __t117;
        let __t184: f64 = __t180 + __t183;
        let __t185: f64 = __t99 + __t99;
        let __t186: f64 = __t126 + __t178;
        let __t187: f64 = __t128 + __t181;
        let __t188: f64 = __t186 + __t187;
        let __t189: f64 = -__t125;
        let __t190: f64 = __t189 - __t125;
        let __t191: f64 = -__t69;
        let __t192: f64 = __t191 - __t69;
        let __t193: f64 = -__t82;
        let __t194: f64 = __t193 - __t82;
        let mut __jac = ::dirac::nalgebra::SMatrix::<f64, 4usize, 4usize>::zeros();
        __jac[(0usize, 0usize)] = __t108;
        __jac[(0usize, 1usize)] = __t188;
        __jac[(0usize, 3usize)] = __t192;
        __jac[(1usize, 0usize)] = __t184;
        __jac[(1usize, 1usize)] = __t134;
        __jac[(1usize, 3usize)] = __t194;
        __jac[(2usize, 2usize)] = __t102;
        __jac[(3usize, 0usize)] = __t185;
        __jac[(3usize, 1usize)] = __t190;
        __jac[(3usize, 3usize)] = __t138;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t168, __t173, __t93, __t177]),
            __jac,
        )
    }
    #[inline]
    fn minus_momentum(
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
        let __t160: f64 = __t49 - __g0_0;
        let __t161: f64 = __t32 * __t160;
        let __t195: f64 = __t97 * __t161;
        let __t196: f64 = -__t195;
        let __t197: f64 = __t99 * __t160;
        let __t199: f64 = __t196 - __t197;
        let __t200: f64 = __t140 + __t199;
        let __t201: f64 = __t124 * __t161;
        let __t202: f64 = __t125 * __t160;
        let __t203: f64 = __t201 + __t202;
        let __t204: f64 = __t148 + __t203;
        ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t200, __t204, __t154])
    }
    const MINUS_ELIMINATES_GROUP: bool = true;
    #[inline]
    #[allow(unused_variables)]
    fn minus_eliminated_residual(
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
            let __t294: f64 = __t32 * __t49;
            let __t340: f64 = -__t294;
            let __t341: f64 = __t340 - __t294;
            let __t342: f64 = __mu_0 + __t341;
            let __t344: f64 = __t342 / __t138;
            let __t346: f64 = __t49 + __t344;
            let __t347: f64 = __t32 * __t346;
            let __t348: f64 = __t65 * __t347;
            let __t349: f64 = __t69 * __t346;
            let __t350: f64 = __t348 + __t349;
            let __t351: f64 = __t68 + __t350;
            let __t352: f64 = __w_0 + __t351;
            let __t353: f64 = __t78 * __t347;
            let __t354: f64 = __t82 * __t346;
            let __t355: f64 = __t353 + __t354;
            let __t356: f64 = __t81 + __t355;
            let __t357: f64 = __w_1 + __t356;
            ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t352, __t357, __t93])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn minus_eliminated_residual_jacobian(
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
            let __t185: f64 = __t99 + __t99;
            let __t189: f64 = -__t125;
            let __t190: f64 = __t189 - __t125;
            let __t294: f64 = __t32 * __t49;
            let __t340: f64 = -__t294;
            let __t341: f64 = __t340 - __t294;
            let __t342: f64 = __mu_0 + __t341;
            let __t344: f64 = __t342 / __t138;
            let __t346: f64 = __t49 + __t344;
            let __t347: f64 = __t32 * __t346;
            let __t348: f64 = __t65 * __t347;
            let __t349: f64 = __t69 * __t346;
            let __t350: f64 = __t348 + __t349;
            let __t351: f64 = __t68 + __t350;
            let __t352: f64 = __w_0 + __t351;
            let __t353: f64 = __t78 * __t347;
            let __t354: f64 = __t82 * __t346;
            let __t355: f64 = __t353 + __t354;
            let __t356: f64 = __t81 + __t355;
            let __t357: f64 = __w_1 + __t356;
            let __t358: f64 = __t185 / __t138;
            let __t359: f64 = __t358 - __t97;
            let __t360: f64 = __t32 * __t359;
            let __t361: f64 = __t65 * __t360;
            let __t362: f64 = __t69 * __t359;
            let __t363: f64 = __t361 + __t362;
            let __t364: f64 = __t102 + __t363;
            let __t365: f64 = __t11 * __t347;
            let __t367: f64 = __t78 * __t360;
            let __t368: f64 = __t367 - __t365;
            let __t369: f64 = __t110 * __t346;
            let __t371: f64 = __t82 * __t359;
            let __t372: f64 = __t371 - __t369;
            let __t373: f64 = __t368 + __t372;
            let __t374: f64 = __t190 / __t138;
            let __t375: f64 = __t124 + __t374;
            let __t376: f64 = __t32 * __t375;
            let __t377: f64 = __t65 * __t376;
            let __t378: f64 = __t365 + __t377;
            let __t379: f64 = __t69 * __t375;
            let __t380: f64 = __t369 + __t379;
            let __t381: f64 = __t378 + __t380;
            let __t382: f64 = __t78 * __t376;
            let __t383: f64 = __t82 * __t375;
            let __t384: f64 = __t382 + __t383;
            let __t385: f64 = __t102 + __t384;
            let mut __jac = ::dirac::nalgebra::SMatrix::<f64, 3usize, 3usize>::zeros();
            __jac[(0usize, 0usize)] = __t364;
            __jac[(0usize, 1usize)] = __t381;
            __jac[(1usize, 0usize)] = __t373;
            __jac[(1usize, 1usize)] = __t385;
            __jac[(2usize, 2usize)] = __t102;
            (
                ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t352, __t357, __t93]),
                __jac,
            )
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn minus_eliminated_group(
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
            let __t294: f64 = __t32 * __t49;
            let __t340: f64 = -__t294;
            let __t341: f64 = __t340 - __t294;
            let __t342: f64 = __mu_0 + __t341;
            let __t344: f64 = __t342 / __t138;
            let __t345: f64 = -__t344;
            ::dirac::nalgebra::SVector::<f64, 1usize>::from([__t345])
        })
    }
    #[inline]
    #[allow(unused_variables)]
    fn minus_eliminated_group_block(
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
impl ::dirac::runtime::Unreduced<3usize, 1usize, 4usize> for ChargedParticle {
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
        let __t205: f64 = __q0_1 + __t5;
        let __t206: f64 = __t11 * __t205;
        let __t207: f64 = -__t2;
        let __t208: f64 = __t207 - __t2;
        let __t209: f64 = __t25 * __t208;
        let __t210: f64 = __t32 * __t206;
        let __t211: f64 = __t33 * __t206;
        let __t212: f64 = __t21 * __t210;
        let __t213: f64 = __t211 + __t212;
        let __t214: f64 = __t209 + __t213;
        let __p_0: f64 = p_k[0usize];
        let __t216: f64 = __t214 + __p_0;
        let __t217: f64 = -__q0_0;
        let __t218: f64 = __t217 - __t2;
        let __t219: f64 = __t11 * __t218;
        let __t220: f64 = -__t5;
        let __t221: f64 = __t220 - __t5;
        let __t222: f64 = __t25 * __t221;
        let __t223: f64 = __t32 * __t219;
        let __t224: f64 = __t33 * __t219;
        let __t225: f64 = __t21 * __t223;
        let __t226: f64 = __t224 + __t225;
        let __t227: f64 = __t222 + __t226;
        let __p_1: f64 = p_k[1usize];
        let __t229: f64 = __t227 + __p_1;
        let __t230: f64 = -__t8;
        let __t231: f64 = __t230 - __t8;
        let __t232: f64 = __t25 * __t231;
        let __p_2: f64 = p_k[2usize];
        let __t234: f64 = __t232 + __p_2;
        let __t235: f64 = -__t33;
        let __t236: f64 = __t235 - __t33;
        let __p_3: f64 = p_k[3usize];
        let __t238: f64 = __t236 + __p_3;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t216, __t229, __t234, __t238])
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
        let __t174: f64 = -__t32;
        let __t205: f64 = __q0_1 + __t5;
        let __t206: f64 = __t11 * __t205;
        let __t207: f64 = -__t2;
        let __t208: f64 = __t207 - __t2;
        let __t209: f64 = __t25 * __t208;
        let __t210: f64 = __t32 * __t206;
        let __t211: f64 = __t33 * __t206;
        let __t212: f64 = __t21 * __t210;
        let __t213: f64 = __t211 + __t212;
        let __t214: f64 = __t209 + __t213;
        let __p_0: f64 = p_k[0usize];
        let __t216: f64 = __t214 + __p_0;
        let __t217: f64 = -__q0_0;
        let __t218: f64 = __t217 - __t2;
        let __t219: f64 = __t11 * __t218;
        let __t220: f64 = -__t5;
        let __t221: f64 = __t220 - __t5;
        let __t222: f64 = __t25 * __t221;
        let __t223: f64 = __t32 * __t219;
        let __t224: f64 = __t33 * __t219;
        let __t225: f64 = __t21 * __t223;
        let __t226: f64 = __t224 + __t225;
        let __t227: f64 = __t222 + __t226;
        let __p_1: f64 = p_k[1usize];
        let __t229: f64 = __t227 + __p_1;
        let __t230: f64 = -__t8;
        let __t231: f64 = __t230 - __t8;
        let __t232: f64 = __t25 * __t231;
        let __p_2: f64 = p_k[2usize];
        let __t234: f64 = __t232 + __p_2;
        let __t235: f64 = -__t33;
        let __t236: f64 = __t235 - __t33;
        let __p_3: f64 = p_k[3usize];
        let __t238: f64 = __t236 + __p_3;
        let __t239: f64 = __q0_1 * __t11;
        let __t241: f64 = __t32 * __t239;
        let __t243: f64 = __t206 * __t241;
        let __t244: f64 = -__t243;
        let __t245: f64 = __t210 * __t239;
        let __t247: f64 = __t244 - __t245;
        let __t248: f64 = __t102 + __t247;
        let __t249: f64 = __t219 * __t241;
        let __t250: f64 = -__t249;
        let __t251: f64 = __t11 * __t33;
        let __t253: f64 = __t250 - __t251;
        let __t254: f64 = __t223 * __t239;
        let __t255: f64 = -__t254;
        let __t256: f64 = __t21 * __t110;
        let __t258: f64 = __t255 - __t256;
        let __t259: f64 = __t253 + __t258;
        let __t260: f64 = __t241 + __t241;
        let __t261: f64 = __q0_0 * __t11;
        let __t262: f64 = __t32 * __t261;
        let __t263: f64 = __t206 * __t262;
        let __t264: f64 = __t251 + __t263;
        let __t265: f64 = __t210 * __t261;
        let __t266: f64 = __t256 + __t265;
        let __t267: f64 = __t264 + __t266;
        let __t268: f64 = __t219 * __t262;
        let __t269: f64 = __t223 * __t261;
        let __t270: f64 = __t268 + __t269;
        let __t271: f64 = __t102 + __t270;
        let __t272: f64 = -__t262;
        let __t273: f64 = __t272 - __t262;
        let __t274: f64 = __t210 + __t210;
        let __t275: f64 = __t223 + __t223;
        let __t276: f64 = __t174 - __t32;
        let mut __jac = ::dirac::nalgebra::SMatrix::<f64, 4usize, 4usize>::zeros();
        __jac[(0usize, 0usize)] = __t248;
        __jac[(0usize, 1usize)] = __t267;
        __jac[(0usize, 3usize)] = __t274;
        __jac[(1usize, 0usize)] = __t259;
        __jac[(1usize, 1usize)] = __t271;
        __jac[(1usize, 3usize)] = __t275;
        __jac[(2usize, 2usize)] = __t102;
        __jac[(3usize, 0usize)] = __t260;
        __jac[(3usize, 1usize)] = __t273;
        __jac[(3usize, 3usize)] = __t276;
        (
            ::dirac::nalgebra::SVector::<
                f64,
                4usize,
            >::from([__t216, __t229, __t234, __t238]),
            __jac,
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
        let __t239: f64 = __q0_1 * __t11;
        let __t241: f64 = __t32 * __t239;
        let __t261: f64 = __q0_0 * __t11;
        let __t262: f64 = __t32 * __t261;
        let __t277: f64 = __t2 + __t2;
        let __t278: f64 = __t25 * __t277;
        let __t279: f64 = __t33 * __t239;
        let __t280: f64 = -__t279;
        let __t281: f64 = __t21 * __t241;
        let __t283: f64 = __t280 - __t281;
        let __t284: f64 = __t278 + __t283;
        let __t285: f64 = __t5 + __t5;
        let __t286: f64 = __t25 * __t285;
        let __t287: f64 = __t33 * __t261;
        let __t288: f64 = __t21 * __t262;
        let __t289: f64 = __t287 + __t288;
        let __t290: f64 = __t286 + __t289;
        let __t291: f64 = __t8 + __t8;
        let __t292: f64 = __t25 * __t291;
        let __t293: f64 = __t33 + __t33;
        ::dirac::nalgebra::SVector::<f64, 4usize>::from([__t284, __t290, __t292, __t293])
    }
}
