"""What a flash file (s19/hex) given to ``check`` holds beyond the A2L's memory (part of ``check --image``).

Every byte of a build's flash file lies in one of the A2L's MEMORY_SEGMENTs: bytes in none are a file of another
ECU, or an A2L without the segment (its objects there cannot be placed, a flash refuses the file). One warning a
module, on MOD_PAR, naming the ranges and the segments there are.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.a2l.document import A2lDocument, Block
from workbench.a2l.reports import finding_at
from workbench.findings import Report, Severity

if TYPE_CHECKING:
    from workbench.image import MemoryImage

__all__ = ["check_image_memory"]

_SHOWN = 4  # ranges named; the rest counted


def check_image_memory(doc: A2lDocument, module: Block, name: str, image: MemoryImage, report: Report) -> None:
    """Report the ranges of ``image`` (the file ``name``) that lie in no MEMORY_SEGMENT of ``module``.

    :raises A2lParseError: a MEMORY_SEGMENT without its parameters (the caller reports it).
    """
    mod_par = doc.mod_par(module.name)
    segments = doc.memory_segments(module.name)
    if mod_par is None or not segments:  # nothing to place against: the check says so elsewhere
        return
    from workbench.image import AddressRange

    covering = [AddressRange(s.address, s.address + s.size) for s in segments]
    outside = [part for held in image.ranges for part in held.outside(covering)]
    if not outside:
        return
    shown = " ".join(map(str, outside[:_SHOWN])) + (f" and {len(outside) - _SHOWN} more" if len(outside) > _SHOWN
                                                    else "")
    listed = ", ".join(f"{s.name} {AddressRange(s.address, s.address + s.size)}" for s in segments)
    report.add(finding_at(doc, mod_par.keyword_token, "image-outside-memory", "MOD_PAR",
                          f"{name} holds {sum(r.size for r in outside)} bytes in no MEMORY_SEGMENT: {shown} (the "
                          f"segments: {listed}): a file of another ECU, or a MEMORY_SEGMENT missing", "MOD_PAR",
                          Severity.WARNING))
