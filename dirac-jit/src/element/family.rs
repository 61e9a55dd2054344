//! The runtime's traits for a [`JitElement`]: each family at its stencil width (`Family`,
//! `ConstraintFamily`), the width dispatched from run time to one instance per width up to
//! [`MAX_WIDTH`](super::MAX_WIDTH), and `ElementLagrangian`.

use std::ops::Range;

use dirac_runtime::element::{
    ConstraintFamily, ConstraintVisitor, ElementLagrangian, Family, FamilyVisitor,
};

use super::{FamilyKernels, JitElement, Table};
use crate::codegen::Kernel;
use crate::system::UNUSED;

/// One family of a [`JitElement`] at stencil width `S`.
struct JitFamily<'a, const S: usize> {
    system: &'a JitElement,
    table: &'a Table,
    kernels: FamilyKernels,
    force: bool,
}

/// Two `S`-vectors, as a kernel writes them.
#[repr(C)]
struct Two<const S: usize> {
    a: [f64; S],
    b: [f64; S],
}

/// Two `S`-vectors and an `S × S` matrix (row by row), as a kernel writes them.
#[repr(C)]
struct Three<const S: usize> {
    a: [f64; S],
    b: [f64; S],
    m: [[f64; S]; S],
}

/// An `S`-vector and an `S × S` matrix (row by row).
#[repr(C)]
struct VectorMatrix<const S: usize> {
    v: [f64; S],
    m: [[f64; S]; S],
}

/// A number and an `S`-vector.
#[repr(C)]
struct ValueGradient<const S: usize> {
    value: f64,
    gradient: [f64; S],
}

impl<const S: usize> Family<S> for JitFamily<'_, S> {
    /// A placeholder: the depth is the family's own ([`Family::depth`]).
    const DEPTH: usize = 0;

    fn depth(&self) -> usize {
        self.table.depth
    }

    fn force(&self) -> bool {
        self.force
    }

    fn elements(&self, visit: &mut dyn FnMut(&[i64], [i64; S])) {
        let t = self.table;
        for e in 0..t.len() {
            let mut stencil = [0i64; S];
            stencil.copy_from_slice(&t.stencils[e * S..(e + 1) * S]);
            visit(&t.indices[e * t.depth..(e + 1) * t.depth], stencil);
        }
    }

    fn d1_d2(&self, indices: &[i64], q0: &[f64; S], q1: &[f64; S]) -> ([f64; S], [f64; S]) {
        let mut out = Two {
            a: [0.0; S],
            b: [0.0; S],
        };
        self.system.call(
            self.kernels.d1_d2,
            q0.as_ptr(),
            q1.as_ptr(),
            indices,
            (&mut out as *mut Two<S>).cast(),
        );
        (out.a, out.b)
    }

    fn d1_d2_d12(
        &self,
        indices: &[i64],
        q0: &[f64; S],
        q1: &[f64; S],
    ) -> ([f64; S], [f64; S], [[f64; S]; S]) {
        let mut out = Three {
            a: [0.0; S],
            b: [0.0; S],
            m: [[0.0; S]; S],
        };
        self.system.call(
            self.kernels.d1_d2_d12,
            q0.as_ptr(),
            q1.as_ptr(),
            indices,
            (&mut out as *mut Three<S>).cast(),
        );
        (out.a, out.b, out.m)
    }

    fn step_partials(
        &self,
        indices: &[i64],
        q0: &[f64; S],
        q1: &[f64; S],
        blocks: &mut [[[f64; S]; S]; 3],
        u1: &mut [f64],
        u2: &mut [f64],
    ) -> bool {
        let m = self.system.code.system.controls.len();
        if u1.len() != S * m || u2.len() != S * m {
            return false;
        }
        let mut out = vec![0.0; 3 * S * S + 2 * S * m];
        self.system.call(
            self.kernels.partials,
            q0.as_ptr(),
            q1.as_ptr(),
            indices,
            out.as_mut_ptr(),
        );
        let (square, controls) = out.split_at(3 * S * S);
        for (k, block) in blocks.iter_mut().enumerate() {
            for (a, row) in block.iter_mut().enumerate() {
                row.copy_from_slice(&square[k * S * S + a * S..k * S * S + (a + 1) * S]);
            }
        }
        u1.copy_from_slice(&controls[..S * m]);
        u2.copy_from_slice(&controls[S * m..]);
        true
    }

    fn value(&self, indices: &[i64], q0: &[f64; S], q1: &[f64; S]) -> f64 {
        let mut out = 0.0;
        self.system.call(
            self.kernels.value,
            q0.as_ptr(),
            q1.as_ptr(),
            indices,
            &mut out,
        );
        out
    }

    fn energy(&self, indices: &[i64], q: &[f64; S], v: &[f64; S]) -> f64 {
        let Some(kernel) = self.kernels.energy else {
            return f64::NAN;
        };
        let mut out = 0.0;
        self.system
            .call(kernel, q.as_ptr(), v.as_ptr(), indices, &mut out);
        out
    }

    fn legendre(&self, indices: &[i64], q: &[f64; S], v: &[f64; S]) -> ([f64; S], [[f64; S]; S]) {
        let Some(kernel) = self.kernels.legendre else {
            return ([f64::NAN; S], [[f64::NAN; S]; S]);
        };
        let mut out = VectorMatrix {
            v: [0.0; S],
            m: [[0.0; S]; S],
        };
        self.system.call(
            kernel,
            q.as_ptr(),
            v.as_ptr(),
            indices,
            (&mut out as *mut VectorMatrix<S>).cast(),
        );
        (out.v, out.m)
    }
}

