"""High order from Python: `System.run(scheme="gauss", order=2s)` steps a continuous Lagrangian
given as text by the Gauss–Legendre variational integrator of order 2s — against Kepler's
equation, with the momentum kept bit for bit, both reduced sides and the unreduced form giving
the same motion — and refuses what it cannot run, saying what it accepts."""

import math

import numpy as np
import pytest

import dirac

from sources import function


KEPLER = """
#[reduced_lagrangian(shape(r), group(theta), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}
"""

E = 0.5
START = dict(x=[1.0 - E], w=[0.0], mu=[math.sqrt(1.0 - E * E)], g=[0.0])


def one_orbit(system, order, n, **keywords):
    """The state after one period of the e = 0.5 orbit (a = 1, k = 1) in `n` steps."""
    h = 2 * math.pi / n
    return system.run({"h": h, "k": 1.0}, steps=n, scheme="gauss", order=order, **keywords)


def test_the_order_is_2s_against_keplers_equation_and_mu_is_kept_bit_for_bit():
    kepler = dirac.compile(KEPLER)
    for order, n0 in [(4, 100), (6, 100), (8, 80)]:
        errors = []
        for n in (n0, round(1.5 * n0)):
            run = one_orbit(kepler, order, n, tol=1e-14, **START)
            assert np.all(run["mu"] == START["mu"][0])
            # Back at periapsis after one period.
            errors.append(max(abs(run["x"][-1, 0] - (1.0 - E)),
                              abs(run["g"][-1, 0] - 2 * math.pi)))
        observed = math.log(errors[0] / errors[1]) / math.log(1.5)
        assert abs(observed - order) < 0.3, (order, errors, observed)


def test_both_reduced_sides_and_the_unreduced_form_give_the_same_motion():
    kepler = dirac.compile(KEPLER)
    plus = one_orbit(kepler, 8, 60, method="plus", **START)
    minus = one_orbit(kepler, 8, 60, method="minus", **START)
    for key in ("x", "w", "mu", "g"):
        assert np.array_equal(plus[key], minus[key]), key
    unreduced = one_orbit(kepler, 8, 60, method="unreduced",
                          q=[START["x"][0], 0.0], p=[0.0, START["mu"][0]])
    assert np.all(unreduced["p"]["theta"] == START["mu"][0])
    assert np.max(np.abs(unreduced["q"]["r"] - plus["x"][:, 0])) < 1e-13
    # The continuous energy of every state, without drift at this order.
    energies = one_orbit(kepler, 8, 60, energies=True, **START)["energy"]
    assert np.max(np.abs(energies - energies[0])) < 1e-9


def test_what_gauss_cannot_run_is_refused_saying_what_is_accepted():
    kepler = dirac.compile(KEPLER)
    params = {"h": 0.1, "k": 1.0}
    for order in (7, 0, 34):
        with pytest.raises(ValueError, match="even order from 2 to 32"):
            kepler.run(params, steps=3, scheme="gauss", order=order, **START)
    with pytest.raises(ValueError, match='"gauss"'):
        kepler.run(params, steps=3, scheme="runge-kutta", **START)
    discrete = dirac.compile(function("src/systems/kepler.rs", "kepler"))
    with pytest.raises(ValueError, match="continuous Lagrangian"):
        discrete.run(params, steps=3, scheme="gauss", order=4, **START)
    # Ensembles and files run the integrators themselves: no scheme keyword.
    with pytest.raises(TypeError, match="scheme"):
        kepler.ensemble(params, steps=3, scheme="gauss", x=[[0.5]], w=[[0.0]], mu=[[0.8]],
                        g=[[0.0]])
