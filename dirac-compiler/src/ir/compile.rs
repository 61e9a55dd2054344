//! The middle of the compiler for `#[reduced_lagrangian]`: the lowered body, the connection
//! matrix, the invariance check, and the paper's constructions — both reduced steppers (at the
//! cheapest group origin), the unreduced stepper, the Hessian of `L_d` and the momentum-level
//! elimination — on one hash-consed graph.

use syn::ItemFn;

use crate::ctxt::Ctxt;
use crate::front::signature::Signature;
use crate::front::Spec;
use crate::ir::constraint::{self, ConstrainedCode};
use crate::ir::discretize::{self, Continuous};
use crate::ir::force::{self, Forces};
use crate::ir::graph::{Graph, Node, NodeId, Sym};
use crate::ir::lower::{Lowering, Names};
use crate::ir::reduce::{
    eliminate_group, firsts, lagrangian_hessian, partials, reduce, reduced_stepper,
    unreduced_stepper, Eliminated, Mode, Partials, Side, StepForces, Stepper, GROUP_ORIGINS,
};

/// The lowered body and connection: what the invariance check reads.
pub struct Lowered {
    /// The graph every later stage adds to.
    pub graph: Graph,
    /// `L_d(q0, q1)`: the lowered body, or `L_d` formed from a continuous `L` by its rule.
    pub body: NodeId,
    /// Rows of the connection matrix `B`.
    pub b: Vec<Vec<NodeId>>,
    /// The Legendre map and energy of a continuous Lagrangian.
    pub continuous: Option<Continuous>,
    /// The discrete forces `f_d^±`, when the attribute declares `force = ...`.
    pub forces: Option<Forces>,
    /// The constraints, when declared.
    pub constraints: Option<constraint::Constraints>,
    /// Adaptive steps: the time coordinate's index among the group coordinates, the monitor
    /// `g` (over `Q0`, shape entries only) and the user's `L` before the transformation.
    pub adapt: Option<(usize, NodeId, NodeId)>,
}

/// The graph and its roots.
pub struct Compiled {
    /// The graph all roots live in.
    pub graph: Graph,
    /// `L_d(q0, q1)`, the lowered body.
    pub body: NodeId,
    /// Rows of the connection matrix `B`.
    pub b: Vec<Vec<NodeId>>,
    /// The reduced (+) equations, eq. (4.6).
    pub plus: SideCode,
    /// The reduced (−) equations, eq. (4.8) with the signs of Definition 2.8.
    pub minus: SideCode,
    /// The unreduced stepper, Definitions 2.7/2.8.
    pub unreduced: Stepper,
    /// The unreduced stepper's partial derivatives, for its sensitivities.
    pub unreduced_partials: Option<Partials>,
    /// `(D11, D12, D22)` of `L_d`, for the step-map Jacobian (dense systems without forces only:
    /// a forced step has no Hessian form, its sensitivities are [`Partials`]).
    pub hessian: Option<[Vec<Vec<NodeId>>; 3]>,
    /// The Legendre map and energy of a continuous Lagrangian.
    pub continuous: Option<Continuous>,
    /// The discrete forces `f_d^±`, when declared.
    pub forces: Option<Forces>,
    /// The constrained steppers, when constraints are declared.
    pub constrained: Option<ConstrainedCode>,
    /// Adaptive steps: the time coordinate's index among the group coordinates, the monitor
    /// and the user's `L` before the transformation.
    pub adapt: Option<(usize, NodeId, NodeId)>,
}

/// What one side of the reduced equations compiles to.
pub struct SideCode {
    /// Which side.
    pub side: Side,
    /// The reduced Lagrangian at the paper's group origin (`α = 0`: eqs. (4.5), (4.7)).
    pub lagrangian: NodeId,
    /// The general stepper, at the group origin with the least code.
    pub stepper: Stepper,
    /// The stepper with its group unknowns eliminated, when they enter affinely.
    pub eliminated: Option<Eliminated>,
    /// Whether the eliminated stepper is the better default (no more code than the general).
    pub elimination_pays: bool,
    /// The general stepper's partial derivatives, for its sensitivities.
    pub partials: Option<Partials>,
}

