"""Whether a calibration value may be written: limits, monotony, shape, write access.

:func:`check_limits` returns every :class:`LimitViolation` of a value (an empty list: it may be
written); the session refuses a write that has any, before it sends a byte, with
:class:`workbench.errors.LimitsError`. The rules:

- ``read-only``: READ_ONLY, or CALIBRATION_ACCESS NO_CALIBRATION / NOT_IN_MCD_SYSTEM;
- ``kind``: the value is of another kind than the object (a MAP given for a CURVE);
- ``shape``: a VAL_BLK's MATRIX_DIM, an ASCII's length, a CURVE's or MAP's values against its
  axes (values given without axes: against the numbers of points the A2L fixes), an axis longer
  than MAX_AXIS_POINTS (or, when its count is fixed, of another length);
- ``text``: a text where the conversion takes numbers, or a text an enum (verbal conversion) does
  not list (the message lists those it does);
- ``limits``: a number outside LOWER/UPPER (with ``extended=True``: outside EXTENDED_LIMITS, where
  the object has them), or NaN; checked for the values and every axis (against its AXIS_DESCR, the
  AXIS_PTS it refers to, or a CURVE_AXIS' rescale curve's axis, whose points these become). A value within float32 precision (relative 1e-7) of a limit passes;
- ``monotony``: axis points against MONOTONY (MON_INCREASE, MON_DECREASE, STRICT_INCREASE,
  STRICT_DECREASE, MONOTONOUS, STRICT_MON, NOT_MON); an axis without MONOTONY must not decrease.

A violation names the object (and axis), the rule, how many elements break it and the first, and
the limit with its unit. The limit is written in the A2L's display format (its FORMAT's decimals:
``800.00 bar``), the refused value with those decimals and as many more as it takes to differ from
the limit (``800.0004 is above the upper limit 800.00 bar``, not ``800 ... 800``).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.display_format import format_parts
from workbench.a2l.objects import AxisPts, Characteristic
from workbench.calib.cells import index_problem
from workbench.calib.values import CalValue
from workbench.errors import ConversionError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel

__all__ = ["LimitViolation", "check_axis_point", "check_cells", "check_limits"]

_AXES_OF = {"CURVE": 1, "MAP": 2, "CUBOID": 3, "CUBE_4": 4, "CUBE_5": 5}
_ARRAYS = ("VAL_BLK", *_AXES_OF)
_TOLERANCE = 1e-7
_MORE_DECIMALS = 20  # the most decimals a refused value gets beyond its format's to differ from the limit
_FIXED_BELOW = 1e15  # numbers this large are written %g, not with every digit before the point
# a number typed with a unit ("20 mbar"): named as a unit the object does not have, not as "not a number"; a hex
# number (0x10) is no 0 in "x10"
_NUMBER_AND_UNIT = re.compile(r"(?![+-]?0[xX])[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*(?P<unit>[^\d\s.,+-]\S*)")


@dataclass(frozen=True)
class LimitViolation:
    """One rule a value breaks. ``index``: the first element that breaks it (None: the whole value)."""

    name: str
    rule: str  # read-only, kind, shape, text, limits, monotony
    message: str
    index: tuple[int, ...] | None = None

    def __str__(self) -> str:
        return self.message


def check_limits(model: "A2lModel", value: CalValue, *, extended: bool = False) -> list[LimitViolation]:
    """Every violation of ``value`` against its object in ``model`` (see the module docstring).

    :raises UnknownSymbolError: the object does not exist.
    """
    obj = model.object(value.name)
    found: list[LimitViolation] = []
    if not isinstance(obj, (Characteristic, AxisPts)):
        return [LimitViolation(value.name, "kind", f"{value.name} is a {obj.kind}, not a calibration object")]
    kind = obj.type if isinstance(obj, Characteristic) else "AXIS_PTS"
    found += _write_access(obj)
    if value.kind != kind:
        found.append(LimitViolation(obj.name, "kind", f"{obj.name} is a {kind}, the value a {value.kind}"))
        return found
    if kind == "AXIS_PTS":
        found += _axis_rules(model, obj.name, "", np.asarray(value.value), obj, obj.monotony, extended,
                             obj.max_axis_points)
        return found
    if kind == "ASCII":
        capacity = int(np.prod(obj.shape)) if obj.shape else 1
        if not isinstance(value.value, str):
            found.append(LimitViolation(obj.name, "shape", f"{obj.name} is a string, the value {value.value!r}"))
        elif len(value.value) > capacity:
            found.append(LimitViolation(obj.name, "shape", f"{obj.name} holds {capacity} characters, the value has "
                                                           f"{len(value.value)}"))
        return found
    shape = np.shape(value.value)
    if kind == "VALUE" and shape != ():
        found.append(LimitViolation(obj.name, "shape", f"{obj.name} is a VALUE, the value has shape {shape}"))
    if kind == "VAL_BLK" and shape != obj.shape:
        found.append(LimitViolation(obj.name, "shape", f"{obj.name} has shape {obj.shape} (MATRIX_DIM), the value "
                                                       f"{shape}"))
    if kind in _AXES_OF:
        found += _axes_rules(model, obj, value, extended)
    values = np.asarray(value.value, dtype=object)
    texts = _texts(model, obj.name, "", values, obj)
    return found + (texts or _range(model, obj.name, "", values, obj, extended))


def check_cells(model: "A2lModel", name: str, cells: Mapping[tuple[int, ...], Any], *, extended: bool = False,
                shape: tuple[int, ...] | None = None) -> list[LimitViolation]:
    """Every violation of single values written into an array object (VAL_BLK, CURVE, MAP, ..., the points of an
    AXIS_PTS): write access, each index against the shape (``shape``, else where the A2L fixes it), texts and
    limits of each value. A point's order against the other points needs them all: :func:`check_limits` of the
    axis with the points in place.

    :raises UnknownSymbolError: the object does not exist.
    """
    obj = model.object(name)
    if isinstance(obj, AxisPts):
        return _write_access(obj) or [violation for index, value in cells.items()
                                      for violation in check_axis_point(model, name, index, value, extended=extended)]
    if not isinstance(obj, Characteristic) or obj.type not in _ARRAYS:
        kind = obj.type if isinstance(obj, Characteristic) else obj.kind
        return [LimitViolation(name, "kind", f"{name} ({kind}): values are written by cell only into a VAL_BLK, "
                                             "CURVE, MAP, CUBOID or the points of an AXIS_PTS")]
    found = _write_access(obj)
    shape = shape or (obj.shape if obj.type == "VAL_BLK" else _static_shape(model, obj))
    for index, value in cells.items():
        label = f"[{', '.join(str(i) for i in index)}]"
        # the number of points not fixed in the A2L: the indices counted here, their range where the points are read
        problem = index_problem(name, shape, index) if shape else None if len(index) == len(obj.axes) else \
            f"{name} has {len(obj.axes)} axes: give one index for each, not {len(index)}"
        if problem is not None:
            found.append(LimitViolation(name, "shape", problem, index))
            continue
        values = np.asarray(value, dtype=object)
        if values.shape != ():
            found.append(LimitViolation(name, "shape", f"{name}{label}: one value, not {values.shape}", index))
            continue
        found += _texts(model, name, label, values, obj) or _range(model, name, label, values, obj, extended)
    return found


def check_axis_point(model: "A2lModel", name: str, index: tuple[int, ...], value: Any, *,
                     extended: bool = False) -> list[LimitViolation]:
    """What one point of the AXIS_PTS ``name`` breaks on its own (write access, index, limits); its order
    against the other points needs them all: :func:`check_limits` of the axis with the point in place.

    :raises UnknownSymbolError: the object does not exist.
    """
    obj = model.object(name)
    if not isinstance(obj, AxisPts):
        return [LimitViolation(name, "kind", f"{name} is no AXIS_PTS")]
    label = f"[{', '.join(str(i) for i in index)}]"
    problem = index_problem(name, (obj.max_axis_points,), index, "points at most")
    if problem is not None:
        return [LimitViolation(name, "shape", problem, index)]
    values = np.asarray(value, dtype=object)
    if values.shape != ():
        return [LimitViolation(name, "shape", f"{name}{label}: one value, not {values.shape}", index)]
    return _write_access(obj) + (_texts(model, name, label, values, obj)
                                 or _range(model, name, label, values, obj, extended))


def _write_access(obj: Characteristic | AxisPts) -> list[LimitViolation]:
    if obj.writable:
        return []
    why = "READ_ONLY" if obj.read_only else f"CALIBRATION_ACCESS {obj.calibration_access}"
    return [LimitViolation(obj.name, "read-only", f"{obj.name} cannot be written ({why})")]


def _texts(model: "A2lModel", name: str, label: str, values: np.ndarray, source) -> list[LimitViolation]:
    """The texts among ``values`` that the conversion of ``source`` cannot take (numbers pass)."""
    flat = values.reshape(-1).tolist()
    texts = [v for v in flat if isinstance(v, str)]
    if not texts:
        return []
    conversion = model.conversion(source)
    if conversion.verbal:
        for text in texts:
            try:
                known = conversion.text_of(text)  # a text that differs from one of the table only in case is that one
            except ConversionError as exc:  # several do
                return [LimitViolation(name, "text", f"{name}{label}: {str(exc).partition(': ')[2]}")]
            if known is None:
                return [LimitViolation(name, "text", f"{name}{label}: {text!r} is not one of its values "
                                       f"({conversion.allowed_shown})")]
        return []
    unit = model.unit_of(source)
    decimals = _decimals(model, source)
    lower, upper = (_number(limit, decimals) for limit in (source.lower_limit, source.upper_limit))
    span = f"a value from {lower} to {upper}{' ' + unit if unit else ''}"
    if (typed := _NUMBER_AND_UNIT.fullmatch(texts[0].strip())) and typed["unit"] != unit:
        return [LimitViolation(name, "text", f"{name}{label}: {texts[0]!r} is in {typed['unit']}, "
                                             f"{name} in {unit or 'no unit'} (no unit conversion: give {span})")]
    return [LimitViolation(name, "text", f"{name}{label}: {texts[0]!r} is not a number ({span})")]


def _static_shape(model: "A2lModel", obj: Characteristic) -> tuple[int, ...] | None:
    """The numbers of points the A2L fixes for ``obj``'s axes (None: one of them lies in ECU memory)."""
    from workbench.calib.layout import object_layout

    layout = object_layout(model, obj)
    return None if layout.needs_counts else layout.resolve().shape


