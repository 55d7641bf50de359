"""DAQ in a thread of its own: the session's measurement feeds the ring buffers, nothing else.

:class:`DaqAcquisition` runs ``session.measure(names)`` in a background thread and appends every
batch to the signals' :class:`~workbench.gui.ringbuffer.RingBuffer`\\ s; the plots read the buffers on
their own timer. When the set of signals changes, the running measurement is stopped and a new
one started with the new set (the ECU's DAQ lists are configured for what is displayed, as CANape
does). Times are the ECU's DAQ timestamps mapped to host time, minus the hub's origin.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from PySide6.QtCore import QObject, Signal

from workbench.errors import WorkbenchError

log = logging.getLogger(__name__)

__all__ = ["DaqAcquisition", "DaqState"]

_READ_TIMEOUT_S = 0.1  # how long one read waits for samples: also how soon a change of signals is taken


class DaqState:
    """What the status bar shows about the running measurement (written by the thread, read by the GUI)."""

    def __init__(self):
        self.signals: tuple[str, ...] = ()
        self.samples = 0
        self.lost = 0
        self.overloads = 0
        self.running = False


class DaqAcquisition(QObject):
    """Measures the wanted signals of one session until :meth:`stop`.

    ``sink(name, times, values)`` gets every signal's new samples (from the acquisition thread).
    """

    failed = Signal(object)  # the exception that stopped the measurement
    started = Signal(object)  # the names being measured

    def __init__(self, session, sink: Callable, origin: float, parent: QObject | None = None):
        super().__init__(parent)
        self.session = session
        self.sink = sink
        self.origin = origin
        self.state = DaqState()
        self._wanted: tuple[str, ...] = ()
        self._changed = threading.Event()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

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

    def stop(self, timeout_s: float = 5.0) -> None:
        """Stop the measurement and wait for the thread (the DAQ lists are stopped on the ECU)."""
        self._stop.set()
        self._changed.set()
        if self._thread is not None:
            self._thread.join(timeout_s)
            self._thread = None

    def _run(self) -> None:
        while not self._stop.is_set():
            self._changed.wait()
            self._changed.clear()
            if self._stop.is_set():
                break
            names = self._wanted
            if not names:
                continue
            try:
                self._measure(names)
            except WorkbenchError as exc:
                self.state.running = False
                if not self._stop.is_set():
                    self.failed.emit(exc)
                self._wanted = ()
            except Exception as exc:  # noqa: BLE001 - shown as a dialog; the thread must not die silently
                log.exception("DAQ acquisition")
                self.state.running = False
                self.failed.emit(exc)
                self._wanted = ()

    def _measure(self, names: tuple[str, ...]) -> None:
        state = self.state
        with self.session.measure(list(names)) as measurement:
            state.signals, state.running = names, True
            self.started.emit(names)
            while not self._stop.is_set() and not self._changed.is_set():
                for batch in measurement.read(_READ_TIMEOUT_S):
                    times = batch.host_time - self.origin
                    for name, values in batch.values.items():
                        self.sink(name, times, values)
                stats = measurement.stats
                state.samples, state.lost, state.overloads = stats.samples, stats.lost, stats.overloads
        state.running = False
