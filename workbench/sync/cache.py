"""Cache synchronisation (thesis 5.4, figure 39): does the ECU hold what the reference file holds?

::

    report = sync_compare(session, "assets/FLCU.s19")   # or a dataset (.dcm/.cdfx), or a saved hex
    if not report.equal:
        print(report.to_text())                         # the differing objects, both values
        sync_download(session, report)                  # file -> ECU, verified by BUILD_CHECKSUM
        # or sync_upload(report)                        # ECU -> file, written anew atomically

With an image the ECU's working page is compared per calibration segment: the ranges the image
holds there (through the segment's ADDRESS_MAPPING) and those of every calibration object, by
BUILD_CHECKSUM against the same checksum computed on the image (:mod:`workbench.sync.scan`). An
unchanged ECU is confirmed without uploading a byte of calibration memory; of a changed one only
the blocks that differ are uploaded (at most 128 bytes each, narrowed down by checksums). The rest
of the ECU's memory is then known to equal the image, so both sides are decoded by name without
reading more, and bytes that differ outside every object (padding, the EPK) are listed apart.

With a dataset there is no image to checksum: exactly its objects are read (merged into few
UPLOADs) and compared with the file's values as the ECU would hold them (0.2 is float32's 0.2 in a
FLOAT32 object); units or axis names the file labels otherwise are noted, not counted.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from workbench.calib.dataset import DatasetDiff, diff_datasets
from workbench.calib.dataset.diff import EQUAL, ObjectDiff
from workbench.calib.layout import ResolvedLayout
from workbench.calib.memory import Span
from workbench.calib.values import CalValue
from workbench.errors import InputError, WorkbenchError, epk_text, same_epk
from workbench.progress import Progress
from workbench.session import Session
from workbench.session.memory import merge_spans
from workbench.sync.areas import CalibrationArea, ImageView, calibration_areas, image_epks
from workbench.sync.ecu import EcuReader, on_pages
from workbench.sync.reference import DatasetReference, ImageReference, Reference, load_reference
from workbench.sync.scan import ChecksumScan, scan_ranges
from workbench.sync.store import ByteStore
from workbench.sync.values import (as_stored, as_typed_value, calibration_names, decode_values, label_differences,
                                   object_layouts, resolve_all, without_name)

__all__ = ["AreaCheck", "ByteDifference", "SyncReport", "sync_compare"]


@dataclass(frozen=True)
class AreaCheck:
    """One calibration segment compared by checksums."""

    area: CalibrationArea
    scan: ChecksumScan
    uploaded: int  # bytes of the differing blocks read from the ECU

    def to_dict(self) -> dict:
        return {"name": self.area.name, "start": self.area.span.address, "size": self.area.span.size,
                "compared": [[s.address, s.end] for s in self.scan.compared],
                "compared_bytes": sum(s.size for s in self.scan.compared), "checksums": self.scan.checksums,
                "checksum_type": self.scan.checksum_type,
                "differing": [[s.address, s.end] for s in self.scan.differing], "uploaded": self.uploaded}

    def describe(self) -> str:
        ranges = len(self.scan.compared)
        head = (f"{self.area}: {ranges} range{'s' if ranges != 1 else ''}, "
                f"{sum(s.size for s in self.scan.compared)} bytes compared by {self.scan.checksums} BUILD_CHECKSUM"
                f"{' (' + self.scan.checksum_type + ')' if self.scan.checksum_type else ''}")
        if self.scan.equal:
            return f"{head}: equal"
        count = len(self.scan.differing)
        return f"{head}: {count} block{' differs' if count == 1 else 's differ'}, {self.uploaded} bytes read"


@dataclass(frozen=True)
class ByteDifference:
    """Bytes that differ where no calibration object lies (padding, the EPK, data the A2L does not describe)."""

    span: Span
    reference: bytes
    ecu: bytes

    def __str__(self) -> str:
        return f"{self.span}: file {self.reference.hex(' ').upper()}, ECU {self.ecu.hex(' ').upper()}"


@dataclass
class SyncReport:
    """The ECU compared with a reference: by object (``diff``: A the reference, B the ECU) and, for an image, by
    segment (``areas``) and the bytes outside objects (``outside``)."""

    reference: Reference
    diff: DatasetDiff
    areas: list[AreaCheck] = field(default_factory=list)
    outside: list[ByteDifference] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    bytes_uploaded: int = 0  # calibration memory read from the ECU
    ecu_values: dict[str, CalValue] = field(default_factory=dict)  # the differing objects as the ECU holds them
    reference_values: dict[str, CalValue] = field(default_factory=dict)  # ... and as the reference holds them
    ecu_memory: ByteStore | None = None  # image: the compared ranges as the ECU holds them

    @property
    def equal(self) -> bool:
        return self.diff.equal and not self.outside

    @property
    def changed(self) -> list[str]:
        return [o.name for o in self.diff.objects if o.status != EQUAL]

    @property
    def checksums(self) -> int:
        return sum(a.scan.checksums for a in self.areas)

    def with_tolerance(self, abs_tol: float = 0.0, rel_tol: float = 0.0) -> DatasetDiff:
        """The object diff again, numbers within the tolerances (as :func:`diff_datasets` takes them) equal."""
        again = diff_datasets(self.reference_values, self.ecu_values, abs_tol=abs_tol, rel_tol=rel_tol)
        by_name = {o.name: o for o in again.objects}
        return DatasetDiff(self.diff.a_label, self.diff.b_label, [by_name.get(o.name, o) for o in self.diff.objects],
                           abs_tol, rel_tol)

    def summary(self) -> str:
        name = Path(self.reference.label).name
        if self.equal:
            return f'the data in the ECU equals "{name}" ({len(self.diff.objects)} objects)'
        count = len(self.changed)
        parts = [f"{count} object{' differs' if count == 1 else 's differ'}"] if count else []
        if self.outside:
            parts.append(f"{sum(d.span.size for d in self.outside)} bytes outside the objects")
        return f'the data in the ECU differs from "{name}": {", ".join(parts)}'

    def to_text(self, decimals: Callable[[str, str], int | None] | None = None) -> str:
        """The file compared, each segment's checksums, the differing objects (columns ``file`` and ``ECU``;
        ``decimals`` as :meth:`DatasetDiff.to_text` takes it), notes, and a summary with the bytes read from the ECU."""
        lines = [f"file: {self.reference.label}"]
        lines += [area.describe() for area in self.areas]
        if not self.diff.equal:  # the table without the A/B header and the count line
            lines += self.diff.to_text(columns=("file", "ECU"), decimals=decimals).splitlines()[2:-1]
        lines += [f"outside the objects: {difference}" for difference in self.outside]
        lines += [f"note: {note}" for note in self.notes]
        lines.append(f"{self.summary()}; {self.bytes_uploaded} bytes read from the ECU")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"reference": self.reference.label,
                "kind": "image" if isinstance(self.reference, ImageReference) else "dataset",
                "equal": self.equal, "changed": self.changed, "summary": self.summary(),
                "bytes_uploaded": self.bytes_uploaded, "checksums": self.checksums,
                "areas": [area.to_dict() for area in self.areas],
                "outside": [{"start": d.span.address, "end": d.span.end, "reference": d.reference.hex(),
                             "ecu": d.ecu.hex()} for d in self.outside],
                "diff": self.diff.to_dict(), "notes": self.notes}


def sync_compare(session: Session, reference: Reference | str | Path, *, progress: Progress | None = None
                 ) -> SyncReport:
    """Compare the ECU's working page with ``reference`` (an image or dataset, or the path of one).

    :raises InputError: the reference cannot be read, or an image holds another EPK than the A2L.
    :raises WorkbenchError: the ECU runs no application (boot), refused or did not answer.
    :raises Cancelled: ``progress`` was cancelled.
    """
    if not isinstance(reference, (ImageReference, DatasetReference)):
        reference = load_reference(reference)
    if session.in_boot:
        raise WorkbenchError("the ECU runs its boot loader (no application): there is no calibration data to compare")
    areas = calibration_areas(session.doc, session.config, session.module)
    with session.lock, on_pages(session, "working"):
        if isinstance(reference, ImageReference):
            return _compare_image(session, reference, areas, progress)
        return _compare_dataset(session, reference, progress)


# --- an image --------------------------------------------------------------------------------------


def _compare_image(session: Session, reference: ImageReference, areas: list[CalibrationArea],
                   progress: Progress | None) -> SyncReport:
    model = session.model
    view = ImageView(reference.image, areas)
    _check_epk(session, view, reference)
    layouts, problems = object_layouts(model, calibration_names(model))
    on_file = ByteStore(fallback=view.fetch)
    placed, failed = resolve_all(layouts, on_file.fetch)
    problems.update(failed)
    spans = {name: layout.spans() for name, layout in placed.items()}
    outside_areas = [name for name, own in spans.items() if not any(area.contains(s) for s in own for area in areas)]
    unknown = [area for area in areas if not view.held(area)]  # no bytes there, and no ADDRESS_MAPPING to them
    for name, own in spans.items():
        if any(area.contains(s) for s in own for area in unknown):
            problems[name] = f"{reference.path.name} holds nothing for {unknown[0].name}"
            del placed[name]
    spans = {name: own for name, own in spans.items() if name in placed}
    reader = EcuReader(session, progress, "uploading the blocks that differ")
    checks = []
    in_ecu = ByteStore(fallback=reader)
    for area in (area for area in areas if area not in unknown):
        compared = merge_spans(view.held(area) + [s for own in spans.values() for s in own if area.contains(s)],
                               gap=0, limit=area.span.size)
        expected = view.fetch(compared)
        for span, data in expected.items():
            on_file.put(span.address, data, span.extension)
            in_ecu.put(span.address, data, span.extension)
        scan = scan_ranges(session.master, list(expected.items()), max_block=area.max_checksum_block,
                           progress=progress)
        before = reader.bytes_read
        for span, data in reader(scan.differing).items():
            in_ecu.put(span.address, data, span.extension)
        checks.append(AreaCheck(area, scan, reader.bytes_read - before))
    leaves = [leaf for check in checks for leaf in check.scan.differing]
    touched = [name for name, own in spans.items() if name in outside_areas or _overlaps(own, leaves)]
    diff, ecu_values, file_values = _object_diff(model, placed, touched, on_file, in_ecu, reference.label, problems)
    report = SyncReport(reference, diff, checks, _outside_objects(leaves, on_file, in_ecu, placed),
                        bytes_uploaded=reader.bytes_read, ecu_values=ecu_values, reference_values=file_values,
                        ecu_memory=in_ecu)
    report.notes += [f"{name}: not compared ({why})" for name, why in problems.items()]
    report.notes += [f"{name}: in no calibration segment, compared by reading it" for name in outside_areas]
    return report


def _check_epk(session: Session, view: ImageView, reference: ImageReference) -> None:
    """Refuse an image of other software: its EPK at an ADDR_EPK it holds differs from the A2L's."""
    epk = session.doc.epk(session.module)
    if not epk:
        return
    for found in image_epks(view, session.doc, session.module):
        if found.text is not None and not same_epk(found.text, epk):
            where = f" in {found.label}" if len(session.doc.epk_addresses(session.module)) > 1 else ""
            raise InputError(f"{reference.label} holds EPK {epk_text(found.text)}{where}, the A2L {epk_text(epk)}: it "
                             "belongs to other software (flash it, or compare a file of this software)")


