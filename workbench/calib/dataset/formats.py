"""The dataset file formats by name and extension, and the functions that load and save them.

One module pair per format, found through :data:`FORMATS` (as python-can finds its
interfaces): ``<reader>.read(data, path) -> Dataset``, ``<writer>.write(dataset) -> bytes`` and
``<writer>.losses(dataset) -> list[Finding]`` (what the format cannot keep). Modules are
imported on first use.
"""

from __future__ import annotations

import codecs
import importlib
from dataclasses import dataclass
from pathlib import Path

from workbench.calib.dataset.model import Dataset
from workbench.errors import InputError
from workbench.fileio import read_input, write_output
from workbench.findings import Finding

__all__ = ["FORMATS", "dataset_losses", "dump_dataset", "format_of", "load_dataset", "load_dataset_string",
           "save_dataset"]


@dataclass(frozen=True)
class Format:
    name: str
    description: str
    extensions: tuple[str, ...]
    reader: str  # module with read(data, path)
    writer: str  # module with write(dataset, encoding) and losses(dataset)


FORMATS: dict[str, Format] = {
    "dcm": Format("dcm", "DCM (DAMOS Konservierungsformat 2.0)", (".dcm",),
                  "workbench.calib.dataset.dcm_read", "workbench.calib.dataset.dcm_write"),
    "cdfx": Format("cdfx", "CDFX (ASAM CDF 2.0 XML)", (".cdfx", ".cdf", ".xml"),
                   "workbench.calib.dataset.cdfx_read", "workbench.calib.dataset.cdfx_write"),
}


def format_of(path: str | Path, format: str | None = None) -> Format:
    """The format named ``format``, else the one ``path``'s extension says (case-insensitive).

    :raises InputError: an unknown format name or extension (naming the known ones).
    """
    if format is not None:
        if format.lower() not in FORMATS:
            raise InputError(f"unknown dataset format {format!r} (known: {', '.join(FORMATS)})")
        return FORMATS[format.lower()]
    suffix = Path(path).suffix.lower()
    for candidate in FORMATS.values():
        if suffix in candidate.extensions:
            return candidate
    known = ", ".join(e for f in FORMATS.values() for e in f.extensions)
    if not suffix:
        raise InputError(f"{path}: no extension to tell the dataset format by (known: {known})")
    raise InputError(f"{path}: not a dataset file by its extension {suffix!r} (known: {known})")


def load_dataset(path: str | Path, format: str | None = None) -> Dataset:
    """The dataset in the file ``path``; the format from ``format`` or the extension.

    :raises InputError: the file cannot be read or its format is unknown.
    :raises DatasetParseError: the file is malformed (``file:line[:column]: what was expected``).
    """
    spec = format_of(path, format)
    data = read_input(path, f"a {spec.description} file")
    _refuse_other_format(path, spec, data)
    return importlib.import_module(spec.reader).read(data, str(path))


def _refuse_other_format(path: str | Path, spec: Format, data: bytes) -> None:
    """:raises InputError: the file holds the other format than its extension says (a CDFX saved as .dcm): said as
    such, not as the first line the reader cannot take."""
    start = data.removeprefix(b"\xef\xbb\xbf").lstrip()[:1]
    xml = start == b"<" or data.startswith((b"\xff\xfe<", b"\xfe\xff\x00<"))
    if spec.name == "dcm" and xml:
        raise InputError(f"{path}: XML, not a DCM (a CDFX file named .dcm? name it .cdfx)")
    if spec.name == "cdfx" and start and not xml and not data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise InputError(f"{path}: not XML, so not a CDFX (a DCM file named {Path(path).suffix}? name it .dcm)")


def load_dataset_string(data: str | bytes, format: str, path: str = "<string>") -> Dataset:
    """The dataset in ``data`` (text or the bytes of a file) in ``format`` ("dcm", "cdfx")."""
    spec = format_of(path, format)
    raw = data.encode("utf-8") if isinstance(data, str) else data
    return importlib.import_module(spec.reader).read(raw, path)


def dump_dataset(dataset: Dataset, format: str, encoding: str = "utf-8") -> bytes:
    """The file content of ``dataset`` in ``format`` and ``encoding``; what the format cannot hold
    at all is left out (see :func:`dataset_losses`).

    :raises InputError: a DCM character ``encoding`` cannot hold.
    """
    return importlib.import_module(format_of("", format).writer).write(dataset, _known(encoding))


def dataset_losses(dataset: Dataset, format: str) -> list[Finding]:
    """What ``format`` cannot keep of ``dataset``, as warnings naming the object (kind ``left-out``:
    an object the format cannot hold at all, left out of the file)."""
    return importlib.import_module(format_of("", format).writer).losses(dataset)


def save_dataset(dataset: Dataset, path: str | Path, format: str | None = None, encoding: str = "utf-8"
                 ) -> list[Finding]:
    """Write ``dataset`` to ``path`` atomically; returns what the format could not keep (warnings,
    objects it cannot hold at all left out).

    ``encoding``: UTF-8 unless a tool wants another (``cp1252`` for an ANSI DCM).

    :raises InputError: a character ``encoding`` cannot hold, or a place that cannot be written.
    :raises WorkbenchError: the write failed (e.g. a full disk).
    """
    spec = format_of(path, format)
    writer = importlib.import_module(spec.writer)
    data = writer.write(dataset, _known(encoding))
    write_output(path, data)
    return writer.losses(dataset)


def _known(encoding: str) -> str:
    try:
        codecs.lookup(encoding)
    except LookupError:
        raise InputError(f"unknown encoding {encoding!r}") from None
    return encoding
