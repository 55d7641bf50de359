"""A calibration object's bytes <-> its physical value (:class:`~workbench.calib.values.CalValue`).

Works on a :class:`~workbench.calib.layout.ResolvedLayout` (where each field lies) and the bytes
read there. Decoding converts raw values with the object's COMPU_METHOD (axes with theirs);
encoding converts back, rounds for the data type (half away from zero), refuses what does not fit,
and returns only the fields - trimmed to the bytes - that differ from the current memory, so
writing a MAP's values leaves its axis points alone unless they changed too.

What a value may be when writing:

- VALUE: a number or a text (verbal conversion), or a CalValue of kind VALUE;
- ASCII: a ``str`` (at most MATRIX_DIM/NUMBER characters; the rest is filled with NUL);
- VAL_BLK: an array of the MATRIX_DIM shape;
- CURVE, MAP, ...: an array ``(nx, ny, ...)`` of the values (the axes stay), or a CalValue whose
  ``axes`` give new points too. A new number of points is written when the layout stores it
  (NO_AXIS_PTS); axes that are fixed (FIX_AXIS) cannot change; a COM_AXIS whose points changed is
  written into the AXIS_PTS it refers to, a CURVE_AXIS into its rescale curve (below), each edit
  with that object's name;
- AXIS_PTS: an array of points, or a CalValue of kind AXIS_PTS.

A CURVE_AXIS (AXIS_DESCR with CURVE_AXIS_REF) stores no points: its rescale curve maps the axis'
input quantity to a map index, and the ECU looks the map up at that (fractional) index. ASAM
MCD-2MC: "CURVE_AXIS uses a separate CURVE to rescale the axis. The referenced CURVE is used to lookup
an axis index, and the index value is used by the controller to determine the operating point in the
CURVE, MAP, CUBOID, CUBE_4, or CUBE_5" (the AXIS_DESCR attribute; its Appendix B works an example:
X_NORM takes 850 to index 3.9 of a 7 x 6 map, the index clamped to the curve's ends; asamint's
``calibration/curve_axis.py`` implements it so). So the curve's axis holds input values and its
values indices, and the map's number of points is its own (FIX_NO_AXIS_PTS, NO_AXIS_PTS in memory,
MAX_AXIS_POINTS), not the curve's. Point k of the axis, in the input quantity's unit, is where the
curve equals k (:func:`curve_axis_points`; NaN for an index the curve never reaches): the ASAM CDF
2.0 demo writes exactly these as the map's axis labels (its curves X_CURVE_N3 and Y_CURVE_N2 give
0, 1, 2 at 800, 1600, 3200 rpm and 0, 1 at 300, 350; the map's points are 800, 1600, 3200 and 300,
350). Written points make the curve give index k at point k: its axis the points, its values 0 ..
n-1 (only what differs is sent); a curve of another number of points that memory cannot change is
refused (write the curve itself).
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.calib import rawtypes
from workbench.calib.memory import ByteEdit, MemoryBytes, Span, read_spans
from workbench.calib.values import Axis, CalValue
from workbench.errors import ConversionError, LimitsError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel
    from workbench.a2l.objects import AxisPts, Characteristic
    from workbench.calib.layout import Field, ResolvedLayout

__all__ = ["decode", "encode", "read_value", "to_raw", "value_decoder", "value_edits"]

_ENCODINGS = {None: "latin-1", "UTF8": "utf-8", "UTF16": "utf-16", "UTF32": "utf-32"}


# -- by name, with a reader ------------------------------------------------------------------------------

def read_value(model: "A2lModel", obj: "str | Characteristic | AxisPts", read: Callable[[Span], bytes]) -> CalValue:
    """A calibration object's physical value, its bytes fetched with ``read(span) -> bytes`` (counts
    first when the layout stores them, then the object and its axis objects)."""
    from workbench.calib.layout import object_layout

    layout = object_layout(model, obj)
    resolved = layout.resolve(read_spans(layout.fixed_part(), read))
    return resolved.decode(read_spans(resolved.spans(), read))


def value_edits(model: "A2lModel", value: CalValue, read: Callable[[Span], bytes], *, check: bool = True,
                extended: bool = False) -> list[ByteEdit]:
    """The edits that write ``value`` over what ``read`` finds now (only what changes).

    :param check: refuse a value that breaks its object's rules (:func:`~workbench.calib.limits.check_limits`;
        ``extended``: against EXTENDED_LIMITS) with :class:`LimitsError`, before anything is computed.
    :raises LimitsError, ConversionError: the value cannot be written.
    """
    from workbench.calib.layout import object_layout
    from workbench.calib.limits import check_limits

    if check:
        violations = check_limits(model, value, extended=extended)
        if violations:
            raise LimitsError(violations)
    layout = object_layout(model, value.name)
    resolved = layout.resolve(read_spans(layout.fixed_part(), read))
    return resolved.encode(value, read_spans(resolved.spans(), read))


def to_raw(model: "A2lModel", name: str, value: Any) -> Any:
    """A physical value of ``name`` as its raw data type holds it (enum texts become their numbers; integers for
    integer types)."""
    obj = model.object(name)
    datatype = model.datatype_of(obj)
    raw = model.conversion(obj).to_raw(value, datatype)
    if datatype.startswith("FLOAT"):
        return raw
    rounded = np.round(np.asarray(raw, dtype=float)).astype(np.int64)
    return rounded if rounded.ndim else int(rounded)


# -- reading -------------------------------------------------------------------------------------------

def decode(layout: "ResolvedLayout", memory: MemoryBytes) -> CalValue:
    """The object's value, physical. :raises WorkbenchError: ``memory`` lacks bytes of :meth:`spans`."""
    model, obj = layout.model, layout.obj
    unit = model.unit_of(obj)
    comment = obj.long_identifier
    if layout.kind == "AXIS_PTS":
        return CalValue(obj.name, "AXIS_PTS", _axis_points(layout, 0, memory), unit=unit, comment=comment)
    if layout.kind == "ASCII":
        return CalValue(obj.name, "ASCII", _text(layout, memory), unit=unit, comment=comment)
    raw = _field_values(layout, "FNC_VALUES", memory)
    if obj.bit_mask is not None:
        raw = rawtypes.extract_bits(raw, obj.bit_mask, layout.field("FNC_VALUES").datatype)
    physical = model.conversion(obj).to_physical(raw)
    if layout.kind == "VALUE":
        return CalValue(obj.name, "VALUE", _scalar(physical), unit=unit, comment=comment)
    axes = tuple(_axis(layout, index, memory) for index in range(len(layout.counts)))
    return CalValue(obj.name, layout.kind, physical, axes, unit, comment)


