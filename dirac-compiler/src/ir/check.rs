//! The compile-time invariance check. The reduction (eqs. (4.5)–(4.8)) is only valid for a
//! G-invariant discrete Lagrangian, `L_d(g + q0, g + q1) = L_d(q0, q1)` with `g` translating the
//! declared group coordinates: otherwise the reduced Lagrangian depends on where `g_k` is set to
//! zero and the emitted stepper integrates a different system, silently. This stage evaluates the
//! lowered body at deterministic pseudo-random points and rejects a body that changes when one
//! group coordinate is translated, naming the coordinate and the point.
//!
//! A sampled check is not a proof: a body could break invariance only outside the sampled box, or
//! by an amount below the tolerance. It catches the realistic mistakes (an absolute group
//! coordinate anywhere in the body), which change `L_d` by O(1) at almost every point.

use std::ops::Not;

use crate::ctxt::Ctxt;
use crate::front::layout::{GroupDecl, Layout};
use crate::front::ranges::Ranges;
use crate::front::signature::Signature;
use crate::front::Spec;
use crate::ir::compile::Lowered;
use crate::ir::graph::{Graph, NodeId, Sym};

/// Number of sample points.
const POINTS: usize = 16;
/// The generator's seed: fixed, so a compile error names the same point on every build.
const SEED: u64 = 0xD12A_C5EE_D0F1_A7E5;
/// Default sampling box of every coordinate (of `q0` and `q1` alike).
const COORDS: (f64, f64) = (-2.0, 2.0);
/// Default sampling range of every parameter: positive, because step sizes, masses and lengths
/// are, and a body is often only defined for those (`1.0 / h`, `m.sqrt()`).
const PARAMS: (f64, f64) = (0.5, 2.0);
/// Translations applied to one group coordinate at a time: a small, a negative and a large one,
/// so a periodic dependence (`q0.theta.cos()`) cannot hide behind one unlucky shift.
const SHIFTS: [f64; 3] = [0.37, -1.9, 5.0];
/// Relative tolerance on `|L(q0 + g, q1 + g) − L(q0, q1)| ≤ TOL · max(1, |L|)`. For an invariant
/// body the two evaluations differ only by round-off: translating both configurations by `g`
/// perturbs a difference `q1.theta − q0.theta` by a few ulps of `|g| + 4` (about 1e-15 here), and
/// the body amplifies that by its sensitivity to the difference. An invariant body fails only if
/// `|∂L_d/∂(q1.theta − q0.theta)|` exceeds about 1e6 · max(1, |L_d|), which takes extreme
/// constants or parameter ranges; a real violation changes `L_d` by O(1) relative
/// (`cos(θ + 0.37) − cos θ`). 1e-9 sits between the two with orders of magnitude to spare on
/// each side (the 210 random invariant Lagrangians of `tests/random_exprs` all pass).
const TOL: f64 = 1e-9;

/// SplitMix64 (Steele, Lea & Flood 2014): tiny, fast, and good enough to spread sample points.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi]`, rounded to three significant digits (kept inside the range), so the
    /// point an error message prints is exactly the point that was evaluated.
    fn sample(&mut self, (lo, hi): (f64, f64)) -> f64 {
        let v = lo + (hi - lo) * self.unit();
        let r = round_sig(v, 3);
        if (lo..=hi).contains(&r) {
            r
        } else {
            v
        }
    }
}

/// `v` rounded to `digits` significant decimal digits (the nearest f64 to that decimal).
fn round_sig(v: f64, digits: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let e = digits - 1 - v.abs().log10().floor() as i32;
    if e >= 0 {
        let scale = 10f64.powi(e);
        (v * scale).round() / scale
    } else {
        let scale = 10f64.powi(-e);
        (v / scale).round() * scale
    }
}

/// One sample point: both configurations and the parameters.
struct Point {
    q0: Vec<f64>,
    q1: Vec<f64>,
    params: Vec<f64>,
}

/// Where each coordinate and parameter is sampled: the declared range or the default.
struct Boxes {
    /// One per component of the user's configuration vector.
    coords: Vec<(f64, f64)>,
    /// One per user coordinate (for messages).
    declared: Vec<(f64, f64)>,
    params: Vec<(f64, f64)>,
}