/// Lowers the body (and a continuous `L` to `L_d` by its rule) and the connection matrix;
/// `None` after errors, all recorded in `cx`.
pub fn lower(cx: &Ctxt, spec: &Spec, sig: &Signature, func: &ItemFn) -> Option<Lowered> {
    let names = Names::of(sig, spec.layout.lowering_coords());
    let (s, k) = (spec.layout.s(), spec.layout.k());
    let mut graph = Graph::default();
    let body = Lowering::new(&mut graph, cx, &names).body(&func.block);
    // Adaptive steps: the time-transformed L₂ in place of L.
    let (body, adapt) = match (&spec.adapt, body) {
        (Some(adapt), Some(l)) => {
            if !sig.continuous || spec.rule.is_none() {
                cx.error_spanned_by(
                    &adapt.monitor,
                    "adaptive steps transform a continuous Lagrangian: write `fn l(q: Config, v: Velocity, ..)` with \
                     `rule = midpoint` (or `trapezoid`, `left`, `right`)",
                );
                (None, None)
            } else {
                let names = Names::of(sig, spec.layout.lowering_coords());
                let time = crate::ir::adapt::Declared {
                    name: &adapt.time,
                    monitor: &adapt.monitor,
                    at: crate::ir::adapt::TimeAt {
                        point: s + adapt.index,
                        velocity: s + adapt.index,
                    },
                };
                // With `translate(..)` the user's coordinates are sums of adapted ones, and a
                // monitor of differences reads group coordinates that cancel: sampled instead.
                let declared = spec.layout.declared;
                let is_group = |i: usize| !declared && i >= s;
                let transformed =
                    crate::ir::adapt::transform(cx, &mut graph, l, &time, names, &is_group)
                        .filter(|a| {
                            let varies = declared
                                && crate::ir::adapt::varies_with_group(&graph, a.monitor, s, k);
                            if varies {
                                crate::ir::adapt::monitor_reads_group(cx, &adapt.monitor);
                            }
                            !varies
                        })
                        .map(|mut a| {
                            // Invariant, so read at the group's origin: a function of the shape.
                            if declared {
                                a.monitor = graph.substitute(a.monitor, &mut |g, sym| match sym {
                                    Sym::Q0(i) if i >= s => g.constant(0.0),
                                    other => g.var(other),
                                });
                            }
                            a
                        });
                match transformed {
                    Some(a) => (Some(a.lagrangian), Some((adapt.index, a.monitor, l))),
                    None => (None, None),
                }
            }
        }
        (_, body) => (body, None),
    };
    // A continuous L(q, v): keep it for the Legendre map and energy, and form L_d by the rule.
    let (body, continuous) = match (body, spec.rule.as_ref().filter(|_| sig.continuous)) {
        (Some(l), Some(&(_, rule))) => {
            let h = graph.var(Sym::Param(sig.step_index()));
            let parts = discretize::continuous(&mut graph, l, s + k, rule, mode_for(s + k));
            (
                Some(discretize::discretize(&mut graph, l, s + k, h, rule)),
                Some(parts),
            )
        }
        (body, _) => (body, None),
    };
    let b: Option<Vec<Vec<NodeId>>> = match &spec.connection {
        None => {
            let zero = graph.constant(0.0);
            Some(vec![vec![zero; s]; k])
        }
        Some(rows) => rows
            .iter()
            .map(|row| {
                row.iter()
                    .map(|e| Lowering::new(&mut graph, cx, &names).constant_entry(e))
                    .collect()
            })
            .collect(),
    };
    let forces = spec.force.as_ref().map(|closure| {
        let form = match spec.rule.as_ref().filter(|_| sig.continuous) {
            Some(&(_, rule)) => {
                let h = graph.var(Sym::Param(sig.step_index()));
                force::Form::Continuous { rule, h }
            }
            None => force::Form::Discrete,
        };
        // A continuous force `F(q, v)` is kept beside its discrete forces: the stages of a
        // Gauss–Legendre step read it.
        match (&spec.adapt, form) {
            (adapt, force::Form::Continuous { rule, h }) => {
                let parts = force::lower_parts(cx, &mut graph, closure, names, s + k, false)?;
                let f = match adapt {
                    // Adaptive steps: the force transformed in time with the Lagrangian.
                    Some(adapt) => {
                        let time = crate::ir::adapt::TimeAt {
                            point: s + adapt.index,
                            velocity: s + adapt.index,
                        };
                        crate::ir::adapt::transform_force(cx, &mut graph, &parts[0], time, closure)?
                    }
                    None => parts[0].clone(),
                };
                let discrete = force::discretize(&mut graph, &f, s + k, h, rule);
                Some((discrete, Some(f)))
            }
            (_, form) => {
                force::lower(cx, &mut graph, closure, names, s + k, form).map(|f| (f, None))
            }
        }
    });
    let constraints = spec.constraints.as_ref().map(|closure| {
        let names = Names::of(sig, spec.layout.lowering_coords());
        let h = graph.var(Sym::Param(sig.step_index()));
        constraint::lower(
            cx,
            &mut graph,
            closure,
            names,
            sig.continuous,
            !spec.nonholonomic,
            h,
        )
    });
    let (forces, continuous_force) = match forces {
        Some(f) => {
            let (discrete, continuous) = f?;
            (Some(discrete), continuous)
        }
        None => (None, None),
    };
    // The stages of a Gauss–Legendre step: on the dense backend, without constraints.
    let continuous = continuous.map(|mut c| {
        let n = s + k;
        if n <= DENSE_MAX && spec.constraints.is_none() {
            c.stage = Some(discretize::stage(
                &mut graph,
                &c,
                continuous_force.as_deref(),
                n,
                mode_for(n),
            ));
        }
        c
    });
    let constraints = match constraints {
        Some(c) => Some(c?),
        None => None,
    };
    Some(Lowered {
        graph,
        body: body?,
        b: b?,
        continuous,
        forces,
        constraints,
        adapt,
    })
}

