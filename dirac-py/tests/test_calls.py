"""What every run method does with a call it cannot honour, and README.md's Python as written:
a keyword it does not take is a TypeError naming it (and the closest one it takes); a run whose
trajectory cannot be allocated is refused before anything is allocated; Ctrl-C ends a run
promptly, with the trajectory so far on the KeyboardInterrupt."""

import math
import os
import pathlib
import re
import resource
import signal
import threading
import time

import numpy as np
import pytest

import dirac

from sources import ROOT, function


KEPLER = function("src/systems/kepler.rs", "kepler")
RIGID_BODY = function("src/systems/rotations.rs", "rigid_body")
TODA_N = function("examples/common/toda_n.rs", "toda_n")

KEPLER_PARAMS = {"h": 0.01, "k": 1.0}
# A circular orbit: it runs for as many steps as asked.
KEPLER_START = dict(x=[1.0], w=[0.0], mu=[1.0], g=[0.0])
BODY_PARAMS = {"h": 0.01, "j1": 1.0, "j2": 2.0, "j3": 3.0}
BODY_START = dict(q={"r": np.eye(3)}, p={"r": [0.3, 1.0, 0.2]})
TODA_PARAMS = {"m": 1.0, "d": 1.0, "h": 0.05}


def toda_start(n):
    i = np.arange(n)
    return dict(q=i * 1.0 + 0.1 * np.sin(2 * np.pi * i / n), p=0.05 + 0.0 * i)


def test_readme_python_runs_as_written():
    """Every ```python block of README.md, run as a user pastes it, in a fresh namespace."""
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    assert blocks, "README.md has no Python block"
    for i, block in enumerate(blocks):
        exec(compile(block, f"README.md, Python block {i + 1}", "exec"), {"__name__": "readme"})


# -- keywords ---------------------------------------------------------------------------------


def unexpected(call, keyword, closest=None):
    with pytest.raises(TypeError) as info:
        call()
    message = str(info.value)
    assert f"'{keyword}'" in message, message
    if closest is not None:
        assert f"did you mean '{closest}'" in message, message
    return message


def test_every_run_method_refuses_a_keyword_it_does_not_take():
    kepler = dirac.compile(KEPLER)
    p, s = KEPLER_PARAMS, KEPLER_START
    unexpected(lambda: kepler.run(p, steps=10, ordr=4, **s), "ordr", "order")
    unexpected(lambda: kepler.run(p, steps=10, tolerance=1e-3, **s), "tolerance", "tol")
    unexpected(lambda: kepler.run(p, steps=10, method="minus", energie=True, **s), "energie",
               "energies")
    # A start of the other method is named as such.
    message = unexpected(lambda: kepler.run(p, steps=10, q=[1.0, 0.0], p=[0.0, 1.0], **s), "q")
    assert "unreduced" in message, message
    message = unexpected(lambda: kepler.run(p, steps=10, method="unreduced", q=[1.0, 0.0],
                                            p=[0.0, 1.0], x=[1.0]), "x")
    assert "x, w, mu, g" in message, message
    starts = {k: np.array([v]) for k, v in s.items()}
    unexpected(lambda: kepler.ensemble(p, steps=10, ordr=2, **starts), "ordr", "order")
    unexpected(lambda: kepler.write(p, steps=10, path="unused", methd="minus", **s), "methd",
               "method")
    body = dirac.compile(RIGID_BODY)
    unexpected(lambda: body.run(BODY_PARAMS, steps=10, ordr=4, **BODY_START), "ordr", "order")
    unexpected(lambda: body.write(BODY_PARAMS, steps=10, path="unused", tolerance=1e-3,
                                  **BODY_START), "tolerance", "tol")
    toda = dirac.compile(TODA_N)
    unexpected(lambda: toda.run(TODA_PARAMS, steps=10, sizes={"n": 8}, ordr=4, **toda_start(8)),
               "ordr", "order")
    # Spelled right, the same calls run.
    assert kepler.run(p, steps=10, order=4, tol=1e-12, **s)["x"].shape == (11, 1)


# -- memory -----------------------------------------------------------------------------------


def refused(call):
    """The OutOfMemoryError of `call`, which must arrive at once and without the memory."""
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.monotonic()
    with pytest.raises(dirac.OutOfMemoryError) as info:
        call()
    assert time.monotonic() - start < 2.0
    # ru_maxrss is in KiB: the peak grew by less than 64 MiB.
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 64 * 1024
    assert isinstance(info.value, MemoryError)
    assert info.value.bytes > 10**12 and "steps" in info.value.what
    return info.value


