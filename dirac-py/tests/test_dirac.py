"""The Python package against the paper and against itself: Table 1 of the paper from Python,
the arrays' shapes, ensembles equal to single runs, the typed errors as exceptions, and systems
built from keyword arguments and from SymPy."""

import math
import pathlib

import numpy as np
import pytest

import dirac

from sources import function


CHARGED = function("src/paper.rs", "charged_particle")
DSP = function("src/paper.rs", "double_spherical_pendulum")
KEPLER = function("src/systems/kepler.rs", "kepler")

# The paper's Table 1: |q(T) − q_N| for the charged particle, T = 20 (as printed, 4–5 digits).
TABLE_1 = [(10, 1.6781), (50, 0.25971), (100, 0.06626), (200, 0.01664)]


def test_table_1_of_the_paper():
    particle = dirac.compile(CHARGED)
    assert particle.shape == ["x", "y", "z"]
    assert particle.group == ["theta"]
    assert particle.parameters == ["h", "m", "b0"]
    T = 20.0
    exact = np.array([math.sin(T), math.cos(T) - 1.0, T])
    for n, printed in TABLE_1:
        run = particle.run({"h": T / n, "m": 1.0, "b0": 1.0}, steps=n,
                           x=[0, 0, 0], w=[1, 0, 1], mu=[1], g=[0])
        error = np.linalg.norm(run["x"][-1] - exact)
        # The printed digits, rounded.
        assert abs(error - printed) <= 0.6 * 10 ** (math.floor(math.log10(printed)) - 3), (n, error)
        # μ is conserved exactly.
        assert np.all(run["mu"] == 1.0)


def test_arrays_have_the_documented_shapes():
    dsp = dirac.compile(DSP)
    params = dict(zip(dsp.parameters, [0.01, 1.0, 1.0, 1.0, 1.0, 9.81]))
    run = dsp.run(params, steps=50, x=[0.5, 0.1, 0.9], w=[0.0, 0.2, 0.0], mu=[0.3], g=[0.0])
    assert run["t"].shape == (51,)
    assert run["x"].shape == (51, 3) and run["w"].shape == (51, 3)
    assert run["mu"].shape == (51, 1) and run["g"].shape == (51, 1)
    assert run["iterations"].shape == (50,) and run["residuals"].shape == (50,)
    assert run["t"][-1] == pytest.approx(0.5)
    # The (−) equations and the unreduced ones integrate the same motion.
    minus = dsp.run(params, steps=50, method="minus",
                    x=[0.5, 0.1, 0.9], w=[0.0, 0.2, 0.0], mu=[0.3], g=[0.0])
    assert np.max(np.abs(minus["x"] - run["x"])) < 1e-9
    q0 = np.concatenate([run["x"][0], run["g"][0]])
    p0 = np.concatenate([run["w"][0], run["mu"][0]])  # B = 0: p = (w, μ)
    unreduced = dsp.run(params, steps=50, method="unreduced", q=q0, p=p0)
    names = dsp.shape + dsp.group
    assert list(unreduced["q"]) == names and list(unreduced["p"]) == names
    assert all(unreduced["q"][n].shape == (51,) for n in names)
    for i, n in enumerate(dsp.shape):
        assert np.max(np.abs(unreduced["q"][n] - run["x"][:, i])) < 1e-9
    # A reduced run's configuration and momenta by coordinate too: x and g, p by eq. (3.7).
    assert list(run["q"]) == names and list(run["p"]) == names
    for i, n in enumerate(dsp.shape):
        assert np.array_equal(run["q"][n], run["x"][:, i])
        assert np.array_equal(run["p"][n], run["w"][:, i])  # B = 0: p_x = w
    assert np.array_equal(run["q"][dsp.group[0]], run["g"][:, 0])
    assert np.array_equal(run["p"][dsp.group[0]], run["mu"][:, 0])