/// Systems with at most this many configuration coordinates get the dense fixed-size backend
/// (`Lu<N>`, everything on the stack); larger ones the sparse backend (`SparseLu` on the
/// compile-time pattern of the step Jacobian), and no Hessian impl or momentum-level elimination
/// (whose `S × S` matrices are dense). Equal to `dirac_runtime::DENSE_MAX`, which documents the
/// choice (checked by `tests/backends.rs`).
pub const DENSE_MAX: usize = 16;

/// Systems with at least this many coordinates get their first derivatives by reverse
/// accumulation ([`Mode::Reverse`]), smaller ones by forward passes. Reverse pays on dense
/// couplings: the scaling chain's reduced (+) residual with its Jacobian takes 355 against 538
/// operations at 4 links, 815 against 1698 at 8, 6263 against 29266 at 32. It would also save
/// operations on the paper's systems (charged particle 54 against 77, double spherical pendulum
/// 670 against 745), but change their generated code and their rounding; they have 4
/// coordinates and keep forward mode, their code and their benchmark figures.
pub const REVERSE_FROM: usize = 5;

/// The differentiation mode of a system with `n` coordinates; see [`REVERSE_FROM`].
pub fn mode_for(n: usize) -> Mode {
    if n >= REVERSE_FROM {
        Mode::Reverse
    } else {
        Mode::Forward
    }
}

