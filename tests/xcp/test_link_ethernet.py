"""The link's XCP on UDP and TCP against scripted slaves on loopback: LEN/CTR framing, several packets in one
datagram or a packet cut across segments, the slave's counter checked, large packets, and a lost ECU said at
once (a closed connection, nothing listening) or after DTOs stopped coming."""

from __future__ import annotations

import socket
import struct
import threading
import time

import pytest

from workbench.errors import ConnectionLostError, WorkbenchError
from workbench.xcp.link import Link, LinkSettings

HEADER = struct.Struct("<HH")


def framed(ctr: int, *packets: bytes) -> bytes:
    return b"".join(HEADER.pack(len(packet), ctr + index) + packet for index, packet in enumerate(packets))


class UdpSlave:
    """Answers each datagram with ``answer(packet) -> [datagram, ...]`` (already framed)."""

    def __init__(self, answer):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.settimeout(0.02)
        self.port = self.sock.getsockname()[1]
        self.answer = answer
        self.commands: list[tuple[int, bytes]] = []  # (CTR, packet)
        self.peer = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                data, self.peer = self.sock.recvfrom(0xFFFF)
            except TimeoutError:
                continue
            length, ctr = HEADER.unpack_from(data)
            packet = data[4:4 + length]
            self.commands.append((ctr, packet))
            for datagram in self.answer(packet):
                self.sock.sendto(datagram, self.peer)

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self.sock.close()


class TcpSlave:
    """Accepts one connection; ``answer(packet) -> [bytes to write, ...]`` (each written on its own, with a pause
    between)."""

    def __init__(self, answer):
        self.listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.listener.bind(("127.0.0.1", 0))
        self.listener.listen(1)
        self.port = self.listener.getsockname()[1]
        self.answer = answer
        self.connection: socket.socket | None = None
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            self.connection, _ = self.listener.accept()
            self.connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            while data := self.connection.recv(0xFFFF):  # ends when the test shuts the connection down
                length, _ = HEADER.unpack_from(data)
                for piece in self.answer(data[4:4 + length]):
                    self.connection.sendall(piece)
                    time.sleep(0.02)
        except OSError:
            return

    def drop(self) -> None:
        """Close the connection, as an ECU that resets does."""
        self.connection.shutdown(socket.SHUT_RDWR)
        self.connection.close()

    def close(self) -> None:
        if self.connection is not None and self.connection.fileno() != -1:
            self.drop()
        self.listener.close()
        self._thread.join(timeout=5)


def udp(port: int) -> LinkSettings:
    return LinkSettings("UDP", host="127.0.0.1", port=port)


def test_udp_several_packets_in_one_datagram_and_the_counters(caplog):
    counter = iter(range(100))

    def answer(packet):
        ctr = next(counter)
        if packet[0] == 0xF4:  # a DTO and an event come in the datagram before the response; then CTR jumps by 3
            return [framed(ctr, bytes([0x00, 1]), bytes([0xFD, 0x00]), bytes([0xFF, 7])),
                    framed(ctr + 6, bytes([0x01]))]
        return [framed(ctr, bytes([0xFF]) + packet[1:])]

    slave = UdpSlave(answer)
    try:
        with Link(udp(slave.port)) as link:
            assert link.exchange(bytes([0xFF, 0]), 1.0) == bytes([0xFF, 0])
            with caplog.at_level("INFO", "workbench.xcp.transport.ethernet"):
                assert link.exchange(bytes([0xF4, 4]), 1.0) == bytes([0xFF, 7])
                time.sleep(0.05)
                assert link.exchange(bytes([0xFC]), 1.0) == bytes([0xFF])
            assert link.events[-1] == bytes([0xFD, 0x00])
            assert link.counter_gaps >= 1  # 1 + 3 -> 7: a gap, counted and logged, nothing failed
            assert "CTR jumped" in caplog.text
        assert [ctr for ctr, _ in slave.commands] == [0, 1, 2]  # the master counts its own packets
    finally:
        slave.close()


def test_udp_packets_up_to_the_largest_dto():
    big = bytes([0xFF]) + bytes(range(256)) * 4  # 1025 bytes: MAX_DTO 1024 + PID
    slave = UdpSlave(lambda packet: [framed(0, big)])
    try:
        with Link(udp(slave.port)) as link:
            assert link.exchange(bytes([0xF5, 0xFF]) + bytes(253), 1.0) == big  # and a 255-byte CTO goes out
        assert len(slave.commands[0][1]) == 255
    finally:
        slave.close()