def test_a_trajectory_that_cannot_be_allocated_is_refused_before_it_is():
    kepler = dirac.compile(KEPLER)
    refused(lambda: kepler.run(KEPLER_PARAMS, steps=10**12, **KEPLER_START))
    starts = {k: np.array([v] * 2) for k, v in KEPLER_START.items()}
    refused(lambda: kepler.ensemble(KEPLER_PARAMS, steps=10**12, **starts))
    body = dirac.compile(RIGID_BODY)
    refused(lambda: body.run(BODY_PARAMS, steps=10**12, **BODY_START))
    toda = dirac.compile(TODA_N)
    refused(lambda: toda.run(TODA_PARAMS, steps=10**12, sizes={"n": 100}, **toda_start(100)))


# -- Ctrl-C -----------------------------------------------------------------------------------

# Far more steps than run in the time before the interrupt, even optimized (seconds); their
# trajectory (under 2 GB) can be reserved, and only what is computed before the interrupt is
# touched.
LONG = 5_000_000


def interrupted(call, after=0.3):
    """The KeyboardInterrupt of `call`, with SIGINT sent to this process after `after` seconds
    from another thread (as Ctrl-C sends it), and the seconds from the signal to the exception."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(after, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as info:
            call()
        return info.value, time.monotonic() - start - after
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_ctrl_c_ends_a_run_promptly_with_the_trajectory_so_far():
    kepler = dirac.compile(KEPLER)
    error, late = interrupted(lambda: kepler.run(KEPLER_PARAMS, steps=LONG, **KEPLER_START))
    assert late < 2.0, late
    run = error.trajectory
    rows = run["t"].shape[0]
    assert 2 <= rows < LONG + 1
    assert run["x"].shape == (rows, 1) and run["iterations"].shape == (rows - 1,)
    # The states so far are the run's own: the circular orbit's radius, μ kept exactly.
    assert np.max(np.abs(run["x"] - 1.0)) < 1e-2 and np.all(run["mu"] == 1.0)
    assert run["t"][-1] == pytest.approx(0.01 * (rows - 1))


def test_a_short_run_returns_at_once():
    """The run's thread wakes the caller when it is done: a run of one step does not wait for
    the caller's next look at the signals (20 ms)."""
    kepler = dirac.compile(KEPLER)
    start = time.monotonic()
    for _ in range(100):
        kepler.run(KEPLER_PARAMS, steps=1, **KEPLER_START)
    assert time.monotonic() - start < 1.0


def test_ctrl_c_ends_an_ensemble_and_a_run_of_each_kind_of_system():
    kepler = dirac.compile(KEPLER)
    starts = {k: np.array([v] * 2) for k, v in KEPLER_START.items()}
    error, late = interrupted(lambda: kepler.ensemble(KEPLER_PARAMS, steps=LONG, **starts))
    assert late < 2.0, late
    ens = error.ensemble
    assert ens["x"].shape[0] == 2 and 2 <= ens["x"].shape[1] < LONG + 1
    assert np.isfinite(ens["x"][:, 0]).all()
    body = dirac.compile(RIGID_BODY)
    error, late = interrupted(lambda: body.run(BODY_PARAMS, steps=LONG, **BODY_START))
    assert late < 2.0, late
    assert 2 <= error.trajectory["q"]["r"].shape[0] < LONG + 1
    toda = dirac.compile(TODA_N)
    error, late = interrupted(lambda: toda.run(TODA_PARAMS, steps=LONG // 5, sizes={"n": 20},
                                               **toda_start(20)))
    assert late < 2.0, late
    assert error.trajectory["q"]["x"].shape[1] == 20


def test_ctrl_c_ends_a_run_written_to_parquet_with_the_states_so_far_written(tmp_path):
    kepler = dirac.compile(KEPLER)
    out = tmp_path / "kepler.parquet"
    error, late = interrupted(
        lambda: kepler.write(KEPLER_PARAMS, steps=LONG, path=str(out), **KEPLER_START))
    assert late < 2.0, late
    assert 1 <= error.steps < LONG and pathlib.Path(error.path).exists()
    assert error.t == pytest.approx(0.01 * error.steps)
    pq = pytest.importorskip("pyarrow.parquet")
    table = pq.read_table(error.path)
    assert table.num_rows == error.steps + 1
    assert math.isclose(table.column("t").to_numpy()[-1], error.t)
