"""MuJoCo's side of the 7-DoF arm comparison (benches/mujoco/run.sh runs it).

Loads examples/data/iiwa14.urdf into MuJoCo with the mechanics dirac's model of the same file has
(dirac_multibody reads the links' inertials and the joints, and writes neither limits nor
<dynamics> damping into the system text): no contacts, no joint limits, no damping, armature or
friction loss, gravity (0, 0, -9.81), h = 1 ms, from the start of dirac-jit's example urdf_arm.
The fixed joints are fused, as MuJoCo reads a URDF by default (the bodies they fuse are massless
or fixed to the world, so the motion is the same, and MuJoCo's step is the cheaper for it).
Then steps it 10^6 times per integrator (RK4, implicitfast, Euler), single thread, in C:

* energy: mujoco.rollout.rollout on a model with the e_potential and e_kinetic sensors, whose
  values mj_step computes at the state each step starts from (the last state's by
  mj_energyPos/mj_energyVel); MuJoCo's reset on a diverged state is off, so a divergence shows as
  the first step whose energy is not finite;
* timed, over as many steps as stayed finite: the rollout on the model without sensors (every
  state stored, as dirac's run collects its trajectory), and mj_step(m, d, nstep) (nothing stored).

With --start (dirac's `{"start": ...}` line from `urdf_arm --machine`) it checks the models first:
the mass matrix and both energies at the start against dirac's, on the model with every link a body
of its own (the potential energy then counts the fixed base link's, as dirac's does) and on the
fused one. Each --check (dirac's `{"run": ...}` line of a short run at some h) compares dirac's last
angles with MuJoCo RK4's at h/10 after the same time. Prints one line of JSON (prefixed
`mujoco: `) with the figures, and a human summary to stderr.

usage: iiwa.py [--steps N] [--start JSON] [--check JSON]... [--integrators rk4,implicitfast,euler]
"""

import argparse
import json
import os
import re
import sys
import tempfile
import time

import mujoco
import mujoco.rollout
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, "..", "..", "examples", "data", "iiwa14.urdf")

# The start of dirac-jit/examples/urdf_arm.rs (its `q0` and `v0`), used when --start is not given.
Q0 = [0.3, 0.5, -0.2, -1.2, 0.4, 0.7, -0.1]
V0 = [0.5, -0.4, 0.8, 0.6, -1.0, 0.9, 1.5]

H = 1e-3
# dirac_multibody::STANDARD_GRAVITY, which Model::from_urdf_file gives the model.
GRAVITY = [0.0, 0.0, -9.81]

INTEGRATORS = {
    "rk4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
}


def spec_from_urdf(path, fuse):
    """The URDF as an MjSpec: no visual elements, the inertias as written, the fixed joints fused
    into their parents' bodies or (`fuse` false) every link a body of its own."""
    text = open(path).read()
    compiler = (
        '<mujoco><compiler discardvisual="true" fusestatic="%s" '
        'balanceinertia="false" strippath="false"/></mujoco>' % ("true" if fuse else "false")
    )
    text, n = re.subn(r"(<robot[^>]*>)", r"\1" + compiler, text, count=1)
    if n != 1:
        sys.exit(f"iiwa.py: no <robot> element in {path}")
    if "<mesh" in text.split("-->", 1)[-1]:
        sys.exit(f"iiwa.py: {path} references meshes; this script expects none")
    with tempfile.TemporaryDirectory() as tmp:
        copy = os.path.join(tmp, "model.urdf")
        with open(copy, "w") as f:
            f.write(text)
        return mujoco.MjSpec.from_file(copy)


def model(integrator, sensors=False, h=H, fuse=True):
    spec = spec_from_urdf(URDF, fuse)
    for joint in spec.joints:
        joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
        joint.damping = np.zeros_like(np.atleast_1d(joint.damping))
        joint.armature = 0.0
        joint.frictionloss = 0.0
    spec.option.timestep = h
    spec.option.gravity = GRAVITY
    spec.option.integrator = integrator
    spec.option.disableflags |= (
        mujoco.mjtDisableBit.mjDSBL_CONTACT
        | mujoco.mjtDisableBit.mjDSBL_LIMIT
        | mujoco.mjtDisableBit.mjDSBL_AUTORESET
    )
    if sensors:
        spec.add_sensor(type=mujoco.mjtSensor.mjSENS_E_POTENTIAL, name="potential")
        spec.add_sensor(type=mujoco.mjtSensor.mjSENS_E_KINETIC, name="kinetic")
    m = spec.compile()
    assert m.nq == m.nv == 7, (m.nq, m.nv)
    assert not m.jnt_limited.any() and not m.dof_damping.any() and not m.dof_armature.any()
    assert not m.dof_frictionloss.any() and m.nu == 0
    return m


def start_state(m, q, v):
    d = mujoco.MjData(m)
    d.qpos[:] = q
    d.qvel[:] = v
    mujoco.mj_forward(m, d)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, state, spec)
    return d, state


def energies_at(m, d):
    mujoco.mj_energyPos(m, d)
    mujoco.mj_energyVel(m, d)
    return float(d.energy[0]), float(d.energy[1])


