"""The modes that choose what merge and update do, and findings located at a token of an A2L.

The findings themselves (:class:`~workbench.findings.Finding`, :class:`~workbench.findings.Report`)
are shared with the other packages: :mod:`workbench.findings`.
"""

from __future__ import annotations

import enum
from typing import TYPE_CHECKING

from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["ConflictPolicy", "IncludeMode", "UpdateMode", "finding_at", "findings_at", "written_line"]


class UpdateMode(enum.Enum):
    """What ``update`` does with an object whose symbol is not in the ELF."""

    DEFAULT = "default"  # keep it (address unchanged) and report it
    STRICT = "strict"  # any miss is an error: nothing is written
    REMOVE_MISSING = "remove-missing"  # drop it (and the references to it) and report it


class IncludeMode(enum.Enum):
    """What an update does with the text of included files (``/include``)."""

    KEEP = "keep"  # keep the /include lines; changes in included files are reported, not written
    UPDATE = "update"  # keep the /include lines and rewrite the included files that change, in place
    MERGE = "merge"  # write the included text inline: the output is self-contained


class ConflictPolicy(enum.Enum):
    """What ``merge`` does with two different definitions of one name."""

    ERROR = "error"
    KEEP_FIRST = "keep-first"
    KEEP_LAST = "keep-last"
    RENAME = "rename"


def finding_at(doc: "A2lDocument", token: int, kind: str, name: str, message: str, block: str = "",
               severity: Severity = Severity.INFO) -> Finding:
    """A finding located at a token of ``doc``."""
    file, line, column = doc.token_position(token)
    return Finding(kind, name, message, file, line, column, block, severity)


def findings_at(doc: "A2lDocument", items: list[tuple]) -> list[Finding]:
    """Many findings at once: ``items`` are (token, kind, name, message, block, severity) tuples;
    their positions are computed in one vectorized pass."""
    positions = doc.source_map.positions(doc.tokens.starts[[item[0] for item in items]].tolist())
    return [Finding(kind, name, message, file, line, column, block, severity)
            for (_, kind, name, message, block, severity), (file, line, column) in zip(items, positions)]


def written_line(output, verb: str, done: str, counts: str, tail: str = "") -> str:
    """An editing command's one line after ``output`` is written (None: a dry run): ``verb``/``done`` ("remove",
    "removed") with what ``counts`` says."""
    return (f"would {verb} {counts}{tail}; nothing written (dry run)" if output is None
            else f"wrote {output}: {counts} {done}{tail}")
