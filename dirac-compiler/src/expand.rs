//! Ties the stages together, one phase after another, each with its own error context
//! ([`Ctxt`]), finished before the next phase starts: the attribute and signature
//! ([`crate::front`]), the lowering, the invariance (or equivariance) check, the constructions
//! ([`crate::ir`]), and code generation ([`crate::back`]). A phase with errors ends the
//! compilation: its errors are emitted with the [`crate::fallback`] items, so the user's other
//! code still type-checks and shows no follow-on errors.

use proc_macro2::{Span, TokenStream};
use syn::ItemFn;

use crate::back::backend::Backend;
use crate::back::{system, transition as codegen_transition};
use crate::ctxt::Ctxt;
use crate::fallback;
use crate::front::signature::{parse_signature, Signature};
use crate::front::{parse_spec, transition as ast_transition, Spec};
use crate::ir::compile::Compiled;
use crate::ir::{check, compile, transition as ir_transition};

/// `#[reduced_lagrangian]`: every emitted item, or the errors and the fallback items.
pub fn expand(args: TokenStream, item: TokenStream) -> TokenStream {
    let func: ItemFn = match syn::parse2(item) {
        Ok(f) => f,
        Err(e) => {
            let mut e = e;
            e.combine(syn::Error::new(
                Span::call_site(),
                "`#[reduced_lagrangian]` applies to a function `fn name(q0: Config, q1: Config, h: f64, ...) -> f64`",
            ));
            return e.into_compile_error();
        }
    };
    if crate::front::lie::is_lie(&args) {
        return expand_lie(args, &func).unwrap_or_else(|e| e.into_compile_error());
    }
    if crate::front::element::is_element_wise(&func) {
        return expand_element(args, &func).unwrap_or_else(|e| e.into_compile_error());
    }
    // The attribute and the signature: kept for the fallback even when they have errors.
    let Parsed { spec, sig, parsed } = parse(args, &func);
    match parsed.and_then(|()| {
        let (spec, sig) = (spec.as_ref(), sig.as_ref());
        let (spec, sig) = spec.zip(sig).expect("a clean parse has both");
        let compiled = compile_system(spec, sig, &func)?;
        Ok(system::generate(spec, sig, &func, &compiled))
    }) {
        Ok(out) => out,
        Err(errors) => {
            let mut out = errors.into_compile_error();
            out.extend(fallback::reduced_lagrangian(
                spec.as_ref(),
                sig.as_ref(),
                &func,
            ));
            out
        }
    }
}

/// An element-wise system (the function takes `usize` sizes): the attribute and signature, the
/// body split into families of elements with the stencils' range check, each family's element
/// lowered and differentiated, and the emitted kernels and assembly types
/// ([`crate::front::element`], [`crate::ir::element`], [`crate::back::element`]).
fn expand_element(args: TokenStream, func: &ItemFn) -> syn::Result<TokenStream> {
    let c = compile_element(args, func)?;
    let constraints = c
        .constraints
        .as_ref()
        .map(|(split, codes)| (split, codes.as_slice()));
    Ok(crate::back::element::generate(
        &c.spec,
        func,
        &c.families,
        &c.codes,
        constraints,
        c.min_size,
    ))
}

/// An element-wise system up to the graphs both back ends read.
pub struct ElementCompiled {
    /// The attribute and signature.
    pub spec: crate::front::element::ElementSpec,
    /// Every family of elements, the Lagrangian's first, then the forces'.
    pub families: Vec<crate::front::element::families::FamilySpec>,
    /// Each family's element, differentiated.
    pub codes: Vec<crate::ir::element::ElementCode>,
    /// The constraint rows' families and their elements, when declared.
    pub constraints: Option<(
        crate::front::element::constraints::ConstraintSplit,
        Vec<crate::ir::element::ConstraintCode>,
    )>,
    /// The smallest size every stencil fits in.
    pub min_size: usize,
}

