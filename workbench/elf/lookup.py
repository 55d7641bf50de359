"""Which variable an A2L symbol name means: scopes, qualified names, ambiguity.

C and C++ give one name to several variables: file statics of several units, statics
of several functions, C++ namespaces and classes. An A2L names them the ways its
generator writes them, and all of these are read here:

- the plain name, ``counter``, when it designates one variable (see below);
- a qualified name, with ``::`` or ``.`` between the scopes, the variable and its
  members: ``app::detail::nestedValue``, ``app::Controller::instances`` (a static
  member), ``app::mostDerived.baseId``; a function's static as ``function.variable``
  (``wild_tick.tickCount``, also ``wild_tick::tickCount`` as gdb writes it, or
  ``app::Controller::step.calls`` in C++); only the innermost scopes need to be written
  (``Controller::instances``) as long as the result designates one variable;
- the compile unit in front, as a2ltool and Vector tools write it: the unit's file name
  with ``.`` -> ``_`` (``wild_other_c.fileLocal``, ``wild_c.wild_tick.ambiguous``);
- Vector's suffix in a SYMBOL_LINK, ``ambiguous{Function:wild_tick}{CompileUnit:wild_c}
  {Namespace:Global}`` (namespaces as ``{Namespace:inner}{Namespace:outer}``, innermost
  first, as Vector and a2ltool write them).

Where several variables fit, the one that C would see from file scope wins: the fewest
scopes not written in the name (a global before a namespace member or a function's
static), then the one with external linkage before file statics. Several that are still
equal are an :class:`AmbiguousSymbolError` naming a qualified name for each: never a guess.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from typing import NamedTuple

from workbench.errors import UnknownSymbolError

__all__ = ["AmbiguousSymbolError", "Variable", "VariableTable", "VectorSpec", "scope_splits", "split_vector_spec"]

_IDENTIFIER = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]*")
_VECTOR_PART = re.compile(r"\{(Function|Namespace|CompileUnit):([^{}]*)\}")


class Variable(NamedTuple):
    """A variable with a static address, from DWARF or ``.symtab``."""

    name: str
    address: int | None  # None: no static location (optimised out, or a declaration only)
    type_offset: int | None  # DIE offset of its DWARF type; None without DWARF
    scope: tuple[str, ...] = ()  # namespaces and classes, outermost first; then the function of a function static
    unit: str = ""  # the compile unit's file name with "." -> "_" (a2ltool's "simple unit name")
    external: bool = True  # external linkage (a global); False: a file or function static
    function: bool = False  # a function's static: scope[-1] is the function

    @property
    def qualified_name(self) -> str:
        """How to name this variable alone: ``ns::Class::name``, ``function.name``, ``ns::function.name``."""
        if not self.scope:
            return self.name
        if self.function:
            return "::".join(self.scope) + "." + self.name
        return "::".join(self.scope) + "::" + self.name


class AmbiguousSymbolError(UnknownSymbolError):
    """A name that designates several variables; ``candidates`` are their qualified names."""

    def __init__(self, name: str, candidates: list[str]):
        self.candidates = candidates
        shown = ", ".join(candidates[:6]) + (f" and {len(candidates) - 6} more" if len(candidates) > 6 else "")
        super().__init__(name, f"ambiguous: {len(candidates)} variables fit ({shown}); name one of them")

    def __str__(self) -> str:
        return f"{self.name!r} is {self.where}"


class VectorSpec(NamedTuple):
    """The ``{Function:f}{Namespace:n}{CompileUnit:u}`` suffix of a Vector SYMBOL_LINK."""

    function: str | None
    namespaces: tuple[str, ...]  # outermost first ("Global" left out)
    unit: str | None


def split_vector_spec(path: str) -> tuple[str, VectorSpec | None]:
    """``"x.y{Function:f}{CompileUnit:a_c}{Namespace:Global}"`` -> ``("x.y", VectorSpec("f", (), "a_c"))``."""
    brace = path.find("{")
    if brace < 0:
        return path, None
    function = unit = None
    namespaces: list[str] = []
    position = brace
    for match in _VECTOR_PART.finditer(path, brace):
        if match.start() != position:
            break
        kind, value = match.groups()
        if kind == "Function":
            function = value
        elif kind == "CompileUnit":
            unit = value
        elif value != "Global":
            namespaces.append(value)
        position = match.end()
    if position != len(path):
        return path, None  # not Vector's form: the name stays as written (and is not found)
    return path[:brace], VectorSpec(function, tuple(reversed(namespaces)), unit)


def scope_splits(path: str) -> Iterator[tuple[tuple[str, ...], str, str]]:
    """The ways to read ``path`` as (scopes, variable name, member suffix), the plainest first:
    ``"a.b.c[2]"`` -> ``((), "a", ".b.c[2]")``, ``(("a",), "b", ".c[2]")``, ``(("a", "b"), "c", "[2]")``.
    Scopes written with ``::`` are always scopes; they may be any text (``(anonymous namespace)``,
    ``Holder<int>``)."""
    *written, tail = path.split("::")
    names: list[str] = []
    position = 0
    while True:
        match = _IDENTIFIER.match(tail, position)
        if match is None:
            return
        names.append(match.group())
        position = match.end()
        yield tuple(written) + tuple(names[:-1]), names[-1], tail[position:]
        if not tail.startswith(".", position):
            return
        position += 1


class VariableTable:
    """Variables by name, and the lookup of A2L symbol names among them. The variables may be given as
    plain tuples of :class:`Variable`'s fields (a large ELF has 50,000): only those a lookup meets become
    :class:`Variable` objects."""

    def __init__(self, variables: Iterable[tuple] = ()):
        self.by_name: dict[str, list[tuple]] = {}
        by_name = self.by_name
        for variable in variables:
            known = by_name.get(variable[0])
            if known is None:
                by_name[variable[0]] = [variable]
            else:
                known.append(variable)

    def __bool__(self) -> bool:
        return bool(self.by_name)

    def find(self, path: str) -> tuple[Variable, str] | None:
        """The variable ``path`` names and the member suffix after it (``".b[2]"``); None when no
        variable fits. Raises :class:`AmbiguousSymbolError` when several fit equally."""
        plain, spec = split_vector_spec(path)
        for scopes, name, suffix in scope_splits(plain):
            variables = self.by_name.get(name)
            if not variables:
                continue
            fitting = [v for v in map(Variable._make, variables) if _fits(v, scopes, spec)]
            if fitting:
                return _choose(path, fitting), suffix
        return None


def _fits(variable: Variable, scopes: tuple[str, ...], spec: VectorSpec | None) -> bool:
    if scopes and scopes[0] == variable.unit and variable.unit:
        scopes = scopes[1:]
    own = variable.scope
    if scopes and own[len(own) - len(scopes):] != scopes:
        return False
    if spec is None:
        return True
    if spec.unit is not None and spec.unit != variable.unit:
        return False
    if spec.function is not None and not (variable.function and own[-1] == spec.function):
        return False
    around = own[:-1] if variable.function else own
    return not spec.namespaces or around[len(around) - len(spec.namespaces):] == spec.namespaces


def _choose(path: str, variables: list[Variable]) -> Variable:
    """The one of several fitting variables C would see from file scope (see the module docstring)."""
    placed = [v for v in variables if v.address is not None]
    distinct = {v.address: v for v in reversed(placed or variables)}  # one per address; the first met wins
    if len(distinct) == 1:
        return next(iter(distinct.values()))
    candidates = list(distinct.values())
    fewest = min(len(v.scope) for v in candidates)
    nearest = [v for v in candidates if len(v.scope) == fewest]
    if len(nearest) > 1:
        external = [v for v in nearest if v.external and not v.function]
        nearest = external if len(external) == 1 else nearest
    if len(nearest) == 1:
        return nearest[0]
    raise AmbiguousSymbolError(path, sorted(_distinguishing_names(nearest)))


def _distinguishing_names(variables: list[Variable]) -> list[str]:
    """A qualified name per variable, with the compile unit in front where the scopes alone repeat."""
    names = [v.qualified_name for v in variables]
    return [f"{v.unit}.{name}" if names.count(name) > 1 and v.unit else name for v, name in zip(variables, names)]
