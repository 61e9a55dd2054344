//! The calls of a compiled system's kernels at given parameter values: written once for the
//! system at fixed dimensions ([`JitLie`](super::JitLie)) and at sizes chosen at run time
//! ([`DynJitLie`](super::DynJitLie)).

use dirac_runtime::lie::{CoordinateKind, LiePartials};
use dirac_runtime::nalgebra::DMatrix;

use super::LieCode;
use crate::codegen::Kernel;
use crate::system::UNUSED;
use crate::MAX_PARAMETERS;

impl LieCode {
    /// Calls `kernel` on the parameter `values` and `args` (a step's `q_k`, `p_k`, `z`, or what
    /// the kernel's layout names), writing its outputs at `out`: the one call of the kernels of
    /// [`JitLie`](super::JitLie) and [`DynJitLie`](super::DynJitLie).
    #[inline]
    pub(super) fn call_into(
        &self,
        values: &[f64; MAX_PARAMETERS],
        kernel: Kernel,
        args: [*const f64; 3],
        out: *mut f64,
    ) {
        // SAFETY: every kernel reads only the entries its layout names, which the compiler
        // bounds by the system's sizes — the lengths of the point and chart vectors every caller
        // passes: a `JitLie`'s dimensions are checked equal to the system's on instantiation, and
        // the integrators build a `DynJitLie`'s vectors at `dims()` and refuse a state of other
        // sizes before a step — and writes exactly as many `f64` as its program has outputs,
        // which is the size of the memory at `out` at every call site (a vector of the program's
        // outputs, or the buffer of the step Jacobian, sized by the backend checked on
        // instantiation or by the compiler's pattern).
        unsafe {
            kernel(values.as_ptr(), args[0], args[1], args[2], UNUSED, out);
        }
    }

    /// Step kernel `i` (0 the residual, 1 its Jacobian, 2 the momentum update): the reduced
    /// step's when `reduced` and the system compiled one, else the unreduced step's, which a
    /// system without a reduced step solves in its place.
    #[inline]
    pub(super) fn step_kernel(&self, i: usize, reduced: bool) -> Kernel {
        match self.kernels.reduced {
            Some(k) if reduced => k[i],
            _ => self.kernels.step[i],
        }
    }

    /// The coordinate `i`: its name and kind, `None` past the last.
    #[inline]
    pub(super) fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)> {
        let c = self.system.coordinates.get(i)?;
        Some((c.name.as_str(), self.kinds[i]))
    }

    /// `L_d(q0, q1)` at the parameter `values`.
    #[inline]
    pub(super) fn lagrangian(
        &self,
        values: &[f64; MAX_PARAMETERS],
        q0: *const f64,
        q1: *const f64,
    ) -> f64 {
        let mut out = 0.0;
        self.call_into(values, self.kernels.lagrangian, [q0, q1, UNUSED], &mut out);
        out
    }

    /// The step monitor `g(q)` at the parameter `values`, `None` in physical time.
    #[inline]
    pub(super) fn monitor(&self, values: &[f64; MAX_PARAMETERS], q: *const f64) -> Option<f64> {
        let kernel = self.kernels.monitor?;
        let mut out = 0.0;
        self.call_into(values, kernel, [q, UNUSED, UNUSED], &mut out);
        Some(out)
    }

    /// The partial derivatives of the step at its arguments `args` (`q_k`, `p_k`, `z`), `None`
    /// where the compiler emitted none: the kernel's six row-major blocks `∂R̃/∂w`, `∂R̃/∂δ`,
    /// `∂R̃/∂u`, `∂O/∂w`, `∂O/∂δ`, `∂O/∂u` (`N × N`, `N × N`, `N × m`, ..).
    pub(super) fn step_partials(
        &self,
        values: &[f64; MAX_PARAMETERS],
        args: [*const f64; 3],
    ) -> Option<LiePartials> {
        let kernel = self.kernels.partials?;
        let (n, u) = (self.system.chart_len(), self.system.controls.len());
        let mut out = vec![0.0; 4 * n * n + 2 * n * u];
        self.call_into(values, kernel, args, out.as_mut_ptr());
        let mut blocks = [n, n, u, n, n, u].into_iter().scan(0, |at, cols| {
            let block = DMatrix::from_row_slice(n, cols, &out[*at..*at + n * cols]);
            *at += n * cols;
            Some(block)
        });
        let mut next = || blocks.next().expect("six blocks");
        Some(LiePartials {
            r_w: next(),
            r_y: next(),
            r_u: next(),
            o_w: next(),
            o_y: next(),
            o_u: next(),
        })
    }
}
