"""A test's evidence: the signals it touches, recorded to MDF4 while it runs (:class:`~workbench.record.Recorder`).

One recorder runs per test: DAQ of the watched measurements (each on its A2L event) and, when the bench
has a CAN2 bus, that bus's frames decoded with the DBC. The recorder also feeds the bench's timeline
(its ``on_samples``), so what the expectations judge is what the file holds. A step that names a
measurement not recorded yet restarts the recording with it as a new part (``NAME.part2.mf4`` ...): one
DAQ measurement runs per session, and its signals are fixed when it starts. Watch the signals first
(:meth:`Bench.watch <workbench.testbench.Bench.watch>`) and a test has one file.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from workbench.errors import WorkbenchError
from workbench.logs import logger

if TYPE_CHECKING:
    from workbench.can.dbc_file import DbcFile
    from workbench.record import Recorder, RecordingStats
    from workbench.session import Session
    from workbench.session.measure import SampleBatch
    from workbench.testbench.timeline import Timeline

__all__ = ["Evidence"]

log = logger(__name__)


class Evidence:
    """The MF4 files of one test, at ``path`` (and ``path`` with ``.partN`` for restarts)."""

    def __init__(self, session: Session, path: Path, timeline: Timeline, *, dbc: DbcFile | None = None,
                 can_bus: dict[str, Any] | None = None):
        self.session = session
        self.path = Path(path)
        self.timeline = timeline
        self.dbc = dbc
        self.can_bus = can_bus
        self.signals: list[str] = []
        self.parts: list[Path] = []
        self.stats: list[RecordingStats] = []
        self._recorder: Recorder | None = None

    @property
    def recording(self) -> bool:
        return self._recorder is not None

    @property
    def failure(self) -> BaseException | None:
        """What ended the recording under way early (the ECU lost), None while it runs."""
        return self._recorder.failure if self._recorder is not None else None

    def ensure(self, names: list[str]) -> bool:
        """Record ``names`` too; starts the recording, or restarts it (a new part) when a name is new.
        Returns True when it (re)started."""
        new = [name for name in names if name not in self.signals]
        if self._recorder is not None and not new:
            return False
        self.signals += new
        self.stop()
        self._start()
        return True

    def _start(self) -> None:
        from workbench.record import Recorder

        number = len(self.parts) + 1
        path = self.path if number == 1 else self.path.with_name(f"{self.path.stem}.part{number}{self.path.suffix}")
        path.parent.mkdir(parents=True, exist_ok=True)
        self.timeline.restart(self.signals)
        recorder = Recorder(self.session, path, self.signals, can2=self.dbc, can_bus=self.can_bus,
                            overwrite=True, flush_s=0.5, on_samples=self._on_samples)
        recorder.start()
        self._recorder = recorder
        self.parts.append(path)
        if number > 1:
            log.info("recording part %d to %s: %s", number, path.name, ", ".join(self.signals))

    def _on_samples(self, batch: SampleBatch) -> None:
        for name, values in batch.values.items():
            self.timeline.add(name, batch.host_time, values)

    def stop(self) -> None:
        """Stop the recording and finalize its file; a failed recording raises :class:`WorkbenchError`."""
        recorder, self._recorder = self._recorder, None
        if recorder is None:
            return
        try:
            self.stats.append(recorder.stop())
        except WorkbenchError as exc:
            raise WorkbenchError(f"the evidence {recorder.path.name} is incomplete: {exc}") from None
