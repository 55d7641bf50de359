"""An in-process CAN wire between a master and the simulated ECU on which a timeout costs no time and a loaded
machine causes none.

With its clock standing still (``time_scale=None``), no bus timing model and no delayed answers, the simulator
sends only in answer to a frame, from its receive thread, before it waits for the next one. So once it waits
for a frame with none on the way to it, and none is on the way back, nothing more will come: the master's
receive gives up at once, as it would after T1. While the simulator has a frame to handle, the master waits
for the answer however long the machine takes to schedule it. A timeout then means that no answer comes,
never that it came late, and the tests of what the master does about a missing answer (a power cut, a lost
frame) run at the speed of the code whatever the load.

The master reads in its own thread (``Link`` without DAQ); a python-can Notifier on :attr:`LockstepWire.master`
would poll it without pause while the simulator waits.
"""

from __future__ import annotations

import threading
import time
from collections import deque

import can

__all__ = ["LockstepWire"]

PATIENCE_S = 30.0  # the longest the master waits for a simulator at work: beyond, it is stuck, not slow


class LockstepWire:
    """The two ends: :attr:`master` (give it to ``Session.open(bus=...)``) and :attr:`ecu` (the simulator's
    ``can1``). Both stay the caller's: :meth:`shutdown` them (or leave a ``with`` block)."""

    def __init__(self) -> None:
        self.changed = threading.Condition()
        self.ecu = _End(self, "lockstep-ecu", waits_for_answers=False)
        self.master = _End(self, "lockstep-master", waits_for_answers=True)
        self.ecu.peer, self.master.peer = self.master, self.ecu

    def shutdown(self) -> None:
        self.master.shutdown()
        self.ecu.shutdown()

    def __enter__(self) -> LockstepWire:
        return self

    def __exit__(self, *exc_info) -> None:
        self.shutdown()


class _End(can.BusABC):
    """One end of a :class:`LockstepWire`: frames sent here arrive at the other end."""

    def __init__(self, wire: LockstepWire, name: str, *, waits_for_answers: bool):
        super().__init__(channel=name)
        self.channel_info = name
        self._wire = wire
        self._waits_for_answers = waits_for_answers
        self.peer: _End | None = None
        self.frames: deque[can.Message] = deque()
        self.idle = True  # waiting in recv(), the last frame it took handled (what the ECU end tells the master)

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        msg.timestamp = time.time()
        msg.channel = self.channel_info
        with self._wire.changed:
            self.peer.frames.append(msg)
            self._wire.changed.notify_all()

    def recv(self, timeout: float | None = None) -> can.Message | None:
        """The next frame; None when ``timeout`` is 0 and none is here. The master's end gives up at once when
        the ECU's end is idle with nothing on the way (no answer can come); the ECU's end waits ``timeout``."""
        patient = self._waits_for_answers
        deadline = time.monotonic() + (PATIENCE_S if patient else 1e9 if timeout is None else timeout)
        with self._wire.changed:
            self.idle = True
            self._wire.changed.notify_all()
            while not self.frames:
                left = deadline - time.monotonic()
                if timeout == 0 or left <= 0 or (patient and self.peer.idle and not self.peer.frames):
                    return None
                self._wire.changed.wait(left)
            self.idle = False
            return self.frames.popleft()

    def _recv_internal(self, timeout: float | None):
        return self.recv(timeout), True