/// One family of constraint rows of a [`JitElement`] at stencil width `S`.
struct JitConstraints<'a, const S: usize> {
    system: &'a JitElement,
    table: &'a Table,
    kernel: Kernel,
}

impl<const S: usize> ConstraintFamily<S> for JitConstraints<'_, S> {
    /// A placeholder: the depth is the family's own ([`ConstraintFamily::depth`]).
    const DEPTH: usize = 0;

    fn depth(&self) -> usize {
        self.table.depth
    }

    fn elements(&self, visit: &mut dyn FnMut(&[i64], i64, [i64; S])) {
        let t = self.table;
        for e in 0..t.len() {
            let mut stencil = [0i64; S];
            stencil.copy_from_slice(&t.stencils[e * S..(e + 1) * S]);
            visit(
                &t.indices[e * t.depth..(e + 1) * t.depth],
                t.rows[e],
                stencil,
            );
        }
    }

    fn value_gradient(&self, indices: &[i64], q: &[f64; S]) -> (f64, [f64; S]) {
        let mut out = ValueGradient {
            value: 0.0,
            gradient: [0.0; S],
        };
        self.system.call(
            self.kernel,
            q.as_ptr(),
            UNUSED,
            indices,
            (&mut out as *mut ValueGradient<S>).cast(),
        );
        (out.value, out.gradient)
    }
}

/// Calls `$visit::<S>` with the literal width `S` of `$width` (1 to [`MAX_WIDTH`]; 0 for a
/// term that reads no coordinate).
macro_rules! by_width {
    ($width:expr, $visit:ident) => {
        match $width {
            0 => $visit!(0),
            1 => $visit!(1),
            2 => $visit!(2),
            3 => $visit!(3),
            4 => $visit!(4),
            5 => $visit!(5),
            6 => $visit!(6),
            7 => $visit!(7),
            8 => $visit!(8),
            9 => $visit!(9),
            10 => $visit!(10),
            11 => $visit!(11),
            12 => $visit!(12),
            _ => unreachable!("widths above MAX_WIDTH are refused on compilation"),
        }
    };
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
            macro_rules! visit {
                ($s:literal) => {
                    visitor.constraint::<$s, _>(&JitConstraints::<$s> {
                        system: self,
                        table,
                        kernel,
                    })
                };
            }
            by_width!(table.width, visit);
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
            macro_rules! visit {
                ($s:literal) => {
                    visitor.family::<$s, _>(&JitFamily::<$s> {
                        system: self,
                        table,
                        kernels,
                        force: text.force,
                    })
                };
            }
            by_width!(table.width, visit);
        }
    }
}
