"""Every live signal of a window in one place: XCP measurements by DAQ and CAN2 signals by DBC.

The :class:`SignalHub` owns one :class:`~workbench.gui.ringbuffer.RingBuffer` per signal and
knows each signal's unit and source. Views say which signals they show (:meth:`SignalHub.show`);
the hub measures the union of the XCP ones by DAQ (restarting the measurement when the set
changes) while the CAN monitor decodes every CAN2 message anyway. Times share one origin, the
hub's creation, so XCP and CAN2 samples line up on one time axis.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QObject, Signal

from workbench.gui.formatting import format_value
from workbench.gui.ringbuffer import RingBuffer
from workbench.gui.worker import run_task
from workbench.logs import logger

log = logger(__name__)

__all__ = ["SignalHub", "SignalInfo"]

_CAPACITY = 300_000  # samples kept per signal: 5 minutes at 1 kHz


@dataclass(frozen=True)
class SignalInfo:
    name: str
    source: str  # "XCP" (DAQ), "CAN2" (DBC) or "MDF" (a measurement file)
    unit: str = ""
    description: str = ""
    minimum: float | None = None
    maximum: float | None = None
    states: tuple[tuple[float, str], ...] = ()  # verbal values (TAB_VERB): value -> text
    decimals: int | None = None  # the A2L's FORMAT; None: as many as the value needs
    label: str = ""  # how a legend names it when not by its name (a file's channel: without the file)
    two_states: tuple[tuple[float, str], ...] = ()  # a two-state signal without texts (0/1): its values, labelled

    @property
    def lane_states(self) -> tuple[tuple[float, str], ...]:
        """The states a plot's digital lane labels: the verbal ones, or a two-state signal's values; ():
        the signal is drawn on its unit's scale."""
        return self.states or self.two_states

    def format(self, value: float | None) -> str:
        """``value`` as the A2L shows it: its verbal name, or its FORMAT's decimals."""
        return format_value(value, self.decimals, self.states)


