//! The rigid body in space on `SE(3)`: `pose(X)` held to a hand-written Lie group variational
//! integrator.
//!
//! # The system
//!
//! A rigid body with principal moments `J = diag(j1, j2, j3)` and mass `m`, attitude
//! `R ∈ SO(3)` (body → space) and centre of mass `x ∈ ℝ³`, in uniform gravity `−g e3`, driven by
//! a thrust `T` along its third body axis through the centre of mass: the spatial force
//! `T R e3`, no torque. Its discrete Lagrangian is the kinetic term of the Lie group variational
//! integrator (Lee, Leok & McClamroch 2005, 2007) and the potential by the trapezoid rule,
//!
//! ```text
//! L_d(R0, x0, R1, x1) = tr((I − F) J_d)/h + m |x1 − x0|²/(2h) − (h/2) m g (e3·x0 + e3·x1),
//! F = R0ᵀ R1,   J_d = ½ tr(J) I − J,
//! ```
//!
//! and the thrust enters as the discrete forces of the trapezoid rule,
//! `f_d^−·(η0, δx0) = (h/2) T (R0 e3)·δx0` and `f_d^+·(η1, δx1) = (h/2) T (R1 e3)·δx1`: the
//! thrust's direction moves with `R`.
//!
//! # The discrete equations
//!
//! The variations are `δR = R η̂` (the body frame, `η ∈ ℝ³`) and `δx` (in space), those of the
//! chart `φ_(R,x)(ξ, v) = (R cay(ξ), x + v)` at `0`. The momenta are the covectors `(Π, p)` with
//! `⟨(P_R, p), (R η̂, δx)⟩ = Π·η + p·δx`: `Π` the body angular momentum, `p` the spatial linear
//! momentum. The forced discrete Legendre transforms (the position–momentum form of the forced
//! discrete Lagrange–d'Alembert principle) are
//!
//! ```text
//! (Π_k, p_k) = −D1 L_d(q_k, q_{k+1}) − f_d^−,     (Π_{k+1}, p_{k+1}) = D2 L_d(q_k, q_{k+1}) + f_d^+.
//! ```
//!
//! With `tr(η̂ A) = −η · vee(A − Aᵀ)` for every 3 × 3 matrix `A`:
//!
//! * `δR0 = R0 η̂` gives `δF = −η̂ F` and `D1 L_d·η = tr(η̂ F J_d)/h = −η·vee(F J_d − J_d Fᵀ)/h`,
//!   so `h Π_k = vee(F_k J_d − J_d F_kᵀ)`: the LGVI's `h Π_k + (h²/2) M_k = vee(F_k J_d − J_d
//!   F_kᵀ)` with no torque, `M_k = 0` (gravity and the thrust act at the centre of mass);
//! * `δR1 = R1 η̂` gives `δF = F η̂` and `D2 L_d·η = −tr(F η̂ J_d)/h = η·vee(J_d F − Fᵀ J_d)/h`;
//!   as `J_d F − Fᵀ J_d = Fᵀ (F J_d − J_d Fᵀ) F` and `vee(Fᵀ â F) = Fᵀ a`,
//!   `Π_{k+1} = F_kᵀ Π_k`, and `R_{k+1} = R_k F_k`;
//! * `D_{x0} L_d = −m (x1 − x0)/h − (h/2) m g e3`, so
//!   `p_k = m (x_{k+1} − x_k)/h + (h/2) m g e3 − (h/2) T R_k e3`: with the total force
//!   `f_k = T R_k e3 − m g e3`, `x_{k+1} = x_k + (h/m) p_k + (h²/(2m)) f_k`;
//! * `D_{x1} L_d = m (x1 − x0)/h − (h/2) m g e3`, so
//!   `p_{k+1} = m (x_{k+1} − x_k)/h − (h/2) m g e3 + (h/2) T R_{k+1} e3
//!   = p_k + (h/2)(f_k + f_{k+1})`.
//!
//! Only the rotation's equation is implicit. In the Cayley parameter `f` (half of the `ξ` of
//! `cay(ξ) = (I − ξ̂/2)⁻¹(I + ξ̂/2)`), `F = (I + f̂)(I − f̂)⁻¹ = I + 2 (f̂ + f̂²)/(1 + |f|²)`;
//! multiplying `F J_d − J_d Fᵀ = â`, `a = h Π_k`, by `I − f̂` on the left and `I + f̂` on the
//! right gives `2 (f̂ J_d + J_d f̂) = (I − f̂) â (I + f̂)`. With `f̂ J_d + J_d f̂ = (J f)^`
//! (`tr(J_d) I − J_d = J`), `â f̂ − f̂ â = (a × f)^` and `f̂ â f̂ = −(a·f) f̂`, it is the vector
//! equation of Lee, Leok & McClamroch (2005)
//!
//! ```text
//! G(f) = a + a × f + (a·f) f − 2 J f = 0,      ∇G(f) = â + (a·f) I + f aᵀ − 2 J,
//! ```
//!
//! which [`reference`] solves by Newton from the previous step's `f`. It shares no code with
//! dirac: its own hat, vee and Cayley map (in the half parameter), its own Newton, plain
//! nalgebra.
//!
//! # What is kept
//!
//! The momentum map of the rigid motions `(A, a)·(R, x) = (A R, A x + a)` is, in space,
//! `ℓ = p` and `π = R Π + x × p`. Without gravity and thrust `L_d` is invariant under all of
//! them: `ℓ_{k+1} = ℓ_k` and `π_{k+1} = π_k` (in the equations above, `p_{k+1} = p_k`,
//! `R_{k+1} Π_{k+1} = R_k F_k F_kᵀ Π_k` and `x_{k+1} × p = x_k × p + (h/m) p × p`). Gravity
//! keeps the motions that fix `e3`: the horizontal translations and the rotations about the
//! vertical, so `ℓ_1`, `ℓ_2` and `π_3`.
//!
//! # The motion the steps approximate
//!
//! Euler's and Newton's equations, `Ṙ = R Ω̂`, `Π̇ = Π × Ω` with `Ω = J⁻¹ Π`, `ẋ = p/m`,
//! `ṗ = T R e3 − m g e3`, solved in the test by the classical Runge–Kutta method at a small step
//! ([`reference::exact`]).