def test_udp_nothing_listening_any_more_is_a_lost_link_at_once():
    slave = UdpSlave(lambda packet: [framed(0, bytes([0xFF]))])
    port = slave.port
    link = Link(udp(port))
    try:
        assert link.exchange(bytes([0xFF, 0]), 1.0) == bytes([0xFF])
        slave.close()  # the ECU's process ends: the host answers with ICMP port unreachable
        started = time.monotonic()
        with pytest.raises(ConnectionLostError, match=rf"XCP on UDP \(127.0.0.1:{port}\): nothing listens"):
            for _ in range(3):  # the ICMP error comes with the next datagram's round trip
                link.exchange(bytes([0xFC]), 0.5)
        assert time.monotonic() - started < 1.4
        with pytest.raises(ConnectionLostError):  # and stays lost, without waiting
            link.exchange(bytes([0xFC]), 5.0)
    finally:
        link.close()


def test_tcp_a_packet_cut_across_segments_and_two_in_one():
    def answer(packet):
        whole = framed(0, bytes([0xFF, 1, 2, 3, 4, 5])) + framed(1, bytes([0x00, 9]))
        return [whole[:3], whole[3:8], whole[8:]]

    slave = TcpSlave(answer)
    try:
        with Link(LinkSettings("TCP", host="127.0.0.1", port=slave.port)) as link:
            assert link.exchange(bytes([0xF4, 4]), 1.0) == bytes([0xFF, 1, 2, 3, 4, 5])
    finally:
        slave.close()


def test_tcp_a_closed_connection_is_a_lost_link_at_once_and_connect_tries_again():
    slave = TcpSlave(lambda packet: [framed(0, bytes([0xFF]))])
    link = Link(LinkSettings("TCP", host="127.0.0.1", port=slave.port))
    try:
        assert link.exchange(bytes([0xFF, 0]), 1.0) == bytes([0xFF])
        slave.drop()
        started = time.monotonic()
        with pytest.raises(ConnectionLostError, match="the ECU closed the TCP connection"):
            link.exchange(bytes([0xFC]), 5.0)
        assert time.monotonic() - started < 2.5  # at once, not after the 5 s timeout
        assert link.lost.when <= time.time()
        slave.close()
        # CONNECT: a new connection
        with pytest.raises(WorkbenchError, match=r"cannot reach the ECU: XCP on TCP \(127.0.0.1:\d+\): nothing listens at"):
            link.exchange(bytes([0xFF, 0]), 1.0)
    finally:
        link.close()


def test_tcp_nothing_at_the_address_is_one_line():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    refused = rf"cannot reach the ECU: XCP on TCP \(127.0.0.1:{port}\): nothing listens at 127.0.0.1:{port} \(connection refused\)"
    with pytest.raises(WorkbenchError, match=refused):  # as over UDP, where CONNECT finds it out
        Link(LinkSettings("TCP", host="127.0.0.1", port=port))


def test_no_dto_within_the_watched_time_loses_the_link_and_connect_revives_it():
    dtos = []
    slave = UdpSlave(lambda packet: [framed(0, bytes([0xFF]) + packet[1:])] + (
        [framed(1, bytes([0x00, n])) for n in range(3)] if packet[0] == 0xFF else []))
    try:
        with Link(udp(slave.port)) as link:
            link.dto_handler = lambda packet, host_ns: dtos.append(packet)
            link.watch_dtos(0.2)
            assert link.exchange(bytes([0xFF, 0]), 1.0) == bytes([0xFF, 0])
            link.check()  # DTOs came
            time.sleep(0.3)
            with pytest.raises(ConnectionLostError, match=r"nothing from the ECU for \d+ ms while DAQ runs \(a DTO was "
                                                          r"due within 200 ms\)"):
                link.check()
            with pytest.raises(ConnectionLostError):
                link.exchange(bytes([0xFC]), 1.0)
            assert link.exchange(bytes([0xFF, 0]), 1.0) == bytes([0xFF, 0])  # CONNECT starts over
            assert link.lost is None and link.dto_handler is None
        assert len(dtos) == 3
    finally:
        slave.close()