impl Boxes {
    fn new(ranges: &Ranges, layout: &Layout) -> Self {
        let declared: Vec<(f64, f64)> = ranges.coords.iter().map(|r| r.unwrap_or(COORDS)).collect();
        let coords = layout
            .coords
            .iter()
            .zip(&declared)
            .flat_map(|(c, &b)| std::iter::repeat_n(b, c.len.unwrap_or(1)))
            .collect();
        Boxes {
            coords,
            declared,
            params: ranges.params.iter().map(|r| r.unwrap_or(PARAMS)).collect(),
        }
    }

    fn points(&self) -> Vec<Point> {
        let mut rng = SplitMix64(SEED);
        (0..POINTS)
            .map(|_| Point {
                q0: self.coords.iter().map(|&r| rng.sample(r)).collect(),
                q1: self.coords.iter().map(|&r| rng.sample(r)).collect(),
                params: self.params.iter().map(|&r| rng.sample(r)).collect(),
            })
            .collect()
    }

    /// `coordinates in [-2, 2], parameters in [0.5, 2]`, naming whatever was declared.
    fn describe(&self, names: &Names, with_coords: bool) -> String {
        let part = |what: &str, names: &[String], boxes: &[(f64, f64)], default: (f64, f64)| {
            let mut out: Vec<String> = names
                .iter()
                .zip(boxes)
                .filter(|(_, &b)| b != default)
                .map(|(n, (lo, hi))| format!("`{n}` in [{lo}, {hi}]"))
                .collect();
            let (lo, hi) = default;
            if out.is_empty() {
                out.push(format!("{what} in [{lo}, {hi}]"));
            } else if out.len() < names.len() {
                out.push(format!("other {what} in [{lo}, {hi}]"));
            }
            out
        };
        let mut parts = Vec::new();
        if with_coords {
            parts.extend(part("coordinates", &names.declared, &self.declared, COORDS));
        }
        if !names.params.is_empty() {
            parts.extend(part("parameters", &names.params, &self.params, PARAMS));
        }
        parts.join(", ")
    }
}

/// Checks that the body is invariant under translation of each group coordinate, and that the
/// connection matrix is finite at the sampled parameters; every failure is recorded in `cx`.
///
/// The connection needs no numerical check of Definition 2.1: for the linear form
/// `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)` with a constant `B`, `ω_d(q, q) = 0` identically, and
/// equivariance, `ω_d(g + q0, g' + q1) = g' + ω_d(q0, q1) − g` for the translations of
/// `G = R^K`, holds for every `B`, since `B` multiplies shape differences only, which the action
/// leaves alone. What can go wrong is only the value of `B`: an entry such as `(b - 1.0).sqrt()`
/// that is not a number at the parameters the integrator will run with.
pub fn check(
    cx: &Ctxt,
    lowered: &Lowered,
    spec: &Spec,
    sig: &Signature,
    ranges: &Ranges,
    block: &syn::Block,
) {
    let (graph, body, b) = (&lowered.graph, lowered.body, &lowered.b);
    let boxes = Boxes::new(ranges, &spec.layout);
    let points = boxes.points();
    let names = Names {
        coords: spec.layout.user_components(),
        declared: spec
            .layout
            .coords
            .iter()
            .map(|c| c.name.to_string())
            .collect(),
        params: sig.params.iter().map(|p| p.to_string()).collect(),
        q0: sig.q0.to_string(),
        q1: sig.q1.to_string(),
    };
    invariance(cx, graph, body, block, spec, &boxes, &points, &names);
    connection(cx, graph, b, spec, &boxes, &points, &names);
    if let (Some(forces), Some(closure)) = (&lowered.forces, &spec.force) {
        let roots: Vec<NodeId> = forces.minus.iter().chain(&forces.plus).copied().collect();
        values_invariance(cx, graph, &roots, closure, "force", spec, &points, &names);
    }
    if let (Some(c), Some(closure)) = (&lowered.constraints, &spec.constraints) {
        // The constraint rows of a step read q_k and q_{k+1}, as the forces do.
        values_invariance(
            cx,
            graph,
            &c.rows,
            closure,
            "constraint",
            spec,
            &points,
            &names,
        );
    }
}