use dirac::nalgebra::{Matrix3, Vector3};

/// The hand-written integrator and the exact flow, in plain nalgebra.
mod reference {
    use dirac::nalgebra::{Matrix3, Vector3};

    /// `v̂ w = v × w`.
    pub fn hat(v: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
    }

    /// The vector of the skew part of `a`, `vee((a − aᵀ)/2)`.
    pub fn vee(a: &Matrix3<f64>) -> Vector3<f64> {
        Vector3::new(
            a[(2, 1)] - a[(1, 2)],
            a[(0, 2)] - a[(2, 0)],
            a[(1, 0)] - a[(0, 1)],
        ) * 0.5
    }

    /// `(I + f̂)(I − f̂)⁻¹ = I + 2 (f̂ + f̂²)/(1 + |f|²)`: the Cayley map in the half parameter.
    pub fn cayley_half(f: &Vector3<f64>) -> Matrix3<f64> {
        let s = hat(f);
        Matrix3::identity() + (s + s * s) * (2.0 / (1.0 + f.norm_squared()))
    }

    /// The body's parameters: step `h`, mass `m`, gravity `g`, moments `j`, thrust `thrust`.
    #[derive(Clone, Copy, Debug)]
    pub struct Body {
        pub h: f64,
        pub m: f64,
        pub g: f64,
        pub j: Vector3<f64>,
        pub thrust: f64,
    }

    /// Attitude `r`, position `x`, body angular momentum `pi`, spatial linear momentum `p`.
    #[derive(Clone, Copy, Debug)]
    pub struct State {
        pub r: Matrix3<f64>,
        pub x: Vector3<f64>,
        pub pi: Vector3<f64>,
        pub p: Vector3<f64>,
    }

    impl State {
        /// `(ℓ, π) = (p, R Π + x × p)`.
        pub fn momentum_map(&self) -> (Vector3<f64>, Vector3<f64>) {
            (self.p, self.r * self.pi + self.x.cross(&self.p))
        }
    }

    impl Body {
        /// `J_d = ½ tr(J) I − J`.
        pub fn jd(&self) -> Matrix3<f64> {
            let j = self.j;
            Matrix3::from_diagonal(&Vector3::new(
                j.y + j.z - j.x,
                j.x + j.z - j.y,
                j.x + j.y - j.z,
            )) * 0.5
        }

        /// The total force `T R e3 − m g e3`.
        pub fn force(&self, r: &Matrix3<f64>) -> Vector3<f64> {
            r.column(2) * self.thrust - Vector3::z() * (self.m * self.g)
        }

        /// The Cayley parameter `f` of `F_k` from `a = h Π_k`: `G(f) = 0` by Newton from `guess`
        /// (see the module documentation), to a correction at round-off.
        pub fn solve(&self, a: &Vector3<f64>, guess: Vector3<f64>) -> Vector3<f64> {
            let j = Matrix3::from_diagonal(&self.j);
            let mut f = guess;
            for _ in 0..50 {
                let g = a + a.cross(&f) + f * a.dot(&f) - j * f * 2.0;
                let jacobian =
                    hat(a) + Matrix3::identity() * a.dot(&f) + f * a.transpose() - j * 2.0;
                let df = jacobian.lu().solve(&g).expect("a regular LGVI Jacobian");
                f -= df;
                if df.amax() <= 2.0 * f64::EPSILON * f.amax() {
                    return f;
                }
            }
            panic!("the reference's Newton iteration did not converge");
        }

        /// One step: `F_k` from `h Π_k`, `R_{k+1} = R_k F_k`, `Π_{k+1} = F_kᵀ Π_k`,
        /// `x_{k+1} = x_k + (h/m) p_k + (h²/(2m)) f_k`, `p_{k+1} = p_k + (h/2)(f_k + f_{k+1})`.
        /// `guess` is the previous step's Cayley parameter, updated.
        pub fn step(&self, s: &State, guess: &mut Vector3<f64>) -> State {
            let (h, m) = (self.h, self.m);
            *guess = self.solve(&(s.pi * h), *guess);
            let f = cayley_half(guess);
            let r = s.r * f;
            let force = self.force(&s.r);
            State {
                r,
                x: s.x + s.p * (h / m) + force * (h * h / (2.0 * m)),
                pi: f.transpose() * s.pi,
                p: s.p + (force + self.force(&r)) * (h / 2.0),
            }
        }

        /// `steps` steps from `s`: every state, the first included.
        pub fn run(&self, s: State, steps: usize) -> Vec<State> {
            let mut guess = Vector3::zeros();
            let mut states = vec![s];
            for _ in 0..steps {
                let next = self.step(states.last().unwrap(), &mut guess);
                states.push(next);
            }
            states
        }
    }

