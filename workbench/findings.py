"""Findings: what an operation found or did, located in a file — one type for every package.

An A2L merge, update or check and a DBC check all report :class:`Finding` s gathered in a
:class:`Report`; the CLI prints them one a line (``file:line:column: severity: message``)
or as JSON, and the GUI lists them together. Nothing here formats for one face only.
"""

from __future__ import annotations

import enum
from collections import Counter
from dataclasses import dataclass, field
from typing import NamedTuple

__all__ = ["Finding", "Report", "Severity", "summarize"]


class Severity(enum.IntEnum):
    INFO = 0  # what an operation did (an address updated, a fragment merged)
    WARNING = 1  # worth a look; the result is usable
    ERROR = 2  # the file is wrong, or the operation cannot complete


class Finding(NamedTuple):
    """One thing an operation did or found, located in a file (line and column 1-based, 0: not known).

    A named tuple, not a dataclass: an update of a large A2L makes tens of thousands.
    """

    kind: str  # e.g. "address-updated", "symbol-not-found", "undefined-reference", "overlap", "beyond-dlc"
    name: str  # the object concerned: an A2L name or symbol, a DBC "MESSAGE" or "MESSAGE.SIGNAL"
    message: str  # one sentence for a user; it names the object
    file: str = ""
    line: int = 0
    column: int = 0
    block: str = ""  # the object's keyword in its file: MEASUREMENT, CHARACTERISTIC ... (A2L), BO_, SG_ (DBC)
    severity: Severity = Severity.INFO

    @property
    def location(self) -> str:
        """``file:line:column``, ``file:line`` or ``file`` as far as known; ``""`` without a file."""
        if not self.file:
            return ""
        if not self.line:
            return self.file
        return f"{self.file}:{self.line}:{self.column}" if self.column else f"{self.file}:{self.line}"

    def __str__(self) -> str:
        where = f"{self.location}: " if self.file else ""
        return f"{where}{self.severity.name.lower()}: {self.message}"

    def to_dict(self) -> dict:
        """The fields by name, the severity as its lower-case name (JSON output)."""
        data = self._asdict()
        data["severity"] = self.severity.name.lower()
        return data


def summarize(findings: list[Finding], shown: int = 3) -> str:
    """``"a (file:line:column), b (...), c (...) and 4 more"``: the first findings by name and place."""
    text = ", ".join(f"{f.name} ({f.location})" if f.file else f.name for f in findings[:shown])
    return text + (f" and {len(findings) - shown} more" if len(findings) > shown else "")


@dataclass
class Report:
    """The findings of one operation, in the order they were made.

    ``fails_on`` is the least severity that makes the operation fail: an error for merge and
    update (a warning leaves a usable result), a warning for a check (every finding of a check
    is a problem it was asked to find). :attr:`ok` and the CLI's exit code follow it.
    """

    operation: str
    findings: list[Finding] = field(default_factory=list)
    fails_on: Severity = Severity.ERROR

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
    def problems(self) -> list[Finding]:
        """The warnings and errors (what a check reports), in order."""
        return [f for f in self.findings if f.severity > Severity.INFO]

    @property
    def ok(self) -> bool:
        """No finding of ``fails_on`` severity or worse: the operation succeeded (CLI exit code 0)."""
        return all(f.severity < self.fails_on for f in self.findings)

    def counts(self) -> dict[str, int]:
        """How many findings of each kind."""
        return dict(Counter(f.kind for f in self.findings))

    def to_dict(self) -> dict:
        return {"operation": self.operation, "ok": self.ok, "fails_on": self.fails_on.name.lower(),
                "counts": self.counts(),
                "findings": [f.to_dict() for f in self.findings]}