def test_compositions_of_order_4_and_6_are_more_accurate():
    kepler = dirac.compile(KEPLER)
    # One period of the e = 0.5 orbit (a = 1, k = 1): back at periapsis r = 0.5.
    n = 200
    h = 2 * math.pi / n
    start = dict(x=[0.5], w=[0.0], mu=[math.sqrt(0.75)], g=[0.0])
    errors = []
    for order in (2, 4, 6):
        run = kepler.run({"h": h, "k": 1.0}, steps=n, order=order, **start)
        errors.append(abs(run["x"][-1, 0] - 0.5))
    assert errors[1] < errors[0] / 10 and errors[2] < errors[1]


def test_an_ensemble_is_its_members_runs():
    kepler = dirac.compile(KEPLER)
    params = {"h": 0.01, "k": 1.0}
    rng = np.random.default_rng(7)
    m = 8
    x = 0.5 + 0.5 * rng.random((m, 1))
    w = 0.1 * rng.standard_normal((m, 1))
    mu = 0.8 + 0.2 * rng.random((m, 1))
    g = np.zeros((m, 1))
    ens = kepler.ensemble(params, steps=300, x=x, w=w, mu=mu, g=g)
    assert ens["x"].shape == (m, 301, 1) and ens["t"].shape == (m, 301)
    assert ens["failed"] == []
    for i in range(m):
        one = kepler.run(params, steps=300, x=x[i], w=w[i], mu=mu[i], g=g[i])
        assert np.array_equal(one["x"], ens["x"][i])
        assert np.array_equal(one["mu"], ens["mu"][i])


def test_a_failed_step_raises_with_the_trajectory_so_far():
    # A particle moving left in a potential c √x: its force c / (2 √x) is NaN once x < 0.
    sys = dirac.system("0.5 / h * (q1.x - q0.x) * (q1.x - q0.x) - h * c * q0.x.sqrt()",
                       shape=["x"], parameters=["c"])
    with pytest.raises(dirac.StepError) as info:
        sys.run({"h": 0.1, "c": 1e-6}, steps=100, x=[1.0], w=[-1.0], mu=[], g=[])
    e = info.value
    assert 0 < e.step < 100
    assert e.trajectory["x"].shape == (e.step + 1, 1)
    # Every state before the failure, the last one past the wall x = 0.
    assert np.all(np.isfinite(e.trajectory["x"]))
    assert np.all(e.trajectory["x"][:-1, 0] > 0) and e.trajectory["x"][-1, 0] <= 0
    assert "step" in str(e)


def test_mistakes_in_the_text_raise_with_lines_and_columns():
    with pytest.raises(dirac.CompileError) as info:
        dirac.compile("#[reduced_lagrangian(shape(r), group(phi))]\n"
                      "fn f(q0: Config, q1: Config, h: f64) -> f64 { q0.s }")
    (message, line, column), = info.value.diagnostics
    assert "unknown coordinate `s`" in message
    assert (line, column) == (2, 50)
    assert " --> 2:50" in str(info.value)