/// The phases of an element-wise system: the attribute and signature, the body split into
/// families of elements with the stencils' range check, and each family's element lowered and
/// differentiated.
pub fn compile_element(args: TokenStream, func: &ItemFn) -> syn::Result<ElementCompiled> {
    use crate::front::element::{families, parse as parse_element};
    let cx = Ctxt::new();
    let spec = parse_element(&cx, args, func);
    let spec = cx.finish(spec)?;
    let cx = Ctxt::new();
    let configs = [&spec.sig.q0, &spec.sig.q1];
    let split = families::split(&cx, &func.block, &spec.sizes, &spec.coords, &configs);
    let split = cx.finish(split)?;
    // The forces: their virtual work split into families the same way, reading the
    // displacements as a third configuration.
    let force_split = match &spec.force {
        None => Vec::new(),
        Some(closure) => {
            let cx = Ctxt::new();
            let expected = if spec.sig.continuous { 1 } else { 2 };
            let dq = crate::ir::force::closure_args(&cx, closure, expected);
            let dq = cx.finish(dq)?;
            let block: syn::Block = match &*closure.body {
                syn::Expr::Block(b) => b.block.clone(),
                other => syn::parse_quote!({ #other }),
            };
            let configs: Vec<&syn::Ident> = [&spec.sig.q0, &spec.sig.q1]
                .into_iter()
                .chain(&dq)
                .collect();
            let cx = Ctxt::new();
            let split = families::split(&cx, &block, &spec.sizes, &spec.coords, &configs);
            cx.finish(split)?
        }
    };
    // Every family, the Lagrangian's first.
    let lagrangian_families = split.len();
    let split: Vec<families::FamilySpec> = split.into_iter().chain(force_split).collect();
    let cx = Ctxt::new();
    let all: Vec<&families::FamilySpec> = split.iter().collect();
    let min_size = families::min_size(&cx, &all, &spec.coords, spec.sizes.len());
    let min_size = cx.finish(min_size)?;
    // The constraints: one family per row assignment.
    let constraint_split = match &spec.constraints {
        None => None,
        Some(closure) => {
            let cx = Ctxt::new();
            let c =
                crate::front::element::constraints::split(&cx, closure, &spec.sizes, &spec.coords);
            Some(cx.finish(c)?)
        }
    };
    let constraint_families: Vec<&families::FamilySpec> = constraint_split
        .iter()
        .flat_map(|c| c.families.iter().map(|f| &f.family))
        .collect();
    let min_size = if constraint_families.is_empty() {
        min_size
    } else {
        let cx = Ctxt::new();
        let m = families::min_size(&cx, &constraint_families, &spec.coords, spec.sizes.len());
        min_size.max(cx.finish(m)?)
    };
    let cx = Ctxt::new();
    let depth = split
        .iter()
        .chain(constraint_families.iter().copied())
        .map(|f| f.loops.len())
        .max()
        .unwrap_or(0);
    let codes: Option<Vec<_>> = split
        .iter()
        .enumerate()
        .map(|(i, f)| match &spec.force {
            Some(closure) if i >= lagrangian_families => {
                crate::ir::element::force_element(&cx, &spec, f, depth, closure)
            }
            _ => crate::ir::element::element(&cx, &spec, f, depth),
        })
        .collect();
    let constraint_codes: Option<Vec<_>> =
        constraint_split.as_ref().map_or(Some(Vec::new()), |c| {
            c.families
                .iter()
                .map(|f| {
                    crate::ir::element::constraint_element(&cx, &spec, &f.family, depth, &c.config)
                })
                .collect()
        });
    let (codes, constraint_codes) = cx.finish(codes.zip(constraint_codes))?;
    Ok(ElementCompiled {
        spec,
        families: split,
        codes,
        constraints: constraint_split.map(|c| (c, constraint_codes)),
        min_size,
    })
}

/// A system on rotation groups (`rotation(..)` or `direction(..)` coordinates): the attribute
/// and signature, the body lowered with matrix and vector values, the Lie group variational
/// step on the graph, and the emitted items ([`crate::front::lie`], [`crate::ir::lie`],
/// [`crate::back::lie`]).
fn expand_lie(args: TokenStream, func: &ItemFn) -> syn::Result<TokenStream> {
    let LieCompiled {
        spec,
        sig,
        graph,
        code,
    } = compile_lie(args, func)?;
    Ok(crate::back::lie::generate(&spec, &sig, func, &graph, &code))
}

/// A system on rotation groups up to the graph both back ends read.
pub struct LieCompiled {
    /// The attribute.
    pub spec: crate::ir::lie::LieSpec,
    /// The signature.
    pub sig: Signature,
    /// The graph of every function.
    pub graph: crate::ir::graph::Graph,
    /// The step's roots in the graph.
    pub code: crate::ir::lie::LieCode,
}

/// The phases of a system on rotation groups: the attribute and signature, the body lowered with
/// matrix and vector values, the symmetry checks, and the Lie group variational step (with its
/// reduced step, partial derivatives and adaptive steps where declared) on the graph.
pub fn compile_lie(args: TokenStream, func: &ItemFn) -> syn::Result<LieCompiled> {
    use crate::ir::graph::Graph;
    use crate::ir::lower::Lowering;
    let cx = Ctxt::new();
    let spec =
        crate::front::lie::parse(&cx, args).map(|attr| crate::ir::lie::LieSpec::resolve(&cx, attr));
    let attr = spec.as_ref().map(|s| &s.attr);
    let sig = parse_signature(
        &cx,
        &func.sig,
        attr.and_then(|s| s.step.as_ref()),
        attr.and_then(|s| s.rule.as_ref()),
        attr.is_some_and(|s| s.rule_written),
    );
    if let (Some(attr), Some(sig)) = (attr, &sig) {
        crate::front::signature::check_controls(&cx, &attr.controls, sig);
    }
    let (spec, sig) = cx.finish(spec.zip(sig))?;
    let cx = Ctxt::new();
    let names = crate::ir::lower::Names::of(&sig, spec.lowering_coords());
    let mut graph = Graph::default();
    let mut lowering = Lowering::new(&mut graph, &cx, &names);
    let body = lowering.body(&func.block);
    let skew = lowering.skew_checks().to_vec();
    if body.is_some() {
        crate::ir::lie::check_skew(&cx, &graph, &spec, &skew);
    }
    let body = cx.finish(body)?;
    // Adaptive steps: the time-transformed L₂ in place of L, before the rule.
    let adapt = match &spec.attr.adapt {
        None => None,
        Some(adapt) => {
            let cx = Ctxt::new();
            let adapted = lie_adapt(&cx, &mut graph, &spec, &sig, body, adapt);
            Some((cx.finish(adapted)?, body))
        }
    };
    let body = adapt.as_ref().map_or(body, |(a, _)| a.lagrangian);
    // A continuous L(q, v): L_d by its rule.
    let body = match spec.attr.rule.as_ref().filter(|_| sig.continuous) {
        Some(&(_, rule)) => {
            let h = graph.var(crate::ir::graph::Sym::Param(sig.step_index()));
            crate::ir::lie::discretize(&mut graph, &spec, body, rule, h)
        }
        None => body,
    };
    // The declared translations must be symmetries of L_d.
    let cx = Ctxt::new();
    crate::ir::lie::check_translations(&cx, &graph, &spec, body);
    cx.finish(Some(()))?;
    // The forces, in the displacement symbols of each coordinate.
    let forces = match &spec.attr.force {
        None => None,
        Some(closure) => {
            let names = crate::ir::lower::Names::of(&sig, spec.lowering_coords());
            let cx = Ctxt::new();
            let parts = crate::ir::force::lower_parts(
                &cx,
                &mut graph,
                closure,
                names,
                spec.velocity_len(),
                !sig.continuous,
            );
            let mut parts = cx.finish(parts)?;
            if let Some(a) = &spec.attr.adapt {
                let cx = Ctxt::new();
                let f = crate::ir::adapt::transform_force(
                    &cx,
                    &mut graph,
                    &parts[0],
                    time_at(&spec, a),
                    closure,
                );
                parts[0] = cx.finish(f)?;
            }
            Some(match spec.attr.rule.as_ref().filter(|_| sig.continuous) {
                Some(&(_, rule)) => {
                    let h = graph.var(crate::ir::graph::Sym::Param(sig.step_index()));
                    crate::ir::lie::discretize_force(&mut graph, &spec, &parts[0], rule, h)
                }
                None => (parts[0].clone(), parts[1].clone()),
            })
        }
    };
    // The declared rotations must be symmetries of L_d and of the forces.
    let cx = Ctxt::new();
    let monitor = adapt
        .as_ref()
        .zip(spec.attr.adapt.as_ref())
        .map(|((a, _), spec)| (a.monitor, &spec.monitor));
    crate::ir::lie::check_rotations(&cx, &graph, &spec, body, forces.as_ref(), monitor);
    cx.finish(Some(()))?;
    let mode = compile::mode_for(spec.n());
    let mut code = crate::ir::lie::compile(&mut graph, &spec, body, forces.as_ref(), mode, None);
    // Reduced by every rotation of one rotation coordinate: the step of the reduced Lagrangian.
    if let Some(symmetry) = &spec.symmetry {
        if symmetry.kind == crate::front::lie::SymmetryKind::Rotations {
            let at = spec.coords[symmetry.coords[0].0].point;
            let reduced =
                crate::ir::lie::compile(&mut graph, &spec, body, forces.as_ref(), mode, Some(at));
            code.reduced = Some(reduced.stepper);
        }
        code.symmetry_forced = forces.as_ref().is_some_and(|(minus, plus)| {
            symmetry.coords.iter().any(|&(i, _)| {
                let c = &spec.coords[i];
                (c.velocity..c.velocity + c.kind.velocity_len()).any(|v| {
                    [minus[v], plus[v]]
                        .iter()
                        .any(|&f| graph.as_const(f) != Some(0.0))
                })
            })
        });
    }
    // The step's partial derivatives for its sensitivities, on the dense backend.
    if Backend::for_size(spec.n()).is_dense() {
        let controls: Vec<usize> = spec
            .attr
            .controls
            .iter()
            .filter_map(|c| sig.params.iter().position(|p| p == c))
            .collect();
        code.partials = Some(crate::ir::lie::partials(
            &mut graph,
            &spec,
            body,
            forces.as_ref(),
            &controls,
            mode,
        ));
    }
    code.adapt = adapt
        .zip(spec.attr.adapt.as_ref())
        .map(|((a, l), at)| crate::ir::lie::adaptive(&mut graph, &spec, at.coord, a.monitor, l));
    Ok(LieCompiled {
        spec,
        sig,
        graph,
        code,
    })
}

/// Where the time coordinate of `adapt` is, in the configuration and the velocity.
fn time_at(
    spec: &crate::ir::lie::LieSpec,
    adapt: &crate::front::lie::LieAdapt,
) -> crate::ir::adapt::TimeAt {
    let c = &spec.coords[adapt.coord];
    crate::ir::adapt::TimeAt {
        point: c.point,
        velocity: c.velocity,
    }
}

/// Adaptive steps on rotation groups: the monitor lowered over the configuration, `L` (over
/// `q = Q0`, `v = Q1`) time-transformed ([`crate::ir::adapt`]), with the time coordinate's point
/// and velocity entries.
fn lie_adapt(
    cx: &Ctxt,
    graph: &mut crate::ir::graph::Graph,
    spec: &crate::ir::lie::LieSpec,
    sig: &Signature,
    l: crate::ir::graph::NodeId,
    adapt: &crate::front::lie::LieAdapt,
) -> Option<crate::ir::adapt::Adapted> {
    if !sig.continuous {
        cx.error_spanned_by(
            &adapt.monitor,
            "adaptive steps transform a continuous Lagrangian: write `fn l(q: Config, v: Velocity, ..)` with \
             `rule = trapezoid | left | right`",
        );
        return None;
    }
    let names = crate::ir::lower::Names::of(sig, spec.lowering_coords());
    let groups: Vec<usize> = spec
        .coords
        .iter()
        .filter(|c| c.group())
        .map(|c| c.point)
        .collect();
    let time = crate::ir::adapt::Declared {
        name: &adapt.time,
        monitor: &adapt.monitor,
        at: time_at(spec, adapt),
    };
    crate::ir::adapt::transform(cx, graph, l, &time, names, &|i| groups.contains(&i))
}

/// The attribute and the signature of a system on vector spaces: both as far as they parsed
/// (the fallback needs them even after errors), and whether every check passed.
pub struct Parsed {
    /// The attribute, if it parsed.
    pub spec: Option<Spec>,
    /// The signature, if it parsed.
    pub sig: Option<Signature>,
    /// `Ok` when both parsed and passed their checks; else every error of the phase.
    pub parsed: syn::Result<()>,
}

/// The first phase of a system on vector spaces (not element-wise, not on rotation groups).
pub fn parse(args: TokenStream, func: &ItemFn) -> Parsed {
    let cx = Ctxt::new();
    let spec = parse_spec(&cx, args);
    let sig = parse_signature(
        &cx,
        &func.sig,
        spec.as_ref().and_then(|s| s.step.as_ref()),
        spec.as_ref().and_then(|s| s.rule.as_ref()),
        spec.as_ref().is_some_and(|s| s.rule_written),
    );
    if let (Some(spec), Some(sig)) = (&spec, &sig) {
        crate::front::signature::check_controls(&cx, &spec.controls, sig);
    }
    let parsed = cx.finish(spec.as_ref().zip(sig.as_ref()).map(|_| ()));
    Parsed { spec, sig, parsed }
}

/// The phases after the attribute and signature parsed cleanly: lowering, the invariance check
/// and the paper's constructions, up to the graph both back ends read.
pub fn compile_system(spec: &Spec, sig: &Signature, func: &ItemFn) -> syn::Result<Compiled> {
    let lowered = lower_checked(spec, sig, func)?;
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let dense = Backend::for_size(s + k).is_dense();
    let controls: Vec<usize> = spec
        .controls
        .iter()
        .filter_map(|c| sig.params.iter().position(|p| p == c))
        .collect();
    Ok(compile::construct(lowered, s, k, dense, &controls))
}

/// The lowering and the invariance check of a system on vector spaces: the graph of `L_d`,
/// the connection, the forces and the constraints, once `L_d` is known to be invariant under
/// the group (the reduction, and the momentum map a run keeps exact, are valid only then).
pub fn lower_checked(spec: &Spec, sig: &Signature, func: &ItemFn) -> syn::Result<compile::Lowered> {
    let cx = Ctxt::new();
    let ranges = crate::front::ranges::resolve_ranges(&cx, spec, sig);
    let lowered = compile::lower(&cx, spec, sig, func);
    let lowered = cx.finish(lowered)?;
    // The reduction is only valid for a G-invariant L_d.
    let cx = Ctxt::new();
    check::check(&cx, &lowered, spec, sig, &ranges, &func.block);
    cx.finish(Some(()))?;
    Ok(lowered)
}

/// `#[chart_transition]`: the transition's items, or the errors and the fallback items.
pub fn expand_transition(args: TokenStream, item: TokenStream) -> TokenStream {
    let func: ItemFn = match syn::parse2(item) {
        Ok(f) => f,
        Err(e) => return e.into_compile_error(),
    };
    let cx = Ctxt::new();
    let spec = ast_transition::parse_spec(&cx, args);
    let q = ast_transition::parse_signature(&cx, &func);
    let parsed = cx.finish(spec.as_ref().zip(q.as_ref()));
    let result = parsed.and_then(|(spec, q)| {
        let cx = Ctxt::new();
        let lowered = ir_transition::lower(&cx, spec, q, &func);
        let lowered = cx.finish(lowered)?;
        let cx = Ctxt::new();
        ir_transition::check_equivariance(&cx, spec, &lowered, &func);
        cx.finish(Some(()))?;
        Ok(codegen_transition::generate(spec, &func, &lowered))
    });
    match result {
        Ok(out) => out,
        Err(errors) => {
            let mut out = errors.into_compile_error();
            out.extend(fallback::chart_transition(spec.as_ref(), &func));
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    /// The expansion of the paper's charged particle, pretty-printed and compared with the
    /// committed snapshot `tests/snapshots/charged_particle.expanded.rs`. Set `DIRAC_BLESS=1`
    /// to rewrite the snapshot after an intended change to the generated code.
    #[test]
    fn charged_particle_expansion_matches_the_snapshot() {
        let args = quote!(shape(x, y, z), group(theta));
        let item = quote! {
            /// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
            pub fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
                let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
                let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
                let s = a_dot_dq + (q1.theta - q0.theta);
                0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
            }
        };
        let file: syn::File = syn::parse2(expand(args, item)).expect("the expansion parses");
        let text = prettyplease::unparse(&file);
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/snapshots/charged_particle.expanded.rs");
        if std::env::var_os("DIRAC_BLESS").is_some() {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &text).unwrap();
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "the expansion changed; review it and rerun with DIRAC_BLESS=1:\n{text}"
        );
    }

    #[test]
    fn a_rejected_body_still_emits_the_items_other_code_uses() {
        let args = quote!(shape(x), group(theta));
        let item = quote! {
            fn f(q0: Config, q1: Config, h: f64) -> f64 { if h > 0.0 { q0.x } else { q1.x } }
        };
        let out = expand(args, item).to_string();
        assert!(out.contains("compile_error"), "{out}");
        assert!(out.contains("struct FConfig"), "{out}");
        assert!(out.contains("struct F"), "{out}");
        assert!(out.contains("fn f"), "{out}");
        for item in [
            "DiscreteLagrangian",
            "Reduced",
            "Plus",
            "Minus",
            "Unreduced",
            "SHAPE_DIM",
        ] {
            assert!(out.contains(item), "{item} missing from {out}");
        }
    }
}
