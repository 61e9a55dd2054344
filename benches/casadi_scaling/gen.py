"""Generate C with CasADi for the reduced (+) residual and its Jacobian of eq. (4.6) of Rodriguez Abella & Leok
(B = 0, group origin at the start of the step) for two systems whose size grows with n, to see how CasADi's
generated code scales (compare benches/casadi.sh, the fixed-size double spherical pendulum).

usage: python3 gen.py --system chain|lattice --n N [--cse] [--no-check] OUTDIR

With l(x0, x1, g1) = L_d(q0 = (x0, 0), q1 = (x1, g1)) and the midpoint rule L_d = h L((q0+q1)/2, (q1-q0)/h),
the unknowns are z = (x1, g1) and

    R(z) = ( dl/dx0 + w0,  dl/dg1 - mu0 ),      J = dR/dz  (CasADi's sparse Jacobian, not densified),
    w1   = dl/dx1                               (the momentum update, generated as `wnext`).

Systems (all physical parameters are fixed numbers in the generated code; h is an input):

  chain    n links of a planar pendulum chain hanging from a cart on a horizontal rail; q = (theta[0..n], c),
           shape x = theta (absolute angles from the downward vertical), group g = c (cart position).
           M = 1 (cart), m = 1, l = 1 (links), gr = 9.81. The Lagrangian is built with running sums exactly as
           the Rust body that dirac differentiates (see chain_lagrangian).
  lattice  periodic Toda lattice of n unit masses (m = 1, spacing d = 1): L = sum m/2 xdot_i^2
           - sum_{i=0}^{n-1} exp(-(x_{i+1} - x_i - d)), x_n = x_0 + n d. Adapted coordinates: g = x_0 (group),
           shape r_i = x_i - x_0, i = 1..n-1; so x_0 = g, x_i = g + r_i.

OUTDIR receives scal_gen.c/.h (functions rj(z, x0, w0, mu0, h) -> (R, J) and wnext(z, x0, h) -> w1),
point.txt (the evaluation point the driver times at: h, then z, x0, w0, mu0) and meta.txt
(instructions=... nnz=... nz=...). Unless --no-check, the residual is checked against central differences
of an independent NumPy implementation of l (positions written out, not running sums), and the Jacobian
against central differences of the generated residual.
"""
import argparse, math, os, sys, time
import numpy as np
import casadi as ca

# chain
M_CART, M_LINK, L_LINK, GR = 1.0, 1.0, 1.0, 9.81
# lattice
M_TODA, D_TODA = 1.0, 1.0


def chain_lagrangian(theta, c, vtheta, vc):
    """L = 1/2 M cdot^2 + sum_j 1/2 m (Xdot_j^2 + Ydot_j^2) - sum_j m gr Y_j, with running sums (as in Rust)."""
    vx, vy, y = vc, 0.0, 0.0
    t, u = 0.5 * M_CART * vc * vc, 0.0
    for i in range(theta.numel() if hasattr(theta, "numel") else len(theta)):
        s, co = ca.sin(theta[i]), ca.cos(theta[i])
        vx = vx + L_LINK * co * vtheta[i]
        vy = vy + L_LINK * s * vtheta[i]
        y = y - L_LINK * co
        t = t + 0.5 * M_LINK * (vx * vx + vy * vy)
        u = u + M_LINK * GR * y
    return t - u


def toda_lagrangian(x, v, n):
    """L = sum m/2 v_i^2 - sum_{i<n} exp(-(x_{i+1} - x_i - d)), x_n = x_0 + n d, in user coordinates x."""
    t = 0.0
    for i in range(n):
        t = t + 0.5 * M_TODA * v[i] * v[i]
    u = 0.0
    for i in range(n):
        xn = x[i + 1] if i + 1 < n else x[0] + n * D_TODA
        u = u + ca.exp(-(xn - x[i] - D_TODA))
    return t - u


