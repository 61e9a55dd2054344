"""dirac: structure-preserving variational integrators reduced by a symmetry, for Lagrangians
given as text.

A system is the attribute and function that a Rust program would compile in with
``#[reduced_lagrangian]``, given here as a string (or built from keyword arguments, or from a
SymPy expression); it is compiled to machine code in milliseconds and integrated with NumPy
arrays in and out::

    import dirac
    kepler = dirac.compile('''
        #[reduced_lagrangian(shape(r), group(phi))]
        fn kepler(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
            let r = 0.5 * (q0.r + q1.r);
            let (dr, dphi) = ((q1.r - q0.r) / h, (q1.phi - q0.phi) / h);
            h * (0.5 * (dr * dr + r * r * dphi * dphi) + k / r)
        }''')
    run = kepler.run({"h": 0.01, "k": 1.0}, steps=1000, x=[0.5], w=[0.0], mu=[1.2], g=[0.0])
    run["x"].shape, run["q"]["r"].shape  # (1001, 1), (1001,)

A system on vector spaces runs at any size, constraints and ensembles included: up to 8
coordinates (with constraints up to 6 coordinates, one of them a group coordinate, and 3
constraints) on the fixed-size integrators, bit for bit as the system compiled in; above, on its
element view (the whole Lagrangian one element reading every coordinate, each group coordinate a
translation whose momentum is kept exact), with the same methods, keywords and results — the
same trajectory to round-off, as both solve the same equations.

A system on rotation groups (``rotation(R)``, ``direction(n)`` coordinates) compiles to a
:class:`LieSystem`, started from its coordinates by name (a rotation's matrix, a direction's
unit vector) and their momenta, its trajectory per coordinate::

    top = dirac.compile(HEAVY_TOP)
    run = top.run(params, steps=1000, q={"R": np.eye(3)}, p={"R": [0.1, 0.0, 3.0]},
                  method="reduced")
    run["q"]["R"].shape  # (1001, 3, 3)

An element-wise system (a function that takes ``usize`` sizes, its body a sum over elements)
compiles to an :class:`ElementSystem`, whose sizes are chosen per run::

    toda = dirac.compile(TODA_N)             # coordinates(x[n]), translate(x)
    run = toda.run({"m": 1.0, "d": 1.0, "h": 0.05}, steps=100, sizes={"n": 1000}, q=q0, p=p0)
    run["q"]["x"].shape  # (101, 1000)

Every class has the same methods with the same keywords: ``run``, ``write`` (to Parquet) and
``ensemble`` (many starts on all cores), taking ``steps`` (and ``end_time``), ``method``,
``order``, ``tol`` and the start by coordinate name (``q={..}``, ``p={..}``); every run returns
``t``, ``q`` and ``p`` as dicts by coordinate name, ``iterations`` and ``residuals``, and what the
kind of system adds. ``System.run`` also takes ``scheme="gauss"``: the Gauss–Legendre variational
integrator of any even ``order`` from 2 to 32, for a continuous Lagrangian ``L(q, v)`` without
constraints on at most 8 coordinates::

    kepler.run({"h": 0.1, "k": 1.0}, steps=100, scheme="gauss", order=8, x=[0.5], w=[0.0],
               mu=[0.87], g=[0.0])
Every run method raises ``TypeError`` for a keyword it does not take, ``OutOfMemoryError`` (a
``MemoryError``) before running when the trajectory cannot be allocated, and at Ctrl-C
``KeyboardInterrupt`` with the trajectory so far (``trajectory``), as ``StepError`` carries it.
"""

from ._dirac import (CompileError, ElementSystem, LieSystem, Model, OutOfMemoryError, StepError,
                     System, compile, from_urdf)

__all__ = [
    "CompileError",
    "ElementSystem",
    "LieSystem",
    "Model",
    "OutOfMemoryError",
    "StepError",
    "System",
    "compile",
    "from_urdf",
    "system",
    "from_sympy",
]


