"""XCP on CAN for the master (ASAM XCP Part 3), over any python-can bus: classic CAN and CAN FD.

Commands go out on CAN_ID_MASTER; responses, events and DTOs come on CAN_ID_SLAVE and DTOs also on
the DAQ_LIST_CAN_ID ids (FIXED ones, and those the master assigns to VARIABLE lists with SET_DAQ_ID). Frames of other ids (other nodes, CAN2 on a shared bus) are passed over.
A frame is as long as its packet, except:

* MAX_DLC_REQUIRED: every frame is padded to MAX_DLC (8 on classic CAN, the A2L's MAX_DLC on CAN FD);
* CAN FD: a packet longer than 8 bytes is padded to the next length a DLC can say (12, 16, 20, 24, 32,
  48, 64).

A bus the transport opens itself gets hardware filters for the XCP ids (python-can filters in software
where the backend cannot) and, on udp_multicast, a wide receive buffer. While a receiver runs, python-can's
:class:`~can.Notifier` reads the bus (with one listener for the XCP ids); a bus another Notifier already
reads gets the listener added to that one instead (python-can allows one Notifier per bus).
"""

from __future__ import annotations

import socket
import time
from typing import TYPE_CHECKING

from workbench.bus_defaults import open_bus
from workbench.errors import InputError, WorkbenchError
from workbench.logs import logger
from workbench.xcp_protocol import CanId
from workbench.xcp.transport.base import RECEIVER_POLL_S, Broken, Deliver, LinkBroken, Transport

if TYPE_CHECKING:
    import can

    from workbench.xcp.link import LinkSettings

log = logger(__name__)

__all__ = ["UDP_RECEIVE_BUFFER", "CanTransport", "frame_length", "open_bus", "widen_udp_receive_buffer"]

UDP_RECEIVE_BUFFER = 4 << 20  # bytes: a second of a saturated bus as udp_multicast datagrams
_FD_LENGTHS = (8, 12, 16, 20, 24, 32, 48, 64)


def frame_length(packet_size: int, *, fd: bool, max_dlc: int, max_dlc_required: bool) -> int:
    """The data length of the frame that carries a packet of ``packet_size`` bytes.

    :raises ValueError: the packet does not fit one frame.
    """
    limit = max_dlc if fd else 8
    if packet_size > limit:
        raise ValueError(f"an XCP packet of {packet_size} bytes does not fit a{' CAN FD' if fd else ''} frame "
                         f"of {limit} bytes")
    if max_dlc_required:
        return limit
    if packet_size <= 8:
        return packet_size
    return next(length for length in _FD_LENGTHS if length >= packet_size)