def build(system, n):
    """Symbols and l(x0, x1, g1) for the system: returns (x0, x1, g1, ld, nx)."""
    nx = n if system == "chain" else n - 1
    x0, x1, g1 = ca.SX.sym("x0", nx), ca.SX.sym("x1", nx), ca.SX.sym("g1")
    h = ca.SX.sym("h")
    if system == "chain":
        # q = (theta, c): q0 = (x0, 0), q1 = (x1, g1)
        thm, cm = (x0 + x1) / 2, g1 / 2
        vth, vc = (x1 - x0) / h, g1 / h
        ld = h * chain_lagrangian(thm, cm, vth, vc)
    else:
        # user coordinates at k: (0, x0); at k+1: (g1, g1 + x1)
        xa = ca.vertcat(0, x0)
        xb = ca.vertcat(g1, g1 + x1)
        ld = h * toda_lagrangian((xa + xb) / 2, (xb - xa) / h, n)
    return x0, x1, g1, h, ld, nx


# ---- independent NumPy implementation of l, for the check ------------------------------------------------
def np_l(system, n, h, x0, x1, g1):
    if system == "chain":
        thm, vth = (x0 + x1) / 2, (x1 - x0) / h
        cm, vc = g1 / 2, g1 / h
        X = cm + L_LINK * np.cumsum(np.sin(thm))
        Y = -L_LINK * np.cumsum(np.cos(thm))
        Xd = vc + L_LINK * np.cumsum(np.cos(thm) * vth)
        Yd = L_LINK * np.cumsum(np.sin(thm) * vth)
        L = 0.5 * M_CART * vc**2 + np.sum(0.5 * M_LINK * (Xd**2 + Yd**2)) - np.sum(M_LINK * GR * Y)
        del X
    else:
        xa = np.concatenate([[0.0], x0])
        xb = np.concatenate([[g1], g1 + x1])
        xm, v = (xa + xb) / 2, (xb - xa) / h
        nxt = np.concatenate([xm[1:], [xm[0] + n * D_TODA]])
        L = np.sum(0.5 * M_TODA * v**2) - np.sum(np.exp(-(nxt - xm - D_TODA)))
    return h * L


def point(system, n, nx):
    """A physically sensible, not special evaluation point (h, z, x0, w0, mu0), deterministic."""
    h = 0.01 if system == "chain" else 0.05
    i = np.arange(nx)
    if system == "chain":
        x0 = 0.3 * np.sin(0.7 * i + 0.3)               # link angles
        x1 = x0 + h * 0.5 * np.cos(1.3 * i + 0.1)        # + h * angular velocity
        g1 = h * 0.2
        w0 = 0.4 * np.cos(0.9 * i + 0.2)
        mu0 = 0.15
    else:
        k = i + 1                                        # r_k, k = 1..n-1
        x0 = k * D_TODA + 0.1 * np.sin(2 * math.pi * k / n) - 0.1 * math.sin(0.0)
        x1 = x0 + h * 0.3 * np.cos(2 * math.pi * k / n + 0.2)
        g1 = h * 0.05
        w0 = 0.3 * np.cos(2 * math.pi * k / n + 0.1)
        mu0 = 0.07
    return h, np.concatenate([x1, [g1]]), x0, w0, mu0


