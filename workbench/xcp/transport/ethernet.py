"""XCP on Ethernet for the master (ASAM XCP Part 3): UDP/IP and TCP/IP, framed by :mod:`workbench.xcp_framing`.

Every packet travels behind LEN and CTR. The master counts its own packets in CTR; the slave's are
checked: a gap (datagrams lost on the way, a slave that restarted) is counted in
:attr:`EthernetTransport.counter_gaps` and logged, never fatal. A datagram may carry several packets,
a TCP segment any part of the stream; packets up to 0xFFFF bytes are taken (MAX_CTO 255, MAX_DTO 1024
and beyond).

A closed TCP connection, a stream that cannot be framed, or a socket error (on UDP: the ICMP "port
unreachable" of a host where nothing listens any more) breaks the link at once.
"""

from __future__ import annotations

import logging
import select
import socket

from workbench.errors import WorkbenchError
from workbench.logs import logger
from workbench.xcp.transport.base import LinkBroken, Transport
from workbench.xcp_framing import (
    CTR_MODULO,
    HEADER,
    HEADER_SIZE,
    MAX_PACKET,
    FramingError,
    StreamDecoder,
    frame,
    split_datagram,
)

log = logger(__name__)

__all__ = ["CONNECT_TIMEOUT_S", "RECEIVE_BUFFER", "SEND_TIMEOUT_S", "EthernetTransport"]

CONNECT_TIMEOUT_S = 3.0  # a TCP connection that is not accepted within this is refused
RECEIVE_BUFFER = 4 << 20  # bytes of socket buffer: a DAQ stream at full rate rides out the interpreter's pauses
SEND_TIMEOUT_S = 2.0  # a TCP send that finds no room for this long: the ECU reads nothing any more


