//! `dirac run` of a system on vector spaces at a size the fixed-size instances do not serve
//! (more than `dirac_jit::MAX_DISPATCHED` coordinates; with constraints beyond
//! `dirac_jit::MAX_DISPATCHED_CONSTRAINED`): its element view (`dirac_jit::Code::element_view`:
//! the whole `L_d` one element reading every coordinate, each group coordinate a translation
//! whose momentum `μ = p_g` is kept exact, each constraint row a constraint family) on the
//! element integrators, which take their sizes at run time. The method's words keep their
//! meaning: the reduced (+)/(−) equations (4.6), (4.8) are the element (+)/(−) sides in the
//! user's coordinates (the same trajectory to round-off), "unreduced" the (+) side. A reduced
//! start `x, w, mu, g` becomes `q = (x, g)`, `p = (w − Bᵀ μ, μ)` (eq. (3.7)); the file has the
//! columns `q_<coordinate>`, `p_<coordinate>` of every state, named after the coordinates.

use std::sync::Arc;

use dirac::prelude::*;
use dirac::runtime::element::{ElementConstrainedIntegrator, ElementIntegrator, ElementState};
use dirac_jit::{Code, RunRequest};

use super::{values, write, Config};

/// Integrates the text's system on its element view and writes the run.
pub(super) fn run_view(
    code: &Arc<Code>,
    config: &Config,
    request: RunRequest,
) -> Result<String, String> {
    let view = code.element_view().map_err(|e| e.to_string())?;
    let sys = view
        .instantiate_named(&config.named(), &[])
        .map_err(|e| e.to_string())?;
    let text = code.system();
    let (s, k) = (text.shape.len(), text.group.len());
    let start = match request.equations.form {
        Form::Unreduced => {
            ElementState::new(values(config, "q", s + k)?, values(config, "p", s + k)?)
        }
        Form::Reduced => {
            let (x, w) = (values(config, "x", s)?, values(config, "w", s)?);
            let (mu, g) = (values(config, "mu", k)?, values(config, "g", k)?);
            let b = code
                .connection(&sys.parameter_values())
                .map_err(|e| e.to_string())?;
            let q: Vec<f64> = x.iter().chain(&g).copied().collect();
            let p: Vec<f64> = (0..s)
                .map(|i| w[i] - (0..k).map(|j| b[j * s + i] * mu[j]).sum::<f64>())
                .chain(mu.iter().copied())
                .collect();
            ElementState::new(q, p)
        }
    };
    let (plus, options) = (request.equations.side == Variant::Plus, request.newton);
    match (text.constrained.is_some(), plus) {
        (false, true) => write(ElementIntegrator::new(sys, options), start, config, request),
        (false, false) => write(
            ElementIntegrator::minus(sys, options),
            start,
            config,
            request,
        ),
        (true, true) => write(
            ElementConstrainedIntegrator::new(sys, options),
            start,
            config,
            request,
        ),
        (true, false) => write(
            ElementConstrainedIntegrator::minus(sys, options),
            start,
            config,
            request,
        ),
    }
}
