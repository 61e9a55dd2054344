"""Systems on rotation groups of any size from Python: eight rigid bodies on a chain of springs
(the text the Rust tests compile in, 24 chart coordinates) against each body run alone, and
ensembles of a three-link spherical chain (three directions), beyond the fixed-size instances
the module once capped them at."""


import numpy as np

import dirac

from sources import function


EIGHT_BODIES = function("dirac-jit/tests/texts/eight_bodies.rs", "eight_bodies")

# One of the eight bodies alone: the same J_d, its kinetic term scaled by `s`.
ONE_BODY = """
#[reduced_lagrangian(rotation(r))]
fn one_body(q0: Config, q1: Config, h: f64, s: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.5));
    ((Matrix3::identity() - q0.r.transpose() * q1.r) * jd).trace() * s / h
}
"""

# Three unit links hanging from a pivot, each a direction, under gravity: invariant under the
# rotations about the vertical.
CHAIN = """
#[reduced_lagrangian(direction(n1, n2, n3), rule = trapezoid, symmetry(n1, n2, n3, axis = z))]
fn chain(q: Config, v: Velocity, g: f64) -> f64 {
    let v2 = v.n1 + v.n2;
    let v3 = v.n1 + v.n2 + v.n3;
    let height = 3.0 * q.n1.z + 2.0 * q.n2.z + q.n3.z;
    0.5 * (v.n1.dot(&v.n1) + v2.dot(&v2) + v3.dot(&v3)) - g * height
}
"""


def cayley(x):
    """cay(x) = I + 4/(4 + |x|²) (x̂ + x̂²/2)."""
    hat = np.array([[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]])
    return np.eye(3) + 4.0 / (4.0 + x @ x) * (hat + hat @ hat / 2.0)


def eight_start():
    """The attitudes and body momenta of the Rust tests' start."""
    r = {f"r{i}": cayley(np.array([0.1 * i, -0.2, 0.05 * i])) for i in range(1, 9)}
    p = {f"r{i}": np.array([0.3, 1.0 - 0.1 * i, -0.2 * i]) for i in range(1, 9)}
    return r, p


def test_eight_uncoupled_bodies_are_eight_bodies_alone():
    bodies = dirac.compile(EIGHT_BODIES)
    assert isinstance(bodies, dirac.LieSystem)
    assert bodies.coordinates == [(f"r{i}", "rotation") for i in range(1, 9)]
    q, p = eight_start()
    run = bodies.run({"h": 0.01, "k": 0.0}, steps=200, q=q, p=p)
    assert run["q"]["r8"].shape == (201, 3, 3) and run["p"]["r8"].shape == (201, 3)
    one = dirac.compile(ONE_BODY)
    for i in range(1, 9):
        name = f"r{i}"
        alone = one.run(
            {"h": 0.01, "s": 1.0 + 0.25 * (i - 1)},
            steps=200,
            q={"r": q[name]},
            p={"r": p[name]},
        )
        scale = max(1.0, np.max(np.abs(alone["p"]["r"])))
        assert np.max(np.abs(run["q"][name] - alone["q"]["r"])) < 1e-12, name
        assert np.max(np.abs(run["p"][name] - alone["p"]["r"])) < 1e-12 * scale, name


def test_eight_coupled_bodies_keep_their_spatial_momentum_and_write():
    bodies = dirac.compile(EIGHT_BODIES)
    q, p = eight_start()
    run = bodies.run({"h": 0.01, "k": 3.0}, steps=200, q=q, p=p)
    pi = run["spatial_momentum"]
    assert np.max(np.abs(pi - pi[0])) < 1e-12 * max(1.0, np.max(np.abs(pi[0])))
    # The springs couple them: the first body is not where it would be alone.
    free = bodies.run({"h": 0.01, "k": 0.0}, steps=200, q=q, p=p)
    assert np.max(np.abs(run["q"]["r1"][-1] - free["q"]["r1"][-1])) > 1e-3
    # The (−) step takes the same steps.
    minus = bodies.run({"h": 0.01, "k": 3.0}, steps=200, q=q, p=p, method="minus")
    assert np.max(np.abs(minus["q"]["r5"] - run["q"]["r5"])) < 1e-12


def chain_starts(members):
    """Starts of the chain: the links tilted by member, at rest but for a swing of the last."""
    qs, ps = {f"n{i}": [] for i in (1, 2, 3)}, {f"n{i}": [] for i in (1, 2, 3)}
    for m in range(members):
        for i in (1, 2, 3):
            a = 0.3 + 0.1 * m + 0.2 * i
            qs[f"n{i}"].append(np.array([np.sin(a), 0.0, -np.cos(a)]))
            ps[f"n{i}"].append(np.array([0.0, 0.2 * i, 0.0]))
    return {k: np.array(v) for k, v in qs.items()}, {k: np.array(v) for k, v in ps.items()}


def test_an_ensemble_of_a_three_link_chain_is_its_single_runs():
    chain = dirac.compile(CHAIN)
    assert chain.coordinates == [(f"n{i}", "direction") for i in (1, 2, 3)]
    params = {"h": 0.01, "g": 9.81}
    qs, ps = chain_starts(3)
    many = chain.ensemble(params, steps=150, q=qs, p=ps)
    assert many["failed"] == []
    for m in range(3):
        q = {k: v[m] for k, v in qs.items()}
        p = {k: v[m] for k, v in ps.items()}
        one = chain.run(params, steps=150, q=q, p=p)
        for name in ("n1", "n2", "n3"):
            assert np.array_equal(many["q"][name][m], one["q"][name]), (m, name)
            assert np.array_equal(many["p"][name][m], one["p"][name]), (m, name)
    # Reduced by the rotations about the vertical, as an ensemble too.
    reduced = chain.ensemble(params, steps=50, q=qs, p=ps, method="reduced")
    assert reduced["failed"] == []
    assert np.all(reduced["mu"][:, 1:] == reduced["mu"][:, :1])