    /// The time derivative of Euler's and Newton's equations at `s`.
    fn rates(body: &Body, s: &State) -> State {
        let omega = s.pi.component_div(&body.j);
        State {
            r: s.r * hat(&omega),
            x: s.p / body.m,
            pi: s.pi.cross(&omega),
            p: body.force(&s.r),
        }
    }

    /// `s + d·c`, entry by entry.
    fn axpy(s: &State, d: &State, c: f64) -> State {
        State {
            r: s.r + d.r * c,
            x: s.x + d.x * c,
            pi: s.pi + d.pi * c,
            p: s.p + d.p * c,
        }
    }

    /// The exact motion from `s` over `t`, by the classical Runge–Kutta method with 20,000 steps
    /// per unit time: its error, `O(10⁻¹⁶)` here, is far below the steps' at the sizes tested.
    pub fn exact(body: &Body, s: &State, t: f64) -> State {
        let n = (20_000.0 * t).ceil() as usize;
        let dt = t / n as f64;
        let mut y = *s;
        for _ in 0..n {
            let k1 = rates(body, &y);
            let k2 = rates(body, &axpy(&y, &k1, dt / 2.0));
            let k3 = rates(body, &axpy(&y, &k2, dt / 2.0));
            let k4 = rates(body, &axpy(&y, &k3, dt));
            y = axpy(&y, &k1, dt / 6.0);
            y = axpy(&y, &k2, dt / 3.0);
            y = axpy(&y, &k3, dt / 3.0);
            y = axpy(&y, &k4, dt / 6.0);
        }
        y
    }
}

use reference::{cayley_half, Body, State};

/// The body of the tests: `J = diag(1, 2, 3)`, `m = 3`, `g = 9.81`, thrust `T = 40` (a net
/// upward force: `T > m g`), `h = 0.01`.
fn body(h: f64, g: f64, thrust: f64) -> Body {
    Body {
        h,
        m: 3.0,
        g,
        j: Vector3::new(1.0, 2.0, 3.0),
        thrust,
    }
}

/// A tumbling, drifting start off every axis.
fn start() -> State {
    State {
        r: cayley_half(&Vector3::new(0.15, -0.1, 0.2)),
        x: Vector3::new(1.0, -2.0, 0.5),
        pi: Vector3::new(0.4, 1.0, -0.3),
        p: Vector3::new(0.9, -0.3, 0.6),
    }
}

/// `max(|R − R'|, |x − x'|, |Π − Π'|, |p − p'|)`, entry by entry.
fn distance(a: &State, b: &State) -> f64 {
    (a.r - b.r)
        .amax()
        .max((a.x - b.x).amax())
        .max((a.pi - b.pi).amax())
        .max((a.p - b.p).amax())
}

#[test]
fn the_reference_solves_the_lgvi_equation_and_keeps_the_group() {
    // G(f) = 0 is the LGVI's h Π_k = vee(F J_d − J_d Fᵀ), in the rotation's own terms.
    let b = body(0.01, 9.81, 40.0);
    let s = start();
    let a = s.pi * b.h;
    let f = cayley_half(&b.solve(&a, Vector3::zeros()));
    let jd = b.jd();
    let lgvi = reference::vee(&(f * jd - jd * f.transpose()));
    assert!((lgvi - a).amax() < 1e-17, "{:e}", (lgvi - a).amax());
    assert!((f.transpose() * f - Matrix3::identity()).amax() < 1e-15);
    assert!((f.determinant() - 1.0).abs() < 1e-15);
}

/// The order of the reference (and the correctness of its derivation): `|state_N − state(1)|`
/// after `n` steps of `1/n` against the exact motion.
#[test]
fn the_reference_has_order_two() {
    let errors: Vec<f64> = [20, 40, 80]
        .iter()
        .map(|&n| {
            let b = body(1.0 / n as f64, 9.81, 40.0);
            let last = *b.run(start(), n).last().unwrap();
            distance(&last, &reference::exact(&b, &start(), 1.0))
        })
        .collect();
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((order - 2.0).abs() < 0.1, "order {order} from {errors:?}");
    }
}

/// The drift of `π` over `n` states relative to `|π_0|`, and of its vertical component.
fn angular_drift(states: impl Iterator<Item = Vector3<f64>>) -> (f64, f64) {
    let mut first = None;
    let (mut all, mut vertical): (f64, f64) = (0.0, 0.0);
    for pi in states {
        let pi0: Vector3<f64> = *first.get_or_insert(pi);
        all = all.max((pi - pi0).norm() / pi0.norm());
        vertical = vertical.max((pi.z - pi0.z).abs() / pi0.norm());
    }
    (all, vertical)
}

/// Without forces `ℓ` is copied and `π` kept to round-off, which here is that of the positions:
/// `x_{k+1} = x_k + (h/m) p` adds the same increment at every step, whose rounding accumulates
/// about linearly in `x` (1.4e-13 in `x × p` after 1000 steps, against 2e-14 in `R Π`).
#[test]
fn the_reference_keeps_the_momentum_map_of_rigid_motions() {
    let (l0, _) = start().momentum_map();
    // Free: ℓ bit for bit, π to round-off.
    let free = body(0.01, 0.0, 0.0).run(start(), 1000);
    assert!(free.iter().all(|s| s.momentum_map().0 == l0));
    let (all, _) = angular_drift(free.iter().map(|s| s.momentum_map().1));
    assert!(all < 2e-13, "π drifts by {all:e}");
    // Gravity: the horizontal ℓ bit for bit, the vertical π to round-off; ℓ_3 falls by m g t.
    let b = body(0.01, 9.81, 0.0);
    let fall = b.run(start(), 1000);
    for (k, s) in fall.iter().enumerate() {
        let (l, _) = s.momentum_map();
        assert_eq!((l.x, l.y), (l0.x, l0.y));
        let t = k as f64 * b.h;
        assert!((l.z - (l0.z - b.m * b.g * t)).abs() <= 1e-13 * k as f64 * l.z.abs().max(1.0));
    }
    let (_, vertical) = angular_drift(fall.iter().map(|s| s.momentum_map().1));
    assert!(vertical < 2e-13, "π_3 drifts by {vertical:e}");
}

