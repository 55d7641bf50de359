"""Reading many objects in few commands (byte ranges merged where they are neighbours), and what the
session knows of calibration memory between commands (:class:`KnownMemory`).

The calibration code asks for :class:`~workbench.calib.memory.Span`\\ s; :func:`read_merged` reads
their union in as few transfers as sensible (spans closer than ``gap`` bytes are read as one;
the bytes between them cost less than another command) and hands each span its bytes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

from workbench.calib.memory import Span

__all__ = ["KnownMemory", "merge_spans", "read_merged"]

MERGE_GAP = 16  # bytes: on CAN a SHORT_UPLOAD round trip costs more than two frames of unwanted bytes
MAX_BLOCK = 0x1000  # bytes read at most at once, so one bad address does not fail a large batch's every read


def merge_spans(spans: Iterable[Span], gap: int = MERGE_GAP, limit: int = MAX_BLOCK) -> list[Span]:
    """The spans' union as ranges in address order, neighbours closer than ``gap`` joined (up to ``limit`` bytes)."""
    merged: list[Span] = []
    for span in sorted(set(spans), key=lambda s: (s.extension, s.address)):
        last = merged[-1] if merged else None
        if (last is not None and last.extension == span.extension and span.address <= last.end + gap
                and max(last.end, span.end) - last.address <= limit):
            merged[-1] = Span(last.address, max(last.end, span.end) - last.address, last.extension)
        else:
            merged.append(span)
    return merged


def read_merged(spans: Iterable[Span], read: Callable[[Span], bytes], gap: int = MERGE_GAP) -> dict[Span, bytes]:
    """``{span: bytes}`` for every span, read through ``read`` on merged ranges."""
    wanted = list(dict.fromkeys(spans))
    blocks = {block: read(block) for block in merge_spans(wanted, gap)}
    found: dict[Span, bytes] = {}
    for span in wanted:
        for block, data in blocks.items():
            if block.extension == span.extension and block.address <= span.address and span.end <= block.end:
                found[span] = data[span.address - block.address:span.end - block.address]
                break
    return found


class KnownMemory:
    """Calibration bytes as the session last read or wrote them, so that a write sends only what changes
    and a value written is decoded without reading the rest of its object again.

    What is known holds while the master's :attr:`~workbench.xcp.master.XcpMaster.memory_changes` stays
    where it was when it was learnt: a CONNECT, another DOWNLOAD or PROGRAM, a page switch or copy
    (whoever sends them) makes the session forget it all. The session's own writes move it on too;
    they patch what is known with what they read back and keep it (:meth:`keep`).
    """

    def __init__(self) -> None:
        self._blocks: dict[Span, bytearray] = {}
        self._stamp: int | None = None

    def valid(self, stamp: int) -> bool:
        """Whether what is known still holds at ``stamp``; forgets it all when not."""
        if stamp != self._stamp:
            self._blocks.clear()
            self._stamp = stamp
        return bool(self._blocks)

    def keep(self, stamp: int) -> None:
        """What is known holds at ``stamp`` too (the memory changes since were the caller's own, patched in)."""
        self._stamp = stamp

    def store(self, data: Mapping[Span, bytes]) -> None:
        """Bytes just read (or read back): remembered, and patched into what else is known there."""
        for span, raw in data.items():
            self.patch(span, raw)
            self._blocks[span] = bytearray(raw)

    def patch(self, span: Span, raw: bytes) -> None:
        for block, held in self._blocks.items():
            start, end = max(block.address, span.address), min(block.end, span.end)
            if block.extension == span.extension and start < end:
                held[start - block.address:end - block.address] = raw[start - span.address:end - span.address]

    def get(self, span: Span) -> bytes | None:
        """The bytes of ``span`` when the blocks known hold all of them (one block, or several side by side)."""
        data = bytearray(span.size)
        pieces = []
        for block, held in self._blocks.items():
            start, end = max(block.address, span.address), min(block.end, span.end)
            if block.extension == span.extension and start < end:
                data[start - span.address:end - span.address] = held[start - block.address:end - block.address]
                pieces.append((start, end))
        reached = span.address
        for start, end in sorted(pieces):
            if start > reached:
                break
            reached = max(reached, end)
        return bytes(data) if reached >= span.end else None

    def blocks(self) -> dict[Span, bytes]:
        return {span: bytes(held) for span, held in self._blocks.items()}
