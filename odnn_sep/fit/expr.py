"""Safe parsing of basis expressions ("x**2*sin(5*x)") and disturbance specs ("periodic:1.25").

Expressions are parsed with ``ast`` and evaluated by a small tree walker: only arithmetic, numbers,
the coordinate names and a whitelist of numpy functions are allowed, so a basis string can never
run arbitrary code, and bounded sizes (length, parts, depth, exponents, literals) keep it from
hanging or exhausting memory.
"""
from __future__ import annotations

import ast
import difflib
import math
import warnings

import numpy as np

from odnn_sep.errors import InputError

FUNCS = {name: getattr(np, name) for name in (
    "sin", "cos", "tan", "exp", "log", "log10", "sqrt", "abs", "tanh", "sinh", "cosh", "arctan", "sign",
    "heaviside", "minimum", "maximum", "where")}
ARITY = {"heaviside": 2, "minimum": 2, "maximum": 2, "where": 3}
CONSTS = {"pi": np.pi, "e": np.e}

#: Bounds that keep any expression cheap to check and to evaluate (no big integers, no deep recursion).
MAX_CHARS = 2000
MAX_NODES = 1000
MAX_DEPTH = 40
MAX_EXPONENT = 100.0
MAX_LITERAL = 1e100

_BINOPS = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.true_divide,
           ast.Pow: np.power, ast.Mod: np.mod}
_UNARY = {ast.USub: np.negative, ast.UAdd: np.positive}
_COMPARE = {ast.Gt: np.greater, ast.Lt: np.less, ast.GtE: np.greater_equal, ast.LtE: np.less_equal}
_NAMES = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**", ast.Mod: "%",
          ast.FloorDiv: "//", ast.MatMult: "@", ast.BitAnd: "&", ast.BitOr: "|", ast.BitXor: "^",
          ast.LShift: "<<", ast.RShift: ">>", ast.Eq: "==", ast.NotEq: "!=", ast.Is: "is", ast.In: "in",
          ast.IsNot: "is not", ast.NotIn: "not in", ast.Not: "not", ast.Invert: "~"}


def _fail(expr: str, why: str):
    shown = expr if len(expr) <= 60 else expr[:57] + "..."
    raise InputError(f"basis expression {shown!r} {why}")


def _parse(expr: str) -> ast.Expression:
    if not isinstance(expr, str) or not expr.strip():
        raise InputError("basis expression is empty; write e.g. 'x**2*sin(5*x)'")
    if len(expr) > MAX_CHARS:
        _fail(expr, f"is {len(expr)} characters long; the limit is {MAX_CHARS}")
    if any(ord(c) < 32 for c in expr):
        _fail(expr, "contains a control character (newline, tab, ...); write it on one line")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SyntaxWarning)  # e.g. "1x": the error below says it better
            return ast.parse(expr.strip(), mode="eval")
    except SyntaxError as exc:
        _fail(expr, f"is not valid: {exc.msg}; write e.g. 'x**2*sin(5*x)'")
    except (RecursionError, MemoryError, ValueError):
        _fail(expr, f"is nested too deeply or too large; the limit is {MAX_DEPTH} levels")


def coordinate_names(coords) -> tuple:
    """The names an expression may use for the coordinates: ``coords``, and ``x`` for a 1-D record's
    coordinate named otherwise by its header.

    The help and examples write the coordinate as x; a CSV whose first column is headed ``length``
    refused ``sqrt(x)`` (the message named ``length``), so both names are taken.

    Examples
    --------
    >>> coordinate_names(("length",)), coordinate_names(("x",)), coordinate_names(("x", "y"))
    (('length', 'x'), ('x',), ('x', 'y'))
    """
    coords = tuple(coords)
    return coords + ("x",) if len(coords) == 1 and coords[0] != "x" else coords


def _check_tree(expr: str, tree: ast.Expression, coords) -> None:
    """Walk the tree without recursion: size, depth, and only the allowed constructs."""
    allowed = set(coordinate_names(coords)) | set(FUNCS) | set(CONSTS)
    stack = [(tree.body, 1)]
    count = 0
    while stack:
        node, depth = stack.pop()
        count += 1
        if count > MAX_NODES:
            _fail(expr, f"has more than {MAX_NODES} parts; split it into several --basis terms")
        if depth > MAX_DEPTH:
            _fail(expr, f"is nested more than {MAX_DEPTH} levels deep; simplify it")
        stack.extend((c, depth + 1) for c in _checked_children(expr, node, allowed, coords))


