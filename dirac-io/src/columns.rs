//! What a state and a run are called in a file: the state's columns, named from the annotation
//! (`#[reduced_lagrangian(shape(..), group(..))]`, or `rotation(..)` and `direction(..)`), and
//! the run's description (time step,
//! parameters, Newton options) that goes into the file's key-value metadata.

use dirac::prelude::*;
use dirac::runtime::compose::Composition;
use dirac::runtime::constrained::Form;
use dirac::runtime::lie::{
    DynLieState, LieForm, LieIntegratorIn, LieModel, ReducedForm, ReducedLieStateOf,
    SymmetricLieModel, UnreducedForm,
};
use dirac::runtime::nalgebra::allocator::Allocator;
use dirac::runtime::nalgebra::{DVector, DefaultAllocator, Dim, Dyn};

/// A state whose components are written as `f64` columns, one per coordinate and momentum.
///
/// * [`ReducedState`]: `x_<shape>`, `w_<shape>`, `mu_<group>`, `g_<group>` (shape `x ∈ Σ`,
///   reduced momenta `w ∈ Σ*` and `μ ∈ g*` of eq. (3.6), group coordinate `g`);
/// * [`UnreducedState`]: `q_<coordinate>`, `p_<coordinate>` over the shape then the group
///   coordinates (`q = (x, g)`, `p = (p_x, p_g)`).
///
/// ```
/// use dirac::prelude::*;
/// use dirac_io::StateColumns;
/// let names = ReducedState::<2, 1>::column_names(&["r", "z"], &["theta"]);
/// assert_eq!(names, ["x_r", "x_z", "w_r", "w_z", "mu_theta", "g_theta"]);
/// ```
pub trait StateColumns: Clone + std::fmt::Debug + Send + Sync + 'static {
    /// The number of columns of every state of the type (`2 (S + K)` for a reduced state), or
    /// `None` for states sized at run time ([`ElementState`]: `2n`, from the system's sizes).
    const WIDTH: Option<usize>;
    /// The number of columns of this state: [`Self::WIDTH`] where the type fixes it.
    fn width(&self) -> usize;
    /// The column names, given the shape and group coordinate names of the annotation.
    fn column_names(shape: &[&str], group: &[&str]) -> Vec<String>;
    /// Writes the components into `out` (`out.len() == self.width()`), in the order of the
    /// names.
    fn write_to(&self, out: &mut [f64]);
    /// The state whose components are `values` (`values.len()` its width), named `columns` (as
    /// [`Self::column_names`] names them), the inverse of [`Self::write_to`], bit for bit. A
    /// state of fixed sizes reads the values alone; a state sized at run time whose values do
    /// not say how they split (a state on rotation groups: its point, then its momentum) reads
    /// the split from the names.
    fn read_from(columns: &[String], values: &[f64]) -> Self;
}

fn prefixed<'a>(prefix: &'a str, names: &'a [&'a str]) -> impl Iterator<Item = String> + 'a {
    names.iter().map(move |n| format!("{prefix}_{n}"))
}

impl<const S: usize, const K: usize> StateColumns for ReducedState<S, K> {
    const WIDTH: Option<usize> = Some(2 * (S + K));

    fn width(&self) -> usize {
        2 * (S + K)
    }

    fn column_names(shape: &[&str], group: &[&str]) -> Vec<String> {
        assert_eq!(
            (shape.len(), group.len()),
            (S, K),
            "names of another system"
        );
        prefixed("x", shape)
            .chain(prefixed("w", shape))
            .chain(prefixed("mu", group))
            .chain(prefixed("g", group))
            .collect()
    }

    fn write_to(&self, out: &mut [f64]) {
        let parts = [
            self.x.as_slice(),
            self.w.as_slice(),
            self.mu.as_slice(),
            self.g.as_slice(),
        ];
        let mut i = 0;
        for part in parts {
            out[i..i + part.len()].copy_from_slice(part);
            i += part.len();
        }
    }

