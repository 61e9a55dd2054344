"""Systems on vector spaces of any size from Python: beyond the fixed-size instances (more than 8
coordinates, more than 3 constraints) `System.run`, `write` and `ensemble` run the system's
element view on the element integrators, with the same keywords and results of the same shape.
The 30-coordinate cart and the 20-link chain are the texts `dirac-jit/tests/sizes.rs` compiles in
from Rust; their compiled-in trajectories (the fixed-size reduced and constrained integrators)
are the fixture `data/sizes.json` that test writes and checks."""

import json

import numpy as np
import pytest

import dirac

from sources import ROOT


CART = (ROOT / "dirac-jit/tests/sizes/cart30.rs").read_text()
CHAIN = (ROOT / "dirac-jit/tests/sizes/chain20.rs").read_text()
FIXTURE = json.loads((ROOT / "dirac-py/tests/data/sizes.json").read_text())


def close(a, b, tol=1e-12):
    """`|a − b|∞ ≤ tol · max(|b|∞, 1)`."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    scale = max(np.max(np.abs(b)), 1.0)
    assert np.max(np.abs(a - b)) <= tol * scale, np.max(np.abs(a - b)) / scale


def stacked(run, key, names):
    """The (rows, n) array of `run[key]` (a dict by coordinate) in the order of `names`."""
    return np.stack([run[key][n] for n in names], axis=1)


def test_a_30_coordinate_system_runs_as_compiled_in():
    cart = dirac.compile(CART)
    names = cart.shape + cart.group
    assert len(names) == 30
    f = FIXTURE["cart"]
    run = cart.run(f["parameters"], steps=f["steps"], method="plus", x=f["x"], w=f["w"],
                   mu=[f["mu"]], g=[f["g"]])
    close(stacked(run, "q", names), f["q"])
    close(stacked(run, "p", names), f["p"])
    # The cart's momentum, exactly, and the reduced state beside q and p.
    assert np.all(run["mu"][:, 0] == f["mu"])
    assert run["x"].shape == (f["steps"] + 1, 29)
    close(run["w"], np.asarray(f["p"])[:, :29])
    # The (−) side computes the same trajectory.
    minus = cart.run(f["parameters"], steps=f["steps"], method="minus", x=f["x"], w=f["w"],
                     mu=[f["mu"]], g=[f["g"]])
    close(stacked(minus, "q", names), f["q"], 1e-11)


def test_a_system_with_20_constraints_runs_as_compiled_in():
    chain = dirac.compile(CHAIN)
    assert chain.constraints == 20
    names = chain.shape + chain.group
    f = FIXTURE["chain"]
    run = chain.run(f["parameters"], steps=f["steps"], method="unreduced", q=f["q0"],
                    p=np.zeros(40))
    close(stacked(run, "q", names), f["q"])
    close(stacked(run, "p", names), f["p"])
    assert run["multipliers"].shape == (f["steps"], 20)
    assert np.max(run["constraint_residuals"]) < 1e-9


def chain_starts(members):
    """The chain hanging at `members` different angles, at rest."""
    starts = []
    for i in range(members):
        theta = 0.6 + 0.05 * np.arange(20) + 0.1 * i
        x, y = np.cumsum(0.5 * np.sin(theta)), -np.cumsum(0.5 * np.cos(theta))
        starts.append(np.concatenate([x, y]))
    return np.array(starts)


def test_an_ensemble_of_constrained_systems_is_its_single_runs():
    chain = dirac.compile(CHAIN)
    params = FIXTURE["chain"]["parameters"]
    q = chain_starts(3)
    ens = chain.ensemble(params, steps=20, method="unreduced", q=q, p=np.zeros((3, 40)))
    assert ens["failed"] == []
    for i in range(3):
        one = chain.run(params, steps=20, method="unreduced", q=q[i], p=np.zeros(40))
        for key in ("q", "p"):
            for name, values in one[key].items():
                assert np.array_equal(ens[key][name][i], values), (i, key, name)
        assert np.array_equal(ens["multipliers"][i], one["multipliers"])


def test_an_ensemble_of_small_constrained_systems_is_its_single_runs():
    # Two coordinates and a rod: the fixed-size constrained integrator, members bit for bit.
    pendulum = dirac.compile(
        "#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,\n"
        "    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]\n"
        "fn pendulum(q: Config, v: Velocity, m: f64, l: f64, g: f64) -> f64 {\n"
        "    0.5 * m * (v.x * v.x + v.y * v.y) - m * g * q.y\n"
        "}")
    params = {"m": 1.0, "l": 1.5, "g": 9.81, "h": 0.01}
    angles = np.array([0.3, 0.6, 0.9])
    q = np.stack([1.5 * np.sin(angles), -1.5 * np.cos(angles)], axis=1)
    ens = pendulum.ensemble(params, steps=30, method="unreduced", q=q, p=np.zeros((3, 2)))
    for i in range(3):
        one = pendulum.run(params, steps=30, method="unreduced", q=q[i], p=[0.0, 0.0])
        assert np.array_equal(ens["q"]["x"][i], one["q"]["x"])
        assert np.array_equal(ens["p"]["y"][i], one["p"]["y"])


TEN = """
#[reduced_lagrangian(shape(x[9]), group(c), rule = midpoint)]
fn ten(q: Config, v: Velocity, m: f64, k: f64) -> f64 {
    let mut l = 0.5 * v.c * v.c;
    for i in 0..9 {
        l += 0.5 * m * (v.c + v.x[i]) * (v.c + v.x[i]) - k * (1.0 - q.x[i].cos());
    }
    l
}
"""


def test_a_10_coordinate_system_runs_ensembles():
    ten = dirac.compile(TEN)
    params = {"m": 0.5, "k": 2.0, "h": 0.01}
    x = 0.1 * np.arange(1, 4)[:, None] * np.sin(np.arange(9))[None, :]
    w = np.zeros((3, 9))
    mu, g = np.array([[0.2], [0.3], [0.4]]), np.zeros((3, 1))
    ens = ten.ensemble(params, steps=40, x=x, w=w, mu=mu, g=g)
    assert ens["failed"] == []
    for i in range(3):
        one = ten.run(params, steps=40, x=x[i], w=w[i], mu=mu[i], g=g[i])
        assert np.array_equal(ens["x"][i], one["x"])
        assert np.array_equal(ens["p"]["c"][i], one["p"]["c"])
        # The cart's momentum, exactly.
        assert np.all(one["mu"][:, 0] == mu[i, 0])
    # Order 4 on the element path: the composition of the (+) side.
    four = ten.run(params, steps=40, order=4, x=x[0], w=w[0], mu=mu[0], g=g[0])
    assert np.max(np.abs(four["x"] - ens["x"][0])) < 1e-3


def test_a_large_system_writes_its_run(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    cart = dirac.compile(CART)
    f = FIXTURE["cart"]
    out = tmp_path / "cart.parquet"
    cart.write(f["parameters"], steps=10, path=str(out), method="plus", x=f["x"], w=f["w"],
               mu=[f["mu"]], g=[f["g"]])
    run = cart.run(f["parameters"], steps=10, method="plus", x=f["x"], w=f["w"], mu=[f["mu"]],
                   g=[f["g"]])
    table = pq.read_table(out)
    names = table.column_names
    assert "t" in names
    # The columns named after the coordinates, as an unreduced run names them.
    for name in cart.shape + cart.group:
        assert f"q_{name}" in names and f"p_{name}" in names, (name, names)
    for name in ("x[0]", "x[28]", "c"):
        np.testing.assert_array_equal(table.column(f"q_{name}").to_numpy(), run["q"][name])
        np.testing.assert_array_equal(table.column(f"p_{name}").to_numpy(), run["p"][name])


def test_a_30_coordinate_run_has_its_energies():
    cart = dirac.compile(CART)
    f = FIXTURE["cart"]
    par = f["parameters"]
    run = cart.run(par, steps=f["steps"], energies=True, x=f["x"], w=f["w"], mu=[f["mu"]],
                   g=[f["g"]])
    # The energy at each state by hand: the velocities from the momenta (the mass matrix of
    # the cart and its 29 oscillators inverted), then T + V.
    names = cart.shape + cart.group
    q, p = stacked(run, "q", names), stacked(run, "p", names)
    x, px, pc = q[:, :29], p[:, :29], p[:, 29]
    vc = (pc - px.sum(axis=1)) / par["mc"]
    vx = px / par["m"] - vc[:, None]
    kinetic = 0.5 * par["mc"] * vc**2 + 0.5 * par["m"] * ((vc[:, None] + vx) ** 2).sum(axis=1)
    potential = (par["k"] * (1.0 - np.cos(x))).sum(axis=1) \
        + 0.5 * par["kappa"] * (np.diff(x, axis=1) ** 2).sum(axis=1)
    close(run["energy"], kinetic + potential)
    assert run["energy_midpoints"].shape == (f["steps"],)
    # Conserved to the scheme's order over the run.
    assert np.ptp(run["energy"]) < 1e-3 * abs(run["energy"][0])


def test_what_the_element_path_does_not_support_is_a_value_error():
    # Adaptive steps at a size only the element integrators serve.
    adaptive = dirac.compile("""
        #[reduced_lagrangian(shape(x[9]), group(t), time(t), adapt = |q| 1.0 + q.x[0] * q.x[0],
            rule = midpoint)]
        fn f(q: Config, v: Velocity, m: f64) -> f64 {
            let mut l = 0.0;
            for i in 0..9 {
                l += 0.5 * m * v.x[i] * v.x[i] - q.x[i] * q.x[i];
            }
            l
        }""")
    with pytest.raises(ValueError, match="adaptive steps"):
        adaptive.run({"m": 1.0, "h": 0.01}, steps=2, method="unreduced", q=np.zeros(10),
                     p=np.ones(10))