// ---------------------------------------------------------------------------------------------
// The same body through `#[reduced_lagrangian(pose(b), ..)]`.

use dirac::prelude::*;

/// The body of the module documentation as a `pose`: its `L_d` as written there, the thrust as
/// the trapezoid rule's discrete forces on the translation.
#[reduced_lagrangian(pose(b), step = h,
    force = |dq0, dq1| 0.5 * h * thrust
        * ((q0.b.rotation * Vector3::z()).dot(&dq0.b.linear)
            + (q1.b.rotation * Vector3::z()).dot(&dq1.b.linear)))]
#[allow(clippy::too_many_arguments)]
fn body_in_space(
    q0: Config,
    q1: Config,
    h: f64,
    m: f64,
    g: f64,
    j1: f64,
    j2: f64,
    j3: f64,
    thrust: f64,
) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.b.rotation.transpose() * q1.b.rotation;
    let dx = q1.b.translation - q0.b.translation;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
        - 0.5 * h * m * g * (q0.b.translation.z + q1.b.translation.z)
}

/// The same body as a continuous Lagrangian, `L = ½ Ωᵀ J Ω + ½ m |ẋ|² − m g e3·x`, with the
/// thrust `T R e3` as a force, both by the trapezoid rule.
#[reduced_lagrangian(pose(b), rule = trapezoid,
    force = |dq| thrust * (q.b.rotation * Vector3::z()).dot(&dq.b.linear))]
#[allow(clippy::too_many_arguments)]
fn flying_body(
    q: Config,
    v: Velocity,
    m: f64,
    g: f64,
    j1: f64,
    j2: f64,
    j3: f64,
    thrust: f64,
) -> f64 {
    let (omega, xdot) = (v.b.angular, v.b.linear);
    0.5 * (j1 * omega.x * omega.x + j2 * omega.y * omega.y + j3 * omega.z * omega.z)
        + 0.5 * m * xdot.norm_squared()
        - m * g * q.b.translation.z
}

fn compiled(b: &Body) -> BodyInSpace {
    BodyInSpace {
        h: b.h,
        m: b.m,
        g: b.g,
        j1: b.j.x,
        j2: b.j.y,
        j3: b.j.z,
        thrust: b.thrust,
    }
}

fn continuous(b: &Body) -> FlyingBody {
    FlyingBody {
        h: b.h,
        m: b.m,
        g: b.g,
        j1: b.j.x,
        j2: b.j.y,
        j3: b.j.z,
        thrust: b.thrust,
    }
}

/// The stored state of the contract: `R` row by row, then `x`; the momentum `(Π, p)`.
fn stored(s: &State) -> LieState<12, 6> {
    let mut q = [0.0; 12];
    for i in 0..3 {
        for j in 0..3 {
            q[3 * i + j] = s.r[(i, j)];
        }
        q[9 + i] = s.x[i];
    }
    let p = [s.pi.x, s.pi.y, s.pi.z, s.p.x, s.p.y, s.p.z];
    LieState::from_row_major(q, p)
}

/// [`stored`]'s inverse.
fn read(s: &LieState<12, 6>) -> State {
    State {
        r: Matrix3::from_fn(|i, j| s.q[3 * i + j]),
        x: Vector3::new(s.q[9], s.q[10], s.q[11]),
        pi: Vector3::new(s.p[0], s.p[1], s.p[2]),
        p: Vector3::new(s.p[3], s.p[4], s.p[5]),
    }
}

/// Newton to round-off, for runs compared with a reference solved to round-off.
fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-13,
        rel_tol: 1e-13,
        ..NewtonOptions::default()
    }
}

/// Newton at the round-off of the step's own equations (`1e-15`, a hundredth of [`tight`]).
fn round_off() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-15,
        rel_tol: 1e-15,
        ..NewtonOptions::default()
    }
}

/// `(|R − R'|, |x − x'|, |Π − Π'|, |p − p'|)`, the largest entry of each, over two runs.
fn deviations(a: &[State], b: &[State]) -> [f64; 4] {
    let mut worst = [0.0_f64; 4];
    for (a, b) in a.iter().zip(b) {
        let d = [
            (a.r - b.r).amax(),
            (a.x - b.x).amax(),
            (a.pi - b.pi).amax(),
            (a.p - b.p).amax(),
        ];
        for (w, d) in worst.iter_mut().zip(d) {
            *w = w.max(d);
        }
    }
    worst
}

/// A body spinning about its major axis, held upright by the spin (its third axis vertical, a
/// little nutation), its thrust about balancing its weight (`T = 30`, `m g = 29.4`): it hovers,
/// and every part of its state stays of order 1 to 10.
fn hovering() -> (Body, State) {
    let b = body(0.01, 9.81, 30.0);
    let s = State {
        r: cayley_half(&Vector3::new(0.0, 0.0, 0.3)),
        x: Vector3::new(0.5, -0.2, 1.0),
        pi: Vector3::new(0.2, -0.1, 15.0),
        p: Vector3::new(0.3, -0.2, 0.1),
    };
    (b, s)
}

