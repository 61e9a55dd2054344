# %% [markdown]
# # The paper's Figure 3 from Python
#
# The double spherical pendulum of Rodríguez Abella & Leok (§7.2), given as text, compiled to
# machine code and integrated by the reduced (+) equations: φ1 over time and the XY trace of the
# second bob, as in the paper's Figure 3.
#
# Run it as a script (`python figure3.py out.png`) or cell by cell in a notebook.

# %%
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import dirac

# %% The system: the same text as the compiled-in `dirac::paper::double_spherical_pendulum`.
root = pathlib.Path(__file__).resolve().parents[2]
source = (root / "src/paper.rs").read_text()
start = source.index("pub fn double_spherical_pendulum(")
text = source[source.rindex("#[reduced_lagrangian", 0, start):source.index("\n}\n", start) + 2]
dsp = dirac.compile(text)
print(dsp, f"compiled in {dsp.compile_time * 1e3:.0f} ms")

# %% The paper's run: T = 100, N = 10⁴, m1 = 20, m2 = 35, l1 = 500, l2 = 800, g = 9.8.
params = {"h": 0.01, "m1": 20.0, "m2": 35.0, "l1": 500.0, "l2": 800.0, "g": 9.8}
run = dsp.run(params, steps=10_000, x=[2.25, 2.0, 3.0], w=[0.0, 1.0, 1.0], mu=[0.0], g=[0.0])
assert np.all(run["mu"] == 0.0)  # the momentum of the symmetry, exactly

# %% Back to the bobs: x = (φ1, ϑ2, φ2), g = (ϑ1), θ1 = ϑ1 − ϑ2, θ2 = ϑ1 + ϑ2.
phi1, vt2, phi2 = run["x"].T
vt1 = run["g"][:, 0]
th1, th2 = vt1 - vt2, vt1 + vt2
l1, l2 = params["l1"], params["l2"]
x2 = l1 * np.sin(phi1) * np.cos(th1) + l2 * np.sin(phi2) * np.cos(th2)
y2 = l1 * np.sin(phi1) * np.sin(th1) + l2 * np.sin(phi2) * np.sin(th2)

# %% Figure 3: φ1(t), and the second bob seen from above.
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
a.plot(run["t"], phi1, lw=0.8)
a.set_xlabel("t")
a.set_ylabel("φ1")
b.plot(x2, y2, lw=0.5)
b.set_aspect("equal")
b.set_xlabel("X")
b.set_ylabel("Y")
fig.suptitle("Double spherical pendulum, reduced (+) equations, h = 0.01")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "figure3.png", dpi=120)