/// The paper's constructions on a lowered, checked (G-invariant) Lagrangian; `dense` says whether
/// the system gets the dense backend, and with it the Hessian and the elimination; `controls`
/// are the parameter indices of the controls. The steps' partial derivatives (for their
/// sensitivities) are built for systems with forces or controls (a conservative system's
/// unreduced step Jacobian comes from the Hessian of `L_d`).
pub fn construct(
    lowered: Lowered,
    s: usize,
    k: usize,
    dense: bool,
    controls: &[usize],
) -> Compiled {
    let Lowered {
        mut graph,
        body,
        b,
        continuous,
        forces,
        constraints,
        adapt,
    } = lowered;
    let with_partials = forces.is_some() || !controls.is_empty();
    let mode = match mode_for(s + k) {
        Mode::Forward => Mode::Forward,
        Mode::Reverse => sparser_gradient(&mut graph, body, s, k, &b),
    };
    let controls: Vec<Sym> = controls.iter().map(|&i| Sym::Param(i)).collect();
    // The reduced Lagrangians (4.5), (4.7) with the group origin α that gives the least
    // straight-line code: by G-invariance every α gives the same function (eq. (4.5) is α = 0),
    // but e.g. a midpoint rule at α = ½ no longer carries the group unknown through its
    // trigonometric terms. Ties go to the paper's α = 0.
    let build = |side: Side| {
        let (b, forces) = (&b, &forces);
        move |g: &mut Graph, alpha: f64| {
            let l = reduce(g, side, body, s, b, alpha);
            // G-invariant forces reduce by the same substitution as the Lagrangian.
            let reduced: Option<(Vec<NodeId>, Vec<NodeId>)> = forces.as_ref().map(|f| {
                let mut at = |nodes: &[NodeId]| -> Vec<NodeId> {
                    nodes
                        .iter()
                        .map(|&n| reduce(g, side, n, s, b, alpha))
                        .collect()
                };
                (at(&f.minus), at(&f.plus))
            });
            let step_forces = reduced
                .as_ref()
                .map(|(minus, plus)| StepForces { minus, plus });
            reduced_stepper(g, side, l, step_forces, b, s, k, mode)
        }
    };
    let plus = cheapest(&mut graph, build(Side::Plus));
    let minus = cheapest(&mut graph, build(Side::Minus));
    let unreduced = unreduced_stepper(
        &mut graph,
        body,
        forces.as_ref().map(|f| StepForces {
            minus: &f.minus,
            plus: &f.plus,
        }),
        s + k,
        mode,
    );
    let hessian =
        (dense && forces.is_none()).then(|| lagrangian_hessian(&mut graph, body, s + k, mode));
    // Elimination: the cheapest origin at which the momentum equations are structurally affine
    // (dense systems only: its shape Jacobian is a dense `S × S` matrix).
    let (plus_eliminated, minus_eliminated) = if dense {
        (
            cheapest_eliminated(&mut graph, Side::Plus, s, k, build(Side::Plus)),
            cheapest_eliminated(&mut graph, Side::Minus, s, k, build(Side::Minus)),
        )
    } else {
        (None, None)
    };
    // Use the elimination by default only where it does not cost more code per Newton iteration
    // than the general path (10% slack: it also shrinks the linear solve and, for the paper's charged
    // particle, makes each step linear). Substituting the closed form and differentiating through
    // it can make the shape Jacobian larger than the full one — measured on the double spherical
    // pendulum: 913 against 745 operations, and 12% slower.
    let pays = |e: &Option<Eliminated>, full: &Stepper, g: &Graph| {
        e.as_ref().is_some_and(|e| {
            10 * cost(g, &e.residual, &e.jacobian) <= 11 * cost(g, &full.residual, &full.jacobian)
        })
    };
    let side_code = |graph: &mut Graph, side: Side, stepper: Stepper, eliminated| {
        let elimination_pays = pays(&eliminated, &stepper, graph);
        // Built last, so the nodes of the steppers above keep their numbers (and names).
        let lagrangian = reduce(graph, side, body, s, &b, 0.0);
        let partials = with_partials.then(|| {
            let zero = graph.constant(0.0);
            let mut outputs = stepper.momentum.clone();
            if stepper.impulse.is_empty() {
                outputs.extend(std::iter::repeat_n(zero, k));
            } else {
                outputs.extend(&stepper.impulse);
            }
            let data: Vec<Sym> = (0..s).map(Sym::X0).collect();
            let unknowns: Vec<Sym> = (0..s)
                .map(Sym::X1)
                .chain((0..k).map(side.group()))
                .collect();
            partials(graph, &stepper, &outputs, &data, &unknowns, &controls)
        });
        SideCode {
            side,
            lagrangian,
            stepper,
            eliminated,
            elimination_pays,
            partials,
        }
    };
    let plus = side_code(&mut graph, Side::Plus, plus, plus_eliminated);
    let minus = side_code(&mut graph, Side::Minus, minus, minus_eliminated);
    let unreduced_partials = with_partials.then(|| {
        let n = s + k;
        let data: Vec<Sym> = (0..n).map(Sym::Q0).collect();
        let unknowns: Vec<Sym> = (0..n).map(Sym::Q1).collect();
        let outputs = unreduced.momentum.clone();
        partials(
            &mut graph, &unreduced, &outputs, &data, &unknowns, &controls,
        )
    });
    let constrained = match (constraints, &continuous) {
        (Some(phi), Some(parts)) => Some(constraint::construct(
            &mut graph,
            phi,
            &unreduced,
            &plus.stepper,
            &minus.stepper,
            parts,
            &b,
            s,
            k,
        )),
        _ => None,
    };
    Compiled {
        graph,
        body,
        b,
        plus,
        minus,
        unreduced,
        unreduced_partials,
        hessian,
        continuous,
        forces,
        constrained,
        adapt,
    }
}

