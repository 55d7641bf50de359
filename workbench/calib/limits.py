"""Whether a calibration value may be written: limits, monotony, shape, write access.

:func:`check_limits` returns every :class:`LimitViolation` of a value (an empty list: it may be
written); the session refuses a write that has any, before it sends a byte, with
:class:`workbench.errors.LimitsError`. The rules:

- ``read-only``: READ_ONLY, or CALIBRATION_ACCESS NO_CALIBRATION / NOT_IN_MCD_SYSTEM;
- ``kind``: the value is of another kind than the object (a MAP given for a CURVE);
- ``shape``: a VAL_BLK's MATRIX_DIM, an ASCII's length, a CURVE's or MAP's values against its
  axes, an axis longer than MAX_AXIS_POINTS (or, when its count is fixed, of another length);
- ``limits``: a number outside LOWER/UPPER (with ``extended=True``: outside EXTENDED_LIMITS, where
  the object has them), or NaN; checked for the values and every axis (against its AXIS_DESCR, or
  the AXIS_PTS it refers to). A value within float32 precision (relative 1e-7) of a limit passes;
- ``monotony``: axis points against MONOTONY (MON_INCREASE, MON_DECREASE, STRICT_INCREASE,
  STRICT_DECREASE, MONOTONOUS, STRICT_MON, NOT_MON); an axis without MONOTONY must not decrease.

A violation names the object (and axis), the rule, how many elements break it and the first.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from workbench.a2l.objects import AxisPts, Characteristic
from workbench.calib.values import CalValue

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel

__all__ = ["LimitViolation", "check_limits"]

_AXES_OF = {"CURVE": 1, "MAP": 2, "CUBOID": 3, "CUBE_4": 4, "CUBE_5": 5}
_TOLERANCE = 1e-7


@dataclass(frozen=True)
class LimitViolation:
    """One rule a value breaks. ``index``: the first element that breaks it (None: the whole value)."""

    name: str
    rule: str  # read-only, kind, shape, limits, monotony
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
    if not obj.writable:
        why = "READ_ONLY" if obj.read_only else f"CALIBRATION_ACCESS {obj.calibration_access}"
        found.append(LimitViolation(obj.name, "read-only", f"{obj.name} cannot be written ({why})"))
    if value.kind != kind:
        found.append(LimitViolation(obj.name, "kind", f"{obj.name} is a {kind}, the value a {value.kind}"))
        return found
    if kind == "AXIS_PTS":
        found += _axis_rules(obj.name, "", np.asarray(value.value), obj, obj.monotony, extended, obj.max_axis_points)
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
    found += _range(obj.name, "", np.asarray(value.value, dtype=object), obj, extended)
    return found


def _axes_rules(model: "A2lModel", obj: Characteristic, value: CalValue, extended: bool) -> list[LimitViolation]:
    found = []
    if value.axes and len(value.axes) != len(obj.axes):
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
            found += _axis_rules(obj.name, f"{label} ({source.name})", points, source, source.monotony, extended,
                                 min(descr.max_axis_points, source.max_axis_points) or source.max_axis_points)
        elif descr.attribute != "FIX_AXIS":
            found += _axis_rules(obj.name, label, points, descr, descr.monotony, extended, descr.max_axis_points)
    return found


def _axis_rules(name: str, label: str, points: np.ndarray, limits_of, monotony: str | None, extended: bool,
                max_points: int) -> list[LimitViolation]:
    points = np.asarray(points, dtype=np.float64).reshape(-1)
    found = []
    if max_points and len(points) > max_points:
        found.append(LimitViolation(name, "shape", f"{name}{label}: {len(points)} points, MAX_AXIS_POINTS is {max_points}"))
    found += _range(name, label, points.astype(object), limits_of, extended)
    found += _monotony(name, label, points, monotony)
    return found


def _range(name: str, label: str, values: np.ndarray, limits_of, extended: bool) -> list[LimitViolation]:
    """Violations of LOWER/UPPER (or EXTENDED_LIMITS) by the numbers among ``values`` (texts pass)."""
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
            message = (f"{name}{label}: {many}{numeric[first]:g}{where} is {words.split()[0]} the {word} "
                       f"{which[:-1]} {limit:g}")
        found.append(LimitViolation(name, "limits", message, index))
    return found


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
