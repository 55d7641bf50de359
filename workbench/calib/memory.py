"""ECU memory as the calibration code sees it: byte ranges to read and byte edits to write.

The layout and codec never talk to an ECU. They say which :class:`Span`\\ s they need, take
the bytes read there as a mapping ``{span: bytes}``, and answer with :class:`ByteEdit`\\ s; the
session turns those into UPLOADs and DOWNLOADs, a dataset tool into image patches.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass

from workbench.errors import WorkbenchError

__all__ = ["ByteEdit", "Span", "read_spans", "MemoryBytes"]


@dataclass(frozen=True, order=True)
class Span:
    """``size`` bytes at ``address`` in the address space ``extension`` (ECU_ADDRESS_EXTENSION)."""

    address: int
    size: int
    extension: int = 0

    @property
    def end(self) -> int:
        return self.address + self.size

    def __str__(self) -> str:
        where = f"0x{self.address:X}..0x{self.end - 1:X}" if self.size else f"0x{self.address:X} (empty)"
        return where + (f" (extension {self.extension})" if self.extension else "")


@dataclass(frozen=True)
class ByteEdit:
    """Bytes to write: ``data`` at ``address`` (extension ``extension``), for field ``field`` of object ``name``."""

    address: int
    data: bytes
    extension: int = 0
    name: str = ""
    field: str = ""

    @property
    def span(self) -> Span:
        return Span(self.address, len(self.data), self.extension)


def read_spans(spans: Iterable[Span], read: Callable[[Span], bytes]) -> dict[Span, bytes]:
    """``{span: read(span)}`` for every span (each read once)."""
    return {span: read(span) for span in dict.fromkeys(spans)}


class MemoryBytes:
    """The bytes of some spans, readable at any address inside them. Built from another MemoryBytes it shares that
    one's index: who decodes thousands of objects from one read (a dataset of every calibration) builds it once,
    where each object sorted every span again (minutes for 7,000 calibrations).

    :raises WorkbenchError: (on :meth:`read`) the range lies in no span given, or a span's bytes are short.
    """

    def __init__(self, data: Mapping[Span, bytes] | MemoryBytes):
        if isinstance(data, MemoryBytes):
            self._spans, self._keys, self._reach = data._spans, data._keys, data._reach
            return
        self._spans = sorted(data.items(), key=lambda item: (item[0].extension, item[0].address))
        self._keys = [(span.extension, span.address) for span, _ in self._spans]
        self._reach: list[int] = []  # the farthest end of the spans up to each, in its extension (never decreasing)
        extension, reach = None, 0
        for span, raw in self._spans:
            if len(raw) < span.size:
                raise WorkbenchError(f"{len(raw)} bytes given for {span}, {span.size} expected")
            reach = max(reach, span.end) if span.extension == extension else span.end
            extension = span.extension
            self._reach.append(reach)

    def read(self, address: int, size: int, extension: int = 0) -> bytes:
        found = self.get(address, size, extension)
        if found is None:
            raise WorkbenchError(f"no bytes given for {Span(address, size, extension)}")
        return found

    def get(self, address: int, size: int, extension: int = 0) -> bytes | None:
        """The bytes of the range (from the first span by address that holds all of it), None when no span does."""
        first = bisect.bisect_left(self._keys, (extension,))
        last = bisect.bisect_right(self._keys, (extension, address))  # the spans of the extension starting by address
        holding = bisect.bisect_left(self._reach, address + size, first, last)  # the first reaching to the range's end
        if holding == last:
            return None
        span, raw = self._spans[holding]
        start = address - span.address
        return bytes(raw[start:start + size])