def _overlaps(spans: list[Span], leaves: list[Span]) -> bool:
    return any(s.extension == l.extension and s.address < l.end and l.address < s.end for s in spans for l in leaves)


def _object_diff(model, placed: dict[str, ResolvedLayout], touched: list[str], on_file: ByteStore, in_ecu: ByteStore,
                 label: str, problems: dict[str, str]
                 ) -> tuple[DatasetDiff, dict[str, CalValue], dict[str, CalValue]]:
    """Every placed object: decoded on both sides where a differing block touches it, equal elsewhere (its bytes
    passed the checksums)."""
    layouts = {name: placed[name].plan for name in touched}
    on_file_values, failed = decode_values(layouts, on_file.fetch)
    ecu_values, ecu_failed = decode_values(layouts, in_ecu.fetch)
    for name, why in {**failed, **ecu_failed}.items():
        problems[name] = why
    compared = diff_datasets(on_file_values, {n: v for n, v in ecu_values.items() if n in on_file_values},
                             a_label=label, b_label="ECU")
    by_name = {o.name: o for o in compared.objects}
    diff = DatasetDiff(label, "ECU")
    diff.objects = [by_name[name] if name in by_name else ObjectDiff(name, EQUAL)
                    for name in placed if name in by_name or name not in touched]
    changed = {o.name for o in diff.objects if o.status != EQUAL}
    return diff, {name: value for name, value in ecu_values.items() if name in changed}, \
        {name: value for name, value in on_file_values.items() if name in changed}