def _checked_children(expr: str, node, allowed: set, coords) -> list:
    """The operands of ``node`` after checking that the node itself is allowed."""
    if isinstance(node, ast.BinOp):
        if type(node.op) not in _BINOPS:
            _fail(expr, f"uses the operator {_NAMES.get(type(node.op), type(node.op).__name__)!r}, which is "
                  "not allowed; use + - * / ** %")
        return [node.left, node.right]
    if isinstance(node, ast.UnaryOp):
        if type(node.op) not in _UNARY:
            _fail(expr, f"uses {_NAMES.get(type(node.op), type(node.op).__name__)!r}, which is not allowed")
        return [node.operand]
    if isinstance(node, ast.Compare):
        if len(node.ops) != 1:
            _fail(expr, "chains comparisons (a < b < c); write where(a < b, where(b < c, 1, 0), 0) instead")
        if type(node.ops[0]) not in _COMPARE:
            _fail(expr, f"uses the comparison {_NAMES.get(type(node.ops[0]), '?')!r}; only < <= > >= are allowed")
        return [node.left, *node.comparators]
    if isinstance(node, ast.Call):
        _check_call(expr, node)
        return list(node.args)
    if isinstance(node, ast.Name):
        _check_name(expr, node.id, allowed, coords)
        return []
    if isinstance(node, ast.Constant):
        _check_number(expr, node.value)
        return []
    what = {"Constant": "a constant"}.get(type(node).__name__, type(node).__name__)
    _fail(expr, f"uses {what}, which is not allowed; use arithmetic and functions like sin, cos, exp, log, sqrt")


def _check_call(expr: str, node: ast.Call) -> None:
    if not isinstance(node.func, ast.Name):
        _fail(expr, "calls something that is not an allowed function")
    name = node.func.id
    if name not in FUNCS:
        hint = difflib.get_close_matches(name, sorted(FUNCS), n=1)
        extra = f" (did you mean {hint[0]!r}?)" if hint else ""
        _fail(expr, f"calls unknown function {name!r}{extra}; allowed functions: {sorted(FUNCS)}")
    if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
        _fail(expr, f"passes keyword or starred arguments to {name!r}; give plain arguments")
    if len(node.args) != ARITY.get(name, 1):
        _fail(expr, f"calls {name!r} with {len(node.args)} argument(s); it takes {ARITY.get(name, 1)}")


def _check_name(expr: str, name: str, allowed: set, coords) -> None:
    if name in FUNCS:  # call positions are not walked, so this is a bare function name
        _fail(expr, f"uses the function {name!r} without calling it; write e.g. {name}(x)")
    if name not in allowed:
        hint = difflib.get_close_matches(name, sorted(allowed), n=1)
        extra = f" (did you mean {hint[0]!r}?)" if hint else ""
        _fail(expr, f"uses unknown name {name!r}{extra}; allowed: coordinates {list(coordinate_names(coords))}, "
              f"functions {sorted(FUNCS)}, constants pi, e")


def _check_number(expr: str, v) -> None:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        _fail(expr, f"contains {v!r}, which is not a number")
    try:
        fv = float(v)
    except OverflowError:
        fv = float("inf")
    if not abs(fv) <= MAX_LITERAL:
        _fail(expr, f"contains a number too large to use (limit {MAX_LITERAL:g})")


def _evaluate(expr: str, node, env):
    """Evaluate a checked tree in float64 (numbers never become Python big integers)."""
    if isinstance(node, ast.Constant):
        return np.float64(node.value)
    if isinstance(node, ast.Name):
        return env[node.id]
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_evaluate(expr, node.operand, env))
    if isinstance(node, ast.BinOp):
        left, right = _evaluate(expr, node.left, env), _evaluate(expr, node.right, env)
        if isinstance(node.op, ast.Pow) and np.ndim(right) == 0 and not abs(float(right)) <= MAX_EXPONENT:
            _fail(expr, f"raises to the power {float(right):g}; exponents are limited to +-{MAX_EXPONENT:g}")
        return _BINOPS[type(node.op)](left, right)
    if isinstance(node, ast.Compare):
        left, right = _evaluate(expr, node.left, env), _evaluate(expr, node.comparators[0], env)
        return _COMPARE[type(node.ops[0])](left, right).astype(float)
    if isinstance(node, ast.Call):
        return FUNCS[node.func.id](*(_evaluate(expr, a, env) for a in node.args))
    raise AssertionError(f"unchecked node {type(node).__name__}")  # _check_tree refuses the others


def compile_expression(expr: str, coords: tuple[str, ...]):
    """Return f(X) evaluating ``expr`` with X of shape (n,) or (n, len(coords)).

    Only arithmetic (+ - * / ** %), single comparisons, numbers, the coordinate names, pi, e and
    the functions in ``FUNCS`` are accepted, within the bounds ``MAX_CHARS``, ``MAX_NODES``,
    ``MAX_DEPTH``, ``MAX_EXPONENT`` and ``MAX_LITERAL``; anything else is an InputError.
    A column that is not finite everywhere is an InputError naming the first bad point.

    Parameters
    ----------
    expr : str
        The expression, e.g. ``"x**2*sin(5*x)"``.
    coords : tuple of str
        Names of the coordinates it may use, in column order of X.

    Returns
    -------
    callable
        ``f(X) -> (n,) ndarray``.

    Raises
    ------
    odnn_sep.errors.InputError
        For a refused or oversized expression (at once) or non-finite values (when called).

    Examples
    --------
    >>> f = compile_expression("sin(2*pi*x) + where(x > 0.5, 1, 0)", ("x",))
    >>> f(np.array([0.25, 0.75])).round(12).tolist()
    [1.0, 0.0]
    >>> compile_expression("__import__('os')", ("x",))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: basis expression "__import__('os')" calls unknown function '__import__'; allowed functions: [...]
    """
    return _Expression(expr, tuple(coords))


