//! Systems on vector spaces at sizes the fixed-size instances do not serve: more than
//! `dirac_jit::MAX_DISPATCHED` coordinates, or constraints beyond
//! `dirac_jit::MAX_DISPATCHED_CONSTRAINED` (and every constrained ensemble). `System.run`,
//! `write` and `ensemble` run them on their element view (`dirac_jit::Code::element_view`): the
//! whole `L_d` as one element, each group coordinate a translation whose momentum map
//! `μ = p_g` is kept exact, each constraint row a constraint family, on the element
//! integrators, which take their sizes at run time. The method words keep their meaning: the
//! reduced (+) and (−) equations (4.6), (4.8) are the element (+) and (−) sides in the user's
//! coordinates (the same trajectory, to round-off), "unreduced" the (+) side. A reduced run's
//! start `x, w, μ, g` becomes `q = (x, g)`, `p = (w − Bᵀ μ, μ)` (eq. (3.7)) and its states come
//! back as `x, w = p_x + Bᵀ μ, μ, g` beside `q` and `p`: the result has the same shape on both
//! paths.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use dirac_jit::run::Connection;
use dirac_jit::{Code, JitElement, RunRequest};
use dirac_runtime::element::{
    ElementIntegrator, ElementLagrangian, ElementState, ElementTrajectory,
};
use dirac_runtime::{Form, System};

use crate::element::Flat as ElementFlat;
use crate::ensemble::Member;
use crate::results::{Failed, Flat};
use crate::runs::{collected, Collect, Ensemble};

/// The element view of `code` at `params` and its connection, which map a run of the view back
/// to a run of the system.
struct View {
    sys: JitElement,
    connection: Connection,
    s: usize,
    k: usize,
}

impl View {
    fn new(code: &Arc<Code>, params: &[f64]) -> Result<View, String> {
        let view = code.element_view().map_err(|e| e.to_string())?;
        let sys = view.instantiate(params, &[]).map_err(|e| e.to_string())?;
        let connection = Connection::new(code, params).map_err(|e| e.to_string())?;
        let text = code.system();
        Ok(View {
            sys,
            connection,
            s: text.shape.len(),
            k: text.group.len(),
        })
    }

    /// A run of the view as a run of the system: `q`, `p` and, for a reduced run, `x, w, μ, g`
    /// (eq. (3.7), [`Connection::reduced`]).
    fn flat(&self, form: Form, f: ElementFlat) -> Flat {
        let (s, k) = (self.s, self.k);
        let n = s + k;
        let rows = f.t.len();
        let mut parts = Vec::new();
        if form == Form::Reduced {
            let mut reduced: [Vec<f64>; 4] = Default::default();
            for r in 0..rows {
                let (q, p) = (&f.q[r * n..(r + 1) * n], &f.p[r * n..(r + 1) * n]);
                for (all, one) in reduced.iter_mut().zip(self.connection.reduced(q, p)) {
                    all.extend(one);
                }
            }
            let [x, w, mu, g] = reduced;
            parts.extend([("x", s, x), ("w", s, w), ("mu", k, mu), ("g", k, g)]);
        }
        parts.extend([("q", n, f.q), ("p", n, f.p)]);
        Flat {
            t: f.t,
            parts,
            iterations: f.iterations,
            residuals: f.residuals,
            multipliers: f
                .multipliers
                .map(|(lambda, residual)| (self.sys.constraint_count(), lambda, residual)),
            energies: None,
        }
    }

    fn member(&self, form: Form, m: Member<ElementFlat>) -> Member<Flat> {
        match m {
            Ok(f) => Ok(self.flat(form, f)),
            Err(failed) => {
                let Failed { error, partial } = *failed;
                Err(Box::new(Failed {
                    error,
                    partial: self.flat(form, partial),
                }))
            }
        }
    }

    /// The continuous energies of a run of the view (`ElementIntegrator::energies`: at each
    /// state through the inverse Legendre map, at each step's midpoint), or why there are none.
    fn energies(&self, f: &ElementFlat, r: &RunRequest) -> Result<(Vec<f64>, Vec<f64>), String> {
        let n = self.s + self.k;
        let states: Vec<ElementState> = (0..f.t.len())
            .map(|k| ElementState::new(&f.q[k * n..(k + 1) * n], &f.p[k * n..(k + 1) * n]))
            .collect();
        let h = self.sys.time_step();
        let trajectory = ElementTrajectory {
            h,
            variant: r.equations.side,
            states,
            times: f.t.clone(),
            step_sizes: f.t.windows(2).map(|w| w[1] - w[0]).collect(),
            stats: Vec::new(),
        };
        ElementIntegrator::new(self.sys.clone(), r.newton)
            .energies(&trajectory)
            .map(|e| (e.nodes, e.midpoints))
            .map_err(|e| e.to_string())
    }
}

/// One run of `code` from `start` (`x, w, mu, g` or `q, p`, by the method) on its element
/// view (order 2, 4 or 6; constrained: 2), with the continuous energies of its states when
/// `energies` is set.
pub(crate) fn run_one(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
    energies: bool,
    cancel: &AtomicBool,
) -> Result<Result<Flat, Box<Failed>>, String> {
    let view = View::new(code, params)?;
    let form = r.equations.form;
    let starts = [start.to_vec()];
    let run = collected(dirac_jit::run::view(
        code,
        params,
        &starts,
        &r,
        Collect::new(cancel, false),
    ))?;
    Ok(match run {
        Ok(f) => {
            let e = energies.then(|| view.energies(&f, &r));
            let mut flat = view.flat(form, f);
            flat.energies = e;
            Ok(flat)
        }
        Err(failed) => view.member(form, Err(failed)),
    })
}

/// An ensemble of `code` (order 2), one member per start, on its element view.
pub(crate) fn run_many(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    r: RunRequest,
    cancel: &AtomicBool,
) -> Result<Vec<Member<Flat>>, String> {
    let view = View::new(code, params)?;
    let form = r.equations.form;
    let members = collected(dirac_jit::run::view(
        code,
        params,
        starts,
        &r,
        Ensemble::new(cancel),
    ))?;
    Ok(members.into_iter().map(|m| view.member(form, m)).collect())
}