class SignalHub(QObject):
    """Buffers, units and sources of the signals views show."""

    catalog_changed = Signal()
    measuring = Signal(object)  # the XCP names now measured
    failed = Signal(object)

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self.origin = time.time()
        self._buffers: dict[str, RingBuffer] = {}
        self._lock = threading.Lock()
        self._catalog: dict[str, SignalInfo] = {}
        self._resolver = None  # name -> SignalInfo | None, for names not in the catalog (the A2L's)
        self._shown: dict[int, set[str]] = {}  # view id -> names
        self.acquisition = None  # DaqAcquisition while connected
        self.can_monitor = None  # CanMonitor while a CAN bus is listened to

    # --- catalog --------------------------------------------------------------------------------

    def add_signals(self, infos) -> None:
        for info in infos:
            self._catalog[info.name] = info
        self.catalog_changed.emit()

    def set_resolver(self, resolver) -> None:
        """``resolver(name) -> SignalInfo | None`` describes signals on first use (the A2L's measurements:
        a big A2L has tens of thousands, most never shown)."""
        self._resolver = resolver
        self._catalog = {name: info for name, info in self._catalog.items() if info.source != "XCP"}
        self.catalog_changed.emit()

    def clear(self) -> None:
        """No signals, no samples, nothing measured (another project opens; its views were closed first)."""
        self.detach()
        self.origin = time.time()  # its measurements' time starts anew
        with self._lock:
            self._buffers = {}
        self._catalog = {}
        self._resolver = None
        self._shown = {}
        self.catalog_changed.emit()

    def _lookup(self, name: str) -> SignalInfo | None:
        info = self._catalog.get(name)
        if info is None and self._resolver is not None:
            info = self._resolver(name)
            if info is not None:
                self._catalog[name] = info
        return info

    def info(self, name: str) -> SignalInfo:
        return self._lookup(name) or SignalInfo(name, "XCP")

    def known(self, name: str) -> bool:
        return self._lookup(name) is not None

    def can2_signal(self, signal: str) -> str | None:
        """The ``Message.Signal`` name of the one CAN2 signal called ``signal`` (any case), None when none or
        several messages have one."""
        key = signal.upper()
        found = [name for name, info in self._catalog.items()
                 if info.source == "CAN2" and name.rpartition(".")[2].upper() == key]
        return found[0] if len(found) == 1 else None

    # --- samples --------------------------------------------------------------------------------

    def refused(self, name: str) -> str:
        """Why the ECU does not sample ``name`` on this connection ("" when it does, or nothing is measured)."""
        return self.acquisition.state.refused.get(name, "") if self.acquisition is not None else ""

    def buffer(self, name: str) -> RingBuffer:
        found = self._buffers.get(name)
        if found is None:
            with self._lock:
                found = self._buffers.setdefault(name, RingBuffer(_CAPACITY))
        return found

    def sink(self, name: str, times, values) -> None:
        """Append samples of ``name`` (any thread): the acquisition's and CAN monitor's callback.
        Verbal values (texts of a TAB_VERB) are kept as their numbers, so they plot as steps."""
        values = np.asarray(values)
        if values.dtype == object:
            numbers = {text: raw for raw, text in self.info(name).states}
            values = np.array([numbers.get(v, np.nan) if isinstance(v, str) else v for v in values.ravel()],
                              dtype=np.float64)
        elif values.ndim > 1:  # an array measurement: its first element (views show scalars)
            values = values.reshape(len(values), -1)[:, 0]
        self.buffer(name).append(times, values)

    def load(self, name: str, times, values) -> None:
        """All the samples of ``name`` at once (a measurement file's channel), in a buffer that holds them."""
        buffer = RingBuffer(max(len(times), 1))
        buffer.append(times, values)
        with self._lock:
            self._buffers[name] = buffer

    def mark_gap(self, names) -> None:
        """The samples of ``names`` pause here (any thread): their plots break the line."""
        for name in names:
            self.buffer(name).mark_gap()

    def now(self) -> float:
        """Seconds since the origin, on the samples' time axis."""
        return time.time() - self.origin

    # --- what is measured -----------------------------------------------------------------------

    def show(self, view: QObject, names) -> None:
        """``view`` shows ``names`` from now on (replacing what it showed); a view that goes away
        calls :meth:`hide` (no ``destroyed`` hook: it may fire while Python shuts down)."""
        self._shown[id(view)] = set(names)
        self._update_measurement()

    def hide(self, view: QObject) -> None:
        """``view`` shows nothing any more."""
        self._shown.pop(id(view), None)
        self._update_measurement()

    def shown(self) -> set[str]:
        return set().union(*self._shown.values()) if self._shown else set()

    def xcp_shown(self) -> list[str]:
        return sorted(n for n in self.shown() if self.info(n).source == "XCP")

    def _update_measurement(self) -> None:
        if self.acquisition is not None:
            self.acquisition.measure(self.xcp_shown())

    def attach(self, acquisition, can_monitor=None) -> None:
        """Start measuring through ``acquisition`` (and listen with ``can_monitor``) what views show; a measurement
        attached before is stopped, and ``acquisition`` starts once it has."""
        acquisition.after = self.detach()
        self.acquisition = acquisition
        self.can_monitor = can_monitor
        acquisition.failed.connect(self.failed)
        acquisition.started.connect(self.measuring)
        self._update_measurement()

    def listen(self, can_monitor) -> None:
        """Take CAN2's samples from ``can_monitor`` too (made in a worker, after the measurement was attached)."""
        self.can_monitor = can_monitor

    def detach(self) -> threading.Event:
        """Stop the measurement and the CAN monitor (the buffers keep their samples), without waiting for them in
        this (the GUI) thread: their threads end in a worker, which sets the event returned once they have."""
        acquisition, self.acquisition = self.acquisition, None
        monitor, self.can_monitor = self.can_monitor, None
        stopped = threading.Event()
        if acquisition is None and monitor is None:
            stopped.set()
            return stopped
        if acquisition is not None:
            acquisition.stop()
        can2 = [name for name, info in self._catalog.items() if info.source == "CAN2"] if monitor is not None else []
        run_task(self._stopped, acquisition, monitor, can2, stopped,
                 on_error=lambda exc: log.debug("stopping the measurement: %s", exc))
        return stopped

    def _stopped(self, acquisition, monitor, can2: list[str], stopped: threading.Event) -> None:
        """In a worker: the DAQ thread ended, the CAN monitor's listener taken off its bus (whose receive thread may
        stop: a join) and its signals' lines broken there; then ``stopped`` is set."""
        try:
            if acquisition is not None:
                acquisition.wait()
            if monitor is not None:
                monitor.close()
                self.mark_gap(can2)
        finally:
            stopped.set()
