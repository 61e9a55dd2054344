//! The run-time front end: a system given as text — the same attribute and function a Rust
//! program writes — through the same phases as `#[reduced_lagrangian]` (the attribute and
//! signature, the lowering, the invariance check, the paper's constructions), ending in
//! straight-line [`Program`]s instead of Rust tokens. A mistake gets the message the attribute
//! gives, with its line and column in the text where the attribute has a span.
//!
//! ```
//! let system = dirac_compiler::text::compile(
//!     "#[reduced_lagrangian(shape(r), group(theta))]
//!      fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
//!          let (dr, dth) = (q1.r - q0.r, q1.theta - q0.theta);
//!          let r = 0.5 * (q0.r + q1.r);
//!          0.5 / h * (dr * dr + r * r * dth * dth) + h / r
//!      }",
//! )?;
//! assert_eq!((system.shape.len(), system.group.len()), (1, 1));
//! assert_eq!(system.parameters, ["h"]);
//! # Ok::<(), dirac_compiler::text::Error>(())
//! ```

use std::fmt;

use proc_macro2::{Span, TokenStream};
use syn::{Attribute, ItemFn};

use crate::back::backend::{Csc, DENSE_MAX};
use crate::back::program::{program, Program};
use crate::expand::{compile_system, parse, Parsed};
use crate::ir::compile::{Compiled, SideCode};
use crate::ir::constraint::ConstrainedCode;
use crate::ir::graph::Graph;
use crate::ir::reduce::Stepper as StepperCode;

mod depth;
mod element;
mod flat;
mod lie;

pub use crate::front::attr::{DomainBound, DomainRelation};
pub use depth::{MAX_LEVELS, MAX_NESTING};
pub use element::{
    ConstraintFamily, ElementConstraints, ElementCoordinate, ElementFamily, ElementSystem,
    IndexExpr, Length, Stencil,
};
pub use lie::{LieAdaptive, LieCoordinate, LieKind, LieSymmetry, LieSymmetryKind, LieSystem};

/// The attribute a system given as text carries.
const ATTRIBUTE: &str = "reduced_lagrangian";

/// A system compiled from text: its names, and a straight-line [`Program`] for each function
/// the runtime's traits for systems on vector spaces need (`DiscreteLagrangian`, `Reduced` for
/// both sides, `Unreduced`). Step Jacobians are dense up to 16 coordinates and sparse above
/// ([`Stepper::pattern`]), as the attribute emits them.
#[derive(Clone, Debug)]
pub struct System {
    /// The type name `#[reduced_lagrangian]` would emit (`name = ..`, or the function's name in
    /// CamelCase).
    pub name: String,
    /// The shape coordinates `x`, in the order of the configuration vector (array components as
    /// `x[i]`).
    pub shape: Vec<String>,
    /// The group coordinates `g`, which follow the shape coordinates.
    pub group: Vec<String>,
    /// The parameters, in declaration order (the time step included; last when a continuous
    /// Lagrangian does not take it).
    pub parameters: Vec<String>,
    /// The index of the time step among [`Self::parameters`].
    pub step: usize,
    /// The controls (`controls(..)`), as indices into [`Self::parameters`].
    pub controls: Vec<usize>,
    /// Whether forces are declared (`force = ..`).
    pub forced: bool,
    /// `L_d(q0, q1)`: one output, reading `Q0`, `Q1` and parameters.
    pub lagrangian: Program,
    /// The connection matrix `B`, `K × S` row by row, reading parameters only.
    pub connection: Program,
    /// For a symmetry declared on the user's coordinates (`coordinates(..), translate(..)`): each
    /// component of the user's configuration vector in the adapted coordinates `q` the system's
    /// vectors are in (§2.2.1, the runtime's `AdaptedCoordinates`); `None` when the system's
    /// coordinates are the user's (`shape(..), group(..)`).
    pub adapted: Option<Vec<UserComponent>>,
    /// The reduced (+) equations, eq. (4.6).
    pub plus: Side,
    /// The reduced (−) equations, eq. (4.8) with the signs of Definition 2.8.
    pub minus: Side,
    /// The unreduced equations (Definitions 2.7/2.8): leaves `Q0` = `q_k`, `Q1` = the unknown
    /// `z`, `P` = `p_k`.
    pub unreduced: Stepper,
    /// The unreduced step's partial derivatives for its sensitivities, when forces or controls
    /// are declared ([`Side::partials`]' blocks, with `y = q_k`, `z = q_{k+1}`, `o = p_{k+1}`;
    /// leaves as [`Self::unreduced`]'s).
    pub unreduced_partials: Option<Program>,
    /// `(D11, D12, D22)` of `L_d`, each `N × N` row by row, one after the other, reading `Q0`,
    /// `Q1` and parameters: the step-map Jacobian of a system of at most 16 coordinates without
    /// forces (the runtime's `LagrangianHessian`).
    pub hessian: Option<Program>,
    /// For a continuous Lagrangian `L(q, v)`: the Legendre map and the energy.
    pub continuous: Option<Continuous>,
    /// For a system with constraints (`constraints = |q| [..]` or `nonholonomic = |q, v| [..]`):
    /// the constrained steps of each form.
    pub constrained: Option<Constrained>,
    /// For adaptive steps (`time(t), adapt = |q| g`): the time coordinate and the monitor. The
    /// other programs are those of the time-transformed Lagrangian `L₂`, in fictitious time.
    pub adaptive: Option<Adaptive>,
    /// The declared domain (`domain(r > 0.0, ..)`): bounds on coordinates of `q = (x, g)` that
    /// the integrators check after every step, as the attribute's `System::DOMAIN`.
    /// Empty: no domain.
    pub domain: Vec<DomainBound>,
}

