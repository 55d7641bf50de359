"""Changes to a document as (byte span, new bytes) edits applied to the original buffer.

Everything outside the edited spans stays byte-identical, so ``git diff`` of an
updated file shows only the tokens that changed. Writing adds back the BOM the file
was read with; text inserted by an edit uses the file's newline style.
"""

from __future__ import annotations

from operator import itemgetter
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from workbench.fileio import atomic_write_bytes

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block


class Edit(NamedTuple):
    start: int  # byte offset in the document buffer
    end: int  # exclusive; == start for an insertion
    text: bytes


def apply_edits(data: bytes, edits: list[Edit]) -> bytes:
    """``data`` with every edit applied; edits must not overlap (insertions at one offset keep their order)."""
    if not edits:
        return data
    ordered = sorted(edits, key=_start)
    pieces = []
    position = 0
    for edit in ordered:
        if edit.start < position:
            raise ValueError(f"overlapping edits at byte {edit.start}")
        pieces.append(data[position : edit.start])
        pieces.append(edit.text)
        position = edit.end
    pieces.append(data[position:])
    return b"".join(pieces)


_start = itemgetter(0)  # stable: insertions at one offset keep their order


def replace_token(doc: "A2lDocument", token: int, text: bytes) -> Edit:
    return Edit(doc.tokens.starts_list[token], doc.tokens.ends_list[token], text)


def remove_block(doc: "A2lDocument", block: "Block") -> Edit:
    """Remove a block; when it stands alone on its lines, remove those whole lines."""
    start, end = block.span
    return remove_span(doc.data, start, end)


def remove_span(data: bytes, start: int, end: int) -> Edit:
    """Remove ``data[start:end]``, widened to whole lines when only blanks share them."""
    line_start = data.rfind(b"\n", 0, start) + 1
    line_end = data.find(b"\n", end)
    line_end = len(data) if line_end < 0 else line_end + 1
    if not data[line_start:start].strip() and not data[end:line_end].strip():
        return Edit(line_start, line_end, b"")
    return Edit(start, end, b"")


def indentation_of(data: bytes, offset: int) -> bytes:
    """The blanks at the start of the line that holds ``offset``."""
    line_start = data.rfind(b"\n", 0, offset) + 1
    line = data[line_start:offset]
    return line[: len(line) - len(line.lstrip(b" \t"))]


def newline_bytes(doc: "A2lDocument") -> bytes:
    return doc.source.newline.encode("ascii")


def write_output(doc: "A2lDocument", data: bytes, path: str | Path) -> None:
    """Write a document buffer (in the document's encoding) atomically, with its BOM."""
    atomic_write_bytes(path, doc.source.bom + data)
