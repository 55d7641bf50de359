"""Bytes known at ECU addresses, patched by later writes: what the sync knows of memory without reading it again.

The cache sync knows most of the ECU's calibration memory without uploading it (the blocks whose
checksum equals the reference's hold the reference's bytes) and the rest from the few blocks it
uploads; applying a dataset needs the current bytes and then the bytes as an edit would leave them.
A :class:`ByteStore` holds such pieces per address extension, merges neighbours, lets later bytes
overwrite earlier ones, and reads what it does not hold through ``fallback`` (the ECU), keeping it.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable, Iterable, Mapping

from workbench.calib.memory import ByteEdit, Span
from workbench.errors import WorkbenchError

__all__ = ["ByteStore"]


class ByteStore:
    """Pieces of memory by address; :meth:`read` serves a span from them or through ``fallback``.

    :param fallback: ``fallback(spans) -> {span: bytes}`` for spans the store does not hold wholly
        (None: such a read raises :class:`WorkbenchError`).
    """

    def __init__(self, pieces: Mapping[Span, bytes] | None = None,
                 fallback: Callable[[list[Span]], Mapping[Span, bytes]] | None = None):
        self._starts: dict[int, list[int]] = {}  # extension -> sorted piece starts
        self._data: dict[int, dict[int, bytearray]] = {}  # extension -> start -> bytes
        self.fallback = fallback
        for span, data in (pieces or {}).items():
            self.put(span.address, data, span.extension)

    def copy(self) -> ByteStore:
        """The same bytes in a store of their own (patching the copy leaves this one as it is)."""
        twin = ByteStore(fallback=self.fallback)
        for extension, pieces in self._data.items():
            for start, data in pieces.items():
                twin.put(start, bytes(data), extension)
        return twin

    def put(self, address: int, data: bytes, extension: int = 0) -> None:
        """Hold ``data`` at ``address``, over whatever was held there (neighbouring pieces join)."""
        if not data:
            return
        starts = self._starts.setdefault(extension, [])
        pieces = self._data.setdefault(extension, {})
        end = address + len(data)
        first = bisect.bisect_left(starts, address)
        if first and starts[first - 1] + len(pieces[starts[first - 1]]) >= address:
            first -= 1  # the piece before reaches this one (or touches it)
        last = bisect.bisect_right(starts, end)
        joined = [starts[i] for i in range(first, last)]
        low = min([address] + joined)
        high = max([end] + [s + len(pieces[s]) for s in joined])
        merged = bytearray(high - low)
        for start in joined:
            piece = pieces.pop(start)
            merged[start - low:start - low + len(piece)] = piece
        merged[address - low:end - low] = data
        del starts[first:last]
        starts.insert(first, low)
        pieces[low] = merged

    def apply(self, edits: Iterable[ByteEdit]) -> None:
        for edit in edits:
            self.put(edit.address, edit.data, edit.extension)

    def get(self, span: Span) -> bytes | None:
        """The span's bytes when one piece holds all of them, else None."""
        starts = self._starts.get(span.extension, [])
        index = bisect.bisect_right(starts, span.address) - 1
        if index < 0:
            return None
        start = starts[index]
        piece = self._data[span.extension][start]
        if span.end > start + len(piece):
            return None
        return bytes(piece[span.address - start:span.end - start])

    def read(self, span: Span) -> bytes:
        """The span's bytes; what the store lacks comes from ``fallback`` (and is kept).

        :raises WorkbenchError: the store lacks bytes of the span and has no fallback.
        """
        return self.fetch([span])[span]

    def fetch(self, spans: Iterable[Span]) -> dict[Span, bytes]:
        """``{span: bytes}``; the spans the store lacks are fetched in one call of ``fallback``."""
        wanted = list(dict.fromkeys(spans))
        found = {span: self.get(span) for span in wanted}
        missing = [span for span, data in found.items() if data is None]
        if missing:
            if self.fallback is None:
                raise WorkbenchError(f"no bytes known at {missing[0]}")
            for span, data in self.fallback(missing).items():
                self._fill(span, data)
            found.update({span: self.get(span) for span in missing})
        return found  # type: ignore[return-value]

    def _fill(self, span: Span, data: bytes) -> None:
        """Hold fetched bytes where nothing is held yet: held bytes (patched ones too) stay."""
        merged = bytearray(data)
        for start, piece in self._data.get(span.extension, {}).items():
            low, high = max(start, span.address), min(start + len(piece), span.end)
            if low < high:
                merged[low - span.address:high - span.address] = piece[low - start:high - start]
        self.put(span.address, bytes(merged), span.extension)

    def spans(self) -> list[Span]:
        """The held pieces, in address order per extension."""
        return [Span(start, len(self._data[extension][start]), extension)
                for extension in sorted(self._starts) for start in self._starts[extension]]
