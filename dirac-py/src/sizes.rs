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

use dirac_jit::{Code, JitElement, RunRequest};
use dirac_runtime::element::{
    ElementIntegrator, ElementLagrangian, ElementState, ElementTrajectory,
};
use dirac_runtime::{Form, System};

use crate::element::{self, Flat as ElementFlat};
use crate::ensemble::Member;
use crate::parquet::Written;
use crate::results::{Failed, Flat};

/// The element view of `code` at `params`, and its connection `B` (`K × S`, row by row).
struct View {
    sys: JitElement,
    b: Vec<f64>,
    s: usize,
    k: usize,
}

impl View {
    fn new(code: &Arc<Code>, params: &[f64]) -> Result<View, String> {
        let view = code.element_view().map_err(|e| e.to_string())?;
        let sys = view.instantiate(params, &[]).map_err(|e| e.to_string())?;
        let b = code.connection(params).map_err(|e| e.to_string())?;
        let text = code.system();
        Ok(View {
            sys,
            b,
            s: text.shape.len(),
            k: text.group.len(),
        })
    }

    /// `(Bᵀ μ)_i`.
    fn bt_mu(&self, mu: &[f64], i: usize) -> f64 {
        (0..self.k).map(|j| self.b[j * self.s + i] * mu[j]).sum()
    }

    /// The element state of a start: `q, p` as given, or `x, w, μ, g` by eq. (3.7).
    fn start(&self, form: Form, start: &[Vec<f64>]) -> ElementState {
        match form {
            Form::Unreduced => ElementState::new(start[0].clone(), start[1].clone()),
            Form::Reduced => {
                let (x, w, mu, g) = (&start[0], &start[1], &start[2], &start[3]);
                let q: Vec<f64> = x.iter().chain(g).copied().collect();
                let p: Vec<f64> = (0..self.s)
                    .map(|i| w[i] - self.bt_mu(mu, i))
                    .chain(mu.iter().copied())
                    .collect();
                ElementState::new(q, p)
            }
        }
    }

    /// A run of the view as a run of the system: `q`, `p` and, for a reduced run, `x, w, μ, g`.
    fn flat(&self, form: Form, f: ElementFlat) -> Flat {
        let (s, k) = (self.s, self.k);
        let n = s + k;
        let rows = f.t.len();
        let mut parts = Vec::new();
        if form == Form::Reduced {
            let (mut x, mut w) = (Vec::with_capacity(rows * s), Vec::with_capacity(rows * s));
            let (mut mu, mut g) = (Vec::with_capacity(rows * k), Vec::with_capacity(rows * k));
            for r in 0..rows {
                let (q, p) = (&f.q[r * n..(r + 1) * n], &f.p[r * n..(r + 1) * n]);
                x.extend_from_slice(&q[..s]);
                g.extend_from_slice(&q[s..]);
                mu.extend_from_slice(&p[s..]);
                w.extend((0..s).map(|i| p[i] + self.bt_mu(&p[s..], i)));
            }
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
    let s0 = view.start(form, start);
    let run = element::run_one(view.sys.clone(), s0, r.clone(), cancel);
    let with_energies = |f: &ElementFlat| energies.then(|| view.energies(f, &r));
    Ok(match run {
        Ok(f) => {
            let e = with_energies(&f);
            let mut flat = view.flat(form, f);
            flat.energies = e;
            Ok(flat)
        }
        Err(failed) => view.member(form, Err(failed)),
    })
}

impl View {
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
    let s0: Vec<ElementState> = starts.iter().map(|s| view.start(form, s)).collect();
    let members = element::run_many(view.sys.clone(), &s0, r, cancel)?;
    Ok(members.into_iter().map(|m| view.member(form, m)).collect())
}

/// One run of `code` written to Parquet at `path` on its element view (the columns named
/// after the coordinates, `q` and `p`).
pub(crate) fn write_one(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
    path: &std::path::Path,
    cancel: &AtomicBool,
) -> Result<Written, String> {
    let view = View::new(code, params)?;
    let s0 = view.start(r.equations.form, start);
    element::write_run(view.sys, s0, &r, path, cancel)
}
