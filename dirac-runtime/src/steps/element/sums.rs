//! Sums of a per-element scalar over every element — the discrete Lagrangian `L_d(q0, q1)` and
//! the midpoint energy — serially and in the order of the body, with the first element that
//! reads outside the coordinates reported instead of a panic.

use super::pass::{gather, split_scratch, with_scratch, with_width, Width, WithWidth};
use super::{scratch_len, ElementLagrangian, Family, FamilyVisitor};

/// What a scalar pass sums per element, with the vectors it reads (each of the system's
/// dimension).
#[derive(Clone, Copy)]
enum PerElement<'a> {
    /// The element value `L_d^e(q0, q1)`.
    Value { q0: &'a [f64], q1: &'a [f64] },
    /// The element energy at the midpoint rule's point of `TQ`,
    /// `E^e((q0 + q1)/2, (q1 − q0)/h)` (§7.2.1).
    Midpoint {
        q0: &'a [f64],
        q1: &'a [f64],
        h: f64,
    },
    /// The element energy `E^e(q, v)` at a point of `TQ`.
    EnergyAt { q: &'a [f64], v: &'a [f64] },
}

impl PerElement<'_> {
    /// The element's scalar: its stencil values gathered into `a0`, `a1` (scratch of its width;
    /// `st` the element's checked stencil) and the family's value or energy on them.
    fn eval<F: Family>(
        self,
        f: &F,
        indices: &[i64],
        st: &[usize],
        a0: &mut [f64],
        a1: &mut [f64],
    ) -> f64 {
        match self {
            Self::Value { q0, q1 } => {
                gather(q0, st, a0);
                gather(q1, st, a1);
                f.value(indices, a0, a1)
            }
            Self::Midpoint { q0, q1, h } => {
                for (a, &g) in st.iter().enumerate() {
                    a0[a] = 0.5 * (q0[g] + q1[g]);
                    a1[a] = (q1[g] - q0[g]) / h;
                }
                f.energy(indices, a0, a1)
            }
            Self::EnergyAt { q, v } => {
                gather(q, st, a0);
                gather(v, st, a1);
                f.energy(indices, a0, a1)
            }
        }
    }
}

/// Sums a per-element scalar over every element, serially, in order.
struct Scalar<'a> {
    element: PerElement<'a>,
    /// The number of coordinates: an element reading outside is an error.
    n: usize,
    total: f64,
    /// The first element that reads outside the coordinates.
    invalid: Option<String>,
}

impl FamilyVisitor for Scalar<'_> {
    fn family<F: Family>(&mut self, family: &F) {
        let (element, n, w) = (self.element, self.n, family.width());
        let mut total = self.total;
        let invalid = &mut self.invalid;
        with_scratch(w, 2 * w, |st, values| {
            let (a0, a1) = values.split_at_mut(w);
            family.elements(&mut |indices, stencil| {
                if stencil.len() == w && stencil.iter().all(|&g| g >= 0 && (g as usize) < n) {
                    for (s, &g) in st.iter_mut().zip(stencil) {
                        *s = g as usize;
                    }
                    total += element.eval(family, indices, st, a0, a1);
                } else if invalid.is_none() {
                    *invalid = Some(format!(
                        "element {indices:?} reads coordinates {stencil:?}, outside 0..{n}: the sizes are too small for its stencil"
                    ));
                }
            });
        });
        self.total = total;
    }
}

/// The sum of `element` over every element, or the first element that reads outside the
/// coordinates. The callers check the vectors' lengths against the system's dimension.
fn scalar<L: ElementLagrangian>(system: &L, element: PerElement<'_>) -> Result<f64, String> {
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
    scalar(system, PerElement::Value { q0, q1 })
}

/// `E((q0 + q1)/2, (q1 − q0)/h)`, the sum of the element energies (`q0`, `q1` of the system's
/// dimension).
pub(super) fn energy<L: ElementLagrangian>(
    system: &L,
    q0: &[f64],
    q1: &[f64],
    h: f64,
) -> Result<f64, String> {
    scalar(system, PerElement::Midpoint { q0, q1, h })
}

/// `E(q, v)`, the sum of the element energies at a point of `TQ` (`q`, `v` of the system's
/// dimension).
pub(super) fn energy_at<L: ElementLagrangian>(
    system: &L,
    q: &[f64],
    v: &[f64],
) -> Result<f64, String> {
    scalar(system, PerElement::EnergyAt { q, v })
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
        fn family<F: Family>(&mut self, family: &F) {
            if !family.force() {
                return;
            }
            let w = family.width();
            self.total = with_scratch(w, scratch_len(w), |st, scratch| {
                with_width(
                    w,
                    ImpulseFamily {
                        family,
                        total: self.total,
                        orbit: self.orbit,
                        q0: self.q0,
                        q1: self.q1,
                        st,
                        scratch,
                    },
                )
            });
        }
    }
    /// One force family's part of the impulse, with its width a constant when small.
    struct ImpulseFamily<'a, 'b, F> {
        family: &'a F,
        /// The impulse of the families before this one (the sum continues from it).
        total: f64,
        orbit: &'a [std::ops::Range<usize>],
        q0: &'a [f64],
        q1: &'a [f64],
        st: &'b mut [usize],
        scratch: &'b mut [f64],
    }
    impl<F: Family> WithWidth for ImpulseFamily<'_, '_, F> {
        type Output = f64;
        #[inline(always)]
        fn run<W: Width>(self, width: W) -> f64 {
            let ImpulseFamily {
                family,
                mut total,
                orbit,
                q0,
                q1,
                st,
                scratch,
            } = self;
            let (n, w) = (q0.len(), width.get());
            let inside = |g: usize| orbit.iter().any(|r| r.contains(&g));
            let (a0, a1, out) = split_scratch(scratch, w);
            let (a0, a1, st, out) = (&mut a0[..w], &mut a1[..w], &mut st[..w], &mut out[..2 * w]);
            family.elements(&mut |indices, stencil| {
                let valid =
                    stencil.len() == w && stencil.iter().all(|&g| g >= 0 && (g as usize) < n);
                if !valid {
                    return;
                }
                for (s, &g) in st.iter_mut().zip(stencil) {
                    *s = g as usize;
                }
                if !st.iter().any(|&g| inside(g)) {
                    return;
                }
                gather(q0, st, a0);
                gather(q1, st, a1);
                family.d1_d2(indices, a0, a1, out);
                let (minus, plus) = out.split_at(w);
                for (a, &g) in st.iter().enumerate() {
                    if inside(g) {
                        total += minus[a] + plus[a];
                    }
                }
            });
            total
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