def test_a_pendulum_with_its_rod_as_a_constraint_swings_as_the_pendulum_equation():
    pendulum = dirac.compile(
        "#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,\n"
        "    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]\n"
        "fn f(q: Config, v: Velocity, m: f64, l: f64, g: f64) -> f64 {\n"
        "    0.5 * m * (v.x * v.x + v.y * v.y) - m * g * q.y\n"
        "}")
    assert pendulum.constraints == 1 and pendulum.holonomic
    l, g, h, steps = 1.5, 9.81, 0.002, 500
    th0 = 0.8
    q0 = [l * math.sin(th0), -l * math.cos(th0)]
    run = pendulum.run({"m": 1.0, "l": l, "g": g, "h": h}, steps=steps, method="unreduced",
                       q=q0, p=[0.0, 0.0])
    assert run["multipliers"].shape == (steps, 1)
    assert np.max(run["constraint_residuals"]) < 1e-10
    theta = np.arctan2(run["q"]["x"], -run["q"]["y"])
    # θ'' = −(g/l) sin θ by the classical Runge–Kutta method, 20 substeps per step.
    def rhs(y):
        return np.array([y[1], -g / l * math.sin(y[0])])
    y, k = np.array([th0, 0.0]), h / 20
    reference = [y[0]]
    for _ in range(steps):
        for _ in range(20):
            a = rhs(y)
            b = rhs(y + 0.5 * k * a)
            c = rhs(y + 0.5 * k * b)
            d = rhs(y + k * c)
            y = y + k / 6 * (a + 2 * b + 2 * c + d)
        reference.append(y[0])
    assert np.max(np.abs(theta - np.array(reference))) < 1e-4
    pq = pytest.importorskip("pyarrow.parquet")
    out = pathlib.Path(__import__("tempfile").mkdtemp()) / "rod.parquet"
    pendulum.write({"m": 1.0, "l": l, "g": g, "h": h}, steps=50, path=str(out),
                   method="unreduced", q=q0, p=[0.0, 0.0])
    table = pq.read_table(out)
    assert np.array_equal(table.column("q_x").to_numpy(), run["q"]["x"][:51])
    assert pq.read_metadata(next(out.glob("part-*.parquet"))).metadata[b"dirac.constraints"] == b"1"
    # An ensemble of one member: the run itself, bit for bit.
    ens = pendulum.ensemble({"m": 1.0, "l": l, "g": g, "h": h}, steps=2, method="unreduced",
                            q=np.array([q0]), p=np.zeros((1, 2)))
    assert np.array_equal(ens["q"]["x"][0], run["q"]["x"][:3])
    with pytest.raises(ValueError, match="order 2"):
        pendulum.run({"m": 1.0, "l": l, "g": g, "h": h}, steps=2, method="unreduced",
                     q=q0, p=[0.0, 0.0], order=4)
    # A bead on a vertical cylinder, free along its axis: reduced, μ exactly kept.
    bead = dirac.compile(
        "#[reduced_lagrangian(shape(x, y), group(z), rule = midpoint,\n"
        "    constraints = |q| [q.x * q.x + q.y * q.y - r * r])]\n"
        "fn bead(q: Config, v: Velocity, m: f64, r: f64) -> f64 {\n"
        "    0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) - 0.5 * (q.x - 0.3) * (q.x - 0.3)\n"
        "}")
    run = bead.run({"m": 1.0, "r": 1.0, "h": 0.01}, steps=300, x=[1.0, 0.0], w=[0.0, 0.8],
                   mu=[0.4], g=[0.0])
    assert np.all(run["mu"] == 0.4)
    assert np.max(run["constraint_residuals"]) < 1e-10
    # Beyond the fixed-size instances (4 constraints): compiled, to run on its element view
    # (test_sizes.py runs 20 constraints).
    four = dirac.compile("#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,\n"
                         "    constraints = |q| [q.x, q.y, q.x + q.y, q.x - q.y])]\n"
                         "fn f(q: Config, v: Velocity, m: f64) -> f64 { 0.5 * m * (v.x * v.x + v.y * v.y) }")
    assert four.constraints == 4


def test_bad_input_raises_value_errors():
    kepler = dirac.compile(KEPLER)
    start = dict(x=[0.5], w=[0.0], mu=[1.0], g=[0.0])
    with pytest.raises(ValueError, match="parameter `k` not given"):
        kepler.run({"h": 0.01}, steps=1, **start)
    with pytest.raises(ValueError, match="no parameter `kk`"):
        kepler.run({"h": 0.01, "k": 1.0, "kk": 2.0}, steps=1, **start)
    with pytest.raises(ValueError, match="`x` has 2 values"):
        kepler.run({"h": 0.01, "k": 1.0}, steps=1, x=[0.5, 1.0], w=[0.0], mu=[1.0], g=[0.0])
    with pytest.raises(ValueError, match="not finite"):
        kepler.run({"h": 0.01, "k": 1.0}, steps=1, x=[float("nan")], w=[0.0], mu=[1.0], g=[0.0])
    with pytest.raises(ValueError, match="unknown method"):
        kepler.run({"h": 0.01, "k": 1.0}, steps=1, method="sideways", **start)