def system(body, *, shape=(), group=(), parameters=(), step="h", continuous=False,
           rule=None, connection=None, controls=(), force=None, name="system"):
    """A system from keyword arguments: the attribute's keys and the function's body.

    ``body`` is the function body in the attribute's language (``q0.x``, ``q1.x`` and the
    parameters for a discrete Lagrangian; ``q.x``, ``v.x`` for a continuous one, with ``rule``).
    The time step ``step`` is a parameter of a discrete Lagrangian whether listed or not.
    """
    keys = [f"shape({', '.join(shape)})", f"group({', '.join(group)})"]
    if connection is not None:
        rows = ", ".join("[" + ", ".join(str(e) for e in row) + "]" for row in connection)
        keys.append(f"connection = [{rows}]")
    if step != "h":
        keys.append(f"step = {step}")
    if rule is not None:
        keys.append(f"rule = {rule}")
    if controls:
        keys.append(f"controls({', '.join(controls)})")
    if force is not None:
        keys.append(f"force = {force}")
    params = list(parameters)
    if continuous:
        args = ["q: Config", "v: Velocity"]
    else:
        args = ["q0: Config", "q1: Config"]
        if step not in params:
            params.insert(0, step)
    args += [f"{p}: f64" for p in params]
    text = (f"#[reduced_lagrangian({', '.join(keys)})]\n"
            f"fn {name}({', '.join(args)}) -> f64 {{\n{body}\n}}\n")
    return compile(text)


def from_sympy(lagrangian, *, q, v, shape, group=(), parameters=(), rule="midpoint",
               name="system", **keys):
    """A continuous Lagrangian ``L(q, v)`` given as a SymPy expression.

    ``q`` and ``v`` are the SymPy symbols of the coordinates and velocities, in the same order;
    ``shape`` and ``group`` name the coordinates (by the names of the ``q`` symbols);
    ``parameters`` are the SymPy symbols of the parameters. The expression is written in the
    attribute's body language (fully parenthesized, so the compiler evaluates it in SymPy's
    order), each coordinate read as ``q.<name>`` and each velocity as ``v.<name>``; other
    keyword arguments are those of :func:`system`.
    """
    import sympy

    q, v = list(q), list(v)
    if len(q) != len(v):
        raise ValueError(f"{len(q)} coordinates and {len(v)} velocities")
    reads = {s: f"q.{s}" for s in q}
    reads.update({vs: f"v.{qs}" for qs, vs in zip(q, v)})
    reads.update({p: str(p) for p in parameters})
    body = _rust(sympy.sympify(lagrangian), reads)
    return system(body, shape=shape, group=group, parameters=[str(p) for p in parameters],
                  continuous=True, rule=rule, name=name, **keys)


_FUNCTIONS = {"sin": "sin", "cos": "cos", "tan": "tan", "asin": "asin", "acos": "acos",
              "atan": "atan", "exp": "exp", "log": "ln", "sinh": "sinh", "cosh": "cosh",
              "tanh": "tanh"}


def _rust(e, reads):
    """A SymPy expression in the body language: `+ - * /`, `powi`, `powf`, `sqrt`, the
    elementary functions as methods, every operation parenthesized."""
    import sympy

    if e.is_Symbol:
        if e not in reads:
            raise ValueError(f"`{e}` is neither a coordinate, a velocity nor a parameter")
        return reads[e]
    if e.is_Integer or e.is_Float:
        return repr(float(e))
    if e.is_Rational:
        return f"({float(e.p)!r} / {float(e.q)!r})"
    if e is sympy.pi:
        return repr(float(sympy.pi))
    if e.is_Add:
        return "(" + " + ".join(_rust(a, reads) for a in e.args) + ")"
    if e.is_Mul:
        return "(" + " * ".join(_rust(a, reads) for a in e.args) + ")"
    if e.is_Pow:
        base, exp = e.args
        b = _rust(base, reads)
        if exp.is_Integer:
            return f"{b}.powi({int(exp)})"
        if exp == sympy.Rational(1, 2):
            return f"{b}.sqrt()"
        return f"{b}.powf({_rust(exp, reads)})"
    if isinstance(e, sympy.atan2):
        y, x = e.args
        return f"{_rust(y, reads)}.atan2({_rust(x, reads)})"
    if isinstance(e, sympy.Function) and type(e).__name__ in _FUNCTIONS and len(e.args) == 1:
        return f"{_rust(e.args[0], reads)}.{_FUNCTIONS[type(e).__name__]}()"
    raise ValueError(f"`{e}` ({type(e).__name__}) has no counterpart in the body language")
