"""Offline calibration: values by name in a flash file (s19/hex) the build produced, no ECU, as CANape and INCA edit
a HEX file. The counterpart of the session's values by name::

    from workbench import ImageCalibration
    from workbench.calib.dataset import load_dataset
    from workbench.sync import apply_dataset

    cal = ImageCalibration.open("FLCU.s19", "FLCU.a2l")
    cal.read("xsSWITCH_TANK_THR")                   # 20.0, physical, as Session.read
    cal.write("xsSWITCH_TANK_THR", 22.5)            # checked as online (limits, shape, texts, writable memory)
    cal.write_cells("zvRailPConv", {(3,): 41.0})     # one point of a curve
    apply_dataset(cal, load_dataset("tuned.dcm"))   # every object checked first, then written
    cal.changed()                                   # ['xsSWITCH_TANK_THR', ...]: what differs from the file
    cal.save("FLCU_tuned.s19")                      # atomically; only the records of changed bytes rewritten

The image is read at the A2L's addresses as the cache sync and the window read it
(:class:`~workbench.sync.areas.ImageView`: through the calibration segments' ADDRESS_MAPPING, CAL RAM onto CAL ROM),
and decoded and encoded by the same codec as the ECU's memory: byte order, record layouts, conversions, limits and
the ``_EN``/``_VALUE`` fix calibrations are the online ones. Unlike the sync, which reads what a file lacks as erased
flash (what the boot would copy), reading or writing an object whose bytes the file does not hold is refused naming
the object and the addresses: an edit must never invent bytes the build did not produce. An image whose EPK
differs from the A2L's is read-only, as a session on such an ECU is; a write that would touch the EPK is refused.

Saving keeps the file as it was but the records that hold a changed byte (:func:`~workbench.image.patched_text`),
so a diff of the two files shows the edits alone; another extension than the input's converts the format.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from workbench.a2l.objects import AxisPts, Measurement
from workbench.calib.cells import axis_with_points, cell_edits, cell_span, cell_values
from workbench.calib.codec import to_raw, value_edits
from workbench.calib.fixes import FixPair, fix_pairs_of, resolve_fix
from workbench.calib.layout import object_layout
from workbench.calib.memory import ByteEdit, MemoryBytes, Span
from workbench.calib.values import CalValue
from workbench.calib.writable import check_inside, checked_cells, checked_value, writable_spans
from workbench.errors import EpkMismatchError, InputError, epk_text, same_epk
from workbench.image import AddressRange, MemoryImage, is_intel_hex
from workbench.sync.areas import ImageView, calibration_areas, image_epks
from workbench.sync.store import ByteStore
from workbench.sync.values import calibration_names, object_layouts, resolve_all, without_name

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument
    from workbench.a2l.model import A2lModel
    from workbench.calib.dataset import Dataset
    from workbench.session.fixes import FixState
    from workbench.sync.reference import ImageReference

__all__ = ["ImageCalibration"]


class ImageCalibration:
    """The calibrations of ``doc`` (an A2L) in ``image``, read and written by name in physical units.

    :param text: the S-record or Intel HEX text ``image`` was loaded from; :meth:`save` rewrites only its records
        that changed (None: an image built in code, saved by bincopy).
    :param path: the file it came from (names it in messages).
    :param accept_epk_mismatch: write although the image's EPK differs from the A2L's (read-only otherwise).
    """

    def __init__(self, doc: A2lDocument, image: MemoryImage, *, text: str | None = None,
                 path: str | Path | None = None, module: str | None = None, accept_epk_mismatch: bool = False):
        from workbench.a2l import read_xcp_config
        from workbench.errors import A2lParseError

        self.doc, self.image, self.module = doc, image, module
        self.accept_epk_mismatch = accept_epk_mismatch
        self.path = Path(path) if path is not None else None
        self._text = text
        self.model: A2lModel = doc.model(module)
        try:
            self.config = read_xcp_config(doc, module)
        except A2lParseError:  # no IF_DATA XCP (an A2L for offline work): the DATA MEMORY_SEGMENTs as they stand
            self.config = None
        self.view = ImageView(image, calibration_areas(doc, self.config, module))
        self.lock = threading.RLock()  # a window's workers read while the user edits
        self._original = ByteStore()  # the file's bytes where something was written since (image addresses)
        self._edited: dict[str, None] = {}  # objects written, in order
        self._writable = writable_spans(doc.memory_segments(module), self.config.segments if self.config else ())

    @classmethod
    def open(cls, path: str | Path, a2l: str | Path | A2lDocument | None = None, *, module: str | None = None,
             accept_epk_mismatch: bool = False) -> ImageCalibration:
        """The flash file ``path`` (s19/s28/s37/srec/mot or Intel HEX) with the A2L ``a2l`` (default: the demo's).

        :raises InputError: either file is missing or malformed (the message names file:line).
        """
        from workbench import demo
        from workbench.a2l import A2lDocument
        from workbench.a2l.includes import load_a2l_to_work
        from workbench.fileio import read_input
        from workbench.image import parse_image

        doc = a2l if isinstance(a2l, A2lDocument) else load_a2l_to_work(a2l or demo.a2l())
        path = Path(path)
        text = read_input(path, "an S-record or Intel HEX file").decode("ascii", errors="replace")
        return cls(doc, parse_image(text, path), text=text, path=path, module=module,
                   accept_epk_mismatch=accept_epk_mismatch)

    @property
    def label(self) -> str:
        return self.path.name if self.path is not None else "the image"

    # --- the EPK ------------------------------------------------------------------------------

    @property
    def epk(self) -> str | None:
        """The EPK the image holds at the A2L's ADDR_EPK: where it names several (one per part), the first that
        differs from the A2L's, else the first the image holds (None: the A2L names none, or the image lacks it)."""
        held = [found.text for found in image_epks(self.view, self.doc, self.module) if found.text is not None]
        expected = self.doc.epk(self.module)
        return next((text for text in held if not same_epk(text, expected)), held[0] if held else None)

    def require_writable(self) -> None:
        """:raises EpkMismatchError: the image's EPK differs from the A2L's: the A2L does not describe it."""
        expected, found = self.doc.epk(self.module), self.epk
        if found is not None and not same_epk(found, expected) and not self.accept_epk_mismatch:
            error = EpkMismatchError(expected, found)
            error.args = ((f"{self.label} holds the EPK {epk_text(found)}, the A2L {epk_text(expected)}: the A2L "
                           "does not describe this software; the image is read-only (--accept-epk-mismatch, "
                           "accept_epk_mismatch=True: write anyway)"),)
            raise error

    # --- reading ------------------------------------------------------------------------------

    def read(self, name: str, *, raw: bool = False) -> Any:
        """The physical value of a calibration object (as :meth:`Session.read <workbench.session.Session.read>`:
        a number or text, or an array indexed [x, y]); ``raw``: as the memory holds it, before the COMPU_METHOD.

        :raises UnknownSymbolError: no such object. :raises InputError: a measurement (an image holds none), or
            the file lacks bytes of the object (the message names them).
        """
        value = self.read_value(name).value
        return to_raw(self.model, name, value) if raw else value

    def read_value(self, name: str) -> CalValue:
        """A calibration object's value with its axes and unit."""
        return self.read_many([name], values=True)[name]

    def read_many(self, names: Iterable[str], *, values: bool = False) -> dict[str, Any]:
        """``{name: value}`` of several objects (``values``: whole :class:`CalValue`\\ s)."""
        names = list(dict.fromkeys(names))
        for name in names:
            if isinstance(self.model.object(name), Measurement):
                raise InputError(f"{name} is a MEASUREMENT: a flash image holds calibrations only (measurements "
                                 "live in the ECU's RAM)")
        layouts, problems = object_layouts(self.model, names)
        found, failed = self._decode(layouts)
        problems.update(failed)
        if problems:
            name, why = next(iter(problems.items()))
            raise InputError(f"{name}: {why}")
        return {name: found[name] if values else found[name].value for name in names}

    def dataset(self, names: Iterable[str] | None = None) -> Dataset:
        """The image's values of every calibration (or of ``names``: names and globs) as a dataset, as
        :func:`~workbench.sync.read_dataset` reads the ECU's; objects the file lacks are left out, each named in
        ``dataset.notes`` (named explicitly: an :class:`InputError`)."""
        from workbench.sync.snapshot import dataset_of

        wanted = calibration_names(self.model, names)
        layouts, problems = object_layouts(self.model, wanted)
        values, failed = self._decode(layouts)
        problems.update(failed)
        if problems and names is not None:
            name, why = next(iter(problems.items()))
            raise InputError(f"{name}: {why}")
        dataset = dataset_of(self.model, values, problems, f"{self.label}, EPK {self.epk or 'not held'}")
        dataset.source = str(self.path or "image")
        return dataset

    def fetch(self, spans: Iterable[Span]) -> dict[Span, bytes]:
        """``{span: bytes}`` at the A2L's addresses (bytes the file lacks read as erased flash, as the sync reads
        them; :meth:`lacking` says where)."""
        return self.view.fetch(list(dict.fromkeys(spans)))

    def lacking(self, name: str, spans: Iterable[Span]) -> str | None:
        """Why ``name`` cannot be read or written at ``spans``: the first span whose bytes the file lacks (None:
        it holds them all)."""
        for span in spans:
            missing = self.view.lacking(span)
            if missing:
                where = f"{span}" + (f" (at {' '.join(map(str, missing))} in the file)"
                                     if missing[0].start != span.address else "")
                return f"{name}: {self.label} holds no bytes at {where}"
        return None

    def _decode(self, layouts) -> tuple[dict[str, CalValue], dict[str, str]]:
        with self.lock:  # a write under way in another thread (the window's workers) changes the image
            return self._decode_held(layouts)

    def _decode_held(self, layouts) -> tuple[dict[str, CalValue], dict[str, str]]:
        resolved, problems = resolve_all(layouts, self.fetch)
        for name, layout in list(resolved.items()):
            why = self.lacking(name, list(layouts[name].fixed_part()) + layout.spans())
            if why is not None:
                problems[name] = without_name(name, why)
                del resolved[name]
        data = MemoryBytes(self.fetch(span for layout in resolved.values() for span in layout.spans()))
        return {name: layout.decode(data) for name, layout in resolved.items()}, problems

    # --- writing ------------------------------------------------------------------------------

    def writable_spans(self) -> list[Span] | None:
        """Where the A2L lets calibrations be written (None: it has no MEMORY_SEGMENTs to tell), as online."""
        return self._writable

    def write(self, name: str, value: Any, *, allow_extended_limits: bool = False) -> CalValue:
        """Write a calibration into the image (in memory; :meth:`save` writes the file) and return what it holds now.
        ``value`` as :meth:`Session.write <workbench.session.Session.write>` takes it; only the bytes that change
        are written.

        :raises InputError: unknown name, read-only object, a value beyond the limits, of the wrong shape, outside
            the writable memory, or where the file holds no bytes (LimitsError, ConversionError are InputErrors).
        :raises EpkMismatchError: the image's EPK differs from the A2L's.
        """
        with self.lock:
            self.require_writable()
            target = checked_value(self.model, name, value, extended=allow_extended_limits, writable=self._writable)
            layout = object_layout(self.model, name)
            self._require_held(name, layout.fixed_part())
            edits = value_edits(self.model, target, self._held_read(name), check=False)
            self._apply(name, edits)
            return self.read_value(name)

    def write_cells(self, name: str, cells: Mapping[Any, Any], *, allow_extended_limits: bool = False
                    ) -> dict[tuple[int, ...], Any]:
        """Write single values of an array object (``{(x, y): value}``), or points of an AXIS_PTS (their order
        checked among the image's points), as :meth:`Session.write_cells <workbench.session.Session.write_cells>`;
        returns ``{(x, y, ...): value now held}``."""
        with self.lock:
            self.require_writable()
            indexed = checked_cells(self.model, name, cells, extended=allow_extended_limits, writable=self._writable)
            layout = object_layout(self.model, name)
            self._require_held(name, layout.fixed_part())
            resolved = layout.resolve(self.fetch(layout.fixed_part()))
            if isinstance(self.model.object(name), AxisPts):
                axis = axis_with_points(name, self.read(name), indexed)
                written = self.write(name, axis, allow_extended_limits=allow_extended_limits).value
                return {index: written[index[0]] for index in indexed}
            spans = [cell_span(resolved, index) for index in indexed]
            check_inside(name, ((span, f"the value {list(index)}") for span, index in zip(spans, indexed)),
                         self._writable)
            self._require_held(name, spans)
            self._apply(name, cell_edits(resolved, indexed, self.fetch(spans)))
            return cell_values(resolved, self.fetch(spans), indexed)

    def _held_read(self, name: str):
        def read(span: Span) -> bytes:
            self._require_held(name, [span])
            return self.view.read(span)
        return read

    def _require_held(self, name: str, spans: Iterable[Span]) -> None:
        why = self.lacking(name, spans)
        if why is not None:
            raise InputError(f"{why}; not written")

    def _apply(self, name: str, edits: list[ByteEdit]) -> None:
        """Write ``edits`` into the image, keeping the file's bytes they replace (what :meth:`changed` compares)."""
        check_inside(name, ((edit.span, edit.field) for edit in edits), self._writable)
        self._require_held(name, [edit.span for edit in edits])
        self._require_outside_epk(name, edits)
        for edit in edits:
            for start, size in self.view.pieces(edit.span):
                if self._original.get(Span(start, size)) is None:
                    for piece_start, piece_size in _unknown(self._original, start, size):
                        self._original.put(piece_start, self.image.read(piece_start, piece_size))
            self.view.write(edit.span, edit.data)
        if edits:
            self._edited[name] = None

    def _require_outside_epk(self, name: str, edits: list[ByteEdit]) -> None:
        for found in image_epks(self.view, self.doc, self.module):
            epk = [AddressRange(start, start + size) for start, size in self.view.pieces(found.span)]
            for edit in edits:
                for start, size in self.view.pieces(edit.span):
                    if any(start < e.end and e.start < start + size for e in epk):
                        raise InputError(f"{name}: its bytes at {edit.span} hold the EPK (ADDR_EPK "
                                         f"0x{found.place.address:X}): not written")

    # --- fix calibrations ----------------------------------------------------------------------

    def fixes(self) -> list[FixState]:
        """Every ``_EN``/``_VALUE`` pair of the A2L with its override value and switch as the image holds them (no
        live value: an image has none); a pair whose bytes the file lacks is left out."""
        pairs = fix_pairs_of(self.model)
        layouts, _ = object_layouts(self.model, [name for pair in pairs for name in (pair.enable, pair.value)])
        values, _ = self._decode(layouts)  # one pass; a pair the file lacks has no values
        return [self._fix_state(pair, {name: values[name].value for name in (pair.enable, pair.value)})
                for pair in pairs if pair.enable in values and pair.value in values]

    def override(self, signal: str, value: Any) -> FixState:
        """The image starts with ``signal`` replaced by ``value`` (the _VALUE's units): _VALUE, then _EN = 1, both
        checked before either is written, as :meth:`Session.override <workbench.session.Session.override>`."""
        pair = resolve_fix(fix_pairs_of(self.model), signal)
        with self.lock:
            for name, written in ((pair.value, value), (pair.enable, 1)):
                checked_value(self.model, name, written, writable=self._writable)
            self.write(pair.value, value)
            self.write(pair.enable, 1)
            return self._fix_state(pair, self.read_many([pair.enable, pair.value]))

    def release(self, signal: str) -> FixState:
        """The image starts with ``signal`` computed by the ECU: _EN = 0 (the _VALUE stays for the next time)."""
        pair = resolve_fix(fix_pairs_of(self.model), signal)
        with self.lock:
            self.write(pair.enable, 0)
            return self._fix_state(pair, self.read_many([pair.enable, pair.value]))

    def _fix_state(self, pair: FixPair, values: Mapping[str, Any]) -> FixState:
        from workbench.session.fixes import FixState  # the session's: imported only here (the session is heavy)

        active = to_raw(self.model, pair.enable, values[pair.enable]) == 1
        return FixState(pair, None, values[pair.value], active, None, "an image holds no live values")

    # --- what changed, saving -------------------------------------------------------------------

    def changes(self) -> list[AddressRange]:
        """The image addresses whose bytes differ from the file's, merged, in order."""
        with self.lock:
            return self._changes()

    def _changes(self) -> list[AddressRange]:
        found: list[AddressRange] = []
        for span in self._original.spans():
            before, now = self._original.get(span), self.image.read(span.address, span.size)
            run = None
            for offset in range(span.size):
                if before[offset] != now[offset]:
                    run = run if run is not None else offset
                elif run is not None:
                    found.append(AddressRange(span.address + run, span.address + offset))
                    run = None
            if run is not None:
                found.append(AddressRange(span.address + run, span.end))
        return found

    def changed(self) -> list[str]:
        """The objects written whose bytes now differ from the file's, in the order written."""
        with self.lock:
            changes = self._changes()
            return self._changed(changes) if changes else []

    def _changed(self, changes: list[AddressRange]) -> list[str]:
        found = []
        for name in self._edited:
            layout = object_layout(self.model, name)
            spans = layout.resolve(self.fetch(layout.fixed_part())).spans()
            pieces = [AddressRange(start, start + size) for span in spans for start, size in self.view.pieces(span)]
            if any(p.start < c.end and c.start < p.end for p in pieces for c in changes):
                found.append(name)
        return found

    def reference(self) -> ImageReference:
        """The image as it is now (a copy), as the cache sync compares it with an ECU (``sync_compare``)."""
        from workbench.sync.reference import ImageReference

        with self.lock:
            copy = self.image.crop(0, 1 << 64)
        return ImageReference(self.path or Path("image"), copy)

    @property
    def modified(self) -> bool:
        """Whether the image differs from the file it was loaded from."""
        return bool(self.changes())

    def notes(self, file: str | Path = "FILE") -> list[str]:
        """What to know before flashing the changed image (saved as ``file``): the flash regions the changes lie in
        and the command that flashes them, the EPK kept, and the checksums that do not follow the changes."""
        from workbench.flash.layout import FlashLayout

        changes = self.changes()
        if not changes:
            return []
        regions = [r.name for r in FlashLayout.from_a2l(self.doc, self.config, self.module).regions
                   if any(r.start < c.end and c.start < r.start + r.size for c in changes)]
        notes = []
        if regions:
            options = " ".join(f"--region {name}" for name in regions)
            epk = f"; its EPK {epk_text(self.epk)} is the original's" if self.epk is not None else ""
            notes.append(f"the changes lie in {', '.join(regions)}: `workbench flash {file} {options}` programs them "
                         f"(verified against the new bytes){epk}")
        notes.append("a checksum the build keeps in the image over the calibration data (one the A2L does not "
                     "describe, checked by some boot loaders) is not computed again")
        return notes

    def save(self, path: str | Path) -> Path:
        """Write the image to ``path`` atomically: the input's format, every line as it was but the records that
        hold a changed byte (another extension than the input's, or an image built in code: written anew by
        bincopy, S-records or Intel HEX by the extension). After it the image counts as that file's.

        :raises InputError: ``path`` cannot be written, or is a read-only file (the message names it).
        """
        from workbench.fileio import write_output
        from workbench.image import patched_text
        from workbench.image.files import image_suffixes, is_image_file

        path = Path(path)
        if not is_image_file(path):
            raise InputError(f"{path}: an image is saved as {image_suffixes()}")
        with self.lock:
            if self._text is not None and is_intel_hex(path) == is_intel_hex(self.path or path):
                text = patched_text(self._text, self.image, self.changes())
                write_output(path, text.encode("ascii"))
                self._text = text
            else:
                self.image.save(path)
                self._text = None
            self.path, self._original, self._edited = path, ByteStore(), {}
        return path


def _unknown(store: ByteStore, start: int, size: int) -> list[tuple[int, int]]:
    """The runs of ``[start, start + size)`` the store holds no byte of."""
    held = [AddressRange(s.address, s.end) for s in store.spans()]
    return [(part.start, part.size) for part in AddressRange(start, start + size).outside(held)]
