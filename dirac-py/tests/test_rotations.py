"""Systems on rotation groups from Python: a rigid body against a Lie group variational
integrator written here in NumPy, the reduced runs of both kinds of symmetry against the
unreduced ones, adaptive steps started from a velocity, Parquet, the errors, and a rigid body in
space (a pose) against an SE(3) integrator written here in NumPy."""


import numpy as np
import pytest

import dirac

from sources import function


RIGID_BODY = function("src/systems/rotations.rs", "rigid_body")
HEAVY_TOP = function("src/systems/rotations.rs", "heavy_top")
DSP_ON_SPHERES = function("src/systems/rotations.rs", "dsp_on_spheres")


def cayley(x):
    """cay(x) = I + 4/(4 + |x|²) (x̂ + x̂²/2)."""
    hat = np.array([[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]])
    return np.eye(3) + 4.0 / (4.0 + x @ x) * (hat + hat @ hat / 2.0)


def vee(a):
    return np.array([a[2, 1], a[0, 2], a[1, 0]])


def lgvi(r, pi, j, h, steps):
    """The free rigid body's Lie group variational integrator (Lee, Leok & McClamroch):
    h Π_k = vee(F J_d − J_d Fᵀ) solved for F = cay(z) by Newton with a central-difference
    Jacobian, Π_{k+1} = Fᵀ Π_k, R_{k+1} = R_k F; J_d = tr(J)/2 I − J."""
    jd = np.trace(j) / 2.0 * np.eye(3) - j
    rs, pis = [r], [pi]
    z = np.zeros(3)
    for _ in range(steps):
        def g(z):
            f = cayley(z)
            return vee(f @ jd - jd @ f.T) - h * pi
        for _ in range(50):
            jac = np.column_stack([(g(z + e) - g(z - e)) / 2e-7 for e in 1e-7 * np.eye(3)])
            dz = np.linalg.solve(jac, -g(z))
            z = z + dz
            if np.linalg.norm(dz) < 1e-16:
                break
        f = cayley(z)
        r, pi = r @ f, f.T @ pi
        rs.append(r)
        pis.append(pi)
    return np.array(rs), np.array(pis)


def test_a_rigid_body_from_text_is_the_lie_group_variational_integrator():
    body = dirac.compile(RIGID_BODY)
    assert isinstance(body, dirac.LieSystem)
    assert body.coordinates == [("r", "rotation")]
    assert body.symmetry == ("rotations", ["r"])
    assert body.parameters == ["h", "j1", "j2", "j3"]
    params = {"h": 0.05, "j1": 1.0, "j2": 2.0, "j3": 3.0}
    r0, pi0 = cayley(np.array([0.1, 0.2, -0.3])), np.array([0.3, 1.0, 0.2])
    run = body.run(params, steps=200, q={"r": r0}, p={"r": pi0})
    assert run["t"].shape == (201,)
    assert run["q"]["r"].shape == (201, 3, 3) and run["p"]["r"].shape == (201, 3)
    assert run["spatial_momentum"].shape == (201, 3)
    assert run["iterations"].shape == (200,)
    rs, pis = lgvi(r0, pi0, np.diag([1.0, 2.0, 3.0]), 0.05, 200)
    assert np.max(np.abs(run["q"]["r"] - rs)) < 1e-11
    assert np.max(np.abs(run["p"]["r"] - pis)) < 1e-11
    # The spatial angular momentum R Π is kept.
    assert np.max(np.abs(run["spatial_momentum"] - r0 @ pi0)) < 1e-12
    # The reduced run (every rotation) takes the same steps, π carried as a parameter.
    reduced = body.run(params, steps=200, q={"r": r0}, p={"r": pi0}, method="reduced")
    assert np.max(np.abs(reduced["q"]["r"] - run["q"]["r"])) < 1e-12
    assert np.all(reduced["mu"] == reduced["mu"][0])
    # The composition of order 4 from the same start.
    four = body.run(params, steps=20, q={"r": r0}, p={"r": pi0}, order=4)
    assert four["q"]["r"].shape == (21, 3, 3)


