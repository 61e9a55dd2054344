//! Randomly generated discrete Lagrangians: the first and second derivatives that
//! `#[reduced_lagrangian]` generates at compile time agree with num-dual at run time.
//!
//! `random_exprs/generate.rs` (a deterministic generator with a fixed seed) renders the cases into
//! the committed file `random_exprs/cases.rs`, each case twice: the macro input `case_NNN` and a
//! generic num-dual reference `case_NNN_ref` over `q = (a, b, c[, d])`. For each case,
//! [`check_case`] builds the reduced Lagrangian of eq. (4.5),
//! `l(x0, x1, g1) = L_d((x0, 0), (x1, g1 + B (x1 − x0)))`, from the reference on second-order
//! dual numbers in `v = (x0, x1, g1)`, and compares at several pseudo-random points
//!
//! * `Reduced<Plus, ..>::residual` (labelled `plus_residual`) and the vector of
//!   `residual_jacobian` with `(∂l/∂x0 + w_k, ∂l/∂g1 − μ_k)` at random momenta,
//! * the matrix of `residual_jacobian` with the Hessian block `∂(∂l/∂x0, ∂l/∂g1)/∂(x1, g1)`,
//! * `momentum` with `∂l/∂x1`,
//! * `reduced_lagrangian` (`l_{d+}`), `lagrangian` (the user's function body) and `connection`
//!   with the reference values,
//!
//! to `|a − b| ≤ 1e-12 · max(1, |a|, |b|)`.
//!
//! `cases_are_current` regenerates the text and checks it equals the committed file;
//! `DIRAC_BLESS=1 cargo test --test random_derivatives cases_are_current` rewrites it.

use dirac::nalgebra::{SMatrix, SVector};
use dirac::{Plus, Reduced};
use num_dual::{hessian, Dual2SVec64};

#[allow(dead_code)]
#[path = "random_exprs/generate.rs"]
mod generate;

#[allow(unused, unused_parens, clippy::all)]
mod random_exprs {
    include!("random_exprs/cases.rs");
}

/// Points per case.
const POINTS: usize = 5;
const TOL: f64 = 1e-12;

mod common;
use common::Rng;

/// What the comparisons saw.
#[derive(Default)]
pub struct Stats {
    pub cases: usize,
    pub comparisons: usize,
    /// Largest `|a − b| / max(1, |a|, |b|)` and where it was seen.
    pub worst: (f64, String),
    pub failures: Vec<String>,
    /// Largest `|reference|` compared, and how many compared reference values were nonzero.
    pub largest: f64,
    pub nonzero: usize,
    /// Perturbation added to every reference Jacobian entry (to show the check can fail).
    pub perturb_jacobian: f64,
}

impl Stats {
    fn compare(&mut self, case: &str, what: &str, at: &str, generated: f64, reference: f64) {
        self.comparisons += 1;
        self.largest = self.largest.max(reference.abs());
        self.nonzero += usize::from(reference != 0.0);
        let scale = 1f64.max(generated.abs()).max(reference.abs());
        let scaled = (generated - reference).abs() / scale;
        if scaled > self.worst.0 || scaled.is_nan() {
            self.worst = (scaled, format!("{case} {what} at {at}"));
        }
        if scaled.is_nan() || scaled > TOL || !generated.is_finite() || !reference.is_finite() {
            self.failures.push(format!(
                "{case}: {what} at {at}: generated {generated:e}, num-dual {reference:e}, scaled error {scaled:e}"
            ));
        }
    }
}