    fn read_from(_: &[String], values: &[f64]) -> Self {
        let mut state = ReducedState::<S, K> {
            x: SVector::zeros(),
            w: SVector::zeros(),
            mu: SVector::zeros(),
            g: SVector::zeros(),
        };
        state.x.copy_from_slice(&values[..S]);
        state.w.copy_from_slice(&values[S..2 * S]);
        state.mu.copy_from_slice(&values[2 * S..2 * S + K]);
        state.g.copy_from_slice(&values[2 * S + K..2 * (S + K)]);
        state
    }
}

impl<const N: usize> StateColumns for UnreducedState<N> {
    const WIDTH: Option<usize> = Some(2 * N);

    fn width(&self) -> usize {
        2 * N
    }

    fn column_names(shape: &[&str], group: &[&str]) -> Vec<String> {
        assert_eq!(shape.len() + group.len(), N, "names of another system");
        let all: Vec<&str> = shape.iter().chain(group).copied().collect();
        prefixed("q", &all).chain(prefixed("p", &all)).collect()
    }

    fn write_to(&self, out: &mut [f64]) {
        out[..N].copy_from_slice(self.q.as_slice());
        out[N..2 * N].copy_from_slice(self.p.as_slice());
    }

    fn read_from(_: &[String], values: &[f64]) -> Self {
        let mut state = UnreducedState::<N> {
            q: SVector::zeros(),
            p: SVector::zeros(),
        };
        state.q.copy_from_slice(&values[..N]);
        state.p.copy_from_slice(&values[N..2 * N]);
        state
    }
}

/// States on rotation groups ([`LieState`]): the stored point then the momentum, named `q_<entry>`
/// and `p_<component>`. The names come from [`lie_names`]: a rotation `R` stores `q_R_00` …
/// `q_R_22` (row by row) and its discrete body momentum `p_R_x`, `p_R_y`, `p_R_z`; a direction `n`
/// stores its frame `[e1 e2 n]` row by row (`q_n_00` … `q_n_22`, so `n = (q_n_02, q_n_12, q_n_22)`)
/// and its momentum's components in the frame, `p_n_1`, `p_n_2`; a pose `X` stores its rotation
/// as a rotation's (`q_X_00` … `q_X_22`) then its position `q_X_x`, `q_X_y`, `q_X_z`, and its
/// body angular momentum `p_X_ax`, `p_X_ay`, `p_X_az` then its linear momentum `p_X_x`, `p_X_y`,
/// `p_X_z`; a scalar `x` stores `q_x` and `p_x`. Every entry is written, so a state reads back
/// bit for bit. Each coordinate's kind names its entries
/// ([`Group::point_suffixes`](dirac::runtime::lie::Group::point_suffixes)).
impl<const P: usize, const N: usize> StateColumns for LieState<P, N> {
    const WIDTH: Option<usize> = Some(P + N);

    fn width(&self) -> usize {
        P + N
    }

    /// `point` and `chart` are the names of the point's entries and of the momentum's
    /// components ([`lie_names`]).
    fn column_names(point: &[&str], chart: &[&str]) -> Vec<String> {
        assert_eq!(
            (point.len(), chart.len()),
            (P, N),
            "names of another system"
        );
        prefixed("q", point).chain(prefixed("p", chart)).collect()
    }

    fn write_to(&self, out: &mut [f64]) {
        out[..P].copy_from_slice(self.q.as_slice());
        out[P..P + N].copy_from_slice(self.p.as_slice());
    }

    fn read_from(_: &[String], values: &[f64]) -> Self {
        let mut state = LieState::<P, N> {
            q: SVector::zeros(),
            p: SVector::zeros(),
        };
        state.q.copy_from_slice(&values[..P]);
        state.p.copy_from_slice(&values[P..P + N]);
        state
    }
}

/// Reduced states on rotation groups ([`ReducedLieState`]): the columns of [`LieState`], then
/// the momentum of the symmetry `mu_x`, `mu_y`, `mu_z` (the spatial momentum `π` for every
/// rotation, `μ e` for the rotations about the axis `e`). Every entry is written, so a state reads
/// back bit for bit.
impl<const P: usize, const N: usize> StateColumns for ReducedLieState<P, N> {
    const WIDTH: Option<usize> = Some(P + N + 3);

