#!/usr/bin/env python3
r"""CasADi + IPOPT baseline: discrete-mechanics optimal control (DMOC) swing-up of the cart-pole.

Run (the interpreter comes from scripts/setup-casadi.sh, which installs casadi into target/py):

    "$(scripts/setup-casadi.sh)" examples/dmoc/cartpole_casadi.py [--N 100] [--T 2.0]
        [--guess linear|rest] [--repeats 10] [--csv PATH] [--check]

It prints one line of JSON on standard output: the optimal cost, IPOPT's iteration count, the
median and minimum wall time of the ``solver(...)`` call alone (the same solve repeated from the
same initial guess; building the transcription is not timed), and the largest constraint violation
at the optimum; with ``--check`` also the result of the forward simulation described below.

The discrete problem (exactly this one)
---------------------------------------
Cart-pole: cart mass ``mc = 1.0``, point mass ``m = 0.1`` at the end of a massless pole of length
``l = 0.5``, gravity ``g = 9.81``. Coordinates ``q = (theta, s)`` in this order: ``theta`` the pole
angle from upright, ``s`` the cart position; the bob is at ``(s + l sin theta, l cos theta)``.
Continuous Lagrangian

    L(q, v) = 1/2 (mc + m) s'^2 + m l cos(theta) s' theta' + 1/2 m l^2 theta'^2 - m g l cos(theta).

Midpoint rule: ``L_d(q0, q1) = h L((q0 + q1)/2, (q1 - q0)/h)``. A horizontal force ``u_k`` acts on
the cart, constant over step k; its virtual work is ``u delta s``, and the midpoint discrete forces
are ``f_k^- = f_k^+ = (h/2) (0, u_k)`` (components in (theta, s) order).

Horizon ``T = 2.0``, ``N = 100`` steps, ``h = T/N``. Boundary: ``q_0 = (pi, 0)`` at rest
(``p_0 = 0``), ``q_N = (0, 0)`` at rest (``p_N = 0``).

Objective ``J = h sum_{k=0}^{N-1} u_k^2``.

Constraints, the forced discrete Euler-Lagrange equations in position-momentum form (Marsden and
West), with ``D1, D2`` the partial derivatives of ``L_d`` in its first and second argument:

    D1 L_d(q_0, q_1) + f_0^- + p_0 = 0
    D2 L_d(q_{k-1}, q_k) + f_{k-1}^+ + D1 L_d(q_k, q_{k+1}) + f_k^- = 0    for k = 1 .. N-1
    D2 L_d(q_{N-1}, q_N) + f_{N-1}^+ - p_N = 0

Unknowns ``q_1 .. q_{N-1}`` and ``u_0 .. u_{N-1}`` (3N - 2 of them; 2(N + 1) equations).

Initial guess: ``--guess linear`` (the default, the primary run): ``q_k`` linear in k between the
two boundary configurations, ``u_k = 0``; ``--guess rest``: ``q_k = q_0`` for k < N, ``u_k = 0``.

Solver: CasADi SX expressions, exact first and second derivatives by CasADi, IPOPT (shipped with
the casadi wheel, MUMPS) with ``tol = 1e-12``, exact Hessian, ``print_level = 0``.

``--check``: from ``(q_0, p_0 = 0)`` and the optimal u, each step solves the 2x2 nonlinear equation
``D1 L_d(q_k, q_{k+1}) + f_k^- + p_k = 0`` for ``q_{k+1}`` by Newton (started at ``q_k``, exact
Jacobian), then sets ``p_{k+1} = D2 L_d(q_k, q_{k+1}) + f_k^+``; it reports how far the simulated
``q_N`` and ``p_N`` are from ``(0, 0)`` and ``0``, and the largest difference between the simulated
and the optimal ``q_k``.

``--csv PATH`` writes the optimum as ``k,theta,s,u`` for k = 0 .. N (u empty at k = N).
"""

import argparse
import json
import math
import statistics
import sys
import time

import casadi as ca
import numpy as np

MC, M, L, G = 1.0, 0.1, 0.5, 9.81
Q_START = (math.pi, 0.0)
Q_END = (0.0, 0.0)


def lagrangian(q, v):
    theta, _s = q[0], q[1]
    thetadot, sdot = v[0], v[1]
    return (0.5 * (MC + M) * sdot**2 + M * L * ca.cos(theta) * sdot * thetadot
            + 0.5 * M * L**2 * thetadot**2 - M * G * L * ca.cos(theta))


def discrete_derivatives(h):
    """CasADi functions D1 L_d(q0, q1) and D2 L_d(q0, q1) of the midpoint rule, as 2-vectors."""
    q0 = ca.SX.sym("q0", 2)
    q1 = ca.SX.sym("q1", 2)
    ld = h * lagrangian((q0 + q1) / 2, (q1 - q0) / h)
    d1 = ca.Function("D1Ld", [q0, q1], [ca.gradient(ld, q0)])
    d2 = ca.Function("D2Ld", [q0, q1], [ca.gradient(ld, q1)])
    return d1, d2


