"""The cost of Python around a run: `run` of the paper's double spherical pendulum for 10⁴
steps (parameters in, NumPy arrays out), against the same run timed inside Rust around the
integrator alone, interleaved in one process; medians and spread over repeats.

    python overhead.py [repeats]
"""

import pathlib
import statistics
import sys
import time

import dirac

root = pathlib.Path(__file__).resolve().parents[2]
source = (root / "src/paper.rs").read_text()
start = source.index("pub fn double_spherical_pendulum(")
text = source[source.rindex("#[reduced_lagrangian", 0, start):source.index("\n}\n", start) + 2]
dsp = dirac.compile(text)
params = {"h": 0.01, "m1": 20.0, "m2": 35.0, "l1": 500.0, "l2": 800.0, "g": 9.8}
state = dict(x=[2.25, 2.0, 3.0], w=[0.0, 1.0, 1.0], mu=[0.0], g=[0.0])
repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 15
# One untimed run of each first: the first call pays for pages and caches, not for Python.
dsp.run(params, steps=10_000, **state)
dsp._core_seconds(params, steps=10_000, **state)
python, core, ratios = [], [], []
for _ in range(repeats):
    t = time.perf_counter()
    dsp.run(params, steps=10_000, **state)
    p = time.perf_counter() - t
    c = dsp._core_seconds(params, steps=10_000, **state)
    python.append(p)
    core.append(c)
    ratios.append(p / c)
print(f"10^4 steps: Python run {statistics.median(python) * 1e3:.2f} ms, the integrator alone "
      f"{statistics.median(core) * 1e3:.2f} ms; overhead {100 * (statistics.median(ratios) - 1):.1f}% "
      f"(per-repeat {100 * (min(ratios) - 1):.1f}% to {100 * (max(ratios) - 1):.1f}%) over {repeats} repeats")
