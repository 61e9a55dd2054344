//! The runtime's traits for a [`JitElement`]: each family (`Family`, `ConstraintFamily`) at
//! its stencil width, which is data — the kernels read `width` stencil values and write their
//! outputs straight into the runtime's scratch, one instance of the assembly for every width —
//! and `ElementLagrangian`.

use std::ops::Range;

use dirac_runtime::element::{
    ConstraintFamily, ConstraintVisitor, ElementLagrangian, Family, FamilyVisitor,
};

use super::{FamilyKernels, JitElement, Table};
use crate::codegen::Kernel;
use crate::system::UNUSED;

/// One family of a [`JitElement`].
struct JitFamily<'a> {
    system: &'a JitElement,
    table: &'a Table,
    kernels: FamilyKernels,
    force: bool,
}

impl JitFamily<'_> {
    /// Calls `kernel` on the stencil values `a`, `b` of element `indices`, writing `len`
    /// outputs into `out`; NaN in every output when the slices are shorter than the kernel
    /// reads or writes (never, from the runtime's passes: the guard keeps the call sound).
    fn call(
        &self,
        kernel: Kernel,
        indices: &[i64],
        a: &[f64],
        b: &[f64],
        out: &mut [f64],
        len: usize,
    ) {
        let w = self.table.width;
        if a.len() < w || b.len() < w || out.len() < len || indices.len() < self.table.depth {
            out.fill(f64::NAN);
            return;
        }
        self.system
            .call(kernel, a.as_ptr(), b.as_ptr(), indices, out.as_mut_ptr());
    }
}

impl Family for JitFamily<'_> {
    fn width(&self) -> usize {
        self.table.width
    }

    fn depth(&self) -> usize {
        self.table.depth
    }

    fn force(&self) -> bool {
        self.force
    }

    fn elements(&self, visit: &mut dyn FnMut(&[i64], &[i64])) {
        let t = self.table;
        for e in 0..t.len() {
            visit(
                &t.indices[e * t.depth..(e + 1) * t.depth],
                &t.stencils[e * t.width..(e + 1) * t.width],
            );
        }
    }

    fn d1_d2(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) {
        let w = self.table.width;
        self.call(self.kernels.d1_d2, indices, q0, q1, out, 2 * w);
    }

    fn d1_d2_d12(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) {
        let w = self.table.width;
        self.call(self.kernels.d1_d2_d12, indices, q0, q1, out, 2 * w + w * w);
    }

    fn step_partials(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) -> bool {
        let (w, m) = (self.table.width, self.system.code.system.controls.len());
        let len = 3 * w * w + 2 * w * m;
        if out.len() != len {
            return false;
        }
        self.call(self.kernels.partials, indices, q0, q1, out, len);
        true
    }

    fn value(&self, indices: &[i64], q0: &[f64], q1: &[f64]) -> f64 {
        let mut out = [0.0];
        self.call(self.kernels.value, indices, q0, q1, &mut out, 1);
        out[0]
    }

    fn energy(&self, indices: &[i64], q: &[f64], v: &[f64]) -> f64 {
        let Some(kernel) = self.kernels.energy else {
            return f64::NAN;
        };
        let mut out = [0.0];
        self.call(kernel, indices, q, v, &mut out, 1);
        out[0]
    }

    fn legendre(&self, indices: &[i64], q: &[f64], v: &[f64], out: &mut [f64]) {
        let Some(kernel) = self.kernels.legendre else {
            out.fill(f64::NAN);
            return;
        };
        let w = self.table.width;
        self.call(kernel, indices, q, v, out, w + w * w);
    }
}

/// One family of constraint rows of a [`JitElement`].
struct JitConstraints<'a> {
    system: &'a JitElement,
    table: &'a Table,
    kernel: Kernel,
}

impl ConstraintFamily for JitConstraints<'_> {
    fn width(&self) -> usize {
        self.table.width
    }

    fn depth(&self) -> usize {
        self.table.depth
    }

    fn elements(&self, visit: &mut dyn FnMut(&[i64], i64, &[i64])) {
        let t = self.table;
        for e in 0..t.len() {
            visit(
                &t.indices[e * t.depth..(e + 1) * t.depth],
                t.rows[e],
                &t.stencils[e * t.width..(e + 1) * t.width],
            );
        }
    }

    fn value_gradient(&self, indices: &[i64], q: &[f64], out: &mut [f64]) {
        let w = self.table.width;
        if q.len() < w || out.len() < 1 + w || indices.len() < self.table.depth {
            out.fill(f64::NAN);
            return;
        }
        self.system
            .call(self.kernel, q.as_ptr(), UNUSED, indices, out.as_mut_ptr());
    }
}

crate::model::impl_system! {
    impl[] for JitElement; |sys| {
        coordinates: sys.code.system.coordinates.iter().map(|c| c.name.as_str()).collect(),
    }
}

impl ElementLagrangian for JitElement {
    /// Empty: a system given at run time names its sizes through `size_names`.
    const SIZES: &'static [&'static str] = &[];
    /// A placeholder, read through `min_size`.
    const MIN_SIZE: usize = 0;
    /// A placeholder, read through `continuous`.
    const CONTINUOUS: bool = false;

    fn size_names(&self) -> Vec<&str> {
        self.code.system.sizes.iter().map(String::as_str).collect()
    }

    fn min_size(&self) -> usize {
        self.code.system.min_size
    }

    fn continuous(&self) -> bool {
        self.code.system.continuous
    }

    fn forced(&self) -> bool {
        self.code.system.families.iter().any(|f| f.force)
    }

    fn constrained(&self) -> bool {
        self.code.system.constraints.is_some()
    }

    fn constraint_count(&self) -> usize {
        self.at.rows
    }

    fn constraint_families<V: ConstraintVisitor>(&self, visitor: &mut V) {
        for (table, &kernel) in self.at.constraints.iter().zip(&self.code.constraints) {
            visitor.constraint(&JitConstraints {
                system: self,
                table,
                kernel,
            });
        }
    }

    fn sizes(&self) -> Vec<usize> {
        self.at.sizes.clone()
    }

    fn dim(&self) -> usize {
        *self.at.offsets.last().expect("starts with 0") as usize
    }

    fn translations(&self) -> Vec<Vec<Range<usize>>> {
        let o = &self.at.offsets;
        self.code
            .system
            .translations
            .iter()
            .map(|members| {
                members
                    .iter()
                    .map(|&c| o[c] as usize..o[c + 1] as usize)
                    .collect()
            })
            .collect()
    }

    fn families<V: FamilyVisitor>(&self, visitor: &mut V) {
        for ((table, &kernels), text) in self
            .at
            .families
            .iter()
            .zip(&self.code.families)
            .zip(&self.code.system.families)
        {
            visitor.family(&JitFamily {
                system: self,
                table,
                kernels,
                force: text.force,
            });
        }
    }
}
