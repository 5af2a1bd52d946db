"""Safe formulas for everything a user types: u(t), V(t), coefficients, curves.

The text is tokenized and parsed by Python's ``ast`` *only as a syntax tree*; the tree
is walked against a whitelist and turned into a sympy expression built node by node
(no ``eval``, no ``sympify`` of user text).  Allowed: numbers, the declared variables
(``t`` by default), ``+ - * / ^ **``, parentheses, the functions
``sin cos tan asin acos atan sinh cosh tanh exp log sqrt abs`` and the constants
``pi`` and ``e``.  Limits: length, nesting depth, node count, number magnitude and
exponent size.  Every message names what is wrong and where (column, 1-based).
"""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.message import N_, Message

MAX_LENGTH = 400
MAX_DEPTH = 24
MAX_NODES = 300
MAX_NUMBER = 1e12
MAX_EXPONENT = 64
MAX_VALUE = 1e15

FUNCTIONS: dict[str, Callable[[sp.Basic], sp.Basic]] = {
    "sin": sp.sin,
    "cos": sp.cos,
    "tan": sp.tan,
    "asin": sp.asin,
    "acos": sp.acos,
    "atan": sp.atan,
    "sinh": sp.sinh,
    "cosh": sp.cosh,
    "tanh": sp.tanh,
    "exp": sp.exp,
    "log": sp.log,
    "sqrt": sp.sqrt,
    "abs": sp.Abs,
}
CONSTANTS: dict[str, sp.Basic] = {"pi": sp.pi, "e": sp.E}
#: A number written with a decimal comma (``0,5``): refused with its dotted form.
_DECIMAL_COMMA = re.compile(r"\d+,\d+")
_ALLOWED_CHARS = set("0123456789.+-*/^() \t_abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ,")


class FormulaError(ValueError):
    """A formula was refused; the message says what and where."""


@dataclass(frozen=True)
class Formula:
    """A parsed formula: its text, its sympy expression and a vectorized evaluator."""

    text: str
    expr: sp.Expr
    variables: tuple[str, ...] = ("t",)
    _fn: Callable[..., np.ndarray] | None = field(default=None, compare=False, repr=False)

    @property
    def is_constant(self) -> bool:
        cached = self.__dict__.get("_is_constant")
        if cached is None:
            cached = not (
                self.expr.free_symbols & {sp.Symbol(v, real=True) for v in self.variables}
            )
            object.__setattr__(self, "_is_constant", cached)
        return cached

    @property
    def constant_value(self) -> float | None:
        """The number this formula stands for when it does not depend on its variables (cached)."""
        if "_constant_value" not in self.__dict__:
            object.__setattr__(
                self, "_constant_value", float(self.expr) if self.is_constant else None
            )
        return self.__dict__["_constant_value"]

    def __call__(self, *args: float | np.ndarray) -> np.ndarray | float:
        """Evaluate (numpy broadcasting).  Non-finite results are returned as they are;
        callers that integrate check finiteness with :meth:`check_finite`."""
        c = self.constant_value
        if c is not None:  # a number: its value, broadcast over the arguments
            if any(np.ndim(a) > 0 for a in args):
                return np.full(np.broadcast(*args).shape, c)
            return c
        fn = self._fn
        if fn is None:
            fn = sp.lambdify(
                [sp.Symbol(v, real=True) for v in self.variables], self.expr, modules="numpy"
            )
            object.__setattr__(self, "_fn", fn)
        with np.errstate(all="ignore"):
            out = fn(*args)
        if np.ndim(out) == 0 and any(np.ndim(a) > 0 for a in args):
            out = np.full(np.broadcast(*args).shape, float(out))
        return out

    def value(self, *args: float) -> float:
        return float(self(*args))

    def check_finite(self, t: np.ndarray) -> None:
        """Raise :class:`FormulaError` naming the first sample where the value is not finite."""
        vals = np.asarray(self(t), dtype=float) * np.ones_like(t, dtype=float)
        bad = ~np.isfinite(vals)
        if bad.any():
            t_bad = float(np.asarray(t, dtype=float).ravel()[np.argmax(bad.ravel())])
            raise FormulaError(
                Message(N_("{text} is not finite at t = {t:g}"), text=repr(self.text), t=t_bad)
            )

    def __str__(self) -> str:
        return self.text