def test_keyword_and_sympy_systems_match_the_text():
    sympy = pytest.importorskip("sympy")
    x, y, z, th, vx, vy, vz, vth, m, b0 = sympy.symbols("x y z theta vx vy vz vtheta m b0")
    s = sympy.Rational(1, 2) * b0 * (-y * vx + x * vy) + vth
    lagrangian = sympy.Rational(1, 2) * m * (vx**2 + vy**2 + vz**2) + sympy.Rational(1, 2) * s**2
    from_sympy = dirac.from_sympy(lagrangian, q=[x, y, z, th], v=[vx, vy, vz, vth],
                                  shape=["x", "y", "z"], group=["theta"], parameters=[m, b0],
                                  rule="left")
    assert from_sympy.parameters == ["m", "b0", "h"]
    text = dirac.compile(function("src/paper.rs", "charged_particle_continuous"))
    params = {"h": 0.1, "m": 1.0, "b0": 1.0}
    start = dict(x=[0, 0, 0], w=[1, 0, 1], mu=[1], g=[0])
    a = from_sympy.run(params, steps=200, **start)
    b = text.run(params, steps=200, **start)
    # SymPy orders the operations its own way: the same motion to round-off.
    assert np.max(np.abs(a["x"] - b["x"])) < 1e-10