/// 1000 steps of the pose system and of the reference from `s`: the largest deviation of each
/// part (`R`, `x`, `Π`, `p`), absolute and relative to the part's largest entry over the run.
fn against_reference(b: &Body, s: &State, options: NewtonOptions) -> ([f64; 4], [f64; 4]) {
    let traj = LieIntegrator::new(compiled(b), options)
        .run(stored(s))
        .steps(1000)
        .collect()
        .map_err(|e| e.source)
        .unwrap();
    let states: Vec<State> = traj.states.iter().map(read).collect();
    let reference = b.run(*s, 1000);
    let d = deviations(&states, &reference);
    let size = |f: &dyn Fn(&State) -> f64| reference.iter().map(f).fold(0.0, f64::max);
    let sizes = [
        1.0,
        size(&|s| s.x.amax()),
        size(&|s| s.pi.amax()),
        size(&|s| s.p.amax()),
    ];
    (d, std::array::from_fn(|i| d[i] / sizes[i]))
}

/// The pose system takes the reference's steps over 1000 steps: `R` to 1e-12 and `x`, `Π`, `p`
/// to 1e-12 of their size over the run (coasting: `|x|` ≤ 4, `|Π|` ≈ 1; hovering: `|x|` ≤ 11,
/// `|Π|` = 15; falling: `|x|` ≈ 490, `|p|` ≈ 290); thrusting while tumbling, to 2e-12
/// (measured: `R` 8.9e-13, `Π` 5.7e-13 of its size).
///
/// Newton solves to [`round_off`]: its residual test is one norm over the whole chart,
/// `‖R‖∞ ≤ abs_tol + rel_tol·ρ` with `ρ` the largest momentum, here the linear `|p|` against
/// `|Π|` ≈ 1, so the rotation's part of the residual is accepted at `rel_tol·|p|` and only a
/// tolerance well below the reference's solves it as tightly. That takes the translation's
/// residual `m (x1 − x0)/h − ..` to the round-off of the momenta wherever the body is: it reads
/// the chart increment `v` of `x1 = x0 + v` itself, not `(x0 + v) − x0`, which is `v` rounded
/// at `|x0|` and would put a floor of `ε |x| m/h` ≈ 3e-11 under it (Newton at `1e-15` would
/// stop converging after some 200 falling steps).
#[test]
fn a_pose_steps_as_the_hand_written_lgvi() {
    let (hover, hover_start) = hovering();
    for (what, b, s, tolerance) in [
        ("coasting", body(0.01, 0.0, 0.0), start(), 1e-12),
        ("hovering", hover, hover_start, 1e-12),
        ("falling", body(0.01, 9.81, 0.0), start(), 1e-12),
        ("thrusting", body(0.01, 9.81, 40.0), start(), 2e-12),
    ] {
        let (d, r) = against_reference(&b, &s, round_off());
        println!(
            "{what}: R {:.1e}, x {:.1e}, Π {:.1e}, p {:.1e} (relative: x {:.1e}, Π {:.1e}, p {:.1e})",
            d[0], d[1], d[2], d[3], r[1], r[2], r[3]
        );
        assert!(r.iter().all(|d| *d < tolerance), "{what}: {r:?}");
    }
}

/// Without forces the momentum map of rigid motions is kept: `ℓ` and `π` from the runtime's
/// momentum map, which is also checked against `(p, R Π + x × p)`. `ℓ` to round-off of `p`;
/// `π` to the round-off of storing the positions, as in the hand-written steps: the step solves
/// for the increment `v` exactly and stores `x_{k+1} = x_k + v`, rounded at `|x|`, which moves
/// `x × p` by up to `ε |x| |p|` a step (no more than the reference's own drift over the run).
#[test]
fn a_free_pose_keeps_its_linear_and_angular_momentum() {
    let b = body(0.01, 0.0, 0.0);
    let integ = LieIntegrator::new(compiled(&b), NewtonOptions::default());
    let s0 = stored(&start());
    let (l0, pi0) = start().momentum_map();
    assert_eq!(integ.linear_momentum(&s0), l0);
    assert!((integ.spatial_momentum(&s0) - pi0).amax() < 1e-15);
    let traj = integ
        .run(s0)
        .steps(1000)
        .collect()
        .map_err(|e| e.source)
        .unwrap();
    let linear = traj
        .states
        .iter()
        .map(|s| (integ.linear_momentum(s) - l0).norm() / l0.norm())
        .fold(0.0, f64::max);
    let (angular, _) = angular_drift(traj.states.iter().map(|s| integ.spatial_momentum(s)));
    let (by_hand, _) = angular_drift(b.run(start(), 1000).iter().map(|s| s.momentum_map().1));
    println!(
        "free: ℓ drifts by {linear:e}, π by {angular:e} (relative, 1000 steps; \
         the hand-written steps' π by {by_hand:e})"
    );
    assert!(linear < 1e-14, "ℓ drifts by {linear:e}");
    assert!(angular < 1e-13, "π drifts by {angular:e}");
}

