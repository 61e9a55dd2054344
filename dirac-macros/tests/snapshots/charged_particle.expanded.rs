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
    ///Generated code: 42 operations for R(z), 77 for R(z) with ∂R/∂z, 32 for the momentum update.
    pub const GENERATED: &'static str = "Generated code: 42 operations for R(z), 77 for R(z) with ∂R/∂z, 32 for the momentum update.";
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
        let __t51: f64 = __t49 + __g1_0;
        let __t58: f64 = __t32 * __t51;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __t70: f64 = __t58 * __t65;
        let __t71: f64 = __t51 * __t69;
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
        let __t83: f64 = __t58 * __t78;
        let __t84: f64 = __t51 * __t82;
        let __t85: f64 = __t83 + __t84;
        let __t86: f64 = __t81 + __t85;
        let __w_1: f64 = w_k[1usize];
        let __t88: f64 = __t86 + __w_1;
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __t94: f64 = __t58 + __t58;
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
        let __t51: f64 = __t49 + __g1_0;
        let __t58: f64 = __t32 * __t51;
        let __t64: f64 = __x0_1 + __t42;
        let __t65: f64 = __t11 * __t64;
        let __t66: f64 = -__t39;
        let __t67: f64 = __t66 - __t39;
        let __t68: f64 = __t25 * __t67;
        let __t69: f64 = __t32 * __t65;
        let __t70: f64 = __t58 * __t65;
        let __t71: f64 = __t51 * __t69;
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
        let __t83: f64 = __t58 * __t78;
        let __t84: f64 = __t51 * __t82;
        let __t85: f64 = __t83 + __t84;
        let __t86: f64 = __t81 + __t85;
        let __w_1: f64 = w_k[1usize];
        let __t88: f64 = __t86 + __w_1;
        let __t89: f64 = -__t45;
        let __t90: f64 = __t89 - __t45;
        let __t91: f64 = __t25 * __t90;
        let __w_2: f64 = w_k[2usize];
        let __t93: f64 = __t91 + __w_2;
        let __t94: f64 = __t58 + __t58;
        let __mu_0: f64 = mu_k[0usize];
        let __t96: f64 = __t94 - __mu_0;
        let __t97: f64 = __t11 * __x0_1;
        let __t101: f64 = __t32 * __t97;
        let __t102: f64 = -__t101;
        let __t109: f64 = __t11 * __x0_0;
        let __t112: f64 = __t32 * __t109;
        let __t120: f64 = __t25 * (-2f64);
        let __t121: f64 = __t65 * __t101;
        let __t122: f64 = -__t121;
        let __t123: f64 = __t69 * __t97;
        let __t125: f64 = __t122 - __t123;
        let __t126: f64 = __t120 + __t125;
        let __t128: f64 = __t11 * __t32;
        let __t130: f64 = __t78 * __t101;
        let __t131: f64 = -__t130;
        let __t132: f64 = __t11 * __t58;
        let __t134: f64 = __t131 - __t132;
        let __t135: f64 = __t82 * __t97;
        let __t136: f64 = -__t135;
        let __t137: f64 = __t51 * __t128;
        let __t139: f64 = __t136 - __t137;
        let __t140: f64 = __t134 + __t139;
        let __t141: f64 = __t102 - __t101;
        let __t142: f64 = __t65 * __t112;
        let __t143: f64 = __t132 + __t142;
        let __t144: f64 = __t69 * __t109;
        let __t145: f64 = __t137 + __t144;
        let __t146: f64 = __t143 + __t145;
        let __t147: f64 = __t78 * __t112;
        let __t148: f64 = __t82 * __t109;
        let __t149: f64 = __t147 + __t148;
        let __t150: f64 = __t120 + __t149;
        let __t151: f64 = __t112 + __t112;
        let __t152: f64 = __t69 + __t69;
        let __t153: f64 = __t82 + __t82;
        let __t154: f64 = __t32 + __t32;
        let mut __jac = ::dirac::nalgebra::SMatrix::<f64, 4usize, 4usize>::zeros();
        __jac[(0usize, 0usize)] = __t126;
        __jac[(0usize, 1usize)] = __t146;
        __jac[(0usize, 3usize)] = __t152;
        __jac[(1usize, 0usize)] = __t140;
        __jac[(1usize, 1usize)] = __t150;
        __jac[(1usize, 3usize)] = __t153;
        __jac[(2usize, 2usize)] = __t120;
        __jac[(3usize, 0usize)] = __t141;
        __jac[(3usize, 1usize)] = __t151;
        __jac[(3usize, 3usize)] = __t154;
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
        let __t51: f64 = __t49 + __g1_0;
        let __t58: f64 = __t32 * __t51;
        let __t97: f64 = __t11 * __x0_1;
        let __t99: f64 = __t39 + __t39;
        let __t100: f64 = __t25 * __t99;
        let __t101: f64 = __t32 * __t97;
        let __t103: f64 = __t58 * __t97;
        let __t104: f64 = -__t103;
        let __t105: f64 = __t51 * __t101;
        let __t107: f64 = __t104 - __t105;
        let __t108: f64 = __t100 + __t107;
        let __t109: f64 = __t11 * __x0_0;
        let __t110: f64 = __t42 + __t42;
        let __t111: f64 = __t25 * __t110;
        let __t112: f64 = __t32 * __t109;
        let __t113: f64 = __t58 * __t109;
        let __t114: f64 = __t51 * __t112;
        let __t115: f64 = __t113 + __t114;
        let __t116: f64 = __t111 + __t115;
        let __t117: f64 = __t45 + __t45;
        let __t118: f64 = __t25 * __t117;
        ::dirac::nalgebra::SVector::<f64, 3usize>::from([__t108, __t116, __t118])
    }
}
