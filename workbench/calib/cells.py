"""Single values of an array object (VAL_BLK, CURVE, MAP, CUBOID ...): where each lies, its bytes and back.

Writing one cell of a map needs neither the rest of the map nor its axes: the cell's place follows
from the record layout (:mod:`workbench.calib.layout`: COLUMN_DIR varies the X index fastest,
ROW_DIR the last; with STATIC_ADDRESS_OFFSETS each value keeps its place in the MAX_AXIS_POINTS
array), so a session downloads and reads back those bytes alone. A cell is indexed as the value
is, ``[x, y, ...]``. An object with a BIT_MASK needs the cells' current bytes to keep the other bits.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.calib import rawtypes
from workbench.calib.memory import ByteEdit, MemoryBytes, Span
from workbench.errors import ConversionError, InputError

if TYPE_CHECKING:
    from workbench.calib.layout import ResolvedLayout

__all__ = ["axis_with_points", "cell_edits", "cell_span", "cell_values", "index_problem"]

_AXIS_KINDS = ("CURVE", "MAP", "CUBOID", "CUBE_4", "CUBE_5")
_AXIS_LETTERS = "xyzuv"  # a cell is NAME[x, y, ...]: ASAP2's axes X, Y, Z, Z4, Z5


def index_problem(name: str, shape: tuple[int, ...], index: tuple[int, ...], noun: str = "values") -> str | None:
    """Why ``index`` names none of the ``noun`` of ``name`` (an array of ``shape``), one rule for every face that
    takes ``NAME[x, y]``; None: it names one. ``zvCurve has 9 values: index 12 is beyond (0-8)``,
    ``xvMap has 6 x 5 values: y index 7 is beyond (0-4)``."""
    if len(index) == len(shape) and all(0 <= i < n for i, n in zip(index, shape)):
        return None
    if not shape:
        return f"{name} has one value: name it without an index"
    if shape == (1,):
        noun = noun.replace("s", "", 1)  # "1 value", "1 point at most"
    has = f"{name} has {' x '.join(map(str, shape))} {noun}"
    if len(index) != len(shape):
        wanted = "one index" if len(shape) == 1 else f"{len(shape)} indices [{', '.join(_AXIS_LETTERS[:len(shape)])}]"
        return f"{has}: give {wanted}, not {len(index)}"
    axis, beyond, size = next((axis, i, n) for axis, (i, n) in enumerate(zip(index, shape)) if not 0 <= i < n)
    which = "index" if len(shape) == 1 else f"{_AXIS_LETTERS[axis]} index"
    return f"{has}: {which} {beyond} is beyond ({f'0-{size - 1}' if size > 1 else '0' if size else 'none'})"


def cell_span(layout: ResolvedLayout, index: tuple[int, ...]) -> Span:
    """The bytes of the value at ``index``.

    :raises ConversionError: the object holds no value there.
    """
    field = layout.field("FNC_VALUES")
    shape = layout.shape
    problem = index_problem(layout.name, shape, index)
    if problem is not None:
        raise ConversionError(problem)
    static = layout.plan.record_layout.static_address_offsets and layout.kind in _AXIS_KINDS
    stored = tuple(axis.max_points for axis in layout.plan.axes) if static else shape
    order = "F" if field.mode == "COLUMN_DIR" else "C"
    size = rawtypes.element_size(field.datatype)
    position = int(np.ravel_multi_index(index, stored, order=order))
    return Span(layout.address + field.offset + position * size, size, layout.extension)


def cell_edits(layout: ResolvedLayout, cells: Mapping[tuple[int, ...], Any],
               current: Mapping[Span, bytes] | None = None) -> list[ByteEdit]:
    """The edits that write each cell's physical value (converted, rounded, range-checked for the data
    type); cells next to each other in memory become one edit. ``current``: the cells' bytes now
    (needed for a BIT_MASK).

    :raises ConversionError: a value the conversion or data type cannot take, a cell outside the
        object, a BIT_MASK without ``current``.
    """
    obj = layout.obj
    field = layout.field("FNC_VALUES")
    spans = {index: cell_span(layout, index) for index in cells}
    values = np.array([cells[index] for index in spans], dtype=object)
    try:
        raw = layout.model.conversion(obj).to_raw(values, datatype=field.datatype)
    except ConversionError as exc:
        raise ConversionError(f"{obj.name}: {exc}") from None
    raw = rawtypes.to_datatype(raw, field.datatype, obj.name)
    if obj.bit_mask is not None:
        if current is None:
            raise ConversionError(f"{obj.name} has a BIT_MASK: writing a value needs its current bytes to keep "
                                  "the other bits")
        memory = MemoryBytes(current)
        old = np.concatenate([_raw(memory, span, field) for span in spans.values()])
        raw = rawtypes.insert_bits(old, raw, obj.bit_mask, field.datatype, obj.name)
    edits: list[ByteEdit] = []
    for span, number in sorted(zip(spans.values(), raw.tolist()), key=lambda pair: pair[0]):
        data = rawtypes.encode(np.array([number]), field.datatype, field.byte_order)
        last = edits[-1] if edits else None
        if last is not None and last.span.end == span.address and last.extension == span.extension:
            edits[-1] = ByteEdit(last.address, last.data + data, last.extension, obj.name, field.spelled)
        else:
            edits.append(ByteEdit(span.address, data, span.extension, obj.name, field.spelled))
    return edits


def cell_values(layout: ResolvedLayout, memory: Mapping[Span, bytes], indices: Iterable[tuple[int, ...]]
                ) -> dict[tuple[int, ...], Any]:
    """The physical value of each cell from ``memory`` (which holds at least the cells' bytes)."""
    obj = layout.obj
    field = layout.field("FNC_VALUES")
    indices = list(indices)
    held = MemoryBytes(memory)
    raw = np.concatenate([_raw(held, cell_span(layout, index), field) for index in indices])
    if obj.bit_mask is not None:
        raw = rawtypes.extract_bits(raw, obj.bit_mask, field.datatype)
    physical = np.asarray(layout.model.conversion(obj).to_physical(raw), dtype=object)
    return dict(zip(indices, physical.tolist()))


def _raw(memory: MemoryBytes, span: Span, field) -> np.ndarray:
    return rawtypes.decode(memory.read(span.address, span.size, span.extension), field.datatype, field.byte_order, 1)


def axis_with_points(name: str, axis: Any, points: Mapping[tuple[int, ...], Any]) -> np.ndarray:
    """The points of the AXIS_PTS ``name`` (``axis``, as held now) with ``points`` (``{(i,): value}``) put in, to be
    written whole (its order is checked with the others).

    :raises InputError: a point beyond the axis.
    """
    axis = np.array(axis, dtype=object)
    problem = next(filter(None, (index_problem(name, axis.shape, index, "points") for index in points)), None)
    if problem is not None:
        raise InputError(problem)
    for (index,), value in points.items():
        axis[index] = value
    return axis
