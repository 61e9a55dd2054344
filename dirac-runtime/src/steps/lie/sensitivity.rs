//! Sensitivities of the unreduced step on rotation groups: the derivatives of a step's result
//! with respect to its start and its controls, in the charts at the two points, by the
//! implicit-function theorem on the step residual.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::{zeros, LieIntegratorOf, LieModel, LieStateOf};
use crate::error::StepError;
use crate::newton::slice_inf_norm;
use crate::stepper::{system_at, StepAt, StepStats};

impl<L, P: Dim, N: Dim> LieIntegratorOf<L, P, N>
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The sensitivity of step `k` from `state` to `next` under the controls `u` (empty: the
    /// system's own), in the charts at the two points: the state near `(q, p)` is
    /// `(φ_q(δ), p)` — `δ` the chart coordinate, `p` the momentum in the chart at the perturbed
    /// point — so [`Sensitivity::state`](crate::Sensitivity::state) is `∂(w, p_{k+1})/∂(δ, p_k)` (each `N × N` block in the
    /// order of [`LieModel::coordinate`]) and [`Sensitivity::control`](crate::Sensitivity::control) is
    /// `∂(w, p_{k+1})/∂u`, where `q'_{k+1} = φ_{q_{k+1}}(w)`. By the implicit-function theorem
    /// on the step residual in these charts ([`LiePartials`](super::LiePartials)): `dw = −R̃_w⁻¹ (R̃_δ dδ + dp + R̃_u
    /// du)`, `dp_{k+1} = O_w dw + O_δ dδ + O_u du`.
    ///
    /// A typed error for a system compiled without its partials (the sparse backend), a step
    /// whose chart Jacobian is singular, or controls of the wrong number.
    pub fn sensitivity(
        &self,
        k: usize,
        state: &LieStateOf<P, N>,
        next: &LieStateOf<P, N>,
        u: &[f64],
    ) -> Result<crate::Sensitivity, StepError> {
        let owned = system_at(self.system(), k, self.system().time_step(), u)?;
        let sys = owned.as_ref().unwrap_or(self.system());
        let z = self.chart_coordinates(&state.q, &next.q);
        let parts = sys
            .step_partials(&state.q, &state.p, &z)
            .ok_or(StepError::Unsupported {
                what: "step sensitivities: the compiler emits the step's partial derivatives for \
                       systems on rotation groups of at most 16 dimensions",
            })?;
        let m = self.system().control_count();
        let n = self.system().dims().1.value();
        let cols = 2 * n + m;
        let mut rhs = nalgebra::DMatrix::<f64>::zeros(n, cols);
        rhs.view_mut((0, 0), (n, n)).copy_from(&parts.r_y);
        for i in 0..n {
            rhs[(i, n + i)] = 1.0;
        }
        rhs.view_mut((0, 2 * n), (n, m)).copy_from(&parts.r_u);
        let mut r = zeros(self.system().dims().1);
        sys.residual_into(&state.q, &state.p, &z, &mut r);
        let residual = slice_inf_norm(r.as_slice());
        let lu = parts.r_w.clone().lu();
        let dw = -lu
            .solve(&rhs)
            .ok_or(StepError::SingularJacobian { step: k, residual })?;
        let mut dp = &parts.o_w * &dw;
        let mut view = dp.view_mut((0, 0), (n, n));
        view += &parts.o_y;
        let mut view = dp.view_mut((0, 2 * n), (n, m));
        view += &parts.o_u;
        let mut full = nalgebra::DMatrix::<f64>::zeros(2 * n, cols);
        full.view_mut((0, 0), (n, cols)).copy_from(&dw);
        full.view_mut((n, 0), (n, cols)).copy_from(&dp);
        Ok(crate::Sensitivity {
            state: full.view((0, 0), (2 * n, 2 * n)).into_owned(),
            control: full.view((0, 2 * n), (2 * n, m)).into_owned(),
        })
    }

    /// The largest relative defect `|L_d(q0, q1; −h) + L_d(q1, q0; h)|` over sample pairs
    /// `(q, φ_q(δ d_j))` and the reversed pairs, for three fixed directions `d_j` and
    /// `δ = 0.05`: zero for a symmetric discrete Lagrangian, up to round-off.
    pub fn symmetry_defect(&self, q: &OVector<f64, P>) -> f64 {
        self.defect_of_symmetry(q)
    }

    /// Takes step `k` from `state` with the controls `u` in a fresh workspace and returns the
    /// new state, the step's statistics and its [`Self::sensitivity`].
    pub fn step_sensitivity(
        &self,
        k: usize,
        state: &LieStateOf<P, N>,
        u: &[f64],
    ) -> Result<(LieStateOf<P, N>, StepStats, crate::Sensitivity), StepError> {
        let at = StepAt::new(k, self.system().time_step()).with_controls(u);
        let mut next = state.clone();
        let stats = self.unreduced_step_into(&mut self.new_workspace(), at, state, &mut next)?;
        let sensitivity = self.sensitivity(k, state, &next, u)?;
        Ok((next, stats, sensitivity))
    }
}