def _axes_rules(model: "A2lModel", obj: Characteristic, value: CalValue, extended: bool) -> list[LimitViolation]:
    found = []
    if not value.axes:  # the values alone, the axes as they are: their shape is known when the A2L fixes it
        shape = _static_shape(model, obj)
        if shape is not None and np.shape(value.value) != shape:
            return [LimitViolation(obj.name, "shape", f"{obj.name} has shape {shape}, the value "
                                                      f"{np.shape(value.value)}")]
        return []
    if len(value.axes) != len(obj.axes):
        return [LimitViolation(obj.name, "shape", f"{obj.name} has {len(obj.axes)} axes, the value {len(value.axes)}")]
    lengths = tuple(len(np.asarray(axis.values).reshape(-1)) for axis in value.axes)
    if value.axes and np.shape(value.value) != lengths:
        found.append(LimitViolation(obj.name, "shape", f"{obj.name}: the values have shape {np.shape(value.value)}, "
                                                       f"the axes {lengths}"))
    for descr, axis in zip(obj.axes, value.axes):
        points = np.asarray(axis.values).reshape(-1)
        label = f" axis {descr.axis}"
        fixed = descr.fix_axis_points
        if fixed is not None and len(points) != len(fixed):
            found.append(LimitViolation(obj.name, "shape", f"{obj.name}{label} is fixed at {len(fixed)} points, the "
                                                           f"value has {len(points)}"))
        if descr.attribute in ("COM_AXIS", "RES_AXIS") and descr.axis_pts_ref:
            source = model.resolve(descr, "axis_pts_ref", "AXIS_PTS", f"CHARACTERISTIC {obj.name}")
            found += _axis_rules(model, obj.name, f"{label} ({source.name})", points, source, source.monotony,
                                 extended, min(descr.max_axis_points, source.max_axis_points) or source.max_axis_points)
        elif descr.attribute == "CURVE_AXIS" and descr.curve_axis_ref:
            # the points become the rescale curve's axis (calib.codec); an index it never reaches has none (NaN)
            curve = model.resolve(descr, "curve_axis_ref", "CHARACTERISTIC", f"CHARACTERISTIC {obj.name}")
            reached = [p for p in points.tolist() if not (isinstance(p, float) and p != p)]
            if curve.axes:
                found += _axis_rules(model, obj.name, f"{label} ({curve.name})", np.asarray(reached, dtype=object),
                                     curve.axes[0], curve.axes[0].monotony, extended, descr.max_axis_points)
        elif descr.attribute != "FIX_AXIS":
            found += _axis_rules(model, obj.name, label, points, descr, descr.monotony, extended,
                                 descr.max_axis_points)
    return found