/// Adaptive steps: the Lagrangian is replaced by its regularized Poincaré time transformation
/// `L₂ = t' L(q, q'/t') + (t' − g)²/(2g)`, whose step parameter is a fictitious step `ε` and
/// whose steps cover `Δt ≈ ε g(x)` of physical time (the runtime's `adaptive` module).
#[derive(Clone, Debug)]
pub struct Adaptive {
    /// The index of the time coordinate `t` among the group coordinates.
    pub time: usize,
    /// The monitor `g(x) > 0`: one output, reading the shape as `Q0` (`S` entries) and
    /// parameters.
    pub monitor: Program,
}

/// The constraints of a system and its constrained steps (RATTLE form: a position step on
/// `z = (q_{k+1}, λ_k)`, then a projection on `y = (v_{k+1}, ν_{k+1})`; the runtime's
/// `Constrained` trait), for each form of the step: unreduced on `(q, p)`, reduced on each side
/// on `(x, w, μ, g)`. Both solves of a form have `Z = N + M` unknowns; their Jacobians are dense
/// up to 16 unknowns and sparse above ([`Stepper::pattern`]).
#[derive(Clone, Debug)]
pub struct Constrained {
    /// The number of constraints `M`.
    pub m: usize,
    /// Whether they are holonomic, `φ(q) = 0`, or nonholonomic, `A(q) v = 0`.
    pub holonomic: bool,
    /// `φ(q)`: `M` outputs reading `Q0` and parameters (none for nonholonomic constraints).
    pub constraint: Program,
    /// The unreduced steps. Position step: leaves `Q0` = `q_k`, `P` = `p_k`, `Q1` and `Lambda`
    /// = the unknowns `z = (q_{k+1}, λ_k)`; its momentum update is `p̃ = D2 L_d + f_d^+` (`N`
    /// outputs). Projection: `Q0` = `q_{k+1}`, `P` = `p̃`, `Q1` and `Lambda` = `y = (v, ν)`;
    /// its update is the projected `p_{k+1}`.
    pub unreduced: ConstrainedSteps,
    /// The reduced (+) steps. Position step: leaves `X0` = `x_k`, `W` = `w_k`, `Mu` = `μ_k`,
    /// `X1`, `U` and `Lambda` = `z = (x_{k+1}, u, λ_k)`; its update is `w̃_{k+1}` (`S` outputs).
    /// Projection: `Q0` (shape entries only) = `x_{k+1}`, `W` = `w̃_{k+1}`, `Mu` = `μ_{k+1}`,
    /// `Q1` and `Lambda` = `y`; its update is `(w_{k+1}, μ_{k+1})`.
    pub plus: ConstrainedSteps,
    /// The reduced (−) steps, leaves as for [`Self::plus`].
    pub minus: ConstrainedSteps,
}

