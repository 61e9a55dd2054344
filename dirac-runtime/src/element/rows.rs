//! The constraint rows of a run-time-sized system as a run sees them, and the passes over them
//! and over the elements that a constrained step's saddle-point systems are assembled from
//! (see the [parent module](super::constrained)).

use super::assembly::{gather, FamilyData};
use super::{ConstraintFamily, ConstraintVisitor, ElementLagrangian, Family, FamilyVisitor};

/// The rows of one constraint family as a run sees them.
pub(super) struct RowData {
    pub(super) width: usize,
    pub(super) depth: usize,
    pub(super) count: usize,
    pub(super) indices: Vec<i64>,
    /// The row of every element.
    pub(super) rows: Vec<usize>,
    /// The stencil of every element, `width` per element.
    pub(super) stencils: Vec<usize>,
    /// For every element slot, the KKT positions of `A`'s entry (row `n + row`, column
    /// `stencil[a]`) and of `−Aᵀ`'s (row `stencil[a]`, column `n + row`).
    pub(super) a_pos: Vec<usize>,
    pub(super) at_pos: Vec<usize>,
}

/// Collects the constraint rows and checks them against `n` coordinates and `m` rows.
pub(super) struct RowCollector {
    pub(super) n: usize,
    pub(super) m: usize,
    pub(super) families: Vec<RowData>,
    pub(super) invalid: Option<String>,
}

impl ConstraintVisitor for RowCollector {
    fn constraint<const S: usize, F: ConstraintFamily<S>>(&mut self, family: &F) {
        let (n, m, index) = (self.n, self.m, self.families.len());
        let mut data = RowData {
            width: S,
            depth: family.depth(),
            count: 0,
            indices: Vec::new(),
            rows: Vec::new(),
            stencils: Vec::new(),
            a_pos: Vec::new(),
            at_pos: Vec::new(),
        };
        let invalid = &mut self.invalid;
        family.elements(&mut |indices, row, stencil| {
            data.count += 1;
            data.indices.extend_from_slice(indices);
            match usize::try_from(row).ok().filter(|&r| r < m) {
                Some(r) => data.rows.push(r),
                None => {
                    invalid.get_or_insert_with(|| {
                        format!(
                            "constraint element {indices:?} of family {index} assigns row {row}, \
                             outside 0..{m} (the constraint vector's length)"
                        )
                    });
                    data.rows.push(0);
                }
            }
            for (slot, &g) in stencil.iter().enumerate() {
                match usize::try_from(g).ok().filter(|&g| g < n) {
                    Some(g) => data.stencils.push(g),
                    None => {
                        invalid.get_or_insert_with(|| {
                            format!(
                                "constraint element {indices:?} of family {index} reads \
                                 coordinate {g} (slot {slot}), outside 0..{n}: the sizes are too \
                                 small for its stencil"
                            )
                        });
                        data.stencils.push(0);
                    }
                }
            }
        });
        self.families.push(data);
    }
}

/// Evaluates the constraint rows at `q`: `φ(q)` into `phi` (when given) and each element
/// slot's gradient into `grad` (when given, in the rows' stencil order).
pub(super) struct Rows<'a> {
    pub(super) data: &'a [RowData],
    pub(super) next: usize,
    pub(super) q: &'a [f64],
    pub(super) phi: Option<&'a mut [f64]>,
    pub(super) grad: Option<&'a mut [f64]>,
    /// Where the current family's slots start in `grad`.
    pub(super) offset: usize,
}

impl ConstraintVisitor for Rows<'_> {
    fn constraint<const S: usize, F: ConstraintFamily<S>>(&mut self, family: &F) {
        let data = &self.data[self.next];
        self.next += 1;
        for e in 0..data.count {
            let st = &data.stencils[e * S..(e + 1) * S];
            let (value, gradient) = family.value_gradient(
                &data.indices[e * data.depth..(e + 1) * data.depth],
                &gather::<S>(self.q, st),
            );
            if let Some(phi) = self.phi.as_deref_mut() {
                phi[data.rows[e]] = value;
            }
            if let Some(grad) = self.grad.as_deref_mut() {
                grad[self.offset + e * S..self.offset + (e + 1) * S].copy_from_slice(&gradient);
            }
        }
        self.offset += data.count * S;
    }
}