    fn width(&self) -> usize {
        P + N + 3
    }

    fn column_names(point: &[&str], chart: &[&str]) -> Vec<String> {
        let mut names = LieState::<P, N>::column_names(point, chart);
        names.extend(["mu_x", "mu_y", "mu_z"].map(String::from));
        names
    }

    fn write_to(&self, out: &mut [f64]) {
        self.unreduced().write_to(&mut out[..P + N]);
        out[P + N..].copy_from_slice(self.mu.as_slice());
    }

    fn read_from(_: &[String], values: &[f64]) -> Self {
        let state = LieState::<P, N>::read_from(&[], &values[..P + N]);
        ReducedLieState {
            q: state.q,
            p: state.p,
            mu: Vector3::new(values[P + N], values[P + N + 1], values[P + N + 2]),
        }
    }
}

/// States on rotation groups sized at run time ([`DynLieState`]): the columns of [`LieState`],
/// `P + N` of them for the system's sizes; read back by their names (the point's entries are the
/// `q_` columns, the momentum's the `p_` columns), bit for bit.
impl StateColumns for DynLieState {
    const WIDTH: Option<usize> = None;

    fn width(&self) -> usize {
        self.q.len() + self.p.len()
    }

    fn column_names(point: &[&str], chart: &[&str]) -> Vec<String> {
        prefixed("q", point).chain(prefixed("p", chart)).collect()
    }

    fn write_to(&self, out: &mut [f64]) {
        let m = self.q.len();
        out[..m].copy_from_slice(self.q.as_slice());
        out[m..m + self.p.len()].copy_from_slice(self.p.as_slice());
    }

    fn read_from(columns: &[String], values: &[f64]) -> Self {
        let m = point_columns(columns).min(values.len());
        DynLieState {
            q: DVector::from_column_slice(&values[..m]),
            p: DVector::from_column_slice(&values[m..]),
        }
    }
}

/// The number of a state's columns that name its stored point (`q_`), which come first.
fn point_columns(columns: &[String]) -> usize {
    columns.iter().take_while(|c| c.starts_with("q_")).count()
}

/// Reduced states on rotation groups sized at run time: the columns of [`DynLieState`], then
/// `mu_x`, `mu_y`, `mu_z`.
impl StateColumns for ReducedLieStateOf<Dyn, Dyn> {
    const WIDTH: Option<usize> = None;

    fn width(&self) -> usize {
        self.q.len() + self.p.len() + 3
    }

    fn column_names(point: &[&str], chart: &[&str]) -> Vec<String> {
        let mut names = DynLieState::column_names(point, chart);
        names.extend(["mu_x", "mu_y", "mu_z"].map(String::from));
        names
    }

    fn write_to(&self, out: &mut [f64]) {
        let m = self.q.len() + self.p.len();
        self.unreduced().write_to(&mut out[..m]);
        out[m..m + 3].copy_from_slice(self.mu.as_slice());
    }

    fn read_from(columns: &[String], values: &[f64]) -> Self {
        let m = values.len().saturating_sub(3);
        let state = DynLieState::read_from(columns, &values[..m]);
        let mu = |i: usize| values.get(m + i).copied().unwrap_or(f64::NAN);
        ReducedLieStateOf {
            q: state.q,
            p: state.p,
            mu: Vector3::new(mu(0), mu(1), mu(2)),
        }
    }
}

/// States of element-wise systems sized at run time ([`ElementState`]): `q_<i>` then `p_<i>` for
/// every coordinate index `i` of the flattened configuration (`0 .. n`, as
/// [`ElementLagrangian::dim`] counts them), so the width is the system's, `2n`, known only when
/// it is built. Every entry is written, so a state reads back bit for bit.
impl StateColumns for ElementState {
    const WIDTH: Option<usize> = None;

    fn width(&self) -> usize {
        self.q.len() + self.p.len()
    }