/// The forces and the constraints must be G-invariant for the reduction (see
/// `crate::ir::reduce::reduced_stepper` and `crate::ir::constraint`): each value unchanged when
/// one group coordinate is translated in both configurations. One error, at the closure, for the
/// first broken group coordinate; `what` names the values.
#[allow(clippy::too_many_arguments)] // two call sites; a struct would only rename them
fn values_invariance(
    cx: &Ctxt,
    graph: &Graph,
    roots: &[NodeId],
    closure: &syn::ExprClosure,
    what: &str,
    spec: &Spec,
    points: &[Point],
    names: &Names,
) {
    let layout = &spec.layout;
    let eval = |q0: &[f64], q1: &[f64], params: &[f64]| {
        graph.eval(roots, &|sym| match sym {
            Sym::Q0(i) => q0[i],
            Sym::Q1(i) => q1[i],
            Sym::Param(i) => params[i],
            other => unreachable!("the {what}s read q0, q1 and parameters, not {other:?}"),
        })
    };
    let s = layout.s();
    for p in points {
        let (a0, a1) = (layout.to_adapted(&p.q0), layout.to_adapted(&p.q1));
        let f = eval(&a0, &a1, &p.params);
        if f.iter().any(|v| !v.is_finite()) {
            continue;
        }
        for (j, decl) in layout.group_decls.iter().enumerate() {
            for shift in SHIFTS {
                let (mut q0, mut q1) = (a0.clone(), a1.clone());
                q0[s + j] += shift;
                q1[s + j] += shift;
                let shifted = eval(&q0, &q1, &p.params);
                let changed = f
                    .iter()
                    .zip(&shifted)
                    .any(|(a, b)| ((b - a).abs() <= TOL * a.abs().max(1.0)).not());
                if !changed {
                    continue;
                }
                let group = match decl {
                    GroupDecl::Coordinate { component, .. } => {
                        format!("group coordinate `{component}`")
                    }
                    GroupDecl::Translate { names: moved, .. } => {
                        let list: Vec<String> = moved.iter().map(ToString::to_string).collect();
                        format!("translation `translate({})`", list.join(", "))
                    }
                };
                cx.error_spanned_by(
                    closure,
                    format!(
                        "the {what} is not invariant under the {group}: at {}, shifting it by {shift} in both configurations \
                         changes its value; `#[reduced_lagrangian]` reduces by this symmetry, so a {what} may depend on \
                         the group coordinates only through differences (as the Lagrangian does)",
                        // The values read a step's two configurations, whatever the body's
                        // arguments are called.
                        names.point_named(&p.q0, &p.q1, &p.params, "q_k", "q_k+1"),
                    ),
                );
                return;
            }
        }
    }
}

/// Names for messages.
struct Names {
    /// The components of the user's configuration vector.
    coords: Vec<String>,
    /// The user's coordinates, as declared.
    declared: Vec<String>,
    params: Vec<String>,
    q0: String,
    q1: String,
}

impl Names {
    /// `q0 = (x = 0.31, theta = -1.2), q1 = (…), h = 0.8, m = 1.3`.
    fn point(&self, q0: &[f64], q1: &[f64], params: &[f64]) -> String {
        self.point_named(q0, q1, params, &self.q0, &self.q1)
    }

    /// [`Self::point`] with the two configurations named `n0`, `n1`.
    fn point_named(&self, q0: &[f64], q1: &[f64], params: &[f64], n0: &str, n1: &str) -> String {
        let config = |q: &[f64]| {
            let fields: Vec<String> = self
                .coords
                .iter()
                .zip(q)
                .map(|(n, v)| format!("{n} = {v}"))
                .collect();
            format!("({})", fields.join(", "))
        };
        let mut parts = vec![
            format!("{n0} = {}", config(q0)),
            format!("{n1} = {}", config(q1)),
        ];
        parts.extend(self.params(params));
        parts.join(", ")
    }

    fn params(&self, params: &[f64]) -> Vec<String> {
        self.params
            .iter()
            .zip(params)
            .map(|(n, v)| format!("{n} = {v}"))
            .collect()
    }
}

