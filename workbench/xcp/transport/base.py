"""What an XCP transport does for the link: packets onto the wire and back, in the caller's thread or in a
receiver of its own.

A transport knows its wire (CAN frames, UDP datagrams, a TCP stream) and nothing of XCP commands; the
:class:`~workbench.xcp.link.Link` above it decides which thread reads. Two ways to read:

* :meth:`Transport.receive` in the caller's thread (no DAQ running): what one read of the wire brings;
* :meth:`Transport.start_receiver` until :meth:`Transport.stop_receiver`: every packet goes to ``deliver``
  from one thread (XCP on Ethernet: a thread on the socket; XCP on CAN: python-can's Notifier).

A transport that cannot go on (the peer closed the connection, the socket or the bus failed) raises
:class:`LinkBroken` from :meth:`~Transport.send` and :meth:`~Transport.receive`, or reports it to
``broken`` from its receiver; the link turns it into :class:`~workbench.errors.ConnectionLostError`.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from workbench.errors import WorkbenchError
from workbench.logs import logger

log = logger(__name__)

__all__ = ["RECEIVER_POLL_S", "Broken", "Deliver", "LinkBroken", "Transport"]

Deliver = Callable[[bytes, int], None]  # (packet, host receive time in ns since the epoch)
Broken = Callable[[str], None]  # (what happened, for people)
RECEIVER_POLL_S = 0.05  # how long a receiver waits on the wire before it looks whether it should stop


class LinkBroken(Exception):
    """The transport cannot go on; ``reason`` says why, for people ("the ECU closed the TCP connection")."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(reason)


class Transport:
    """One XCP transport. Subclasses implement :meth:`send`, :meth:`receive`, :meth:`describe` and
    :meth:`close`; the receiver here is a thread that calls :meth:`receive` (XCP on CAN has its own)."""

    kind = ""

    def __init__(self) -> None:
        self._receiver: threading.Thread | None = None
        self._receiving = False

    def describe(self) -> str:
        raise NotImplementedError

    def send(self, packet: bytes) -> None:
        """Send one XCP packet (PID first).

        :raises LinkBroken: the wire is gone. :raises WorkbenchError: this packet could not be sent.
        """
        raise NotImplementedError

    def receive(self, timeout_s: float) -> list[bytes] | None:
        """The slave's packets in what one read of the wire brings, waiting up to ``timeout_s`` (0: what is
        there); ``[]`` when something came that carries none (another node's frame), None when nothing came.

        :raises LinkBroken: the wire is gone.
        """
        raise NotImplementedError

    def start_receiver(self, deliver: Deliver, broken: Broken) -> None:
        """Hand every packet to ``deliver`` from a thread of the transport's own until :meth:`stop_receiver`;
        ``broken`` hears once why the wire is gone (the receiver ends then)."""
        self._receiving = True
        self._receiver = threading.Thread(target=self._run_receiver, args=(deliver, broken),
                                          name=f"xcp-{self.kind.lower()}-rx", daemon=True)
        self._receiver.start()

    def _run_receiver(self, deliver: Deliver, broken: Broken) -> None:
        while self._receiving:
            try:
                packets = self.receive(RECEIVER_POLL_S)
            except LinkBroken as exc:
                if self._receiving:
                    broken(exc.reason)
                return
            except Exception as exc:  # the receiver must never end with a traceback on the user's terminal
                log.debug("XCP receiver failed", exc_info=True)
                broken(f"reception failed: {type(exc).__name__}: {exc}")
                return
            if packets:
                now = time.time_ns()
                for packet in packets:
                    deliver(packet, now)

    def stop_receiver(self) -> None:
        """Stop the receiver (it ends within :data:`RECEIVER_POLL_S`); safe to call when none runs."""
        self._receiving = False
        receiver, self._receiver = self._receiver, None
        if receiver is not None and receiver is not threading.current_thread():
            receiver.join(timeout=2 * RECEIVER_POLL_S + 1.0)

    def add_listener(self, listener) -> None:
        """Hand every frame of the wire to ``listener`` too, while a receiver runs (XCP on CAN only)."""
        raise WorkbenchError(f"{self.describe()} has no bus to listen to")

    def remove_listener(self, listener) -> None:
        raise ValueError("no such listener")

    def close(self) -> None:
        raise NotImplementedError
