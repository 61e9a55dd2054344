"""Element-wise systems from Python: sizes chosen per run, a Toda lattice against a midpoint
integrator written here in NumPy, a grid's shapes, a chain of links with a constraint per link,
and the errors."""


import numpy as np
import pytest

import dirac

from sources import function


TODA_N = function("examples/common/toda_n.rs", "toda_n")
MEMBRANE = function("examples/common/membrane.rs", "membrane")
LINK_CHAIN = function("examples/common/link_chain.rs", "link_chain")


def toda_midpoint(q, p, m, d, h, steps):
    """The midpoint rule's discrete Euler–Lagrange equations for the periodic Toda lattice
    L = Σ m v²/2 − V(q), V = Σ_{i<n−1} exp(−(x_{i+1} − x_i − d)) + exp(−(x_0 + n d − x_{n−1} − d)),
    in position–momentum form: p_k = m (q1 − q0)/h + (h/2) ∇V(q̄), p_{k+1} = m (q1 − q0)/h −
    (h/2) ∇V(q̄), q̄ = (q0 + q1)/2, solved for q1 by Newton with the exact Jacobian."""
    n = len(q)

    def bonds(x):
        # Each bond: (a, b, stretch) with V = exp(−stretch).
        out = [(i, i + 1, x[i + 1] - x[i] - d) for i in range(n - 1)]
        out.append((n - 1, 0, x[0] + n * d - x[n - 1] - d))
        return out

    def grad_hess(x):
        g, hess = np.zeros(n), np.zeros((n, n))
        for a, b, s in bonds(x):
            e = np.exp(-s)
            # ∂/∂x_b of exp(−s) is −e, ∂/∂x_a is +e (s = x_b − x_a + const).
            g[b] -= e
            g[a] += e
            for i, si in ((a, -1.0), (b, 1.0)):
                for j, sj in ((a, -1.0), (b, 1.0)):
                    hess[i, j] += e * si * sj
        return g, hess

    qs, ps = [q.copy()], [p.copy()]
    for _ in range(steps):
        q1 = q + h * p / m
        for _ in range(50):
            g, hess = grad_hess(0.5 * (q + q1))
            r = m * (q1 - q) / h + 0.5 * h * g - p
            dq = np.linalg.solve(m / h * np.eye(n) + 0.25 * h * hess, -r)
            q1 = q1 + dq
            if np.max(np.abs(dq)) < 1e-15:
                break
        g, _ = grad_hess(0.5 * (q + q1))
        q, p = q1, m * (q1 - q) / h - 0.5 * h * g
        qs.append(q)
        ps.append(p)
    return np.array(qs), np.array(ps)


def test_a_lattice_sized_per_run_is_the_midpoint_rule():
    toda = dirac.compile(TODA_N)
    assert isinstance(toda, dirac.ElementSystem)
    assert toda.sizes == ["n"] and toda.coordinates == ["x"]
    assert toda.parameters == ["m", "d", "h"]
    params = {"m": 1.0, "d": 1.0, "h": 0.05}
    for n in (12, 40):
        i = np.arange(n)
        q0 = i * 1.0 + 0.1 * np.sin(2 * np.pi * i / n)
        p0 = 0.2 * np.cos(2 * np.pi * i / n) + 0.05
        run = toda.run(params, steps=100, sizes={"n": n}, q=q0, p=p0)
        assert run["t"].shape == (101,) and run["q"]["x"].shape == (101, n)
        assert run["momentum_map"].shape == (101, 1)
        qs, ps = toda_midpoint(q0, p0, 1.0, 1.0, 0.05, 100)
        assert np.max(np.abs(run["q"]["x"] - qs)) < 1e-10
        assert np.max(np.abs(run["p"]["x"] - ps)) < 1e-10
        # Σ p, the translation's momentum, kept to round-off.
        assert np.max(np.abs(run["momentum_map"][:, 0] - p0.sum())) < 1e-11
    # The (−) side and the compositions from the same start.
    start = dict(sizes={"n": 12}, q=np.arange(12.0), p=np.zeros(12))
    minus = toda.run(params, steps=50, method="minus", **start)
    plus = toda.run(params, steps=50, **start)
    assert np.max(np.abs(minus["q"]["x"] - plus["q"]["x"])) < 1e-10
    four = toda.run(params, steps=10, order=4, **start)
    assert four["q"]["x"].shape == (11, 12)


