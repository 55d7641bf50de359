"""Many calibration objects decoded at once from any bytes: the ECU, an s19/hex, bytes patched in between.

:func:`decode_values` asks a ``fetch(spans) -> {span: bytes}`` for the NO_AXIS_PTS counts of every
object first, then for every object's bytes, so an ECU is read in two merged batches and an image
costs nothing but decoding. An object that cannot be decoded (a layout the codec refuses, a count
beyond MAX_AXIS_POINTS) is named with the reason instead of stopping the others.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import replace
from typing import TypeVar

from workbench.a2l.model import A2lModel
from workbench.a2l.objects import AxisPts, Characteristic
from workbench.calib.codec import value_edits
from workbench.calib.dataset.numbers import as_typed
from workbench.calib.layout import ObjectLayout, ResolvedLayout, object_layout
from workbench.calib.memory import MemoryBytes, Span
from workbench.calib.values import CalValue
from workbench.errors import InputError, UnknownSymbolError, WorkbenchError
from workbench.sync.store import ByteStore

__all__ = ["Fetch", "as_stored", "as_typed_value", "calibration_names", "decode_values", "label_differences",
           "object_layouts", "relabel", "resolve_all", "without_name"]

Fetch = Callable[[list[Span]], Mapping[Span, bytes]]
_T = TypeVar("_T")
_R = TypeVar("_R")
CALIBRATION_KINDS = ("CHARACTERISTIC", "AXIS_PTS")


def calibration_names(model: A2lModel, names: Iterable[str] | None = None) -> list[str]:
    """Every CHARACTERISTIC and AXIS_PTS of the A2L (in its order), or those ``names`` give: exact
    names, or globs (``xsPRV_*``), each in the order given.

    :raises UnknownSymbolError: a name the A2L lacks (the closest are suggested).
    :raises InputError: a MEASUREMENT named, or a glob that matches no calibration.
    """
    if names is None:
        return [o.name for o in model.find("*", kind=CALIBRATION_KINDS)]
    found = model.expand(names, CALIBRATION_KINDS, what="calibration")
    for name in found:
        if model.kind_of(name) not in CALIBRATION_KINDS:
            raise InputError(f"{name} is a {model.kind_of(name)}, not a calibration object")
    return found


def object_layouts(model: A2lModel, names: Iterable[str]) -> tuple[dict[str, ObjectLayout], dict[str, str]]:
    """``({name: layout}, {name: why it has none})``: unknown names, measurements and layouts the codec
    refuses land in the second mapping."""
    layouts: dict[str, ObjectLayout] = {}
    problems: dict[str, str] = {}
    for name in names:
        try:
            obj = model.object(name)
            if not isinstance(obj, (Characteristic, AxisPts)):
                problems[name] = f"a {obj.kind}, not a calibration object"
                continue
            layouts[name] = object_layout(model, obj)
        except UnknownSymbolError as exc:
            alike = f"; did you mean {', '.join(exc.suggestions)}?" if exc.suggestions else ""
            problems[name] = f"not in the A2L{alike}"
        except WorkbenchError as exc:
            problems[name] = without_name(name, str(exc))
    return layouts, problems


def without_name(name: str, message: str) -> str:
    """A message about ``name`` without the name in front (a report names the object in its own column)."""
    return message[len(name) + 2:] if message.startswith(f"{name}: ") else message


def resolve_all(layouts: Mapping[str, ObjectLayout], fetch: Fetch) -> tuple[dict[str, ResolvedLayout], dict[str, str]]:
    """Every layout placed, with the counts it reads from memory fetched in one batch."""
    firsts = MemoryBytes(fetch([span for layout in layouts.values() for span in layout.fixed_part()]))
    problems: dict[str, str] = {}
    return _each(layouts, lambda layout: layout.resolve(firsts), problems), problems


def decode_values(layouts: Mapping[str, ObjectLayout], fetch: Fetch) -> tuple[dict[str, CalValue], dict[str, str]]:
    """``({name: value}, {name: why not})`` of every layout, its bytes from ``fetch`` (two batches)."""
    resolved, problems = resolve_all(layouts, fetch)
    data = MemoryBytes(fetch([span for layout in resolved.values() for span in layout.spans()]))
    return _each(resolved, lambda layout: layout.decode(data), problems), problems


def _each(items: Mapping[str, _T], action: Callable[[_T], _R], problems: dict[str, str]) -> dict[str, _R]:
    """``action`` of every item by name; the names it fails on go to ``problems`` with the reason."""
    done: dict[str, _R] = {}
    for name, item in items.items():
        try:
            done[name] = action(item)
        except WorkbenchError as exc:
            problems[name] = without_name(name, str(exc))
    return done


def as_typed_value(model: A2lModel, value: CalValue) -> CalValue:
    """A value read from the ECU or an image as a dataset keeps it: its floats as typed (0.3, not the
    0.30000001192092896 a FLOAT32 holds; :func:`~workbench.calib.dataset.numbers.as_typed`), which write
    back the same float32. A FLOAT64_IEEE object keeps every digit it holds."""
    if model.datatype_of(model.object(value.name)) == "FLOAT64_IEEE":
        return value
    axes = tuple(replace(axis, values=as_typed(axis.values)) for axis in value.axes)
    return replace(value, value=as_typed(value.value), axes=axes)


def as_stored(model: A2lModel, value: CalValue, current: ByteStore) -> CalValue:
    """``value`` as the ECU would hold it once written over ``current`` (rounded to its data types: 0.2 in a
    file is float32's 0.2 in a FLOAT32_IEEE object), so a file and an ECU compare by what writing would change.
    Unit and axis labels are the A2L's (see :func:`label_differences`).

    :raises InputError: the value cannot be written (a shape, a text or a number its type cannot take).
    """
    edits = value_edits(model, value, current.read, check=False)
    if not edits:
        return _decode(model, value.name, current.read)
    patched = current.copy()
    patched.apply(edits)
    return _decode(model, value.name, patched.read)


def _decode(model: A2lModel, name: str, read: Callable[[Span], bytes]) -> CalValue:
    layout = object_layout(model, name)
    resolved = layout.resolve({span: read(span) for span in layout.fixed_part()})
    return resolved.decode({span: read(span) for span in resolved.spans()})


def relabel(value: CalValue, like: CalValue) -> CalValue:
    """``value`` with ``like``'s unit, comment and axis labels (kind, name, unit) where the shapes agree: a value
    read through the A2L compared with a file's by numbers, whatever labels the file's tool wrote."""
    if len(value.axes) != len(like.axes):
        return replace(value, unit=like.unit, comment=like.comment)
    axes = tuple(replace(axis, kind=other.kind, name=other.name, unit=other.unit)
                 for axis, other in zip(value.axes, like.axes))
    return replace(value, unit=like.unit, comment=like.comment, axes=axes)


def label_differences(ecu: CalValue, file: CalValue) -> list[str]:
    """The labels (unit, axis kinds and names) in which a file's value differs from the A2L's, as text."""
    found = []
    if ecu.unit != file.unit:
        found.append(f"unit {file.unit!r} in the file, {ecu.unit!r} in the A2L")
    for letter, ours, theirs in zip("xyz45", ecu.axes, file.axes):
        for attribute in ("kind", "name", "unit"):
            if getattr(ours, attribute) != getattr(theirs, attribute) and getattr(theirs, attribute):
                found.append(f"{letter} axis {attribute} {getattr(theirs, attribute)!r} in the file, "
                             f"{getattr(ours, attribute)!r} in the A2L")
    return found