def value_decoder(layout: "ResolvedLayout") -> Callable[[bytes], Any]:
    """``data -> value``: the physical value (``decode(...).value``) from the bytes of ``layout.span()``
    alone, which must hold all of the object (no axis object of its own). A plain VALUE is one struct
    unpack and its conversion (a polled read's few microseconds); anything else goes through :func:`decode`."""
    span, field = layout.span(), layout.field("FNC_VALUES")
    fmt = rawtypes.struct_format(field.datatype, field.byte_order) if field is not None else None
    if layout.kind != "VALUE" or layout.obj.bit_mask is not None or fmt is None:
        return lambda data: decode(layout, MemoryBytes({span: data})).value
    unpack, offset = struct.Struct(fmt).unpack_from, field.offset
    conversion = layout.model.conversion(layout.obj)
    if conversion.conversion_type in ("IDENTICAL", "NO_COMPU_METHOD"):
        return lambda data: unpack(data, offset)[0]
    to_physical = conversion.to_physical
    return lambda data: _scalar(to_physical(unpack(data, offset)[0]))


def _field_values(layout: "ResolvedLayout", keyword: str, memory: MemoryBytes, axis: str | None = None) -> np.ndarray:
    """The raw values of a field, in value order: FNC_VALUES shaped ``(nx, ny, ...)``, axis points
    first to last."""
    field = layout.field(keyword, axis)
    if keyword == "FNC_VALUES":
        shape = layout.shape
        static = layout.plan.record_layout.static_address_offsets and layout.kind in _AXIS_KINDS
        stored = tuple(axis.max_points for axis in layout.plan.axes) if static else shape
        count = int(np.prod(stored)) if stored else 1
        raw = rawtypes.decode(_bytes(layout, field, memory, count), field.datatype, field.byte_order, count)
        order = "F" if field.mode == "COLUMN_DIR" else "C"
        values = raw.reshape(stored, order=order) if stored else raw
        return values[tuple(slice(0, n) for n in shape)] if static else values
    raw = rawtypes.decode(_bytes(layout, field, memory, field.count), field.datatype, field.byte_order, field.count)
    return raw[::-1] if field.mode == "INDEX_DECR" else raw


