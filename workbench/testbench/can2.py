"""The bench's CAN2 port: frames sent from the DBC by message and signal names, frames heard decoded.

The bench plays the other nodes of CAN2 (for the FLCU: the PCM) on a python-can bus of its own.
Every frame it hears of a DBC message is decoded into the :class:`~workbench.testbench.timeline.Timeline`
as ``MESSAGE.SIGNAL`` (physical values, numbers) and its receive time is kept for period checks.

Periodic frames start half a period after a frame the ECU sent (when one is heard within a period):
the ECU reads its mailboxes once per task cycle, so a message that arrives mid-cycle is read once
per cycle even when the host's scheduling jitters by a few milliseconds, as a real PCM whose cycle
is not in phase with the ECU's would be most of the time.

python-can's ``udp_multicast`` hands a bus its own frames back (the host's multicast loopback, which
``workbench sim`` in another process needs): the bench marks what it sends in the frame's ``channel``
field, which that interface carries, and drops its own frames as other interfaces do.
"""

from __future__ import annotations

import math
import threading
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.bus_defaults import open_bus
from workbench.errors import InputError, UnknownSymbolError
from workbench.logs import logger

if TYPE_CHECKING:
    import can

    from workbench.can.dbc_file import DbcFile
    from workbench.testbench.timeline import Timeline

__all__ = ["Can2Port"]

log = logger(__name__)

PHASE_WAIT_S = 0.15  # how long a periodic start waits to hear the ECU's cycle


