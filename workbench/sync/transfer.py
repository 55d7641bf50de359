"""The user's choice after a cache sync (thesis figure 39): upload (ECU -> file) or download (file -> ECU).

:func:`sync_upload` writes the reference anew with what the ECU holds, atomically: an image keeps
everything it held (the application, the other regions) with the differing blocks replaced by the
ECU's bytes at their flash addresses; a dataset keeps its objects, order and metadata with the
ECU's values of the differing objects (in the file's own units and axis labels).

:func:`sync_download` makes the ECU hold what the file holds. From an image: the bytes that differ,
and only those, with DOWNLOAD, refused before anything is written when one lies outside the A2L's
writable memory; then every compared range is checked again with BUILD_CHECKSUM. From a dataset:
the whole dataset through :func:`~workbench.sync.apply.apply_dataset`, as ``cal load`` applies it (every
object checked first, one refused and nothing is written; only what changes written and read back),
then read again and compared.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from workbench.calib.dataset import Dataset, save_dataset
from workbench.calib.memory import Span
from workbench.errors import InputError, WorkbenchError
from workbench.image import MemoryImage
from workbench.progress import Progress
from workbench.progress import report as report_progress
from workbench.session import Session
from workbench.sync.apply import APPLIED, apply_dataset
from workbench.sync.areas import ImageView
from workbench.sync.cache import SyncReport, sync_compare
from workbench.sync.ecu import on_pages
from workbench.sync.reference import DatasetReference, ImageReference
from workbench.sync.scan import scan_ranges
from workbench.sync.values import object_layouts, relabel, resolve_all

__all__ = ["DownloadResult", "sync_download", "sync_upload"]

_JOIN_GAP = 8  # bytes: equal bytes between two differing runs are written again rather than costing a SET_MTA


def sync_upload(report: SyncReport, output: str | Path | None = None) -> Path:
    """Write the reference (or ``output``) with the ECU's data where it differs; returns the path written.

    :raises InputError: the place cannot be written. :raises WorkbenchError: the write failed (disk full ...).
    """
    target = Path(output) if output is not None else report.reference.path
    reference = report.reference
    if isinstance(reference, ImageReference):
        _uploaded_image(report, reference).save(target)
    else:
        save_dataset(_uploaded_dataset(report, reference), target)
    return target


def _uploaded_image(report: SyncReport, reference: ImageReference) -> MemoryImage:
    """The reference image with every differing block replaced by the ECU's bytes (erased bytes the file lacked
    stay out of it)."""
    areas = [check.area for check in report.areas]
    view = ImageView(reference.image, areas)
    patches = [(view.image_address(leaf.address, leaf.extension), report.ecu_memory.read(leaf))
               for check in report.areas for leaf in check.scan.differing]
    image = MemoryImage()
    image.header = reference.image.header
    for start, data in reference.image.segments:
        patched = bytearray(data)
        for address, new in patches:
            low, high = max(start, address), min(start + len(data), address + len(new))
            if low < high:
                patched[low - start:high - start] = new[low - address:high - address]
        image.add(start, bytes(patched))
    for address, new in patches:
        for start, run in MemoryImage.from_flash_content(address, new).segments:
            for piece_start, piece in _not_held(reference.image, start, run):
                image.add(piece_start, piece)
    return image


def _not_held(image: MemoryImage, address: int, data: bytes) -> list[tuple[int, bytes]]:
    """The parts of ``data`` at ``address`` that ``image`` holds no bytes for."""
    pieces, cursor = [], address
    for held in image.crop(address, address + len(data)).ranges:
        if held.start > cursor:
            pieces.append((cursor, data[cursor - address:held.start - address]))
        cursor = held.end
    if cursor < address + len(data):
        pieces.append((cursor, data[cursor - address:]))
    return pieces


def _uploaded_dataset(report: SyncReport, reference: DatasetReference) -> Dataset:
    dataset = reference.dataset
    updated = Dataset(dict(dataset.objects), dict(dataset.info), dataset.source, dataset.format,
                      list(dataset.comments), dict(dataset.functions))
    for field_name in ("name", "system", "title", "a2l_file", "data_file", "variant_criteria", "module_header"):
        setattr(updated, field_name, getattr(dataset, field_name))
    for name, value in report.ecu_values.items():
        updated[name] = relabel(value, dataset[name])
    return updated


@dataclass(frozen=True)
class DownloadResult:
    """What a download wrote: ``objects`` changed, ``bytes`` sent, and how it was verified."""

    objects: list[str]
    bytes: int | None  # None: written object by object (a dataset)
    verified: str

    def describe(self) -> str:
        size = f" ({self.bytes} byte{'s' if self.bytes != 1 else ''})" if self.bytes is not None else ""
        return f"downloaded {len(self.objects)} object{'s' if len(self.objects) != 1 else ''}{size}; {self.verified}"


def sync_download(session: Session, report: SyncReport, *, skip_unknown: bool = False,
                  progress: Progress | None = None) -> DownloadResult:
    """Write what differs from the reference into the ECU's working page, then verify.

    :param skip_unknown: a dataset's objects the A2L does not know (the compare left them out too) are left out
        instead of refusing the download (as :func:`~workbench.sync.apply.apply_dataset` takes it).

    :raises EpkMismatchError: the session is read-only.
    :raises InputError: differing bytes outside the A2L's writable memory (nothing written), or a dataset
        object refused by the checks (nothing written; see :class:`~workbench.sync.apply.ApplyRefused`).
    :raises WorkbenchError: a write failed (the message names what reached the ECU), or the ECU still
        differs afterwards.
    """
    session.require_writable()
    if isinstance(report.reference, DatasetReference):
        return _download_dataset(session, report, skip_unknown, progress)
    return _download_image(session, report, progress)


def _download_image(session: Session, report: SyncReport, progress: Progress | None) -> DownloadResult:
    assert report.ecu_memory is not None
    areas = [check.area for check in report.areas]
    view = ImageView(report.reference.image, areas)
    runs = [run for check in report.areas for leaf in check.scan.differing
            for run in _differing_runs(leaf, view.read(leaf), report.ecu_memory.read(leaf))]
    writable = session.writable_spans()
    outside = [run for run, _ in runs if writable is not None and not any(
        w.extension == run.extension and w.address <= run.address and run.end <= w.end for w in writable)]
    if outside:
        raise InputError(f"the file differs from the ECU at {outside[0]}, outside the A2L's writable memory; nothing "
                         "written (flash the file instead)")
    owners = _owners(session, report.changed, view)
    total = sum(run.size for run, _ in runs)
    done = 0
    with session.lock, on_pages(session, "working"):
        for index, (run, data) in enumerate(runs):
            report_progress(progress, done, total, f"downloading {run}")
            try:
                session.write_memory(run.address, data, run.extension)
            except WorkbenchError as exc:
                reached = [name for name, spans in owners.items() if _overlap(spans, [r for r, _ in runs[:index]])]
                raise WorkbenchError(f"{exc}; {done} of {total} bytes were downloaded before {run}: objects that "
                                     f"reached the ECU: {', '.join(reached) or 'none'}") from exc
            done += run.size
        report_progress(progress, total, total, "downloaded")
        for check in report.areas:
            ranges = [(span, view.read(span)) for span in check.scan.compared]
            again = scan_ranges(session.master, ranges, max_block=check.area.max_checksum_block, narrow=False)
            if not again.equal:
                raise WorkbenchError(f"after the download {check.area.name} still differs from the file at "
                                     f"{', '.join(map(str, again.differing))}")
    checksums = sum(len(check.scan.compared) for check in report.areas)
    return DownloadResult(report.changed, total, f"verified: BUILD_CHECKSUM of {checksums} ranges equals the file's")


def _owners(session: Session, names: list[str], view: ImageView) -> dict[str, list[Span]]:
    """Where each named object lies (placed with the file's counts)."""
    placed, _ = resolve_all(object_layouts(session.model, names)[0], view.fetch)
    return {name: layout.spans() for name, layout in placed.items()}


def _overlap(spans: list[Span], others: list[Span]) -> bool:
    return any(a.extension == b.extension and a.address < b.end and b.address < a.end for a in spans for b in others)


def _differing_runs(leaf: Span, wanted: bytes, held: bytes) -> list[tuple[Span, bytes]]:
    """The runs of ``leaf`` where the ECU holds other bytes than wanted (runs closer than _JOIN_GAP joined)."""
    differs = np.flatnonzero(np.frombuffer(wanted, np.uint8) != np.frombuffer(held, np.uint8))
    runs: list[tuple[int, int]] = []
    for offset in differs.tolist():
        if runs and offset - runs[-1][1] <= _JOIN_GAP:
            runs[-1] = (runs[-1][0], offset + 1)
        else:
            runs.append((offset, offset + 1))
    return [(Span(leaf.address + start, end - start, leaf.extension), wanted[start:end]) for start, end in runs]


def _download_dataset(session: Session, report: SyncReport, skip_unknown: bool,
                      progress: Progress | None) -> DownloadResult:
    """The whole dataset through apply_dataset, the rule ``cal load`` follows: every object checked first (one
    refused, nothing written), then only the objects whose bytes change written; those read again after."""
    reference = report.reference
    assert isinstance(reference, DatasetReference)
    applied = apply_dataset(session, reference.dataset, skip_unknown=skip_unknown, progress=progress,
                            source=reference.label)
    written = Dataset(source=reference.dataset.source or reference.label)
    for name in applied.named(APPLIED):
        written.add(reference.dataset[name], reference.dataset.info_of(name))
    again = sync_compare(session, DatasetReference(reference.path, written))
    if not again.equal:
        raise WorkbenchError(f"after the download the ECU still differs from {reference.label} in "
                             f"{', '.join(again.changed)}")
    return DownloadResult(applied.named(APPLIED), None,
                          f"verified: {len(written)} objects read back equal the file's")