/// Gravity keeps the horizontal translations and the rotations about the vertical (`π_3` to the
/// round-off of storing the positions, as without forces).
#[test]
fn a_pose_in_gravity_keeps_its_horizontal_linear_and_vertical_angular_momentum() {
    let b = body(0.01, 9.81, 0.0);
    let integ = LieIntegrator::new(compiled(&b), NewtonOptions::default());
    let traj = integ
        .run(stored(&start()))
        .steps(1000)
        .collect()
        .map_err(|e| e.source)
        .unwrap();
    let l0 = integ.linear_momentum(&traj.states[0]);
    let horizontal = traj
        .states
        .iter()
        .map(|s| {
            let l = integ.linear_momentum(s);
            (l.x - l0.x).abs().max((l.y - l0.y).abs()) / l0.norm()
        })
        .fold(0.0, f64::max);
    let (_, vertical) = angular_drift(traj.states.iter().map(|s| integ.spatial_momentum(s)));
    let (_, by_hand) = angular_drift(b.run(start(), 1000).iter().map(|s| s.momentum_map().1));
    println!(
        "gravity: horizontal ℓ drifts by {horizontal:e}, vertical π by {vertical:e} \
         (the hand-written steps' by {by_hand:e})"
    );
    assert!(horizontal < 1e-14, "horizontal ℓ drifts by {horizontal:e}");
    assert!(vertical < 1e-13, "vertical π drifts by {vertical:e}");
    // The vertical momentum falls by m g h per step: not kept.
    let fall = integ.linear_momentum(traj.last()).z - l0.z;
    assert!((fall + b.m * b.g * 10.0).abs() < 1e-10, "{fall}");
}

/// With gravity and thrust, the forced discrete Noether balance of both parts, step by step:
/// `ℓ_{k+1} − ℓ_k = (h/2)(f_k + f_{k+1})` and
/// `π_{k+1} − π_k = (h/2)(x_k × f_k + x_{k+1} × f_{k+1})`, with the total force
/// `f = T R e3 − m g e3` and its moment about the origin: each to round-off of the momentum's
/// size (`|ℓ|` up to 200 here; for `π`, of its terms' `|Π| + |x| |p|`).
#[test]
fn a_thrusting_pose_balances_the_impulse_and_its_moment() {
    let b = body(0.01, 9.81, 40.0);
    let integ = LieIntegrator::new(compiled(&b), NewtonOptions::default());
    let traj = integ
        .run(stored(&start()))
        .steps(1000)
        .collect()
        .map_err(|e| e.source)
        .unwrap();
    let (mut linear, mut angular): (f64, f64) = (0.0, 0.0);
    for w in traj.states.windows(2) {
        let (a, c) = (read(&w[0]), read(&w[1]));
        let (fa, fc) = (b.force(&a.r), b.force(&c.r));
        let (l0, l1) = (integ.linear_momentum(&w[0]), integ.linear_momentum(&w[1]));
        let (pi0, pi1) = (integ.spatial_momentum(&w[0]), integ.spatial_momentum(&w[1]));
        let impulse = (fa + fc) * (b.h / 2.0);
        let moment = (a.x.cross(&fa) + c.x.cross(&fc)) * (b.h / 2.0);
        linear = linear.max((l1 - l0 - impulse).amax() / l1.norm());
        // π's terms are larger than π itself: round-off is relative to them.
        let terms = c.pi.norm() + c.x.norm() * c.p.norm();
        angular = angular.max((pi1 - pi0 - moment).amax() / terms);
    }
    println!("thrust: impulse balance off by {linear:e}, its moment's by {angular:e} (relative)");
    assert!(linear < 1e-14, "the impulse is off by {linear:e}");
    assert!(
        angular < 1e-14,
        "the moment of the impulse is off by {angular:e}"
    );
}

/// The (−) integrator solves for the current point in the chart at the next one, and the pose's
/// chart is inverted by a sign (`cay(−ξ) = cay(ξ)ᵀ`, `x − v`): its equations are the (+) ones
/// at `z = −w`, and negation is exact, so the steps are the same bit for bit.
#[test]
fn the_minus_integrator_takes_the_same_steps_bit_for_bit() {
    let b = body(0.01, 9.81, 40.0);
    let plus = LieIntegrator::new(compiled(&b), NewtonOptions::default())
        .run(stored(&start()))
        .steps(1000)
        .collect()
        .map_err(|e| e.source)
        .unwrap();
    let minus = LieIntegrator::minus(compiled(&b), NewtonOptions::default())
        .run(stored(&start()))
        .steps(1000)
        .collect()
        .map_err(|e| e.source)
        .unwrap();
    assert_eq!(plus.states, minus.states);
}

/// `max |state_N − state(1)|` after `n` steps of `1/n` against the exact motion.
fn error_at_one(n: usize, rule: bool) -> f64 {
    let b = body(1.0 / n as f64, 9.81, 40.0);
    let last = if rule {
        *LieIntegrator::new(continuous(&b), tight())
            .run(stored(&start()))
            .steps(n)
            .collect()
            .map_err(|e| e.source)
            .unwrap()
            .last()
    } else {
        *LieIntegrator::new(compiled(&b), tight())
            .run(stored(&start()))
            .steps(n)
            .collect()
            .map_err(|e| e.source)
            .unwrap()
            .last()
    };
    distance(&read(&last), &reference::exact(&b, &start(), 1.0))
}

#[test]
fn a_pose_has_order_two_against_euler_and_newton() {
    for rule in [false, true] {
        let errors: Vec<f64> = [20, 40, 80]
            .iter()
            .map(|&n| error_at_one(n, rule))
            .collect();
        for w in errors.windows(2) {
            let order = (w[0] / w[1]).log2();
            println!("rule = {rule}: order {order:.3} from {errors:?}");
            assert!((order - 2.0).abs() < 0.1, "order {order} from {errors:?}");
        }
    }
}

