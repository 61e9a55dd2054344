"""Step schedules from Python: `schedule=[h0, h1, ...]` gives the size of each step to `run`,
`write` and `ensemble` of every class (the run API's `StepSizes`). A step of size `h_k` is the
step of the system whose parameter `h` is `h_k` (bit for bit from the same first guess of
Newton's, to round-off after it: a run's Newton starts each step from the last steps); the times
are the running sums of the sizes; a schedule is positive finite sizes, one for each step, else a
`ValueError`. The same schedule through the Rust run API is `dirac-io/tests/cli_schedule.rs`."""

import json

import numpy as np
import pytest

import dirac

from sources import ROOT, function
from test_surface import COORDINATES, SYSTEMS, assert_same, member_start, written_columns


def schedule(h, n):
    """`n` sizes around `h`, no two neighbours equal."""
    return [h * (1.0 + 0.5 * np.sin(1.7 * k)) for k in range(n)]


def state(run, k):
    """State `k` of `run` as a start, by coordinate name."""
    return {key: {name: run[key][name][k] for name in run[key]} for key in ("q", "p")}


@pytest.mark.parametrize("kind", SYSTEMS)
def test_each_step_of_a_schedule_is_the_step_of_that_size_bit_for_bit(kind):
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    sizes = schedule(params["h"], 6)
    run = system.run(params, steps=6, schedule=sizes, method=method, **fixed,
                     **member_start(kind, 0))
    assert np.array_equal(run["t"], np.concatenate([[0.0], np.cumsum(sizes)]))
    # Step k from state k with the system's own size h = sizes[k]: the same state (the same
    # bits for the first step, whose Newton starts from the same guess).
    for k, h in enumerate(sizes):
        one = system.run(dict(params, h=h), steps=1, method=method, **fixed, **state(run, k))
        for key in ("q", "p"):
            for name in COORDINATES[kind]:
                a, b = np.asarray(one[key][name][1]), np.asarray(run[key][name][k + 1])
                if k == 0:
                    assert np.array_equal(a, b), (key, name)
                assert np.max(np.abs(a - b)) <= 1e-13 * max(np.max(np.abs(b)), 1.0), (k, key)
    # A schedule of the system's own size steps as the system does (the times summed).
    own = system.run(params, steps=6, schedule=[params["h"]] * 6, method=method, **fixed,
                     **member_start(kind, 0))
    fixed_run = system.run(params, steps=6, method=method, **fixed, **member_start(kind, 0))
    assert_same(own["q"], fixed_run["q"])
    assert any(not np.array_equal(run["q"][n], fixed_run["q"][n]) for n in COORDINATES[kind])


