"""Generate C with CasADi `map` for the (+) residual and its sparse Jacobian of the periodic Toda lattice in the
particles' own (user) coordinates, so that the generated code does not grow with n (compare
benches/casadi_scaling/, which builds the whole lattice as one SX graph, code O(n)).

usage: python3 gen.py --n N [--jac elem|mx] [--no-check] OUTDIR

Lattice: n unit masses (m = 1), spacing d = 1, positions x_0..x_{n-1}, periodic with x_n = x_0 + n d;

    L(x, v) = sum_{i<n} m/2 v_i^2 - sum_{i<n-1} exp(-(x_{i+1} - x_i - d)) - exp(-(x_0 + n d - x_{n-1} - d)).

Midpoint rule L_d(q0, q1) = h L((q0 + q1)/2, (q1 - q0)/h). Unknown z = q1; inputs z, q0, p0 (n each), h:

    R(z) = p0 + dL_d/dq0(q0, z),   J = dR/dz (sparse: tridiagonal + the two periodic corners, 3n nonzeros),
    p1   = dL_d/dq1(q0, z)         (generated as `pnext`, not timed).

L_d is a sum of n kinetic elements  h m/2 ((a1 - a0)/h)^2        (a = particle i at q0, q1)
and n bond elements                -h exp(-((b0 + b1)/2 + o - (a0 + a1)/2 - d))
                                   (a = particle i, b = particle (i+1) mod n, o = 0, or n d for the wrap bond i = n-1).
Each element is a CasADi SX Function of its own few scalars; its derivatives are taken by CasADi (SX AD) inside the
element, and the element functions are mapped over the n elements with `map(..., "serial", n)` (h is a shared,
not repeated, input; the wrap offsets are the mapped row [0 .. 0, n d]). The mapped calls are assembled in MX with
cyclic shifts (two slices each) and a reshape, so the generated C is a loop over elements whose size does not
depend on n; only the Jacobian's output sparsity pattern (4n + 3 integers, part of CasADi's function interface)
grows with n.

--jac elem (default)  R and J from one mapped call of the element functions (R, dR/d(own q1 entries)), the three
                      Jacobian diagonals interleaved into CasADi's compressed-column nonzero order by a reshape.
--jac mx              R from the mapped element gradients, J = casadi.jacobian(R, z) of the assembled MX
                      expression (CasADi colours the columns and calls the mapped forward derivative). The code
                      stays O(1) but CasADi emits O(n) seed/extraction index tables, so the C file grows with n.

OUTDIR receives map_gen.c/.h (rj(z, q0, p0, h) -> (R, J), pnext(z, q0, h) -> p1), point.txt (the timed point:
h, then z, q0, p0) and meta.txt (nnz=... table_bytes=... instructions=...). Unless --no-check, at n = 8 and at
the requested n if n <= 1000: R and p1 are compared with an independent NumPy implementation of the closed-form
derivatives (at n = 8 also with central differences of a NumPy L_d), and J with central differences of the
generated R (every column); exit 2 on failure.
"""
import argparse, math, os, re, sys, time
import numpy as np
import casadi as ca

M, D = 1.0, 1.0


# ---- element functions (SX) and their mapped assembly (MX) -----------------------------------------------
def elements():
    a0, a1, b0, b1, h, o = (ca.SX.sym(s) for s in ("a0", "a1", "b0", "b1", "h", "o"))
    ld_bond = -h * ca.exp(-(((b0 + b1) / 2 + o) - (a0 + a1) / 2 - D))
    ld_kin = h * (M / 2) * ((a1 - a0) / h) ** 2
    ga0, gb0 = ca.gradient(ld_bond, a0), ca.gradient(ld_bond, b0)
    gk0 = ca.gradient(ld_kin, a0)
    bi, bo = [a0, a1, b0, b1, h, o], ["a0", "a1", "b0", "b1", "h", "o"]
    ki, ko = [a0, a1, h], ["a0", "a1", "h"]
    return {
        # residual contributions dL_d/dq0 at particles a and b
        "bond_r": ca.Function("bond_r", bi, [ga0, gb0], bo, ["ga0", "gb0"]),
        "kin_r": ca.Function("kin_r", ki, [gk0], ko, ["gk0"]),
        # the same plus their derivatives with respect to the element's own unknowns (a1, b1)
        "bond_rj": ca.Function("bond_rj", bi, [ga0, gb0, ca.jacobian(ga0, a1), ca.jacobian(ga0, b1),
                                               ca.jacobian(gb0, a1), ca.jacobian(gb0, b1)],
                               bo, ["ga0", "gb0", "dga0_da1", "dga0_db1", "dgb0_da1", "dgb0_db1"]),
        "kin_rj": ca.Function("kin_rj", ki, [gk0, ca.jacobian(gk0, a1)], ko, ["gk0", "dgk0_da1"]),
        # momentum at the end of the step, dL_d/dq1
        "bond_p": ca.Function("bond_p", bi, [ca.gradient(ld_bond, a1), ca.gradient(ld_bond, b1)], bo,
                              ["ga1", "gb1"]),
        "kin_p": ca.Function("kin_p", ki, [ca.gradient(ld_kin, a1)], ko, ["gk1"]),
    }