class EthernetTransport(Transport):
    """XCP on ``protocol`` ("UDP" or "TCP") to ``host``:``port``; connects (TCP) or binds a peer (UDP) at once.

    :raises WorkbenchError: the host does not resolve, or (TCP) nothing accepts the connection.
    """

    def __init__(self, protocol: str, host: str, port: int):
        super().__init__()
        self.kind = protocol.upper()
        self.host, self.port = host, port
        self.counter_gaps = 0  # discontinuities in the slave's CTR
        self._tx_ctr = 0
        self._rx_ctr: int | None = None  # the CTR the slave's next packet should carry
        self._buffer = bytearray(MAX_PACKET + 64)
        self._view = memoryview(self._buffer)
        self._timeout = SEND_TIMEOUT_S  # the socket's, changed only when a wait asks for another (a system call)
        self._decoder = StreamDecoder(MAX_PACKET) if self.kind == "TCP" else None
        self._socket = self._connect()

    def describe(self) -> str:
        return f"XCP on {self.kind} ({self.host}:{self.port})"

    def _connect(self) -> socket.socket:
        kind = socket.SOCK_STREAM if self.kind == "TCP" else socket.SOCK_DGRAM
        where = self.describe()  # as a CONNECT over UDP that nothing answers says it (Session.connect)
        try:
            family, _, _, _, address = socket.getaddrinfo(self.host, self.port, 0, kind)[0]
        except (socket.gaierror, UnicodeError) as exc:
            reason = getattr(exc, "strerror", None) or exc
            raise WorkbenchError(f"cannot reach the ECU: {where}: unknown host ({reason})") from None
        sock = socket.socket(family, kind)
        try:
            if kind == socket.SOCK_STREAM:
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                sock.settimeout(CONNECT_TIMEOUT_S)
            _widen_receive_buffer(sock)
            sock.connect(address)  # UDP: the slave's datagrams only, and its ICMP errors reported to us
            sock.settimeout(SEND_TIMEOUT_S)
        except OSError as exc:
            sock.close()
            reason = "no answer" if isinstance(exc, TimeoutError) else self._why(exc)
            raise WorkbenchError(f"cannot reach the ECU: {where}: {reason}") from None
        return sock

    def reconnect(self) -> None:
        """A new connection (TCP) after the link broke; the slave's CTR starts over.

        :raises WorkbenchError: nothing accepts the connection.
        """
        if self.kind == "TCP":
            self._socket.close()
            self._socket = self._connect()
            self._decoder = StreamDecoder(MAX_PACKET)
            self._timeout = SEND_TIMEOUT_S
        self._rx_ctr = None

    # --- packets ------------------------------------------------------------------------------

    def send(self, packet: bytes) -> None:
        data = frame(packet, self._tx_ctr)
        self._tx_ctr = (self._tx_ctr + 1) % CTR_MODULO
        if self._timeout < SEND_TIMEOUT_S and self.kind == "TCP":  # a stream may wait for room, not too briefly
            self._set_timeout(SEND_TIMEOUT_S)
        try:
            self._socket.sendall(data)
        except OSError as exc:
            raise LinkBroken(self._why(exc)) from None

    def receive(self, timeout_s: float) -> list[bytes] | None:
        sock = self._socket
        try:
            if timeout_s <= 0:
                if not select.select((sock,), (), (), 0)[0]:
                    return None
            elif timeout_s != self._timeout:
                self._set_timeout(timeout_s)
            size = sock.recv_into(self._buffer)  # the socket's timeout: poll and read in one call
        except TimeoutError:
            return None
        except (OSError, ValueError) as exc:  # ValueError: select() on a socket closed under it
            raise LinkBroken(self._why(exc) if isinstance(exc, OSError) else "the socket was closed") from None
        if self._decoder is None and size > HEADER_SIZE:
            length, ctr = HEADER.unpack_from(self._buffer)
            if size == HEADER_SIZE + length:  # one packet, as a response mostly comes
                self._check_counter(ctr)
                return [bytes(self._view[HEADER_SIZE:size])]
        data = self._view[:size]
        if self._decoder is None:
            try:
                framed = split_datagram(data, MAX_PACKET)
            except FramingError as exc:
                log.info("%s: a datagram that is not XCP dropped: %s", self.describe(), exc)
                return []
        else:
            if not size:
                raise LinkBroken("the ECU closed the TCP connection")
            try:
                framed = self._decoder.feed(data)
            except FramingError as exc:
                raise LinkBroken(f"the ECU's TCP stream cannot be framed ({exc})") from None
        return self._check_counters(framed)

    def _set_timeout(self, seconds: float) -> None:
        self._socket.settimeout(seconds)
        self._timeout = seconds

    def _check_counters(self, framed: list[tuple[int, bytes]]) -> list[bytes]:
        for ctr, _ in framed:
            self._check_counter(ctr)
        return [packet for _, packet in framed]

    def _check_counter(self, ctr: int) -> None:
        expected = self._rx_ctr
        if expected is not None and ctr != expected:
            self.counter_gaps += 1
            log.log(logging.INFO if self.counter_gaps == 1 else logging.DEBUG,
                    "%s: the slave's CTR jumped from %d to %d (%d packet(s) missing, or the slave restarted)",
                    self.describe(), expected, ctr, (ctr - expected) % CTR_MODULO)
        self._rx_ctr = (ctr + 1) % CTR_MODULO

    def _why(self, exc: OSError) -> str:
        if isinstance(exc, ConnectionRefusedError):
            return f"nothing listens at {self.host}:{self.port} (connection refused)"
        if isinstance(exc, (ConnectionResetError, BrokenPipeError)):
            return "the ECU closed the TCP connection" if self.kind == "TCP" else f"the socket failed: {exc.strerror}"
        return f"the socket failed: {exc.strerror or exc}"

    def close(self) -> None:
        self.stop_receiver()
        self._socket.close()


def _widen_receive_buffer(sock: socket.socket) -> None:
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)
    except OSError:  # capped by the system (net.core.rmem_max): keep what it gives
        log.debug("could not widen the socket's receive buffer", exc_info=True)