@pytest.mark.parametrize("kind", SYSTEMS)
def test_every_class_writes_and_runs_ensembles_on_a_schedule(kind, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    sizes = schedule(params["h"], 12)
    start = member_start(kind, 1)
    run = system.run(params, steps=10, schedule=sizes, method=method, **fixed, **start)
    assert len(run["t"]) == 11
    out = tmp_path / f"{kind}.parquet"
    summary = system.write(params, steps=10, path=str(out), schedule=sizes, method=method,
                           **fixed, **start)
    assert summary["steps"] == 10 and summary["t"] == run["t"][-1]
    table = pq.read_table(out)
    assert np.array_equal(table.column("t").to_numpy(), run["t"])
    for name in COORDINATES[kind]:
        written = written_columns(kind, table, name, "p")
        assert np.array_equal(written, run["p"][name].reshape(written.shape)), name
    stacked = {key: {n: np.array([v, v]) for n, v in start[key].items()} for key in ("q", "p")}
    ens = system.ensemble(params, steps=10, schedule=sizes, method=method, **fixed, **stacked)
    assert ens["failed"] == [] and ens["t"].shape == (2, 11)
    for i in range(2):
        assert_same({n: a[i] for n, a in ens["q"].items()}, run["q"], f"member {i}")


@pytest.mark.parametrize("kind", SYSTEMS)
def test_a_schedule_with_an_end_time_lands_on_it(kind):
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    sizes = schedule(params["h"], 20)
    end = sum(sizes[:3]) + 0.5 * sizes[3]
    run = system.run(params, steps=20, schedule=sizes, end_time=end, method=method, **fixed,
                     **member_start(kind, 0))
    assert len(run["t"]) == 5 and run["t"][-1] == end
    assert np.array_equal(run["t"][:4], np.concatenate([[0.0], np.cumsum(sizes[:3])]))


@pytest.mark.parametrize("kind", SYSTEMS)
def test_a_schedule_that_is_not_one_positive_size_per_step_is_a_value_error(kind, tmp_path):
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    h = params["h"]
    start = member_start(kind, 0)
    stacked = {key: {n: np.array([v]) for n, v in start[key].items()} for key in ("q", "p")}
    calls = {
        "run": lambda **k: system.run(params, steps=3, method=method, **fixed, **start, **k),
        "write": lambda **k: system.write(params, steps=3, path=str(tmp_path / "x.parquet"),
                                          method=method, **fixed, **start, **k),
        "ensemble": lambda **k: system.ensemble(params, steps=3, method=method, **fixed,
                                                **stacked, **k),
    }
    for name, call in calls.items():
        for sizes, message in [
            ([h, 0.0, h], r"schedule\[1\] = 0"),
            ([h, h, -h], r"schedule\[2\] = -"),
            ([float("nan"), h, h], r"schedule\[0\] = NaN"),
            ([h, float("inf"), h], r"schedule\[1\] = inf"),
            ([h, h], "2 step sizes for 3 steps"),
        ]:
            with pytest.raises(ValueError, match=message):
                call(schedule=sizes)
        assert not (tmp_path / "x.parquet").exists(), name


ROD = ("#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,\n"
       "    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]\n"
       "fn f(q: Config, v: Velocity, m: f64, l: f64, g: f64) -> f64 {\n"
       "    0.5 * m * (v.x * v.x + v.y * v.y) - m * g * q.y\n"
       "}")
CART = (ROOT / "dirac-jit/tests/sizes/cart30.rs").read_text()
CHAIN = (ROOT / "dirac-jit/tests/sizes/chain20.rs").read_text()
HEAVY_TOP = function("src/systems/rotations.rs", "heavy_top")
FIXTURE = json.loads((ROOT / "dirac-py/tests/data/sizes.json").read_text())


def cart_start():
    f = FIXTURE["cart"]
    return dict(x=f["x"], w=f["w"], mu=[f["mu"]], g=[f["g"]])


PATHS = {
    # (text, parameters, method, start): the paths a run of each kind dispatches to.
    "reduced": (SYSTEMS["flat"][0], SYSTEMS["flat"][1], "minus",
                dict(x=[0.5], w=[0.0], mu=[0.8660254037844386], g=[0.0])),
    "constrained": (ROD, {"m": 1.0, "l": 1.5, "g": 9.81, "h": 0.002}, "unreduced",
                    dict(q=[1.5 * np.sin(0.8), -1.5 * np.cos(0.8)], p=[0.0, 0.0])),
    "30 coordinates": (CART, FIXTURE["cart"]["parameters"], "plus", cart_start()),
    "20 constraints": (CHAIN, FIXTURE["chain"]["parameters"], "unreduced",
                       dict(q=FIXTURE["chain"]["q0"], p=np.zeros(40))),
    "rotations reduced": (HEAVY_TOP, {"h": 0.01, "j1": 1.0, "j2": 1.0, "j3": 0.5, "mgl": 2.0},
                          "reduced", dict(q={"r": np.eye(3)}, p={"r": [0.2, -0.1, 3.0]})),
}


@pytest.mark.parametrize("path", PATHS)
def test_every_kind_of_run_takes_a_schedule(path):
    """The first step of a schedule is the system's step of that size, bit for bit; the
    times are the sums of the sizes, on the reduced, constrained, sized-as-data and rotation
    paths alike."""
    text, params, method, start = PATHS[path]
    system = dirac.compile(text)
    sizes = schedule(params["h"], 5)[1:]  # the first size not h
    run = system.run(params, steps=4, schedule=sizes, method=method, **start)
    assert np.array_equal(run["t"], np.concatenate([[0.0], np.cumsum(sizes)]))
    one = system.run(dict(params, h=sizes[0]), steps=1, method=method, **start)
    fixed = system.run(params, steps=1, method=method, **start)
    for name in run["q"]:
        assert np.array_equal(one["q"][name][1], run["q"][name][1]), name
        assert np.array_equal(one["p"][name][1], run["p"][name][1]), name
    assert any(not np.array_equal(fixed["p"][n][1], run["p"][n][1]) for n in run["p"])