/// The two solves of one form of a constrained step.
#[derive(Clone, Debug)]
pub struct ConstrainedSteps {
    /// The position step.
    pub position: Stepper,
    /// `μ_{k+1} − μ_k` of a reduced position step (leaves as the step's): the forces' group
    /// impulse minus the group component of the constraint impulse; `None` when both vanish
    /// (then `μ` is copied) and for the unreduced step.
    pub impulse: Option<Program>,
    /// The projection.
    pub projection: Stepper,
}

/// One side of the reduced equations.
#[derive(Clone, Debug)]
pub struct Side {
    /// The reduced Lagrangian `l_{d±}(x0, x1, u)` (eqs. (4.5), (4.7)): leaves `X0`, `X1`, `U`.
    pub lagrangian: Program,
    /// The step: leaves `X0` = `x_k`, `X1` and `U` = the unknown `z = (x_{k+1}, u)`, `W` = `w_k`,
    /// `Mu` = `μ_k`.
    pub stepper: Stepper,
    /// The group impulse `f_{d,g}^− + f_{d,g}^+` of the step (same leaves), when a force has a
    /// group component.
    pub impulse: Option<Program>,
    /// The step with its group unknowns solved in closed form, when they enter affinely.
    pub eliminated: Option<Eliminated>,
    /// The step's partial derivatives for its sensitivities, when forces or controls are
    /// declared (leaves as [`Self::stepper`]'s): the blocks `∂R/∂y`, `∂R/∂u`, `∂o/∂y`, `∂o/∂z`,
    /// `∂o/∂u` of the runtime's `StepPartials` (`y = x_k`, `z` the unknowns, `o` the updates
    /// `(w_{k+1}, Δμ)`, `u` the controls), each row by row, one after the other.
    pub partials: Option<Program>,
}

/// Momentum-level elimination: Newton on the shape unknowns alone, the group unknowns in closed
/// form. Leaves as for [`Side::stepper`], with `X1` = `x_{k+1}` and no `U`.
#[derive(Clone, Debug)]
pub struct Eliminated {
    /// The shape residual `R_x(x_{k+1}, u(x_{k+1}))` and its `S × S` Jacobian (column by
    /// column): `S + S²` outputs.
    pub residual_jacobian: Program,
    /// The shape residual alone: `S` outputs.
    pub residual: Program,
    /// The group unknowns `u(x_{k+1})`: `K` outputs.
    pub group: Program,
    /// The block `A = ∂R_g/∂u` the closed form inverts, `K × K` column by column.
    pub block: Program,
    /// The compiler's verdict: whether this path is the better default (no more code than the
    /// general one).
    pub pays: bool,
}

/// The straight-line functions of a step with `n` unknowns and `m` momenta.
#[derive(Clone, Debug)]
pub struct Stepper {
    /// The residual `R(z)`: `n` outputs.
    pub residual: Program,
    /// `R(z)` and `∂R/∂z` from one straight line: `n` outputs, then the `n × n` Jacobian column
    /// by column (nalgebra's order) — or, for a system of more than 16 coordinates, the values of
    /// its structural nonzeros in the order of [`Self::pattern`].
    pub residual_jacobian: Program,
    /// The momentum update: `m` outputs.
    pub momentum: Program,
    /// The residual and the momentum update from one straight line: `n + m` outputs.
    pub residual_momentum: Program,
    /// For a system of more than 16 coordinates (the attribute's sparse backend), the
    /// structurally nonzero entries of `∂R/∂z` in compressed sparse columns; `None` for a dense
    /// Jacobian.
    pub pattern: Option<Pattern>,
}

/// The structurally nonzero entries of an `n × n` Jacobian, in compressed sparse columns:
/// column `j` holds rows `row_idx[col_ptr[j]..col_ptr[j + 1]]`, increasing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    /// Column starts, `n + 1` of them.
    pub col_ptr: Vec<usize>,
    /// The row of each entry.
    pub row_idx: Vec<usize>,
}

/// A component of the user's configuration vector in the adapted coordinates `q`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UserComponent {
    /// `q[i]`: a coordinate no declared translation moves, or a translation's group
    /// coordinate `g = a[0]`.
    Var(usize),
    /// `q[g] + q[r]`: a component `c = g + r_c` moved by the translation whose group coordinate
    /// is `q[g]`, its shape coordinate `r_c = c − a[0]` at `q[r]`.
    Sum(usize, usize),
}

