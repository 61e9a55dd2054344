//! The element view of a system on vector spaces given as text: its whole discrete Lagrangian
//! as one family of a single element (a term outside loops) whose stencil reads every
//! coordinate, so that the run-time-sized element integrators (`dirac::runtime::element`) run a
//! system of any number of coordinates from one build, without an instance per dimension.
//!
//! - The coordinates are the system's, in its order: the shape coordinates `x`, then the group
//!   coordinates `g` (each a scalar coordinate of the view).
//! - The element is `L_d` itself (formed by the rule from a continuous `L`), differentiated as
//!   the fixed-size system is: `D_1 L_d`, `D_2 L_d`, `D_1 D_2 L_d`, the step partials, and for a
//!   continuous Lagrangian the energy and the Legendre map with its Jacobian. Declared forces
//!   are a second family of one element (the discrete forces `f_d^∓` in the places of
//!   `D_1 L_d`, `D_2 L_d`), so that the momentum maps change by their impulse.
//! - Each group coordinate `g_j` is a translation of its own: `L_d` depends on it only through
//!   `g_{k+1} − g_k` (checked, as for the reduction), and its momentum map is `μ_j = p_{g_j}`.
//!   The element integrators keep `μ_{k+1} = μ_k` (plus the forces' impulse) exactly, as the
//!   reduced integrators do.
//! - Each holonomic constraint row `φ_i(q) = 0` is a constraint family of one element reading
//!   the coordinates `φ_i` reads.
//!
//! Why the same trajectory: the element integrator's (+) step solves the position–momentum form
//! of the discrete Lagrange–Dirac (+) equations (Definition 2.7) in `(x, g)`. In the adapted
//! coordinates of §2.2.1 these are the reduced (+) equations (4.6) — the same unknowns
//! `q_{k+1}`, the same solution, with `w = p_x + Bᵀ μ` (eq. (3.7)) and `μ_{k+1} = μ_k` — written
//! in another basis, so a reduced (+) run and the element (+) run of this view compute the same
//! trajectory up to round-off (Newton's iterates and the linear solver differ, not the
//! equations). Likewise the reduced (−) equations (4.8) and the element (−) side (Definition
//! 2.8), and the unreduced step (Definitions 2.7/2.8) and the element (+) side.
//!
//! Refused (a typed error): adaptive steps (`time(t), adapt = ..`: a time coordinate the
//! element integrators do not have), a domain (`domain(..)`, which they do not check) and
//! nonholonomic constraints (they integrate holonomic ones).

use proc_macro2::TokenStream;
use syn::ItemFn;

use super::element::{family_of, ConstraintFamily, ElementConstraints, IndexExpr, Stencil};
use super::{ElementCoordinate, ElementFamily, ElementSystem};
use crate::back::program::program;
use crate::expand::{lower_checked, parse, Parsed};
use crate::ir::compile::mode_for;
use crate::ir::diff::derivatives;
use crate::ir::element::step_blocks_of;
use crate::ir::graph::{Graph, NodeId, Sym};
use crate::ir::reduce::firsts;

/// The coordinates `node` reads (`Q0(i)` or `Q1(i)`: coordinate `i`), sorted.
fn reads(g: &Graph, node: NodeId) -> Vec<usize> {
    let mut coords: Vec<usize> = g
        .symbols(&[node])
        .into_iter()
        .filter_map(|s| match s {
            Sym::Q0(i) | Sym::Q1(i) => Some(i),
            _ => None,
        })
        .collect();
    coords.sort_unstable();
    coords.dedup();
    coords
}

/// `node` over the slots of `coords`: coordinate `coords[a]` read as slot `a`.
fn to_slots(g: &mut Graph, node: NodeId, coords: &[usize]) -> NodeId {
    g.substitute(node, &mut |g, sym| {
        let slot = |i: usize| {
            coords
                .binary_search(&i)
                .expect("a row reads the coordinates it was given")
        };
        match sym {
            Sym::Q0(i) => g.var(Sym::Q0(slot(i))),
            Sym::Q1(i) => g.var(Sym::Q1(slot(i))),
            other => g.var(other),
        }
    })
}

/// `D_1 D_2` of `d1` (row `a`: `∂d1_a/∂q1_b`), one forward pass per column.
fn mixed(g: &mut Graph, d1: &[NodeId], n: usize) -> Vec<Vec<NodeId>> {
    let columns: Vec<Vec<NodeId>> = (0..n).map(|b| derivatives(g, d1, Sym::Q1(b))).collect();
    (0..d1.len())
        .map(|a| columns.iter().map(|c| c[a]).collect())
        .collect()
}

