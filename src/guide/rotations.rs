//! # Rotations and directions
//!
//! Rigid bodies, tops, satellites and pendula in 3-D have configurations in the rotation group
//! `SO(3)` and on the sphere `S²`, and a body that also moves through space in the group of
//! rigid motions `SE(3)` ([`pose(X)`](#bodies-in-space-posex)). Written in angles, they meet
//! the singular configurations that the paper's Remark 7.1 describes and that an
//! [atlas](crate::runtime::atlas) of charts works around (the double spherical pendulum
//! switches chart 933 times in 10⁶ steps). Declared as rotations, directions and poses, they
//! are stepped on the group itself: the Lie group variational integrators of Lee, Leok and
//! McClamroch, derived by the compiler from the discrete Lagrangian you write, with no chart to
//! switch and no angle anywhere.
//!
//! ## Declaring rotations and directions
//!
//! `rotation(R, ..)` declares coordinates in `SO(3)`, read in the body as 3 × 3 matrices;
//! `direction(n, ..)` coordinates on `S²`, read as unit 3-vectors; `shape(x, ..)` ordinary real
//! coordinates beside them. The body is written with nalgebra's spelling, so the function is
//! ordinary Rust too: products, `transpose()`, `trace()`, `dot(&b)`, `cross(&b)`, `norm()`,
//! `norm_squared()`, entries `m[(i, j)]` and `v.x`, `Matrix3::identity()`,
//! `Matrix3::from_diagonal(&v)`, `Vector3::new(..)`, and [`hat`](crate::lie::hat) /
//! [`vee`](crate::lie::vee) (all in the prelude). The free rigid body of Lee, Leok & McClamroch:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// `L_d = tr((I − F) J_d)/h`, `F = R0ᵀ R1`, `J_d = ½ tr(J) I − J`.
//! #[reduced_lagrangian(rotation(r))]
//! fn body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
//!     let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
//!     let f = q0.r.transpose() * q1.r;
//!     ((Matrix3::identity() - f) * jd).trace() / h
//! }
//!
//! let sys = Body { h: 0.01, j1: 1.0, j2: 2.0, j3: 3.0 };
//! let integ = LieIntegrator::new(sys, NewtonOptions::default());
//! let start = sys.state(
//!     &BodyConfig { r: Matrix3::identity() },
//!     &BodyMomentum { r: Vector3::new(0.3, 1.0, -0.2) },
//! );
//! let traj = integ.run(start).steps(1000).collect().unwrap();
//! let (first, last) = (&traj.states[0], traj.last());
//! // Rotating the body in space is a symmetry: the spatial angular momentum is kept.
//! let drift = (integ.spatial_momentum(last) - integ.spatial_momentum(first)).norm();
//! assert!(drift < 1e-13);
//! assert!(dirac::lie::orthogonality_defect(&sys.config(last).r) < 1e-14);
//! ```
//!
//! The attribute emits `<Name>Config` (the coordinates as `Matrix3`, `Vector3` and `f64`),
//! `<Name>Momentum` (for a rotation its discrete body momentum `Π`, left-trivialized:
//! `⟨P, R η̂⟩ = Π·η` — the discrete Legendre momentum of the step, see *Momenta* below;
//! for a direction its momentum, a vector tangent to the sphere; for a scalar its momentum),
//! `state`, `config` and `momenta` to go between them and a [`LieState`](crate::LieState), and
//! implements [`LieLagrangian`](crate::LieLagrangian). [`LieIntegrator`](crate::LieIntegrator)
//! steps it through the same run as every integrator: steps or an end time, step sizes per step,
//! stop conditions, observers, ensembles, and compositions of order 4 and 6
//! ([`Composition`](crate::Composition)) for a symmetric `L_d`.
//!
//! ## The step
//!
//! At every step the unknown is the chart coordinate `z ∈ R^N` of the next point in a chart
//! centred at the current one: `R_{k+1} = R_k cay(z)` with the Cayley retraction
//! `cay(ξ) = (I − ξ̂/2)⁻¹(I + ξ̂/2)` for a rotation, `n_{k+1} = (n_k + a e1 + b e2)/|…|` in a
//! frame `(e1, e2)` of the tangent plane carried along with `n` for a direction, `x_k + z` for a
//! scalar. The equations are the discrete Lagrange–Dirac equations in position–momentum form with
//! the variations `δR = R η̂` (the module [`crate::lie`] derives them):
//!
//! ```text
//! p_k · η     = −D1 L_d(q_k, q_{k+1}) · dφ_{q_k}(0) η
//! p_{k+1} · η =  D2 L_d(q_k, q_{k+1}) · dφ_{q_{k+1}}(0) η
//! ```
//!
//! On a rotation, `Π_k = −T*L(D1 L_d)`, `Π_{k+1} = T*L(D2 L_d)`. The compiler differentiates
//! through the retraction, so Newton runs on the first line with its exact 3 × 3 (or `N × N`)
//! Jacobian; the second is explicit. Next points are products of rotations: they stay on `SO(3)`
//! and `S²` to round-off with no projection.
//!
//! **Write the relative rotation as `q0.R.transpose() * q1.R`.** The compiler recognises it and
//! evaluates `F = R0ᵀ R1` from the step's own increment (`cay(z)`) rather than by multiplying two
//! stored rotations, whose round-off (`ε` in entries of size `h`) a kinetic term divided by `h`
//! would amplify into momentum drift. Written this way, the rigid body matches a hand-written
//! LGVI to 6e-13 over 1000 steps and keeps its spatial angular momentum to 6e-13 over 10⁶.
//!
//! ## Choices
//!
//! * **The retraction.** Cayley for rotations: rational, so its derivatives are straight-line code
//!   with no special function, exact where `ξ → 0`, and a rotation for every `ξ`. It differs from
//!   the exponential by `O(|ξ|³)`, which changes `L_d` at third order in `h` and keeps a
//!   second-order `L_d` second order.
//! * **Continuous Lagrangians.** `fn l(q: Config, v: Velocity, ..)` with `rule = trapezoid`
//!   (or `left`, `right`) reads `v.R` as the body angular velocity `Ω`, `v.n` as a direction's
//!   velocity and `v.x` as a scalar's rate; the compiler forms
//!   `L_d = h/2 (L(q0, v) + L(q1, v))` with `Ω = cay⁻¹(R0ᵀ R1)/h` (the Cayley parameter of the
//!   relative rotation, `cay⁻¹(F) = 2 vee(F − Fᵀ)/(1 + tr F)` with the exact vee of a skew
//!   matrix) and the chords `(n1 − n0)/h`, `(x1 − x0)/h`. The trapezoid rule is symmetric, so of
//!   order 2 (4 composed); left and right are of order 1. The midpoint rule is refused: the mean
//!   of two rotations is not a rotation.
//!
//!   ```
//!   use dirac::prelude::*;
//!
//!   /// The heavy top, `L = ½ Ωᵀ J Ω − m g l e3ᵀ R e3`.
//!   #[reduced_lagrangian(rotation(r), rule = trapezoid)]
//!   fn top(q: Config, v: Velocity, j1: f64, j3: f64, mgl: f64) -> f64 {
//!       let omega = v.r;
//!       0.5 * (j1 * (omega.x * omega.x + omega.y * omega.y) + j3 * omega.z * omega.z)
//!           - mgl * q.r[(2, 2)]
//!   }
//!
//!   let sys = Top { h: 0.01, j1: 1.0, j3: 0.4, mgl: 2.0 };
//!   let start = sys.state(
//!       &TopConfig { r: dirac::lie::cayley(&Vector3::new(0.6, 0.0, 0.0)) },
//!       &TopMomentum { r: Vector3::new(0.1, 0.3, 4.0) },
//!   );
//!   let integ = LieIntegrator::new(sys, NewtonOptions::default());
//!   let traj = integ.run(start).end_time(10.0).collect().unwrap();
//!   // Rotations about the vertical and about the body's axis are symmetries.
//!   let vertical = |s| integ.spatial_momentum(s).z;
//!   assert!((vertical(traj.last()) - vertical(&start)).abs() < 1e-12);
//!   assert!((traj.last().p[2] - start.p[2]).abs() < 1e-12);
//!   ```
//!
//!   This top and [`systems::rotations::heavy_top`](crate::systems::rotations::heavy_top) are
//!   different discrete maps of the same motion. Here the rule forms
//!   `L_d = (h/2)(L(R0, Ω) + L(R1, Ω))` with the Cayley velocity `Ω = cay⁻¹(R0ᵀ R1)/h`, so the
//!   kinetic term is `(h/2) ΩᵀJΩ`; `heavy_top` writes the Lie group variational integrator's
//!   `tr((I − F) J_d)/h`, which for `F = cay(hΩ)` is `(h/2) ΩᵀJΩ / (1 + h²|Ω|²/4)`. The
//!   potential is the same trapezoid in both. So the two steps, and the momenta their states
//!   store, agree to `O(h²)` and not bit for bit: both are symmetric and of order 2, each keeps
//!   its own discrete momenta exactly, and a state of one is not a state of the other.
//! * **The rule.** Or you write `L_d` directly. Rules of order 2 that are symmetric
//!   (`L_d(q0, q1; −h) = −L_d(q1, q0; h)`) — the kinetic term `tr((I − F) J_d)/h` with a potential
//!   averaged over both ends (trapezoid), or chord velocities `|n1 − n0|²/h` — give a symmetric
//!   step of order 2 that the triple jump raises to 4 (`tests/rotations.rs` measures both
//!   against Euler's equations solved in the test). A potential at one end only gives order 1.
//! * **Momenta.** A state stores, for a rotation, the *discrete* Legendre momentum
//!   `Π_k = −T*L(D1 L_d)` of the step, left-trivialized — not the continuous body momentum
//!   `∂L/∂Ω = JΩ` of an angular velocity. For the free rigid body
//!   `Π_k = vee(F_k J_d − J_d F_kᵀ)/h`, which for `F_k = cay(hΩ)` is `JΩ − (h/2) JΩ × Ω` to
//!   `O(h²)` (the momentum at the step's start of a motion whose velocity mid-step is `Ω`); a
//!   potential moves it by `−(h/2) M` with its torque `M` (the trapezoid rule; for the heavy
//!   top `M = m g l Rᵀe3 × e3`), so `Π_k` and `JΩ` differ at first order in `h`. To start from an attitude `R` and an angular velocity
//!   `Ω`, take the momentum of the first step that moves with `Ω`:
//!   [`sys.discrete_legendre_state(&q, &Ω)`](crate::LieLagrangian::discrete_legendre_state)
//!   (`q` the stored point, `<Name>Config::to_point`), whose run then steps by
//!   `R_{k+1} = R_k cay(hΩ)` first. For the spatial angular momentum use
//!   [`LieIntegrator::spatial_momentum`](crate::LieIntegrator::spatial_momentum),
//!   `π = Σ R Π + Σ n × P`.
//!
//!   ```
//!   use dirac::prelude::*;
//!   use dirac::systems::rotations::{HeavyTop, HeavyTopConfig};
//!
//!   let top = HeavyTop { h: 0.01, j1: 1.0, j2: 1.0, j3: 0.4, mgl: 2.0 };
//!   let r = dirac::lie::cayley(&Vector3::new(0.6, 0.0, 0.0));
//!   let omega = Vector3::new(0.1, 0.3, 10.0);
//!   let start = top.discrete_legendre_state(&HeavyTopConfig { r }.to_point(), &omega)?;
//!   let integ = LieIntegrator::new(top, NewtonOptions::default());
//!   let traj = integ.run(start).steps(1).collect()?;
//!   let first = top.config(&traj.states[1]).r;
//!   assert!((first - r * dirac::lie::cayley(&(0.01 * omega))).amax() < 1e-12);
//!   # Ok::<(), Box<dyn std::error::Error>>(())
//!   ```
//!
//! ## Translations beside rotations
//!
//! `group(x, ..)` declares scalar coordinates whose translations are a symmetry — a rigid body
//! in space: `rotation(R), group(x, y, z)`. The compiler checks the invariance of `L_d` at sample
//! configurations (a body that is not invariant is a compile error at the coordinate), and the
//! step updates their momenta by the discrete Noether balance itself,
//! `μ_{k+1} = μ_k + f_d^− + f_d^+`: bit for bit constant without forces, and moved by exactly the
//! forces' impulse with them (a thruster on a spacecraft, `tests/rotations.rs`). These
//! coordinates stay in the state (the step solves their equations with the rest) rather than
//! being reduced away as the reduced integrators do.
//!
//! ## Bodies in space: `pose(X)`
//!
//! `pose(X, ..)` declares a coordinate in the group of rigid motions `SE(3) = SO(3) ⋉ R³`: a
//! body's attitude and position together. The body reads `q0.X.rotation` (a 3 × 3 matrix,
//! body → space) and `q0.X.translation` (a 3-vector); the chart is
//! `φ_(R,x)(ξ, v) = (R cay(ξ), x + v)`, the rotation in the body frame as for `rotation(R)` and
//! the translation in space, so a state stores 12 entries (`R` row by row, then `x`) and a
//! momentum `(Π, p)`: the discrete body angular momentum, as a rotation's, and the spatial
//! linear momentum. A force reads `dq.X.angular` (`η` of `δR = R η̂`) and `dq.X.linear` (`δx`);
//! a continuous Lagrangian `v.X.angular` (the body angular velocity `Ω`, from the relative
//! rotation as for `rotation(R)`) and `v.X.linear` (`ẋ = (x1 − x0)/h`). The attribute emits
//! `<Name>Pose { rotation, translation }` and `<Name>PoseMomentum { angular, linear }` for
//! the fields of `<Name>Config` and `<Name>Momentum`.
//!
//! Unlike `rotation(R), group(x, y, z)`, whose translations must be a symmetry of `L_d`, a pose
//! may sit in a field that depends on where it is — here gravity — and what it keeps is read
//! from the momentum map of the rigid motions `(A, a)·(R, x) = (A R, A x + a)`:
//! [`LieIntegrator::linear_momentum`](crate::LieIntegrator::linear_momentum), `ℓ = p`, and
//! [`LieIntegrator::spatial_momentum`](crate::LieIntegrator::spatial_momentum), to which a pose
//! adds its angular momentum about the origin `R Π + x × p`. A body in gravity, with a thrust
//! `T` along its third axis as discrete forces by the trapezoid rule (`J = diag(1, 2, 3)`, so
//! `J_d = diag(2, 1, 0)`):
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// `L_d = tr((I − R0ᵀR1) J_d)/h + m |x1 − x0|²/(2h) − (h/2) m g e3·(x0 + x1)`.
//! #[reduced_lagrangian(pose(b),
//!     force = |dq0, dq1| 0.5 * h * thrust
//!         * ((q0.b.rotation * Vector3::z()).dot(&dq0.b.linear)
//!             + (q1.b.rotation * Vector3::z()).dot(&dq1.b.linear)))]
//! fn flyer(q0: Config, q1: Config, h: f64, m: f64, g: f64, thrust: f64) -> f64 {
//!     let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
//!     let f = q0.b.rotation.transpose() * q1.b.rotation;
//!     let dx = q1.b.translation - q0.b.translation;
//!     ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
//!         - 0.5 * h * m * g * (q0.b.translation.z + q1.b.translation.z)
//! }
//!
//! let start = |sys: &Flyer| {
//!     sys.state(
//!         &FlyerConfig {
//!             b: FlyerPose {
//!                 rotation: dirac::lie::cayley(&Vector3::new(0.3, -0.2, 0.4)),
//!                 translation: Vector3::new(1.0, -2.0, 0.5),
//!             },
//!         },
//!         &FlyerMomentum {
//!             b: FlyerPoseMomentum {
//!                 angular: Vector3::new(0.4, 1.0, -0.3),
//!                 linear: Vector3::new(0.9, -0.3, 0.6),
//!             },
//!         },
//!     )
//! };
//! // Falling, tumbling: gravity keeps the horizontal translations and the rotations about the
//! // vertical, so the horizontal ℓ and the vertical π.
//! let falling = Flyer { h: 0.01, m: 3.0, g: 9.81, thrust: 0.0 };
//! let integ = LieIntegrator::new(falling, NewtonOptions::default());
//! let (s0, traj) = (start(&falling), integ.run(start(&falling)).steps(1000).collect()?);
//! let (l0, l1) = (integ.linear_momentum(&s0), integ.linear_momentum(traj.last()));
//! assert!((l1.x - l0.x).abs().max((l1.y - l0.y).abs()) < 1e-14);
//! assert!((l1.z - (l0.z - 3.0 * 9.81 * 10.0)).abs() < 1e-10); // m g t, t = 10
//! let vertical = |s| integ.spatial_momentum(s).z;
//! // Kept to round-off: each stored position rounds at `ε |x|`, which moves `x × p` by up to
//! // `ε |x| |p|` a step (here `|x| |p|` grows to 1.4·10⁵; the drift is about 1e-13).
//! assert!((vertical(traj.last()) - vertical(&s0)).abs() < 1e-12);
//! // Thrusting: ℓ moves by the forces' impulse, ℓ_{k+1} − ℓ_k = (h/2)(f_k + f_{k+1}) with
//! // f = T R e3 − m g e3, to round-off at every step.
//! let thrusting = Flyer { thrust: 40.0, ..falling };
//! let integ = LieIntegrator::new(thrusting, NewtonOptions::default());
//! let traj = integ.run(start(&thrusting)).steps(100).collect()?;
//! let force = |s| thrusting.config(s).b.rotation * Vector3::z() * 40.0 - Vector3::z() * 29.43;
//! for w in traj.states.windows(2) {
//!     let change = integ.linear_momentum(&w[1]) - integ.linear_momentum(&w[0]);
//!     assert!((change - (force(&w[0]) + force(&w[1])) * 0.005).amax() < 1e-14);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `tests/se3.rs` holds this system to a hand-written SE(3) Lie group variational integrator
//! (its own Cayley map and Newton on the equations derived there): over 1000 steps every part
//! of the state agrees to 1e-12 of its size, coasting, hovering, falling and thrusting while
//! tumbling, with Newton's tolerances at 1e-15 (Newton's tolerance is one norm over the chart,
//! so where `|p|` ≈ 200 dwarfs `|Π|` ≈ 1 the rotation is solved to `rel_tol |p|`, and only a
//! tolerance well below the default solves it as tightly as the reference); the (−) integrator
//! takes the same steps bit for bit; the step, and the continuous form `L(q, v)` with the
//! trapezoid rule, are of order 2 against Euler's and Newton's equations; `‖RᵀR − I‖` stays at
//! 2e-14 over 10⁴ steps. Without forces `ℓ` is kept to round-off and `π` to the round-off of
//! storing the positions, as in the hand-written steps (7e-14 of `|π|` over 1000 steps).
//!
//! A position far from the origin costs the step no digits. The body's `x1 − x0` is compiled
//! as the chart increment `v` of `x1 = x0 + v`: the same in real arithmetic, while
//! `(x0 + v) − x0` in floating point is `v` rounded at `|x0|`, which would put a floor
//! `ε |x| m/h` under the residual `m (x1 − x0)/h − ..` and stop Newton once the body is far
//! enough (at the default tolerances, after 230 s of free fall). The residual, its Jacobian,
//! the momentum update and the sensitivities all read `v`, for a pose's position and for a
//! scalar alike, and the residual stays at the round-off of the momenta: the body of
//! `tests/se3.rs` falls for 5·10⁴ steps (500 s, 1.2·10⁶ m) at the default tolerances, on the
//! exact parabola of the discrete free fall to 2e-12. Storing `x_{k+1} = x_k + v` still rounds
//! at `|x|`, as any integrator's positions do.
//!
//! ## Forces, torques and controls
//!
//! `force = |dq| W` (with a rule) or `force = |dq0, dq1| W` (a discrete Lagrangian) is the virtual
//! work, as for ordinary coordinates, with the virtual displacement of a rotation read as the
//! algebra element `η` of `δR = R η̂` — so `τ.dot(&dq.r)` is the work of a torque `τ` in the body
//! frame — of a direction as the tangent vector `δn`, and of a scalar as `δx`. The forced step is
//! `p_k = −D1 L_d − f_d^−`, `p_{k+1} = D2 L_d + f_d^+` in the charts of `q_k` and `q_{k+1}`, and
//! the discrete Noether balance `π_{k+1} − π_k = R_k f_d^− + R_{k+1} f_d^+` holds to round-off.
//! `controls(u, ..)` names parameters a control law sets before every step
//! (`.feedback(..)`, `.controls(..)` on the run). The satellite of
//! [`crate::systems::rotations`] drives its wheel with a motor torque `u`: the wheel's momentum
//! moves by `h u` per step to round-off while the satellite's spatial angular momentum stays put.
//!
//! ## Step sensitivities
//!
//! [`LieIntegrator::sensitivity`](crate::LieIntegrator::sensitivity) (and `step_sensitivity`)
//! gives the derivative of a step in the charts at its two points: a state near `(q, p)` is
//! `(φ_q(δ), p)`, so the `2N × 2N` matrix is `∂(w, p_{k+1})/∂(δ, p_k)` with
//! `q'_{k+1} = φ_{q_{k+1}}(w)`, and one column per control. The compiler emits the partial
//! derivatives of the step residual in these charts (every relative rotation from the charts'
//! own increments); the runtime applies the implicit-function theorem. `tests/rotations.rs`
//! checks it against central differences on the group. [`LieIntegrator::chart_coordinates`](crate::LieIntegrator::chart_coordinates)
//! is the inverse of the chart, for reading a nearby state in the chart of another.
//!
//! ## Ready-made systems
//!
//! [`crate::systems::rotations`] has the free rigid body, the heavy top (the Lagrange top, and the
//! 3-D pendulum for unequal moments), a satellite with a reaction wheel (a rotation beside an
//! ordinary angle) and the paper's double spherical pendulum on `S² × S²`, which gives the same
//! discrete trajectory as the Cartesian run with rod constraints and runs 10⁶ steps from the
//! paper's state with `| |n| − 1 | ≤ 4e-16` and no chart. `cargo run --release --example rotations`
//! runs them all and times them against hand-written steps. Over 10⁶ steps the rigid body keeps
//! `‖RᵀR − I‖` at 3.2e-13 and its spatial angular momentum to 5.7e-13 (a hand-written LGVI of
//! the same `L_d`: 6.8e-13 and 5.5e-13), and the pendulum on `S² × S²` runs from the paper's
//! state with no chart and `| |n| − 1 |` ≤ 3.4e-16.
//!
//! ## Limits
//!
//! Systems with rotation, direction or pose coordinates take a discrete Lagrangian or a
//! continuous one with the trapezoid, left or right rule, scalar and translation coordinates
//! beside them, forces, controls, `step` and `name`, and rotation symmetries of their rotations
//! and directions (`symmetry(..)`, see [Reduction by rotations](super::rotation_reduction)).
//! Not yet available for them: the reduced state of declared translations (they are kept in
//! the state, their momenta exact), the reduction of a pose by rigid motions (it is stepped
//! whole, its momentum map kept to round-off), and constraints. `LieIntegrator::minus` solves the (−) equations (trivialized at the next
//! point), which take the same steps. Above 16 dimensions the step runs on the sparse backend, as
//! every other system does, without step sensitivities. `dirac-io` writes these states to
//! Parquet with one column per stored entry (a rotation's nine, a direction's frame, a pose's twelve) and per
//! momentum component. In the unreduced step a rotation's momentum map is kept to round-off; the
//! [reduced integrator](super::rotation_reduction) carries it as a parameter.