def _axis_rules(model: "A2lModel", name: str, label: str, points: np.ndarray, limits_of, monotony: str | None,
                extended: bool, max_points: int) -> list[LimitViolation]:
    texts = _texts(model, name, label, np.asarray(points, dtype=object), limits_of)
    if texts:
        return texts
    points = np.asarray(points, dtype=np.float64).reshape(-1)
    found = []
    if max_points and len(points) > max_points:
        found.append(LimitViolation(name, "shape", f"{name}{label}: {len(points)} points, MAX_AXIS_POINTS is {max_points}"))
    found += _range(model, name, label, points.astype(object), limits_of, extended)
    found += _monotony(name, label, points, monotony)
    return found


def _range(model: "A2lModel", name: str, label: str, values: np.ndarray, limits_of, extended: bool
           ) -> list[LimitViolation]:
    """Violations of LOWER/UPPER (or EXTENDED_LIMITS) by the numbers among ``values`` (texts pass), the limits
    in the display format of ``limits_of`` (an object or axis) and its unit."""
    lower, upper = limits_of.lower_limit, limits_of.upper_limit
    which = "limits"
    if extended and getattr(limits_of, "extended_limits", None):
        lower, upper = limits_of.extended_limits
        which = "extended limits"
    flat = values.reshape(-1)
    numbers = np.array([not isinstance(v, str) for v in flat.tolist()], dtype=bool)
    if not numbers.any():
        return []
    numeric = np.full(len(flat), np.nan)
    numeric[numbers] = [float(v) for v in flat[numbers].tolist()]
    found = []
    checks = (("below the lower", numbers & (numeric < lower) & ~_close(numeric, lower), lower),
              ("above the upper", numbers & (numeric > upper) & ~_close(numeric, upper), upper),
              ("not a number:", numbers & np.isnan(numeric), None))
    for words, bad, limit in checks:
        if not bad.any():
            continue
        first = int(np.flatnonzero(bad)[0])
        index = tuple(int(i) for i in np.unravel_index(first, values.shape)) if values.shape else None
        where = f" at {list(index)}" if index is not None else ""
        count = int(bad.sum())
        many = f"{count} values, first " if count > 1 else ""
        if limit is None:
            message = f"{name}{label}: {many}NaN{where} is not a number"
        else:
            word = "lower" if "lower" in words else "upper"
            unit = model.unit_of(limits_of)
            shown, limit_text = _beside_limit(float(numeric[first]), limit, _decimals(model, limits_of))
            message = (f"{name}{label}: {many}{shown}{where} is {words.split()[0]} the {word} "
                       f"{which[:-1]} {limit_text}{' ' + unit if unit else ''}")
        found.append(LimitViolation(name, "limits", message, index))
    return found


