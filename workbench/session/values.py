"""Reading and writing objects by name, in physical units: the part of :class:`~workbench.session.Session`
a calibration script uses most.

A write is refused before anything is sent when the session is read-only (EPK mismatch), the object
is read-only, the value breaks its limits (EXTENDED_LIMITS only with ``allow_extended_limits``), its
shape, texts or monotony, or it lies outside the memory the A2L says is writable
(:mod:`workbench.calib.writable`, which the CLI runs before it connects). Once connected, XCP must be
on a page it may write (a segment's reference page is refused, saying how to switch), which the
session asks the ECU once and then knows; the segments are those the page switching uses, the A2L's or,
where it has none, the ECU's.

A write sends what changes and reads back only that: a VALUE is one DOWNLOAD (after SET_MTA) and
one read-back; the values of a CURVE or MAP are compared with what the session knows of the object
(the bytes it last read with :meth:`read_value` or wrote, kept while no CONNECT, page switch or
other DOWNLOAD came between; else read once), and only the elements that differ are written;
:meth:`write_cells` writes single values without knowing the rest. The value returned is decoded
from the bytes read back, the rest of the object as known. A write that fails halfway says which
fields reached the ECU.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

from workbench.a2l.objects import AxisPts, Characteristic, Measurement
from workbench.calib.cells import axis_with_points, cell_edits, cell_span, cell_values
from workbench.calib.codec import to_raw, value_decoder
from workbench.calib.layout import ObjectLayout, ResolvedLayout, object_layout
from workbench.calib.memory import ByteEdit, MemoryBytes, Span
from workbench.calib.signals import MeasurementCodec, measurement_codec
from workbench.calib.values import CalValue
from workbench.calib.writable import check_inside, checked_cells, checked_value, writable_spans
from workbench.errors import (InputError, PageError, PartialWriteError, WorkbenchError, XcpCommandError,
                              placeholder_hint)
from workbench.logs import logger
from workbench.session.memory import KnownMemory, read_merged
from workbench.xcp_protocol import Err, Resource

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel
    from workbench.a2l.xcp import XcpSegment
    from workbench.session.session import Session

log = logger(__name__)

__all__ = ["ValueAccess"]

_NOT_WRITABLE = "XCP_WRITE_ACCESS_NOT_ALLOWED"


class ValueAccess:
    """Mixed into :class:`Session`: values by name. Layouts and codecs are kept per name (the A2L does not change)."""

    lock: Any
    _known_memory: KnownMemory
    _layouts: dict
    _resolved: dict
    _codecs: dict
    _readers: dict
    _model: A2lModel | None

    @property
    def model(self: Session) -> A2lModel:
        """The A2L's objects (:class:`~workbench.a2l.model.A2lModel`)."""
        model = self._model
        if model is None:  # kept: finding the module again costs more than a polled read's own work
            model = self._model = self.doc.model(self.module)
        return model

    # --- reading ------------------------------------------------------------------------------

    def read(self: Session, name: str, *, page: str | int | None = None, raw: bool = False) -> Any:
        """The physical value of a MEASUREMENT or calibration object: a number or text, or an array
        (a measurement array, a VAL_BLK, a CURVE's or MAP's values [x, y], an AXIS_PTS' points).

        :param page: read a calibration from ``"working"`` or ``"reference"`` (default: the page XCP is on).
        :param raw: the value as the ECU holds it, before the COMPU_METHOD (integers for integer types).
        :raises UnknownSymbolError: no such object (the closest names are suggested).
        """
        reader = self._readers.get(name) if page is None else None
        if reader is not None:  # read before, static and in one span: one command and its decoding
            self.require_application()  # the ECU may be in its boot loader since (reconnected after a reset)
            span, decode = reader
            with self.lock:  # the hot path of polling: one command, no merging of spans
                data = self._read_block(span, {name: [span]})
            value = decode(data)
        else:
            value = self.read_many([name], page=page)[name]
            self._keep_reader(name)
        return self.to_raw(name, value) if raw else value

    def _keep_reader(self: Session, name: str) -> None:
        """Remember how to read ``name`` again when its bytes lie in one span that never moves."""
        codec = self._codecs.get(name)
        if codec is not None:
            self._readers[name] = (codec.span, codec.decode)
            return
        resolved = self._resolved.get(name)
        if resolved is not None and resolved.spans() == [resolved.span()]:
            self._readers[name] = (resolved.span(), value_decoder(resolved))

    def to_raw(self: Session, name: str, value: Any) -> Any:
        """A physical value of ``name`` as its raw data type holds it (enum texts become their numbers)."""
        return to_raw(self.model, name, value)

    def read_value(self: Session, name: str, *, page: str | int | None = None) -> CalValue:
        """A calibration object's value with its axes and unit (:class:`~workbench.calib.values.CalValue`)."""
        obj = self.model.object(name)
        if not isinstance(obj, (Characteristic, AxisPts)):
            raise InputError(f"{name} is a {type(obj).__name__.upper()}, not a calibration object: use read()")
        self.require_application()
        with self.lock, self.on_page(page, self.segments_of([name]) if page is not None else None):
            resolved = self._resolve([name])[name]
            return resolved.decode(self._fresh_bytes(resolved.spans(), name))

    def read_many(self: Session, names: Iterable[str], *, page: str | int | None = None) -> dict[str, Any]:
        """Several objects at once, neighbouring addresses merged into few UPLOADs: ``{name: value}``."""
        names = list(dict.fromkeys(names))
        codecs = {name: self._codec(name) for name in names if isinstance(self.model.object(name), Measurement)}
        self.require_application()
        with self.lock, self.on_page(page, self.segments_of(names) if page is not None else None):
            resolved = self._resolve([name for name in names if name not in codecs])
            owners = {name: [codec.span] for name, codec in codecs.items()}
            owners.update({name: layout.spans() for name, layout in resolved.items()})
            data = self._read_spans([span for spans in owners.values() for span in spans], owners)
        memory = MemoryBytes(data)  # indexed once for all the objects
        return {name: codecs[name].decode(data[codecs[name].span]) if name in codecs
                else resolved[name].decode(memory).value for name in names}

    def _codec(self: Session, name: str) -> MeasurementCodec:
        codec = self._codecs.get(name)
        if codec is None:
            codec = self._codecs[name] = measurement_codec(self.model, name)
        return codec

    def _resolve(self: Session, names: list[str], read=None) -> dict[str, ResolvedLayout]:
        """Each object placed in memory; layouts kept per name, resolved ones too unless they read counts
        (``read(spans) -> {span: bytes}``, default: from the ECU)."""
        layouts = {name: self._plan(name) for name in names}
        static = {name: self._resolved[name] for name in names if name in self._resolved}
        dynamic = [name for name in names if name not in static]
        counts = [span for name in dynamic for span in layouts[name].fixed_part()]
        firsts = (read or self._read_spans)(counts) if counts else {}
        for name in dynamic:
            resolved = static[name] = layouts[name].resolve(firsts)
            if not layouts[name].needs_counts:
                self._resolved[name] = resolved
        return static

    def _read_spans(self: Session, spans: Iterable[Span], owners: dict[str, list[Span]] | None = None
                    ) -> dict[Span, bytes]:
        """The bytes of ``spans``; a refused read names the objects of ``owners`` (name -> its spans) it
        concerned and where."""
        return read_merged(spans, lambda block: self._read_block(block, owners))

    def _read_block(self: Session, block: Span, owners: dict[str, list[Span]] | None) -> bytes:
        try:
            return self.master.read(block.address, block.size, block.extension)
        except XcpCommandError as exc:
            raise exc.about(_reading(block, owners or {})) from None

    # --- writing ------------------------------------------------------------------------------

    def write(self: Session, name: str, value: Any, *, allow_extended_limits: bool = False) -> CalValue:
        """Write a calibration in physical units and return what the ECU holds afterwards.

        ``value``: a number or an enum's text (VALUE), a ``str`` (ASCII), an array of the object's
        shape (VAL_BLK; a CURVE's or MAP's values, indexed [x, y], its axes unchanged), or a
        :class:`CalValue` (new axis points too). Only the elements that differ from what the session
        knows are sent (see the module docstring); one cell: :meth:`write_cells`.

        :raises InputError: unknown name, read-only object, a value beyond the limits, of the wrong
            shape or outside the writable memory (LimitsError, ConversionError are InputErrors).
        :raises EpkMismatchError: the session is read-only (the ECU's EPK differs from the A2L's).
        :raises PageError: XCP is on a page it may not write (the reference page); nothing was sent.
        :raises XcpCommandError, XcpTimeoutError: the ECU refused or did not answer (the message says
            which fields were written before).
        """
        with self.lock:
            self.require_writable()
            layout, edits = self._planned(name, value, allow_extended_limits)
            self._apply(name, edits)
            return self._written_value(name, layout)

    def write_many(self: Session, values: Mapping[str, Any], *, allow_extended_limits: bool = False
                   ) -> dict[str, CalValue]:
        """Write several calibrations as one step (a sweep's gains, a controller's parameters): every value checked
        as :meth:`write` checks it before anything is sent, then the bytes that change written with those of the
        objects beside them in one DOWNLOAD (a struct's members, neighbours in the A2L's memory) and read back
        at once. Returns what the ECU holds, by name. Three gains side by side take one SET_MTA, DOWNLOAD and
        read-back instead of three of each.

        :raises InputError: as :meth:`write`, or two of the objects give other bytes for the same address (a map
            and its shared axis with other points); nothing was sent.
        :raises WorkbenchError: a write failed; the message names the objects that reached the ECU.
        """
        with self.lock:
            self.require_writable()
            planned = {name: self._planned(name, value, allow_extended_limits) for name, value in values.items()}
            self._apply_many([edit for _, edits in planned.values() for edit in edits])
            return {name: self._written_value(name, layout) for name, (layout, _) in planned.items()}

    def _planned(self: Session, name: str, value: Any, extended: bool) -> tuple[ResolvedLayout, list[ByteEdit]]:
        """``name`` placed in memory and the edits that write ``value`` there, every check made (nothing sent)."""
        static = self._static_layout(name)
        target = checked_value(self.model, name, value, extended=extended, writable=self.writable_spans(),
                               resolved=static)
        layout = static or self._write_layout(name)
        bits = getattr(layout.obj, "bit_mask", None) is not None  # the other bits of a BIT_MASK come from the ECU
        edits = None if bits else layout.encode(target)  # the conversion's refusals: before anything is sent
        self._check_pages(name, layout.spans())
        if bits or layout.kind not in ("VALUE", "ASCII"):  # only the elements that differ
            edits = layout.encode(target, self._known_bytes(layout.spans()))
            if not edits:  # nothing differs from what the session knew: make sure
                edits = layout.encode(target, self._fresh_bytes(layout.spans()))
        return layout, edits

    def write_cells(self: Session, name: str, cells: Mapping[Any, Any], *, allow_extended_limits: bool = False
                    ) -> dict[tuple[int, ...], Any]:
        """Write single values of a VAL_BLK, CURVE, MAP or CUBOID, or points of an AXIS_PTS: ``cells`` maps an
        index ``(x, y, ...)`` (an int for one axis) to a physical value. Only those values are sent and read
        back; returns ``{(x, y, ...): value the ECU holds}``. An AXIS_PTS' points are checked in place among
        the points the ECU holds (monotony), which the session reads unless it knows them.

        :raises: as :meth:`write` (an index outside the object is a LimitsError).
        """
        with self.lock:
            self.require_writable()
            static = self._static_layout(name)
            indexed = checked_cells(self.model, name, cells, extended=allow_extended_limits,
                                    writable=self.writable_spans(), resolved=static)
            if isinstance(self.model.object(name), AxisPts):
                return self._write_axis_points(name, indexed, static, allow_extended_limits)
            layout = static or self._write_layout(name)
            spans = [cell_span(layout, index) for index in indexed]
            bits = layout.obj.bit_mask is not None
            edits = None if bits else cell_edits(layout, indexed)
            self._check_pages(name, spans)
            if bits:
                edits = cell_edits(layout, indexed, self._known_bytes(spans))
            self._apply(name, edits)
            return cell_values(layout, self._known_bytes(spans), indexed)

    def _write_axis_points(self: Session, name: str, points: dict[tuple[int, ...], Any], static: ResolvedLayout | None,
                           extended: bool) -> dict[tuple[int, ...], Any]:
        """The axis as the session knows it with ``points`` in place, written as :meth:`write` writes it (its order
        and memory checked, only the points that change sent)."""
        layout = static or self._write_layout(name)
        axis = axis_with_points(name, layout.decode(self._known_bytes(layout.spans())).value, points)
        written = self.write(name, axis, allow_extended_limits=extended).value
        return {index: written[index[0]] for index in points}

    def writable_spans(self: Session) -> list[Span] | None:
        """Where the A2L lets calibrations be written (None: the A2L has no MEMORY_SEGMENTs to tell)."""
        return self._writable_memory

    @cached_property
    def _writable_memory(self: Session) -> list[Span] | None:  # the A2L does not change: read once
        return writable_spans(self.doc.memory_segments(self.module), self.config.segments)

    def _static_layout(self: Session, name: str) -> ResolvedLayout | None:
        """A calibration object placed in memory from the A2L alone; None when a count lies in ECU memory
        (or ``name`` is no calibration object: the checks say so)."""
        if name in self._resolved:
            return self._resolved[name]
        if self.model.kind_of(name) not in ("CHARACTERISTIC", "AXIS_PTS") or self._plan(name).needs_counts:
            return None
        resolved = self._resolved[name] = self._plan(name).resolve()
        return resolved

    def _plan(self: Session, name: str) -> ObjectLayout:
        if name not in self._layouts:
            self._layouts[name] = object_layout(self.model, name)
        return self._layouts[name]

    def _write_layout(self: Session, name: str) -> ResolvedLayout:
        """The object placed in memory, counts stored in the ECU taken from what the session knows."""
        return self._resolve([name], self._known_bytes)[name]

    def remember(self: Session, data: Mapping[Span, bytes]) -> None:
        """Calibration bytes the caller has just read from the ECU (e.g. with :meth:`read_memory`, on
        the page XCP is on, nothing written since): known from now on, as if the session had read them,
        so that a write there reads nothing again (forgotten at the next CONNECT, page switch or
        another's DOWNLOAD)."""
        with self.lock:
            self._known().store(data)

    def _known(self: Session) -> KnownMemory:
        self._known_memory.valid(self.master.memory_changes)
        return self._known_memory

    def _known_bytes(self: Session, spans: Iterable[Span]) -> dict[Span, bytes]:
        """The bytes of ``spans``: as the session knows them, the others read (and known from then on)."""
        known = self._known()
        spans = list(spans)
        missing = [span for span in spans if known.get(span) is None]
        if missing:
            known.store(self._read_spans(missing))
        return {span: known.get(span) for span in spans}

    def _fresh_bytes(self: Session, spans: Iterable[Span], name: str | None = None) -> dict[Span, bytes]:
        spans = list(spans)
        data = self._read_spans(spans, {name: spans} if name else None)
        self._known().store(data)
        return data

    def _apply(self: Session, name: str, edits: list[ByteEdit]) -> None:
        """Check the edits' memory and page, DOWNLOAD each, read them back and compare byte for byte."""
        if not edits:
            return
        check_inside(name, ((edit.span, edit.field) for edit in edits), self.writable_spans())
        self._known()
        done: list[ByteEdit] = []
        for edit in edits:
            try:
                self.master.write(edit.address, edit.data, edit.extension)
            except WorkbenchError as exc:
                if not done:
                    self._explain_refusal(name, edit, exc)
                    raise
                raise PartialWriteError(name, [_field(e) for e in done], _field(edit), exc) from exc
            done.append(edit)
        back = self._read_spans([edit.span for edit in edits])
        self._known_memory.keep(self.master.memory_changes)  # the changes since were these edits
        self._known_memory.store(back)
        wrong = [_field(edit) for edit in edits if back[edit.span] != edit.data]
        if wrong:
            raise WorkbenchError(f"{name}: the ECU holds other bytes than were written to {', '.join(wrong)} "
                                 "(a read-only area, or the ECU overwrote them)")

    def _apply_many(self: Session, edits: list[ByteEdit]) -> None:
        """The edits of several objects in runs of adjacent bytes (a DOWNLOAD each), read back at once."""
        for edit in edits:
            check_inside(edit.name, [(edit.span, edit.field)], self.writable_spans())
        runs: list[tuple[ByteEdit, list[ByteEdit]]] = []  # (the bytes of a run, the edits in it)
        for edit in sorted(edits, key=lambda e: (e.extension, e.address)):
            run = runs[-1] if runs else None
            if run is not None and run[0].extension == edit.extension and edit.address < run[0].span.end:
                offset = edit.address - run[0].address  # overlapping: the same bytes, or two objects disagree
                if run[0].data[offset:offset + len(edit.data)] != edit.data[:len(run[0].data) - offset]:
                    raise InputError(f"{edit.name} and {run[1][-1].name} give other bytes for {edit.span}: write "
                                     "them one after the other (Session.write)")
                edit = replace(edit, address=run[0].span.end, data=edit.data[run[0].span.end - edit.address:])
            if run is not None and run[0].extension == edit.extension and edit.address == run[0].span.end:
                runs[-1] = (replace(run[0], data=run[0].data + edit.data), run[1] + [edit])
            else:
                runs.append((edit, [edit]))
        self._known()
        for index, (run, _) in enumerate(runs):
            try:
                self.master.write(run.address, run.data, run.extension)
            except WorkbenchError as exc:
                if index == 0:
                    self._explain_refusal(run.name, run, exc)
                    raise
                reached = {e.name for _, inside in runs[:index] for e in inside}
                missed = {e.name for _, inside in runs[index:] for e in inside}
                half = sorted(reached & missed)
                raise WorkbenchError(f"{exc}; reached the ECU: {', '.join(sorted(reached - missed)) or 'none'}"
                                     + (f", in part: {', '.join(half)}" if half else "")
                                     + f"; not written: {', '.join(sorted(missed - reached))}") from exc
        back = self._read_spans([run.span for run, _ in runs])
        self._known_memory.keep(self.master.memory_changes)  # the changes since were these edits
        self._known_memory.store(back)
        wrong = sorted({edit.name for run, inside in runs for edit in inside if back[run.span][
            edit.address - run.address:edit.span.end - run.address] != edit.data})
        if wrong:
            raise WorkbenchError(f"{', '.join(wrong)}: the ECU holds other bytes than were written (a read-only area, "
                                 "or the ECU overwrote them)")

    def _written_value(self: Session, name: str, layout: ResolvedLayout) -> CalValue:
        """The value the ECU holds now: the bytes read back, the rest as the session knows it."""
        plan = self._layouts[name]
        if plan.needs_counts:
            layout = plan.resolve(self._known_bytes(plan.fixed_part()))
        return layout.decode(self._known_bytes(layout.spans()))

    # --- pages --------------------------------------------------------------------------------

    def _check_pages(self: Session, name: str, spans: list[Span]) -> None:
        """:raises PageError: a span lies in a calibration segment whose page XCP accesses may not be written."""
        for segment in self._segments_of(spans):
            protected = {p.number for p in segment.pages if p.xcp_write_access == _NOT_WRITABLE}
            page = self._xcp_page(segment.number) if protected else None
            if page in protected:
                working, reference = self.page_numbers(segment.number)
                which = "the reference page" if page == reference else f"page {page}"
                option = f" --segment {segment.number}" if segment.number else ""
                raise PageError(f"{name} is not written: {which} of segment {segment.number} is active and XCP may "
                                f"not write it; switch to the working page first: `workbench cal page working{option}` "
                                f"(Session.set_page('working'))")

    def _segments_of(self: Session, spans: list[Span]) -> list[XcpSegment]:
        return [segment for segment in self._page_segments()
                if any(span.extension == segment.address_extension
                       and segment.address <= span.address < segment.address + segment.size for span in spans)]

    def _page_segments(self: Session) -> tuple[XcpSegment, ...]:
        """The calibration segments the page switching uses (:meth:`Session.calibration_segments`: the A2L's,
        else the ECU's); none when neither tells, or the ECU offers no CAL/PAG now (boot)."""
        info = self.master.connect_info
        if not self.config.segments and info is not None and not info.resources & Resource.CAL_PAG:
            return ()
        try:
            return self.calibration_segments()
        except InputError:
            return ()

    def _xcp_page(self: Session, segment: int) -> int | None:
        """The page XCP accesses in ``segment`` (asked once, then known); None: the slave does not say."""
        master = self.master
        if segment in master.xcp_pages:
            return master.xcp_pages[segment]
        info = master.connect_info
        if info is not None and not info.resources & Resource.CAL_PAG:
            return None
        try:
            return master.get_cal_page(segment, 0x02)
        except XcpCommandError as exc:
            if exc.command == "UNLOCK":  # the key met on the way was refused and the slave disconnected: say that
                raise
            log.debug("GET_CAL_PAGE of segment %d: %s", segment, exc)
            return None

    def _explain_refusal(self: Session, name: str, edit: ByteEdit, exc: WorkbenchError) -> None:
        """A DOWNLOAD refused as write-protected: when XCP turns out to be on a page it may not write
        (switched by another master since the session asked), say so instead."""
        if isinstance(exc, XcpCommandError) and exc.code in (Err.WRITE_PROTECTED, Err.ACCESS_DENIED):
            for segment in self._segments_of([edit.span]):
                self.master.xcp_pages.pop(segment.number, None)
            try:
                self._check_pages(name, [edit.span])
            except PageError as page_error:
                raise page_error from exc


def _field(edit: ByteEdit) -> str:
    return f"{edit.name}.{edit.field}" if edit.field else edit.name or str(edit.span)


def _reading(block: Span, owners: dict[str, list[Span]]) -> str:
    """What a refused read was for: the objects in ``block`` and where, and the likely cause of an
    address 0 (an A2L whose addresses were never updated from the ELF)."""
    names = [name for name, spans in owners.items()
             if any(s.extension == block.extension and s.address < block.end and block.address < s.end for s in spans)]
    shown = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
    return (f"reading {shown} ({block})" if names else f"reading {block}") + placeholder_hint(block.address)
