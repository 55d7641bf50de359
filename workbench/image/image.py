"""Memory images: which bytes an s19/hex file puts at which addresses (bincopy underneath).

A :class:`MemoryImage` is sparse: it holds only the address ranges a file fills, so
flashing programs exactly what the file holds and never a whole region (thesis 5.4:
"Partial: FC0000h-FC000Dh FC0010h-FC0C22h FDFFF0h-FDFFFFh").
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import bincopy

from workbench.errors import InputError
from workbench.fileio import read_input, write_output
from workbench.image.files import ELF_MAGIC, elf_given, is_intel_hex
from workbench.image.reading import read_image_text

__all__ = ["ERASED", "AddressRange", "MemoryImage", "load_image", "parse_image"]

ERASED = 0xFF
_PROGRAMMED = re.compile(rb"[^\xff]+")


@dataclass(frozen=True, order=True)
class AddressRange:
    """The half-open byte range ``[start, end)``."""

    start: int
    end: int

    @property
    def size(self) -> int:
        return self.end - self.start

    def __str__(self) -> str:  # the flash tools' notation: inclusive end, hex with an "h"
        return f"{self.start:X}h-{self.end - 1:X}h"

    def outside(self, covering) -> list[AddressRange]:
        """The parts of this range that none of ``covering`` (anything with ``start`` and ``end``) holds, in order."""
        parts, cursor = [], self.start
        for other in sorted(covering, key=lambda r: r.start):
            if other.end <= cursor or other.start >= self.end:
                continue
            if other.start > cursor:
                parts.append(AddressRange(cursor, other.start))
            cursor = max(cursor, other.end)
        if cursor < self.end:
            parts.append(AddressRange(cursor, self.end))
        return parts


class MemoryImage:
    """Bytes at addresses, as loaded from an S-record or Intel HEX file, or built in code."""

    def __init__(self) -> None:
        self._bin = bincopy.BinFile(header_encoding=None)  # an S0 header is bytes: latin-1 text, binary data

    @classmethod
    def from_bytes(cls, address: int, data: bytes) -> MemoryImage:
        image = cls()
        image.add(address, data)
        return image

    @classmethod
    def from_flash_content(cls, address: int, data: bytes) -> MemoryImage:
        """The bytes of a flash read-out at ``address`` that are programmed: the runs that are not :data:`ERASED`
        (an erased byte needs no programming, so an image of a read-out leaves it out)."""
        image = cls()
        for run in _PROGRAMMED.finditer(data):
            image.add(address + run.start(), run.group())
        return image

    @property
    def header(self) -> bytes | None:
        """The S-record file's S0 header (its bytes, as written: any encoding), kept when the image is written again."""
        return self._bin.header

    @header.setter
    def header(self, value: bytes | None) -> None:
        if value is not None:
            self._bin.header = value

    def add(self, address: int, data: bytes, overwrite: bool = False) -> None:
        """Put ``data`` at ``address``; raises :class:`InputError` if it overlaps held bytes and not ``overwrite``."""
        try:
            self._bin.add_binary(bytes(data), address=address, overwrite=overwrite)
        except bincopy.AddDataError as exc:
            raise InputError(f"image data at 0x{address:X} overlaps bytes already in the image") from exc

    @property
    def segments(self) -> list[tuple[int, bytes]]:
        """The contiguous ``(address, data)`` pieces, in address order."""
        return [(seg.minimum_address, bytes(seg.data)) for seg in self._bin.segments]

    @property
    def ranges(self) -> list[AddressRange]:
        return [AddressRange(seg.minimum_address, seg.maximum_address) for seg in self._bin.segments]

    @property
    def size(self) -> int:
        """Number of bytes the image holds (gaps excluded)."""
        return sum(r.size for r in self.ranges)

    def read(self, address: int, size: int, fill: int = ERASED) -> bytes:
        """``size`` bytes from ``address``; bytes the image does not hold read as ``fill``."""
        out = bytearray([fill]) * size
        end = address + size
        for start, data in self.segments:
            lo, hi = max(start, address), min(start + len(data), end)
            if lo < hi:
                out[lo - address : hi - address] = data[lo - start : hi - start]
        return bytes(out)

    def crop(self, start: int, end: int) -> MemoryImage:
        """A new image with only the bytes inside ``[start, end)``."""
        cropped = MemoryImage()
        cropped.header = self.header
        for seg_start, data in self.segments:
            lo, hi = max(seg_start, start), min(seg_start + len(data), end)
            if lo < hi:
                cropped.add(lo, data[lo - seg_start : hi - seg_start])
        return cropped

    def to_srec(self, data_bytes_per_record: int = 32) -> str:
        """The image as Motorola S-records with 32-bit addresses (S3/S7)."""
        return self._bin.as_srec(number_of_data_bytes=data_bytes_per_record, address_length_bits=32)

    def to_ihex(self) -> str:
        return self._bin.as_ihex()

    def save(self, path: str | Path) -> None:
        """Write the image atomically; ``.hex``/``.ihex`` gives Intel HEX, anything else S-records."""
        path = Path(path)
        text = self.to_ihex() if is_intel_hex(path) else self.to_srec()
        write_output(path, text.encode("ascii"))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, MemoryImage) and self.segments == other.segments

    def __repr__(self) -> str:
        return f"MemoryImage({' '.join(map(str, self.ranges)) or 'empty'})"


def load_image(path: str | Path) -> MemoryImage:
    """Load an S-record (s19/s28/s37/srec/mot) or Intel HEX file.

    :raises InputError: the file is missing, malformed or cut short; the message names ``path:line``.
    """
    path = Path(path)
    return parse_image(read_input(path, "an S-record or Intel HEX file").decode("ascii", errors="replace"), path)


def parse_image(text: str, path: str | Path = "<text>") -> MemoryImage:
    """The image the S-record or Intel HEX ``text`` describes (``path`` names it in errors); what is checked and
    accepted: :mod:`workbench.image.reading`.

    :raises InputError: the text is malformed, cut short or gives two contents for one address: ``path:line``.
    """
    if text.startswith(ELF_MAGIC.decode("ascii")):
        raise elf_given(path)
    read = read_image_text(text, path)
    image = MemoryImage()
    for address, data in read.pieces:
        image.add(address, data)
    image.header = read.header
    image._bin.execution_start_address = read.start_address
    return image