def test_the_double_spherical_pendulum_on_two_spheres_reduced_about_the_vertical():
    dsp = dirac.compile(DSP_ON_SPHERES)
    assert dsp.coordinates == [("n1", "direction"), ("n2", "direction")]
    assert dsp.symmetry == ("axis z", ["n1", "n2"])
    params = dict(h=0.01, m1=1.0, m2=1.0, l1=1.0, l2=1.0, g=9.81)
    n1 = np.array([0.6, 0.0, -0.8])
    n2 = np.array([0.0, 0.6, -0.8])
    q = {"n1": n1, "n2": n2}
    p = {"n1": [0.0, 0.5, 0.0], "n2": [0.3, 0.0, 0.0]}
    run = dsp.run(params, steps=500, q=q, p=p)
    assert run["q"]["n1"].shape == (501, 3) and run["p"]["n2"].shape == (501, 3)
    assert np.max(np.abs(np.linalg.norm(run["q"]["n1"], axis=1) - 1.0)) < 1e-14
    # Momenta are tangent to their spheres.
    assert np.max(np.abs(np.sum(run["q"]["n2"] * run["p"]["n2"], axis=1))) < 1e-12
    reduced = dsp.run(params, steps=500, q=q, p=p, method="reduced")
    # μ e₃, the vertical angular momentum, exactly constant; the same motion.
    assert np.all(reduced["mu"] == reduced["mu"][0]) and reduced["mu"][0, 2] != 0.0
    assert np.max(np.abs(reduced["q"]["n2"] - run["q"]["n2"])) < 1e-9
    minus = dsp.run(params, steps=500, q=q, p=p, method="minus")
    assert np.max(np.abs(minus["q"]["n1"] - run["q"]["n1"])) < 1e-9


def test_adaptive_steps_start_from_a_velocity():
    swing = dirac.compile(
        "#[reduced_lagrangian(direction(n), group(t), rule = trapezoid, symmetry(n, axis = z),\n"
        "    time(t), adapt = |q| 1.5 + q.n.z)]\n"
        "fn swinging(q: Config, v: Velocity, g: f64) -> f64 { 0.5 * v.n.dot(&v.n) - g * q.n.z }")
    assert swing.parameters == ["g", "h"]
    # Released from rest at 53° from the vertical, slightly off its plane.
    run = swing.run({"g": 1.0, "h": 0.05}, steps=400, q={"n": [0.8, 0.0, -0.6], "t": 0.0},
                    v={"n": [0.0, 0.05, 0.0], "t": 1.0})
    steps = np.diff(run["q"]["t"])
    # Physical time advances by ε g(n): shorter steps near the bottom (n_z = −1).
    assert np.all(steps > 0) and steps.max() / steps.min() > 1.5
    # The energy −p_t is kept to the order of the method.
    energy = -run["p"]["t"]
    assert np.max(np.abs(energy - energy[0])) < 1e-12
    with pytest.raises(ValueError, match="adaptive"):
        dirac.compile(RIGID_BODY).run({"h": 0.1, "j1": 1, "j2": 2, "j3": 3}, steps=1,
                                      q={"r": np.eye(3)}, v={"r": [1.0, 0.0, 0.0]})


def test_a_failed_step_raises_with_the_trajectory_so_far():
    # A body spinning about x under a potential √(R₂₂ − 1/2), NaN once it has turned by 60°.
    wall = dirac.compile(
        "#[reduced_lagrangian(rotation(r))]\n"
        "fn wall(q0: Config, q1: Config, h: f64, c: f64) -> f64 {\n"
        "    let f = q0.r.transpose() * q1.r;\n"
        "    ((Matrix3::identity() - f) * Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 1.0))).trace() / h\n"
        "        - h * c * (q0.r[(2, 2)] - 0.5).sqrt()\n"
        "}")
    with pytest.raises(dirac.StepError) as info:
        wall.run({"h": 0.1, "c": 1e-6}, steps=100, q={"r": np.eye(3)}, p={"r": [1.0, 0.0, 0.0]})
    e = info.value
    assert 0 < e.step < 100
    traj = e.trajectory["q"]["r"]
    assert traj.shape == (e.step + 1, 3, 3)
    assert np.all(np.isfinite(traj)) and traj[-2, 2, 2] > 0.5


def test_bad_input_raises_value_errors():
    top = dirac.compile(HEAVY_TOP)
    assert top.symmetry == ("axis z", ["r"])
    params = {"h": 0.01, "j1": 1.0, "j2": 1.0, "j3": 0.5, "mgl": 2.0}
    with pytest.raises(ValueError, match="is not a rotation"):
        top.run(params, steps=1, q={"r": np.ones((3, 3))}, p={"r": [0, 0, 1]})
    with pytest.raises(ValueError, match="needs `r`"):
        top.run(params, steps=1, q={}, p={"r": [0, 0, 1]})
    with pytest.raises(ValueError, match="not a coordinate"):
        top.run(params, steps=1, q={"r": np.eye(3), "s": 1.0}, p={"r": [0, 0, 1]})
    with pytest.raises(ValueError, match="has 2 values"):
        top.run(params, steps=1, q={"r": np.eye(3)}, p={"r": [0, 1]})
    with pytest.raises(ValueError, match="unknown method"):
        top.run(params, steps=1, q={"r": np.eye(3)}, p={"r": [0, 0, 1]}, method="sideways")
    with pytest.raises(ValueError, match="declares no symmetry"):
        dirac.compile(RIGID_BODY.replace(", symmetry(r)", "")).run(
            {"h": 0.1, "j1": 1, "j2": 2, "j3": 3}, steps=1, q={"r": np.eye(3)},
            p={"r": [0, 0, 1]}, method="reduced")