_AXIS_KINDS = ("CURVE", "MAP", "CUBOID", "CUBE_4", "CUBE_5")


def _bytes(layout: "ResolvedLayout", field: "Field", memory: MemoryBytes, count: int) -> bytes:
    size = count * rawtypes.element_size(field.datatype)
    return memory.read(layout.address + field.offset, size, layout.extension)


def _axis(layout: "ResolvedLayout", index: int, memory: MemoryBytes) -> Axis:
    plan = layout.plan.axes[index]
    descr = plan.descr
    if plan.reference is not None:
        referenced = layout.references[plan.name]
        value = decode(referenced, memory)
        if plan.attribute == "CURVE_AXIS":
            points = _rescaled_points(layout, value, layout.counts[index])
            return Axis(points, plan.attribute, referenced.name, value.axes[0].unit, descr.input_quantity)
        return Axis(np.asarray(value.value), plan.attribute, referenced.name, value.unit, descr.input_quantity)
    return Axis(_axis_points(layout, index, memory), plan.attribute, None, layout.model.unit_of(descr),
                descr.input_quantity)


def curve_axis_points(inputs: Any, indices: Any, count: int) -> np.ndarray:
    """The ``count`` points of a CURVE_AXIS whose rescale curve gives ``indices`` at ``inputs`` (its
    axis): point k is the first input at which the curve, linear between its points, equals k; NaN
    where it never does (see the module docstring)."""
    xs, ys = np.asarray(inputs, dtype=np.float64), np.asarray(indices, dtype=np.float64)
    points = np.full(count, np.nan)
    for k in range(count):
        for j in range(len(ys)):
            if ys[j] == k:
                points[k] = xs[j]
                break
            if j + 1 < len(ys) and min(ys[j], ys[j + 1]) < k < max(ys[j], ys[j + 1]):
                points[k] = xs[j] + (k - ys[j]) * (xs[j + 1] - xs[j]) / (ys[j + 1] - ys[j])
                break
    return points


def _rescaled_points(layout: "ResolvedLayout", curve: CalValue, count: int) -> np.ndarray:
    try:
        return curve_axis_points(curve.axes[0].values, curve.value, count)
    except (TypeError, ValueError):
        raise ConversionError(f"{layout.name}: the rescale curve {curve.name} of a CURVE_AXIS holds texts, "
                              "not map indices") from None


def _axis_points(layout: "ResolvedLayout", index: int, memory: MemoryBytes) -> np.ndarray:
    """The physical points of one of the object's own axes (STD_AXIS, FIX_AXIS, an AXIS_PTS)."""
    plan = layout.plan.axes[index]
    descr = plan.descr
    source = descr if descr is not None else layout.obj
    count = layout.counts[index]
    if plan.attribute == "FIX_AXIS":
        raw = _fix_axis_raw(layout, plan, count, memory)
    else:
        raw = _field_values(layout, "AXIS_PTS", memory, plan.name)
        if _deposit(layout, source) == "DIFFERENCE":
            raw = np.cumsum(raw)
    return np.asarray(layout.model.conversion(source).to_physical(raw))


def _fix_axis_raw(layout: "ResolvedLayout", plan, count: int, memory: MemoryBytes) -> np.ndarray:
    points = plan.descr.fix_axis_points
    if points is not None:
        return np.asarray(points[:count], dtype=np.float64)
    offset = _field_values(layout, "OFFSET", memory, plan.name)[0]
    distance = layout.field("DIST_OP", plan.name)
    if distance is not None:
        step = _field_values(layout, "DIST_OP", memory, plan.name)[0]
    else:
        step = 2.0 ** _field_values(layout, "SHIFT_OP", memory, plan.name)[0]
    return offset + np.arange(count) * np.float64(step)


