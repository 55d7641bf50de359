"""A requirement test run in a process of its own, followed as it goes: ``python -m workbench test ... --report DIR
--verdict-log FILE`` (pytest's state never lives in the caller's process), its verdicts read line by line
(:mod:`workbench.testbench.verdicts`), stopped as Ctrl-C stops it. The window's *Requirement tests* dialog runs its
tests so; a script can too::

    from workbench.testbench.run import RequirementRun, RunOptions

    run = RequirementRun(RunOptions(report="out", req=["SW_REQ_ID_001"])).start()
    while run.poll() is None:
        for event in run.events():
            ...                         # {"event": "verdict", "nodeid": ..., "verdict": "passed", ...}
        time.sleep(0.2)
    print(run.exit_code, run.error())   # workbench test's: 0 passed, 1 a test failed or broke, 2 bad input

The process runs in a process group (session) of its own: :meth:`RequirementRun.cancel` interrupts it and its
pytest-xdist workers as Ctrl-C in a terminal does (the tests stop, the report says INTERRUPTED and is written), and
ends them if they have not ended :data:`CANCEL_GRACE_S` later.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from workbench.testbench.verdicts import VerdictReader

__all__ = ["CANCEL_GRACE_S", "FLCU_SUITE", "RequirementRun", "RunOptions"]

FLCU_SUITE = Path(__file__).resolve().parent / "flcu_suite"  # the FLCU's requirement tests, shipped with the package
CANCEL_GRACE_S = 10.0  # how long a cancelled run may take to stop (a test's teardown restores the ECU's values)


@dataclass
class RunOptions:
    """What ``workbench test`` is given. ``paths``: test files or folders (none: the FLCU suite); ``ecu``: the ECU's
    options as every ``workbench`` command takes them (none: a simulated ECU per test)."""

    report: str | Path
    paths: list[str] = field(default_factory=list)
    req: list[str] = field(default_factory=list)
    keyword: str = ""
    workers: int = 0  # -n (simulated ECUs only); 0: one process
    repeat: int = 0
    requirements: str = ""  # the catalogue CSV the report traces
    ecu: list[str] = field(default_factory=list)  # ["--interface", "socketcan", "--channel", "can0", ...]

    def arguments(self, verdict_log: str | Path | None = None) -> list[str]:
        """The arguments of ``workbench test``."""
        argv = [*self.paths, "--report", str(self.report)]
        for requirement_id in self.req:
            argv += ["--req", requirement_id]
        for option, value in (("-k", self.keyword), ("-n", self.workers), ("--repeat", self.repeat),
                              ("--requirements", self.requirements), ("--verdict-log", verdict_log)):
            if value:
                argv += [option, str(value)]
        return argv + list(self.ecu)


class RequirementRun:
    """One run of ``workbench test`` in a process of its own (see the module's docstring)."""

    def __init__(self, options: RunOptions, python: str = sys.executable):
        self.options = options
        self.python = python
        self.process: subprocess.Popen | None = None
        self.cancelled_at: float | None = None  # time.monotonic() of cancel()
        self._folder: Path | None = None
        self._reader: VerdictReader | None = None
        self._output_read = 0  # bytes of stdout read_output() returned

    @property
    def command(self) -> list[str]:
        """The command line run (the verdict log in a folder of the run's own)."""
        log = self._folder / "verdicts.jsonl" if self._folder is not None else None
        return [self.python, "-m", "workbench", "test", *self.options.arguments(log)]

    @property
    def report(self) -> Path:
        return Path(self.options.report) / "report.html"

    def start(self) -> RequirementRun:
        self._folder = Path(tempfile.mkdtemp(prefix="workbench-test-run-"))
        self._reader = VerdictReader(self._folder / "verdicts.jsonl")
        group: dict[str, Any] = ({"creationflags": subprocess.CREATE_NEW_PROCESS_GROUP} if os.name == "nt"
                                 else {"start_new_session": True})
        with open(self._folder / "stdout.txt", "wb") as out, open(self._folder / "stderr.txt", "wb") as err:
            self.process = subprocess.Popen(self.command, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                            env={**os.environ, "PYTHONUNBUFFERED": "1"}, **group)
        return self

    def events(self) -> list[dict[str, Any]]:
        """The verdict log's events since the last call."""
        return self._reader.read() if self._reader is not None else []

    def poll(self) -> int | None:
        """The exit code once the process has ended, else None (a cancelled run is ended harder past its grace)."""
        if self.process is None:
            return None
        code = self.process.poll()
        if code is None and self.cancelled_at is not None:
            late = time.monotonic() - self.cancelled_at - CANCEL_GRACE_S
            if late > 0:
                self._signal(signal.SIGKILL if late > CANCEL_GRACE_S / 2 and os.name != "nt" else signal.SIGTERM)
        return code

    @property
    def exit_code(self) -> int | None:
        return self.process.returncode if self.process is not None else None

    def cancel(self) -> None:
        """Interrupt the run as Ctrl-C does (every process of its group); :meth:`poll` ends it if it goes on."""
        if self.process is None or self.process.poll() is not None or self.cancelled_at is not None:
            return
        self.cancelled_at = time.monotonic()
        self._signal(signal.CTRL_BREAK_EVENT if os.name == "nt" else signal.SIGINT)

    def _signal(self, number: int) -> None:
        try:
            if os.name == "nt":
                self.process.send_signal(number)
            else:
                os.killpg(self.process.pid, number)  # its group: the pytest-xdist workers too
        except (ProcessLookupError, PermissionError):  # ended meanwhile
            pass

    def read_output(self) -> str:
        """What the run wrote on stdout (pytest's terminal output) since the last call."""
        if self._folder is None:
            return ""
        try:
            with open(self._folder / "stdout.txt", "rb") as file:
                file.seek(self._output_read)
                data = file.read()
        except FileNotFoundError:
            return ""
        end = data.rfind(b"\n") + 1  # whole lines only (0: none yet)
        self._output_read += end
        return data[:end].decode("utf-8", errors="replace")

    def error(self) -> str:
        """The command's one-line error (``workbench test``'s stderr without ``error:``), else its last line."""
        lines = [line for line in self._text("stderr.txt").splitlines() if line.strip()]
        for line in reversed(lines):
            if line.startswith("error: "):
                return line.removeprefix("error: ")
        return lines[-1] if lines else ""

    def _text(self, name: str) -> str:
        if self._folder is None:
            return ""
        try:
            return (self._folder / name).read_text(encoding="utf-8", errors="replace")
        except FileNotFoundError:
            return ""

    def close(self) -> None:
        """Stop the process if it still runs and remove the run's own folder (the report stays)."""
        if self.process is not None and self.process.poll() is None:
            self._signal(signal.SIGKILL if os.name != "nt" else signal.SIGTERM)
            self.process.wait()
        if self._folder is not None:
            shutil.rmtree(self._folder, ignore_errors=True)
            self._folder = None
