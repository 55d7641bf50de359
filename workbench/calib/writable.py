"""What the A2L alone says about a write, before any ECU is asked: the value to write, and where it may go.

:func:`checked_value` makes the :class:`~workbench.calib.values.CalValue` to write from what a caller
gives (a number, an enum's text, a string, an array of the object's shape, a CalValue) and refuses it
with :class:`~workbench.errors.LimitsError` when it breaks its object's rules
(:func:`~workbench.calib.limits.check_limits`: write access, kind, shape, texts, limits, monotony),
with :class:`~workbench.errors.ConversionError` when its conversion or data type cannot take it (a
value a TAB_NOINTP does not list, beyond the data type), or with
:class:`~workbench.errors.InputError` when it is a measurement or lies outside the memory the A2L
lets calibrations be written to. :func:`checked_cells` does the same for single values of an
array. A session runs them before it sends anything; the CLI before it even connects.

Writable memory (:func:`writable_spans`): the MEMORY_SEGMENTs of RAM (or EEPROM, registers) holding
data, and the XCP SEGMENTs (calibration pages). An A2L without MEMORY_SEGMENTs does not tell: then
nothing is refused for its address; nor for an address extension none of them is in (MEMORY_SEGMENTs
describe extension 0; XCPlite's parameters on a stack frame, behind a pointer or in application memory
have extensions 2, 3, 128 of their own). Where an object's size depends on counts in ECU memory, its
bytes are checked once they are known (:func:`check_inside`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.objects import AxisPts, Measurement
from workbench.calib.cells import cell_edits, cell_span
from workbench.calib.layout import object_layout
from workbench.calib.limits import check_cells, check_limits
from workbench.calib.memory import Span
from workbench.calib.values import CalValue
from workbench.errors import InputError, LimitsError

if TYPE_CHECKING:
    from workbench.a2l.document import MemorySegment
    from workbench.calib.layout import ResolvedLayout
    from workbench.a2l.model import A2lModel
    from workbench.a2l.xcp import XcpSegment

__all__ = ["check_inside", "checked_cells", "checked_value", "writable_spans"]

_WRITABLE_PROGRAM_TYPES = {"DATA", "OFFLINE_DATA", "VARIABLES", "CALIBRATION_VARIABLES", "SERAM"}
_WRITABLE_MEMORY = {"RAM", "EEPROM", "REGISTER"}


def writable_spans(memory_segments: Iterable[MemorySegment], xcp_segments: Iterable[XcpSegment]) -> list[Span] | None:
    """Where the A2L lets calibrations be written (None: it has no MEMORY_SEGMENTs to tell)."""
    memory_segments = list(memory_segments)
    if not memory_segments:
        return None
    spans = [Span(s.address, s.size) for s in memory_segments
             if s.prg_type in _WRITABLE_PROGRAM_TYPES and s.memory_type in _WRITABLE_MEMORY]
    return spans + [Span(s.address, s.size, s.address_extension) for s in xcp_segments]


def check_inside(name: str, spans: Iterable[tuple[Span, str]], writable: list[Span] | None) -> None:
    """:raises InputError: one of the ``(span, what)`` lies outside ``writable`` (None: nothing is refused; nor
    is a span in an address extension ``writable`` does not describe)."""
    if writable is None:
        return
    described = {w.extension for w in writable}
    for span, what in spans:
        if span.extension in described and not any(w.extension == span.extension and w.address <= span.address and span.end <= w.end
                   for w in writable):
            raise InputError(f"{name}: {what or 'its bytes'} at {span} lie outside the A2L's writable memory "
                             "(MEMORY_SEGMENTs of calibration RAM); not written")


def checked_value(model: A2lModel, name: str, value: Any, *, extended: bool = False,
                  writable: list[Span] | None = None, resolved: ResolvedLayout | None = None) -> CalValue:
    """``value`` as the CalValue to write into ``name`` (a bare array: the values, the axes as they are).

    :param extended: check against EXTENDED_LIMITS instead of the limits.
    :param resolved: the object placed in memory, when the caller has it (a session): its bytes are
        checked against ``writable``, and the caller encodes the value itself (conversion refusals).
    :raises UnknownSymbolError: no such object. :raises LimitsError: the value breaks its object's
        rules. :raises ConversionError: the conversion or data type cannot take it. :raises InputError:
        a measurement, or memory the A2L does not let be written.
    """
    obj = model.object(name)
    if isinstance(obj, Measurement):
        raise InputError(f"{name} is a MEASUREMENT: measurements are read, calibrations written")
    if isinstance(value, CalValue):
        if value.name != name:
            raise InputError(f"the value is {value.name}'s, not {name}'s")
        target = value
    else:
        target = CalValue(name, getattr(obj, "type", "AXIS_PTS"), _bare(getattr(obj, "type", "AXIS_PTS"), value),
                          unit=model.unit_of(obj))
    violations = check_limits(model, target, extended=extended)
    if violations:
        raise LimitsError(violations)
    trial = resolved is None and getattr(obj, "bit_mask", None) is None  # a BIT_MASK needs the ECU's other bits
    resolved = resolved or _static(model, name)
    if resolved is not None:
        spans = resolved.spans() if target.axes else [resolved.span()]
        check_inside(name, ((span, "") for span in spans), writable)
        if trial:  # what the conversion or the data type refuses
            resolved.encode(target)
    return target


def checked_cells(model: A2lModel, name: str, cells: Mapping[Any, Any], *, extended: bool = False,
                  writable: list[Span] | None = None, resolved: ResolvedLayout | None = None
                  ) -> dict[tuple[int, ...], Any]:
    """``cells`` (index -> physical value; an index is ``(x, y, ...)``, or an int for one axis) checked
    for writing into the array object ``name`` (or as points of the AXIS_PTS ``name``): ``{(x, y, ...): value}``.

    :raises UnknownSymbolError, LimitsError, ConversionError, InputError: as :func:`checked_value`.
    """
    if not cells:
        raise InputError(f"{name}: no values to write")
    indexed = {_index(index): value.item() if isinstance(value, np.generic) else value
               for index, value in cells.items()}
    violations = check_cells(model, name, indexed, extended=extended, shape=resolved.shape if resolved else None)
    if violations:
        raise LimitsError(violations)
    if isinstance(model.object(name), AxisPts):  # placed and checked with the axis they go into (Session.write_cells)
        return indexed
    trial = resolved is None
    resolved = resolved or _static(model, name)
    if resolved is not None:
        check_inside(name, ((cell_span(resolved, index), f"the value {list(index)}") for index in indexed), writable)
        if trial and resolved.obj.bit_mask is None:
            cell_edits(resolved, indexed)
    return indexed


def _static(model: A2lModel, name: str) -> ResolvedLayout | None:
    """The object placed in memory when the A2L alone tells where everything lies (no count in ECU memory)."""
    layout = object_layout(model, name)
    return None if layout.needs_counts else layout.resolve()


def _bare(kind: str, value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if kind in ("VALUE", "ASCII"):
        return value
    array = np.asarray(value)
    return array.astype(float) if array.dtype.kind not in "OUS" else array.astype(object)


def _index(index: Any) -> tuple[int, ...]:
    items = index if isinstance(index, (tuple, list)) else (index,)
    try:
        return tuple(int(i) for i in items)
    except (TypeError, ValueError):
        raise InputError(f"a cell is indexed by integers [x, y, ...], not {index!r}") from None