/// `φ(q)` and the gradients at `q`.
pub(super) fn rows_at<L: ElementLagrangian>(
    sys: &L,
    data: &[RowData],
    q: &[f64],
    phi: Option<&mut [f64]>,
    grad: Option<&mut [f64]>,
) {
    let mut visit = Rows {
        data,
        next: 0,
        q,
        phi,
        grad,
        offset: 0,
    };
    sys.constraint_families(&mut visit);
}

/// `r_q −= A(q_k)ᵀ λ` from the gradients `a` (by slot) and, when `kkt` is given, the `−Aᵀ`
/// block of those gradients and the `A` block of `with_a` (times its sign) into the KKT values.
pub(super) fn constraint_forces(
    data: &[RowData],
    a: &[f64],
    lambda: &[f64],
    r: &mut [f64],
    mut kkt: Option<&mut [f64]>,
    with_a: Option<(&[f64], f64)>,
) {
    let mut offset = 0;
    for f in data {
        let w = f.width;
        for e in 0..f.count {
            let l = lambda[f.rows[e]];
            for k in e * w..(e + 1) * w {
                let slot = offset + k;
                r[f.stencils[k]] -= a[slot] * l;
                if let Some(kkt) = kkt.as_deref_mut() {
                    kkt[f.at_pos[k]] -= a[slot];
                    if let Some((a1, sign)) = with_a {
                        kkt[f.a_pos[k]] += sign * a1[slot];
                    }
                }
            }
        }
        offset += f.count * w;
    }
}

/// Adds every element's `∂L^e/∂v (q, v)` into `r` and, when given, `∂²L^e/∂v²` into the KKT
/// values through the step Jacobian's positions.
pub(super) struct Legendre<'a> {
    pub(super) families: &'a [FamilyData],
    pub(super) next: usize,
    pub(super) q: &'a [f64],
    pub(super) v: &'a [f64],
    pub(super) r: &'a mut [f64],
    pub(super) kkt: Option<(&'a mut [f64], &'a [usize])>,
}

impl FamilyVisitor for Legendre<'_> {
    fn family<const S: usize, F: Family<S>>(&mut self, family: &F) {
        let data = &self.families[self.next];
        self.next += 1;
        if family.force() || S == 0 {
            return;
        }
        for e in 0..data.count {
            let st = &data.stencils[e * S..(e + 1) * S];
            let (g, hessian) = family.legendre(
                &data.indices[e * data.depth..(e + 1) * data.depth],
                &gather::<S>(self.q, st),
                &gather::<S>(self.v, st),
            );
            for a in 0..S {
                self.r[st[a]] += g[a];
            }
            if let Some((kkt, j_to_kkt)) = self.kkt.as_mut() {
                let pos = &data.positions[e * S * S..(e + 1) * S * S];
                for a in 0..S {
                    for b in 0..S {
                        kkt[j_to_kkt[pos[a * S + b]]] += hessian[a][b];
                    }
                }
            }
        }
    }
}

/// `r_ν = A(q_{k+1}) v` from the gradients `a` (by slot).
pub(super) fn constraint_velocities(data: &[RowData], a: &[f64], v: &[f64], r_nu: &mut [f64]) {
    r_nu.fill(0.0);
    let mut offset = 0;
    for f in data {
        for (e, st) in f.stencils.chunks_exact(f.width.max(1)).enumerate() {
            let row = f.rows[e];
            for (b, &g) in st.iter().enumerate() {
                r_nu[row] += a[offset + e * f.width + b] * v[g];
            }
        }
        offset += f.count * f.width;
    }
}
