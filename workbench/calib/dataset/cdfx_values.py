"""From the SW-INSTANCEs of a CDFX file to calibration values: categories, shapes, axes.

:mod:`~workbench.calib.dataset.cdfx_read` walks the XML into :class:`Instance` s; :func:`add_instances`
turns each into a :class:`~workbench.calib.values.CalValue`:

* VALUE, DEPENDENT_VALUE, BOOLEAN: one ``V`` or ``VT``; ASCII: one ``VT``;
* VAL_BLK and VALUE_ARRAY: an array of ``SW-ARRAYSIZE`` (x first), or of the shape of the VG groups;
* CURVE, MAP, CUBOID, CUBE_4, CUBE_5: one SW-AXIS-CONT per dimension, values x fastest (the
  innermost VG runs along x, one VG per point of each further axis);
* COM_AXIS, RES_AXIS, CURVE_AXIS without axes of their own: the axis points (AXIS_PTS); a RES_AXIS
  of rescale pairs (VG groups of two) is kept as a ``(2, n)`` VAL_BLK of category RES_AXIS;
* any other category is read by the shape of its values (a note says so).

An axis that references another instance without listing its points takes them from that
instance; a CURVE_AXIS computes them from its rescale curve (point k where the curve gives index k,
:func:`~workbench.calib.codec.curve_axis_points`). Left out with a note (the file is still read): an
axis whose points the file does not give (a RES_AXIS computed from its reference, a reference to an
instance the file does not hold: computing or finding them needs the A2L), variant-coded values,
an instance without values. Refused with a :class:`~workbench.errors.DatasetParseError`: counts and shapes that do
not match, a text where a number belongs.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from workbench.calib.codec import curve_axis_points
from workbench.calib.dataset.model import CsFlag, Dataset, HistoryEntry, InstancePart, ObjectInfo
from workbench.calib.dataset.numbers import NumberError, scalar, to_array
from workbench.calib.values import Axis, CalValue
from workbench.errors import DatasetParseError
from workbench.findings import Finding, Severity

__all__ = ["ARRAY_CATEGORIES", "AXIS_CATEGORIES", "AXIS_KINDS", "CATEGORIES", "GRID_CATEGORIES",
           "SCALAR_CATEGORIES", "AxisCont", "Instance", "add_instances"]

SCALAR_CATEGORIES = ("VALUE", "DEPENDENT_VALUE", "BOOLEAN")
ARRAY_CATEGORIES = ("VAL_BLK", "VALUE_ARRAY")
GRID_CATEGORIES = ("CURVE", "MAP", "CUBOID", "CUBE_4", "CUBE_5")  # 1 to 5 axes
AXIS_CATEGORIES = ("COM_AXIS", "RES_AXIS", "CURVE_AXIS")
AXIS_KINDS = ("STD_AXIS", "FIX_AXIS") + AXIS_CATEGORIES
CONTAINER_CATEGORIES = ("STRUCTURE", "UNION")  # and every *_ARRAY: instances that hold instances
CATEGORIES = SCALAR_CATEGORIES + ("ASCII",) + ARRAY_CATEGORIES + GRID_CATEGORIES + AXIS_CATEGORIES + ("BLOB",)


@dataclass
class AxisCont:
    line: int
    kind: str = ""
    unit: str = ""
    ref: str | None = None
    size: int | None = None
    points: list | None = None


@dataclass
class Instance:
    """One SW-INSTANCE with values, as read, before references between instances are resolved."""

    name: str  # ``outer.member``, ``outer[2]`` for nested instances
    line: int
    container: tuple[InstancePart, ...] = ()
    category: str = ""
    long_name: str = ""
    display_name: str = ""
    feature: str = ""
    model_link: str = ""
    unit: str = ""
    size: list[int] | None = None
    values: list | None = None
    value_line: int = 0
    value_runs: tuple[tuple[int, int], ...] = ()  # the lines of its V/VT values, as ObjectInfo keeps them
    axes: list[AxisCont] = field(default_factory=list)
    history: tuple[HistoryEntry, ...] = ()
    flags: tuple[CsFlag, ...] = ()
    comments: tuple[str, ...] = ()
    left_out: str = ""  # why it cannot be read (variant-coded ...): a note instead of a value


class _LeftOut(Exception):
    def __init__(self, reason: str, line: int):
        super().__init__(reason)
        self.reason, self.line = reason, line


def add_instances(dataset: Dataset, instances: dict[str, Instance], path: str) -> None:
    """Add the value of every instance to ``dataset``, in file order; what cannot be read goes to its notes.

    :raises DatasetParseError: an instance whose values do not match its category, size or axes.
    """
    builder = _Builder(dataset, instances, path)
    for instance in instances.values():
        builder.add(instance)


class _Builder:
    def __init__(self, dataset: Dataset, instances: dict[str, Instance], path: str):
        self.dataset, self.instances, self.path = dataset, instances, path

    def note(self, kind: str, instance: Instance, message: str, line: int = 0) -> None:
        self.dataset.notes.append(Finding(kind, instance.name, f"{instance.name}: {message}", self.path,
                                          line or instance.line, severity=Severity.WARNING))

    def fail(self, instance: Instance, message: str, line: int = 0) -> DatasetParseError:
        return DatasetParseError(f"{instance.name}: {message}", self.path, line or instance.line)

    def add(self, instance: Instance) -> None:
        try:
            if instance.left_out:
                raise _LeftOut(instance.left_out, instance.line)
            value = self.value(instance)
        except _LeftOut as left:
            self.note("left-out", instance, f"{left.reason}; left out", left.line)
            return
        except NumberError as exc:
            raise self.fail(instance, str(exc)) from None
        info = ObjectInfo(display_name=instance.display_name, functions=(instance.feature,) if instance.feature else (),
                          comments=instance.comments, history=instance.history, flags=instance.flags,
                          category=instance.category, line=instance.line, value_line=instance.value_line,
                          value_runs=instance.value_runs,
                          container=instance.container, model_link=instance.model_link)
        self.dataset.add(value, info)

    def value(self, instance: Instance) -> CalValue:
        category, items = instance.category, instance.values
        common = {"unit": instance.unit, "comment": instance.long_name}
        if category in SCALAR_CATEGORIES + ("ASCII",):
            if len(items) != 1 or isinstance(items[0], list):
                raise self.fail(instance, f"a {category} holds one value, found {len(_flat(items))}")
            if category == "ASCII":
                if not isinstance(items[0], str):
                    raise self.fail(instance, "an ASCII holds its text in <VT>")
                return CalValue(instance.name, "ASCII", items[0], comment=instance.long_name)
            return CalValue(instance.name, "VALUE", _item(items[0]), **common)
        if category in ARRAY_CATEGORIES:
            return CalValue(instance.name, "VAL_BLK", self.block(instance), **common)
        if category in AXIS_CATEGORIES and not instance.axes:
            if category == "RES_AXIS" and items and all(isinstance(i, list) and len(i) == 2 for i in items):
                return CalValue(instance.name, "VAL_BLK", self.block(instance), **common)  # rescale pairs
            if any(isinstance(i, list) for i in items):
                raise self.fail(instance, "axis points in VG groups: only a RES_AXIS holds groups (of two)")
            return CalValue(instance.name, "AXIS_PTS", to_array(items), **common)
        if category in GRID_CATEGORIES or (category == "CURVE_AXIS" and len(instance.axes) == 1):
            kind = "CURVE" if category == "CURVE_AXIS" else category
            expected = GRID_CATEGORIES.index(kind) + 1
            if len(instance.axes) != expected:
                raise self.fail(instance, f"a {category} has {expected} SW-AXIS-CONT, found {len(instance.axes)}")
            return self.grid_value(instance, kind, common)
        return self.by_shape(instance, common)

    def by_shape(self, instance: Instance, common: dict) -> CalValue:
        """A category this reader does not know (or BLOB, a container with values): its kind from its values."""
        items, axes = instance.values, instance.axes
        if axes:
            if len(axes) > len(GRID_CATEGORIES):
                raise self.fail(instance, f"{len(axes)} SW-AXIS-CONT (at most {len(GRID_CATEGORIES)} axes)")
            kind = GRID_CATEGORIES[len(axes) - 1]
            value = self.grid_value(instance, kind, common)
        elif len(items) == 1 and not isinstance(items[0], list):
            kind = "VALUE"
            value = CalValue(instance.name, kind, _item(items[0]), **common)
        else:
            kind = "VAL_BLK"
            value = CalValue(instance.name, kind, self.block(instance), **common)
        if instance.category not in CATEGORIES and instance.category not in CONTAINER_CATEGORIES \
                and not instance.category.endswith("_ARRAY"):
            what = f"category {instance.category!r} is not one of CDF 2.1's" if instance.category else "no CATEGORY"
            self.note("read-as", instance, f"{what}; read as a {kind} by its values")
        return value

    def grid_value(self, instance: Instance, kind: str, common: dict) -> CalValue:
        axes = tuple(self.axis(instance, a) for a in instance.axes)
        shape = tuple(len(a.values) for a in axes)
        return CalValue(instance.name, kind, self.grid(instance, shape), axes=axes, **common)

    def block(self, instance: Instance) -> np.ndarray:
        shape = tuple(instance.size) if instance.size else _nested_shape(instance.values)
        if shape is None:
            raise self.fail(instance, "VG groups of different lengths and no SW-ARRAYSIZE")
        return self.grid(instance, shape)

    def grid(self, instance: Instance, shape: tuple[int, ...]) -> np.ndarray:
        """The values in ``shape`` (x first), read x fastest; VG groups must match the shape."""
        items = instance.values
        flat = _flat(items)
        if len(flat) != int(np.prod(shape)):
            raise self.fail(instance, f"{len(flat)} values for the shape {' x '.join(map(str, shape))}"
                                      f"{_odd_group(items)}")
        if any(isinstance(i, list) for i in items) and _squeezed(_nested_shape(items)) != _squeezed(shape):
            rows = "one VG per Y point holding the values along X" if len(shape) == 2 else "innermost VGs along x"
            raise self.fail(instance, f"its VG groups do not make {' x '.join(map(str, shape))} values ({rows})")
        return to_array(flat).reshape(shape, order="F").copy()

    def axis(self, instance: Instance, axis: AxisCont) -> Axis:
        kind = axis.kind
        referenced = self.instances.get(axis.ref) if axis.ref else None
        if not kind:
            kind = referenced.category if referenced and referenced.category in AXIS_CATEGORIES else "STD_AXIS"
        points = axis.points
        if points is None:
            points = self.referenced_points(instance, axis, kind, referenced)
        if axis.size is not None and axis.size != len(points):
            raise self.fail(instance, f"the axis's SW-ARRAYSIZE says {axis.size}, it has {len(points)} points", axis.line)
        unit = axis.unit or (referenced.unit if referenced is not None and axis.points is None else "")
        return Axis(to_array(points), kind=kind, name=axis.ref, unit=unit)

    def referenced_points(self, instance: Instance, axis: AxisCont, kind: str, referenced: Instance | None) -> list:
        """The points of an axis that lists none, from the instance it references."""
        if kind == "CURVE_AXIS":
            return self.rescaled_points(instance, axis, referenced)
        if referenced is None:
            what = f"references {axis.ref!r}, which the file does not hold," if axis.ref else "has"
            raise _LeftOut(f"an axis that {what} no SW-VALUES-PHYS", axis.line)
        if referenced.values is None or any(isinstance(p, list) for p in referenced.values):
            raise _LeftOut(f"its axis {axis.ref} holds rescale pairs (VG groups), not axis points; computing "
                           f"the points needs the A2L", axis.line)
        return referenced.values


    def rescaled_points(self, instance: Instance, axis: AxisCont, curve: Instance | None) -> list:
        """A CURVE_AXIS that lists no points: point k where its rescale curve (input -> index) gives k."""
        if curve is None or len(curve.axes) != 1 or axis.size is None or curve.values is None \
                or any(isinstance(v, (list, str)) for v in curve.values):
            why = "the file does not hold its rescale curve" if curve is None else "no SW-ARRAYSIZE and rescale curve"
            raise _LeftOut(f"its CURVE_AXIS lists no axis points (SW-VALUES-PHYS) and {why} to compute them from "
                           f"({axis.ref})", axis.line)
        inputs = self.axis(curve, curve.axes[0]).values
        return curve_axis_points(inputs, to_array(curve.values), axis.size).tolist()


def _item(item):
    return item if isinstance(item, str) else scalar(item)


def _odd_group(items: list) -> str:
    """Which VG group of a hand-edited grid lost or gained a value: the first whose length differs from most."""
    lengths = [len(_flat(item)) for item in items if isinstance(item, list)]
    if len(lengths) < 3 or len(lengths) != len(items):
        return ""
    usual = max(set(lengths), key=lengths.count)
    odd = next(n for n, length in enumerate(lengths) if length != usual)
    return f" (VG {odd + 1} of {len(lengths)} holds {lengths[odd]} values, the others {usual})"


def _flat(items: list) -> list:
    out: list = []
    for item in items:
        if isinstance(item, list):
            out += _flat(item)
        else:
            out.append(item)
    return out


def _squeezed(shape: tuple[int, ...] | None) -> tuple[int, ...] | None:
    """``shape`` without trailing 1s: a curve's values in one VG group are still a curve."""
    while shape and len(shape) > 1 and shape[-1] == 1:
        shape = shape[:-1]
    return shape


def _nested_shape(items: list) -> tuple[int, ...] | None:
    """The shape of nested VG groups, x first (innermost group along x); None when ragged."""
    if not any(isinstance(i, list) for i in items):
        return (len(items),)
    if not all(isinstance(i, list) for i in items):
        return None
    shapes = {_nested_shape(i) for i in items}
    if len(shapes) != 1 or None in shapes:
        return None
    return shapes.pop() + (len(items),)
