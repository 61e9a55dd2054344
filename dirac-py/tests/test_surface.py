"""One class surface: a system on vector spaces, one on rotation groups and an element-wise one
each run, write to Parquet and run ensembles with the same keywords (`steps`, `method`, `order`,
`tol`, the start by coordinate name, the sizes of an element-wise system as `sizes=`), and return
results of one shape: `t`, `q` and `p` dicts by coordinate, `iterations`, `residuals`. What is
written reads back bit for bit as the run, and an ensemble's members are its single runs bit for
bit (the same steps in the same order), a failed member reported by its index."""

import numpy as np
import pytest

import dirac

from sources import function


KEPLER = function("src/systems/kepler.rs", "kepler")
RIGID_BODY = function("src/systems/rotations.rs", "rigid_body")
TODA_N = function("examples/common/toda_n.rs", "toda_n")

N = 8  # the lattice's particles


def member_start(kind, i):
    """Member `i`'s start of each kind, by coordinate name."""
    e = 0.01 * i
    if kind == "flat":
        # Kepler unreduced, near the circular orbit.
        return dict(q={"r": 1.0 + e, "phi": 0.0}, p={"r": e, "phi": 1.0})
    if kind == "lie":
        return dict(q={"r": np.eye(3)}, p={"r": [0.3 + e, 1.0, 0.2 - e]})
    j = np.arange(N)
    return dict(q={"x": j + 0.1 * np.sin(2 * np.pi * j / N) + e}, p={"x": 0.05 + e * np.cos(j)})


SYSTEMS = {
    # (text, parameters, method, the keywords every call takes besides the start)
    "flat": (KEPLER, {"h": 0.01, "k": 1.0}, "unreduced", {}),
    "lie": (RIGID_BODY, {"h": 0.01, "j1": 1.0, "j2": 2.0, "j3": 3.0}, "plus", {}),
    "element": (TODA_N, {"m": 1.0, "d": 1.0, "h": 0.05}, "plus", {"sizes": {"n": N}}),
}
COORDINATES = {"flat": ["r", "phi"], "lie": ["r"], "element": ["x"]}


def written_columns(kind, table, name, key):
    """What `write` wrote of coordinate `name`'s `key` ("q" or "p"), shaped as `run` returns it."""
    columns = table.column_names
    if kind == "flat":
        return table.column(f"{key}_{name}").to_numpy()
    if kind == "lie":
        if key == "q":
            entries = [f"q_{name}_{i}{j}" for i in range(3) for j in range(3)]
            return np.column_stack([table.column(c).to_numpy() for c in entries]).reshape(-1, 3, 3)
        return np.column_stack([table.column(f"p_{name}_{a}").to_numpy() for a in "xyz"])
    entries = [c for c in columns if c.startswith(f"{key}_") and c[2:].isdigit()]
    assert len(entries) == N, columns
    return np.column_stack([table.column(f"{key}_{i}").to_numpy() for i in range(N)])


def assert_same(a, b, path="run"):
    """`a` and `b` equal bit for bit, dicts key by key (NaN where both are NaN)."""
    if isinstance(a, dict):
        assert list(a) == list(b), (path, list(a), list(b))
        for key in a:
            assert_same(a[key], b[key], f"{path}[{key!r}]")
        return
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, (path, a.shape, b.shape)
    assert np.array_equal(a, b, equal_nan=True), path


@pytest.mark.parametrize("kind", SYSTEMS)
def test_every_class_runs_with_the_same_keywords_and_returns_one_shape(kind):
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    run = system.run(params, steps=20, method=method, order=2, tol=1e-14, **fixed,
                     **member_start(kind, 0))
    assert run["t"].shape == (21,)
    for key in ("q", "p"):
        assert list(run[key]) == COORDINATES[kind], (key, list(run[key]))
        for values in run[key].values():
            assert values.shape[0] == 21
    assert run["iterations"].shape == (20,) and run["residuals"].shape == (20,)
    # The compositions take the same keywords.
    four = system.run(params, steps=5, method=method, order=4, **fixed, **member_start(kind, 0))
    assert list(four["q"]) == COORDINATES[kind]


