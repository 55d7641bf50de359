"""Results as data: findings with a kind, a name and a file:line:column, and the modes that choose them.

The CLI prints findings as text or JSON, the GUI lists them; nothing here formats for
one face only.
"""

from __future__ import annotations

import enum
from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["ConflictPolicy", "Finding", "IncludeMode", "Report", "Severity", "UpdateMode", "finding_at", "findings_at",
           "summarize"]


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


class Severity(enum.IntEnum):
    INFO = 0
    WARNING = 1
    ERROR = 2


class Finding(NamedTuple):
    """One thing an operation did or found, located in a file (line and column 1-based).

    A named tuple, not a dataclass: an update of a large file makes tens of thousands.
    """

    kind: str  # e.g. "address-updated", "symbol-not-found", "renamed", "undefined-reference"
    name: str  # the A2L object (or symbol) concerned
    message: str
    file: str = ""
    line: int = 0
    column: int = 0
    block: str = ""  # MEASUREMENT, CHARACTERISTIC ...
    severity: Severity = Severity.INFO

    @property
    def location(self) -> str:
        return f"{self.file}:{self.line}:{self.column}" if self.file else ""

    def __str__(self) -> str:
        where = f"{self.location}: " if self.file else ""
        return f"{where}{self.severity.name.lower()}: {self.message}"

    def to_dict(self) -> dict:
        data = self._asdict()
        data["severity"] = self.severity.name.lower()
        return data


def finding_at(doc: "A2lDocument", token: int, kind: str, name: str, message: str, block: str = "",
               severity: Severity = Severity.INFO) -> Finding:
    """A finding located at a token of ``doc``."""
    file, line, column = doc.token_position(token)
    return Finding(kind, name, message, file, line, column, block, severity)


def findings_at(doc: "A2lDocument", items: list[tuple]) -> list[Finding]:
    """Many findings at once: ``items`` are (token, kind, name, message, block, severity) tuples;
    their positions are computed in one vectorized pass."""
    starts = doc.tokens.starts_list
    positions = doc.source_map.positions([starts[item[0]] for item in items])
    return [Finding(kind, name, message, file, line, column, block, severity)
            for (_, kind, name, message, block, severity), (file, line, column) in zip(items, positions)]


def summarize(findings: list[Finding], shown: int = 3) -> str:
    """``"a (file:line:column), b (...), c (...) and 4 more"``: the first findings by name and place."""
    text = ", ".join(f"{f.name} ({f.location})" if f.file else f.name for f in findings[:shown])
    return text + (f" and {len(findings) - shown} more" if len(findings) > shown else "")


@dataclass
class Report:
    """The findings of one operation, in the order they were made."""

    operation: str
    findings: list[Finding] = field(default_factory=list)

    def add(self, finding: Finding) -> None:
        self.findings.append(finding)

    def extend(self, findings) -> None:
        self.findings.extend(findings)

    def of_kind(self, kind: str) -> list[Finding]:
        return [f for f in self.findings if f.kind == kind]

    @property
    def errors(self) -> list[Finding]:
        return [f for f in self.findings if f.severity >= Severity.ERROR]

    @property
    def warnings(self) -> list[Finding]:
        return [f for f in self.findings if f.severity == Severity.WARNING]

    @property
    def ok(self) -> bool:
        return not self.errors

    def counts(self) -> dict[str, int]:
        """How many findings of each kind."""
        return dict(Counter(f.kind for f in self.findings))

    def to_dict(self) -> dict:
        return {"operation": self.operation, "ok": self.ok, "counts": self.counts(),
                "findings": [f.to_dict() for f in self.findings]}