def test_a_run_written_to_parquet_reads_back_bit_for_bit(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    kepler = dirac.compile(KEPLER)
    params = {"h": 0.01, "k": 1.0}
    start = dict(x=[0.5], w=[0.0], mu=[math.sqrt(0.75)], g=[0.0])
    out = tmp_path / "kepler.parquet"
    summary = kepler.write(params, steps=500, path=str(out), **start)
    assert summary["steps"] == 500 and summary["t"] == pytest.approx(5.0)
    table = pq.read_table(out)
    # The columns are named after the text's coordinates.
    for name in ["t", "x_r", "w_r", "mu_phi", "g_phi"]:
        assert name in table.column_names, table.column_names
    run = kepler.run(params, steps=500, **start)
    assert np.array_equal(table.column("t").to_numpy(), run["t"])
    assert np.array_equal(table.column("x_r").to_numpy(), run["x"][:, 0])
    assert np.array_equal(table.column("mu_phi").to_numpy(), run["mu"][:, 0])
    assert np.array_equal(table.column("g_phi").to_numpy(), run["g"][:, 0])
    # The parameters travel with the file.
    part = next(out.glob("part-*.parquet"))
    metadata = pq.read_metadata(part).metadata
    assert metadata[b"dirac.shape"] == b"r" and metadata[b"dirac.group"] == b"phi"
    assert metadata[b"dirac.parameters"] == b"h,k"
    assert float(metadata[b"dirac.parameter.k"]) == 1.0


def test_a_failed_write_keeps_the_states_before_it(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    wall = dirac.system("0.5 / h * (q1.x - q0.x) * (q1.x - q0.x) - h * c * q0.x.sqrt()",
                        shape=["x"], parameters=["c"])
    out = tmp_path / "wall.parquet"
    with pytest.raises(dirac.StepError) as info:
        wall.write({"h": 0.1, "c": 1e-6}, steps=100, path=str(out), x=[1.0], w=[-1.0])
    assert pathlib.Path(info.value.path) == out
    assert pq.read_table(out).num_rows == info.value.step + 1


def test_a_translation_declared_on_the_users_coordinates_converts_both_ways():
    chain = dirac.compile(
        "#[reduced_lagrangian(coordinates(x[4]), translate(x), rule = midpoint)]\n"
        "fn chain(q: Config, v: Velocity, k: f64) -> f64 {\n"
        "    let mut l = 0.0;\n"
        "    for i in 0..4 { l += 0.5 * v.x[i] * v.x[i]; }\n"
        "    for i in 0..3 { l -= 0.5 * k * (q.x[i + 1] - q.x[i] - 1.0).powi(2); }\n"
        "    l\n"
        "}")
    assert chain.adapted
    assert (len(chain.shape), len(chain.group)) == (3, 1)
    q_user = np.array([0.1, 1.3, 1.9, 3.2])
    p_user = np.array([0.5, -0.2, 0.1, 0.3])
    q, p = chain.to_adapted(q_user), chain.momentum_to_adapted(p_user)
    # The group coordinate is x[0], the shape the other components relative to it; the group
    # momentum is the total momentum.
    assert q[3] == q_user[0] and np.allclose(q[:3], q_user[1:] - q_user[0])
    assert p[3] == pytest.approx(p_user.sum())
    assert np.allclose(chain.from_adapted(q), q_user)
    assert np.allclose(chain.momentum_from_adapted(p), p_user)
    run = chain.run({"k": 2.0, "h": 0.05}, steps=200, method="unreduced", q=q, p=p)
    # The total momentum: to round-off unreduced, exactly reduced (μ = p_g).
    assert np.max(np.abs(run["p"][chain.group[0]] - p[3])) < 1e-12
    reduced = chain.run({"k": 2.0, "h": 0.05}, steps=200, x=q[:3], w=p[:3], mu=[p[3]], g=[q[3]])
    assert np.all(reduced["mu"] == p[3])
    rows = np.column_stack([run["q"][n] for n in chain.shape + chain.group])
    user = np.array([chain.from_adapted(row) for row in rows])
    assert user.shape == (201, 4)
    assert np.max(np.abs(user[:, 0] - reduced["g"][:, 0])) < 1e-10
    with pytest.raises(ValueError, match="3 values"):
        chain.to_adapted([0.0, 1.0, 2.0])


def test_the_continuous_energy_of_a_run_at_its_states_and_midpoints():
    dsp = dirac.compile(function("src/paper.rs", "double_spherical_pendulum_continuous"))
    params = dict(m1=1.0, m2=1.0, l1=1.0, l2=1.0, g=9.81, h=0.01)
    start = dict(x=[2.25, 2.0, 3.0], w=[0.0, 1.0, 1.0], mu=[0.0], g=[0.0])
    run = dsp.run(params, steps=500, energies=True, **start)
    assert run["energy"].shape == (501,) and run["energy_midpoints"].shape == (500,)
    # A variational integrator: the energy oscillates by O(h²) about its value (2% here, the
    # pendulum's chaotic swing at h = 0.01); the midpoint energies about theirs.
    e = run["energy"]
    assert np.max(np.abs(e - e[0])) < 2e-2 * abs(e[0])
    mid = run["energy_midpoints"]
    assert np.max(np.abs(mid - mid[0])) < 5e-2 * abs(mid[0])
    # Halving the step quarters the oscillation.
    half = dsp.run(dict(params, h=0.005), steps=1000, energies=True, **start)["energy"]
    ratio = np.max(np.abs(e[:201] - e[0])) / np.max(np.abs(half[:401] - half[0]))
    assert 3.0 < ratio < 5.0, ratio
    # The same energies unreduced, from the untrivialized start.
    unreduced = dsp.run(params, steps=10, energies=True, method="unreduced",
                        q=[2.25, 2.0, 3.0, 0.0], p=[0.0, 1.0, 1.0, 0.0])
    assert abs(unreduced["energy"][0] - e[0]) < 1e-12 * abs(e[0])
    with pytest.raises(ValueError, match="discrete Lagrangian"):
        dirac.compile(DSP).run(dict(zip(dirac.compile(DSP).parameters, [0.01, 1, 1, 1, 1, 9.81])),
                               steps=2, energies=True, **start)