def jac_sparsity(n):
    """Tridiagonal + corners (n - 1, 0) and (0, n - 1), compressed column, rows sorted: 3n nonzeros (n >= 3)."""
    colind = 3 * np.arange(n + 1)
    j = np.arange(1, n - 1)
    mid = np.stack([j - 1, j, j + 1], axis=1).ravel()
    row = np.concatenate([[0, 1, n - 1], mid, [0, n - 2, n - 1]])
    return ca.Sparsity(n, n, colind.tolist(), row.tolist())


def build(n, jac):
    el = elements()
    z, q0, p0, h = ca.MX.sym("z", n), ca.MX.sym("q0", n), ca.MX.sym("p0", n), ca.MX.sym("h")
    nxt = lambda v: ca.vertcat(v[1:], v[0])            # particle (i+1) mod n
    prv = lambda v: ca.horzcat(v[:, n - 1], v[:, :n - 1])  # row vector: entry of element (i-1) mod n at i
    off = ca.horzcat(ca.MX.zeros(1, n - 1), ca.MX(n * D))  # wrap offset per bond, mapped input
    bond_args = [q0.T, z.T, nxt(q0).T, nxt(z).T, h, off]
    kin_args = [q0.T, z.T, h]
    # reduce_in: h (index 4 of bond, 2 of kin) is one shared scalar, not repeated n times
    mapb = lambda f: f.map(f.name() + "_map", "serial", n, [4], [])
    mapk = lambda f: f.map(f.name() + "_map", "serial", n, [2], [])
    if jac == "elem":
        ga0, gb0, jaa, jab, jba, jbb = mapb(el["bond_rj"])(*bond_args)
        gk0, jk = mapk(el["kin_rj"])(*kin_args)
        R = p0 + (gk0 + ga0 + prv(gb0)).T
        # column j of J: row j-1 <- bond j-1 (a = j-1, b = j), row j <- diagonal, row j+1 <- bond j (a = j, b = j+1)
        up, dg, lo = prv(jab), jk + jaa + prv(jbb), jba
        nz = ca.reshape(ca.vertcat(up, dg, lo), 3 * n, 1)  # interleaved (up_j, dg_j, lo_j), j = 0..n-1
        # columns 0 and n-1 hold a corner: rows (0, 1, n-1) and (0, n-2, n-1)
        nz = ca.vertcat(dg[0], lo[0], up[0], nz[3:3 * n - 3], lo[n - 1], up[n - 1], dg[n - 1])
        J = ca.MX(jac_sparsity(n), nz)
    else:
        ga0, gb0 = mapb(el["bond_r"])(*bond_args)
        gk0 = mapk(el["kin_r"])(*kin_args)
        R = p0 + (gk0 + ga0 + prv(gb0)).T
        J = ca.jacobian(R, z)
    ga1, gb1 = mapb(el["bond_p"])(*bond_args)
    gk1 = mapk(el["kin_p"])(*kin_args)
    P1 = (gk1 + ga1 + prv(gb1)).T
    rj = ca.Function("rj", [z, q0, p0, h], [R, J], ["z", "q0", "p0", "h"], ["R", "J"])
    pnext = ca.Function("pnext", [z, q0, h], [P1], ["z", "q0", "h"], ["p1"])
    return rj, pnext


# ---- independent NumPy implementation, for the check -------------------------------------------------------
def np_ld(n, h, q0, q1):
    """L_d(q0, q1) = h L((q0 + q1)/2, (q1 - q0)/h), L written out as in the docstring."""
    x, v = (q0 + q1) / 2, (q1 - q0) / h
    u = np.sum(np.exp(-(x[1:] - x[:-1] - D))) + np.exp(-(x[0] + n * D - x[n - 1] - D))
    return h * (np.sum(M / 2 * v**2) - u)


def np_r_p1(n, h, q0, q1, p0):
    """Closed form. With e_i = exp(-(x_{i+1} - x_i - d)) at the midpoint x (x_n = x_0 + n d),
    dL/dx_i = e_{i-1} - e_i (from -V), and d(midpoint)/dq0 = d(midpoint)/dq1 = 1/2, d v/dq0 = -1/h, d v/dq1 = 1/h:
        dL_d/dq0_i = -m (q1_i - q0_i)/h + h/2 (e_{i-1} - e_i),
        dL_d/dq1_i = +m (q1_i - q0_i)/h + h/2 (e_{i-1} - e_i)   (indices mod n)."""
    x = (q0 + q1) / 2
    xn = np.concatenate([x[1:], [x[0] + n * D]])
    e = np.exp(-(xn - x - D))
    f = h / 2 * (np.roll(e, 1) - e)
    return p0 - M * (q1 - q0) / h + f, M * (q1 - q0) / h + f