    fn column_names(shape: &[&str], group: &[&str]) -> Vec<String> {
        let all: Vec<&str> = shape.iter().chain(group).copied().collect();
        prefixed("q", &all).chain(prefixed("p", &all)).collect()
    }

    fn write_to(&self, out: &mut [f64]) {
        let n = self.q.len();
        out[..n].copy_from_slice(self.q.as_slice());
        out[n..n + self.p.len()].copy_from_slice(self.p.as_slice());
    }

    fn read_from(_: &[String], values: &[f64]) -> Self {
        let n = values.len() / 2;
        ElementState::new(&values[..n], &values[n..])
    }
}

/// Adaptive steps: the metadata entry `dirac.physical_time` naming the column of the time
/// coordinate `name` (`g_<name>` of a reduced state, `q_<name>` otherwise) — the physical time
/// `t_k` (the run's clock, so the file's `t` column holds the same values).
fn physical_time(columns: &[String], name: &str) -> Option<(String, String)> {
    columns
        .iter()
        .find(|c| **c == format!("g_{name}") || **c == format!("q_{name}"))
        .map(|c| ("dirac.physical_time".to_owned(), c.clone()))
}

/// The names of a stored point's entries and of the momentum's components of a system on
/// rotation groups (see [`LieState`]'s columns), each coordinate's entries as its kind names
/// them.
///
/// ```
/// use dirac::runtime::lie::CoordinateKind;
///
/// let (point, chart) =
///     dirac_io::lie_names(&[("s", CoordinateKind::SCALAR), ("X", CoordinateKind::POSE)]);
/// assert_eq!(point.len(), 1 + 12);
/// assert_eq!(&point[..3], ["s", "X_00", "X_01"]);
/// assert_eq!(&point[10..], ["X_x", "X_y", "X_z"]);
/// assert_eq!(chart, ["s", "X_ax", "X_ay", "X_az", "X_x", "X_y", "X_z"]);
/// ```
pub fn lie_names(coordinates: &[(&str, CoordinateKind)]) -> (Vec<String>, Vec<String>) {
    let named = |name: &str, suffixes: &[&str]| -> Vec<String> {
        suffixes
            .iter()
            .map(|s| match *s {
                "" => name.to_owned(),
                s => format!("{name}_{s}"),
            })
            .collect()
    };
    let (mut point, mut chart) = (Vec::new(), Vec::new());
    for &(name, kind) in coordinates {
        point.extend(named(name, kind.group().point_suffixes()));
        chart.extend(named(name, kind.group().chart_suffixes()));
    }
    (point, chart)
}

/// The coordinates of a system on rotation groups, in the order of the point and the chart
/// ([`LieModel::coordinate`]: the constant `COORDINATES` of a compiled-in system).
fn lie_coordinates<L, P: Dim, N: Dim>(system: &L) -> Vec<(&str, CoordinateKind)>
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    (0..).map_while(|i| system.coordinate(i)).collect()
}

/// The parameters of any system by name, in declaration order ([`RunInfo::parameters`]).
fn parameters<L: System>(system: &L) -> Vec<(String, f64)> {
    system
        .parameter_names()
        .iter()
        .map(|p| (*p).to_owned())
        .zip(system.parameter_values())
        .collect()
}

/// A run as a file describes it: the state's column names, the time step, the parameters by
/// name and whatever else identifies the run (integrator, Newton options), written as the
/// Parquet file's key-value metadata (keys `dirac.*`, see the [crate documentation](crate)).
#[derive(Clone, Debug, PartialEq)]
pub struct RunInfo {
    /// The state's column names ([`StateColumns::column_names`]).
    pub columns: Vec<String>,
    /// The time step `h` of one step of the run (for a composition, the macro step): the
    /// `t` column is `step · h`.
    pub h: f64,
    /// The parameters, by name, in declaration order.
    pub parameters: Vec<(String, f64)>,
    /// Further key-value metadata, written as given (keys should start with `dirac.`).
    pub metadata: Vec<(String, String)>,
}

