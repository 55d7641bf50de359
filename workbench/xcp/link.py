"""One XCP link to an ECU: XCP on CAN (any python-can bus) or XCP on Ethernet (UDP, TCP), at wire speed.

The master (:mod:`workbench.xcp.master`) sends packets and reads responses through five members:
:meth:`Link.exchange`, :meth:`Link.send`, :meth:`Link.receive`, :meth:`Link.close` and
:attr:`Link.dto_handler`. Which thread reads the wire depends on what runs:

* no DAQ: the caller's own thread sends and then reads the transport directly (no hand-over between
  threads, so a command costs what the wire costs);
* DAQ (a ``dto_handler`` set): one receiver (a thread on the socket; python-can's Notifier on CAN) hands
  every DTO to the handler with its host receive time and every response to the waiting caller.

A late response to a command that timed out (or a doubled one) would be taken for the answer to the next
command; every exchange therefore drops what came before it sends, except for the last frame of a master
block, whose early error response must not be lost. Event (EV) and service (SERV) packets are logged,
never taken for responses; an EV_CMD_PENDING (a slave that needs longer than the command's timeout, as a
long erase) starts the wait for the response over, EV_DAQ_OVERLOADs are counted, and an EV_SESSION_TERMINATED
(the slave disconnected this master on its own) makes the link lost at once.

A lost ECU is said at once as :class:`~workbench.errors.ConnectionLostError`: a closed TCP connection, a
socket or bus error, and while DAQ runs with :meth:`Link.watch_dtos` nothing from the ECU for the time
given. The link stays lost (every call raises it, without waiting for timeouts) until a CONNECT goes out
again: it tries once more (TCP: on a new connection). (A command unanswered with its SYNCH is the master's
to say: :class:`~workbench.errors.EcuSilentError`; it may try again, as a flash's repairs do.)
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, NoReturn

from workbench.errors import ConnectionLostError, WorkbenchError
from workbench.logs import logger
from workbench.xcp.transport import LinkBroken, open_transport
from workbench.bus_defaults import BusSpec
from workbench.xcp_framing import MAX_PACKET
from workbench.xcp_protocol import (EV_CMD_PENDING, EV_DAQ_OVERLOAD, EV_SESSION_TERMINATED, PID_ERR, PID_EV, PID_SERV,
                                    CanId, Cmd)

if TYPE_CHECKING:
    import can

log = logger(__name__)

__all__ = ["DtoHandler", "Link", "LinkSettings"]

DtoHandler = Callable[[bytes, int], None]  # (packet, host receive time in ns since the epoch)
_CONNECT = int(Cmd.CONNECT)
_GRACE_S = 0.25  # at most this long a silence is confirmed before the ECU counts as lost


@dataclass(frozen=True)
class LinkSettings:
    """How to reach the ECU: ``transport`` "CAN", "UDP" or "TCP".

    CAN: the ``bus`` (opened from it unless the link is handed an open one), the ids of commands
    (``can_id_master``), of responses and DTOs (``can_id_slave``) and of DTOs moved to ids of their own
    (``daq_can_ids``, DAQ_LIST_CAN_ID FIXED) and of DAQ lists the master moves to ids of its choice
    (``assigned_daq_can_ids``: (list, id) pairs, DAQ_LIST_CAN_ID VARIABLE: SET_DAQ_ID before they start);
    ``fd``: CAN FD frames of up to ``max_dlc`` bytes. Ethernet: ``host`` and ``port``.
    """

    transport: str = "CAN"
    bus: BusSpec | None = None
    can_id_master: CanId = CanId(0x7F0)
    can_id_slave: CanId = CanId(0x7F1)
    max_dlc_required: bool = False
    daq_can_ids: tuple[CanId, ...] = ()
    host: str | None = None
    port: int | None = None
    fd: bool = False
    max_dlc: int = 8
    assigned_daq_can_ids: tuple[tuple[int, CanId], ...] = ()

    @property
    def dto_can_ids(self) -> tuple[CanId, ...]:
        """XCP on CAN: every id DTOs come on besides CAN_ID_SLAVE (fixed and assigned), each once."""
        return tuple(dict.fromkeys((*self.daq_can_ids, *(can_id for _, can_id in self.assigned_daq_can_ids))))

    def describe(self) -> str:
        if self.transport == "CAN":
            where = self.bus.describe() if self.bus is not None else "bus"
            return f"XCP on CAN{' FD' if self.fd else ''} ({where}, ids {self.can_id_master}/{self.can_id_slave})"
        return f"XCP on {self.transport} ({self.host}:{self.port})"


class Link:
    """An open XCP link. ``bus`` (CAN only) is a python-can bus the caller owns and keeps open.

    :raises InputError: bad settings (an unknown interface or transport, no host or port).
    :raises WorkbenchError: the bus cannot be opened or the ECU's address cannot be reached.
    """

    def __init__(self, settings: LinkSettings, bus: can.BusABC | None = None):
        self.settings = settings
        self.closed = False
        self.lost: ConnectionLostError | None = None
        self.events: deque[bytes] = deque(maxlen=64)  # the newest EV and SERV packets
        self._pending = 0  # EV_CMD_PENDINGs received: each restarts the wait for a response
        self.overload_events = 0  # EV_DAQ_OVERLOADs received (a slave with OVERLOAD_INDICATION_EVENT lost DTOs)
        self._lock = threading.RLock()  # one caller on the wire at a time
        self._arrived = threading.Condition()  # guards the responses and ``lost`` between receiver and caller
        self._responses: deque[bytes] = deque()
        self._handler: DtoHandler | None = None
        self._listeners: list = []  # other listeners on the bus (add_listener)
        self._receiving = False
        self._dto_silence_s: float | None = None
        self._last_seen = 0.0  # time.monotonic() of the ECU's last packet (or of the DTO watch's start)
        self._transport = open_transport(settings, bus)

    @property
    def is_can(self) -> bool:
        return self.settings.transport == "CAN"

    @property
    def max_packet(self) -> int:
        """The longest packet the transport carries: a CAN frame's 8 bytes (CAN FD: MAX_DLC), on Ethernet LEN's 0xFFFF."""
        if self.is_can:
            return self.settings.max_dlc if self.settings.fd else 8
        return MAX_PACKET

    @property
    def counter_gaps(self) -> int:
        """XCP on Ethernet: jumps in the slave's packet counter seen so far (packets lost on the way)."""
        return getattr(self._transport, "counter_gaps", 0)

    def describe(self) -> str:
        return self._transport.describe()

    # --- DTOs ---------------------------------------------------------------------------------

    @property
    def dto_handler(self) -> DtoHandler | None:
        return self._handler

    @dto_handler.setter
    def dto_handler(self, handler: DtoHandler | None) -> None:
        """Set: DTOs go to ``handler`` from a receiver that starts now; None: the receiver stops (the caller's
        thread reads the wire again) and DTOs are dropped."""
        with self._lock:
            self._handler = handler
            if handler is None:
                self._dto_silence_s = None
            self._update_receiver()

    def _update_receiver(self) -> None:
        """A receiver runs while DTOs are awaited or other listeners share the bus; else the caller reads."""
        wanted = not self.closed and (self._handler is not None or bool(self._listeners))
        if wanted and not self._receiving:
            self._receiving = True
            self._transport.start_receiver(self._dispatch, self._broken)
        elif not wanted and self._receiving:
            self._transport.stop_receiver()
            self._receiving = False

    # --- other listeners on the bus (XCP on CAN) ----------------------------------------------

    @property
    def can_bus(self) -> can.BusABC:
        """XCP on CAN: the python-can bus the link uses (its own or the caller's)."""
        if not self.is_can:
            raise WorkbenchError(f"{self.describe()} runs on no CAN bus")
        return self._transport.bus

    def add_listener(self, listener) -> None:
        """XCP on CAN: also hand every frame of the bus (the XCP ones too) to ``listener`` (a python-can
        Listener or a callable) from the link's receiver, which runs while any listens."""
        with self._lock:
            if self.closed:
                raise WorkbenchError("the XCP link is closed")
            self._transport.add_listener(listener)
            self._listeners.append(listener)
            self._update_receiver()

    def remove_listener(self, listener) -> None:
        with self._lock:
            self._listeners.remove(listener)
            self._transport.remove_listener(listener)
            self._update_receiver()

    def watch_dtos(self, silence_s: float | None) -> None:
        """While a ``dto_handler`` is set, take ``silence_s`` seconds (from now) without a packet from the ECU
        (a DTO, or a response) for a lost ECU; None: do not watch. :meth:`check` and every command say so."""
        with self._arrived:
            self._dto_silence_s = silence_s
            self._last_seen = time.monotonic()

    @property
    def quiet_s(self) -> float:
        """Seconds since the ECU's last packet (or since :meth:`watch_dtos` was called, if later)."""
        return time.monotonic() - self._last_seen

    def check(self) -> None:
        """:raises ConnectionLostError: the link is lost (also: DTOs watched and none within the time)."""
        silence = self._dto_silence_s
        if silence is not None and self._handler is not None and self.lost is None:
            quiet = time.monotonic() - self._last_seen
            if quiet > silence and not self._heard_within(min(silence, _GRACE_S)):
                quiet = time.monotonic() - self._last_seen
                reason = (f"nothing from the ECU for {_duration(quiet)} while DAQ runs (a DTO was due within "
                          f"{_duration(silence)})")
                if self._responses:  # answers to commands this master did not send (none awaits them)
                    reason += (f"; {len(self._responses)} response(s) came that this master did not ask for: another "
                               "master on these ids (a second workbench, CANape) may have disconnected the ECU or "
                               "stopped its DAQ (XCP takes one master at a time)")
                self._lose(ConnectionLostError(self.describe(), reason, time.time() - quiet + silence))
        if self.lost is not None:
            raise ConnectionLostError(self.lost.what, self.lost.reason, self.lost.when)

    def give_up(self, reason: str) -> None:
        """The master found the ECU gone (``reason``, for people): the link is lost from now on, as if the transport
        had said so (every call raises at once until a CONNECT)."""
        self._lose(ConnectionLostError(self.describe(), reason))

    def _heard_within(self, seconds: float) -> bool:
        """Whether a packet comes within ``seconds``: on a loaded host the receiving threads may merely not
        have run for a while, which is no lost ECU."""
        seen, deadline = self._last_seen, time.monotonic() + seconds
        while time.monotonic() < deadline:
            time.sleep(0.01)
            if self._last_seen != seen:
                return True
        return False

    def heard(self, seconds: float) -> list[tuple[CanId, bytes]]:
        """XCP on CAN: the packets that come on the slave's ids within ``seconds`` (with their id), while this
        master asks nothing; [] on Ethernet (a slave answers each master at its own address) and while a
        receiver runs. :raises ConnectionLostError: the bus failed."""
        with self._lock:
            if not self.is_can or self._receiving or self.closed or self.lost is not None:
                return []
            try:
                return self._transport.heard(seconds)
            except LinkBroken as exc:
                self._fail(exc.reason)

    # --- packets ------------------------------------------------------------------------------

    def exchange(self, packet: bytes, timeout_s: float, *, drop_queued: bool = True) -> bytes | None:
        """Send a command packet (PID first) and return the next response or error packet, None on timeout.

        ``drop_queued``: forget responses that came late before sending (False for the last frame of a
        master block, whose early error response must not be lost).

        :raises ConnectionLostError: the link is lost. :raises WorkbenchError: the link is closed, or the
            packet could not be sent.
        """
        with self._lock:
            if self.closed or self.lost is not None or self._dto_silence_s is not None:
                if packet[0] == _CONNECT and self.lost is not None:
                    self._revive()
                self._usable()
            if drop_queued:
                self._drop_responses()
                if self.lost is not None and packet[0] != _CONNECT:  # an event read just now ended the session
                    self._usable()
            self._send(packet)
            return self._receive(timeout_s)

    def send(self, packet: bytes) -> None:
        """Send a packet that gets no response (the leading frames of a master block)."""
        with self._lock:
            self._usable()
            self._send(packet)

    def receive(self, timeout_s: float) -> bytes | None:
        """The next response packet (slave block mode, a response that came late), None on timeout."""
        with self._lock:
            self._usable()
            return self._receive(timeout_s)

    def _usable(self) -> None:
        if self.closed:
            raise WorkbenchError("the XCP link is closed")
        self.check()

    def _send(self, packet: bytes) -> None:
        try:
            self._transport.send(packet)
        except LinkBroken as exc:
            self._fail(exc.reason)

    def _receive(self, timeout_s: float) -> bytes | None:
        responses = self._responses
        pending = self._pending  # EV_CMD_PENDINGs so far: one more restarts the wait
        if self._receiving:
            with self._arrived:
                while not responses and self.lost is None:
                    if not self._arrived.wait_for(lambda: responses or self.lost is not None
                                                  or self._pending != pending, timeout_s):
                        break
                    pending = self._pending
                if responses:
                    return responses.popleft()
            self.check()
            return None
        if responses:  # the rest of a datagram that carried several
            return responses.popleft()
        deadline = time.monotonic() + timeout_s
        while True:
            packets = self._read_wire(max(0.0, deadline - time.monotonic()))
            if packets is None:
                return None
            if responses:
                return responses.popleft()
            if self.lost is not None:  # an event said so (EV_SESSION_TERMINATED): no answer will come
                self.check()
            if self._pending != pending:
                pending, deadline = self._pending, time.monotonic() + timeout_s
            if deadline <= time.monotonic():  # something else came (another node's frame, a DTO)
                return None

    def _read_wire(self, timeout_s: float) -> list[bytes] | None:
        """The caller's thread reads the transport (no receiver runs): responses are queued, the rest
        dispatched; the packets read, None when nothing came within ``timeout_s``."""
        try:
            packets = self._transport.receive(timeout_s)
        except LinkBroken as exc:
            self._fail(exc.reason)
        for packet in packets or ():
            if packet[0] >= PID_ERR:
                self._responses.append(packet)
            else:
                self._dispatch(packet, 0)  # an event; a DTO after DAQ stopped is dropped
        return packets

    def _drop_responses(self) -> None:
        if not self._receiving:  # what the wire holds: read it now, to drop it with the rest
            while self._read_wire(0) is not None:
                pass
        with self._arrived:
            if self._responses:
                log.debug("dropping %d late response(s)", len(self._responses))
                self._responses.clear()

    def _dispatch(self, packet: bytes, host_ns: int) -> None:
        """Where a packet from the slave goes: a response to the caller, a DTO to the handler."""
        pid = packet[0]
        self._last_seen = time.monotonic()
        if pid >= PID_ERR:
            with self._arrived:
                self._responses.append(packet)
                self._arrived.notify()
        elif pid >= PID_SERV:
            code = packet[1] if pid == PID_EV and len(packet) > 1 else None
            if code == EV_CMD_PENDING:
                with self._arrived:
                    self._pending += 1
                    self._arrived.notify()
            elif code == EV_DAQ_OVERLOAD:
                self.overload_events += 1
            elif code == EV_SESSION_TERMINATED:  # the slave disconnected this master: nothing answers until CONNECT
                self._lose(ConnectionLostError(self.describe(), "the ECU ended the XCP session "
                                                                "(EV_SESSION_TERMINATED): it reset, or another master "
                                                                "took it over"))
            self.events.append(packet)
            log.info("%s: %s packet %s", self.describe(), "event" if pid == PID_EV else "service request",
                     packet.hex(" "))
        else:
            handler = self._handler
            if handler is not None:
                try:
                    handler(packet, host_ns)
                except Exception as exc:  # a receiver must not die of one DTO (nor print a traceback)
                    log.error("DTO %s not taken: %s: %s", packet[:8].hex(" "), type(exc).__name__, exc)
                    log.debug("the DTO handler failed", exc_info=True)

    # --- a lost link --------------------------------------------------------------------------

    def _broken(self, reason: str) -> None:
        """The transport cannot go on (from the receiver's thread or the caller's)."""
        self._lose(ConnectionLostError(self.describe(), reason))

    def _fail(self, reason: str) -> NoReturn:
        """The transport broke under the caller: the link is lost (or was closed under it); raise that."""
        self._broken(reason)
        self._usable()
        raise ConnectionLostError(self.describe(), reason)

    def _lose(self, error: ConnectionLostError) -> None:
        with self._arrived:
            if self.lost is None and not self.closed:
                self.lost = error
                log.debug("link lost: %s", error)
            self._arrived.notify_all()

    def _revive(self) -> None:
        """A CONNECT after the link was lost: start over (TCP: on a new connection; a DAQ that ran is gone).

        :raises WorkbenchError: a new connection cannot be made.
        """
        if self._receiving:
            self._transport.stop_receiver()
            self._receiving = False
        self._handler = None
        self._dto_silence_s = None
        reconnect = getattr(self._transport, "reconnect", None)
        if reconnect is not None:
            reconnect()
        with self._arrived:
            self.lost = None
            self._responses.clear()

    # --- closing ------------------------------------------------------------------------------

    def close(self) -> None:
        """Stop the receiver and close what this link opened; safe to call twice."""
        if self.closed:
            return
        with self._arrived:
            self.closed = True
            self._handler = None
            self._arrived.notify_all()
        try:
            self._transport.close()
        except Exception:  # closing must not fail a session that is going away
            log.debug("closing the XCP transport failed", exc_info=True)

    def __enter__(self) -> Link:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def _duration(seconds: float) -> str:
    return f"{seconds * 1000:.0f} ms" if seconds < 10 else f"{seconds:.1f} s"