def _deposit(layout: "ResolvedLayout", source) -> str:
    return getattr(source, "deposit", None) or layout.model.mod_common.deposit or "ABSOLUTE"


def _text(layout: "ResolvedLayout", memory: MemoryBytes) -> str:
    field = layout.field("FNC_VALUES")
    raw = _bytes(layout, field, memory, field.count)
    encoding = _text_encoding(layout, field)
    text = raw.decode(encoding, "replace")
    return text.split("\0", 1)[0]


def _text_encoding(layout: "ResolvedLayout", field: "Field") -> str:
    encoding = layout.obj.encoding
    if encoding not in _ENCODINGS:
        raise layout.plan.error(f"ENCODING {encoding} is not supported (UTF8, UTF16, UTF32)")
    name = _ENCODINGS[encoding]
    if name in ("utf-16", "utf-32"):
        name += "-be" if field.byte_order.startswith("MSB_FIRST") else "-le"
    return name


def _scalar(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.reshape(-1)[0].item() if value.dtype != object else value.reshape(-1)[0]
    return value


# -- writing -------------------------------------------------------------------------------------------

def encode(layout: "ResolvedLayout", value: Any, current: MemoryBytes | None) -> list[ByteEdit]:
    """The edits that make memory hold ``value`` (see the module docstring).

    :raises ConversionError: wrong kind or shape, a value the conversion or data type cannot take,
        a fixed axis changed, a BIT_MASK without ``current``.
    """
    obj = layout.obj
    if isinstance(value, CalValue):
        if value.name != obj.name:
            raise ConversionError(f"a value of {value.name} cannot be written to {obj.name}")
        if value.kind != layout.kind:
            raise ConversionError(f"{obj.name} is a {layout.kind}, the value a {value.kind}")
        axes, bare = value.axes, value.value
    else:
        axes, bare = (), value
    if layout.kind == "AXIS_PTS":
        return _write_axis_pts(layout, bare, current)
    if layout.kind == "ASCII":
        return _write_text(layout, bare, current)
    target = layout
    new_counts = _new_counts(layout, axes)
    if new_counts is not None:
        target = layout.with_counts(new_counts)
    new: list[tuple["Field", bytes]] = []
    new.append((target.field("FNC_VALUES"), _values_bytes(target, bare, current)))
    edits: list[ByteEdit] = []
    for index, axis in enumerate(axes):
        edits.extend(_write_axis(target, index, axis, new, current))
    if new_counts is not None:
        for index, plan in enumerate(target.plan.axes):
            if plan.in_memory:
                field = target.field("NO_AXIS_PTS", plan.name)
                new.append((field, rawtypes.encode(np.array([target.counts[index]]), field.datatype, field.byte_order)))
    return _edits(target, new, current) + edits


def _new_counts(layout: "ResolvedLayout", axes: tuple[Axis, ...]) -> dict[str, int] | None:
    """Axis -> points when the value's axes have another number of points than memory holds."""
    if not axes:
        return None
    if len(axes) != len(layout.counts):
        raise ConversionError(f"{layout.name} has {len(layout.counts)} axes, the value {len(axes)}")
    counts = {}
    changed = False
    for plan, count, axis in zip(layout.plan.axes, layout.counts, axes):
        points = len(np.asarray(axis.values).reshape(-1))
        counts[plan.name] = points
        if points == count:
            continue
        changed = True
        if not plan.in_memory:
            shared = plan.reference is not None and plan.attribute != "CURVE_AXIS"
            where = f" (it comes from {plan.reference.name})" if shared else ""
            raise ConversionError(f"{layout.name}: axis {plan.name} has {count} points{where}, the value {points}; "
                                  "its number of points is not stored in memory, so it cannot change")
        if points > plan.max_points or points < 1:
            raise ConversionError(f"{layout.name}: {points} points on axis {plan.name}, MAX_AXIS_POINTS is "
                                  f"{plan.max_points}")
    return counts if changed else None


def _raw_for(layout: "ResolvedLayout", source, values: Any, datatype: str, what: str) -> np.ndarray:
    """Physical -> raw of the data type (converted, rounded, range-checked); a refusal names ``what``."""
    try:
        raw = layout.model.conversion(source).to_raw(values, datatype=datatype)
    except ConversionError as exc:
        raise ConversionError(f"{what}: {exc}") from None
    return rawtypes.to_datatype(raw, datatype, what)


def _values_bytes(layout: "ResolvedLayout", value: Any, current: MemoryBytes | None) -> bytes:
    obj = layout.obj
    field = layout.field("FNC_VALUES")
    shape = layout.shape
    array = np.asarray(value, dtype=object if _is_text(value) else None)
    if array.shape != shape and not (shape == () and array.size == 1):
        raise ConversionError(f"{obj.name}: a {layout.kind} of shape {shape}, the value has shape {array.shape}")
    raw = _raw_for(layout, obj, array.reshape(shape), field.datatype, obj.name)
    if obj.bit_mask is not None:
        if current is None:
            raise ConversionError(f"{obj.name} has a BIT_MASK: writing it needs the current bytes to keep the other "
                                  "bits")
        old = _field_values(layout, "FNC_VALUES", current)
        raw = rawtypes.insert_bits(old, raw, obj.bit_mask, field.datatype, obj.name)
    static = layout.plan.record_layout.static_address_offsets and layout.kind in _AXIS_KINDS
    order = "F" if field.mode == "COLUMN_DIR" else "C"
    if static:
        full = tuple(axis.max_points for axis in layout.plan.axes)
        canvas = _static_canvas(layout, field, full, current, order)
        canvas[tuple(slice(0, n) for n in shape)] = raw
        raw = canvas
    flat = np.asarray(raw).reshape(-1, order=order) if np.ndim(raw) else np.asarray(raw).reshape(1)
    return rawtypes.encode(flat, field.datatype, field.byte_order)


def _static_canvas(layout, field, full, current, order) -> np.ndarray:
    """The whole MAX_AXIS_POINTS array of a STATIC_ADDRESS_OFFSETS object: as in memory, else zeros."""
    count = int(np.prod(full))
    if current is not None:
        data = current.read(layout.address + field.offset, count * rawtypes.element_size(field.datatype),
                            layout.extension)
        return rawtypes.decode(data, field.datatype, field.byte_order, count).reshape(full, order=order).copy()
    dtype = np.float64 if field.datatype.startswith("FLOAT") else np.int64
    return np.zeros(full, dtype=dtype)


def _is_text(value: Any) -> bool:
    if isinstance(value, str):
        return True
    array = np.asarray(value) if not isinstance(value, np.ndarray) else value
    return array.dtype == object or array.dtype.kind in "US"


def _write_axis(layout: "ResolvedLayout", index: int, axis: Axis, new: list, current: MemoryBytes | None
                ) -> list[ByteEdit]:
    """Queue (in ``new``) the bytes of one of the value's axes; returns the edits of a referenced object."""
    plan = layout.plan.axes[index]
    points = np.asarray(axis.values).reshape(-1)
    if plan.attribute == "CURVE_AXIS":
        return _write_rescale_curve(layout, index, points, current)
    if plan.reference is not None:
        return _write_axis_pts(layout.references[plan.name], points, current)
    if plan.attribute == "FIX_AXIS":
        if current is None:
            return []
        present = _axis_points(layout, index, current) if layout.counts[index] == len(points) else None
        if present is None or not np.array_equal(present, points):
            raise ConversionError(f"{layout.name}: axis {plan.name} is a FIX_AXIS; its points cannot be written")
        return []
    new.append(_axis_field_bytes(layout, index, points))
    return []


def _write_rescale_curve(layout: "ResolvedLayout", index: int, points: np.ndarray, current: MemoryBytes | None
                         ) -> list[ByteEdit]:
    """The edits that make a CURVE_AXIS' rescale curve give index k at ``points[k]`` (none when the
    curve gives these points already)."""
    plan = layout.plan.axes[index]
    curve = layout.references[plan.name]
    if current is not None:
        present = _rescaled_points(layout, decode(curve, current), len(points))
        if np.array_equal(present, np.asarray(points, dtype=np.float64), equal_nan=True):
            return []
    if len(points) != curve.counts[0] and not curve.plan.axes[0].in_memory:
        raise ConversionError(f"{layout.name}: axis {plan.name} is a CURVE_AXIS; its {len(points)} points would make "
                              f"the rescale curve {curve.name} (input -> index) {len(points)} points long, and it has "
                              f"{curve.counts[0]} that memory cannot change: write {curve.name} itself")
    indices = CalValue(curve.name, "CURVE", np.arange(len(points), dtype=np.float64), (Axis(points),))
    return encode(curve, indices, current)


def _axis_field_bytes(layout: "ResolvedLayout", index: int, points: np.ndarray) -> tuple["Field", bytes]:
    plan = layout.plan.axes[index]
    source = plan.descr if plan.descr is not None else layout.obj
    field = layout.field("AXIS_PTS", plan.name)
    raw = _raw_for(layout, source, points, field.datatype, f"{layout.name} axis {plan.name}")
    if _deposit(layout, source) == "DIFFERENCE":
        raw = np.diff(raw if field.datatype == "A_UINT64" else raw.astype(np.int64), prepend=0)
        raw = rawtypes.to_datatype(raw, field.datatype, f"{layout.name} axis {plan.name} (differences)")
    if field.mode == "INDEX_DECR":
        raw = raw[::-1]
    return field, rawtypes.encode(raw, field.datatype, field.byte_order)


def _write_axis_pts(layout: "ResolvedLayout", value: Any, current: MemoryBytes | None) -> list[ByteEdit]:
    points = np.asarray(value).reshape(-1)
    target = layout
    if len(points) != layout.counts[0]:
        _new_counts(layout, (Axis(points),))  # raises unless the count lies in memory
        target = layout.with_counts({"X": len(points)})
    new = [_axis_field_bytes(target, 0, points)]
    if len(points) != layout.counts[0]:
        field = target.field("NO_AXIS_PTS", "X")
        new.append((field, rawtypes.encode(np.array([len(points)]), field.datatype, field.byte_order)))
    return _edits(target, new, current)


def _write_text(layout: "ResolvedLayout", text: Any, current: MemoryBytes | None) -> list[ByteEdit]:
    if not isinstance(text, str):
        raise ConversionError(f"{layout.name} is an ASCII string; the value is {type(text).__name__}")
    field = layout.field("FNC_VALUES")
    encoding = _text_encoding(layout, field)
    try:
        data = text.encode(encoding)
    except UnicodeEncodeError as error:
        raise ConversionError(f"{layout.name}: {text!r} cannot be written in {encoding} ({error.reason})") from None
    if encoding.startswith(("utf-16", "utf-32")) and data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        data = data[4:] if encoding.startswith("utf-32") else data[2:]
    capacity = field.count * rawtypes.element_size(field.datatype)
    if len(data) > capacity:
        raise ConversionError(f"{layout.name}: {text!r} needs {len(data)} bytes, the string holds {capacity}")
    return _edits(layout, [(field, data + b"\0" * (capacity - len(data)))], current)


def _edits(layout: "ResolvedLayout", new: list[tuple["Field", bytes]], current: MemoryBytes | None) -> list[ByteEdit]:
    """One edit per field whose bytes differ from ``current`` (all when it is None), trimmed to the
    elements that differ."""
    edits = []
    for field, data in new:
        address = layout.address + field.offset
        start, end = 0, len(data)
        old = current.get(address, len(data), layout.extension) if current is not None else None
        if old is not None:  # a field that moved beyond what was read (a new number of points) is written whole
            changed = np.flatnonzero(np.frombuffer(data, np.uint8) != np.frombuffer(old, np.uint8))
            if not len(changed):
                continue
            size = rawtypes.element_size(field.datatype)  # whole elements: no torn value in between
            start, end = int(changed[0]) // size * size, -(-(int(changed[-1]) + 1) // size) * size
        edits.append(ByteEdit(address + start, data[start:end], layout.extension, layout.name, field.spelled))
    return edits
