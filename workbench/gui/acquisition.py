"""DAQ in a thread of its own: the session's measurement feeds the ring buffers, nothing else.

:class:`DaqAcquisition` runs ``session.measure(names)`` in a background thread and appends every
batch to the signals' :class:`~workbench.gui.ringbuffer.RingBuffer`\\ s; the plots read the buffers on
their own timer. When the set of signals changes, the running measurement is stopped and a new
one started with the new set (the ECU's DAQ lists are configured for what is displayed, as CANape
does). Times are the ECU's DAQ timestamps mapped to host time, minus the hub's origin.

A signal the ECU refuses to sample (WRITE_DAQ refused: an address outside what its DAQ may read; SET_DAQ_LIST_MODE
refused: an event it does not have, an A2L of another build) does not
stop the others, as in CANape: the measurement is tried on halves of the signals until the refused ones are
found, then runs without them; ``refused`` names them with the ECU's answer (the state keeps them, and they are
not asked for again on this session).

Recording (:meth:`DaqAcquisition.record`) swaps the plain measurement for a
:class:`~workbench.record.Recorder` of the same signals, whose ``on_samples`` feeds the buffers:
one set of DAQ lists on the ECU serves both the plots and the file. While a recording runs, the
set of signals stays the one recorded (an MDF file cannot grow channels); a signal shown meanwhile
is measured once the recording stops.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from PySide6.QtCore import QObject, Signal

from workbench.errors import ConnectionLostError, WorkbenchError, XcpCommandError
from workbench.logs import logger

log = logger(__name__)

__all__ = ["DaqAcquisition", "DaqState", "RecordRequest"]

_SIGNALS_REFUSED = ("WRITE_DAQ", "SET_DAQ_LIST_MODE")  # refusals of a signal's address or event, not of the lists' room
_READ_TIMEOUT_S = 0.1  # how long one read waits for samples: also how soon a change of signals is taken


class DaqState:
    """What the status bar shows about the running measurement (written by the thread, read by the GUI)."""

    def __init__(self):
        self.signals: tuple[str, ...] = ()
        self.samples = 0
        self.lost = 0
        self.overloads = 0
        self.running = False
        self.clock = ""  # which clock times the samples, for people (Measurement.time_source)
        self.ecu_clock = True  # the ECU's DAQ timestamps; False: the master's receive time (a slave without them)
        self.refused: dict[str, str] = {}  # signal -> why the ECU does not sample it (not measured on this session)
        self.recording: Path | None = None  # the MDF4 file being written
        self.recorded_s = 0.0
        self.file_bytes = 0


@dataclass(frozen=True)
class RecordRequest:
    """What :meth:`DaqAcquisition.record` records besides the measured signals."""

    path: Path
    can2: Any = None  # a workbench.can.DbcFile: the CAN2 bus decoded into the file
    raw_can: bool = False  # the CAN2 bus logged raw (ASAM bus logging)


class DaqAcquisition(QObject):
    """Measures the wanted signals of one session until :meth:`stop`.

    ``sink(name, times, values)`` gets every signal's new samples (from the acquisition thread);
    ``gap(names)`` is told when their measurement pauses (stopped, restarted with other signals, failed),
    so the plots break their lines there.
    """

    failed = Signal(object)  # the exception that stopped the measurement
    refused = Signal(object)  # {name: why} of signals the ECU refused to sample (the others are measured)
    started = Signal(object)  # the names being measured
    recording_started = Signal(object)  # the RecordRequest
    recording_stopped = Signal(object)  # workbench.record.RecordingStats, or None when it could not start

    def __init__(self, session, sink: Callable, origin: float, parent: QObject | None = None,
                 gap: Callable | None = None):
        super().__init__(parent)
        self.session = session
        self.sink = sink
        self.gap = gap or (lambda names: None)
        self.origin = origin
        self.state = DaqState()
        self._wanted: tuple[str, ...] = ()
        self._recording: RecordRequest | None = None
        self._changed = threading.Event()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.after: threading.Event | None = None  # set: the measurement before on the session has stopped

    def measure(self, names) -> None:
        """Measure ``names`` from now on (an empty set stops the DAQ lists, the thread waits)."""
        wanted = tuple(sorted(set(names)))
        if wanted == self._wanted and self._thread is not None:
            return
        self._wanted = wanted
        self._changed.set()
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="workbench-daq", daemon=True)
            self._thread.start()

    def record(self, request: RecordRequest) -> None:
        """Record the measured signals (and the CAN2 bus, as ``request`` says) to ``request.path`` from
        now on, replacing a file there when the recording ends; ``recording_started`` follows, or
        ``failed`` and ``recording_stopped(None)``."""
        self._recording = request
        self._changed.set()
        self.measure(self._wanted)

    def stop_recording(self) -> None:
        """End the recording (the file is finalized; ``recording_stopped`` follows), measuring goes on."""
        self._recording = None
        self._changed.set()

    @property
    def recording(self) -> bool:
        return self._recording is not None

    def stop(self) -> None:
        """Ask the thread to stop the measurement (the DAQ lists are stopped on the ECU); :meth:`wait` for it
        (not in the GUI thread: it ends within one read, :data:`_READ_TIMEOUT_S`, or a DAQ command's timeout)."""
        self._stop.set()
        self._changed.set()

    def wait(self, timeout_s: float = 5.0) -> None:
        """Wait until the thread asked to :meth:`stop` has ended."""
        thread = self._thread
        if thread is not None:
            thread.join(timeout_s)

    def _run(self) -> None:
        if self.after is not None:  # one DAQ measurement at a time on a session
            self.after.wait(5.0)
        while not self._stop.is_set():
            self._changed.wait()
            self._changed.clear()
            if self._stop.is_set():
                break
            names, request = self._wanted, self._recording
            try:
                if request is not None:
                    self._record(names, request)
                elif names:
                    self._measure(names)
            except Exception as exc:  # noqa: BLE001 - shown as a dialog; the thread must not die silently
                if not isinstance(exc, WorkbenchError):
                    log.exception("DAQ acquisition")
                self.state.running = False
                if not self._stop.is_set() and not self.session.closed:  # closed under it: the user's doing
                    self.failed.emit(exc)
                lost = isinstance(exc, ConnectionLostError)  # nothing more to measure on this session
                if request is not None:  # the Recorder finalized the file with what came
                    self._recording = None
                    self.recording_stopped.emit(None)
                    if not lost:  # measuring goes on without the file
                        self._changed.set()
                        continue
                self._wanted = ()

    def _measure(self, names: tuple[str, ...]) -> None:
        state = self.state
        names = tuple(name for name in names if name not in state.refused)
        if not names:
            return
        try:
            try:
                measurement = self.session.measure(list(names)).start()
            except XcpCommandError as exc:
                measurement = self._without_refused(names, exc)
                if measurement is None:
                    return
                names = tuple(measurement.names)
            with measurement:
                state.clock, state.ecu_clock = measurement.time_source, measurement.ecu_timestamps
                state.signals, state.running = names, True
                self.started.emit(names)
                while not self._stop.is_set() and not self._changed.is_set():
                    for batch in measurement.read(_READ_TIMEOUT_S):
                        times = batch.host_time - self.origin
                        for name, values in batch.values.items():
                            self.sink(name, times, values)
                    stats = measurement.stats
                    state.samples, state.lost, state.overloads = stats.samples, stats.lost, stats.overloads
        finally:
            state.running = False
            self.gap(names)

    def _without_refused(self, names: tuple[str, ...], exc: XcpCommandError):
        """After the ECU refused the measurement of ``names`` (``exc``): the refused signals found by halves (those the
        ECU refuses alone), said in ``refused``, and the measurement of the rest started (None: nothing left).

        :raises XcpCommandError: ``exc``, when it is no signal's (a list the ECU has no room for) or none alone fails.
        """
        if exc.command not in _SIGNALS_REFUSED:
            raise exc
        refused: dict[str, str] = {}

        def find(group: tuple[str, ...], error: XcpCommandError | None) -> None:
            if error is None:
                try:
                    self.session.measure(list(group)).start().stop()
                    return
                except XcpCommandError as failed:
                    if failed.command not in _SIGNALS_REFUSED:
                        raise
                    error = failed
            if len(group) == 1:
                refused[group[0]] = self._why_refused(group[0], error)
                return
            half = len(group) // 2
            find(group[:half], None)
            find(group[half:], None)

        find(names, exc)
        if not refused:
            raise exc
        self.state.refused.update(refused)
        self.refused.emit(dict(refused))
        rest = [name for name in names if name not in refused]
        return self.session.measure(rest).start() if rest else None

    def _why_refused(self, name: str, error: XcpCommandError) -> str:
        """The ECU's answer, with the event it refused for ``name`` (its address is in a WRITE_DAQ refusal already)."""
        if error.command != "SET_DAQ_LIST_MODE":
            return str(error)
        event = self.session.measure([name]).events[name]
        return f"{error} (its DAQ event, {self.session.event_name(event)}: one the ECU does not have?)"

    def _record(self, names: tuple[str, ...], request: RecordRequest) -> None:
        from workbench.record import Recorder

        def deliver(batch) -> None:
            times = batch.host_time - self.origin
            for name, values in batch.values.items():
                self.sink(name, times, values)

        state = self.state
        names = tuple(name for name in names if name not in state.refused)
        recorder = Recorder(self.session, request.path, names, can2=request.can2, raw_can=request.raw_can,
                            overwrite=True, on_samples=deliver)
        try:
            with recorder:
                if recorder.measurement is not None:
                    state.clock, state.ecu_clock = recorder.measurement.time_source, recorder.measurement.ecu_timestamps
                state.signals, state.running, state.recording = names, True, request.path
                self.started.emit(names)
                self.recording_started.emit(request)
                while not self._stop.is_set() and self._recording is request and recorder.running:
                    self._stop.wait(_READ_TIMEOUT_S)  # not _changed: a change of signals waits for the end
                    stats = recorder.stats
                    state.recorded_s, state.file_bytes = stats.seconds, stats.file_bytes
                    state.samples, state.lost, state.overloads = stats.samples, stats.lost, stats.overloads
        finally:
            state.running, state.recording = False, None
            self.gap(names)
        if self._recording is request:  # the recording ended by itself (the session closed)
            self._recording = None
        self.recording_stopped.emit(recorder.stats)
        self._changed.set()  # measure what is shown now, without the file