/// Checks one generated case against its num-dual reference at [`POINTS`] points.
///
/// `S = 2` shape coordinates, `K` group coordinates, `N = S + K`, `M = 2S + K` dual directions.
pub fn check_case<Sys, const S: usize, const K: usize, const N: usize, const M: usize>(
    stats: &mut Stats,
    name: &str,
    make: fn(f64, f64) -> Sys,
    connection: fn(f64, f64) -> SMatrix<f64, K, S>,
    lag: fn(
        [Dual2SVec64<M>; N],
        [Dual2SVec64<M>; N],
        Dual2SVec64<M>,
        Dual2SVec64<M>,
    ) -> Dual2SVec64<M>,
    lag_f64: fn([f64; N], [f64; N], f64, f64) -> f64,
) where
    Sys: Reduced<Plus, S, K, N, Linear = dirac::runtime::Lu<N>>,
{
    assert_eq!((S + K, 2 * S + K), (N, M));
    stats.cases += 1;
    // One stream per case, so adding a case does not move the others' points.
    let mut rng = Rng(0x5EED
        ^ name
            .bytes()
            .fold(0u64, |h, b| h.wrapping_mul(131).wrapping_add(u64::from(b))));
    for _ in 0..POINTS {
        // The box generate.rs assumes: h ∈ [0.5, 1.5], p ∈ [−1, 1], x0, x1, g1 ∈ [−1, 1].
        let (h, p) = (rng.uniform(0.5, 1.5), rng.uniform(-1.0, 1.0));
        let sys = make(h, p);
        let b = connection(h, p);
        let v = SVector::<f64, M>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let x0 = SVector::<f64, S>::from_fn(|i, _| v[i]);
        let z = SVector::<f64, N>::from_fn(|i, _| v[S + i]);
        let at = format!(
            "h = {h:?}, p = {p:?}, x_k = {:?}, z = {:?}",
            x0.as_slice(),
            z.as_slice()
        );

        // The oracle: l(x0, x1, g1) on dual numbers, gradient and Hessian in v = (x0, x1, g1).
        let (value, grad, hess) = hessian(
            |v: SVector<Dual2SVec64<M>, M>| {
                let zero = Dual2SVec64::<M>::from(0.0);
                let q0: [Dual2SVec64<M>; N] =
                    std::array::from_fn(|i| if i < S { v[i] } else { zero });
                let q1: [Dual2SVec64<M>; N] = std::array::from_fn(|i| {
                    if i < S {
                        v[S + i]
                    } else {
                        let j = i - S;
                        let mut g = v[2 * S + j];
                        for c in 0..S {
                            g += (v[S + c] - v[c]) * b[(j, c)];
                        }
                        g
                    }
                });
                lag(q0, q1, h.into(), p.into())
            },
            &v,
        );

        let emitted_b = sys.connection();
        for j in 0..K {
            for c in 0..S {
                stats.compare(
                    name,
                    &format!("B[{j},{c}]"),
                    &at,
                    emitted_b[(j, c)],
                    b[(j, c)],
                );
            }
        }
        // Row r of R is ∂l/∂x0_r (r < S) or ∂l/∂g1_{r−S}: v index r or S + r. Column c is z_c: S + c.
        let out = |r: usize| if r < S { r } else { S + r };
        // R = (∂l/∂x0 + w_k, ∂l/∂g1 − μ_k): the momenta enter additively.
        let w_k = SVector::<f64, S>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let mu_k = SVector::<f64, K>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let offset = |r: usize| if r < S { w_k[r] } else { -mu_k[r - S] };
        let residual = sys.residual(&x0, &w_k, &mu_k, &z);
        let (residual_j, jac) = sys.residual_jacobian(&x0, &w_k, &mu_k, &z);
        let momentum = sys.momentum(&x0, &z);
        for r in 0..N {
            stats.compare(
                name,
                &format!("plus_residual[{r}]"),
                &at,
                residual[r],
                grad[out(r)] + offset(r),
            );
            stats.compare(
                name,
                &format!("plus_residual_jacobian.0[{r}]"),
                &at,
                residual_j[r],
                grad[out(r)] + offset(r),
            );
            for c in 0..N {
                let reference = hess[(out(r), S + c)] + stats.perturb_jacobian;
                stats.compare(
                    name,
                    &format!("plus_residual_jacobian.1[({r},{c})]"),
                    &at,
                    jac[(r, c)],
                    reference,
                );
            }
        }
        for i in 0..S {
            stats.compare(
                name,
                &format!("plus_momentum[{i}]"),
                &at,
                momentum[i],
                grad[S + i],
            );
        }
        let x1 = z.fixed_rows::<S>(0).into_owned();
        let g1 = z.fixed_rows::<K>(S).into_owned();
        stats.compare(
            name,
            "reduced_lagrangian_plus",
            &at,
            sys.reduced_lagrangian(&x0, &x1, &g1),
            value,
        );
        // L_d at a point with g0 ≠ 0: the user's body against the reference body, in f64.
        let q0: [f64; N] =
            std::array::from_fn(|i| if i < S { x0[i] } else { 0.25 + 0.5 * g1[i - S] });
        let q1: [f64; N] = std::array::from_fn(|i| z[i] * 0.9);
        stats.compare(
            name,
            "lagrangian",
            &at,
            sys.lagrangian(&SVector::from(q0), &SVector::from(q1)),
            lag_f64(q0, q1, h, p),
        );
    }
}

fn run(perturb_jacobian: f64) -> Stats {
    let mut stats = Stats {
        perturb_jacobian,
        ..Stats::default()
    };
    random_exprs::run_all(&mut stats);
    stats
}

#[test]
fn random_expressions_match_num_dual() {
    let stats = run(0.0);
    assert_eq!(stats.cases, random_exprs::CASES);
    assert!(stats.cases >= 200);
    println!(
        "{} cases, {} points each, {} comparisons ({} with a nonzero reference, largest |reference| {:.3e}); \
         worst scaled error {:.3e} ({})",
        stats.cases,
        POINTS,
        stats.comparisons,
        stats.nonzero,
        stats.largest,
        stats.worst.0,
        stats.worst.1
    );
    assert!(
        stats.failures.is_empty(),
        "{} disagreements between generated derivatives and num-dual:\n{}",
        stats.failures.len(),
        stats.failures.join("\n")
    );
}

/// The comparison is not vacuous: a reference Jacobian off by 1e-10 fails everywhere.
#[test]
fn a_perturbed_reference_is_caught() {
    let stats = run(1e-10);
    let jacobian_entries = stats.cases * POINTS;
    let caught = stats
        .failures
        .iter()
        .filter(|f| f.contains("plus_residual_jacobian.1"))
        .count();
    assert!(
        caught >= jacobian_entries,
        "only {caught} perturbed Jacobian entries were caught"
    );
}

#[test]
fn every_operation_and_feature_is_covered() {
    let generated = generate::generate();
    assert!(generated.cases >= 200);
    for (op, count) in generate::OPS.iter().zip(generated.op_counts) {
        assert!(
            count >= generated.cases / generate::OPS.len(),
            "{op:?} appears only {count} times"
        );
    }
    for (feature, count) in generate::FEATURES.iter().zip(generated.feature_counts) {
        assert!(count >= 5, "{feature:?} is used by only {count} cases");
    }
}

#[test]
fn cases_are_current() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/random_exprs/cases.rs");
    let generated = generate::generate().text;
    if std::env::var_os("DIRAC_BLESS").is_some_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("write cases.rs");
        return;
    }
    let committed = std::fs::read_to_string(&path).expect("read cases.rs");
    assert!(
        committed == generated,
        "tests/random_exprs/cases.rs is not what tests/random_exprs/generate.rs produces; \
         regenerate it with `DIRAC_BLESS=1 cargo test --test random_derivatives cases_are_current`"
    );
}
