"""Frames in and out of one python-can bus for the simulator, with the bus timing model.

Without a :class:`BusClock` a :class:`Transmitter` sends at once, in the caller's thread.
With one, frames wait in transmit buffers and go on the bus no faster than a real bus of
that bit rate carries them (see :class:`BusClock` for the lead a sender may have).
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable

import can

from workbench.logs import logger
from workbench.sim.can_timing import BusClock

__all__ = ["ECHOING_INTERFACES", "EchoFilter", "Receiver", "Transmitter"]

log = logger(__name__)

TX_BUFFER_FRAMES = 256  # DTOs the slave can buffer for transmission
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
    """Puts frames on one bus; with a clock, paced by the bus model from two transmit buffers.

    * :meth:`send` takes frames that must not be lost (XCP responses, CAN2 messages): they
      wait in an unbounded buffer (one response per request keeps it short) and go before any
      queued DTO, as XCP drivers send a pending response before the next DTO;
    * :meth:`send_dtos` takes the DTOs of one DAQ list sample, all or none: when the DTO
      buffer (``capacity`` frames) has no room for all of them the whole sample is dropped
      (a DAQ overload), so a master never assembles a sample from two cycles.

    A thread puts buffered frames on the bus as the bus model frees up; a frame that finds
    the buffers empty and the bus model idle goes out at once from the caller's thread,
    sparing a thread hand-off per round trip. :attr:`sent` and :attr:`dropped` count frames.
    """

    def __init__(
        self,
        bus: can.BusABC,
        clock: BusClock | None = None,
        name: str = "bus",
        echoes: EchoFilter | None = None,
        capacity: int = TX_BUFFER_FRAMES,
    ):
        self.bus = bus
        self.clock = clock
        self.name = name
        self.capacity = capacity
        self._echoes = echoes
        self.sent = 0
        self.dropped = 0
        self._on_bus = threading.Lock()  # one frame at a time, in the order the echo filter expects
        self._ready = threading.Condition()
        self._priority: deque[tuple[can.Message, float | None]] = deque()
        self._dtos: deque[tuple[can.Message, float | None]] = deque()
        self._busy = False  # a frame is between the buffers and the bus
        self._closed = False
        self._thread: threading.Thread | None = None
        if clock is not None:
            self._thread = threading.Thread(target=self._run, name=f"sim-tx-{name}", daemon=True)
            self._thread.start()

    def send(self, message: can.Message) -> None:
        """Transmit a frame that must not be lost (it waits for the bus, never for buffer room)."""
        self._enqueue([message], self._priority)

    def send_dtos(self, messages: list[can.Message]) -> bool:
        """Transmit one DAQ list sample's DTOs; False (none sent) when the DTO buffer lacks room for all."""
        return self._enqueue(messages, self._dtos, self.capacity)

    def _enqueue(self, messages: list[can.Message], lane: deque, limit: int | None = None) -> bool:
        direct = None
        with self._ready:
            if self._closed or (limit is not None and self._thread is not None and len(lane) + len(messages) > limit):
                self.dropped += len(messages)
                return False
            if self._thread is None:
                direct, messages = messages, []
            elif messages and not (self._busy or self._priority or self._dtos):
                end = self.clock.occupy(messages[0])
                if self.clock.is_due(end):
                    direct, self._busy = messages[:1], True
                else:
                    lane.append((messages[0], end))
                messages = messages[1:]
            lane.extend((message, None) for message in messages)
            self._ready.notify()
        for message in direct or ():
            self._put_on_bus(message)
        return True

    def _run(self) -> None:
        while True:
            with self._ready:
                while not self._closed and (self._busy or not (self._priority or self._dtos)):
                    self._ready.wait(_POLL_S)
                if self._closed:
                    return
                message, end = (self._priority or self._dtos).popleft()
                self._busy = True
            self.clock.wait_until(self.clock.occupy(message) if end is None else end)
            try:
                self._put_on_bus(message)
            except Exception:  # a bus bug must not end transmission
                log.exception("%s: frame 0x%X not sent", self.name, message.arbitration_id)

    def _put_on_bus(self, message: can.Message) -> None:
        ok = False
        try:
            with self._on_bus:
                if self._echoes is not None:
                    self._echoes.sent(message)
                self.bus.send(message)
            ok = True
        except (can.CanError, OSError) as exc:
            log.warning("%s: frame 0x%X not sent: %s", self.name, message.arbitration_id, exc)
        finally:  # whatever the bus raised, the next frame may go
            with self._ready:
                self._busy = False
                if ok:
                    self.sent += 1
                else:
                    self.dropped += 1
                self._ready.notify()

    def close(self) -> None:
        """Stop the thread; frames still buffered are not sent. Safe to call twice."""
        with self._ready:
            self._closed = True
            self._ready.notify_all()
        if self._thread is not None:
            self._thread.join(timeout=2)


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
        self._name = name
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f"sim-rx-{name}", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        failing = False
        while not self._stop.is_set():
            try:
                message = self.bus.recv(timeout=_POLL_S)
            except can.CanError as exc:  # said once per outage, not every poll
                log.log(logging.DEBUG if failing else logging.WARNING, "%s: receive failed: %s", self._name, exc)
                failing = True
                self._stop.wait(_POLL_S)
                continue
            except (OSError, ValueError) as exc:  # the bus was shut down under us
                if not self._stop.is_set():
                    log.error("%s: reception ended: %s", self._name, exc)
                return
            failing = False
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