#[test]
fn the_attitude_stays_a_rotation_over_ten_thousand_steps() {
    let b = body(0.01, 9.81, 40.0);
    let integ = LieIntegrator::new(compiled(&b), NewtonOptions::default());
    let mut worst: f64 = 0.0;
    integ
        .run(stored(&start()))
        .steps(10_000)
        .observe(|_, _, s: &LieState<12, 6>, _| {
            let r = read(s).r;
            worst = worst.max((r.transpose() * r - Matrix3::identity()).amax());
        })
        .stream()
        .unwrap();
    println!("|RᵀR − I| ≤ {worst:e} over 10⁴ steps");
    assert!(worst < 1e-13, "|RᵀR − I| = {worst:e}");
}

/// The continuous form's translation is the discrete one's (`h/2 (½ m |ẋ|² + ½ m |ẋ|²)` with
/// `ẋ = (x1 − x0)/h` is `m |x1 − x0|²/(2h)`, the potential the same trapezoid): without thrust,
/// which couples it to the attitude, its positions and linear momenta are the discrete
/// form's to round-off. Its rotation differs (`h/2 ΩᵀJΩ` at the Cayley velocity against the
/// LGVI's `tr((I − F) J_d)/h`, `O(h³)` apart per step): the attitudes agree to `O(h²)`.
#[test]
fn the_continuous_form_agrees_with_the_discrete_one() {
    let b = body(0.01, 9.81, 0.0);
    let run = |rule: bool| -> Vec<State> {
        let s0 = stored(&start());
        let states = if rule {
            LieIntegrator::new(continuous(&b), tight())
                .run(s0)
                .steps(1000)
                .collect()
                .map_err(|e| e.source)
                .unwrap()
                .states
        } else {
            LieIntegrator::new(compiled(&b), tight())
                .run(s0)
                .steps(1000)
                .collect()
                .map_err(|e| e.source)
                .unwrap()
                .states
        };
        states.iter().map(read).collect()
    };
    let (a, c) = (run(false), run(true));
    let translation = a
        .iter()
        .zip(&c)
        .map(|(a, c)| (a.x - c.x).amax().max((a.p - c.p).amax()))
        .fold(0.0, f64::max);
    println!("continuous against discrete, translation: {translation:e}");
    assert!(translation < 1e-12, "{translation:e}");
    // The attitudes at t = 1: the difference falls by 4 as the step halves.
    let attitude = |n: usize| {
        let b = body(1.0 / n as f64, 9.81, 40.0);
        let ends: Vec<Matrix3<f64>> = [false, true]
            .iter()
            .map(|&rule| {
                let s0 = stored(&start());
                let last = if rule {
                    *LieIntegrator::new(continuous(&b), tight())
                        .run(s0)
                        .steps(n)
                        .collect()
                        .map_err(|e| e.source)
                        .unwrap()
                        .last()
                } else {
                    *LieIntegrator::new(compiled(&b), tight())
                        .run(s0)
                        .steps(n)
                        .collect()
                        .map_err(|e| e.source)
                        .unwrap()
                        .last()
                };
                read(&last).r
            })
            .collect();
        (ends[0] - ends[1]).amax()
    };
    let ratio = attitude(20) / attitude(40);
    assert!((ratio - 4.0).abs() < 0.4, "ratio {ratio}");
}

/// A start whose attitude is not a rotation, or whose position is not finite, is refused with
/// a typed error before the first step.
#[test]
fn a_pose_off_the_group_or_not_finite_is_refused() {
    let b = body(0.01, 9.81, 40.0);
    let integ = LieIntegrator::new(compiled(&b), NewtonOptions::default());
    let mut s0 = stored(&start());
    s0.q[1] += 1e-6;
    let err = integ.run(s0).steps(10).collect().unwrap_err();
    assert!(matches!(err.source, StepError::OffManifold { .. }), "{err}");
    assert_eq!(err.trajectory.states.len(), 1);
    let mut s0 = stored(&start());
    s0.q[10] = f64::NAN;
    let err = integ.run(s0).steps(10).collect().unwrap_err();
    assert!(
        matches!(err.source, StepError::NonFinite { step: 0, .. }),
        "{err}"
    );
    assert_eq!(err.trajectory.states.len(), 1);
}

/// The emitted types store a pose as the contract says, `R` row by row then `x`, its momentum
/// `(Π, p)`, and read it back.
#[test]
fn the_emitted_types_store_the_pose_row_by_row_then_the_position() {
    let sys = compiled(&body(0.01, 9.81, 40.0));
    let s = start();
    let state = sys.state(
        &BodyInSpaceConfig {
            b: BodyInSpacePose {
                rotation: s.r,
                translation: s.x,
            },
        },
        &BodyInSpaceMomentum {
            b: BodyInSpacePoseMomentum {
                angular: s.pi,
                linear: s.p,
            },
        },
    );
    assert_eq!(state, stored(&s));
    let (q, p) = (sys.config(&state).b, sys.momenta(&state).b);
    assert_eq!((q.rotation, q.translation), (s.r, s.x));
    assert_eq!((p.angular, p.linear), (s.pi, s.p));
}

