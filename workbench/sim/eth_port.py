"""XCP on Ethernet for the simulated ECU: UDP/IP or TCP/IP, framed as :mod:`workbench.xcp_framing` says.

One master at a time, as ECUs do:

* UDP: the sender of a CONNECT becomes the master (a CONNECT from another address takes the
  session over); while a session runs, packets from anyone else are ignored. Responses and
  DTOs go to the master's address from the port the slave listens on.
* TCP: a newly accepted connection replaces the previous one; a connection that closes, or
  whose stream cannot be framed, ends the XCP session as a DISCONNECT would.

The slave's CTR counts every packet it sends (responses and DTOs) from 0 for each new master.
Responses go out at once; DTOs wait in a buffer of :data:`DTO_BUFFER_PACKETS` packets that a
thread empties, packing them into datagrams of at most :data:`MAX_DATAGRAM` bytes (one Ethernet
frame; a larger DTO travels alone). A sample that does not fit the buffer is dropped whole (a
DAQ overload). A datagram that is not a sequence of framed packets of 1..MAX_CTO bytes is
ignored whole: the slave never acts on part of it.
"""

from __future__ import annotations

import contextlib
import logging
import selectors
import socket
import threading
from collections import deque
from dataclasses import dataclass
from typing import Any

from workbench.errors import InputError, WorkbenchError
from workbench.logs import logger
from workbench.sim.ecu import SimulatedEcu
from workbench.xcp_framing import CTR_MODULO, FramingError, StreamDecoder, frame, split_datagram
from workbench.sim.xcp_port import XcpPort
from workbench.xcp_protocol import Cmd

__all__ = ["EthernetEndpoint", "EthernetXcpPort"]

log = logger(__name__)

PROTOCOLS = ("UDP", "TCP")
DEFAULT_PORT = 5555  # XCP on Ethernet's customary port
MAX_DATAGRAM = 1472  # UDP payload of one Ethernet frame: MTU 1500 minus the IPv4 and UDP headers
DTO_BUFFER_PACKETS = 256
SEND_TIMEOUT_S = 2.0  # a TCP master that reads nothing for this long loses its connection
_POLL_S = 0.05


@dataclass(frozen=True)
class EthernetEndpoint:
    """Where the simulated ECU serves XCP on Ethernet: ``protocol`` "UDP" or "TCP" (any case).

    ``port`` 0 takes any free port (:meth:`EthernetXcpPort.describe` tells which); None is the
    A2L's PORT when :func:`~workbench.sim.serve.serve_demo` serves it, else XCP's usual 5555.
    """

    host: str = "127.0.0.1"
    port: int | None = None
    protocol: str = "UDP"

    def __post_init__(self) -> None:
        object.__setattr__(self, "protocol", str(self.protocol).upper())
        if self.protocol not in PROTOCOLS:
            raise ValueError(f"protocol must be UDP or TCP, got {self.protocol!r}")
        if self.port is not None and not 0 <= self.port <= 0xFFFF:
            raise ValueError(f"port must be 0..65535, got {self.port}")