class CanTransport(Transport):
    """XCP on CAN as ``settings`` say, on ``bus`` (the caller's, left open and unfiltered) or on a bus
    opened from ``settings.bus``.

    :raises InputError: an unknown interface. :raises WorkbenchError: the bus cannot be opened.
    """

    kind = "CAN"

    def __init__(self, settings: LinkSettings, bus: can.BusABC | None = None):
        import can

        super().__init__()
        self._can = can
        self.settings = settings
        self._owned = bus is None
        if bus is None and settings.bus is None:
            raise InputError("XCP on CAN needs a bus: its python-can settings or an open bus")
        self.bus = open_bus(settings.bus.kwargs()) if bus is None else bus
        self._master = settings.can_id_master
        self._ids = tuple(dict.fromkeys((settings.can_id_slave, *settings.dto_can_ids)))  # what the slave sends on
        self._incoming = frozenset((can_id.id, can_id.extended) for can_id in self._ids)
        self._fd = settings.fd
        limit = settings.max_dlc if settings.fd else 8  # the frame length of each packet size, looked up per command
        self._lengths = [frame_length(size, fd=settings.fd, max_dlc=limit, max_dlc_required=settings.max_dlc_required)
                         for size in range(limit + 1)]
        data_bitrate = settings.bus.options.get("data_bitrate") if settings.bus is not None else None
        self._bitrate_switch = settings.fd and bool(data_bitrate)
        self._notifier: can.Notifier | None = None
        self._shared_notifier: can.Notifier | None = None
        self._listener: _XcpListener | None = None
        self._others: list = []  # listeners beside the link's (add_listener): they hear every frame
        if self._owned:
            widen_udp_receive_buffer(self.bus)
            self.bus.set_filters(self._filters())

    def describe(self) -> str:
        if self.settings.bus is None:  # a bus the caller opened: python-can says what it is
            settings = self.settings
            return (f"XCP on CAN{' FD' if self._fd else ''} ({self.bus.channel_info}, ids {settings.can_id_master}/"
                    f"{settings.can_id_slave})")
        return self.settings.describe()

    def _filters(self) -> list[dict]:
        return [{"can_id": can_id.id, "can_mask": can_id.mask, "extended": can_id.extended} for can_id in self._ids]

    # --- packets ------------------------------------------------------------------------------

    def send(self, packet: bytes) -> None:
        if len(packet) >= len(self._lengths):
            settings = self.settings
            try:  # too long for a frame: say so
                frame_length(len(packet), fd=self._fd, max_dlc=settings.max_dlc,
                             max_dlc_required=settings.max_dlc_required)
            except ValueError as exc:
                raise WorkbenchError(str(exc)) from None
        length = self._lengths[len(packet)]
        master = self._master
        message = self._can.Message(arbitration_id=master.id, is_extended_id=master.extended, is_fd=self._fd,
                                    bitrate_switch=self._bitrate_switch, data=packet.ljust(length, b"\0"), check=False)
        try:
            self.bus.send(message)
        except (self._can.CanError, OSError, ValueError) as exc:  # a full transmit queue, a bus that is off
            raise WorkbenchError(f"cannot send to the ECU ({self.describe()}): {exc}") from None
        if self._others:  # they hear the whole bus: the link's own frames too, as sent (a bus does not echo them)
            message.timestamp, message.is_rx = time.time(), False
            for listener in self._others:
                listener(message)

    def receive(self, timeout_s: float) -> list[bytes] | None:
        message = self._recv(timeout_s)
        if message is None:
            return None
        if (message.arbitration_id, message.is_extended_id) in self._incoming and _is_data(message):
            return [bytes(message.data)]
        return []

    def heard(self, seconds: float) -> list[tuple[CanId, bytes]]:
        """The packets that come on the slave's ids (responses, DTOs) within ``seconds``, read from the bus while
        no receiver runs: before this master's CONNECT they are another master's (or a DAQ nobody stopped)."""
        heard = []
        drained = time.monotonic() + 0.05
        while time.monotonic() < drained and self._recv(0) is not None:
            pass  # queued before now: this bus's earlier session (our own late DTOs before a reconnect), not news
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            message = self._recv(left)
            if message is None:
                break
            key = (message.arbitration_id, message.is_extended_id)
            if key in self._incoming and _is_data(message):
                heard.append((CanId(*key), bytes(message.data)))
        return heard

    def _recv(self, timeout_s: float) -> can.Message | None:
        try:
            return self.bus.recv(timeout_s)
        except (self._can.CanError, OSError, ValueError) as exc:
            raise LinkBroken(f"the CAN bus failed: {exc}") from None

    # --- the receiver: python-can's Notifier --------------------------------------------------

    def start_receiver(self, deliver: Deliver, broken: Broken) -> None:
        can = self._can
        self._listener = _XcpListener(self._incoming, deliver, broken, self)
        running = [notifier for notifier in can.Notifier.find_instances(self.bus) if not notifier.stopped]
        if running:  # someone reads this bus already: listen there (python-can allows one Notifier per bus)
            self._shared_notifier = running[0]
            for listener in (self._listener, *self._others):
                self._shared_notifier.add_listener(listener)
        else:
            self._notifier = can.Notifier(self.bus, [self._listener, *self._others], timeout=RECEIVER_POLL_S)

    def stop_receiver(self) -> None:
        notifier, self._notifier = self._notifier, None
        shared, self._shared_notifier = self._shared_notifier, None
        listener, self._listener = self._listener, None
        if listener is not None:
            listener.deliver = None
        if notifier is not None:
            notifier.stop(timeout=2 * RECEIVER_POLL_S + 1.0)
        for taken in (listener, *self._others) if shared is not None else ():
            if taken is not None and taken in shared.listeners:
                shared.remove_listener(taken)

    def add_listener(self, listener) -> None:
        if not self._others and self._owned:
            self.bus.set_filters(None)  # they hear every frame, not only the XCP ones
        self._others.append(listener)
        notifier = self._notifier or self._shared_notifier
        if notifier is not None:
            notifier.add_listener(listener)

    def remove_listener(self, listener) -> None:
        self._others.remove(listener)
        notifier = self._notifier or self._shared_notifier
        if notifier is not None and listener in notifier.listeners:
            notifier.remove_listener(listener)
        if not self._others and self._owned:
            self.bus.set_filters(self._filters())

    def _stop_from_receiver(self) -> None:
        """The bus failed under the Notifier: stop it from its own thread (it would read the dead bus again
        and again); stop() then joins nothing."""
        notifier = self._notifier
        if notifier is not None:
            notifier.stop(timeout=0)

    def close(self) -> None:
        self.stop_receiver()
        if self._owned:
            self.bus.shutdown()


class _XcpListener:
    """The one Notifier listener of the link: the XCP ids' frames to ``deliver``, a bus failure to ``broken``."""

    def __init__(self, incoming: frozenset, deliver: Deliver, broken: Broken, transport: CanTransport):
        self.incoming = incoming
        self.deliver: Deliver | None = deliver
        self.broken = broken
        self.transport = transport
        self.failed = False

    def __call__(self, message: can.Message) -> None:
        deliver = self.deliver
        if (deliver is not None and (message.arbitration_id, message.is_extended_id) in self.incoming
                and _is_data(message)):
            deliver(bytes(message.data), time.time_ns())

    def on_error(self, exc: Exception) -> None:
        """Called by the Notifier for an error of the bus: handled here, so no traceback reaches the terminal."""
        log.debug("CAN receive failed", exc_info=exc)
        if not self.failed and self.deliver is not None:
            self.failed = True
            self.broken(f"the CAN bus failed: {exc}")
            self.transport._stop_from_receiver()

    def stop(self) -> None:
        self.deliver = None


def _is_data(message: can.Message) -> bool:
    return not (message.is_error_frame or message.is_remote_frame) and bool(message.data)


def widen_udp_receive_buffer(bus: can.BusABC) -> None:
    """udp_multicast carries each CAN frame as a datagram: with the kernel's default buffer (about 200 kB,
    ~270 frames) a busy interpreter pausing for 30 ms at a saturated bus's 8,000 frames/s loses frames."""
    sock = getattr(getattr(bus, "_multicast", None), "_socket", None)  # python-can keeps it private
    if sock is not None:
        try:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, UDP_RECEIVE_BUFFER)
        except OSError:  # capped by the system (net.core.rmem_max): keep what it gives
            log.debug("could not widen the udp_multicast receive buffer", exc_info=True)