@pytest.mark.parametrize("kind", SYSTEMS)
def test_every_class_writes_what_it_runs_bit_for_bit(kind, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    start = member_start(kind, 1)
    out = tmp_path / f"{kind}.parquet"
    summary = system.write(params, steps=30, path=str(out), method=method, **fixed, **start)
    assert summary["steps"] == 30
    table = pq.read_table(out)
    run = system.run(params, steps=30, method=method, **fixed, **start)
    assert np.array_equal(table.column("t").to_numpy(), run["t"])
    for name in COORDINATES[kind]:
        for key in ("q", "p"):
            written = written_columns(kind, table, name, key)
            assert np.array_equal(written, run[key][name].reshape(written.shape)), (name, key)


@pytest.mark.parametrize("kind", SYSTEMS)
def test_every_class_runs_ensembles_whose_members_are_its_runs(kind):
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    m = 3
    members = [member_start(kind, i) for i in range(m)]
    # The starts stacked along a leading member axis, coordinate by coordinate.
    starts = {key: {name: np.array([s[key][name] for s in members]) for name in members[0][key]}
              for key in ("q", "p")}
    ens = system.ensemble(params, steps=25, method=method, **fixed, **starts)
    assert ens["failed"] == []
    assert ens["t"].shape == (m, 26)
    for i, start in enumerate(members):
        one = system.run(params, steps=25, method=method, **fixed, **start)
        assert_same({k: v[i] for k, v in ens.items() if k != "failed" and not isinstance(v, dict)},
                    {k: v for k, v in one.items() if not isinstance(v, dict)}, f"member {i}")
        for key in ("q", "p"):
            assert_same({n: a[i] for n, a in ens[key].items()}, one[key], f"member {i} {key}")


WALLS = {
    # A particle or lattice in a potential c √x: NaN once x < 0, reached by the members moving
    # towards it.
    "flat": ("#[reduced_lagrangian(shape(x), group())]\n"
             "fn wall(q0: Config, q1: Config, h: f64, c: f64) -> f64 {\n"
             "    0.5 / h * (q1.x - q0.x) * (q1.x - q0.x) - h * c * q0.x.sqrt()\n"
             "}", {"h": 0.1, "c": 1e-6}, {}, lambda v: dict(x=[[1.0]] * len(v), w=[[u] for u in v])),
    "lie": ("#[reduced_lagrangian(rotation(r))]\n"
            "fn wall(q0: Config, q1: Config, h: f64, c: f64) -> f64 {\n"
            "    let f = q0.r.transpose() * q1.r;\n"
            "    ((Matrix3::identity() - f) * Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 1.0)))"
            ".trace() / h\n"
            "        - h * c * (q0.r[(2, 2)] - 0.5).sqrt()\n"
            "}", {"h": 0.1, "c": 1e-6}, {},
            lambda v: dict(q={"r": np.array([np.eye(3)] * len(v))},
                           p={"r": np.array([[u, 0.0, 0.0] for u in v])})),
    "element": ("#[reduced_lagrangian(coordinates(x[n]), rule = midpoint)]\n"
                "fn wall(q: Config, v: Velocity, c: f64, n: usize) -> f64 {\n"
                "    let mut l = 0.0;\n"
                "    for i in 0..n { l += 0.5 * v.x[i] * v.x[i] + c * q.x[i].sqrt(); }\n"
                "    l\n"
                "}", {"c": 1e-6, "h": 0.1}, {"sizes": {"n": 2}},
                lambda v: dict(q=np.ones((len(v), 2)), p=np.array([[u, u] for u in v]))),
}


@pytest.mark.parametrize("kind", WALLS)
def test_a_failed_member_is_reported_by_its_index_the_others_run_to_the_end(kind):
    text, params, fixed, starts = WALLS[kind]
    wall = dirac.compile(text)
    # Member 1 runs into the wall (the body turning about its first axis until cos θ < 1/2);
    # members 0 and 2 move away from it or stay.
    speeds = [0.01, -1.0, 0.0] if kind != "lie" else [0.0, 1.0, 0.0]
    with pytest.raises(dirac.StepError) as info:
        wall.ensemble(params, steps=100, **fixed, **starts(speeds))
    e = info.value
    assert e.member == 1 and 0 < e.step < 100
    ens = e.ensemble
    assert [(i, step) for i, step, _ in ens["failed"]] == [(1, e.step)]
    name = COORDINATES["lie"][0] if kind == "lie" else "x"
    q = ens["q"][name]
    assert q.shape[:2] == (3, 101)
    # The others to the end; the failed one up to its last state, NaN after it.
    assert np.all(np.isfinite(q[0])) and np.all(np.isfinite(q[2]))
    assert np.all(np.isfinite(q[1, : e.step + 1])) and np.all(np.isnan(q[1, e.step + 1:]))
    # Its own trajectory on the exception, as a single run's.
    assert e.trajectory["q"][name].shape[0] == e.step + 1


def test_keywords_every_class_refuses_name_the_keyword():
    for kind, (text, params, method, fixed) in SYSTEMS.items():
        system = dirac.compile(text)
        start = member_start(kind, 0)
        stacked = {key: {n: np.array([v]) for n, v in start[key].items()} for key in ("q", "p")}
        fixed = dict(fixed, method=method)
        calls = {
            "run": lambda **k: system.run(params, steps=1, **fixed, **start, **k),
            "write": lambda **k: system.write(params, steps=1, path="unused", **fixed, **start,
                                              **k),
            "ensemble": lambda **k: system.ensemble(params, steps=1, **fixed, **stacked, **k),
        }
        for name, call in calls.items():
            with pytest.raises(TypeError, match="'ordr'") as info:
                call(ordr=2)
            assert "did you mean 'order'" in str(info.value) or name == "write", (kind, name)


def test_the_sizes_given_before_the_steps_still_run_with_a_deprecation_warning():
    toda = dirac.compile(TODA_N)
    params = SYSTEMS["element"][1]
    start = member_start("element", 0)
    new = toda.run(params, 10, sizes={"n": N}, **start)
    with pytest.warns(DeprecationWarning, match="sizes="):
        old = toda.run(params, {"n": N}, 10, **start)
    assert_same(old, new)


@pytest.mark.parametrize("kind", SYSTEMS)
def test_a_request_the_system_cannot_run_is_a_value_error_from_every_class(kind):
    """One run request, checked in one place: the same words and messages for every class."""
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    start = member_start(kind, 0)
    for keywords, message in [
        (dict(method="sideways"), "unknown method `sideways`"),
        (dict(method=method, order=3), "accepted 2"),
        (dict(method=method, tol=float("nan")), "positive finite"),
        (dict(method=method, tol=-1e-12), "positive finite"),
        (dict(method=method, tol=0.0), "positive finite"),
        (dict(method=method, end_time=-1.0), "positive finite"),
        (dict(method=method, end_time=float("inf")), "positive finite"),
    ]:
        with pytest.raises(ValueError, match=message):
            system.run(params, steps=1, **fixed, **keywords, **start)


@pytest.mark.parametrize("kind", SYSTEMS)
def test_every_class_runs_writes_and_runs_ensembles_up_to_an_end_time(kind, tmp_path):
    """`end_time=` with `steps` an upper bound: the last step shortened to land on the time
    exactly (a time between two of the system's steps), the same for run, write and ensemble."""
    pq = pytest.importorskip("pyarrow.parquet")
    text, params, method, fixed = SYSTEMS[kind]
    system = dirac.compile(text)
    h = params["h"]
    end = 6.5 * h
    start = member_start(kind, 0)
    run = system.run(params, steps=1000, end_time=end, method=method, **fixed, **start)
    assert run["t"][-1] == end and len(run["t"]) == 8, run["t"]
    assert np.all(np.diff(run["t"])[:-1] == pytest.approx(h)) and run["t"][-1] - run["t"][-2] < h
    for values in run["q"].values():
        assert values.shape[0] == 8
    # At most `steps`: whichever ends the run first.
    assert len(system.run(params, steps=3, end_time=end, method=method, **fixed, **start)["t"]) == 4
    out = tmp_path / f"{kind}.parquet"
    summary = system.write(params, steps=1000, path=str(out), end_time=end, method=method,
                           **fixed, **start)
    assert summary["steps"] == 7 and summary["t"] == end
    assert np.array_equal(pq.read_table(out).column("t").to_numpy(), run["t"])
    stacked = {key: {n: np.array([v, v]) for n, v in start[key].items()} for key in ("q", "p")}
    ens = system.ensemble(params, steps=1000, end_time=end, method=method, **fixed, **stacked)
    assert ens["t"].shape == (2, 8) and ens["failed"] == []
    for i in range(2):
        assert_same({n: a[i] for n, a in ens["q"].items()}, run["q"], f"member {i}")
