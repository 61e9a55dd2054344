//! Systems on rotation groups given as text: the phases of `#[reduced_lagrangian]` with
//! `rotation(..)` or `direction(..)` coordinates (the attribute and signature, the lowering with
//! matrix and vector values, the symmetry checks, the Lie group variational step on the graph),
//! ending in the straight-line [`Program`]s of the runtime's `LieLagrangian` and `LieSymmetric`.

use proc_macro2::TokenStream;
use syn::ItemFn;

use super::{stepper, Program, Stepper};
use crate::back::program::program;
use crate::expand::{compile_lie as compile_phases, LieCompiled};
use crate::front::lie::SymmetryKind;
use crate::ir::graph::{Graph, NodeId, Sym};
pub use crate::ir::group::Kind as LieKind;

/// A system on rotation groups compiled from text: its coordinates and names, and a
/// straight-line [`Program`] for each function of the runtime's `LieLagrangian` (and
/// `LieSymmetric` where a symmetry is declared). A point `q` stores scalars as themselves,
/// rotations and directions as 9 entries row by row (a direction as its frame `[e1 e2 n]`), poses
/// as their rotation's 9 entries then their position's 3; the
/// chart and the momenta have [`Self::chart_len`] entries. Step Jacobians are dense up to 16
/// chart coordinates and sparse above ([`Stepper::pattern`]), as the attribute emits them.
#[derive(Clone, Debug)]
pub struct LieSystem {
    /// The type name `#[reduced_lagrangian]` would emit.
    pub name: String,
    /// The coordinates, in the order of the point and the chart.
    pub coordinates: Vec<LieCoordinate>,
    /// The parameters, in declaration order (the time step included).
    pub parameters: Vec<String>,
    /// The index of the time step among [`Self::parameters`].
    pub step: usize,
    /// The controls (`controls(..)`), as indices into [`Self::parameters`].
    pub controls: Vec<usize>,
    /// Whether forces are declared (`force = ..`).
    pub forced: bool,
    /// Whether the Lagrangian is a continuous `L(q, v)` (discretized by its rule).
    pub continuous: bool,
    /// `L_d(q0, q1)`: one output, reading the points `Q0`, `Q1` (`P` entries each) and
    /// parameters.
    pub lagrangian: Program,
    /// The chart `φ_{q_k}(z)`: `P` outputs, reading `Base` = `q_k`, `Chart` = `z` and
    /// parameters.
    pub retract: Program,
    /// The step: the residual `R(z) = D1 L̃(0, z) + p_k`, its Jacobian and the momentum update,
    /// reading `Base` = `q_k`, `P` = `p_k`, `Chart` = `z` and parameters.
    pub stepper: Stepper,
    /// The step's partial derivatives for its sensitivities (dense systems only), leaves as
    /// [`Self::stepper`]'s: the blocks `∂R̃/∂w`, `∂R̃/∂δ` (`N × N`), `∂R̃/∂u` (`N × U`, `U` the
    /// number of controls), `∂O/∂w`, `∂O/∂δ`, `∂O/∂u`, each row by row, one after the other.
    pub partials: Option<Program>,
    /// The declared rotation symmetry (`symmetry(..)`).
    pub symmetry: Option<LieSymmetry>,
    /// Adaptive steps (`time(t), adapt = |q| g`).
    pub adaptive: Option<LieAdaptive>,
}

/// One coordinate of a [`LieSystem`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LieCoordinate {
    /// Its name in the text.
    pub name: String,
    /// What it is.
    pub kind: LieKind,
}

/// A declared rotation symmetry and its reduced step.
#[derive(Clone, Debug)]
pub struct LieSymmetry {
    /// Which rotations.
    pub kind: LieSymmetryKind,
    /// Whether the forces act on a coordinate the symmetry moves.
    pub forced: bool,
    /// For every rotation of one rotation coordinate, the step with that rotation replaced by
    /// the identity (leaves as [`LieSystem::stepper`]'s); `None` for the rotations about an
    /// axis, whose reduced step is the unreduced one with the momentum's group part set.
    pub reduced: Option<Stepper>,
}

/// Which rotations a symmetry is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LieSymmetryKind {
    /// Every rotation `R ↦ g R` of the rotation coordinate `coordinate`.
    Rotations {
        /// Its index in [`LieSystem::coordinates`].
        coordinate: usize,
    },
    /// Every rigid motion of the pose coordinate `coordinate`.
    RigidMotions {
        /// Its index in [`LieSystem::coordinates`].
        coordinate: usize,
    },
    /// The rotations about coordinate axis `axis` (0, 1, 2) of the listed coordinates together.
    Axis {
        /// 0, 1 or 2.
        axis: usize,
        /// Their indices in [`LieSystem::coordinates`].
        coordinates: Vec<usize>,
    },
}