class _Expression:
    """A checked expression as a callable ``f(X)``; pickles by its text (a fitted Separator and its
    basis go to other processes: multiprocessing, joblib), and is checked again when unpickled."""

    def __init__(self, expr: str, coords: tuple):
        tree = _parse(expr)
        _check_tree(expr, tree, coords)
        self.expr, self.coords, self._tree = expr, coords, tree

    def __reduce__(self):
        return (_Expression, (self.expr, self.coords))

    def __repr__(self):
        return f"expression({self.expr!r})"

    def __call__(self, X):
        expr, coords, tree = self.expr, self.coords, self._tree
        X = np.asarray(X, dtype=float)
        env = dict(FUNCS, **CONSTS)
        if X.ndim == 1:
            env.update(dict.fromkeys(coordinate_names(coords[:1]), X))
        else:
            env.update({c: X[:, i] for i, c in enumerate(coords)})
        with np.errstate(all="ignore"):
            out = np.asarray(_evaluate(expr, tree.body, env), dtype=float)
        if out.ndim > 1 or (out.ndim == 1 and out.shape[0] != X.shape[0]):
            _fail(expr, f"gives an array of shape {out.shape}; it must give one value per point")
        out = np.broadcast_to(out, X.shape[:1])
        bad = ~np.isfinite(out)
        if bad.any():
            i = int(np.argmax(bad))
            at = X[i] if X.ndim == 1 else tuple(float(v) for v in X[i])
            _fail(expr, f"is not finite at {int(bad.sum())} of {bad.size} point(s) (first at {coords[0] if X.ndim == 1 else coords} = {at}: {out[i]}); "
                  "change the expression or the data range")
        return out


def basis_from_expressions(exprs, coords=("x",), names=None):
    """Build a core Basis from expression strings.

    Parameters
    ----------
    exprs : iterable of str
        One expression per physics term (see :func:`compile_expression`).
    coords : tuple of str, optional
        Coordinate names.
    names : list of str, optional
        Term names (default the expressions).

    Returns
    -------
    odnn_sep.core.Basis

    Raises
    ------
    odnn_sep.errors.InputError
        For no expression or a refused one.

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
    """The disturbance class named by ``spec``: 'orthogonal' | 'even[:c]' | 'even:cx,cy' | 'periodic:P' |
    'band:LO:HI' | 'convex' | 'monotone[:dec]' (``ndim``: dimension of the coordinates, for ``even``).

    Parameters
    ----------
    spec : str
        The class, as given to ``--disturbance``.
    ndim : int, optional
        Dimension of the coordinates.

    Returns
    -------
    odnn_sep.core.base.Disturbance
        ``Orthogonal``, ``Even``, ``Periodic``, ``Band``, ``Convex`` or ``Monotone``.

    Raises
    ------
    odnn_sep.errors.InputError
        For an unknown or malformed ``spec`` (with the closest valid kind).

    Examples
    --------
    >>> parse_disturbance("periodic:2.5").describe(), parse_disturbance("monotone:dec").increasing
    ('periodic with period 2.5', False)
    >>> parse_disturbance("convex", ndim=2)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --disturbance 'convex' is for a 1-D signal (a CSV); a 2-D field (.npz) takes orthogonal or even[:cx,cy]
    """
    from odnn_sep.core import Band, Convex, Even, Monotone, Orthogonal, Periodic

    kinds = ["orthogonal", "even", "periodic", "band", "convex", "monotone"]
    parts = spec.strip().lower().split(":")
    kind, args = parts[0], parts[1:]
    if ndim > 1 and kind in kinds[2:]:
        # the engine's own refusal spoke of "sample points x of shape (1500, 2)", which a field's user never made
        raise InputError(f"--disturbance {spec!r} is for a 1-D signal (a CSV); a {ndim}-D field (.npz) takes "
                         "orthogonal or even[:cx,cy]")
    try:
        if kind == "orthogonal" and not args:
            return Orthogonal()
        if kind == "even":
            if not args:
                return Even(center=0.0 if ndim == 1 else (0.0,) * ndim)
            c = tuple(float(v) for v in args[0].split(","))
            if len(c) not in (1, ndim) or not all(math.isfinite(v) for v in c):
                # a centre of the wrong dimension failed inside numpy with a traceback
                want = "one number" if ndim == 1 else f"one number or {ndim} (comma-separated)"
                raise InputError(f"--disturbance {spec!r}: the centre of symmetry must be {want}, finite, for "
                                 f"{ndim}-D coordinates; e.g. even:{','.join(['0'] * ndim)}")
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
    except InputError:
        raise
    except ValueError:
        pass
    hint = difflib.get_close_matches(kind, kinds, n=1)
    extra = f" (did you mean {hint[0]!r}?)" if hint and hint[0] != kind else ""
    raise InputError(f"disturbance spec {spec!r} is not understood{extra}; use orthogonal, even[:center], "
                     "periodic:PERIOD, band:LO:HI, convex or monotone[:inc|dec]")