/// A falling body at the default Newton options for 5·10⁴ steps (500 s, `|x|` up to 1.2·10⁶):
/// every step converges, and the translation is the discrete free fall, which is the exact
/// parabola. With `f = −m g e3` constant the step is `x_{k+1} = x_k + (h/m) p_k + (h²/(2m)) f`,
/// `p_{k+1} = p_k + h f`, so `p_k = p_0 + t_k f` and
/// `x_k = x_0 + (h/m) Σ_{j<k} (p_0 + j h f) + k h² f/(2m) = x_0 + t_k p_0/m + t_k² f/(2m)`
/// (`Σ_{j<k} j = k(k − 1)/2`): the trapezoid rule integrates a constant force exactly. The
/// position and momentum are held to it to the round-off of their size accumulated over the
/// steps (`n ε` ≈ 1.1e-11 at most), and the attitude and body momentum (decoupled from the
/// translation) to the hand-written integrator's to 1e-8: at the default options the rotation's
/// part of the residual is accepted at `rel_tol |p|`, with `|p|` up to 1.5·10⁴.
///
/// Before the step read its chart increment, the translation's residual had a floor of
/// `ε |x| m/h`, above the default tolerance `1e-12 |p|` from `t` ≈ 231 s on.
#[test]
fn a_falling_pose_converges_for_fifty_thousand_steps_at_the_default_options() {
    let b = body(0.01, 9.81, 0.0);
    let n = 50_000;
    let s0 = start();
    let reference = b.run(s0, n);
    let force = Vector3::new(0.0, 0.0, -b.m * b.g);
    let (mut position, mut momentum, mut rotation): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut last = 0;
    LieIntegrator::new(compiled(&b), NewtonOptions::default())
        .run(stored(&s0))
        .steps(n)
        .observe(|k, _, s: &LieState<12, 6>, _| {
            let s = read(s);
            let t = k as f64 * b.h;
            let x = s0.x + s0.p * (t / b.m) + force * (t * t / (2.0 * b.m));
            let p = s0.p + force * t;
            position = position.max((s.x - x).amax() / x.amax());
            momentum = momentum.max((s.p - p).amax() / p.amax());
            let r = &reference[k];
            rotation = rotation.max((s.r - r.r).amax().max((s.pi - r.pi).amax()));
            last = k;
        })
        .stream()
        .map_err(|e| e.source)
        .unwrap();
    println!(
        "falling for {last} steps at the default options: x {position:.1e}, p {momentum:.1e} \
         (relative to the parabola), R and Π {rotation:.1e} (from the hand-written steps)"
    );
    assert_eq!(last, n);
    assert!(position < 1e-11, "x is off the parabola by {position:e}");
    assert!(momentum < 1e-11, "p is off by {momentum:e}");
    assert!(rotation < 1e-8, "the attitude is off by {rotation:e}");
}

/// The free body in space (no gravity, no thrust), reduced by every rigid motion of its pose.
#[reduced_lagrangian(pose(b), rule = trapezoid, symmetry(b))]
fn free_body_in_space(_q: Config, v: Velocity, m: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let (omega, xdot) = (v.b.angular, v.b.linear);
    0.5 * (j1 * omega.x * omega.x + j2 * omega.y * omega.y + j3 * omega.z * omega.z)
        + 0.5 * m * xdot.norm_squared()
}

/// Reduced by the rigid motions, the free body takes the unreduced steps (to round-off), its
/// spatial momentum `(π, p)` the run's parameter: `p` copied bit for bit, `R Π + x × p = π` at
/// every step to the round-off of one evaluation, far from the origin too, where the
/// unreduced step's `π` gathers the round-off of `x × p` step by step.
#[test]
fn reduced_by_rigid_motions_the_free_body_keeps_its_spatial_momentum() {
    let sys = FreeBodyInSpace {
        h: 0.01,
        m: 3.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    // Drifting fast, from 100 m away: |x × p| is large against |π|.
    let mut s = start();
    s.x = Vector3::new(100.0, -50.0, 30.0);
    s.p = Vector3::new(30.0, -12.0, 18.0);
    let state = stored(&s);
    let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let unreduced = LieIntegrator::new(sys, NewtonOptions::default());
    let steps = 20_000;
    let a = reduced
        .run(reduced.reduce(&state))
        .steps(steps)
        .collect()
        .unwrap();
    let b = unreduced.run(state).steps(steps).collect().unwrap();
    let (pi, p) = (a.states[0].mu, read(&state).p);
    let mut worst_reduced: f64 = 0.0;
    let mut worst_unreduced: f64 = 0.0;
    for (x, y) in a.states.iter().zip(&b.states) {
        assert_eq!(read(&x.unreduced()).p, p, "p is copied bit for bit");
        assert_eq!(x.mu, pi);
        let m = reduced.momentum_map(&x.unreduced()).unwrap();
        worst_reduced = worst_reduced.max((m - pi).norm() / pi.norm());
        let m = reduced.momentum_map(y).unwrap();
        worst_unreduced = worst_unreduced.max((m - pi).norm() / pi.norm());
    }
    // The two runs part only as the tumbling amplifies their round-off.
    let gap = distance(&read(&a.states[500].unreduced()), &read(&b.states[500]));
    println!(
        "rigid motions: reduced π within {worst_reduced:.1e}, unreduced {worst_unreduced:.1e}; \
         reduced against unreduced {gap:.1e} after 500 steps"
    );
    // One evaluation of R Π + x × p: a few ε |x| |p| / |π|.
    let scale = f64::EPSILON * s.x.norm() * s.p.norm() / pi.norm();
    assert!(
        worst_reduced < 8.0 * scale,
        "{worst_reduced:e} against {scale:e}"
    );
    let size = read(&b.states[500]).x.amax().max(1.0);
    assert!(gap < 1e-12 * size, "{gap:e} at |x| = {size}");
    assert!(worst_unreduced > worst_reduced);
}