/// Adaptive steps on rotation groups: the time coordinate, the monitor and the state on the
/// level set of the time-transformed system.
#[derive(Clone, Debug)]
pub struct LieAdaptive {
    /// The index of the time coordinate among [`LieSystem::coordinates`].
    pub time: usize,
    /// The monitor `g(q)`: one output, reading the point `Q0` and parameters.
    pub monitor: Program,
    /// The monitor and the momentum of the state at the configuration `Q0` (a point) with the
    /// physical velocity `Q1` (`velocity_len()` of a [`LieKind`] entries per coordinate): `1 + N`
    /// outputs.
    pub level: Program,
}

impl LieSystem {
    /// `P`: the length of a stored point.
    pub fn point_len(&self) -> usize {
        self.coordinates.iter().map(|c| c.kind.point_len()).sum()
    }

    /// `N`: the dimension of the configuration space, the length of a chart and a momentum.
    pub fn chart_len(&self) -> usize {
        self.coordinates.iter().map(|c| c.kind.chart_len()).sum()
    }

    /// The length of a velocity of a continuous Lagrangian.
    pub fn velocity_len(&self) -> usize {
        self.coordinates.iter().map(|c| c.kind.velocity_len()).sum()
    }
}

/// The phases of `#[reduced_lagrangian]` on a system on rotation groups, then the programs.
pub(super) fn compile_parts(args: TokenStream, func: &ItemFn) -> syn::Result<LieSystem> {
    let LieCompiled {
        spec,
        sig,
        mut graph,
        code,
    } = compile_phases(args, func)?;
    let g = &mut graph;
    let coordinates = spec
        .coords
        .iter()
        .map(|c| LieCoordinate {
            name: c.name.to_string(),
            kind: c.kind,
        })
        .collect();
    let lagrangian = between_points(g, &spec, code.lagrangian);
    let symmetry = spec.symmetry.as_ref().map(|s| LieSymmetry {
        kind: match s.kind {
            SymmetryKind::Rotations => LieSymmetryKind::Rotations {
                coordinate: s.coords[0].0,
            },
            SymmetryKind::RigidMotions => LieSymmetryKind::RigidMotions {
                coordinate: s.coords[0].0,
            },
            SymmetryKind::Axis(axis) => LieSymmetryKind::Axis {
                axis,
                coordinates: s.coords.iter().map(|&(i, _)| i).collect(),
            },
        },
        forced: code.symmetry_forced,
        reduced: code.reduced.as_ref().map(|st| stepper(g, st)),
    });
    let partials = code.partials.as_ref().map(|parts| {
        let roots: Vec<NodeId> = parts.blocks.iter().flatten().flatten().copied().collect();
        program(g, &roots)
    });
    let adaptive = code.adapt.as_ref().map(|a| LieAdaptive {
        time: a.coord,
        monitor: program(g, &[a.monitor]),
        level: program(
            g,
            &std::iter::once(a.monitor)
                .chain(a.momentum.iter().copied())
                .collect::<Vec<_>>(),
        ),
    });
    let step = sig.step_index();
    Ok(LieSystem {
        name: spec
            .attr
            .name
            .clone()
            .unwrap_or_else(|| crate::back::items::camel_case(&func.sig.ident))
            .to_string(),
        coordinates,
        parameters: sig.parameter_names(),
        step,
        controls: spec
            .attr
            .controls
            .iter()
            .filter_map(|u| sig.params.iter().position(|p| p == u))
            .collect(),
        forced: spec.attr.force.is_some(),
        continuous: sig.continuous,
        lagrangian,
        retract: program(g, &code.retract),
        stepper: stepper(g, &code.stepper),
        partials,
        symmetry,
        adaptive,
    })
}

/// `L_d` over the two points alone: each relative rotation `Rel` it reads (`R0ᵀ R1`, which the
/// step substitutes with its own `cay(ξ)ᵀ cay(z)`) formed from the stored matrices.
fn between_points(g: &mut Graph, spec: &crate::ir::lie::LieSpec, l: NodeId) -> Program {
    let mut rel: Vec<Option<NodeId>> = vec![None; spec.p()];
    for (p, _) in spec.rotations() {
        for r in 0..3 {
            for col in 0..3 {
                let mut sum = None;
                for k in 0..3 {
                    let a = g.var(Sym::Q0(p + 3 * k + r));
                    let b = g.var(Sym::Q1(p + 3 * k + col));
                    let t = g.mul(a, b);
                    sum = Some(sum.map_or(t, |s| g.add(s, t)));
                }
                rel[p + 3 * r + col] = sum;
            }
        }
    }
    let l = g.substitute(l, &mut |g, sym| match sym {
        Sym::Rel(i) => rel[i].expect("Rel reads a rotation coordinate"),
        other => g.var(other),
    });
    program(g, &[l])
}