#[allow(clippy::too_many_arguments)] // one call site; a struct would only rename them
fn invariance(
    cx: &Ctxt,
    graph: &Graph,
    body: NodeId,
    block: &syn::Block,
    spec: &Spec,
    boxes: &Boxes,
    points: &[Point],
    names: &Names,
) {
    // The sample points are drawn in the user's coordinates (where `ranges(...)` applies) and
    // evaluated in the configuration vector `q = T⁻¹ q_user` the body was lowered in (the
    // identity unless the symmetry is declared with `translate(...)`).
    let layout = &spec.layout;
    let eval = |q0: &[f64], q1: &[f64], params: &[f64]| {
        graph.eval(&[body], &|sym| match sym {
            Sym::Q0(i) => q0[i],
            Sym::Q1(i) => q1[i],
            Sym::Param(i) => params[i],
            other => unreachable!("the body reads q0, q1 and parameters, not {other:?}"),
        })[0]
    };
    let s = layout.s();
    let mut finite = 0;
    // The first failure for each group coordinate: one error per broken coordinate.
    let mut broken: Vec<bool> = vec![false; layout.k()];
    for p in points {
        let (a0, a1) = (layout.to_adapted(&p.q0), layout.to_adapted(&p.q1));
        let l = eval(&a0, &a1, &p.params);
        // Outside its domain the body says nothing about invariance; skip the point.
        if !l.is_finite() {
            continue;
        }
        finite += 1;
        for (j, decl) in layout.group_decls.iter().enumerate() {
            if broken[j] {
                continue;
            }
            for shift in SHIFTS {
                let (mut q0, mut q1) = (a0.clone(), a1.clone());
                q0[s + j] += shift;
                q1[s + j] += shift;
                let shifted = eval(&q0, &q1, &p.params);
                // Written so that a NaN after the shift counts as a change: an invariant body
                // that is finite at a point is finite at every translate of it.
                if (shifted - l).abs() <= TOL * l.abs().max(1.0) {
                    continue;
                }
                broken[j] = true;
                let (before, after) = distinct(l, shifted);
                let (q0_name, q1_name) = (&names.q0, &names.q1);
                let point = names.point(&p.q0, &p.q1, &p.params);
                match decl {
                    GroupDecl::Coordinate { ident, component: group } => cx.error_spanned_by(
                        ident,
                        format!(
                            "the discrete Lagrangian is not invariant under translation of the group coordinate `{group}`: \
                             at {point}, shifting `{group}` by {shift} in both `{q0_name}` and `{q1_name}` changes L_d from {before} to {after}; \
                             `#[reduced_lagrangian]` reduces by translations of the group coordinates, so L_d may depend on \
                             them only through differences such as `{q1_name}.{group} - {q0_name}.{group}`; \
                             if L_d depends on `{group}` itself, declare it in `shape(...)`",
                        ),
                    ),
                    GroupDecl::Translate { key, names: moved } => {
                        let list: Vec<String> = moved.iter().map(ToString::to_string).collect();
                        let declared = format!("translate({})", list.join(", "));
                        let first = &moved[0];
                        let example = match layout.coords.iter().find(|c| c.name == *first).and_then(|c| c.len) {
                            Some(n) if n > 1 => format!("`{q0_name}.{first}[1] - {q0_name}.{first}[0]`"),
                            _ if moved.len() > 1 => format!("`{q0_name}.{} - {q0_name}.{first}`", moved[1]),
                            _ => format!("`{q1_name}.{first} - {q0_name}.{first}`"),
                        };
                        cx.error_spanned_by(
                            quote::quote!(#key #first),
                            format!(
                                "the discrete Lagrangian is not invariant under the translation `{declared}`: at {point}, adding {shift} \
                                 to every component of {} in both `{q0_name}` and `{q1_name}` changes L_d from {before} to {after}; \
                                 a declared translation must leave L_d unchanged, so L_d may depend on the translated coordinates only \
                                 through differences such as {example}; if L_d depends on their absolute values, remove `{declared}`",
                                list.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "),
                            ),
                        );
                    }
                }
                break;
            }
        }
    }
    if finite == 0 {
        let p = &points[0];
        let l = eval(
            &layout.to_adapted(&p.q0),
            &layout.to_adapted(&p.q1),
            &p.params,
        );
        let example = names.params.first().map_or("x", String::as_str);
        let message = format!(
            "the discrete Lagrangian is not finite at any of the {POINTS} points where `#[reduced_lagrangian]` checks its \
             invariance ({}; e.g. L_d = {} at {}); accepted: a body that is finite somewhere in the sampled box \
             — if it is defined only for some parameter or coordinate values, declare them with `ranges({example} = (lo, hi), ...)`",
            boxes.describe(names, true),
            fmt_sig(l, 6),
            names.point(&p.q0, &p.q1, &p.params),
        );
        // Point at the body's value (the whole expression, not only its first token).
        match block.stmts.last() {
            Some(last) => cx.error_spanned_by(last, message),
            None => cx.error_spanned_by(block, message),
        }
    }
}

fn connection(
    cx: &Ctxt,
    graph: &Graph,
    b: &[Vec<NodeId>],
    spec: &Spec,
    boxes: &Boxes,
    points: &[Point],
    names: &Names,
) {
    let Some(rows) = &spec.connection else { return };
    for (j, (row, row_exprs)) in b.iter().zip(rows).enumerate() {
        for (i, (&entry, expr)) in row.iter().zip(row_exprs).enumerate() {
            let bad = points.iter().find_map(|p| {
                let v = graph.eval(&[entry], &|sym| match sym {
                    Sym::Param(k) => p.params[k],
                    other => unreachable!("connection entries read parameters, not {other:?}"),
                })[0];
                (!v.is_finite()).then_some((v, p))
            });
            let Some((v, p)) = bad else { continue };
            let at = names.params(&p.params);
            let at = if at.is_empty() {
                String::new()
            } else {
                format!(" at {}", at.join(", "))
            };
            cx.error_spanned_by(
                expr,
                format!(
                    "the connection entry in row `{}`, column `{}` is {}{at}; accepted: entries that are finite at every \
                     sampled parameter value ({}) — if the parameters are restricted, declare their ranges with \
                     `ranges(name = (lo, hi), ...)`",
                    spec.layout.group[j],
                    spec.layout.shape[i],
                    fmt_sig(v, 6),
                    boxes.describe(names, false),
                ),
            );
        }
    }
}

/// Formats `a` and `b` with the fewest significant digits (at least 6) that tell them apart.
fn distinct(a: f64, b: f64) -> (String, String) {
    for digits in 6..=17 {
        let (x, y) = (fmt_sig(a, digits), fmt_sig(b, digits));
        if x != y || digits == 17 {
            return (x, y);
        }
    }
    unreachable!("the loop returns at 17 digits")
}

/// `v` with `digits` significant digits, trailing zeros trimmed: `1.23457`, `-0.00123`, `1.5e12`.
fn fmt_sig(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let exp = v.abs().log10().floor() as i32;
    if (-4..6).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.prec$e}", prec = digits - 1);
        let (mantissa, e) = s.split_once('e').expect("`{:e}` writes an exponent");
        let mantissa = if mantissa.contains('.') {
            mantissa.trim_end_matches('0').trim_end_matches('.')
        } else {
            mantissa
        };
        format!("{mantissa}e{e}")
    }
}

