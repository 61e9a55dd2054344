//! The backend choice and the straight-line code of a stepper: the residual, the residual with
//! its Jacobian (dense fixed-size or sparse with a compile-time pattern, by size), the momentum
//! update.

use proc_macro2::TokenStream;
use quote::quote;

use crate::back::emit::straight_line;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::reduce::Stepper;

pub use crate::ir::compile::DENSE_MAX;

/// The linear algebra of a step, chosen by size (see [`DENSE_MAX`]): it fixes the types of the
/// Jacobian and of the solver in the impls' signatures, so the table of
/// [`crate::back::impls`] needs it for stubs too.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// `Lu<N>` on an `SMatrix<f64, N, N>`.
    Dense,
    /// `SparseLu<N, NNZ>` on the `NNZ` structural nonzeros, `CscValues<NNZ>`.
    Sparse {
        /// The number of structural nonzeros of the Jacobian.
        nnz: usize,
    },
}

impl Backend {
    /// The backend of an `n × n` Jacobian whose pattern is not known (a stub after an error):
    /// sparse above [`DENSE_MAX`] with `n` nonzeros (the fewest of a nonsingular matrix; a stub
    /// is never called, only its types must agree with the real impl's up to the count).
    pub fn for_size(n: usize) -> Backend {
        if n <= DENSE_MAX {
            Backend::Dense
        } else {
            Backend::Sparse { nnz: n }
        }
    }

    /// Whether this is the dense backend.
    pub fn is_dense(self) -> bool {
        self == Backend::Dense
    }

