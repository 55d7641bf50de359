"""Reading and writing objects by name, in physical units: the part of :class:`~workbench.session.Session`
a calibration script uses most.

A write is refused before anything is sent when the object is read-only, the value breaks its
limits (EXTENDED_LIMITS only with ``allow_extended_limits``), its shape or monotony, or it lies
outside the memory the A2L says is writable (a calibration MEMORY_SEGMENT of RAM, or a
calibration page's working page). It is then written with DOWNLOAD (only the bytes that change),
read back and compared; a write that fails halfway says which fields reached the ECU.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.objects import AxisPts, Characteristic, Measurement
from workbench.calib.codec import value_edits
from workbench.calib.layout import ResolvedLayout, object_layout
from workbench.calib.memory import ByteEdit, Span
from workbench.calib.signals import MeasurementCodec, measurement_codec
from workbench.calib.values import CalValue
from workbench.errors import InputError, PartialWriteError, WorkbenchError
from workbench.session.memory import read_merged

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel
    from workbench.session.session import Session

__all__ = ["ValueAccess"]

_WRITABLE_PROGRAM_TYPES = {"DATA", "OFFLINE_DATA", "VARIABLES", "CALIBRATION_VARIABLES", "SERAM"}
_WRITABLE_MEMORY = {"RAM", "EEPROM", "REGISTER"}


class ValueAccess:
    """Mixed into :class:`Session`: values by name. Layouts and codecs are kept per name (the A2L does not change)."""

    lock: Any
    _layouts: dict
    _resolved: dict
    _codecs: dict

    @property
    def model(self: Session) -> A2lModel:
        """The A2L's objects (:class:`~workbench.a2l.model.A2lModel`)."""
        return self.doc.model(self.module)

    # --- reading ------------------------------------------------------------------------------

    def read(self: Session, name: str, *, page: str | int | None = None, raw: bool = False) -> Any:
        """The physical value of a MEASUREMENT or calibration object: a number or text, or an array
        (a measurement array, a VAL_BLK, a CURVE's or MAP's values [x, y], an AXIS_PTS' points).

        :param page: read a calibration from ``"working"`` or ``"reference"`` (default: the page XCP is on).
        :param raw: the value as the ECU holds it, before the COMPU_METHOD (integers for integer types).
        :raises UnknownSymbolError: no such object (the closest names are suggested).
        """
        value = self.read_many([name], page=page)[name]
        return self.to_raw(name, value) if raw else value

    def to_raw(self: Session, name: str, value: Any) -> Any:
        """A physical value of ``name`` as its raw data type holds it (enum texts become their numbers)."""
        obj = self.model.object(name)
        datatype = self.model.datatype_of(obj)
        raw = self.model.conversion(obj).to_raw(value, datatype)
        if datatype.startswith("FLOAT"):
            return raw
        rounded = np.round(np.asarray(raw, dtype=float)).astype(np.int64)
        return rounded if rounded.ndim else int(rounded)

    def read_value(self: Session, name: str, *, page: str | int | None = None) -> CalValue:
        """A calibration object's value with its axes and unit (:class:`~workbench.calib.values.CalValue`)."""
        obj = self.model.object(name)
        if not isinstance(obj, (Characteristic, AxisPts)):
            raise InputError(f"{name} is a {type(obj).__name__.upper()}, not a calibration object: use read()")
        with self.lock, self.on_page(page):
            resolved = self._resolve([name])[name]
            return resolved.decode(self._read_spans(resolved.spans()))

    def read_many(self: Session, names: Iterable[str], *, page: str | int | None = None) -> dict[str, Any]:
        """Several objects at once, neighbouring addresses merged into few UPLOADs: ``{name: value}``."""
        names = list(dict.fromkeys(names))
        codecs = {name: self._codec(name) for name in names if isinstance(self.model.object(name), Measurement)}
        with self.lock, self.on_page(page):
            resolved = self._resolve([name for name in names if name not in codecs])
            spans = [codec.span for codec in codecs.values()] + [s for r in resolved.values() for s in r.spans()]
            data = self._read_spans(spans)
        return {name: codecs[name].decode(data[codecs[name].span]) if name in codecs
                else resolved[name].decode(data).value for name in names}

    def _codec(self: Session, name: str) -> MeasurementCodec:
        codec = self._codecs.get(name)
        if codec is None:
            codec = self._codecs[name] = measurement_codec(self.model, name)
        return codec

    def _resolve(self: Session, names: list[str]) -> dict[str, ResolvedLayout]:
        """Each object placed in memory; layouts kept per name, resolved ones too unless they read counts."""
        layouts = {}
        for name in names:
            if name not in self._layouts:
                self._layouts[name] = object_layout(self.model, name)
            layouts[name] = self._layouts[name]
        static = {name: self._resolved[name] for name in names if name in self._resolved}
        dynamic = [name for name in names if name not in static]
        counts = [span for name in dynamic for span in layouts[name].fixed_part()]
        firsts = self._read_spans(counts) if counts else {}
        for name in dynamic:
            resolved = static[name] = layouts[name].resolve(firsts)
            if not layouts[name].needs_counts:
                self._resolved[name] = resolved
        return static

    def _read_spans(self: Session, spans: Iterable[Span]) -> dict[Span, bytes]:
        return read_merged(spans, lambda span: self.master.read(span.address, span.size, span.extension))

    # --- writing ------------------------------------------------------------------------------

    def write(self: Session, name: str, value: Any, *, allow_extended_limits: bool = False) -> CalValue:
        """Write a calibration in physical units and return what the ECU holds afterwards.

        ``value``: a number or an enum's text (VALUE), a ``str`` (ASCII), an array of the object's
        shape (VAL_BLK; a CURVE's or MAP's values, indexed [x, y], its axes unchanged), or a
        :class:`CalValue` (new axis points too).

        :raises InputError: unknown name, read-only object, a value beyond the limits, of the wrong
            shape or outside the writable memory (LimitsError, ConversionError are InputErrors).
        :raises EpkMismatchError: the session is read-only (the ECU's EPK differs from the A2L's).
        :raises XcpCommandError, XcpTimeoutError: the ECU refused or did not answer (the message says
            which fields were written before).
        """
        with self.lock:
            self.require_writable()
            target = self._as_cal_value(name, value)
            read = self._reader()
            edits = value_edits(self.model, target, read, extended=allow_extended_limits)
            self._check_writable_memory(name, edits)
            self._apply(name, edits)
            return self.read_value(name)

    def _as_cal_value(self: Session, name: str, value: Any) -> CalValue:
        if isinstance(value, CalValue):
            if value.name != name:
                raise InputError(f"the value is {value.name}'s, not {name}'s")
            return value
        obj = self.model.object(name)
        if isinstance(obj, Measurement):
            raise InputError(f"{name} is a MEASUREMENT: measurements are read, calibrations written")
        current = self.read_value(name)
        if current.kind in ("VALUE", "ASCII"):
            return CalValue(name, current.kind, value.item() if isinstance(value, np.generic) else value,
                            current.axes, current.unit, current.comment)
        array = np.asarray(value)
        if array.dtype.kind not in "OU":
            array = array.astype(float)
        return CalValue(name, current.kind, array, current.axes, current.unit, current.comment)

    def _reader(self: Session):
        cache: dict[Span, bytes] = {}

        def read(span: Span) -> bytes:
            if span not in cache:
                cache.update(self._read_spans([span]))
            return cache[span]

        return read

    def _check_writable_memory(self: Session, name: str, edits: list[ByteEdit]) -> None:
        writable = self.writable_spans()
        if writable is None:
            return
        for edit in edits:
            span = edit.span
            if not any(w.extension == span.extension and w.address <= span.address and span.end <= w.end
                       for w in writable):
                raise InputError(f"{name}: {edit.field or 'its bytes'} at {span} lie outside the A2L's writable "
                                 f"memory (MEMORY_SEGMENTs of calibration RAM); not written")

    def writable_spans(self: Session) -> list[Span] | None:
        """Where the A2L lets calibrations be written (None: the A2L has no MEMORY_SEGMENTs to tell)."""
        segments = self.doc.memory_segments(self.module)
        if not segments:
            return None
        spans = [Span(s.address, s.size) for s in segments
                 if s.prg_type in _WRITABLE_PROGRAM_TYPES and s.memory_type in _WRITABLE_MEMORY]
        spans += [Span(s.address, s.size, s.address_extension) for s in self.config.segments]
        return spans

    def _apply(self: Session, name: str, edits: list[ByteEdit]) -> None:
        """DOWNLOAD every edit, then read each back and compare byte for byte."""
        done: list[ByteEdit] = []
        for edit in edits:
            try:
                self.master.write(edit.address, edit.data, edit.extension)
            except WorkbenchError as exc:
                if not done:
                    raise
                raise PartialWriteError(name, [_field(e) for e in done], _field(edit), exc) from exc
            done.append(edit)
        back = self._read_spans([edit.span for edit in edits])
        wrong = [_field(edit) for edit in edits if back[edit.span] != edit.data]
        if wrong:
            raise WorkbenchError(f"{name}: the ECU holds other bytes than were written to {', '.join(wrong)} "
                                 "(a read-only area, or the ECU overwrote them)")


def _field(edit: ByteEdit) -> str:
    return f"{edit.name}.{edit.field}" if edit.field else edit.name or str(edit.span)
