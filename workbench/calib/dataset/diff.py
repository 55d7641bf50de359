"""Compare two datasets object by object: what only one holds, what changed (element by element), what is equal.

An object is *shape-changed* when its kind, its value's shape or its axes' lengths differ (its
elements are then not compared), *changed* when a value, an axis point, a unit or an axis's
kind or name differs, else *equal*. Numbers compare by value (``1`` equals ``1.0``, NaN equals
NaN); with a tolerance, two numbers are equal when ``|b - a| <= max(abs_tol, rel_tol * max(|a|, |b|))``.
Long names, comments and history are not compared.

The text (:meth:`DatasetDiff.to_text`) shows values as ``cal get`` does: a number with its unit (the
COMPU_METHOD's, as the dataset or the ECU's A2L gives it), an enum's text bare; a text is quoted
only where bare it could not be told apart (empty, blanks at its ends, or looking like the other side).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from workbench.calib.dataset.numbers import format_number, shown_difference, shown_value
from workbench.calib.values import CalValue

__all__ = ["DatasetDiff", "ElementDiff", "ObjectDiff", "diff_datasets"]

ONLY_IN_A, ONLY_IN_B, SHAPE_CHANGED, CHANGED, EQUAL = "only-in-a", "only-in-b", "shape-changed", "changed", "equal"
STATUSES = (ONLY_IN_A, ONLY_IN_B, SHAPE_CHANGED, CHANGED, EQUAL)
_AXIS_LETTERS = "xyz"


@dataclass(frozen=True)
class ElementDiff:
    """One difference inside an object: ``where`` is ``value``, ``value[3]``, ``value[2, 1]``, ``x[4]``,
    ``unit``, ``x.kind``, ``shape`` ...; ``at`` the axis points of a value element; ``delta`` is
    ``b - a`` for two numbers; ``units`` the units ``a`` and ``b`` are in (``""``: none, or not a physical
    value), which are context, not part of the difference (not compared)."""

    where: str
    a: object
    b: object
    delta: int | float | None = None
    at: tuple = ()
    units: tuple[str, str] = field(default=("", ""), compare=False)


@dataclass(frozen=True)
class ObjectDiff:
    name: str
    status: str
    a: CalValue | None = None
    b: CalValue | None = None
    differences: tuple[ElementDiff, ...] = ()


@dataclass
class DatasetDiff:
    """The comparison of dataset ``a`` with dataset ``b``: one :class:`ObjectDiff` per name (a's order, then b's)."""

    a_label: str
    b_label: str
    objects: list[ObjectDiff] = field(default_factory=list)
    abs_tol: float = 0.0
    rel_tol: float = 0.0

    @property
    def equal(self) -> bool:
        return all(o.status == EQUAL for o in self.objects)

    def counts(self) -> dict[str, int]:
        return {status: sum(o.status == status for o in self.objects) for status in STATUSES}

    def reversed(self) -> "DatasetDiff":
        """The same comparison seen from the other side: B against A (B - A becomes A - B)."""
        swap = {ONLY_IN_A: ONLY_IN_B, ONLY_IN_B: ONLY_IN_A}
        objects = [ObjectDiff(o.name, swap.get(o.status, o.status), o.b, o.a,
                              tuple(ElementDiff(d.where, d.b, d.a, None if d.delta is None else -d.delta, d.at, d.units[::-1])
                                    for d in o.differences)) for o in self.objects]
        return DatasetDiff(self.b_label, self.a_label, objects, self.abs_tol, self.rel_tol)

    def to_dict(self) -> dict:
        """Every object with its status and differences, JSON-ready (NaN and infinities as "NaN", "Inf", "-Inf")."""
        return {
            "a": self.a_label, "b": self.b_label, "equal": self.equal,
            "tolerance": {"absolute": self.abs_tol, "relative": self.rel_tol},
            "counts": self.counts(),
            "objects": [{
                "name": o.name, "status": o.status,
                "kind": {"a": o.a.kind if o.a else None, "b": o.b.kind if o.b else None},
                "unit": {"a": o.a.unit if o.a else None, "b": o.b.unit if o.b else None},
                "differences": [{"where": d.where, "a": _json(d.a), "b": _json(d.b), "delta": _json(d.delta),
                                 "at": [_json(p) for p in d.at], "unit": {"a": d.units[0], "b": d.units[1]}}
                                for d in o.differences],
            } for o in self.objects],
        }

    def to_text(self, *, show_equal: bool = False, columns: tuple[str, str] = ("A", "B"),
                decimals: Callable[[str, str], int | None] | None = None) -> str:
        """A table, one line per difference, and a summary line; ``columns`` heads the two sides' columns;
        ``decimals(name, where)``: the decimals ``cal get`` shows that element with (the A2L's FORMAT, e.g.
        :func:`workbench.a2l.model.value_decimals`), None for the shortest text."""
        places = decimals or (lambda name, where: None)
        a, b = columns
        rows = [("name", "status", "where", a, b, f"{b} - {a}")]
        for o in self.objects:
            if o.status == EQUAL and not show_equal:
                continue
            if o.status in (ONLY_IN_A, ONLY_IN_B, EQUAL):
                shown = places(o.name, "value")
                rows.append((o.name, o.status, "", _describe(o.a, shown), _describe(o.b, shown), ""))
                continue
            for d in o.differences:
                at = zip(_AXIS_LETTERS, d.at, (axis.unit for axis in o.a.axes))
                where = d.where + (f" ({', '.join(f'{l} {_show(p, unit, places(o.name, l))}' for l, p, unit in at)})"
                                   if d.at else "")
                rows.append((o.name, o.status, where, *_shown(d, places(o.name, d.where))))
        counts = self.counts()
        objects = f"{len(self.objects)} object{'' if len(self.objects) == 1 else 's'}"
        summary = (f"{objects}: {counts[EQUAL]} equal, {counts[CHANGED]} changed, {counts[SHAPE_CHANGED]} shape changed, "
                   f"{counts[ONLY_IN_A]} only in A, {counts[ONLY_IN_B]} only in B")
        header = f"A: {self.a_label}\nB: {self.b_label}"
        if len(rows) == 1:
            return f"{header}\n{summary}"
        widths = [max(len(r[i]) for r in rows) for i in range(6)]
        table = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
        return "\n".join([header, *table, summary])


def diff_datasets(a, b, *, abs_tol: float = 0.0, rel_tol: float = 0.0, a_label: str | None = None,
                  b_label: str | None = None) -> DatasetDiff:
    """Compare dataset (or name -> CalValue mapping) ``a`` with ``b``; tolerances as in the module docstring."""
    result = DatasetDiff(a_label or getattr(a, "source", None) or "A", b_label or getattr(b, "source", None) or "B",
                         abs_tol=abs_tol, rel_tol=rel_tol)
    for name, value in a.items():
        other = b.get(name)
        result.objects.append(ObjectDiff(name, ONLY_IN_A, a=value) if other is None
                              else _compare(name, value, other, abs_tol, rel_tol))
    result.objects += [ObjectDiff(name, ONLY_IN_B, b=value) for name, value in b.items() if name not in a]
    return result


def _compare(name: str, a: CalValue, b: CalValue, abs_tol: float, rel_tol: float) -> ObjectDiff:
    shape = _shape_differences(a, b)
    if shape:
        return ObjectDiff(name, SHAPE_CHANGED, a, b, tuple(shape))
    found: list[ElementDiff] = []
    if a.unit != b.unit:
        found.append(ElementDiff("unit", a.unit, b.unit))
    for letter, axis_a, axis_b in zip(_AXIS_LETTERS, a.axes, b.axes):
        for attribute in ("kind", "name", "unit"):
            if getattr(axis_a, attribute) != getattr(axis_b, attribute):
                found.append(ElementDiff(f"{letter}.{attribute}", getattr(axis_a, attribute), getattr(axis_b, attribute)))
        units = (axis_a.unit, axis_b.unit)
        for i, (pa, pb) in enumerate(zip(map(_plain, axis_a.values), map(_plain, axis_b.values))):
            if not _same(pa, pb, abs_tol, rel_tol):
                found.append(ElementDiff(f"{letter}[{i}]", pa, pb, _delta(pa, pb), units=units))
    units = (a.unit, b.unit)
    if isinstance(a.value, np.ndarray):
        points = [axis.values for axis in a.axes]
        for index in np.ndindex(a.value.shape):
            va, vb = _plain(a.value[index]), _plain(b.value[index])
            if not _same(va, vb, abs_tol, rel_tol):
                at = tuple(_plain(p[i]) for p, i in zip(points, index))
                found.append(ElementDiff(f"value[{', '.join(map(str, index))}]", va, vb, _delta(va, vb), at, units))
    elif not _same(a.value, b.value, abs_tol, rel_tol):
        found.append(ElementDiff("value", a.value, b.value, _delta(a.value, b.value), units=units))
    return ObjectDiff(name, CHANGED if found else EQUAL, a, b, tuple(found))


def _shape_differences(a: CalValue, b: CalValue) -> list[ElementDiff]:
    if a.kind != b.kind:
        return [ElementDiff("kind", a.kind, b.kind)]
    found = []
    if a.shape != b.shape:
        found.append(ElementDiff("shape", a.shape, b.shape))
    if len(a.axes) != len(b.axes):
        found.append(ElementDiff("axes", len(a.axes), len(b.axes)))
    for letter, axis_a, axis_b in zip(_AXIS_LETTERS, a.axes, b.axes):
        if len(axis_a.values) != len(axis_b.values):
            found.append(ElementDiff(f"{letter} points", len(axis_a.values), len(axis_b.values)))
    return found


def _plain(value):
    """A numpy scalar as the Python number (or str) it holds."""
    return value.item() if isinstance(value, np.generic) else value


def _is_number(value) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def _same(a, b, abs_tol: float, rel_tol: float) -> bool:
    if _is_number(a) and _is_number(b):
        fa, fb = float(a), float(b)
        if math.isnan(fa) or math.isnan(fb):
            return math.isnan(fa) and math.isnan(fb)
        if a == b:
            return True
        if math.isinf(fa) or math.isinf(fb):
            return False
        return abs(fb - fa) <= max(abs_tol, rel_tol * max(abs(fa), abs(fb)))
    return type(a) is type(b) and a == b if isinstance(a, str) or isinstance(b, str) else a == b


def _delta(a, b):
    if not (_is_number(a) and _is_number(b)):
        return None
    if isinstance(a, (int, np.integer)) and isinstance(b, (int, np.integer)):
        return int(b) - int(a)
    return float(b) - float(a)


def _describe(value: CalValue | None, places: int | None = None) -> str:
    if value is None:
        return ""
    if value.kind in ("VALUE", "ASCII"):
        return _show(value.value, value.unit, places)
    return f"{value.kind} {' x '.join(map(str, value.shape))}"


def _show(value, unit: str = "", places: int | None = None, *, exact: bool = False) -> str:
    """A value as ``cal get`` shows it: a number with its unit (``places`` decimals when known), a text bare
    (quoted when bare it would be empty or lose its blanks, or ``exact``); ``exact``: every digit of a number."""
    if isinstance(value, str):
        return value if value and value == value.strip() and not exact else repr(value)
    if isinstance(value, tuple):
        return "(" + ", ".join(map(str, value)) + ")"
    if _is_number(value):
        return (format_number(value) if exact else shown_value(value, places)) + (f" {unit}" if unit else "")
    return str(value)


def _shown(difference: ElementDiff, places: int | None = None) -> tuple[str, str, str]:
    """A, B and B - A as the table shows them: numbers with ``places`` decimals or float32 values in their short
    text, texts bare, unless that hides the difference (then every digit, texts quoted); B - A in the unit both
    share, with ``places`` decimals unless they round it to zero."""
    (unit_a, unit_b), delta = difference.units, difference.delta
    a, b = _show(difference.a, unit_a, places), _show(difference.b, unit_b, places)
    exact = a == b
    if exact:
        a, b = _show(difference.a, unit_a, exact=True), _show(difference.b, unit_b, exact=True)
    if delta is None:
        return a, b, ""
    text = format_number(delta) if exact else shown_difference(difference.a, difference.b)
    if not exact and isinstance(delta, float) and math.isfinite(delta):  # as the values: cal get's decimals
        rounded = shown_value(delta, places)
        text = rounded if float(rounded) != 0 and (places is not None or float(text).is_integer()) else text
    return a, b, _signed(text) + (f" {unit_a}" if unit_a and unit_a == unit_b else "")


def _signed(text: str) -> str:
    return text if text.startswith("-") or text == "NaN" else f"+{text}"


def _json(value):
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else format_number(value)
    if isinstance(value, tuple):
        return list(value)
    return value
