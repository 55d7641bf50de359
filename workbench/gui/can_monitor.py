"""CAN2 beside XCP: a listener on the ECU's bus that decodes the DBC's messages and keeps a trace.

:class:`CanMonitor` listens through the session (:meth:`~workbench.session.Session.listen_can`: on the
XCP bus the link's own receive thread, on another bus one it shares with a recorder), decodes every frame
the DBCs know into signals named ``Message.Signal`` (their samples go to the same sink as the DAQ's),
keeps the newest frames for the trace view, and counts the bits on the bus for the bus load. Nothing here
blocks the GUI.
"""

from __future__ import annotations

import collections
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
import numpy as np

from workbench.bus_defaults import BusSpec
from workbench.logs import logger

log = logger(__name__)

__all__ = ["CanMonitor", "DbcSignal", "TraceEntry", "dbc_signals"]

_TRACE_FRAMES = 2000


@dataclass(frozen=True)
class DbcSignal:
    name: str  # Message.Signal
    message: str
    signal: str
    unit: str
    minimum: float | None
    maximum: float | None
    comment: str


@dataclass(frozen=True)
class TraceEntry:
    time: float  # s since the monitor's origin
    arbitration_id: int
    extended: bool
    data: bytes
    message: str  # the DBC's name, "" when unknown
    decoded: str  # "Signal=value unit, ..."


def dbc_signals(databases: Iterable) -> list[DbcSignal]:
    """Every signal of the cantools databases' messages, named ``Message.Signal``."""
    found = []
    for database in databases:
        for message in database.messages:
            for signal in message.signals:
                found.append(DbcSignal(f"{message.name}.{signal.name}", message.name, signal.name, signal.unit or "",
                                       signal.minimum, signal.maximum, _comment(signal.comment)))
    return found


class CanMonitor:
    """Listen to ``bus`` through ``session`` (default: its XCP bus) and decode with ``databases`` (cantools).

    :raises InputError: no ``bus`` on a session whose XCP runs on Ethernet. :raises WorkbenchError: the bus
        cannot be opened.
    """

    def __init__(self, session, databases: Iterable, sink: Callable, origin: float, bitrate: int | None = None,
                 bus: BusSpec | None = None):
        self.databases = list(databases)
        self.sink = sink
        self.origin = origin
        self.bitrate = bitrate
        self.trace: collections.deque[TraceEntry] = collections.deque(maxlen=_TRACE_FRAMES)
        self.frames = 0
        self._bits = 0
        self._load_window: collections.deque[tuple[float, int]] = collections.deque()
        self._lock = threading.Lock()
        self._messages = {}
        for database in self.databases:
            for message in database.messages:
                self._messages[(message.frame_id, message.is_extended_frame)] = message
        self.listening = session.listen_can(self._on_frame, bus)

    def _on_frame(self, msg) -> None:
        if msg.is_error_frame or msg.is_remote_frame:
            return
        from workbench.sim.can_timing import frame_bits

        now = msg.timestamp - self.origin
        bits = frame_bits(msg)
        message = self._messages.get((msg.arbitration_id, msg.is_extended_id))
        decoded = ""
        if message is not None:
            try:
                values = message.decode(bytes(msg.data), decode_choices=False)
            except (ValueError, KeyError) as exc:  # cantools: a frame too short, bad multiplexer
                decoded = f"cannot decode: {exc}"
            else:
                for name, value in values.items():
                    self.sink(f"{message.name}.{name}", np.array([now]), np.array([float(value)]))
                units = {s.name: s.unit or "" for s in message.signals}
                decoded = ", ".join(f"{name}={_number(value)}{' ' + units[name] if units[name] else ''}"
                                    for name, value in values.items())
        with self._lock:
            self.frames += 1
            self._bits += bits
            self._load_window.append((msg.timestamp, bits))
            self.trace.append(TraceEntry(now, msg.arbitration_id, msg.is_extended_id, bytes(msg.data),
                                         message.name if message is not None else "", decoded))

    def bus_load(self, window_s: float = 1.0) -> float | None:
        """Share of the bus' capacity used over the last ``window_s`` (0..1), None without a bit rate."""
        if not self.bitrate:
            return None
        horizon = time.time() - window_s
        with self._lock:
            while self._load_window and self._load_window[0][0] < horizon:
                self._load_window.popleft()
            bits = sum(b for _, b in self._load_window)
        return bits / (self.bitrate * window_s)

    def trace_snapshot(self) -> list[TraceEntry]:
        with self._lock:
            return list(self.trace)

    def close(self) -> None:
        """Stop listening (the bus closes with its last listener); safe to call twice."""
        self.listening.close()


def _number(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _comment(comment) -> str:
    if isinstance(comment, dict):  # cantools keeps multilingual comments as a dict
        return next(iter(comment.values()), "")
    return comment or ""