/// The Legendre map and energy of a continuous Lagrangian, reading `Q0` = `q`, `Q1` = `v` and
/// parameters.
#[derive(Clone, Debug)]
pub struct Continuous {
    /// The quadrature rule that forms `L_d` from `L` ("midpoint", "trapezoid", "left" or
    /// "right").
    pub rule: String,
    /// `L(q, v)`: one output.
    pub lagrangian: Program,
    /// `∂L/∂v`: one output per coordinate.
    pub legendre: Program,
    /// `∂L/∂v` and its Jacobian `∂²L/∂v²`, as a step's residual and Jacobian
    /// ([`Stepper::residual_jacobian`], dense up to 16 coordinates and sparse above, with its
    /// [`Stepper::pattern`]); its other programs are the Legendre map alone.
    pub legendre_jacobian: Stepper,
    /// `⟨∂L/∂v, v⟩ − L`: one output.
    pub energy: Program,
    /// What a Gauss–Legendre step evaluates at a stage, for a system on the dense backend (at
    /// most 16 coordinates) without constraints; `None` otherwise.
    pub stage: Option<StagePrograms>,
}

/// The stage derivatives of a continuous Lagrangian (the attribute's `StageDerivatives`), over
/// `Q0` = `q`, `Q1` = `v` and the parameters.
#[derive(Clone, Debug)]
pub struct StagePrograms {
    /// `f = ∂L/∂q + F(q, v)` then `p = ∂L/∂v`: `2N` outputs.
    pub values: Program,
    /// `f`, `p`, then `∂f/∂q`, `∂f/∂v`, `∂p/∂q` and `∂p/∂v`, each `N × N` column by column:
    /// `2N + 4N²` outputs.
    pub jacobian: Program,
}

/// One mistake in the text: the attribute's message and where it points.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// What was found and what is accepted.
    pub message: String,
    /// The line of the offending token, from 1.
    pub line: usize,
    /// Its column, from 1, in characters.
    pub column: usize,
}

/// Every mistake of a compilation, in the order the compiler found them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// The mistakes.
    pub diagnostics: Vec<Diagnostic>,
    /// The text, for the source lines in [`fmt::Display`].
    source: String,
}

impl Error {
    /// The errors of `error`; one without a position in the text (the attribute's own
    /// call-site errors) points at the attribute, where rustc shows it.
    fn from_syn(error: syn::Error, source: &str, attribute: Option<Span>) -> Error {
        let at = |span: Span| {
            let start = span.start();
            (start.line, start.column + 1)
        };
        let fallback = attribute.map_or((1, 1), at);
        let call_site = Span::call_site();
        let nowhere =
            |span: Span| span.start() == call_site.start() && span.end() == call_site.end();
        let diagnostics = error
            .into_iter()
            .map(|e| {
                let (line, column) = if nowhere(e.span()) {
                    fallback
                } else {
                    at(e.span())
                };
                Diagnostic {
                    message: e.to_string(),
                    line,
                    column,
                }
            })
            .collect();
        Error {
            diagnostics,
            source: source.to_owned(),
        }
    }
}