def build(n, t):
    """The NLP: unknowns x = (q_1 .. q_{N-1}, u_0 .. u_{N-1}), objective, constraints g = 0."""
    h = t / n
    d1, d2 = discrete_derivatives(h)
    qs = ca.SX.sym("q", 2, n - 1)
    us = ca.SX.sym("u", n)
    q = [ca.DM(Q_START)] + [qs[:, k] for k in range(n - 1)] + [ca.DM(Q_END)]
    p0 = ca.DM.zeros(2)
    pn = ca.DM.zeros(2)

    def force(k):  # f_k^- = f_k^+ = (h/2) (0, u_k)
        return ca.vertcat(0, h / 2 * us[k])

    g = [d1(q[0], q[1]) + force(0) + p0]
    for k in range(1, n):
        g.append(d2(q[k - 1], q[k]) + force(k - 1) + d1(q[k], q[k + 1]) + force(k))
    g.append(d2(q[n - 1], q[n]) + force(n - 1) - pn)
    x = ca.vertcat(ca.vec(qs), us)  # vec is column-major: theta_1, s_1, theta_2, s_2, ...
    nlp = {"x": x, "f": h * ca.sumsqr(us), "g": ca.vertcat(*g)}
    return nlp, d1, d2


def initial_guess(n, guess):
    qg = np.empty((2, n - 1))
    for k in range(1, n):
        if guess == "linear":
            a = k / n
            qg[:, k - 1] = [(1 - a) * Q_START[i] + a * Q_END[i] for i in range(2)]
        else:  # "rest": q_k = q_0 for k < N
            qg[:, k - 1] = Q_START
    return np.concatenate([qg.flatten(order="F"), np.zeros(n)])


def unpack(x, n):
    x = np.asarray(x).ravel()
    qs = x[: 2 * (n - 1)].reshape((2, n - 1), order="F")
    q = np.column_stack([Q_START, qs, Q_END])  # 2 x (N+1)
    return q, x[2 * (n - 1):]


def forward_check(q_opt, u, t, d1, d2):
    """Simulate the forced discrete Euler-Lagrange equations from (q_0, p_0 = 0) with u."""
    n = len(u)
    h = t / n
    qa = ca.SX.sym("qa", 2)
    qb = ca.SX.sym("qb", 2)
    pk = ca.SX.sym("pk", 2)
    uk = ca.SX.sym("uk")
    f = ca.vertcat(0, h / 2 * uk)
    res = d1(qa, qb) + f + pk
    step = ca.Function("step", [qa, qb, pk, uk], [res, ca.jacobian(res, qb)])
    newp = ca.Function("newp", [qa, qb, uk], [d2(qa, qb) + f])
    q = np.array(Q_START, dtype=float)
    p = np.zeros(2)
    traj = [q.copy()]
    max_newton = 0
    for k in range(n):
        qn = q.copy()
        for it in range(1, 51):
            r, jac = step(q, qn, p, u[k])
            dq = np.linalg.solve(np.array(jac), -np.array(r).ravel())
            qn = qn + dq
            if np.max(np.abs(dq)) <= 1e-15 * (1 + np.max(np.abs(qn))):
                break
        r, _ = step(q, qn, p, u[k])
        if np.max(np.abs(np.array(r))) > 1e-12:
            raise RuntimeError(f"Newton did not converge at step {k}: residual {r}")
        max_newton = max(max_newton, it)
        p = np.array(newp(q, qn, u[k])).ravel()
        q = qn
        traj.append(q.copy())
    traj = np.array(traj).T
    return {
        "check_qN_error": float(np.max(np.abs(q - np.array(Q_END)))),
        "check_pN_error": float(np.max(np.abs(p))),
        "check_max_q_deviation": float(np.max(np.abs(traj - q_opt))),
        "check_max_newton_iterations": max_newton,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--N", type=int, default=100, help="number of steps (default 100)")
    ap.add_argument("--T", type=float, default=2.0, help="horizon (default 2.0)")
    ap.add_argument("--guess", choices=["linear", "rest"], default="linear",
                    help="initial guess: q_k linear in k (default) or q_k = q_0 for k < N")
    ap.add_argument("--repeats", type=int, default=10, help="timed solves (default 10)")
    ap.add_argument("--csv", metavar="PATH", help="write k,theta,s,u of the optimum")
    ap.add_argument("--check", action="store_true",
                    help="simulate the forced discrete equations forward with the optimal u")
    args = ap.parse_args()
    n, t = args.N, args.T
    if n < 2 or t <= 0 or args.repeats < 1:
        ap.error("need N >= 2, T > 0, repeats >= 1")

    nlp, d1, d2 = build(n, t)
    opts = {
        "ipopt.tol": 1e-12,
        "ipopt.print_level": 0,
        "ipopt.hessian_approximation": "exact",
        "ipopt.sb": "yes",
        "print_time": False,
    }
    solver = ca.nlpsol("solver", "ipopt", nlp, opts)
    x0 = initial_guess(n, args.guess)
    zeros = np.zeros(2 * (n + 1))

    times = []
    sol = None
    for _ in range(args.repeats):
        start = time.perf_counter()
        sol = solver(x0=x0, lbg=zeros, ubg=zeros)
        times.append(time.perf_counter() - start)
    stats = solver.stats()

    q, u = unpack(sol["x"], n)
    gval = np.array(sol["g"]).ravel()
    out = {
        "cost": float(sol["f"]),
        "iterations": int(stats["iter_count"]),
        "solve_seconds_median": statistics.median(times),
        "solve_seconds_min": min(times),
        "repeats": args.repeats,
        "N": n,
        "T": t,
        "max_constraint_violation": float(np.max(np.abs(gval))),
        "guess": args.guess,
        "status": stats["return_status"],
    }
    if args.check:
        out.update(forward_check(q, u, t, d1, d2))
    if args.csv:
        with open(args.csv, "w") as fh:
            fh.write("k,theta,s,u\n")
            for k in range(n + 1):
                uk = repr(float(u[k])) if k < n else ""
                fh.write(f"{k},{float(q[0, k])!r},{float(q[1, k])!r},{uk}\n")
    print(json.dumps(out))
    return 0 if stats["success"] else 1


if __name__ == "__main__":
    sys.exit(main())