def test_a_grid_returns_its_coordinates_shape():
    membrane = dirac.compile(MEMBRANE)
    assert membrane.sizes == ["nx", "ny"]
    params = dict(rho=1.0, c2=1.0, beta=0.5, delta=0.1, h=0.02)
    nx, ny = 9, 7
    u0 = np.fromfunction(lambda i, j: 0.1 * np.sin(2 * np.pi * i / nx) * np.cos(2 * np.pi * j / ny),
                         (nx, ny))
    run = membrane.run(params, steps=20, sizes={"nx": nx, "ny": ny}, q={"u": u0},
                       p={"u": np.zeros((nx, ny))})
    assert run["q"]["u"].shape == (21, nx, ny)
    assert np.array_equal(run["q"]["u"][0], u0)


def test_a_chain_of_links_keeps_its_constraints():
    chain = dirac.compile(LINK_CHAIN)
    assert chain.constrained
    n, l = 5, 0.4
    th = 0.3 * np.sin(np.arange(1, n + 1))
    x, y = np.cumsum(l * np.sin(th)), -np.cumsum(l * np.cos(th))
    q = {"c": 0.0, "x": x, "y": y}
    p = {"c": 0.0, "x": np.zeros(n), "y": np.zeros(n)}
    run = chain.run(dict(mc=1.0, m=0.5, l=l, gr=9.81, h=0.01), steps=200, sizes=[n], q=q, p=p)
    assert run["multipliers"].shape == (200, n)
    assert np.max(run["constraint_residuals"]) < 1e-9
    links = np.hypot(np.diff(run["q"]["x"], axis=1), np.diff(run["q"]["y"], axis=1))
    assert np.max(np.abs(links - l)) < 1e-8
    with pytest.raises(ValueError, match="order"):
        chain.run(dict(mc=1.0, m=0.5, l=l, gr=9.81, h=0.01), steps=1, sizes=[n], q=q, p=p,
                  order=4)


def test_bad_input_raises_value_errors_and_a_failed_step_keeps_the_trajectory():
    toda = dirac.compile(TODA_N)
    params = {"m": 1.0, "d": 1.0, "h": 0.05}
    q, p = np.arange(8.0), np.zeros(8)
    with pytest.raises(ValueError, match="no size `k`"):
        toda.run(params, steps=1, sizes={"k": 8}, q=q, p=p)
    with pytest.raises(ValueError, match="has 7 values"):
        toda.run(params, steps=1, sizes={"n": 8}, q=q[:7], p=p)
    with pytest.raises(ValueError, match="not a coordinate"):
        toda.run(params, steps=1, sizes={"n": 8}, q={"y": q}, p=p)
    with pytest.raises(ValueError, match="unknown method"):
        toda.run(params, steps=1, sizes={"n": 8}, q=q, p=p, method="sideways")
    with pytest.raises(ValueError, match="declares no reduction"):
        toda.run(params, steps=1, sizes={"n": 8}, q=q, p=p, method="reduced")
    with pytest.raises(ValueError, match="positive finite"):
        toda.run(params, steps=1, sizes={"n": 8}, q=q, p=p, tol=float("nan"))
    # Particles flying apart into a potential √x_0, NaN once x_0 < 0.
    wall = dirac.compile(
        "#[reduced_lagrangian(coordinates(x[n]), rule = midpoint)]\n"
        "fn wall(q: Config, v: Velocity, c: f64, n: usize) -> f64 {\n"
        "    let mut l = 0.0;\n"
        "    for i in 0..n { l += 0.5 * v.x[i] * v.x[i] + c * q.x[i].sqrt(); }\n"
        "    l\n"
        "}")
    with pytest.raises(dirac.StepError) as info:
        wall.run({"c": 1e-6, "h": 0.1}, steps=100, sizes=[3], q=np.ones(3), p=-np.ones(3))
    e = info.value
    assert 0 < e.step < 100
    assert e.trajectory["q"]["x"].shape == (e.step + 1, 3)
