//! Sums of a per-element scalar over every element — the discrete Lagrangian `L_d(q0, q1)` and
//! the midpoint energy — serially and in the order of the body, with the first element that
//! reads outside the coordinates reported instead of a panic.

use super::assembly::gather;
use super::{ElementLagrangian, Family, FamilyVisitor};

/// Sums a per-element scalar over every element, serially, in order.
struct Scalar<G> {
    element: G,
    /// The number of coordinates: an element reading outside is an error.
    n: usize,
    total: f64,
    /// The first element that reads outside the coordinates.
    invalid: Option<String>,
}

/// What a scalar pass evaluates per element: its stencil values in `q0` and `q1`.
trait ElementScalar {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64;
}

impl<G: ElementScalar> FamilyVisitor for Scalar<G> {
    fn family<const S: usize, F: Family<S>>(&mut self, family: &F) {
        let (element, n) = (&self.element, self.n);
        let mut total = self.total;
        let invalid = &mut self.invalid;
        family.elements(&mut |indices, stencil| {
            if stencil.iter().all(|&g| g >= 0 && (g as usize) < n) {
                total += element.eval(family, indices, stencil.map(|g| g as usize));
            } else if invalid.is_none() {
                *invalid = Some(format!(
                    "element {indices:?} reads coordinates {stencil:?}, outside 0..{n}: the sizes are too small for its stencil"
                ));
            }
        });
        self.total = total;
    }
}

struct Value<'a> {
    q0: &'a [f64],
    q1: &'a [f64],
}

impl ElementScalar for Value<'_> {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64 {
        f.value(indices, &gather(self.q0, &st), &gather(self.q1, &st))
    }
}

struct Energy<'a> {
    q0: &'a [f64],
    q1: &'a [f64],
    h: f64,
}

impl ElementScalar for Energy<'_> {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64 {
        let q = std::array::from_fn(|a| 0.5 * (self.q0[st[a]] + self.q1[st[a]]));
        let v = std::array::from_fn(|a| (self.q1[st[a]] - self.q0[st[a]]) / self.h);
        f.energy(indices, &q, &v)
    }
}

struct EnergyAt<'a> {
    q: &'a [f64],
    v: &'a [f64],
}

impl ElementScalar for EnergyAt<'_> {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64 {
        f.energy(indices, &gather(self.q, &st), &gather(self.v, &st))
    }
}

/// The sum of `element` over every element, or the first element that reads outside the
/// coordinates. The callers check the vectors' lengths against the system's dimension.
fn scalar<L: ElementLagrangian, G: ElementScalar>(system: &L, element: G) -> Result<f64, String> {
    let mut visit = Scalar {
        element,
        n: system.dim(),
        total: 0.0,
        invalid: None,
    };
    system.families(&mut visit);
    visit.invalid.map_or(Ok(visit.total), Err)
}

/// `L_d(q0, q1)`, the sum of the element values (`q0`, `q1` of the system's dimension).
pub(super) fn value<L: ElementLagrangian>(
    system: &L,
    q0: &[f64],
    q1: &[f64],
) -> Result<f64, String> {
    scalar(system, Value { q0, q1 })
}

/// `E((q0 + q1)/2, (q1 − q0)/h)`, the sum of the element energies (`q0`, `q1` of the system's
/// dimension).
pub(super) fn energy<L: ElementLagrangian>(
    system: &L,
    q0: &[f64],
    q1: &[f64],
    h: f64,
) -> Result<f64, String> {
    scalar(system, Energy { q0, q1, h })
}

/// `E(q, v)`, the sum of the element energies at a point of `TQ` (`q`, `v` of the system's
/// dimension).
pub(super) fn energy_at<L: ElementLagrangian>(
    system: &L,
    q: &[f64],
    v: &[f64],
) -> Result<f64, String> {
    scalar(system, EnergyAt { q, v })
}

/// The impulse of the forces on one translation's orbit over a step: `Σ_e Σ_a (f_d^{e−} +
/// f_d^{e+})_a` over the force families' elements and their slots `a` whose coordinate lies in
/// `orbit`, at `(q0, q1)` — what the forced discrete Noether balance adds to the momentum map,
/// `μ_{k+1} = μ_k + impulse`. Elements reading outside the coordinates are skipped (the step's
/// checks report them).
pub(super) fn impulse<L: ElementLagrangian>(
    system: &L,
    orbit: &[std::ops::Range<usize>],
    q0: &[f64],
    q1: &[f64],
) -> f64 {
    struct Impulse<'a> {
        orbit: &'a [std::ops::Range<usize>],
        q0: &'a [f64],
        q1: &'a [f64],
        total: f64,
    }
    impl FamilyVisitor for Impulse<'_> {
        fn family<const S: usize, F: Family<S>>(&mut self, family: &F) {
            if !family.force() {
                return;
            }
            let (orbit, q0, q1, n) = (self.orbit, self.q0, self.q1, self.q0.len());
            let inside = |g: usize| orbit.iter().any(|r| r.contains(&g));
            let mut total = self.total;
            family.elements(&mut |indices, stencil| {
                let valid = stencil.iter().all(|&g| g >= 0 && (g as usize) < n);
                let st = stencil.map(|g| g.max(0) as usize);
                if !valid || !st.iter().any(|&g| inside(g)) {
                    return;
                }
                let (minus, plus) = family.d1_d2(indices, &gather(q0, &st), &gather(q1, &st));
                for (a, &g) in st.iter().enumerate() {
                    if inside(g) {
                        total += minus[a] + plus[a];
                    }
                }
            });
            self.total = total;
        }
    }
    let mut visit = Impulse {
        orbit,
        q0,
        q1,
        total: 0.0,
    };
    system.families(&mut visit);
    visit.total
}
