"""A run's verdicts as they come, for whoever follows it (the window's *Requirement tests* dialog, a CI job's watcher):
JUnit XML and the report are written at the end, this file line by line as tests end.

``workbench test --verdict-log FILE`` (the plugin's ``--verdict-log``) writes one JSON object a line, flushed at once,
from the process that runs pytest (the controller under pytest-xdist):

* ``{"event": "collected", "root": ..., "tests": [{"nodeid": ..., "requirements": [...]}, ...]}`` — the tests to
  run, their node ids relative to the folder ``root`` (``root/test_x.py::test_one`` runs one again; under
  pytest-xdist each test's requirements come with its verdict only);
* ``{"event": "started", "nodeid": ...}``;
* ``{"event": "verdict", "nodeid": ..., "verdict": ..., "requirements": [...], "message": ..., "duration": s,
  "ecu": ..., "ecu_error": ...}`` — ``verdict`` one of :data:`VERDICTS`, ``message`` the failure's (or skip's) one
  line, ``ecu`` ``"lost"`` when the ECU stopped answering during the test, ``"unreachable"`` when it did not answer
  at its start, else null, and ``ecu_error`` the error that said so (``connection to the ECU lost at ...``);
* ``{"event": "finished", "exitstatus": N}`` — pytest's exit status (2: interrupted, Ctrl-C).

:class:`VerdictReader` reads the lines written since it last read; :func:`requirement_verdicts` judges each
requirement from its tests' verdicts, as the terminal summary and the report do. Imports nothing but the stdlib.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, TextIO

__all__ = ["VERDICTS", "VerdictLog", "VerdictReader", "report_anchor", "requirement_verdicts", "verdict_of"]

# a test's verdict: judged (passed, failed), broke in its body before it judged ("not judged": a lost ECU, CAN2
# silent, a mistake in the test), could not start or end ("error": no ECU at its start, another EPK, a restore that
# failed), skipped, or cut by a stop (Ctrl-C, Cancel)
VERDICTS = ("passed", "failed", "not judged", "error", "skipped", "interrupted")


def verdict_of(entry: Mapping[str, Any]) -> str:
    """The verdict of the plugin's outcome ``entry`` (outcome, and ``when`` it broke)."""
    if entry["outcome"] == "error":
        return "not judged" if entry.get("when") == "call" else "error"
    return entry["outcome"]



def report_anchor(nodeid: str) -> str:
    """The anchor of a test's section in report.html (``report.html#ANCHOR`` opens the report there)."""
    return "t-" + "".join(c if c.isalnum() else "-" for c in nodeid)


def requirement_verdicts(tests: Iterable[tuple[str, str, Iterable[str]]]) -> dict[str, tuple[str, list[str]]]:
    """Each requirement that ``tests`` ((node id, verdict, requirement ids) each) trace: ``(verdict, node ids)``:
    "failed" when a test failed it (those tests), else "not judged" when one broke (those), else "verified" when one
    passed (those), else "" (skipped or interrupted only: the tests that trace it)."""
    by_requirement: dict[str, list[tuple[str, str]]] = {}
    for nodeid, verdict, requirements in tests:
        for requirement_id in requirements:
            by_requirement.setdefault(requirement_id, []).append((nodeid, verdict))
    judged = {}
    for requirement_id, covering in by_requirement.items():
        judged[requirement_id] = ("", [nodeid for nodeid, _ in covering])
        for verdict, says in (("failed", ("failed",)), ("not judged", ("not judged", "error")),
                              ("verified", ("passed",))):
            nodeids = [nodeid for nodeid, each in covering if each in says]
            if nodeids:
                judged[requirement_id] = (verdict, nodeids)
                break
    return judged


class VerdictLog:
    """The writing side (the plugin): one JSON line an event, flushed at once, to a file it replaces."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file: TextIO | None = self.path.open("w", encoding="utf-8")

    def write(self, event: str, **fields: Any) -> None:
        if self._file is not None:
            self._file.write(json.dumps({"event": event, **fields}) + "\n")
            self._file.flush()

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


class VerdictReader:
    """The reading side: :meth:`read` returns the events written since it last read (a line still being written
    waits for its end)."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self._offset = 0
        self._partial = b""

    def read(self) -> list[dict[str, Any]]:
        try:
            with self.path.open("rb") as file:
                file.seek(self._offset)
                data = file.read()
        except FileNotFoundError:  # not yet written: pytest still starts
            return []
        self._offset += len(data)
        *lines, self._partial = (self._partial + data).split(b"\n")
        return [json.loads(line) for line in lines if line.strip()]