class EthernetXcpPort(XcpPort):
    """XCP on UDP/IP or TCP/IP at ``endpoint`` (see the module doc for the rules)."""

    def __init__(self, ecu: SimulatedEcu, lock, endpoint: EthernetEndpoint):
        super().__init__(ecu, lock)
        self.endpoint = endpoint
        self.transport = endpoint.protocol
        self.address: tuple[str, int] | None = None  # bound host and port, once started
        self.sent = 0  # packets
        self.dropped = 0  # DTO packets lost to an overload, or with no master to send to
        self.ignored = 0  # datagrams or packets not taken: malformed, from another master
        self._socket: socket.socket | None = None
        self._peer: Any = None  # UDP: the master's address; TCP: the master's connection
        self._ctr = 0
        self._send_lock = threading.Lock()  # CTR order = order on the wire
        self._dtos: deque[bytes] = deque()
        self._dtos_ready = threading.Condition()
        self._stop = threading.Event()
        self._threads: list[threading.Thread] = []
        self._malformed_seen = False

    # --- life cycle ------------------------------------------------------------------------------

    def start(self) -> None:
        """Bind (and for TCP listen) and start the threads.

        :raises InputError: the host name does not resolve.
        :raises WorkbenchError: the address cannot be bound (in use, not local, no permission).
        """
        endpoint = self.endpoint
        port = DEFAULT_PORT if endpoint.port is None else endpoint.port
        kind = socket.SOCK_DGRAM if endpoint.protocol == "UDP" else socket.SOCK_STREAM
        where = f"{endpoint.host}:{port}"
        try:
            family, _, _, _, address = socket.getaddrinfo(endpoint.host, port, 0, kind, 0, socket.AI_PASSIVE)[0]
        except socket.gaierror as exc:
            raise InputError(f"cannot serve XCP on {endpoint.protocol} at {where}: unknown host ({exc.strerror})") from None
        sock = socket.socket(family, kind)
        try:
            if kind == socket.SOCK_STREAM:
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # rebind while old connections linger
            sock.bind(address)
            if kind == socket.SOCK_STREAM:
                sock.listen(1)
        except OSError as exc:
            sock.close()
            raise WorkbenchError(f"cannot serve XCP on {endpoint.protocol} at {where}: {exc.strerror or exc}") from None
        self._socket = sock
        self.address = sock.getsockname()[:2]
        receive = self._receive_udp if kind == socket.SOCK_DGRAM else self._receive_tcp
        for target, name in ((receive, "sim-eth-rx"), (self._send_dto_buffer, "sim-eth-tx")):
            thread = threading.Thread(target=target, name=name, daemon=True)
            thread.start()
            self._threads.append(thread)

    def close(self) -> None:
        super().close()
        self._stop.set()
        with self._dtos_ready:
            self._dtos_ready.notify_all()
        for thread in self._threads:
            thread.join(timeout=2)
        if isinstance(self._peer, socket.socket):
            self._peer.close()
        if self._socket is not None:
            self._socket.close()

    def describe(self) -> dict[str, Any]:
        host, port = self.address or (self.endpoint.host, self.endpoint.port or DEFAULT_PORT)
        params = self.ecu.params
        return {"transport": self.transport, "host": host, "port": port, "max_cto": params.max_cto,
                "max_dto": params.max_dto}

    # --- receiving ---------------------------------------------------------------------------------

    def _receive_udp(self) -> None:
        sock = self._socket
        sock.settimeout(_POLL_S)
        while not self._stop.is_set():
            try:
                datagram, sender = sock.recvfrom(0xFFFF)
            except TimeoutError:
                continue
            except OSError as exc:
                if not self._stop.is_set():
                    log.error("XCP on UDP: reception ended: %s", exc)
                return
            try:
                packets = split_datagram(datagram, self.ecu.params.max_cto)
            except FramingError as exc:
                self._malformed(f"datagram from {sender[0]}:{sender[1]} ignored: {exc}")
                continue
            for _, packet in packets:
                if packet[0] == Cmd.CONNECT and sender != self._peer:
                    self._new_master(sender)
                if sender != self._peer:
                    self.ignored += 1  # not the master of the running session
                    continue
                self._handle(packet)

    def _receive_tcp(self) -> None:
        listener = self._socket
        selector = selectors.DefaultSelector()
        selector.register(listener, selectors.EVENT_READ)
        connection = decoder = None
        try:
            while not self._stop.is_set():
                ready = {key.fileobj for key, _ in selector.select(_POLL_S)}
                if listener in ready:
                    try:
                        accepted, where = listener.accept()
                    except OSError as exc:  # out of descriptors, the master gave up: keep listening
                        log.warning("XCP on TCP: accept failed: %s", exc)
                        continue
                    if connection is not None:
                        selector.unregister(connection)
                        self._end_connection("a new master connected")
                    connection, decoder = accepted, StreamDecoder(self.ecu.params.max_cto)
                    connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                    connection.settimeout(SEND_TIMEOUT_S)
                    selector.register(connection, selectors.EVENT_READ)
                    self._new_master(connection)
                    log.info("XCP on TCP: master %s:%d connected", *where[:2])
                elif connection is not None and connection in ready:
                    ended = self._read(connection, decoder)
                    if ended:
                        selector.unregister(connection)
                        self._end_connection(ended)
                        connection = decoder = None
        except OSError as exc:
            if not self._stop.is_set():
                log.error("XCP on TCP: reception ended: %s", exc)
        finally:
            selector.close()

    def _read(self, connection: socket.socket, decoder: StreamDecoder) -> str | None:
        """Take what the connection has and handle its packets; why the connection ends, if it does."""
        try:
            data = connection.recv(0xFFFF)
            packets = decoder.feed(data)
        except FramingError as exc:
            self._malformed(f"the stream cannot be framed ({exc})")
            return "stream error"
        except OSError as exc:
            return f"the connection failed ({exc})"
        for _, packet in packets:
            self._handle(packet)
        return None if data else "the master closed the connection"

    def _handle(self, packet: bytes) -> None:
        try:
            self.on_command(packet)
        except Exception:  # one bad packet must not end the ECU's reception
            log.exception("XCP on %s: packet %s: handler failed", self.transport, packet.hex(" "))

    def _malformed(self, what: str) -> None:
        self.ignored += 1
        log.log(logging.DEBUG if self._malformed_seen else logging.WARNING, "XCP on %s: %s", self.transport, what)
        self._malformed_seen = True

    def _new_master(self, peer: Any) -> None:
        """From now on ``peer`` (UDP: an address, TCP: a connection) is the master; CTR starts at 0."""
        with self._send_lock, self._dtos_ready:
            previous, self._peer = self._peer, peer
            self._ctr = 0
            self._dtos.clear()
        if previous is not None:  # UDP (TCP ended the old connection first): the old master's session ends
            with self.lock:
                if self.ecu.slave.connected:
                    log.warning("XCP on UDP: %s:%d takes the session over from %s:%d", *peer[:2], *previous[:2])
                    self.ecu.slave.disconnect()

    def _end_connection(self, reason: str) -> None:
        """Close the TCP connection; the XCP session ends with it."""
        with self._send_lock, self._dtos_ready:
            connection, self._peer = self._peer, None
            self._dtos.clear()
        if connection is not None:
            connection.close()
        with self.lock:
            self.ecu.slave.disconnect()
        log.info("XCP on TCP: %s; XCP session ended", reason)

    # --- sending -------------------------------------------------------------------------------

    def _transmit_response(self, packet: bytes) -> None:
        with self._send_lock:
            self._send([packet])

    def _transmit_dtos(self, packets: list[bytes]) -> bool:
        with self._dtos_ready:
            if self._peer is None or len(self._dtos) + len(packets) > DTO_BUFFER_PACKETS:
                self.dropped += len(packets)
                return False
            self._dtos.extend(packets)
            self._dtos_ready.notify()
        return True

    def _send_dto_buffer(self) -> None:
        while True:
            with self._dtos_ready:
                while not self._dtos and not self._stop.is_set():
                    self._dtos_ready.wait(_POLL_S)
                if self._stop.is_set():
                    return
                packets = list(self._dtos)
                self._dtos.clear()
            with self._send_lock:
                self._send(packets)

    def _send(self, packets: list[bytes]) -> None:
        """Frame ``packets`` with the next CTRs and send them to the master (the send lock held)."""
        peer = self._peer
        if peer is None:
            self.dropped += len(packets)
            return
        datagrams = [bytearray()]
        for packet in packets:
            framed = frame(packet, self._ctr)
            self._ctr = (self._ctr + 1) % CTR_MODULO
            if self.transport == "UDP" and datagrams[-1] and len(datagrams[-1]) + len(framed) > MAX_DATAGRAM:
                datagrams.append(bytearray())
            datagrams[-1] += framed
        try:
            for datagram in datagrams:
                if isinstance(peer, socket.socket):
                    peer.sendall(datagram)
                else:
                    self._socket.sendto(datagram, peer)
            self.sent += len(packets)
        except OSError as exc:
            self.dropped += len(packets)
            log.warning("XCP on %s: %d packet(s) not sent: %s", self.transport, len(packets), exc)
            if isinstance(peer, socket.socket):
                with contextlib.suppress(OSError):  # a half-sent stream cannot be framed again: the receiver ends it
                    peer.shutdown(socket.SHUT_RDWR)