/// Reverse mode when its gradient of the reduced (+) Lagrangian in `(x0, g1)` (the residual's
/// rows, at the paper's group origin) is at most 4/5 of forward mode's, forward mode otherwise.
/// Reverse accumulation shares the adjoints of accumulated sums among all rows and pays where
/// every row reads them: on the chain its gradient is 0.75 of forward's at 4 links, 0.55 at 8,
/// and its residual with Jacobian 355 against 538 and 815 against 1698 operations. Where each row
/// reads a few terms forward passes touch only those: on the Toda lattice the two gradients are
/// within 5% (352 against 363 operations at 16 particles) and the forward-mode residual with
/// Jacobian is smaller (546 against 584), so it stays in forward mode.
fn sparser_gradient(g: &mut Graph, body: NodeId, s: usize, k: usize, b: &[Vec<NodeId>]) -> Mode {
    let l = reduce(g, Side::Plus, body, s, b, 0.0);
    let rows: Vec<Sym> = (0..s).map(Sym::X0).chain((0..k).map(Sym::G1)).collect();
    let forward = firsts(g, Mode::Forward, l, &rows);
    let reverse = firsts(g, Mode::Reverse, l, &rows);
    if 5 * cost(g, &reverse, &[]) <= 4 * cost(g, &forward, &[]) {
        Mode::Reverse
    } else {
        Mode::Forward
    }
}

/// Operations in the straight line that computes a residual and its Jacobian together.
fn cost(g: &Graph, residual: &[NodeId], jacobian: &[Vec<NodeId>]) -> usize {
    let roots: Vec<NodeId> = residual
        .iter()
        .chain(jacobian.iter().flatten())
        .copied()
        .collect();
    g.cone(&roots)
        .into_iter()
        .filter(|&n| !matches!(g.node(n), Node::Const(_) | Node::Var(_)))
        .count()
}

/// The stepper built at the group origin (see [`GROUP_ORIGINS`]) with the least code.
fn cheapest(g: &mut Graph, build: impl Fn(&mut Graph, f64) -> Stepper) -> Stepper {
    let candidates: Vec<Stepper> = GROUP_ORIGINS.iter().map(|&alpha| build(g, alpha)).collect();
    candidates
        .into_iter()
        .min_by_key(|st| cost(g, &st.residual, &st.jacobian))
        .expect("at least one group origin")
}

/// The eliminated stepper with the least code over the group origins where elimination applies.
fn cheapest_eliminated(
    g: &mut Graph,
    side: Side,
    s: usize,
    k: usize,
    build: impl Fn(&mut Graph, f64) -> Stepper,
) -> Option<Eliminated> {
    let candidates: Vec<Eliminated> = GROUP_ORIGINS
        .iter()
        .filter_map(|&alpha| {
            let st = build(g, alpha);
            eliminate_group(g, side, &st, s, k)
        })
        .collect();
    candidates
        .into_iter()
        .min_by_key(|e| cost(g, &e.residual, &e.jacobian))
}