    /// The type of an `n × n` Jacobian.
    pub fn matrix_type(self, n: usize) -> TokenStream {
        match self {
            Backend::Dense => quote!(::dirac::nalgebra::SMatrix<f64, #n, #n>),
            Backend::Sparse { nnz } => quote!(::dirac::runtime::CscValues<#nnz>),
        }
    }

    /// The type of the solver of an `n × n` Jacobian.
    pub fn solver_type(self, n: usize) -> TokenStream {
        match self {
            Backend::Dense => quote!(::dirac::runtime::Lu<#n>),
            Backend::Sparse { nnz } => quote!(::dirac::runtime::SparseLu<#n, #nnz>),
        }
    }
}

/// The three functions of a stepper — residual, residual with Jacobian, momentum update — as
/// straight-line code. `inputs` are the leading arguments after `&self`; `leaf` reads a symbol.
pub struct SteppedFns {
    /// `R(z)`.
    pub residual: TokenStream,
    /// `(R(z), ∂R/∂z)`.
    pub residual_jacobian: TokenStream,
    /// The momentum update.
    pub momentum: TokenStream,
    /// The residual and the momentum update together (they share most subexpressions).
    pub residual_momentum: TokenStream,
    /// The backend of the Jacobian `residual_jacobian` returns.
    pub backend: Backend,
    /// The body of the function that builds the solver's workspace.
    pub solver_new: TokenStream,
    /// The operation counts, for the emitted `GENERATED` note.
    pub counts: String,
}

/// The straight-line functions of `stepper`: `n` unknowns, `m` momenta.
pub fn stepper_fns(
    g: &Graph,
    stepper: &Stepper,
    leaf: &dyn Fn(Sym) -> TokenStream,
    n: usize,
    m: usize,
) -> SteppedFns {
    let na = quote!(::dirac::nalgebra);
    let r = straight_line(g, &stepper.residual, leaf);
    let (r_stmts, r_out) = (&r.stmts, &r.outputs);
    let ResidualJacobian {
        code: rj_code,
        operations: rj_operations,
        nonzeros,
        backend,
        solver_new,
    } = residual_jacobian(g, &stepper.residual, &stepper.jacobian, leaf, n);
    let mo = straight_line(g, &stepper.momentum, leaf);
    let (m_stmts, m_out) = (&mo.stmts, &mo.outputs);
    let fused_roots: Vec<NodeId> = stepper
        .residual
        .iter()
        .chain(&stepper.momentum)
        .copied()
        .collect();
    let rm = straight_line(g, &fused_roots, leaf);
    let (rm_stmts, rm_r, rm_m) = (&rm.stmts, &rm.outputs[..n], &rm.outputs[n..]);
    SteppedFns {
        residual_momentum: quote! {
            #rm_stmts
            (
                #na::SVector::<f64, #n>::from([ #( #rm_r ),* ]),
                #na::SVector::<f64, #m>::from([ #( #rm_m ),* ]),
            )
        },
        residual: quote! {
            #r_stmts
            #na::SVector::<f64, #n>::from([ #( #r_out ),* ])
        },
        residual_jacobian: rj_code,
        backend,
        solver_new,
        momentum: quote! {
            #m_stmts
            #na::SVector::<f64, #m>::from([ #( #m_out ),* ])
        },
        counts: format!(
            "{} operations for the residual, {} for the residual with its Jacobian ({} nonzero entries), {} for the momentum update",
            r.operations,
            rj_operations,
            nonzeros,
            mo.operations
        ),
    }
}

/// The structurally nonzero entries of a square Jacobian (those the graph does not fold to the
/// constant 0) in compressed sparse columns: column `j` holds rows
/// `row_idx[col_ptr[j]..col_ptr[j + 1]]`, increasing, with the nodes `values` in the same order.
/// The sparse backend's pattern and values, for the attribute and for the run-time front end.
pub struct Csc {
    /// Column starts, `n + 1` of them.
    pub col_ptr: Vec<usize>,
    /// The row of each entry.
    pub row_idx: Vec<usize>,
    /// The node of each entry.
    pub values: Vec<NodeId>,
}

impl Csc {
    /// The pattern and values of `jacobian` (row by row: `jacobian[row][col]`).
    pub fn of(g: &Graph, jacobian: &[Vec<NodeId>]) -> Csc {
        let n = jacobian.len();
        let mut col_ptr = vec![0usize; n + 1];
        let (mut row_idx, mut values) = (Vec::new(), Vec::new());
        for col in 0..n {
            for (row, cols) in jacobian.iter().enumerate() {
                let node = cols[col];
                if g.as_const(node) != Some(0.0) {
                    row_idx.push(row);
                    values.push(node);
                }
            }
            col_ptr[col + 1] = row_idx.len();
        }
        Csc {
            col_ptr,
            row_idx,
            values,
        }
    }
}

/// The straight-line code of a residual `R` (`n` entries) and its Jacobian in the backend the
/// size calls for (see [`DENSE_MAX`]), with the backend's types.
pub struct ResidualJacobian {
    /// Statements and the tuple `(R, J)`.
    pub code: TokenStream,
    pub operations: usize,
    pub nonzeros: usize,
    /// The backend of `J` (its type and its solver's).
    pub backend: Backend,
    /// The body that builds the solver's workspace.
    pub solver_new: TokenStream,
}

/// `R` and `∂R/∂z` together: one straight line, so shared subexpressions are computed once, and
/// structurally zero entries of the Jacobian are never computed or stored. Dense systems get a
/// fixed-size matrix; above [`DENSE_MAX`] the structural nonzeros become a static CSC pattern
/// and the Jacobian is the array of their values.
pub fn residual_jacobian(
    g: &Graph,
    residual: &[NodeId],
    jacobian: &[Vec<NodeId>],
    leaf: &dyn Fn(Sym) -> TokenStream,
    n: usize,
) -> ResidualJacobian {
    let na = quote!(::dirac::nalgebra);
    let mut roots = residual.to_vec();
    // The sparse backend stores the entries column by column (compressed sparse columns).
    let sparse = n > DENSE_MAX;
    let mut entries: Vec<(usize, usize)> = Vec::new();
    let mut csc_pattern = None;
    if sparse {
        let csc = Csc::of(g, jacobian);
        roots.extend(&csc.values);
        csc_pattern = Some((csc.col_ptr, csc.row_idx));
    } else {
        for (row, cols) in jacobian.iter().enumerate() {
            for (col, &node) in cols.iter().enumerate() {
                if g.as_const(node) != Some(0.0) {
                    entries.push((row, col));
                    roots.push(node);
                }
            }
        }
    }
    let rj = straight_line(g, &roots, leaf);
    let rj_stmts = &rj.stmts;
    let rj_r = &rj.outputs[..n];
    let rt = quote!(::dirac::runtime);
    let nnz = roots.len() - n;
    let (jacobian_value, backend, solver_new) = if let Some((col_ptr, row_idx)) = csc_pattern {
        let values = &rj.outputs[n..];
        (
            quote! { #rt::CscValues([ #( #values ),* ]) },
            Backend::Sparse { nnz },
            quote! {
                static PATTERN: #rt::CscPattern = #rt::CscPattern {
                    n: #n,
                    col_ptr: &[ #( #col_ptr ),* ],
                    row_idx: &[ #( #row_idx ),* ],
                };
                #rt::SparseLu::new(&PATTERN)
            },
        )
    } else {
        let assigns = entries
            .iter()
            .zip(&rj.outputs[n..])
            .map(|((row, col), e)| quote! { __jac[(#row, #col)] = #e; });
        let jac_mut = if entries.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        (
            quote! {{
                let #jac_mut __jac = #na::SMatrix::<f64, #n, #n>::zeros();
                #( #assigns )*
                __jac
            }},
            Backend::Dense,
            quote!(#rt::Lu::empty()),
        )
    };
    ResidualJacobian {
        code: quote! {
            #rj_stmts
            (#na::SVector::<f64, #n>::from([ #( #rj_r ),* ]), #jacobian_value)
        },
        operations: rj.operations,
        nonzeros: nnz,
        backend,
        solver_new,
    }
}
