//! The constraint rows of a run-time-sized system as a run sees them, and the passes over them
//! and over the elements that a constrained step's saddle-point systems are assembled from
//! (see the [parent module](super::constrained)).

use super::assembly::FamilyData;
use super::pass::{gather, split_scratch, with_scratch};
use super::{
    scratch_len, ConstraintFamily, ConstraintVisitor, ElementLagrangian, Family, FamilyVisitor,
};

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
    fn constraint<F: ConstraintFamily>(&mut self, family: &F) {
        let (n, m, index) = (self.n, self.m, self.families.len());
        let width = family.width();
        let mut data = RowData {
            width,
            depth: family.depth(),
            count: 0,
            indices: Vec::new(),
            rows: Vec::new(),
            stencils: Vec::new(),
            a_pos: Vec::new(),
            at_pos: Vec::new(),
        };
        let invalid = &mut self.invalid;
        let depth = data.depth;
        family.elements(&mut |indices, row, stencil| {
            data.count += 1;
            data.indices
                .extend((0..depth).map(|d| indices.get(d).copied().unwrap_or(0)));
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
            if stencil.len() != width || indices.len() != depth {
                invalid.get_or_insert_with(|| {
                    format!(
                        "constraint element {indices:?} of family {index} reads {} coordinates \
                         in {} loops; its family reads {width} in {depth}",
                        stencil.len(),
                        indices.len()
                    )
                });
            }
            for slot in 0..width {
                let g = stencil.get(slot).copied().unwrap_or(-1);
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
    fn constraint<F: ConstraintFamily>(&mut self, family: &F) {
        let data = &self.data[self.next];
        self.next += 1;
        let w = data.width;
        with_scratch(0, 2 * w + 1, |_, scratch| {
            let (a0, out) = scratch.split_at_mut(w);
            for e in 0..data.count {
                let st = &data.stencils[e * w..(e + 1) * w];
                gather(self.q, st, a0);
                family.value_gradient(&data.indices[e * data.depth..(e + 1) * data.depth], a0, out);
                if let Some(phi) = self.phi.as_deref_mut() {
                    phi[data.rows[e]] = out[0];
                }
                if let Some(grad) = self.grad.as_deref_mut() {
                    grad[self.offset + e * w..self.offset + (e + 1) * w].copy_from_slice(&out[1..]);
                }
            }
        });
        self.offset += data.count * w;
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
    fn family<F: Family>(&mut self, family: &F) {
        let data = &self.families[self.next];
        self.next += 1;
        let w = data.width;
        if family.force() || w == 0 {
            return;
        }
        with_scratch(0, scratch_len(w), |_, scratch| {
            let (a0, a1, out) = split_scratch(scratch, w);
            let out = &mut out[..w + w * w];
            for e in 0..data.count {
                let st = &data.stencils[e * w..(e + 1) * w];
                gather(self.q, st, a0);
                gather(self.v, st, a1);
                family.legendre(
                    &data.indices[e * data.depth..(e + 1) * data.depth],
                    a0,
                    a1,
                    out,
                );
                let (g, hessian) = out.split_at(w);
                for a in 0..w {
                    self.r[st[a]] += g[a];
                }
                if let Some((kkt, j_to_kkt)) = self.kkt.as_mut() {
                    let pos = &data.positions[e * w * w..(e + 1) * w * w];
                    for (&position, &value) in pos.iter().zip(hessian) {
                        kkt[j_to_kkt[position]] += value;
                    }
                }
            }
        });
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