def _fail(text: str, col: int | None, message: Message) -> FormulaError:
    """The refusal ``message``, where it is (column, 1-based) and in which text."""
    if col is None:
        return FormulaError(
            Message(N_("{message} in {text}"), message=message, text=repr(text[:60]))
        )
    return FormulaError(
        Message(
            N_("{message} at column {col} in {text}"),
            message=message,
            col=col,
            text=repr(text[:60]),
        )
    )


def parse_formula(text: str, variables: Sequence[str] = ("t",)) -> Formula:
    """Parse ``text`` as a whitelisted formula of ``variables``; raise :class:`FormulaError`."""
    if not isinstance(text, str):
        raise FormulaError(Message(N_("expected text, got {kind}"), kind=type(text).__name__))
    if len(text) > MAX_LENGTH:
        raise FormulaError(
            Message(
                N_("formula is {length} characters long; the limit is {limit}"),
                length=len(text),
                limit=MAX_LENGTH,
            )
        )
    src = text.strip()
    if not src:
        raise FormulaError(Message(N_("formula is empty")))
    for i, ch in enumerate(src):
        if ch not in _ALLOWED_CHARS:
            raise _fail(src, i + 1, Message(N_("character {char} is not allowed"), char=repr(ch)))
    comma = _DECIMAL_COMMA.search(src)
    if comma is not None:  # 0,5: no formula has a comma between digits (one-argument functions)
        found = comma.group(0)
        raise _fail(
            src,
            comma.start() + 1,
            Message(
                N_("{found} has a decimal comma: write {dotted} with a dot"),
                found=found,
                dotted=found.replace(",", "."),
            ),
        )
    depth = 0
    for i, ch in enumerate(src):
        if ch == "(":
            depth += 1
            if depth > MAX_DEPTH:
                raise _fail(
                    src,
                    i + 1,
                    Message(N_("parentheses nested deeper than {limit}"), limit=MAX_DEPTH),
                )
        elif ch == ")":
            depth -= 1
            if depth < 0:
                raise _fail(src, i + 1, Message(N_("unmatched ')'")))
    if depth:
        raise _fail(src, None, Message(N_("unclosed '('")))
    try:
        tree = ast.parse(src.replace("^", "**"), mode="eval")
    except SyntaxError as exc:
        raise _fail(src, exc.offset, Message(N_("syntax error"))) from None
    except (RecursionError, MemoryError, ValueError):
        raise _fail(src, None, Message(N_("formula too complex"))) from None
    nodes = sum(1 for _ in ast.walk(tree))
    if nodes > MAX_NODES:
        raise FormulaError(
            Message(
                N_("formula has {nodes} syntax nodes; the limit is {limit}"),
                nodes=nodes,
                limit=MAX_NODES,
            )
        )
    symbols = {v: sp.Symbol(v, real=True) for v in variables}
    expr = _build(tree.body, src, symbols, 0)
    if not isinstance(expr, sp.Expr):
        raise _fail(src, None, Message(N_("not a numeric expression")))
    if expr.free_symbols - set(symbols.values()):
        raise _fail(src, None, Message(N_("unknown symbols")))
    if expr.is_number:
        try:
            val = complex(sp.N(expr))
        except (TypeError, ValueError, OverflowError):
            raise _fail(src, None, Message(N_("value cannot be computed"))) from None
        if abs(val.imag) > 1e-12 * max(1.0, abs(val.real)) or not math.isfinite(val.real):
            raise _fail(src, None, Message(N_("value is not a finite real number")))
    return Formula(text=src, expr=expr, variables=tuple(variables))


def _num(value: sp.Basic) -> float | None:
    if value.is_number:
        try:
            return float(sp.N(value))
        except (TypeError, ValueError, OverflowError):
            return None
    return None


def _build(node: ast.AST, src: str, symbols: dict[str, sp.Symbol], depth: int) -> sp.Expr:
    expr = _build_node(node, src, symbols, depth)
    if expr.is_number and not isinstance(node, ast.Constant):
        v = _num(expr)
        if v is not None and (not math.isfinite(v) or abs(v) > MAX_VALUE):
            col = getattr(node, "col_offset", 0) + 1
            raise _fail(
                src,
                col,
                Message(N_("value {value:.3g} is larger than {limit:g}"), value=v, limit=MAX_VALUE),
            )
    return expr


