//! # Articulated bodies
//!
//! Robots, satellites with arms and linkages are trees of rigid bodies joined by revolute and
//! prismatic joints, described in URDF files that every robotics tool reads. A
//! [`Model`](crate::multibody::Model) of [`dirac::multibody`](crate::multibody) reads one (or
//! is built in Rust) and evaluates its mechanics: forward kinematics, energies, momenta, the
//! joint-space mass matrix. To step it, the model writes its Lagrangian as a system given as
//! text — the attribute and function that `#[reduced_lagrangian]` compiles — and the run-time
//! front end ([guide](super::run_time_text)) compiles that text to machine code. So an
//! articulated system is one more front end, not a new integrator: the compiler's exact
//! Jacobians, the run API, sensitivities, step schedules, compositions, Parquet columns named
//! after the coordinates, Python and the command line all serve it as they serve any text.
//!
//! ## From a model to a text
//!
//! [`Model::system_text`](crate::multibody::Model::system_text) writes the text:
//!
//! ```
//! use dirac::multibody::{Model, TextKind, TextOptions};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let model = Model::from_urdf_str(r#"
//!   <robot name="double_pendulum">
//!     <link name="world"/>
//!     <link name="rod1">
//!       <inertial><origin xyz="0 0 -0.45"/><mass value="1.3"/>
//!         <inertia ixx="0.11" ixy="0" ixz="0" iyy="0.11" iyz="0" izz="0.002"/></inertial>
//!     </link>
//!     <link name="rod2">
//!       <inertial><origin xyz="0 0 -0.6"/><mass value="0.7"/>
//!         <inertia ixx="0.08" ixy="0" ixz="0" iyy="0.08" iyz="0" izz="0.001"/></inertial>
//!     </link>
//!     <joint name="shoulder" type="continuous">
//!       <parent link="world"/><child link="rod1"/><axis xyz="0 1 0"/>
//!     </joint>
//!     <joint name="elbow" type="continuous">
//!       <parent link="rod1"/><child link="rod2"/><origin xyz="0 0 -1"/><axis xyz="0 1 0"/>
//!     </joint>
//!   </robot>"#)?;
//! let text = model.system_text()?;
//! assert_eq!(text.kind, TextKind::FixedBase);
//! assert!(text.text.contains("#[reduced_lagrangian(shape(shoulder, elbow), group(), rule = midpoint)]"));
//!
//! // Joint torques as controls, entering as virtual work.
//! let driven = model.system_text_with(&TextOptions { name: "arm".into(), torques: true })?;
//! assert_eq!(driven.controls, ["tau_shoulder", "tau_elbow"]);
//! assert!(driven.text.contains("force = |dq| tau_shoulder * dq.shoulder + tau_elbow * dq.elbow"));
//! # Ok(())
//! # }
//! ```
//!
//! The text of this pendulum (the numbers are the URDF's, folded):
//!
//! ```text
//! #[reduced_lagrangian(shape(shoulder, elbow), group(), rule = midpoint)]
//! fn multibody(q: Config, v: Velocity) -> f64 {
//!     // body 1, "rod1": joint "shoulder" (continuous) from "world"
//!     let s_1 = q.shoulder.sin();
//!     let k_1 = q.shoulder.cos();
//!     let e_1 = Matrix3::new(k_1, 0.0, -s_1, 0.0, 1.0, 0.0, s_1, 0.0, k_1);
//!     let w_1 = Vector3::new(0.0, 1.0, 0.0) * v.shoulder;
//!     let g_1 = e_1 * Vector3::new(0.0, 0.0, (-9.81));
//!     let vc_1 = w_1.cross(&Vector3::new(0.0, 0.0, (-0.45)));
//!     let l_1 = 0.65 * vc_1.norm_squared() + 0.5 * w_1.dot(&(Matrix3::new(0.11, ..) * w_1))
//!         + g_1.dot(&Vector3::new(0.0, 0.0, (-0.585)));
//!     // body 2, "rod2": joint "elbow" (continuous) from "rod1"
//!     let vs_2 = w_1.cross(&Vector3::new(0.0, 0.0, (-1.0)));
//!     let yj_2 = g_1.dot(&Vector3::new(0.0, 0.0, (-1.0)));
//!     ..
//!     let w_2 = e_2 * w_1 + Vector3::new(0.0, 1.0, 0.0) * v.elbow;
//!     let d_2 = e_2 * vs_2;
//!     ..
//!     l_1 + l_2
//! }
//! ```
//!
//! It is `L = T − V` of the model, written by Featherstone's recursion in body coordinates
//! (*Rigid Body Dynamics Algorithms*, 2008, ch. 2–5): for each body, from its parent's, its
//! angular velocity `Ω_b`, the velocity `V_b` of its frame's origin and gravity `γ_b`, all in
//! the body's own frame, and the height term `η_b = g·o_b`,
//!
//! ```text
//! Ω_J = P_Rᵀ Ω_λ,  V_J = P_Rᵀ (V_λ + Ω_λ × P_t),  γ_J = P_Rᵀ γ_λ,  η_J = η_λ + γ_λ·P_t   (joint frame)
//! revolute:   Ω_b = Eᵀ Ω_J + a θ̇,  V_b = Eᵀ V_J,  γ_b = Eᵀ γ_J,  E = a aᵀ + cos θ (1 − a aᵀ) + sin θ [a]×
//! prismatic:  Ω_b = Ω_J,  V_b = V_J + Ω_J × a d + a ḋ,  η_b = η_J + γ_J·a d
//! L = Σ_b ½ m_b |V_b + Ω_b × c_b|² + ½ Ω_bᵀ I_b Ω_b + m_b (η_b + γ_b·c_b)
//! ```
//!
//! (König's theorem for each body; [`dirac::multibody::text`](crate::multibody::text) derives
//! it). Each body adds a fixed number of let-bindings, so the text is `O(n)` long: 8.4 kB for
//! the 7-joint iiwa arm. Coordinates are named after the joints, made identifiers
//! (`hip-left` becomes `hip_left`; [`SystemText::identifier`](crate::multibody::SystemText::identifier)
//! maps a joint to its name in the text, and so to its Parquet columns).
//!
//! ## Running it
//!
//! The crate `dirac-jit` compiles the text ([`compile_model`](https://docs.rs/dirac-jit) reads
//! the model and compiles its text in one call), and the integrators run it as any system given
//! as text:
//!
//! ```text
//! let model = Model::from_urdf_file("examples/data/iiwa14.urdf")?;
//! let code = dirac_jit::compile_model(&model, &TextOptions::default())?;
//! let Compiled::Flat(flat) = &code.compiled else { unreachable!() };
//! let arm = flat.instantiate::<7, 0, 7>(&[1e-3])?;                 // h = 1 ms
//! let start = arm.unreduced_state::<7, 0>(q0, v0)?;               // angles and rates
//! let integ = UnreducedIntegrator::new(arm, NewtonOptions::default());
//! let traj = integ.run(start).steps(10_000).collect()?;
//! let energies = integ.energies(&traj)?;                          // E = T + V at the nodes
//! ```
//!
//! With torques the controls are parameters before `h` (`tau_<joint>`), set per step by a
//! feedback law or a sequence, and `step_sensitivity` gives the step's derivative in the state
//! and the torques (an LQR or a trajectory optimisation of the arm). From Python,
//! `dirac.from_urdf("iiwa14.urdf", torques=True)` reads and compiles the file in one call and
//! returns the same classes `dirac.compile` does (a `System` for a fixed base, a `LieSystem`
//! for a floating one), with the same runs, ensembles and Parquet output (`gravity=[0, 0, 0]`
//! puts a floating base in space); `dirac.Model(root)` builds the same description in Python,
//! link by link and joint by joint, and `compile`s it the same way. On the command line a system file names the robot,
//! `urdf = "iiwa14.urdf"` (with `torques = true`, `gravity = [x, y, z]`), in place of a text,
//! and `dirac run` writes its columns named after the joints.
//!
//! ## The rules, and why
//!
//! * **A fixed base** (revolute, continuous and prismatic joints; fixed joints are fused when
//!   the model is built) is stepped in its joint coordinates, one flat coordinate per joint,
//!   with `rule = midpoint`, `L_d(q₀, q₁) = h L((q₀ + q₁)/2, (q₁ − q₀)/h)`. The rule is
//!   symmetric, so the step is of order 2 and its compositions of order 4 and 6; it evaluates
//!   `L` once per step, half the straight-line code of the trapezoid rule's two evaluations in
//!   every derivative the compiler emits; and it is how the attribute's own systems on vector
//!   spaces are written, so a model steps as the same system written by hand does.
//! * **A floating base** (a `floating` joint from the root, scalar joints below it) puts the
//!   base's pose on `SE(3)` as a `pose(..)` coordinate ([guide](super::rotations)) beside the
//!   joints, with `rule = trapezoid` in the base's body angular velocity (the mean of two
//!   rotations is no rotation, so the midpoint rule is refused there). A rigid motion of the
//!   whole tree moves the base alone and leaves every body's velocity in its own frame
//!   unchanged, so without gravity `L_d` is invariant under all of them, and the discrete
//!   Noether theorem keeps the total linear and angular momentum of the tree to round-off; under
//!   gravity, the horizontal momentum and the vertical angular momentum.
//!
//! ## What is checked
//!
//! `dirac-jit/tests/urdf.rs` runs the models through their texts:
//!
//! * the double pendulum and the planar 3-link arm from their URDF files, and a cart on a slope
//!   with a pole (a prismatic joint) built in Rust, against the same systems written by hand
//!   with the attribute: 1e-13 relative over 1000 steps, and the same energy and Legendre map
//!   at sample states;
//! * the double pendulum's order 2 against its equations of motion solved by Runge–Kutta in the
//!   test (observed orders 1.98, 2.00, 2.00);
//! * the step sensitivities of the arm with joint torques against central differences (7e-9),
//!   and the step-map Jacobian of the conservative text against them;
//! * a branching tree with a prismatic joint carried by turning bodies, and the iiwa arm: the
//!   text's energy and Legendre map are `T + V` and `M(q) q̇` of the model (the
//!   composite-rigid-body algorithm, written independently) to 1e-12;
//! * the iiwa arm at `h = 1 ms`: the energy error over 1000 steps is 8·10⁻⁵ of the kinetic
//!   energy the arm reaches as it falls and swings, and falls by 4 when `h` halves;
//! * a free body from a URDF with one floating joint against the rigid body on `SE(3)` written
//!   by hand: 6e-14 relative over 1000 steps; and its order 2 against its exact motion (the
//!   centre of mass on its parabola, the attitude by Euler's equations; orders 2.00, 2.00);
//! * a satellite base with a 2-joint arm, out of gravity, over 10⁴ steps: the integrator's
//!   momentum map stays put to 8e-14 relative, and the model's own total momentum (evaluated
//!   at each node's configuration and velocity) to 2e-13; with its joints driven by torques
//!   under a feedback law to new angles (the base turning to compensate), to 3e-15 over 5000
//!   steps: joint torques are internal forces.
//!
//! ## What it costs
//!
//! The example `urdf_arm` of `dirac-jit` measures (two runs on a loaded 2-core machine, so the
//! step times scatter by up to 2×; `BENCHMARKS.md`):
//!
//! | system | text | compile | step | Newton iterations |
//! | --- | --- | --- | --- | --- |
//! | iiwa 14, 7 joints, `h` = 1 ms | 8.4 kB | 0.4–0.5 s | 4.3–5.7 µs | 2.0 |
//! | chain of 5 links | 3.4 kB | 0.07–0.15 s | 1.3–1.6 µs | 1.0 |
//! | chain of 10 links | 6.9 kB | 0.9 s | 9–14 µs | 2.0 |
//! | chain of 20 links (sparse backend) | 14 kB | 9.3–9.5 s | 22–40 µs | 4.7 |
//! | chain of 40 links (sparse backend) | 29 kB | 95–112 s | 160–350 µs | 3.8 |
//!
//! ```sh
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target -p dirac-jit --example urdf_arm
//! ```
//!
//! Against MuJoCo 4.0 on the same URDF file (`bash benches/mujoco/run.sh`: no contacts, limits or
//! damping, 10⁶ steps of 1 ms), the iiwa's step costs 0.41–0.57 × MuJoCo's RK4 step (about two
//! of its forward-dynamics evaluations); RK4's energy error is the smaller at this step (3·10⁻³
//! against 0.25 J) but drifts, the midpoint rule's does not, and MuJoCo's Euler and implicitfast
//! steps gain 1 J within 0.6 s of this swing and then diverge (`BENCHMARKS.md`).
//!
//! Two more examples step floating bases from their URDF files (`examples/data`, illustrative
//! masses and inertias); both run in CI and exit with an error when a figure misses its bound:
//!
//! * `space_manipulator`: a 500 kg satellite with a 6-DoF arm, out of gravity, its joints moved
//!   to new angles by a PD law on the torques while the base turns (0.05 rad) and translates in
//!   reaction. Over 10⁵ steps of 1 ms: the total linear momentum kept bit for bit, the angular
//!   momentum to 10⁻¹² relative, the base's attitude orthonormal to 4·10⁻¹⁶ (the step brings
//!   every stored rotation back onto SO(3) after the product `R_k cay(ξ_k)`); the joints end
//!   2·10⁻¹⁴ rad from their targets; 4.7–6.2 µs a step, 3–8 s to compile. Over 10⁶ steps the
//!   attitude stays orthonormal to 4·10⁻¹⁶ and the angular momentum about the origin drifts by
//!   9·10⁻¹¹: the base has drifted 23 m away, and the round-off of `x × p` is 2·10⁻¹⁵ of
//!   `|π|` a step.
//!   Reduced by the rigid motions of the whole tree (next section), the same run keeps the
//!   linear momentum bit for bit and the angular momentum to 1.2·10⁻¹⁶ over 10⁶ steps.
//! * `quadruped_flight`: a 12 kg trunk with four 3-joint legs thrown with a spin, legs swinging
//!   under a PD law, no contact. The horizontal momentum and the vertical angular momentum are
//!   kept to round-off and the vertical momentum falls by `M g h` a step, to round-off; the angular
//!   momentum about the centre of mass (2·10⁻⁵ relative over 2 s at `h` = 1 ms) and the centre
//!   of mass's parabola (0.3 µm) hold at order 2 (observed orders 2.00). 18 chart coordinates,
//!   so the sparse backend: 14–16 µs a step, 4.7 Newton iterations, 0.7–0.9 s to compile.
//!
//! ## A floating base reduced by the rigid motions
//!
//! Out of gravity a tree carried by a floating base is invariant under every rigid motion of
//! the whole, `(A, a)·(R, x) = (A R, A x + a)` applied to the base's pose (every body moves
//! with it; the joints do not change). The model's text then declares `symmetry(<base>)` —
//! checked by the compiler on sample configurations — and
//! [`ReducedLieIntegrator`](crate::ReducedLieIntegrator) carries the total spatial momentum
//! `(π, p) = (R Π + x × p, p)` as the run's parameters, as the reduction by rotations carries
//! `π`: after each step the base's linear momentum is `p`, copied bit for bit, and its body
//! angular momentum `Rᵀ(π − x × p)` at the reconstructed pose (the joints' momenta are the
//! step's), so the total momentum holds at every step to the round-off of one evaluation. The
//! unreduced step keeps it only to a sum of round-offs, which grows as the base drifts away from
//! the origin: over 10⁶ steps of the space manipulator, 9.1·10⁻¹¹ unreduced against 1.2·10⁻¹⁶
//! reduced (`space_manipulator` prints both; `BENCHMARKS.md`). Joint torques are internal
//! forces and leave the symmetry unforced. The reduced steps are the unreduced ones to
//! round-off (the joints end 3·10⁻¹⁴ rad apart after 10⁶ steps), at about 15% more time a step.
//!
//! ```ignore
//! let Compiled::Lie(code) = &dirac_jit::compile_model(&model, &TextOptions::default())?.compiled else { .. };
//! let sys: JitLie<P, N, Dense, Reduced> = code.instantiate_reduced(&[h])?;
//! let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
//! let traj = reduced.run(reduced.reduce(&start)).steps(100_000).collect()?;
//! assert_eq!(traj.last().mu, traj.states[0].mu); // π, the run's parameter
//! ```
//!
//! ## Long chains: the recursive step
//!
//! A fixed-base tree of any size steps at once, with no compilation, by
//! [`ArticulatedIntegrator`](crate::multibody::ArticulatedIntegrator): the same midpoint rule in
//! the joint angles as the model's text, its residual `R = p_k + (h/2) L_q − L_v` by two passes
//! over the tree (`L_v = S·H` and `L_q = H·(V_λ × S) + W·S` from the subtrees' momenta `H` and
//! weights `W`), and Newton's corrections by GMRES on the dense step Jacobian, never formed,
//! preconditioned by the articulated-body solve of its mass term `−M(q̄)/h`; every pass is
//! `O(n)`. The derivation is in [`dirac::multibody::articulated`](crate::multibody::articulated).
//!
//! ```
//! use dirac::multibody::nalgebra::{Matrix3, Vector3};
//! use dirac::multibody::{ArticulatedIntegrator, Inertial, JointSpec, Model, Pose};
//! use dirac::prelude::*;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let rod = Inertial::new(1.0, Vector3::new(0.0, 0.0, -0.25), Matrix3::from_diagonal(&Vector3::new(0.021, 0.021, 0.002)));
//! let mut chain = Model::builder().frame("l0");
//! for i in 1..=50 {
//!     let at = Pose::from_translation(Vector3::new(0.0, 0.0, if i == 1 { 0.0 } else { -0.5 }));
//!     let axis = if i % 2 == 1 { Vector3::y() } else { Vector3::x() };
//!     chain = chain.body(format!("l{i}"), rod).joint(
//!         JointSpec::revolute(format!("j{i}"), format!("l{}", i - 1), format!("l{i}"), axis).at(at),
//!     );
//! }
//! let model = chain.build()?;
//! let integ = ArticulatedIntegrator::new(&model, 1e-3, NewtonOptions::default())?;
//! let q: Vec<f64> = (0..50).map(|j| if j == 0 { 0.8 } else { 0.02 }).collect();
//! let start = integ.state(&q, &vec![0.0; 50])?; // p = M(q) q̇
//! let traj = integ.run(start).steps(200).collect()?;
//! assert!(traj.stats.mean_iterations() <= 3.0);
//! # Ok(())
//! # }
//! ```
//!
//! Checked against the model's own energies and mass matrix (`(p_k + p_{k+1})/2 = M(q̄) v`,
//! `(p_{k+1} − p_k)/h = L_q + τ` by central differences of `T − V`), a tight RK4 solve of the
//! joint-space equations of motion (order 2), the triple jump (order 4), and the compiled text of
//! the 3-link arm and the iiwa, with torques: from each state of a recursive run the compiled
//! step lands on the next one to 1.5·10⁻¹². The example `pendulum_chain` (in CI with 100 links)
//! measured, on chains of 10 to 1000 links from a bend, 2000 … 500 steps of 1 ms
//! (`--scaling 10,30,100,300,1000 --steps 500`, one run on a 2-core machine; `BENCHMARKS.md`):
//!
//! | links | step | Newton corrections (most) |
//! | --- | --- | --- |
//! | 10 | 11 µs | 1.20 (3) |
//! | 100 | 167 µs | 2.12 (3) |
//! | 1000 | 3.3 ms | 2.64 (5) |
//!
//! The time per step grows with slope 1.22 in the number of links: each pass is linear, but the
//! corrections (1.2 to 2.6) and the Krylov vectors per correction grow with the chain's fastest
//! joint rates, which a longer chain falling from a bend reaches (the preconditioner's error is
//! about `h |q̇|`).
//!
//! ## Limits
//!
//! * **The compiled text's cost grows toward `n³` in the number of joints.** In minimal
//!   coordinates the step's Jacobian `D₁D₂L_d` is dense: every joint moves every body below
//!   it. The compiled step evaluates its `n²` entries, each a straight line through the tree
//!   (`O(n³)` operations), and factors it in `O(n³)`; the compiler differentiates the whole `L`
//!   symbolically, so the compile time grows about as `n³` too (slopes 2.2–2.7 and 3.2 from 5
//!   to 40 links). A 7-joint arm is cheap (4 µs); a long chain takes the recursive step below.
//! * **The recursive step: fixed bases, scalar joints.** [`ArticulatedIntegrator`](crate::multibody::ArticulatedIntegrator)
//!   steps the same discrete Lagrangian without compiling, in `O(n)` per residual and per
//!   correction; it takes revolute, continuous and prismatic joints under a fixed base, the (+)
//!   equations, and no step sensitivities (the compiled text has them).
//! * **Joints.** Revolute, continuous, prismatic, fixed (fused), spherical (built in Rust: a
//!   `rotation(..)` coordinate on `SO(3)` in the text, the system then on rotation groups with
//!   the trapezoid rule; a ball-joint pendulum steps as written by hand to 1.6·10⁻¹³ over 1000
//!   steps) and one floating base; a free joint below the root is refused with
//!   [`ModelError::Unsupported`](crate::multibody::ModelError::Unsupported) naming the joint.
//!   Joint limits and `<dynamics>` damping are read and kept, not applied; there is no contact.
//! * **Reduction of a floating base: out of gravity only.** Out of gravity the text declares
//!   `symmetry(<base>)` and the reduced integrator carries the total momentum exactly (below);
//!   under gravity the symmetry is the horizontal translations with the rotations about the
//!   vertical, which are not declared: the unreduced step keeps those momenta by the discrete
//!   Noether theorem to round-off.