def random_point(n, seed):
    rng = np.random.default_rng(seed)
    i = np.arange(n)
    h = 0.05
    q0 = i * D + 0.1 * rng.uniform(-1, 1, n)
    z = q0 + 0.02 * rng.uniform(-1, 1, n)
    p0 = rng.uniform(-0.5, 0.5, n)
    return h, z, q0, p0


def check(n, rj, pnext):
    h, z, q0, p0 = random_point(n, 12345 + n)
    res, jac = rj(z, q0, p0, h)
    res = np.array(res).ravel()
    ok_nnz = jac.nnz() == 3 * n
    jac = np.array(ca.DM(jac).full())
    r_np, p1_np = np_r_p1(n, h, q0, z, p0)
    err_r = np.max(np.abs(res - r_np) / (1 + np.abs(r_np)))
    p1 = np.array(pnext(z, q0, h)).ravel()
    err_p = np.max(np.abs(p1 - p1_np) / (1 + np.abs(p1_np)))
    # the closed form itself, against central differences of the NumPy L_d (small n only)
    err_fd = 0.0
    if n <= 16:
        for j in range(n):
            e = np.zeros(n); e[j] = 1e-6
            d0 = (np_ld(n, h, q0 + e, z) - np_ld(n, h, q0 - e, z)) / 2e-6
            d1 = (np_ld(n, h, q0, z + e) - np_ld(n, h, q0, z - e)) / 2e-6
            err_fd = max(err_fd, abs(p0[j] + d0 - r_np[j]) / (1 + abs(d0)), abs(d1 - p1_np[j]) / (1 + abs(d1)))
    # J against central differences of the generated residual, every column (actual step: z_j may be ~ n)
    err_j = 0.0
    for j in range(n):
        zp, zm = z.copy(), z.copy()
        zp[j] += 1e-6; zm[j] -= 1e-6
        rp = np.array(rj(zp, q0, p0, h)[0]).ravel()
        rm = np.array(rj(zm, q0, p0, h)[0]).ravel()
        err_j = max(err_j, np.max(np.abs((rp - rm) / (zp[j] - zm[j]) - jac[:, j]) / (1 + np.abs(jac[:, j]))))
    ok = ok_nnz and err_r < 1e-10 and err_p < 1e-10 and err_fd < 1e-6 and err_j < 1e-6
    print(f"check n={n}: R vs NumPy {err_r:.1e}, p1 vs NumPy {err_p:.1e}"
          + (f", NumPy closed form vs FD of NumPy L_d {err_fd:.1e}" if n <= 16 else "")
          + f", J vs FD of R {err_j:.1e}, nnz {'= 3n' if ok_nnz else '!= 3n'} -> {'ok' if ok else 'FAILED'}",
          file=sys.stderr)
    return ok


def timed_point(n):
    """The point the driver times at: h, z, q0, p0."""
    i = np.arange(n)
    h = 0.05
    q0 = i * D + 0.1 * np.sin(2 * math.pi * i / n)
    z = q0 + h * 0.3 * np.cos(2 * math.pi * i / n)
    p0 = 0.3 * np.cos(2 * math.pi * i / n)
    return h, z, q0, p0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, required=True)
    ap.add_argument("--jac", choices=["elem", "mx"], default="elem")
    ap.add_argument("--no-check", action="store_true", help="skip the checks")
    ap.add_argument("outdir")
    a = ap.parse_args()
    if a.n < 3:
        ap.error("n >= 3")
    if not a.no_check:
        for n in sorted({8} | ({a.n} if a.n <= 1000 else set())):
            if not check(n, *build(n, a.jac)):
                sys.exit(2)
    t0 = time.perf_counter()
    rj, pnext = build(a.n, a.jac)
    t_sym = time.perf_counter() - t0
    os.makedirs(a.outdir, exist_ok=True)
    cwd = os.getcwd()
    os.chdir(a.outdir)
    t0 = time.perf_counter()
    # no comments: with --jac mx they would print O(n) index lists
    cg = ca.CodeGenerator("map_gen.c", {"with_header": True, "verbose": False})
    cg.add(rj)
    cg.add(pnext)
    cg.generate()
    t_cg = time.perf_counter() - t0
    src = open("map_gen.c").read()
    tables = sum(len(t) for t in re.findall(r"static const casadi_(?:int|real) \w+\[\d+\] = [^;]*;", src))
    nnz = rj.sparsity_out(1).nnz()
    h, z, q0, p0 = timed_point(a.n)
    with open("point.txt", "w") as f:
        f.write(" ".join(repr(float(v)) for v in [h, *z, *q0, *p0]) + "\n")
    with open("meta.txt", "w") as f:
        f.write(f"nnz={nnz} table_bytes={tables} instructions={rj.n_instructions()}\n")
    os.chdir(cwd)
    print(f"gen: n={a.n} jac={a.jac} nnz={nnz} instructions={rj.n_instructions()} c_bytes={len(src)} "
          f"of which static tables {tables} (code {len(src) - tables}) sym_s={t_sym:.2f} codegen_s={t_cg:.2f}",
          file=sys.stderr)


if __name__ == "__main__":
    main()
