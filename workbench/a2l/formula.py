"""ASAP2 formulas (COMPU_METHOD FORM: FORMULA / FORMULA_INV), parsed and evaluated without ``eval``.

A formula is text such as ``"X1 * 0.1 - 40"`` or ``"(X1 >> 4) & 0x0F"``. It is split into tokens,
parsed with the C operator precedence ASAM MCD-2 MC (1.6, 1.7) gives it, and compiled into a
tree of numpy operations: only the operators and functions below exist, so a formula can compute
but never run code. Evaluation is vectorized: ``f(array)`` converts many raw values at once.

- variables: ``X1`` (also ``X``, and ``X2``..``X9`` when the caller declares them); case ignored
- numbers: decimal, exponent, ``0x`` hexadecimal; ``sysc(NAME)``: MOD_PAR's SYSTEM_CONSTANT NAME
- arithmetic ``+ - * / %``, unary ``- +``; bitwise ``& | ^ ~ << >>`` (on 64-bit integers);
  comparisons ``< <= > >= == !=`` and logical ``&& || !`` (1.0 for true, 0.0 for false)
- functions: sin cos tan asin acos atan sinh cosh tanh exp log log10 sqrt abs pow floor ceil min
  max mod (``arcsin``/``arccos``/``arctan`` accepted for the 1.5 spellings)

A formula that does not parse raises :class:`ConversionError` naming the formula and the place.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping

import numpy as np

from workbench.errors import ConversionError

__all__ = ["Formula", "compile_formula"]

Node = Callable[[dict], np.ndarray]

_TOKEN = re.compile(r"""
    \s*(?:
      (?P<number>0[xX][0-9a-fA-F]+|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
    | (?P<name>[A-Za-z_][A-Za-z0-9_]*)
    | (?P<op>&&|\|\||<<|>>|<=|>=|==|!=|[-+*/%()&|^~!<>,])
    )""", re.VERBOSE)

_FUNCTIONS: dict[str, tuple[int, Callable]] = {  # name -> (arguments, numpy function)
    "sin": (1, np.sin), "cos": (1, np.cos), "tan": (1, np.tan), "asin": (1, np.arcsin), "acos": (1, np.arccos),
    "atan": (1, np.arctan), "sinh": (1, np.sinh), "cosh": (1, np.cosh), "tanh": (1, np.tanh), "exp": (1, np.exp),
    "log": (1, np.log), "log10": (1, np.log10), "sqrt": (1, np.sqrt), "abs": (1, np.abs), "pow": (2, np.power),
    "floor": (1, np.floor), "ceil": (1, np.ceil), "min": (2, np.minimum), "max": (2, np.maximum),
    "mod": (2, np.fmod), "arcsin": (1, np.arcsin), "arccos": (1, np.arccos), "arctan": (1, np.arctan),
}


def _bits(value: np.ndarray) -> np.ndarray:
    return np.trunc(value).astype(np.int64)


def _truth(value: np.ndarray) -> np.ndarray:
    return value != 0


_BINARY: dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {
    "+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide, "%": np.fmod,
    "<<": lambda a, b: np.left_shift(_bits(a), _bits(b)).astype(np.float64),
    ">>": lambda a, b: np.right_shift(_bits(a), _bits(b)).astype(np.float64),
    "&": lambda a, b: np.bitwise_and(_bits(a), _bits(b)).astype(np.float64),
    "|": lambda a, b: np.bitwise_or(_bits(a), _bits(b)).astype(np.float64),
    "^": lambda a, b: np.bitwise_xor(_bits(a), _bits(b)).astype(np.float64),
    "<": lambda a, b: (a < b).astype(np.float64), "<=": lambda a, b: (a <= b).astype(np.float64),
    ">": lambda a, b: (a > b).astype(np.float64), ">=": lambda a, b: (a >= b).astype(np.float64),
    "==": lambda a, b: (a == b).astype(np.float64), "!=": lambda a, b: (a != b).astype(np.float64),
    "&&": lambda a, b: (_truth(a) & _truth(b)).astype(np.float64),
    "||": lambda a, b: (_truth(a) | _truth(b)).astype(np.float64),
}
# C precedence, loosest first; every binary operator is left-associative
_LEVELS = (("||",), ("&&",), ("|",), ("^",), ("&",), ("==", "!="), ("<", "<=", ">", ">="), ("<<", ">>"),
           ("+", "-"), ("*", "/", "%"))
_UNARY: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "-": np.negative, "+": lambda a: a, "!": lambda a: (~_truth(a)).astype(np.float64),
    "~": lambda a: np.invert(_bits(a)).astype(np.float64),
}
_MAX_LENGTH = 4096  # characters: a formula is a line, not a program
_MAX_DEPTH = 40  # nested parentheses, calls and unary operators (each costs a dozen Python frames)


class Formula:
    """A compiled formula: ``formula(x1)`` (or ``formula(X1=.., X2=..)``) -> float64 array."""

    def __init__(self, text: str, node: Node, variables: tuple[str, ...]):
        self.text = text
        self._node = node
        self.variables = variables

    def __repr__(self) -> str:
        return f"Formula({self.text!r})"

    def __call__(self, *args, **named) -> np.ndarray:
        values = dict(zip(self.variables, args))
        values.update({key.upper(): value for key, value in named.items()})
        env = {key: np.asarray(value, dtype=np.float64) for key, value in values.items()}
        with np.errstate(all="ignore"):
            return np.asarray(self._node(env), dtype=np.float64)


def compile_formula(text: str, system_constants: Mapping[str, str] | None = None,
                    variables: tuple[str, ...] = ("X1",)) -> Formula:
    """Parse ``text`` into a :class:`Formula`; ``X`` is another name for ``X1``.

    :raises ConversionError: a syntax error, an unknown name or function, a missing system constant.
    """
    if len(text) > _MAX_LENGTH:
        raise ConversionError(f"formula too long ({len(text)} characters): {text[:40]!r}...")
    parser = _Parser(text, dict(system_constants or {}), tuple(v.upper() for v in variables))
    return Formula(text, parser.parse(), parser.variables)


class _Parser:
    """Precedence climbing over the tokens; each rule returns a closure ``env -> ndarray``."""

    def __init__(self, text: str, constants: dict[str, str], variables: tuple[str, ...]):
        self.text = text
        self.constants = constants
        self.variables = variables
        self.tokens = self._tokenize(text)
        self.position = 0
        self.depth = 0

    def _tokenize(self, text: str) -> list[tuple[str, str, int]]:
        tokens, position = [], 0
        while True:
            match = _TOKEN.match(text, position)
            if match is None or match.end() == position:
                if text[position:].strip():
                    column = position + len(text[position:]) - len(text[position:].lstrip()) + 1
                    raise self._error(f"unexpected {text[column - 1]!r}", column)
                return tokens
            kind = match.lastgroup
            tokens.append((kind, match.group(kind), match.start(kind) + 1))
            position = match.end()

    def _error(self, message: str, column: int | None = None) -> ConversionError:
        where = f" at character {column}" if column else ""
        return ConversionError(f"formula {self.text!r}: {message}{where}")

    def _enter(self, column: int) -> None:
        self.depth += 1
        if self.depth > _MAX_DEPTH:
            raise self._error("nested too deeply", column)

    def _peek(self) -> tuple[str, str, int] | None:
        return self.tokens[self.position] if self.position < len(self.tokens) else None

    def _take(self, value: str | None = None) -> tuple[str, str, int]:
        token = self._peek()
        if token is None:
            raise self._error("unexpected end" + (f", expected {value!r}" if value else ""))
        if value is not None and token[1] != value:
            raise self._error(f"expected {value!r}, found {token[1]!r}", token[2])
        self.position += 1
        return token

    def parse(self) -> Node:
        if not self.tokens:
            raise self._error("empty")
        node = self._binary(0)
        token = self._peek()
        if token is not None:
            raise self._error(f"unexpected {token[1]!r}", token[2])
        return node

    def _binary(self, level: int) -> Node:
        if level == len(_LEVELS):
            return self._unary()
        left = self._binary(level + 1)
        while (token := self._peek()) is not None and token[0] == "op" and token[1] in _LEVELS[level]:
            self.position += 1
            right = self._binary(level + 1)
            left = _apply2(_BINARY[token[1]], left, right)
        return left

    def _unary(self) -> Node:
        token = self._peek()
        if token is not None and token[0] == "op" and token[1] in _UNARY:
            self.position += 1
            self._enter(token[2])
            operand = self._unary()
            self.depth -= 1
            function = _UNARY[token[1]]
            return lambda env: function(operand(env))
        return self._primary()

    def _primary(self) -> Node:
        kind, value, column = self._take()
        if kind == "number":
            number = float(int(value, 16)) if value[:2] in ("0x", "0X") else float(value)
            constant = np.float64(number)
            return lambda env: constant
        if kind == "op" and value == "(":
            self._enter(column)
            node = self._binary(0)
            self._take(")")
            self.depth -= 1
            return node
        if kind == "name":
            return self._name(value, column)
        raise self._error(f"unexpected {value!r}", column)

    def _name(self, name: str, column: int) -> Node:
        upper = name.upper()
        if upper == "X":
            upper = "X1"
        if upper in self.variables:
            def variable(env, key=upper):
                if key not in env:
                    raise ConversionError(f"formula {self.text!r}: no value given for {key}")
                return env[key]
            return variable
        lower = name.lower()
        if lower == "sysc":
            return self._system_constant(column)
        if lower not in _FUNCTIONS:
            raise self._error(f"unknown name {name!r}", column)
        count, function = _FUNCTIONS[lower]
        self._take("(")
        self._enter(column)
        arguments = [self._binary(0)]
        while self._peek() is not None and self._peek()[1] == ",":
            self.position += 1
            arguments.append(self._binary(0))
        self._take(")")
        self.depth -= 1
        if len(arguments) != count:
            raise self._error(f"{lower}() takes {count} argument(s), {len(arguments)} given", column)
        if count == 1:
            only = arguments[0]
            return lambda env: function(only(env))
        return _apply2(function, *arguments)

    def _system_constant(self, column: int) -> Node:
        self._take("(")
        kind, key, _ = self._take()
        self._take(")")
        if key not in self.constants:
            known = ", ".join(sorted(self.constants)) or "none"
            raise self._error(f"no SYSTEM_CONSTANT {key!r} in MOD_PAR (known: {known})", column)
        try:
            constant = np.float64(float(self.constants[key]))
        except ValueError:
            raise self._error(f"SYSTEM_CONSTANT {key!r} is not a number: {self.constants[key]!r}", column) from None
        return lambda env: constant


def _apply2(function: Callable, left: Node, right: Node) -> Node:
    return lambda env: function(left(env), right(env))
