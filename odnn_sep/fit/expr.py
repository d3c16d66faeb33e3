"""Safe parsing of basis expressions ("x**2*sin(5*x)") and disturbance specs ("periodic:1.25").

Expressions are parsed with ``ast`` and only arithmetic, numbers, the coordinate names and a
whitelist of numpy functions are allowed, so a basis string can never run arbitrary code.
"""
from __future__ import annotations

import ast
import difflib

import numpy as np

from odnn_sep.errors import InputError

FUNCS = {name: getattr(np, name) for name in (
    "sin", "cos", "tan", "exp", "log", "log10", "sqrt", "abs", "tanh", "sinh", "cosh", "arctan", "sign",
    "heaviside", "minimum", "maximum", "where")}
CONSTS = {"pi": np.pi, "e": np.e}
OPS = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Load, ast.Constant, ast.Add, ast.Sub,
       ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd, ast.Mod, ast.Compare, ast.Gt, ast.Lt, ast.GtE, ast.LtE)


def compile_expression(expr: str, coords: tuple[str, ...]):
    """Return f(X) evaluating ``expr`` with X of shape (n,) or (n, len(coords))."""
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as exc:
        raise InputError(f"basis expression {expr!r} is not valid: {exc.msg}; write e.g. 'x**2*sin(5*x)'") from None
    allowed = set(coords) | set(FUNCS) | set(CONSTS)
    for node in ast.walk(tree):
        if not isinstance(node, OPS):
            raise InputError(f"basis expression {expr!r} uses {type(node).__name__}, which is not allowed; "
                             "use arithmetic and functions like sin, cos, exp, log, sqrt")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id not in FUNCS:
            hint = difflib.get_close_matches(node.func.id, sorted(FUNCS), n=1)
            extra = f" (did you mean {hint[0]!r}?)" if hint else ""
            raise InputError(f"basis expression {expr!r} calls unknown function {node.func.id!r}{extra}; "
                             f"allowed functions: {sorted(FUNCS)}")
        if isinstance(node, ast.Name) and node.id not in allowed:
            hint = difflib.get_close_matches(node.id, sorted(allowed), n=1)
            extra = f" (did you mean {hint[0]!r}?)" if hint else ""
            raise InputError(f"basis expression {expr!r} uses unknown name {node.id!r}{extra}; "
                             f"allowed: coordinates {list(coords)}, functions {sorted(FUNCS)}, constants pi, e")
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name) and node.func.id in FUNCS):
            raise InputError(f"basis expression {expr!r} calls something that is not an allowed function")
    code = compile(tree, "<basis>", "eval")

    def f(X):
        X = np.asarray(X, dtype=float)
        env = dict(FUNCS, **CONSTS)
        if X.ndim == 1:
            env[coords[0]] = X
        else:
            env.update({c: X[:, i] for i, c in enumerate(coords)})
        with np.errstate(all="ignore"):
            return np.broadcast_to(np.asarray(eval(code, {"__builtins__": {}}, env), dtype=float), X.shape[:1])

    return f


def basis_from_expressions(exprs, coords=("x",), names=None):
    """Build a core Basis from expression strings.

    Examples
    --------
    >>> import numpy as np
    >>> b = basis_from_expressions(["x**2*sin(5*x)"])
    >>> b.evaluate(np.array([0.0, 1.0])).round(4).tolist()
    [[0.0], [-0.9589]]
    """
    from odnn_sep.core import Basis

    exprs = list(exprs)
    if not exprs:
        raise InputError("no basis given; pass at least one --basis expression, e.g. --basis 'sin(5*x)'")
    return Basis([compile_expression(e, tuple(coords)) for e in exprs], names=list(names or exprs))


def parse_disturbance(spec: str, ndim: int = 1):
    """'orthogonal' | 'even[:c]' | 'even:cx,cy' | 'periodic:P' | 'band:LO:HI' | 'convex' | 'monotone[:dec]'."""
    from odnn_sep.core import Band, Convex, Even, Monotone, Orthogonal, Periodic

    kinds = ["orthogonal", "even", "periodic", "band", "convex", "monotone"]
    parts = spec.strip().lower().split(":")
    kind, args = parts[0], parts[1:]
    try:
        if kind == "orthogonal" and not args:
            return Orthogonal()
        if kind == "even":
            if not args:
                return Even(center=0.0 if ndim == 1 else (0.0,) * ndim)
            c = tuple(float(v) for v in args[0].split(","))
            return Even(center=c[0] if len(c) == 1 else c)
        if kind == "periodic" and len(args) == 1:
            return Periodic(float(args[0]))
        if kind == "band" and len(args) == 2:
            return Band(float(args[0]), float(args[1]))
        if kind == "convex" and not args:
            return Convex()
        if kind == "monotone" and len(args) <= 1:
            if args and args[0] not in ("inc", "dec"):
                raise ValueError
            return Monotone(increasing=not (args and args[0] == "dec"))
    except ValueError:
        pass
    hint = difflib.get_close_matches(kind, kinds, n=1)
    extra = f" (did you mean {hint[0]!r}?)" if hint and hint[0] != kind else ""
    raise InputError(f"disturbance spec {spec!r} is not understood{extra}; use orthogonal, even[:center], "
                     "periodic:PERIOD, band:LO:HI, convex or monotone[:inc|dec]")