/// A key-value pair's value for a float: Rust's shortest representation that parses back to the
/// same bits.
pub(crate) fn float_text(v: f64) -> String {
    format!("{v:?}")
}

impl RunInfo {
    /// The description of `system` integrated with states `St`: column names from
    /// [`DiscreteLagrangian::shape_names`] and [`DiscreteLagrangian::group_names`] (the
    /// constants `SHAPE` and `GROUP` of a compiled-in system), the parameters from
    /// [`System::parameter_names`] and [`System::parameter_values`], the
    /// time step from the system.
    pub fn of_system<St, L, const S: usize, const K: usize, const N: usize>(system: &L) -> Self
    where
        St: StateColumns,
        L: DiscreteLagrangian<S, K, N>,
    {
        let parameters = parameters(system);
        let (shape, group) = (system.shape_names(), system.group_names());
        let columns = St::column_names(&shape, &group);
        let mut metadata = vec![
            ("dirac.shape".into(), shape.join(",")),
            ("dirac.group".into(), group.join(",")),
        ];
        metadata.extend(
            system
                .time_index()
                .and_then(|j| group.get(j))
                .and_then(|name| physical_time(&columns, name)),
        );
        RunInfo {
            columns,
            h: system.time_step(),
            parameters,
            metadata,
        }
    }

    /// Adds the Newton options as `dirac.newton.abs_tol`, `.rel_tol`, `.max_iterations` and
    /// `.min_rcond`.
    #[must_use]
    pub fn with_newton(mut self, options: &NewtonOptions) -> Self {
        let entries = [
            ("abs_tol", float_text(options.abs_tol)),
            ("rel_tol", float_text(options.rel_tol)),
            ("max_iterations", options.max_iterations.to_string()),
            ("min_rcond", float_text(options.min_rcond)),
        ];
        for (key, value) in entries {
            self.metadata.push((format!("dirac.newton.{key}"), value));
        }
        self
    }

    /// The columns an ensemble table for this run may have
    /// ([`Table::validate_for`](crate::table::Table::validate_for)): the state's columns
    /// ([`Self::columns`]), the parameters ([`Self::parameters`]), `h` (the time step), and the
    /// Newton options of [`Self::with_newton`] (`abs_tol`, `rel_tol`, `max_iterations`,
    /// `min_rcond`) when the description has them: every input of the run a member closure
    /// can take from a row.
    pub fn table_columns(&self) -> Vec<String> {
        let mut names = self.columns.clone();
        let mut add = |name: &str| {
            if !names.iter().any(|n| n == name) {
                names.push(name.to_owned());
            }
        };
        for (name, _) in &self.parameters {
            add(name);
        }
        add("h");
        for (key, _) in &self.metadata {
            if let Some(option) = key.strip_prefix("dirac.newton.") {
                add(option);
            }
        }
        names
    }

    /// Adds one key-value pair.
    #[must_use]
    pub fn with(mut self, key: impl Into<String>, value: impl Into<String>) -> Self {
        self.metadata.push((key.into(), value.into()));
        self
    }

    /// All key-value metadata this description writes: `dirac.h`, `dirac.parameters` (the names,
    /// comma-separated), `dirac.parameter.<name>` for each, then [`Self::metadata`].
    pub fn key_values(&self) -> Vec<(String, String)> {
        let mut kv = vec![
            ("dirac.h".to_owned(), float_text(self.h)),
            (
                "dirac.parameters".to_owned(),
                self.parameters
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(","),
            ),
        ];
        for (name, value) in &self.parameters {
            kv.push((format!("dirac.parameter.{name}"), float_text(*value)));
        }
        kv.extend(self.metadata.iter().cloned());
        kv
    }
}

/// An integrator that can describe its runs ([`RunInfo`]): the reduced, unreduced and
/// constrained integrators and their compositions, the integrators on rotation groups (reduced or
/// not), and the element-wise ones sized at run time. (An atlas changes coordinates between
/// charts; describe its runs with [`RunInfo::of_system`] of the chart whose names the columns
/// should carry.)
pub trait Describe: Stepper<State: StateColumns> {
    /// The description of a run of `self`.
    fn describe(&self) -> RunInfo;
}