def test_a_run_on_rotation_groups_written_to_parquet_reads_back_bit_for_bit(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    top = dirac.compile(HEAVY_TOP)
    params = {"h": 0.01, "j1": 1.0, "j2": 1.0, "j3": 0.5, "mgl": 2.0}
    start = dict(q={"r": cayley(np.array([0.4, -0.1, 0.2]))}, p={"r": [0.2, -0.1, 3.0]})
    out = tmp_path / "top.parquet"
    summary = top.write(params, steps=300, path=str(out), method="reduced", **start)
    assert summary["steps"] == 300
    table = pq.read_table(out)
    run = top.run(params, steps=300, method="reduced", **start)
    for i in range(3):
        for j in range(3):
            column = table.column(f"q_r_{i}{j}").to_numpy()
            assert np.array_equal(column, run["q"]["r"][:, i, j])
    for k, axis in enumerate("xyz"):
        assert np.array_equal(table.column(f"p_r_{axis}").to_numpy(), run["p"]["r"][:, k])
        assert np.array_equal(table.column(f"mu_{axis}").to_numpy(), run["mu"][:, k])


FREE_BODY_IN_SPACE = """
#[reduced_lagrangian(pose(b))]
fn free_body(q0: Config, q1: Config, h: f64, m: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let f = q0.b.rotation.transpose() * q1.b.rotation;
    let jd = Matrix3::from_diagonal(&Vector3::new(j1, j2, j3));
    let jd = 0.5 * jd.trace() * Matrix3::identity() - jd;
    let dx = q1.b.translation - q0.b.translation;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
}
"""


def test_a_pose_is_given_and_returned_as_its_12_numbers_and_6_momenta():
    """A free rigid body in space, pose(b): its q rows are the rotation row by row then the
    position (shape (12,)), its p rows the body angular then the spatial linear momentum (6,).
    The attitude is the rigid body's LGVI, the centre moves by h p/m a step, and both parts of
    the momentum map of rigid motions, l = p and pi = R Pi + x × p, are kept."""
    body = dirac.compile(FREE_BODY_IN_SPACE)
    assert body.coordinates == [("b", "pose")]
    params = {"h": 0.05, "m": 2.0, "j1": 1.0, "j2": 2.0, "j3": 3.0}
    r0, x0 = cayley(np.array([0.1, 0.2, -0.3])), np.array([1.0, -2.0, 0.5])
    pi0, p0 = np.array([0.3, 1.0, 0.2]), np.array([0.4, 0.1, -0.6])
    start = np.concatenate([r0.ravel(), x0])
    run = body.run(params, steps=200, q={"b": start}, p={"b": np.concatenate([pi0, p0])})
    q, p = run["q"]["b"], run["p"]["b"]
    assert q.shape == (201, 12) and p.shape == (201, 6)
    assert np.array_equal(q[0], start) and np.array_equal(p[0, :3], pi0)
    rs, pis = lgvi(r0, pi0, np.diag([1.0, 2.0, 3.0]), 0.05, 200)
    assert np.max(np.abs(q[:, :9].reshape(-1, 3, 3) - rs)) < 1e-11
    assert np.max(np.abs(p[:, :3] - pis)) < 1e-11
    steps = np.arange(201)[:, None]
    assert np.max(np.abs(q[:, 9:] - (x0 + steps * 0.05 * p0 / 2.0))) < 1e-12
    assert np.max(np.abs(p[:, 3:] - p0)) < 1e-13
    assert run["linear_momentum"].shape == (201, 3)
    assert np.max(np.abs(run["linear_momentum"] - p0)) < 1e-13
    pi = r0 @ pi0 + np.cross(x0, p0)
    assert np.max(np.abs(run["spatial_momentum"] - pi)) < 1e-12
    with pytest.raises(ValueError, match="has 9 values; a pose takes 12"):
        body.run(params, steps=1, q={"b": r0}, p={"b": np.zeros(6)})


BODY_IN_SPACE = """
#[reduced_lagrangian(pose(b),
    force = |dq0, dq1| 0.5 * h * thrust
        * ((q0.b.rotation * Vector3::z()).dot(&dq0.b.linear)
            + (q1.b.rotation * Vector3::z()).dot(&dq1.b.linear)))]
fn body_in_space(q0: Config, q1: Config, h: f64, m: f64, g: f64, thrust: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
    let f = q0.b.rotation.transpose() * q1.b.rotation;
    let dx = q1.b.translation - q0.b.translation;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
        - 0.5 * h * m * g * (q0.b.translation.z + q1.b.translation.z)
}
"""


def se3_lgvi(r, x, pi, p, j, m, g, thrust, h, steps):
    """The rigid body in space with gravity −g e3 and a thrust T R e3 (trapezoid rule), as
    tests/se3.rs derives it: with a = h Π_k, the Cayley parameter f of F_k = (I + f̂)(I − f̂)⁻¹
    solves G(f) = a + a × f + (a·f) f − 2 J f = 0 (Newton, ∇G = â + (a·f) I + f aᵀ − 2 J);
    R_{k+1} = R_k F_k, Π_{k+1} = F_kᵀ Π_k, x_{k+1} = x_k + (h/m) p_k + (h²/2m) f_k,
    p_{k+1} = p_k + (h/2)(f_k + f_{k+1}), f_k = T R_k e3 − m g e3."""
    def hat(v):
        return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])

    def force(r):
        return thrust * r[:, 2] - m * g * np.array([0.0, 0.0, 1.0])

    states = [(r, x, pi, p)]
    f = np.zeros(3)
    for _ in range(steps):
        a = h * pi
        for _ in range(50):
            residual = a + np.cross(a, f) + (a @ f) * f - 2.0 * j @ f
            jacobian = hat(a) + (a @ f) * np.eye(3) + np.outer(f, a) - 2.0 * j
            df = np.linalg.solve(jacobian, residual)
            f = f - df
            if np.max(np.abs(df)) <= 2e-16 * np.max(np.abs(f)):
                break
        s = hat(f)
        big_f = np.eye(3) + 2.0 / (1.0 + f @ f) * (s + s @ s)
        r_next = r @ big_f
        x = x + h / m * p + h * h / (2.0 * m) * force(r)
        p = p + h / 2.0 * (force(r) + force(r_next))
        r, pi = r_next, big_f.T @ pi
        states.append((r, x, pi, p))
    return [np.array(part) for part in zip(*states)]


