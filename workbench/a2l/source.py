"""A2L file bytes: encoding and newline detection, and offset -> file:line:column.

The reader works on the file's bytes (every A2L keyword and number is ASCII), so
unchanged bytes are written back untouched whatever the encoding. Text is decoded
only where a value is needed. An A2L is UTF-8 (with or without BOM) or, when it is
not valid UTF-8, latin-1 (the two encodings met in the wild). A UTF-16 or UTF-32
file (with BOM, or UTF-16 without one) is converted to UTF-8 for reading and
converted back when written, which changes no character.
"""

from __future__ import annotations

import bisect
import codecs
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.errors import A2lParseError
from workbench.fileio import read_input

__all__ = ["Segment", "SourceFile", "SourceMap", "decode_source", "read_source", "source_from_text", "transcoded"]

_UTF8_BOM = codecs.BOM_UTF8
# UTF-32 first: its little-endian BOM starts with UTF-16's
_WIDE_BOMS = (
    (codecs.BOM_UTF32_LE, "utf-32-le"), (codecs.BOM_UTF32_BE, "utf-32-be"),
    (codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be"),
)


@dataclass(eq=False)
class SourceFile:
    """One A2L file as read: its bytes after the BOM, and how to write it back the same way."""

    path: Path | None
    data: bytes = field(repr=False)
    encoding: str  # of ``data``: "utf-8" or "latin-1"
    bom: bytes = b""
    newline: str = "\n"
    file_encoding: str | None = None  # the file's own encoding when ``data`` was converted from it
    _line_starts: np.ndarray | None = field(default=None, repr=False)
    _counted: int = field(default=0, repr=False)  # bytes positions() counted newlines in (see there)

    @property
    def name(self) -> str:
        return str(self.path) if self.path is not None else "<string>"

    def file_bytes(self, data: bytes) -> bytes:
        """``data`` (a new version of :attr:`data`) as the file stores it: its BOM and encoding."""
        if self.file_encoding is not None:
            data = data.decode(self.encoding).encode(self.file_encoding)
        return self.bom + data

    def line_starts(self) -> np.ndarray:
        """Byte offsets at which each line starts (line 1 at index 0)."""
        if self._line_starts is None:
            sep = ord("\r") if self.newline == "\r" else ord("\n")
            breaks = np.flatnonzero(np.frombuffer(self.data, np.uint8) == sep) + 1
            self._line_starts = np.concatenate(([0], breaks)).astype(np.int64)
        return self._line_starts

    def position(self, offset: int) -> tuple[int, int]:
        """1-based (line, column) of a byte offset; the column counts characters, not bytes."""
        return self.positions([offset])[0]

    def positions(self, offsets: list[int]) -> list[tuple[int, int]]:
        """:meth:`position` of many offsets at once (one vectorized search; a few offsets: newlines
        counted up to them, without the line table of the whole file, until the counting has read the file twice:
        the table costs about that, and every object a window opens from a 20 MB file is located)."""
        if not offsets:
            return []
        data, encoding = self.data, self.encoding
        if self._line_starts is None and self._counted + max(offsets) <= 2 * len(data):
            self._counted += max(offsets)
            separator = b"\r" if self.newline == "\r" else b"\n"
            lines, line_starts, line, previous = {}, {}, 1, 0
            for offset in sorted(set(offsets)):
                line += data.count(separator, previous, offset)
                lines[offset], line_starts[offset], previous = line, data.rfind(separator, 0, offset) + 1, offset
            lines, line_starts = [lines[offset] for offset in offsets], [line_starts[offset] for offset in offsets]
        else:
            starts = self.line_starts()
            lines = np.searchsorted(starts, offsets, side="right").tolist()
            line_starts = starts[np.asarray(lines, dtype=np.int64) - 1].tolist()
        return [(line, offset - start + 1 if data[start:offset].isascii()
                 else len(data[start:offset].decode(encoding, "replace")) + 1)
                for line, start, offset in zip(lines, line_starts, offsets)]

    def error(self, message: str, offset: int) -> A2lParseError:
        line, column = self.position(offset)
        return A2lParseError(message, self.name, line, column)


def read_source(path: str | Path) -> SourceFile:
    """Read an A2L file; raises :class:`InputError` if it cannot be read and
    :class:`A2lParseError` if it is not text in a supported encoding."""
    path = Path(path)
    return decode_source(read_input(path, "an A2L file"), path)


def source_from_text(text: str, path: str | Path | None = None) -> SourceFile:
    """A source made from a string (tests, generated text); it is stored as UTF-8."""
    return decode_source(text.encode("utf-8"), Path(path) if path is not None else None)


def decode_source(raw: bytes, path: Path | None) -> SourceFile:
    """Detect BOM, encoding and newline style of ``raw``."""
    name = str(path) if path is not None else "<string>"
    if raw.startswith(b"\x7fELF"):
        raise A2lParseError("this is an ELF file, not an A2L file", name, 1, 1)
    wide = _wide_encoding(raw)
    if wide is not None:
        return _from_wide(raw, path, *wide)
    bom = _UTF8_BOM if raw.startswith(_UTF8_BOM) else b""
    data = raw[len(bom):]
    try:
        if not data.isascii():  # ASCII (most A2L files) is valid UTF-8: no 10 MB decode to find out
            data.decode("utf-8")
        encoding = "utf-8"
    except UnicodeDecodeError as exc:
        if bom:
            probe = SourceFile(path, data, "latin-1")
            line, column = probe.position(exc.start)
            raise A2lParseError(
                f"invalid UTF-8 byte 0x{data[exc.start]:02X} although the file starts with a UTF-8 BOM",
                name, line, column,
            ) from None
        encoding = "latin-1"
    nul = data.find(b"\0")
    source = SourceFile(path, data, encoding, bom, _detect_newline(data))
    if nul >= 0:
        raise source.error("NUL byte: this is a binary file, not an A2L file", nul)
    return source


def _wide_encoding(raw: bytes) -> tuple[bytes, str] | None:
    """(BOM, encoding) of a UTF-16/32 file; without a BOM, UTF-16 is recognised by its NUL
    high bytes (an A2L starts with ASCII: a keyword, a comment or blanks)."""
    for bom, encoding in _WIDE_BOMS:
        if raw.startswith(bom):
            return bom, encoding
    head = raw[:64]
    if len(head) >= 4 and len(head) % 2 == 0:
        if not any(head[1::2]) and all(head[0::2]):
            return b"", "utf-16-le"
        if not any(head[0::2]) and all(head[1::2]):
            return b"", "utf-16-be"
    return None


def _from_wide(raw: bytes, path: Path | None, bom: bytes, encoding: str) -> SourceFile:
    body = raw[len(bom):]
    try:
        text = body.decode(encoding)
    except UnicodeDecodeError as exc:
        unit = 4 if "32" in encoding else 2
        line_text = body[: exc.start - exc.start % unit].decode(encoding)
        line = line_text.count("\n") + 1
        column = len(line_text) - line_text.rfind("\n")
        raise A2lParseError(f"invalid {encoding.upper()} data", str(path) if path is not None else "<string>",
                            line, column) from None
    data = text.encode("utf-8")
    source = SourceFile(path, data, "utf-8", bom, _detect_newline(data), file_encoding=encoding)
    nul = data.find(b"\0")
    if nul >= 0:
        raise source.error("NUL character: this is a binary file, not an A2L file", nul)
    return source


def _detect_newline(data: bytes) -> str:
    first = data.find(b"\n")
    if first > 0 and data[first - 1 : first] == b"\r":
        return "\r\n"
    if first < 0 and b"\r" in data:
        return "\r"
    return "\n"


def transcoded(source: SourceFile, encoding: str) -> SourceFile:
    """``source`` with its data in another encoding (it still writes back as the file was);
    raises :class:`A2lParseError` at a character ``encoding`` cannot hold."""
    text = source.data.decode(source.encoding)
    try:
        data = text.encode(encoding)
    except UnicodeEncodeError as exc:
        line, column = source.position(len(text[: exc.start].encode(source.encoding)))
        raise A2lParseError(
            f"character {text[exc.start]!r} cannot be written in {encoding} (the including file's encoding)",
            source.name, line, column,
        ) from None
    return SourceFile(source.path, data, encoding, source.bom, source.newline, source.file_encoding or source.encoding)


class Segment(NamedTuple):
    """A run of a document's buffer that was copied from one file (includes are spliced in)."""

    offset: int  # where the run starts in the document buffer
    length: int
    source: SourceFile
    source_offset: int  # where the run starts in ``source.data``


class SourceMap:
    """Maps offsets of a document buffer (a file with its includes spliced in) back to files."""

    def __init__(self, segments: list[Segment]):
        self.segments = segments
        self._offsets = [segment.offset for segment in segments]

    @classmethod
    def single(cls, source: SourceFile) -> "SourceMap":
        return cls([Segment(0, len(source.data), source, 0)])

    @property
    def main(self) -> SourceFile:
        return self.segments[0].source

    def segment_bounds(self, offset: int) -> tuple[int, int]:
        """Buffer offsets where the run of one file's text that holds ``offset`` starts and ends."""
        segment = self.segments[max(bisect.bisect_right(self._offsets, offset) - 1, 0)]
        return segment.offset, segment.offset + segment.length

    def locate(self, offset: int) -> tuple[SourceFile, int]:
        """The file a buffer offset came from, and the offset inside that file."""
        index = max(bisect.bisect_right(self._offsets, offset) - 1, 0)
        segment = self.segments[index]
        return segment.source, segment.source_offset + (offset - segment.offset)

    def position(self, offset: int) -> tuple[str, int, int]:
        """(file name, line, column) of a buffer offset."""
        source, local = self.locate(offset)
        return (source.name, *source.position(local))

    def positions(self, offsets: list[int]) -> list[tuple[str, int, int]]:
        """:meth:`position` of many buffer offsets (vectorized when the buffer is one file)."""
        if len(self.segments) == 1:
            source = self.main
            return [(source.name, line, column) for line, column in source.positions(offsets)]
        return [self.position(offset) for offset in offsets]

    def error(self, message: str, offset: int) -> A2lParseError:
        source, local = self.locate(offset)
        return source.error(message, local)

    def files(self) -> list[SourceFile]:
        seen: dict[int, SourceFile] = {}
        for segment in self.segments:
            seen.setdefault(id(segment.source), segment.source)
        return list(seen.values())