def _outside_objects(leaves: list[Span], on_file: ByteStore, in_ecu: ByteStore, placed: dict[str, ResolvedLayout]
                     ) -> list[ByteDifference]:
    """The differing bytes of the uploaded blocks where no object lies."""
    covered = [s for layout in placed.values() for s in layout.spans()]
    found: list[ByteDifference] = []
    for leaf in leaves:
        ours, theirs = on_file.read(leaf), in_ecu.read(leaf)
        differs = np.frombuffer(ours, np.uint8) != np.frombuffer(theirs, np.uint8)
        for span in covered:
            if span.extension == leaf.extension and span.address < leaf.end and leaf.address < span.end:
                differs[max(span.address, leaf.address) - leaf.address:min(span.end, leaf.end) - leaf.address] = False
        edges = np.flatnonzero(np.diff(np.concatenate(([False], differs, [False])).astype(np.int8)))
        for start, end in zip(edges[0::2].tolist(), edges[1::2].tolist()):
            found.append(ByteDifference(Span(leaf.address + start, end - start, leaf.extension), ours[start:end],
                                        theirs[start:end]))
    return found


# --- a dataset -------------------------------------------------------------------------------------


def _compare_dataset(session: Session, reference: DatasetReference, progress: Progress | None) -> SyncReport:
    model = session.model
    dataset = reference.dataset
    layouts, problems = object_layouts(model, dataset)
    reader = EcuReader(session, progress, "reading the dataset's objects")
    in_ecu = ByteStore(fallback=reader)
    ecu_values, failed = decode_values(layouts, in_ecu.fetch)
    problems.update(failed)
    on_file: dict[str, CalValue] = {}
    notes = []
    for name, value in ecu_values.items():
        try:
            on_file[name] = as_stored(model, dataset[name], in_ecu)
        except InputError as exc:
            on_file[name] = dataset[name]
            notes.append(f"{name}: the file's value cannot be written as it is ({without_name(name, str(exc))})")
        notes += [f"{name}: {text}" for text in label_differences(value, dataset[name])]
    diff = diff_datasets(on_file, {name: ecu_values[name] for name in on_file}, a_label=reference.label, b_label="ECU")
    changed = {o.name for o in diff.objects if o.status != EQUAL}
    # as a dataset keeps them (0.03, not the 0.029999999329447746 a FLOAT32 holds: an upload writes them as cal save
    # does); both sides alike, so that with_tolerance compares them as the diff did
    report = SyncReport(reference, diff, bytes_uploaded=reader.bytes_read,
                        ecu_values={name: as_typed_value(model, value) for name, value in ecu_values.items()
                                    if name in changed},
                        reference_values={name: as_typed_value(model, value) for name, value in on_file.items()
                                          if name in changed})
    report.notes = [f"{name}: not compared ({why})" for name, why in problems.items()] + notes
    return report