def test_a_body_in_space_with_gravity_and_thrust_is_the_se3_integrator():
    """The body of tests/se3.rs from text: its attitude, position and both momenta against a
    NumPy SE(3) Lie group variational integrator over 300 steps (to 1e-12 of each part's size),
    and the linear momentum moved by exactly the forces' impulse at every step."""
    body = dirac.compile(BODY_IN_SPACE)
    assert body.coordinates == [("b", "pose")]
    params = {"h": 0.01, "m": 3.0, "g": 9.81, "thrust": 40.0}
    r0, x0 = cayley(np.array([0.3, -0.2, 0.4])), np.array([1.0, -2.0, 0.5])
    pi0, p0 = np.array([0.4, 1.0, -0.3]), np.array([0.9, -0.3, 0.6])
    run = body.run(
        params,
        steps=300,
        q={"b": np.concatenate([r0.ravel(), x0])},
        p={"b": np.concatenate([pi0, p0])},
    )
    q, p = run["q"]["b"], run["p"]["b"]
    j = np.diag([1.0, 2.0, 3.0])
    rs, xs, pis, ps = se3_lgvi(r0, x0, pi0, p0, j, 3.0, 9.81, 40.0, 0.01, 300)
    for got, want in [
        (q[:, :9].reshape(-1, 3, 3), rs),
        (q[:, 9:], xs),
        (p[:, :3], pis),
        (p[:, 3:], ps),
    ]:
        assert np.max(np.abs(got - want)) < 1e-12 * max(1.0, np.max(np.abs(want)))
    forces = 40.0 * q[:, [2, 5, 8]] - np.array([0.0, 0.0, 3.0 * 9.81])
    impulse = 0.005 * (forces[:-1] + forces[1:])
    linear = run["linear_momentum"]
    assert np.max(np.abs(np.diff(linear, axis=0) - impulse)) < 1e-14 * np.max(np.abs(linear))