impl<L, D, const S: usize, const K: usize, const N: usize> Describe
    for ReducedIntegrator<L, D, S, K, N>
where
    Self: Stepper<State = ReducedState<S, K>>,
    D: Side,
    L: Reduced<D, S, K, N>,
{
    fn describe(&self) -> RunInfo {
        let side = match self.variant() {
            Variant::Plus => "reduced (+), eq. (4.6)",
            Variant::Minus => "reduced (-), eq. (4.8)",
        };
        RunInfo::of_system::<ReducedState<S, K>, L, S, K, N>(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", side)
    }
}

impl<L, F, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize> Describe
    for ConstrainedStepper<L, F, S, K, N, M, Z>
where
    Self: Stepper<State = F::State>,
    F: Form<S, K, N>,
    F::State: StateColumns,
    L: Constrained<F, S, K, N, M, Z>,
{
    fn describe(&self) -> RunInfo {
        RunInfo::of_system::<F::State, L, S, K, N>(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", F::EQUATIONS)
            .with("dirac.constraints", M.to_string())
    }
}

impl<L, const S: usize, const K: usize, const N: usize> Describe for UnreducedIntegrator<L, S, K, N>
where
    Self: Stepper<State = UnreducedState<N>>,
    L: Unreduced<S, K, N>,
{
    fn describe(&self) -> RunInfo {
        RunInfo::of_system::<UnreducedState<N>, L, S, K, N>(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", "unreduced (Definitions 2.7/2.8)")
    }
}

/// The Gauss–Legendre integrators, unreduced and reduced: the states of the second-order
/// integrators of the same form, the stage count in `dirac.gauss.stages`.
impl<L, const S: usize, const K: usize, const N: usize> Describe for GaussIntegrator<L, S, K, N>
where
    Self: Stepper<State = UnreducedState<N>>,
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    fn describe(&self) -> RunInfo {
        RunInfo::of_system::<UnreducedState<N>, L, S, K, N>(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", "Gauss–Legendre, unreduced")
            .with("dirac.gauss.stages", self.rule().stages().to_string())
    }
}

impl<L, D, const S: usize, const K: usize, const N: usize> Describe
    for ReducedGaussIntegrator<L, D, S, K, N>
where
    Self: Stepper<State = ReducedState<S, K>>,
    D: Side,
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    fn describe(&self) -> RunInfo {
        let side = match self.variant() {
            Variant::Plus => "Gauss–Legendre, reduced (+), eq. (4.6)",
            Variant::Minus => "Gauss–Legendre, reduced (-), eq. (4.8)",
        };
        RunInfo::of_system::<ReducedState<S, K>, L, S, K, N>(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", side)
            .with("dirac.gauss.stages", self.rule().stages().to_string())
    }
}

/// The integrators on rotation groups, in either form: the columns of the form's states
/// ([`LieState`]'s, then `mu_x`, `mu_y`, `mu_z` for [`ReducedLieState`]), each coordinate with
/// the attribute keyword of its kind (`dirac.coordinates`: `r:rotation`, `x:pose`), the physical
/// time of adaptive steps, the Newton options, then the form's integrator and side, and the
/// reduced form's symmetry.
impl<L, P: Dim, N: Dim, F> Describe for LieIntegratorIn<L, P, N, F>
where
    L: LieModel<P, N>,
    F: LieForm<L, P, N, State: StateColumns> + FormInfo<L, P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    fn describe(&self) -> RunInfo {
        let system = self.system();
        let coordinates = lie_coordinates(system);
        let (point, chart) = lie_names(&coordinates);
        let point: Vec<&str> = point.iter().map(String::as_str).collect();
        let chart: Vec<&str> = chart.iter().map(String::as_str).collect();
        let kinds: Vec<String> = coordinates
            .iter()
            .map(|(name, kind)| format!("{name}:{}", kind.name()))
            .collect();
        let columns = F::State::column_names(&point, &chart);
        let mut metadata = vec![("dirac.coordinates".into(), kinds.join(","))];
        metadata.extend(
            system
                .time_index()
                .and_then(|i| coordinates.get(i))
                .and_then(|&(name, _)| physical_time(&columns, name)),
        );
        let info = RunInfo {
            columns,
            h: system.time_step(),
            parameters: parameters(system),
            metadata,
        };
        F::finish(system, self.variant(), info.with_newton(self.options()))
    }
}

/// What each form of the integrator on rotation groups adds to its description: the
/// integrator's name and side (`variant`), and the reduced form's symmetry.
trait FormInfo<L, P, N> {
    fn finish(system: &L, variant: Variant, info: RunInfo) -> RunInfo;
}

impl<L, P, N> FormInfo<L, P, N> for UnreducedForm {
    fn finish(_: &L, variant: Variant, info: RunInfo) -> RunInfo {
        info.with(
            "dirac.integrator",
            "Lie group variational (Cayley retraction)",
        )
        .with("dirac.variant", format!("{variant:?}"))
    }
}

impl<L: SymmetricLieModel<P, N>, P: Dim, N: Dim> FormInfo<L, P, N> for ReducedForm
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    fn finish(system: &L, variant: Variant, info: RunInfo) -> RunInfo {
        let symmetry = format!("{:?}", system.symmetry());
        info.with("dirac.variant", format!("{variant:?}"))
            .with(
                "dirac.integrator",
                "reduced Lie group variational (Cayley retraction)",
            )
            .with("dirac.symmetry", symmetry)
    }
}

impl<I> Describe for Composition<I>
where
    I: Describe,
    Self: Stepper<State = I::State>,
{
    fn describe(&self) -> RunInfo {
        let mut info = self.base().describe();
        info.h = self.time_step();
        info.with(
            "dirac.composition.stages",
            self.method().stages().to_string(),
        )
    }
}

/// The description of an element-wise system sized at run time: one column per coordinate index
/// ([`ElementState`]'s columns: the coordinate arrays, named in `dirac.coordinates`, flattened
/// in their order) — or, for a system without sizes whose every coordinate is a scalar (the
/// element view of a system on vector spaces), one per coordinate by its name, as an unreduced
/// run names them — the sizes as `dirac.sizes` (`n=200`, in the order of
/// [`ElementLagrangian::size_names`]), the parameters by name as every system's.
fn element_info<L: ElementLagrangian>(system: &L) -> RunInfo {
    let names = system.coordinate_names();
    let indices: Vec<String> = if system.sizes().is_empty() && names.len() == system.dim() {
        names.iter().map(|n| n.to_string()).collect()
    } else {
        (0..system.dim()).map(|i| i.to_string()).collect()
    };
    let indices: Vec<&str> = indices.iter().map(String::as_str).collect();
    let sizes: Vec<String> = system
        .size_names()
        .iter()
        .zip(system.sizes())
        .map(|(name, size)| format!("{name}={size}"))
        .collect();
    RunInfo {
        columns: ElementState::column_names(&indices, &[]),
        h: system.time_step(),
        parameters: parameters(system),
        metadata: vec![
            (
                "dirac.coordinates".into(),
                system.coordinate_names().join(","),
            ),
            ("dirac.sizes".into(), sizes.join(",")),
        ],
    }
}

/// The name of a side's element-wise equations, as the metadata records it.
fn element_side(variant: Variant) -> &'static str {
    match variant {
        Variant::Plus => "element-wise (+)",
        Variant::Minus => "element-wise (-)",
    }
}

impl<L: ElementLagrangian> Describe for ElementIntegrator<L> {
    fn describe(&self) -> RunInfo {
        element_info(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", element_side(self.variant()))
    }
}

impl<L: ElementLagrangian> Describe for ElementConstrainedIntegrator<L> {
    fn describe(&self) -> RunInfo {
        element_info(self.system())
            .with_newton(self.options())
            .with("dirac.integrator", element_side(self.variant()))
            .with(
                "dirac.constraints",
                self.system().constraint_count().to_string(),
            )
    }
}
