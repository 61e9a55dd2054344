"""The table of benches/mujoco/run.sh from the lines it collected.

Reads a file of JSON lines: {"rep": r, "load": "...", "dirac": {...}} and {"rep": r, "mujoco":
{...}} (urdf_arm's `{"run": ...}` and iiwa.py's `mujoco: ` lines), plus one {"start_check": ...}
and {"run_check": ...} from the first repetition. Prints per repetition the per-step times, the
ratio dirac / MuJoCo RK4, and the energy errors; then the ratio's spread over the repetitions.

usage: table.py RESULTS.jsonl
"""

import json
import sys


def main():
    lines = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
    dirac = {x["rep"]: x["dirac"] for x in lines if "dirac" in x}
    mujoco = {x["rep"]: x["mujoco"] for x in lines if "mujoco" in x}
    loads = {x["rep"]: x["load"] for x in lines if "load" in x}
    reps = sorted(set(dirac) & set(mujoco))
    if not reps:
        sys.exit("table.py: no repetition with both sides' figures")
    first = mujoco[reps[0]]
    print(f"MuJoCo {first['mujoco']}; 7-DoF iiwa, h = 1 ms, {dirac[reps[0]]['steps']} steps")

    check = first.get("start_check")
    if check:
        print(
            "models at the start: mass matrix max |diff| "
            f"{check['unfused']['mass_matrix_max_abs_diff']:.1e} (largest entry "
            f"{check['mass_matrix_max_abs']:.2f}), kinetic energy diff "
            f"{check['unfused']['kinetic_diff']:.1e} J, potential energy diff "
            f"{check['unfused']['potential_diff']:.1e} J"
        )
    for c in first.get("run_check", []):
        print(
            f"dirac's angles after {c['steps']} steps of {c['h'] * 1e3:g} ms against MuJoCo RK4 "
            f"at a tenth of the step: max |diff| {c['q_end_max_abs_diff']:.2e} rad"
        )

    names = [r["integrator"] for r in first["runs"]]
    print()
    header = ["rep", "dirac us"] + [f"{n} us" for n in names] + ["dirac/rk4", "load"]
    print("  ".join(f"{h:>12}" for h in header))
    ratios = []
    for rep in reps:
        runs = {r["integrator"]: r for r in mujoco[rep]["runs"]}
        d = dirac[rep]["us_per_step"]
        row = [str(rep), f"{d:.3f}"]
        row += [f"{runs[n]['us_per_step_rollout']:.3f}" for n in names]
        ratio = d / runs["rk4"]["us_per_step_rollout"] if "rk4" in runs else float("nan")
        ratios.append(ratio)
        row += [f"{ratio:.3f}", loads.get(rep, "")]
        print("  ".join(f"{c:>12}" for c in row))
    print(
        f"dirac / MuJoCo RK4 (rollout): {min(ratios):.3f}-{max(ratios):.3f} over {len(ratios)} "
        f"repetitions (target <= 2: {'met' if max(ratios) <= 2 else 'missed'} in "
        f"{sum(r <= 2 for r in ratios)} of {len(ratios)})"
    )
    print("mj_step(nstep) without storing the states, us per step:")
    for n in names:
        times = [
            next(r for r in mujoco[rep]["runs"] if r["integrator"] == n)["us_per_step_mj_step"]
            for rep in reps
        ]
        print(f"  {n}: " + ", ".join(f"{t:.3f}" for t in times))

    print()
    print("energy error (J): largest |E - E0| over the run; drift = mean over the last tenth")
    print("less the first tenth; first step with |E - E0| > 1 J; step after which it diverged")
    print("(|E - E0| > |E0|)")
    for rep in reps:
        d = dirac[rep]
        print(
            f"  rep {rep} dirac: {d['energy_error']:.2e}, drift {d['energy_drift']:+.2e}, "
            f"{d['iterations']:.2f} Newton iterations per step"
        )
        for r in mujoco[rep]["runs"]:
            print(
                f"  rep {rep} {r['integrator']}: {r['energy_error']:.2e}, drift "
                f"{r['energy_drift']:+.2e}, over the first 10^4 steps "
                f"{r['energy_error_1e4']:.2e}, past 1 J at step "
                f"{r['first_step_past_1_joule']}, diverged after "
                f"{r['steps_before_divergence']}"
            )


if __name__ == "__main__":
    main()