def _decimals(model: "A2lModel", limits_of) -> int | None:
    """The decimals of the display format of an object or axis (FORMAT, else its COMPU_METHOD's)."""
    return format_parts(model.format_of(limits_of))[1]


def _number(value: float, decimals: int | None) -> str:
    """``value`` with ``decimals`` (``%g`` without, and for numbers too large to write out)."""
    if decimals is None or not abs(value) < _FIXED_BELOW:
        return f"{value:g}"
    return f"{value:.{decimals}f}"


def _beside_limit(value: float, limit: float, decimals: int | None) -> tuple[str, str]:
    """(the value, the limit) as a refusal shows them: the limit in the A2L's format, the value in it too with as
    many more digits as it takes to read other than the limit (800.0004 beside 800.00, 1e-10 beside 0)."""
    limit_text = _number(limit, decimals)
    if decimals is None or not abs(value) < _FIXED_BELOW:
        candidates = (f"{value:.{digits}g}" for digits in range(6, 18))
    else:
        candidates = (f"{value:.{places}f}" for places in range(decimals, decimals + _MORE_DECIMALS))
    shown = next((text for text in candidates if float(text) != float(limit_text)), repr(value))
    return shown, limit_text


def _close(values: np.ndarray, limit: float) -> np.ndarray:
    return np.abs(values - limit) <= _TOLERANCE * max(abs(limit), 1e-30)


_MONOTONY = {  # name -> (allowed step signs test)
    "MON_INCREASE": lambda d: d >= 0, "MON_DECREASE": lambda d: d <= 0,
    "STRICT_INCREASE": lambda d: d > 0, "STRICT_DECREASE": lambda d: d < 0,
}


def _monotony(name: str, label: str, points: np.ndarray, monotony: str | None) -> list[LimitViolation]:
    rule = monotony or "MON_INCREASE"
    steps = np.diff(points)
    if rule == "NOT_MON" or not len(steps) or np.isnan(steps).any():
        return []
    if rule in ("MONOTONOUS", "STRICT_MON"):
        strict = rule == "STRICT_MON"
        ok = (steps > 0).all() or (steps < 0).all() if strict else (steps >= 0).all() or (steps <= 0).all()
        if ok:
            return []
        return [LimitViolation(name, "monotony", f"{name}{label}: the points are not {rule} ({list(points)})")]
    test = _MONOTONY.get(rule)
    if test is None:
        return [LimitViolation(name, "monotony", f"{name}{label}: unknown MONOTONY {rule}")]
    bad = ~test(steps)
    if not bad.any():
        return []
    first = int(np.flatnonzero(bad)[0])
    return [LimitViolation(name, "monotony", f"{name}{label}: points {first} and {first + 1} ({points[first]:g}, "
                                             f"{points[first + 1]:g}) break {rule}", (first + 1,))]