def check(system, n, nx, rj, ld_f):
    h, z, x0, w0, mu0 = point(system, n, nx)
    res, jac = rj(z, x0, w0, mu0, h)
    res = np.array(res).ravel()
    jac_sp = jac
    jac = np.array(ca.DM(jac).full())
    # 1. residual vs central differences of the independent NumPy l
    x1, g1 = z[:nx], z[nx]
    eps = 1e-6
    worst_r = 0.0
    cols = range(nx) if nx <= 64 else sorted(set(np.linspace(0, nx - 1, 64).astype(int)))
    for j in cols:
        e = np.zeros(nx); e[j] = eps
        d = (np_l(system, n, h, x0 + e, x1, g1) - np_l(system, n, h, x0 - e, x1, g1)) / (2 * eps)
        worst_r = max(worst_r, abs(res[j] - (d + w0[j])) / (1 + abs(d)))
    d = (np_l(system, n, h, x0, x1, g1 + eps) - np_l(system, n, h, x0, x1, g1 - eps)) / (2 * eps)
    worst_r = max(worst_r, abs(res[nx] - (d - mu0)) / (1 + abs(d)))
    # 2. Jacobian vs central differences of the generated residual (every column up to 64 of them)
    nz = nx + 1
    worst_j = 0.0
    cols = range(nz) if nz <= 64 else sorted(set(np.linspace(0, nz - 1, 64).astype(int)) | {nz - 1})
    scale = max(1.0, np.abs(jac).max())
    for j in cols:
        e = np.zeros(nz); e[j] = eps
        rp = np.array(rj(z + e, x0, w0, mu0, h)[0]).ravel()
        rm = np.array(rj(z - e, x0, w0, mu0, h)[0]).ravel()
        worst_j = max(worst_j, np.abs((rp - rm) / (2 * eps) - jac[:, j]).max() / scale)
    ok = worst_r < 1e-6 and worst_j < 1e-6
    print(f"check: residual vs FD of NumPy l: max rel err {worst_r:.2e}; Jacobian vs FD of residual: "
          f"max err / max|J| {worst_j:.2e} -> {'ok' if ok else 'FAILED'}", file=sys.stderr)
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--system", required=True, choices=["chain", "lattice"])
    ap.add_argument("--n", type=int, required=True)
    ap.add_argument("--cse", action="store_true", help="CasADi's optional common-subexpression pass")
    ap.add_argument("--no-check", action="store_true", help="skip the finite-difference checks")
    ap.add_argument("outdir")
    a = ap.parse_args()
    if a.system == "lattice" and a.n < 3:
        ap.error("lattice needs n >= 3")
    if a.n < 1:
        ap.error("n >= 1")
    t0 = time.perf_counter()
    x0, x1, g1, h, ld, nx = build(a.system, a.n)
    w0, mu0 = ca.SX.sym("w0", nx), ca.SX.sym("mu0")
    z = ca.vertcat(x1, g1)
    res = ca.vertcat(ca.gradient(ld, x0) + w0, ca.gradient(ld, g1) - mu0)
    jac = ca.jacobian(res, z)  # sparse; kept sparse in the generated code
    opts = {"cse": True} if a.cse else {}
    rj = ca.Function("rj", [z, x0, w0, mu0, h], [res, jac], opts)
    wnext = ca.Function("wnext", [z, x0, h], [ca.gradient(ld, x1)], opts)
    t_sym = time.perf_counter() - t0
    if not a.no_check:
        ok = check(a.system, a.n, nx, rj, None)
        if not ok:
            sys.exit(2)
    os.makedirs(a.outdir, exist_ok=True)
    cwd = os.getcwd()
    os.chdir(a.outdir)
    t0 = time.perf_counter()
    cg = ca.CodeGenerator("scal_gen.c", {"with_header": True})
    cg.add(rj)
    cg.add(wnext)
    cg.generate()
    t_cg = time.perf_counter() - t0
    hh, zz, xx, ww, mm = point(a.system, a.n, nx)
    with open("point.txt", "w") as f:
        f.write(" ".join(repr(float(v)) for v in [hh, *zz, *xx, *ww, mm]) + "\n")
    with open("meta.txt", "w") as f:
        f.write(f"instructions={rj.n_instructions()} nnz={jac.nnz()} nz={nx + 1}\n")
    os.chdir(cwd)
    print(f"gen: system={a.system} n={a.n} cse={a.cse} nz={nx + 1} instructions={rj.n_instructions()} "
          f"nnz={jac.nnz()} sym_s={t_sym:.2f} codegen_s={t_cg:.2f}", file=sys.stderr)


if __name__ == "__main__":
    main()
