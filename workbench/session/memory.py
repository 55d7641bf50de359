"""Reading many objects in few commands: byte ranges merged where they are neighbours.

The calibration code asks for :class:`~workbench.calib.memory.Span`\\ s; :func:`read_merged` reads
their union in as few transfers as sensible (spans closer than ``gap`` bytes are read as one;
the bytes between them cost less than another command) and hands each span its bytes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from workbench.calib.memory import Span

__all__ = ["merge_spans", "read_merged"]

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
