"""A raw XCP-on-Ethernet master for the tests: frames CTOs with its own CTR, unframes what comes back.

It parses the LEN/CTR headers itself (not with ``workbench.xcp_framing``), so a framing
mistake on the slave's side cannot hide behind the same mistake here.
"""

from __future__ import annotations

import socket
import struct
import time

HEADER = struct.Struct("<HH")


class RawEthMaster:
    def __init__(self, address: tuple[str, int], protocol: str):
        self.protocol = protocol.upper()
        if self.protocol == "UDP":
            self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            self.sock.connect(address)
        else:
            self.sock = socket.create_connection(address, timeout=2)
        self.ctr = 0
        self._stream = b""
        self.datagrams: list[bytes] = []  # every datagram (UDP) or segment (TCP) received

    def send(self, *ctos: bytes) -> None:
        """All ``ctos`` in one datagram (UDP) or one write (TCP), each behind LEN and the next CTR."""
        data = b""
        for cto in ctos:
            data += HEADER.pack(len(cto), self.ctr) + cto
            self.ctr = (self.ctr + 1) & 0xFFFF
        self.send_raw(data)

    def send_raw(self, data: bytes) -> None:
        self.sock.send(data)

    def packets(self, count: int | None = None, quiet_s: float = 0.2, timeout_s: float = 2.0) -> list[tuple[int, bytes]]:
        """The ``(ctr, packet)`` pairs received: ``count`` of them (or fewer after ``timeout_s``), or without
        ``count`` every one until the link stays quiet for ``quiet_s``."""
        deadline = time.monotonic() + timeout_s
        out: list[tuple[int, bytes]] = []
        while count is None or len(out) < count:
            wait = quiet_s if count is None else deadline - time.monotonic()
            if wait <= 0:
                break
            self.sock.settimeout(wait)
            try:
                data = self.sock.recv(0xFFFF)
            except TimeoutError:
                break
            if not data:  # TCP: the slave closed the connection
                break
            self.datagrams.append(data)
            if self.protocol == "UDP":
                out += _unframe(data, whole=True)[0]
            else:
                packets, self._stream = _unframe(self._stream + data, whole=False)
                out += packets
        return out

    def request(self, *ctos: bytes, expect: int | None = None) -> list[tuple[int, bytes]]:
        """Send ``ctos`` in one go; the answers, waiting for ``expect`` of them (default: one each;
        0: collect until the link is quiet, to show the slave stayed silent)."""
        self.send(*ctos)
        expect = len(ctos) if expect is None else expect
        return self.packets(expect or None)

    def closed_by_slave(self, timeout_s: float = 2.0) -> bool:
        """TCP: whether the slave ended the connection (reading gives end of stream)."""
        self.sock.settimeout(timeout_s)
        try:
            while self.sock.recv(0xFFFF):
                pass
            return True
        except (TimeoutError, ConnectionResetError) as exc:
            return isinstance(exc, ConnectionResetError)

    def close(self) -> None:
        self.sock.close()

    def __enter__(self) -> RawEthMaster:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def _unframe(data: bytes, whole: bool) -> tuple[list[tuple[int, bytes]], bytes]:
    packets = []
    while len(data) >= HEADER.size:
        length, ctr = HEADER.unpack_from(data)
        if len(data) < HEADER.size + length:
            break
        packets.append((ctr, data[HEADER.size : HEADER.size + length]))
        data = data[HEADER.size + length :]
    assert not (whole and data), f"a datagram with {len(data)} unframed byte(s) at its end"
    return packets, data