/// The invariance check of one element of an element-wise system (`dirac::runtime::element`):
/// its `L_d^e` (over the stencil's slots, `Q0`/`Q1`) must not change when every slot of a
/// translated coordinate moves by the same amount, or the momentum map the integrator keeps
/// exact is not conserved. `translation_of[a]` is the declared translation (index) slot `a`
/// belongs to, if any; `names[j]` names translation `j` for messages; the error, if any, is
/// reported at `at`. Parameters (and sizes and loop indices read as values) are sampled in the
/// default positive range.
pub fn element_invariance(
    cx: &Ctxt,
    g: &Graph,
    ld: NodeId,
    translation_of: &[Option<usize>],
    names: &[String],
    at: &proc_macro2::TokenStream,
    what: &str,
) {
    let width = translation_of.len();
    let mut rng = SplitMix64(SEED);
    for _ in 0..POINTS {
        let q0: Vec<f64> = (0..width).map(|_| rng.sample(COORDS)).collect();
        let q1: Vec<f64> = (0..width).map(|_| rng.sample(COORDS)).collect();
        let params: Vec<f64> = (0..64).map(|_| rng.sample(PARAMS)).collect();
        let eval = |shift: Option<(usize, f64)>| {
            let moved = |a: usize, v: f64| match shift {
                Some((j, c)) if translation_of[a] == Some(j) => v + c,
                _ => v,
            };
            g.eval(&[ld], &|sym| match sym {
                Sym::Q0(a) => moved(a, q0[a]),
                Sym::Q1(a) => moved(a, q1[a]),
                Sym::Param(i) => params[i % params.len()],
                _ => 0.0,
            })[0]
        };
        let base = eval(None);
        if !base.is_finite() {
            continue;
        }
        for (j, name) in names.iter().enumerate() {
            if !translation_of.contains(&Some(j)) {
                continue;
            }
            for shift in SHIFTS {
                let moved = eval(Some((j, shift)));
                if (moved - base).abs() > TOL * base.abs().max(1.0) {
                    cx.error_spanned_by(
                        at,
                        format!(
                            "this element is not invariant under `translate({name})`: its {what} changes from {base:e} to {moved:e} when every component of the translation moves by {shift}; the momentum map could not be kept. Write the element in differences of the translated coordinates (e.g. `q.x[i + 1] - q.x[i]`), or do not declare the translation"
                        ),
                    );
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    /// The front end, the lowering and this check on `body`, phase by phase as the expansion
    /// runs them, without code generation: the first failing phase's errors as
    /// `compile_error!` tokens, or nothing.
    fn expand(args: proc_macro2::TokenStream, body: proc_macro2::TokenStream) -> String {
        let func: syn::ItemFn = syn::parse_quote! {
            fn f(q0: Config, q1: Config, h: f64, m: f64) -> f64 { #body }
        };
        let phases = || -> syn::Result<()> {
            let cx = Ctxt::new();
            let spec = crate::front::parse_spec(&cx, args);
            let sig = spec.as_ref().and_then(|_| {
                crate::front::signature::parse_signature(&cx, &func.sig, None, None, false)
            });
            let (spec, sig) = cx.finish(spec.zip(sig))?;
            let cx = Ctxt::new();
            let ranges = crate::front::ranges::resolve_ranges(&cx, &spec, &sig);
            let lowered = crate::ir::compile::lower(&cx, &spec, &sig, &func);
            let lowered = cx.finish(lowered)?;
            let cx = Ctxt::new();
            check(&cx, &lowered, &spec, &sig, &ranges, &func.block);
            cx.finish(Some(()))
        };
        phases()
            .err()
            .map_or_else(String::new, |e| e.into_compile_error().to_string())
    }

    #[test]
    fn an_invariant_body_passes() {
        let out = expand(
            quote!(shape(x), group(a, b)),
            quote! {
                let (dx, da, db) = (q1.x - q0.x, q1.a - q0.a, q1.b - q0.b);
                0.5 * m / h * (dx * dx + (da - q0.x * db).powi(2)) - h * (q0.x.cos() + db.sin())
            },
        );
        assert!(!out.contains("compile_error"), "{out}");
    }

    #[test]
    fn a_periodic_dependence_is_caught() {
        let out = expand(
            quote!(shape(x), group(theta)),
            quote! { 0.5 * m / h * (q1.x - q0.x).powi(2) - h * q0.theta.cos() },
        );
        assert!(out.contains("not invariant under translation of the group coordinate `theta`"));
    }

    #[test]
    fn only_the_broken_coordinate_is_named() {
        let out = expand(
            quote!(shape(x), group(a, b)),
            quote! { (q1.a - q0.a).powi(2) + q1.b * q1.b + (q1.x - q0.x).powi(2) / h + m },
        );
        assert!(out.contains("group coordinate `b`"), "{out}");
        assert!(!out.contains("group coordinate `a`"), "{out}");
    }

    #[test]
    fn ranges_make_a_restricted_body_checkable() {
        let body = quote! { (0.4 - h).ln() * (q1.x - q0.x).powi(2) + m * (q1.theta - q0.theta) };
        let without = expand(quote!(shape(x), group(theta)), body.clone());
        assert!(without.contains("compile_error"), "{without}");
        let with = expand(
            quote!(shape(x), group(theta), ranges(h = (0.01, 0.3))),
            body,
        );
        assert!(!with.contains("compile_error"), "{with}");
    }

    #[test]
    fn a_range_mistake_and_a_body_mistake_are_reported_together() {
        let out = expand(
            quote!(shape(x), group(theta), ranges(k = (0.0, 1.0))),
            quote! { if h > 0.0 { q0.x } else { q1.x } },
        );
        assert!(
            out.contains("`k` is not a parameter or coordinate"),
            "{out}"
        );
        assert!(out.contains("`if` is not supported"), "{out}");
    }

    #[test]
    fn ranges_apply_to_every_component_of_an_array_coordinate() {
        let body = quote! {
            let mut l = m * (q1.theta - q0.theta).powi(2);
            for i in 0..3 {
                l += (q1.x[i] - q0.x[i]).powi(2) / h + h * (q0.x[i] - 3.0).ln();
            }
            l
        };
        let without = expand(quote!(shape(x[3]), group(theta)), body.clone());
        assert!(without.contains("not finite at any"), "{without}");
        let with = expand(
            quote!(shape(x[3]), group(theta), ranges(x = (3.5, 6.0))),
            body,
        );
        assert!(!with.contains("compile_error"), "{with}");
    }

    #[test]
    fn declared_translations_are_checked_in_adapted_coordinates() {
        let differences = quote! {
            let mut l = 0.0;
            for i in 0..3 {
                l += (q1.x[i] - q0.x[i]).powi(2) / h - h * m * (q0.x[(i + 1) % 3] - q0.x[i]).cos();
            }
            l + (q1.y - q0.y).powi(2) / h + h * q0.y.sin()
        };
        let ok = expand(
            quote!(coordinates(x[3], y), translate(x)),
            differences.clone(),
        );
        assert!(!ok.contains("compile_error"), "{ok}");
        // `y` is not translated with `x`: translating both together is not a symmetry.
        let broken = expand(quote!(coordinates(x[3], y), translate(x, y)), differences);
        assert!(
            broken.contains("not invariant under the translation `translate(x, y)`"),
            "{broken}"
        );
    }

    #[test]
    fn an_array_group_coordinate_is_checked_per_component() {
        let ok = expand(
            quote!(shape(x), group(c[2])),
            quote! { (q1.c[0] - q0.c[0]).powi(2) / h + m * (q1.c[1] - q0.c[1] - q0.x).powi(2) },
        );
        assert!(!ok.contains("compile_error"), "{ok}");
        let broken = expand(
            quote!(shape(x), group(c[2])),
            quote! { (q1.c[0] - q0.c[0]).powi(2) / h + m * q0.c[1].cos() + q1.x },
        );
        assert!(broken.contains("group coordinate `c[1]`"), "{broken}");
        assert!(!broken.contains("group coordinate `c[0]`"), "{broken}");
    }

    #[test]
    fn integer_index_arithmetic() {
        let out = expand(
            quote!(shape(x[5]), group()),
            quote! {
                let mut l = 0.0;
                for i in 0..5 {
                    l += (q1.x[(i + 4) % 5] - q0.x[i / 2 * 2 - i + i]).powi(2) / h
                        + m * q0.x[(2 * i + 1) % 5] * q0.x[4 - i];
                }
                l
            },
        );
        assert!(!out.contains("compile_error"), "{out}");
        let zero = expand(
            quote!(shape(x[5]), group()),
            quote! { (q1.x[1 % 0] - q0.x[0]).powi(2) / h + m },
        );
        assert!(zero.contains("integer division by zero"), "{zero}");
    }

    #[test]
    fn round_off_is_not_a_violation() {
        // cos(θ1 − θ0) written through absolute angles: invariant, but evaluated with different
        // rounding at every translate.
        let out = expand(
            quote!(shape(x), group(theta)),
            quote! {
                m / h * (q1.theta.cos() * q0.theta.cos() + q1.theta.sin() * q0.theta.sin())
                    + (q1.x - q0.x).powi(2)
            },
        );
        assert!(!out.contains("compile_error"), "{out}");
    }

    #[test]
    fn sampled_values_print_exactly() {
        let mut rng = SplitMix64(SEED);
        for _ in 0..1000 {
            let v = rng.sample((0.001, 0.1));
            assert!((0.001..=0.1).contains(&v));
            assert_eq!(format!("{v}").parse::<f64>().unwrap(), v);
            assert!(format!("{v}").len() <= 7, "{v}");
        }
    }

    #[test]
    fn formatting() {
        assert_eq!(fmt_sig(1.2345678, 6), "1.23457");
        assert_eq!(fmt_sig(-0.5, 6), "-0.5");
        assert_eq!(fmt_sig(1.5e12, 6), "1.5e12");
        assert_eq!(fmt_sig(f64::NAN, 6), "NaN");
        assert_eq!(distinct(1.0, 1.0 + 1e-8), ("1".into(), "1.00000001".into()));
    }
}