class Can2Port:
    """Sends and hears the messages of ``dbc`` on the bus ``settings`` name (python-can ``Bus`` keyword arguments)."""

    def __init__(self, settings: dict[str, Any], dbc: DbcFile, timeline: Timeline):
        import can

        self.dbc = dbc
        self.database = dbc.database
        self.settings = settings
        self._timeline = timeline
        self.bus = open_bus(settings, "CAN2")
        self._by_id = {(m.frame_id, m.is_extended_frame): m for m in self.database.messages}
        self._frames: dict[str, list[float]] = {}  # message -> receive times (bench s)
        self._lock = threading.Lock()
        self._heard = threading.Event()
        self._last_heard: float | None = None  # bench time of the latest frame another node sent
        self._tasks: dict[str, Any] = {}  # message -> python-can periodic task
        self._started: dict[str, float] = {}  # message -> bench time of its task's first frame (its rhythm's origin)
        self._signals: dict[str, dict[str, float]] = {}  # message -> the signal values it is sent with
        self._others: dict[str, int] = {}  # message the bench sends periodically -> frames of it another node sent
        self._sent: set[str] = set()  # messages the bench sent
        self._heard_from: set[str] = set()  # messages another node sent (the ECU's, a PCM's)
        # udp_multicast loops the bench's frames back to it: marked so, they are known as its own
        self._mark = f"workbench-bench-{id(self):x}" if settings.get("interface") == "udp_multicast" else None
        port = self

        class _Listener(can.Listener):
            def on_message_received(self, msg: can.Message) -> None:
                port._on_frame(msg)

        self._notifier = can.Notifier(self.bus, [_Listener()], timeout=0.05)

    # --- hearing --------------------------------------------------------------------------------

    def _on_frame(self, frame: can.Message) -> None:
        try:
            self._take(frame)
        except Exception:  # python-can's notifier thread would end: the frames after it must still come
            log.exception("CAN2 frame 0x%X not taken", frame.arbitration_id)

    def _take(self, frame: can.Message) -> None:
        if frame.is_error_frame or frame.is_remote_frame or (self._mark is not None and frame.channel == self._mark):
            return
        message = self._by_id.get((frame.arbitration_id, frame.is_extended_id))
        if message is None:
            return
        moment = frame.timestamp - self._timeline.epoch
        with self._lock:
            self._frames.setdefault(message.name, []).append(moment)
            if getattr(frame, "is_rx", True):  # not the bench's own echo (receive_own_messages)
                self._last_heard = moment
                self._heard_from.add(message.name)
                if message.name in self._tasks:
                    self._others[message.name] = self._others.get(message.name, 0) + 1
        self._heard.set()
        try:
            decoded = message.decode(bytes(frame.data), decode_choices=False)
        except Exception:  # a frame of the wrong length: its time is kept, it has no values
            return
        for signal, value in decoded.items():
            self._timeline.add(f"{message.name}.{signal}", np.array([frame.timestamp]), np.array([float(value)]))

    def frame_times(self, message: str, start: float = -np.inf, end: float = np.inf) -> np.ndarray:
        """Receive times (bench s) of ``message`` between ``start`` and ``end``."""
        self.message(message)
        with self._lock:
            times = np.array(self._frames.get(message, ()), dtype=float)
        return times[(times >= start) & (times <= end)]

    def competing(self) -> dict[str, int]:
        """The messages the bench sends periodically that another node sends too (-> its frames heard since):
        two senders of one message make its values alternate (a PCM simulated elsewhere as well)."""
        with self._lock:
            return dict(self._others)

    def silent(self) -> bool:
        """True when the bench sent on CAN2 but heard no other node there: no ECU on this bus (a dead or
        wrong bus, other options than the ECU's), so a stimulus on it reached nothing."""
        with self._lock:
            return bool(self._sent) and not self._heard_from

    def describe(self) -> str:
        shown = {key: value for key, value in self.settings.items() if key != "receive_own_messages"}
        return " ".join(f"{key}={value}" for key, value in shown.items())

    # --- sending --------------------------------------------------------------------------------

    def message(self, name: str):
        try:
            return self.database.get_message_by_name(name)
        except KeyError:
            raise UnknownSymbolError(name, f"the messages of {self.dbc.path.name}") from None

    def frame(self, name: str, signals: dict[str, float], dlc: int | None = None):
        """A frame of message ``name`` with ``signals`` (physical; the others keep their previous or
        initial values); values outside a signal's DBC range are sent as given (a fault to inject)."""
        import can

        message = self.message(name)
        unknown = set(signals) - {signal.name for signal in message.signals}
        if unknown:
            raise UnknownSymbolError(sorted(unknown)[0], f"the signals of {name}")
        values = self._signals.setdefault(name, {s.name: s.initial or 0 for s in message.signals})
        values.update(signals)
        try:
            data = message.encode(values, strict=False)
        except Exception as exc:  # cantools' EncodeError and friends: a value the raw type cannot hold
            raise InputError(f"{name}: cannot encode {signals}: {exc}") from None
        if dlc is not None:
            if not 0 <= dlc <= 8:
                raise InputError(f"{name}: a classic CAN frame has a DLC of 0..8, not {dlc}")
            data = bytes(data).ljust(8, b"\0")[:dlc]
        return can.Message(arbitration_id=message.frame_id, is_extended_id=message.is_extended_frame, data=data,
                           channel=self._mark)

    def send(self, name: str, signals: dict[str, float], *, period_s: float | None = None,
             dlc: int | None = None) -> tuple[str, float]:
        """One frame now, or every ``period_s`` until :meth:`stop`; a message already sent periodically
        gets the new values from its next frame on, in the same rhythm (this returns when that frame is due).
        ``dlc`` (another length than the DBC's) holds for this call's frames only. Returns what it did and
        how long it waited for the ECU's cycle (s) before the first frame."""
        task = self._tasks.get(name)
        frame = self.frame(name, signals, dlc)
        self._sent.add(name)
        if task is not None and period_s in (None, task.period):
            task.modify_data(frame)
            # the frame due next carries it (a late one of the task's thread may already): the stimulus begins now
            # and is complete when that frame is due, whence a deadline counts
            time.sleep(self._until_next_frame(name, task.period))
            return "from its next frame on", 0.0
        if task is not None:
            self.stop(name)
        if period_s is None:
            self.bus.send(frame)
            return "once", 0.0
        delay = self._phase_delay(period_s)
        if delay:
            time.sleep(delay)
        self._started[name] = self._timeline.now()
        self._tasks[name] = self.bus.send_periodic(frame, period_s)
        return (f"every {period_s * 1000:g} ms" + (", half a cycle after the ECU's frames" if delay else ""),
                delay)

    def _until_next_frame(self, name: str, period_s: float) -> float:
        """Seconds until the next frame of the periodic ``name``: python-can's tasks keep the rhythm of their
        first frame (the kernel's for SocketCAN's broadcast manager, a thread's due times elsewhere)."""
        since = self._timeline.now() - self._started[name]
        return (math.floor(since / period_s) + 1) * period_s - since

    def _phase_delay(self, period_s: float) -> float:
        """Seconds to wait so that the first frame goes half a period after a frame of another node."""
        if self._last_heard is None:
            self._heard.wait(min(period_s, PHASE_WAIT_S))
        with self._lock:
            last = self._last_heard
        if last is None:
            return 0.0
        now = self._timeline.now()
        due = last + period_s / 2
        while due < now:
            due += period_s
        return due - now

    def stop(self, name: str) -> bool:
        """Stop sending ``name``; False when it was not sent periodically."""
        self.message(name)
        task = self._tasks.pop(name, None)
        if task is None:
            return False
        task.stop()
        return True

    def stop_all(self) -> None:
        for name in list(self._tasks):
            self.stop(name)

    def close(self) -> None:
        self.stop_all()
        self._notifier.stop()
        self.bus.shutdown()