impl fmt::Display for Error {
    /// As rustc shows them: the message, the line and column, the source line and a caret.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.diagnostics.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            writeln!(f, "error: {}", d.message)?;
            write!(f, " --> {}:{}", d.line, d.column)?;
            if let Some(text) = self.source.lines().nth(d.line.wrapping_sub(1)) {
                let pad: String = text
                    .chars()
                    .take(d.column - 1)
                    .map(|c| if c == '\t' { '\t' } else { ' ' })
                    .collect();
                write!(f, "\n  | {text}\n  | {pad}^")?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for Error {}

/// Compiles a system given as text: a function carrying `#[reduced_lagrangian(..)]`, alone or
/// among other items (a whole Rust file is accepted, as long as one function carries the
/// attribute). The attribute's keys, the signature and the body are those of the compiled-in
/// attribute for a system on vector spaces, holonomic and nonholonomic constraints and adaptive
/// steps included. A system on rotation groups compiles with [`compile_lie`], an element-wise
/// system with [`compile_element`] (or either with [`compile_any`]).
pub fn compile(source: &str) -> Result<System, Error> {
    compile_with(source, |args, func| {
        if crate::front::lie::is_lie(&args) {
            return Err(syn::Error::new_spanned(
                &args,
                "a system on rotation groups (`rotation(..)`, `direction(..)`) compiles with \
                 `compile_lie` (or `compile_any`), into its own kind of system",
            ));
        }
        compile_parts(args, func)
    })
}

/// The element view of a system on vector spaces given as text (see [`compile`] for the text):
/// its `L_d` as one element reading every coordinate, each group coordinate a translation, each
/// holonomic constraint row a constraint family — what the run-time-sized element integrators
/// run at any number of coordinates, with the trajectory of the reduced and unreduced
/// integrators (see the module `flat` of this front end: Definitions 2.7/2.8, eqs. (4.6),
/// (4.8)). Adaptive steps, a domain and nonholonomic constraints are refused.
///
/// ```
/// let view = dirac_compiler::text::compile_flat_elements(
///     "#[reduced_lagrangian(shape(r), group(theta))]
///      fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
///          let (dr, dth) = (q1.r - q0.r, q1.theta - q0.theta);
///          let r = 0.5 * (q0.r + q1.r);
///          0.5 / h * (dr * dr + r * r * dth * dth) + h / r
///      }",
/// )?;
/// assert_eq!(view.coordinates.len(), 2);
/// assert_eq!(view.families[0].stencil.slots.len(), 2); // one element reading r and theta
/// assert_eq!(view.translations, [vec![1]]); // theta
/// # Ok::<(), dirac_compiler::text::Error>(())
/// ```
pub fn compile_flat_elements(source: &str) -> Result<ElementSystem, Error> {
    compile_with(source, flat::compile_parts)
}

/// Compiles a system on rotation groups given as text: a function carrying
/// `#[reduced_lagrangian(..)]` with `rotation(..)` or `direction(..)` coordinates (see
/// [`compile`] for the rest of the text). Its attribute, signature and body are those of the
/// compiled-in attribute: `shape(..)`, `group(..)`, `symmetry(..)`, a continuous Lagrangian with
/// its `rule`, forces, controls and adaptive steps.
///
/// ```
/// let system = dirac_compiler::text::compile_lie(
///     "#[reduced_lagrangian(rotation(R), symmetry(R))]
///      fn rigid_body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
///          let f = q0.R.transpose() * q1.R;
///          let jd = Matrix3::from_diagonal(&Vector3::new(j1, j2, j3));
///          let jd = 0.5 * jd.trace() * Matrix3::identity() - jd;
///          ((Matrix3::identity() - f) * jd).trace() / h
///      }",
/// )?;
/// assert_eq!((system.point_len(), system.chart_len()), (9, 3));
/// assert!(system.symmetry.as_ref().is_some_and(|s| s.reduced.is_some()));
/// # Ok::<(), dirac_compiler::text::Error>(())
/// ```
pub fn compile_lie(source: &str) -> Result<LieSystem, Error> {
    compile_with(source, |args, func| {
        if !crate::front::lie::is_lie(&args) {
            return Err(syn::Error::new_spanned(
                &args,
                "a system on vector spaces (no `rotation(..)` or `direction(..)` coordinate) \
                 compiles with `compile` (or `compile_any`)",
            ));
        }
        lie::compile_parts(args, func)
    })
}

/// A system given as text, of any kind.
#[derive(Clone, Debug)]
pub enum AnySystem {
    /// A system on vector spaces ([`compile`]).
    Flat(Box<System>),
    /// A system on rotation groups ([`compile_lie`]).
    Lie(Box<LieSystem>),
    /// An element-wise system sized at run time ([`compile_element`]).
    Element(Box<ElementSystem>),
}

/// Compiles an element-wise system given as text: a function carrying
/// `#[reduced_lagrangian(..)]` that takes `usize` sizes, its body a sum over elements (see
/// [`compile`] for the rest of the text). Its attribute, signature and body are those of the
/// compiled-in attribute: `coordinates(..)` sized by the sizes, `translate(..)`, a continuous
/// Lagrangian with its `rule`, forces, controls and holonomic constraints.
///
/// ```
/// let system = dirac_compiler::text::compile_element(
///     "#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
///      fn chain(q: Config, v: Velocity, k: f64, n: usize) -> f64 {
///          let mut l = 0.0;
///          for i in 0..n { l += 0.5 * v.x[i] * v.x[i]; }
///          for i in 0..n - 1 { l -= 0.5 * k * (q.x[i + 1] - q.x[i]) * (q.x[i + 1] - q.x[i]); }
///          l
///      }",
/// )?;
/// assert_eq!(system.sizes, ["n"]);
/// assert_eq!(system.families.len(), 2);
/// // The spring between x[i] and x[i + 1]: two slots, one loop.
/// assert_eq!(system.families[1].stencil.slots.len(), 2);
/// # Ok::<(), dirac_compiler::text::Error>(())
/// ```
pub fn compile_element(source: &str) -> Result<ElementSystem, Error> {
    compile_with(source, |args, func| {
        if crate::front::lie::is_lie(&args) || !crate::front::element::is_element_wise(func) {
            return Err(syn::Error::new_spanned(
                &func.sig.inputs,
                "not an element-wise system (no `usize` size among the arguments): it compiles \
                 with `compile` or `compile_lie` (or `compile_any`)",
            ));
        }
        element::compile_parts(args, func)
    })
}

/// Compiles a system given as text, whichever its kind: on rotation groups when the attribute
/// declares a `rotation(..)` or `direction(..)` coordinate ([`compile_lie`]), element-wise when
/// the function takes `usize` sizes ([`compile_element`]), on vector spaces otherwise
/// ([`compile`]). What a program that takes any system (a Python module, a command
/// line) calls.
pub fn compile_any(source: &str) -> Result<AnySystem, Error> {
    compile_with(source, |args, func| {
        if crate::front::lie::is_lie(&args) {
            lie::compile_parts(args, func).map(|s| AnySystem::Lie(Box::new(s)))
        } else if crate::front::element::is_element_wise(func) {
            element::compile_parts(args, func).map(|s| AnySystem::Element(Box::new(s)))
        } else {
            compile_parts(args, func).map(|s| AnySystem::Flat(Box::new(s)))
        }
    })
}

/// Finds the function with the attribute and runs `phases` on its arguments, as the attribute
/// runs, with the errors placed in the text. Everything from parsing to dropping the syntax tree
/// runs on a stack as deep as the text's nesting needs ([`depth`]): a text nested too deep for
/// that is refused with an error naming the limit, before it is parsed.
fn compile_with<T>(
    source: &str,
    phases: impl FnOnce(TokenStream, &ItemFn) -> syn::Result<T>,
) -> Result<T, Error> {
    let refused = |span: Span, message: String| {
        let start = span.start();
        Error {
            diagnostics: vec![Diagnostic {
                message,
                line: start.line.max(1),
                column: start.column + 1,
            }],
            source: source.to_owned(),
        }
    };
    // A text `proc_macro2` cannot tokenize gets `syn`'s message below, which parses it again.
    let stack = match without_shebang(source).parse::<TokenStream>() {
        Ok(tokens) => depth::stack_for(tokens).map_err(|e| refused(e.span, e.message))?,
        Err(_) => depth::MIN_STACK,
    };
    // The stack is mapped as the compilation starts; whether that much address space can be
    // had is asked first, so that a machine without it gives an error rather than an abort.
    if Vec::<u8>::new().try_reserve_exact(stack).is_err() {
        return Err(refused(
            Span::call_site(),
            format!(
                "not enough memory for the compiler's stack: the text's nesting needs {stack} \
                 bytes, which cannot be allocated"
            ),
        ));
    }
    stacker::maybe_grow(stack, stack, || {
        let (attribute, args, func) = find(source).map_err(|e| Error::from_syn(e, source, None))?;
        crate::ctxt::as_text(|| phases(args, &func))
            .map_err(|e| Error::from_syn(e, source, Some(attribute)))
    })
}

/// `source` without a first line `#!..` (not `#![..]`), which `syn::parse_file` skips too; the
/// line break stays, so lines and columns are those of `source`. A byte-order mark is skipped.
fn without_shebang(source: &str) -> &str {
    let source = source.strip_prefix('\u{feff}').unwrap_or(source);
    match source.strip_prefix("#!") {
        Some(rest) if !rest.trim_start().starts_with('[') => {
            source.find('\n').map_or("", |at| &source[at..])
        }
        _ => source,
    }
}

/// The attribute's span and arguments, and the function without the attribute.
fn find(source: &str) -> syn::Result<(Span, TokenStream, ItemFn)> {
    // A lone function is a file too.
    let file = syn::parse_file(source)?;
    let mut found: Option<(Span, TokenStream, ItemFn)> = None;
    for item in file.items {
        let syn::Item::Fn(mut func) = item else {
            continue;
        };
        let Some(at) = func.attrs.iter().position(is_attribute) else {
            continue;
        };
        let attr = func.attrs.remove(at);
        let span = attr.pound_token.span;
        if found.is_some() {
            return Err(syn::Error::new_spanned(
                &func.sig.ident,
                "a second function with `#[reduced_lagrangian]`: the text describes one system",
            ));
        }
        let args = match attr.meta {
            syn::Meta::List(list) => list.tokens,
            syn::Meta::Path(_) => TokenStream::new(),
            syn::Meta::NameValue(nv) => {
                return Err(syn::Error::new_spanned(
                    nv,
                    "write the attribute as `#[reduced_lagrangian(shape(..), group(..), ..)]`",
                ))
            }
        };
        found = Some((span, args, func));
    }
    found.ok_or_else(|| {
        syn::Error::new(
            Span::call_site(),
            "no function carries `#[reduced_lagrangian(..)]`: write \
             `#[reduced_lagrangian(shape(..), group(..))] fn name(q0: Config, q1: Config, h: f64, ..) -> f64 { .. }`",
        )
    })
}

fn is_attribute(attr: &Attribute) -> bool {
    attr.path()
        .segments
        .last()
        .is_some_and(|s| s.ident == ATTRIBUTE)
}

/// The phases of `#[reduced_lagrangian]` on a system on vector spaces, then the programs.
fn compile_parts(args: TokenStream, func: &ItemFn) -> syn::Result<System> {
    if crate::front::element::is_element_wise(func) {
        return Err(syn::Error::new_spanned(
            &func.sig.inputs,
            "an element-wise system (sizes as `usize` arguments) compiles with `compile_element` \
             (or `compile_any`), into its own kind of system",
        ));
    }
    let Parsed { spec, sig, parsed } = parse(args, func);
    parsed?;
    let (spec, sig) = spec.zip(sig).expect("a clean parse has both");
    let c = compile_system(&spec, &sig, func)?;
    let step = sig.step_index();
    let controls = spec
        .controls
        .iter()
        .filter_map(|u| sig.params.iter().position(|p| p == u))
        .collect();
    Ok(System {
        name: crate::back::items::type_name(&spec, func).to_string(),
        shape: spec.layout.shape.clone(),
        group: spec.layout.group.clone(),
        parameters: sig.parameter_names(),
        step,
        controls,
        forced: spec.force.is_some(),
        lagrangian: program(&c.graph, &[c.body]),
        connection: program(&c.graph, &c.b.concat()),
        adapted: spec.layout.declared.then(|| {
            spec.layout
                .components
                .iter()
                .map(|c| match *c {
                    crate::front::layout::Component::Var(a) => UserComponent::Var(a),
                    crate::front::layout::Component::Sum(g, r) => UserComponent::Sum(g, r),
                })
                .collect()
        }),
        plus: side(&c, &c.plus),
        minus: side(&c, &c.minus),
        unreduced: stepper(&c.graph, &c.unreduced),
        unreduced_partials: c.unreduced_partials.as_ref().map(|p| partials(&c.graph, p)),
        hessian: c.hessian.as_ref().map(|blocks| {
            let roots: Vec<_> = blocks.iter().flatten().flatten().copied().collect();
            program(&c.graph, &roots)
        }),
        continuous: c.continuous.as_ref().map(|parts| Continuous {
            rule: format!("{:?}", parts.rule).to_lowercase(),
            lagrangian: program(&c.graph, &[parts.lagrangian]),
            legendre: program(&c.graph, &parts.legendre),
            legendre_jacobian: stepper(
                &c.graph,
                &StepperCode {
                    residual: parts.legendre.clone(),
                    jacobian: parts.hessian.clone(),
                    momentum: parts.legendre.clone(),
                    impulse: Vec::new(),
                },
            ),
            energy: program(&c.graph, &[parts.energy]),
            stage: parts.stage.as_ref().map(|stage| {
                let values: Vec<_> = stage.force.iter().chain(&parts.legendre).copied().collect();
                let mut all = values.clone();
                for block in [
                    &stage.force_q,
                    &stage.force_v,
                    &stage.momentum_q,
                    &parts.hessian,
                ] {
                    all.extend(column_major(block));
                }
                StagePrograms {
                    values: program(&c.graph, &values),
                    jacobian: program(&c.graph, &all),
                }
            }),
        }),
        constrained: c.constrained.as_ref().map(|code| constrained(&c, code)),
        domain: spec.domain.clone(),
        adaptive: c.adapt.map(|(time, monitor, _)| Adaptive {
            time,
            monitor: program(&c.graph, &[monitor]),
        }),
    })
}

/// The constrained steps' programs (the attribute's `Constraints` and `Constrained` impls).
fn constrained(c: &Compiled, code: &ConstrainedCode) -> Constrained {
    let g = &c.graph;
    let steps = |(position, projection): (&StepperCode, &StepperCode)| ConstrainedSteps {
        position: stepper(g, position),
        impulse: (!position.impulse.is_empty()).then(|| program(g, &position.impulse)),
        projection: stepper(g, projection),
    };
    Constrained {
        m: code.m,
        holonomic: code.holonomic,
        constraint: program(g, &code.phi),
        unreduced: steps((&code.position, &code.projection)),
        plus: steps((&code.plus.0, &code.plus.1)),
        minus: steps((&code.minus.0, &code.minus.1)),
    }
}

fn side(c: &Compiled, side: &SideCode) -> Side {
    Side {
        lagrangian: program(&c.graph, &[side.lagrangian]),
        stepper: stepper(&c.graph, &side.stepper),
        impulse: (!side.stepper.impulse.is_empty())
            .then(|| program(&c.graph, &side.stepper.impulse)),
        eliminated: side.eliminated.as_ref().map(|e| Eliminated {
            residual_jacobian: program(
                &c.graph,
                &e.residual
                    .iter()
                    .copied()
                    .chain(column_major(&e.jacobian))
                    .collect::<Vec<_>>(),
            ),
            residual: program(&c.graph, &e.residual),
            group: program(&c.graph, &e.group),
            block: program(&c.graph, &column_major(&e.block).collect::<Vec<_>>()),
            pays: side.elimination_pays,
        }),
        partials: side.partials.as_ref().map(|p| partials(&c.graph, p)),
    }
}

/// The blocks of a step's partial derivatives, each row by row, one after the other.
fn partials(g: &Graph, p: &crate::ir::reduce::Partials) -> Program {
    let roots: Vec<_> = [&p.r_y, &p.r_u, &p.o_y, &p.o_z, &p.o_u]
        .into_iter()
        .flatten()
        .flatten()
        .copied()
        .collect();
    program(g, &roots)
}

/// A square matrix's entries column by column, as nalgebra stores them.
fn column_major(
    m: &[Vec<crate::ir::graph::NodeId>],
) -> impl Iterator<Item = crate::ir::graph::NodeId> + '_ {
    (0..m.len()).flat_map(move |col| m.iter().map(move |row| row[col]))
}

/// A stepper's programs, with the Jacobian dense or sparse by size as the attribute's backend
/// (`DENSE_MAX`).
fn stepper(g: &Graph, s: &StepperCode) -> Stepper {
    let mut with_jacobian = s.residual.clone();
    let pattern = if s.residual.len() > DENSE_MAX {
        let csc = Csc::of(g, &s.jacobian);
        with_jacobian.extend(csc.values);
        Some(Pattern {
            col_ptr: csc.col_ptr,
            row_idx: csc.row_idx,
        })
    } else {
        with_jacobian.extend(column_major(&s.jacobian));
        None
    };
    let with_momentum: Vec<_> = s.residual.iter().chain(&s.momentum).copied().collect();
    Stepper {
        residual: program(g, &s.residual),
        residual_jacobian: program(g, &with_jacobian),
        momentum: program(g, &s.momentum),
        residual_momentum: program(g, &with_momentum),
        pattern,
    }
}