def _build_node(node: ast.AST, src: str, symbols: dict[str, sp.Symbol], depth: int) -> sp.Expr:
    col = getattr(node, "col_offset", None)
    col = None if col is None else col + 1
    if depth > 3 * MAX_DEPTH:
        raise _fail(src, col, Message(N_("formula too deeply nested")))
    if isinstance(node, ast.Constant):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise _fail(
                src, col, Message(N_("only numbers are allowed, not {kind}"), kind=type(v).__name__)
            )
        if not math.isfinite(float(v)) or abs(v) > MAX_NUMBER:
            raise _fail(
                src,
                col,
                Message(
                    N_("number {number} is larger than {limit:g}"), number=repr(v), limit=MAX_NUMBER
                ),
            )
        if isinstance(v, int):
            return sp.Integer(v)
        return sp.Rational(str(v)) if len(str(v)) <= 20 else sp.Float(v)
    if isinstance(node, ast.Name):
        if node.id in symbols:
            return symbols[node.id]
        if node.id in CONSTANTS:
            return CONSTANTS[node.id]
        if node.id in FUNCTIONS:
            raise _fail(
                src,
                col,
                Message(N_("function {name} needs an argument in parentheses"), name=repr(node.id)),
            )
        allowed = ", ".join([*symbols, *CONSTANTS])
        raise _fail(
            src,
            col,
            Message(
                N_("unknown name {name} (allowed: {allowed})"),
                name=repr(node.id[:20]),
                allowed=allowed,
            ),
        )
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        inner = _build(node.operand, src, symbols, depth + 1)
        return -inner if isinstance(node.op, ast.USub) else inner
    if isinstance(node, ast.BinOp):
        left = _build(node.left, src, symbols, depth + 1)
        right = _build(node.right, src, symbols, depth + 1)
        op = node.op
        if isinstance(op, ast.Add):
            return left + right
        if isinstance(op, ast.Sub):
            return left - right
        if isinstance(op, ast.Mult):
            return left * right
        if isinstance(op, ast.Div):
            if right.is_number and right.is_zero:
                raise _fail(src, col, Message(N_("division by zero")))
            return left / right
        if isinstance(op, (ast.Pow, ast.BitXor)):
            e = _num(right)
            if right.is_number and (e is None or abs(e) > MAX_EXPONENT):
                raise _fail(
                    src, col, Message(N_("exponent is larger than {limit}"), limit=MAX_EXPONENT)
                )
            b = _num(left)
            if b is not None and e is not None and b != 0 and abs(e * math.log10(abs(b))) > 300:
                raise _fail(src, col, Message(N_("power overflows")))
            if b == 0 and e is not None and e < 0:
                raise _fail(src, col, Message(N_("zero to a negative power")))
            return sp.Pow(left, right)
        raise _fail(src, col, Message(N_("operator {kind} is not allowed"), kind=type(op).__name__))
    if isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
            name = node.func.id if isinstance(node.func, ast.Name) else "this call"
            raise _fail(
                src,
                col,
                Message(
                    N_("function {name} is not allowed (allowed: {allowed})"),
                    name=repr(str(name)[:20]),
                    allowed=", ".join(FUNCTIONS),
                ),
            )
        if node.keywords or len(node.args) != 1:
            raise _fail(
                src, col, Message(N_("{name} takes exactly one argument"), name=node.func.id)
            )
        arg = _build(node.args[0], src, symbols, depth + 1)
        return FUNCTIONS[node.func.id](arg)
    kind = type(node).__name__
    raise _fail(src, col, Message(N_("{kind} is not allowed in a formula"), kind=kind))


def plain_number(value: object) -> str:
    """A number as a person types it: the shortest text that reads back as the same float
    (``1e-05``, ``0.25``, ``3``), never a numpy repr such as ``np.float64(0.25)``."""
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return str(value)[:60]
    if x.is_integer() and abs(x) < 1e16:
        return str(int(x))
    return repr(x)


def parse_number(text: str) -> float:
    """A constant formula (``2.5``, ``pi/2``, ``sqrt(2)``) as a finite float: a typed
    number reads back exactly (``1e-5`` is the float ``1e-05``, as printed)."""
    f = parse_formula(text, variables=())
    try:
        # exact numbers (a typed literal is a Rational) are rounded once, to the nearest
        # float; 15 significant digits would make 1e-5 read as 9.999999999999999e-06
        value = float(f.expr) if f.expr.is_Rational else float(sp.N(f.expr, 30))
    except (TypeError, ValueError, OverflowError):
        raise FormulaError(
            Message(N_("{text} is not a real number"), text=repr(text[:60]))
        ) from None
    if not math.isfinite(value):
        raise FormulaError(Message(N_("{text} is not finite"), text=repr(text[:60])))
    return value


#: The time symbol every formula of ``t`` uses (lessons build derivations with it).
t_symbol = sp.Symbol("t", real=True)
