"""Frames in and out of one python-can bus for the simulator, with the bus timing model.

Without a :class:`BusClock` a :class:`Transmitter` sends at once, in the caller's thread.
With one, frames queue in a transmit buffer and a thread puts them on the bus no faster
than a real bus of that bit rate: each waits until the bus is free and its bits have
passed. A full buffer drops frames marked droppable (DTOs: a DAQ overload) and blocks
for the others (responses).
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections import deque
from collections.abc import Callable

import can

from workbench.sim.can_timing import BusClock

log = logging.getLogger(__name__)

TX_BUFFER_FRAMES = 256
_POLL_S = 0.05
ECHOING_INTERFACES = frozenset({"udp_multicast"})  # they hand a node its own frames back


class EchoFilter:
    """Recognises the frames this node sent when the bus hands them back (udp_multicast does).

    Echoes come back in sending order, so each received frame is compared with the oldest
    frame still unconfirmed; entries older than ``max_age_s`` are forgotten.
    """

    def __init__(self, max_age_s: float = 1.0):
        self._pending: deque[tuple[float, int, bool, bytes]] = deque(maxlen=4096)
        self._lock = threading.Lock()
        self._max_age_s = max_age_s

    def sent(self, message: can.Message) -> None:
        with self._lock:
            self._pending.append((time.monotonic(), message.arbitration_id, message.is_extended_id, bytes(message.data)))

    def is_echo(self, message: can.Message) -> bool:
        key = (message.arbitration_id, message.is_extended_id, bytes(message.data))
        with self._lock:
            now = time.monotonic()
            while self._pending and now - self._pending[0][0] > self._max_age_s:
                self._pending.popleft()
            if self._pending and self._pending[0][1:] == key:
                self._pending.popleft()
                return True
        return False


class Transmitter:
    def __init__(self, bus: can.BusABC, clock: BusClock | None = None, name: str = "bus", echoes: EchoFilter | None = None):
        self.bus = bus
        self.clock = clock
        self.name = name
        self._echoes = echoes
        self.sent = 0
        self.dropped = 0
        self._queue: queue.Queue[can.Message | None] = queue.Queue(TX_BUFFER_FRAMES)
        self._thread: threading.Thread | None = None
        if clock is not None:
            self._thread = threading.Thread(target=self._run, name=f"sim-tx-{name}", daemon=True)
            self._thread.start()

    def send(self, message: can.Message, droppable: bool = False) -> bool:
        """Transmit (or buffer) a frame; False when a droppable frame found the buffer full."""
        if self._thread is None:
            self._put_on_bus(message)
            return True
        try:
            self._queue.put(message, block=not droppable)
        except queue.Full:
            self.dropped += 1
            return False
        return True

    def _run(self) -> None:
        while True:
            message = self._queue.get()
            if message is None:
                return
            self.clock.wait_until(self.clock.occupy(message))
            self._put_on_bus(message)

    def _put_on_bus(self, message: can.Message) -> None:
        try:
            if self._echoes is not None:
                self._echoes.sent(message)
            self.bus.send(message)
            self.sent += 1
        except can.CanError as exc:
            self.dropped += 1
            log.warning("%s: frame 0x%X not sent: %s", self.name, message.arbitration_id, exc)

    def close(self) -> None:
        if self._thread is not None:
            self._queue.put(None)
            self._thread.join(timeout=2)
            self._thread = None


class Receiver:
    """A thread that hands every frame of ``bus`` to ``on_frame`` until :meth:`stop`.

    With a clock, each received frame first occupies the bus (the sender's frame took that
    long on a real bus), so request-response round trips include both frames' time.
    """

    def __init__(
        self,
        bus: can.BusABC,
        on_frame: Callable[[can.Message], None],
        clock: BusClock | None = None,
        name: str = "bus",
        echoes: EchoFilter | None = None,
    ):
        self.bus = bus
        self._on_frame = on_frame
        self._clock = clock
        self._echoes = echoes
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f"sim-rx-{name}", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                message = self.bus.recv(timeout=_POLL_S)
            except can.CanError as exc:
                log.warning("receive failed: %s", exc)
                self._stop.wait(_POLL_S)
                continue
            except (OSError, ValueError):  # the bus was shut down under us
                if self._stop.is_set():
                    return
                raise
            if message is None or message.is_error_frame:
                continue
            if self._echoes is not None and self._echoes.is_echo(message):
                continue
            if self._clock is not None:
                self._clock.wait_until(self._clock.occupy(message))
            try:
                self._on_frame(message)
            except Exception:  # one bad frame must not end the ECU's reception
                log.exception("frame 0x%X: handler failed", message.arbitration_id)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