/// The phases of `#[reduced_lagrangian]` on a system on vector spaces up to its lowered and
/// checked `L_d`, then the element view's programs (see the [module documentation](self)).
pub(super) fn compile_parts(args: TokenStream, func: &ItemFn) -> syn::Result<ElementSystem> {
    if crate::front::element::is_element_wise(func) {
        return Err(syn::Error::new_spanned(
            &func.sig.inputs,
            "an element-wise system (sizes as `usize` arguments) compiles with `compile_element`: \
             it is element-wise already",
        ));
    }
    if crate::front::lie::is_lie(&args) {
        return Err(syn::Error::new_spanned(
            &args,
            "a system on rotation groups (`rotation(..)`, `direction(..)`) has no element view: \
             it compiles with `compile_lie`",
        ));
    }
    let Parsed { spec, sig, parsed } = parse(args, func);
    parsed?;
    let (spec, sig) = spec.zip(sig).expect("a clean parse has both");
    let refuse = |what: &str| {
        Err(syn::Error::new_spanned(
            &func.sig.ident,
            format!(
                "{what}: the element integrators, which run a system on vector spaces of any \
                 size, do not support it (run the system at a size the fixed-size integrators \
                 serve)"
            ),
        ))
    };
    if spec.adapt.is_some() {
        return refuse("adaptive steps (`time(..), adapt = ..`)");
    }
    if !spec.domain.is_empty() {
        return refuse("a declared domain (`domain(..)`)");
    }
    if spec.nonholonomic {
        return refuse("nonholonomic constraints (`nonholonomic = ..`)");
    }
    let lowered = lower_checked(&spec, &sig, func)?;
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let n = s + k;
    let mut g = lowered.graph;
    let mode = mode_for(n);
    let q0: Vec<Sym> = (0..n).map(Sym::Q0).collect();
    let q1: Vec<Sym> = (0..n).map(Sym::Q1).collect();
    let controls: Vec<usize> = spec
        .controls
        .iter()
        .filter_map(|u| sig.params.iter().position(|p| p == u))
        .collect();
    let stencil = Stencil {
        loops: Vec::new(),
        slots: (0..n).map(|c| (c, Vec::new())).collect(),
    };
    // The Lagrangian's element: L_d and its derivatives over every coordinate.
    let ld = lowered.body;
    let d1 = firsts(&mut g, mode, ld, &q0);
    let d12 = mixed(&mut g, &d1, n);
    let d2 = firsts(&mut g, mode, ld, &q1);
    let blocks = step_blocks_of(&mut g, n, &controls, &d1, &d2);
    let continuous = lowered.continuous.as_ref();
    let mut families: Vec<ElementFamily> = vec![family_of(
        &g,
        stencil.clone(),
        false,
        ld,
        [&d1, &d2],
        &d12,
        &blocks,
        continuous.map(|c| c.energy),
        continuous.map(|c| (&c.legendre[..], &c.hessian[..])),
    )];
    // The forces' element: f_d^− and f_d^+ in the places of D_1 L_d and D_2 L_d.
    if let Some(forces) = &lowered.forces {
        let d12 = mixed(&mut g, &forces.minus, n);
        let blocks = step_blocks_of(&mut g, n, &controls, &forces.minus, &forces.plus);
        let zero = g.constant(0.0);
        let (zeros, zero_rows) = (vec![zero; n], vec![vec![zero; n]; n]);
        families.push(family_of(
            &g,
            stencil.clone(),
            true,
            zero,
            [&forces.minus, &forces.plus],
            &d12,
            &blocks,
            continuous.map(|_| zero),
            continuous.map(|_| (&zeros[..], &zero_rows[..])),
        ));
    }
    // One constraint family per row φ_i, reading the coordinates φ_i reads (all of them for a
    // row that reads none: a constant row, which the start's check refuses unless zero).
    let constraints = lowered.constraints.as_ref().map(|c| {
        let rows: Vec<ConstraintFamily> = c
            .phi
            .iter()
            .enumerate()
            .map(|(i, &phi)| {
                let mut coords = reads(&g, phi);
                if coords.is_empty() {
                    coords = (0..n).collect();
                }
                let w = coords.len();
                let phi = to_slots(&mut g, phi, &coords);
                let slots: Vec<Sym> = (0..w).map(Sym::Q0).collect();
                let gradient = firsts(&mut g, mode_for(w), phi, &slots);
                let outputs: Vec<NodeId> = std::iter::once(phi).chain(gradient).collect();
                ConstraintFamily {
                    stencil: Stencil {
                        loops: Vec::new(),
                        slots: coords.iter().map(|&c| (c, Vec::new())).collect(),
                    },
                    row: IndexExpr::Lit(i as i64),
                    value_gradient: program(&g, &outputs),
                }
            })
            .collect();
        ElementConstraints {
            count: IndexExpr::Lit(rows.len() as i64),
            families: rows,
        }
    });
    let names = spec.layout.shape.iter().chain(&spec.layout.group);
    Ok(ElementSystem {
        name: crate::back::items::type_name(&spec, func).to_string(),
        parameters: sig.parameter_names(),
        step: sig.step_index(),
        sizes: Vec::new(),
        controls,
        continuous: continuous.is_some(),
        min_size: 0,
        coordinates: names
            .map(|name| ElementCoordinate {
                name: name.clone(),
                dims: Vec::new(),
            })
            .collect(),
        translations: (s..n).map(|j| vec![j]).collect(),
        families,
        constraints,
    })
}