def check_start(start):
    """MuJoCo's mass matrix and energies at dirac's start against dirac's."""
    out = {}
    for fuse in (False, True):
        m = model(INTEGRATORS["rk4"], fuse=fuse)
        d, _ = start_state(m, start["q"], start["v"])
        mass = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, mass)
        potential, kinetic = energies_at(m, d)
        out["fused" if fuse else "unfused"] = {
            "mass_matrix_max_abs_diff": float(np.abs(mass - np.array(start["mass_matrix"])).max()),
            "potential_diff": potential - start["potential"],
            "kinetic_diff": kinetic - start["kinetic"],
        }
    out["mass_matrix_max_abs"] = float(np.abs(np.array(start["mass_matrix"])).max())
    # Round-off agreement, or the two are not the same mechanics. The fused model's potential
    # lacks the fixed base link's (a constant, which no energy error sees).
    tol = 1e-12 * (start["kinetic"] + abs(start["potential"]) + out["mass_matrix_max_abs"])
    worst = max(
        max(out[k]["mass_matrix_max_abs_diff"], abs(out[k]["kinetic_diff"]))
        for k in ("fused", "unfused")
    )
    worst = max(worst, abs(out["unfused"]["potential_diff"]))
    if not worst <= tol:
        sys.exit(f"iiwa.py: MuJoCo's model differs from dirac's at the start: {out}")
    return out


def check_run(run, q, v):
    """The last angles of dirac's short run against MuJoCo RK4's at a tenth of its step."""
    m = model(INTEGRATORS["rk4"], h=run["h"] / 10)
    d, _ = start_state(m, q, v)
    mujoco.mj_step(m, d, nstep=10 * run["steps"])
    diff = np.abs(d.qpos - np.array(run["q_end"]))
    return {"steps": run["steps"], "h": run["h"], "q_end_max_abs_diff": float(diff.max())}


def measure(name, steps, q, v):
    integrator = INTEGRATORS[name]
    # Energies at every state, from the sensors (computed at the state each step starts from).
    ms = model(integrator, sensors=True)
    ds, state = start_state(ms, q, v)
    states, sensordata = mujoco.rollout.rollout(ms, ds, state, nstep=steps)
    energy = sensordata[0].sum(axis=1)
    # The last state's energy (the sensors of step k are those of the state before it).
    mujoco.mj_setState(ms, ds, states[0, -1], mujoco.mjtState.mjSTATE_FULLPHYSICS)
    energy = np.append(energy, sum(energies_at(ms, ds)))
    del states, sensordata
    # Diverged: the energy not finite, or its error past the energy itself.
    bad = np.flatnonzero(~(np.abs(energy - energy[0]) <= abs(energy[0])))
    # The steps up to the first diverged state (all of them if none).
    kept = int(bad[0]) - 1 if len(bad) else steps
    error = energy[: kept + 1] - energy[0]
    past_1j = np.flatnonzero(np.abs(error) > 1.0)
    tenth = max(len(error) // 10, 1)

    # The timed runs, over the steps before the divergence, repeated from the start to `steps`
    # steps in all (so a diverging integrator's time is not taken on exploding numbers).
    chunk = max(kept, 1)
    rounds = -(-steps // chunk)
    m = model(integrator)
    d, state = start_state(m, q, v)
    # Rollout: every state stored, in C, in this thread (one model, one data).
    started = time.perf_counter()
    for _ in range(rounds):
        mujoco.rollout.rollout(m, d, state, nstep=chunk)
    rollout_s = time.perf_counter() - started
    # mj_step with nstep: the loop in C, nothing stored.
    step_s = 0.0
    for _ in range(rounds):
        d, _ = start_state(m, q, v)
        started = time.perf_counter()
        mujoco.mj_step(m, d, nstep=chunk)
        step_s += time.perf_counter() - started
    timed = rounds * chunk
    return {
        "integrator": name,
        "steps": steps,
        "steps_before_divergence": kept if len(bad) else None,
        "timed_steps": timed,
        "us_per_step_rollout": rollout_s * 1e6 / timed,
        "us_per_step_mj_step": step_s * 1e6 / timed,
        "energy0": float(energy[0]),
        "energy_error": float(np.abs(error).max()),
        "energy_error_1e4": float(np.abs(error[: 10**4 + 1]).max()),
        "energy_drift": float(error[-tenth:].mean() - error[:tenth].mean()),
        "first_step_past_1_joule": int(past_1j[0]) if len(past_1j) else None,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=10**6)
    parser.add_argument("--start", help="dirac's {\"start\": ...} line")
    parser.add_argument(
        "--check", action="append", default=[], help="dirac's {\"run\": ...} line of a short run"
    )
    parser.add_argument("--integrators", default="rk4,implicitfast,euler")
    args = parser.parse_args()

    out = {"mujoco": mujoco.__version__}
    q, v = Q0, V0
    if args.start:
        start = json.loads(args.start)["start"]
        q, v = start["q"], start["v"]
        out["start_check"] = check_start(start)
    out["run_check"] = [check_run(json.loads(c)["run"], q, v) for c in args.check]
    out["runs"] = [measure(name, args.steps, q, v) for name in args.integrators.split(",")]
    print("mujoco: " + json.dumps(out), flush=True)
    for r in out["runs"]:
        print(
            f"  MuJoCo {out['mujoco']} {r['integrator']}: {r['us_per_step_rollout']:.3f} us per"
            f" step (rollout), {r['us_per_step_mj_step']:.3f} (mj_step); largest energy error"
            f" {r['energy_error']:.2e} J, drift {r['energy_drift']:+.2e} J"
            + (
                f" (up to step {r['steps_before_divergence']}: diverged after it)"
                if r["steps_before_divergence"] is not None
                else ""
            ),
            file=sys.stderr,
        )


if __name__ == "__main__":
    main()
