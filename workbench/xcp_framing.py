"""XCP on Ethernet framing (ASAM XCP Part 3, UDP/IP and TCP/IP): every XCP packet travels behind a
4-byte header, LEN (WORD, the packet's length) and CTR (WORD, the sender's packet counter), both
little-endian.

* UDP: a datagram holds one or more framed packets, back to back, nothing else;
* TCP: the stream is a sequence of framed packets, cut anywhere by the network.

Each side counts its own packets in CTR (the slave: responses, events and DTOs alike), from 0,
wrapping after 0xFFFF. A packet is never empty; the receiver names the largest packet it takes
(the slave: MAX_CTO), so a LEN beyond it is a framing error, not a memory problem.

Neutral ground (it imports nothing of the workbench): the simulated slave (:mod:`workbench.sim.eth_port`)
and the master's transport (:mod:`workbench.xcp.transport.ethernet`) frame alike.
"""

from __future__ import annotations

import struct

__all__ = ["CTR_MODULO", "HEADER", "HEADER_SIZE", "MAX_PACKET", "FramingError", "StreamDecoder", "frame", "split_datagram"]

HEADER = struct.Struct("<HH")  # LEN, CTR
HEADER_SIZE = HEADER.size
CTR_MODULO = 0x10000
MAX_PACKET = 0xFFFF  # the largest LEN: what a master takes before CONNECT tells it MAX_CTO and MAX_DTO


class FramingError(ValueError):
    """Bytes that are no sequence of framed XCP packets."""


def frame(packet: bytes, ctr: int) -> bytes:
    """``packet`` behind its LEN/CTR header (``ctr`` is taken modulo 0x10000)."""
    return HEADER.pack(len(packet), ctr % CTR_MODULO) + packet


def split_datagram(datagram: bytes, max_packet: int) -> list[tuple[int, bytes]]:
    """The ``(ctr, packet)`` pairs of a UDP datagram, all or nothing.

    :raises FramingError: a header or packet is cut short, a LEN is 0 or above ``max_packet``.
    """
    packets = []
    offset = 0
    while offset < len(datagram):
        if len(datagram) - offset < HEADER_SIZE:
            raise FramingError(f"{len(datagram) - offset} byte(s) after packet {len(packets)}: no room for a header")
        length, ctr = HEADER.unpack_from(datagram, offset)
        _check_length(length, max_packet)
        offset += HEADER_SIZE
        if len(datagram) - offset < length:
            raise FramingError(f"LEN {length} but {len(datagram) - offset} byte(s) follow the header")
        packets.append((ctr, bytes(datagram[offset : offset + length])))
        offset += length
    if not packets:
        raise FramingError("empty datagram")
    return packets


class StreamDecoder:
    """Framed packets out of a TCP byte stream, fed in pieces as they arrive."""

    def __init__(self, max_packet: int):
        self.max_packet = max_packet
        self._buffer = bytearray()

    def feed(self, data: bytes) -> list[tuple[int, bytes]]:
        """The ``(ctr, packet)`` pairs completed by ``data``; an incomplete tail waits for more.

        :raises FramingError: a LEN of 0 or above ``max_packet`` (the stream cannot be resynchronised).
        """
        self._buffer += data
        packets = []
        while len(self._buffer) >= HEADER_SIZE:
            length, ctr = HEADER.unpack_from(self._buffer)
            _check_length(length, self.max_packet)
            if len(self._buffer) < HEADER_SIZE + length:
                break
            packets.append((ctr, bytes(self._buffer[HEADER_SIZE : HEADER_SIZE + length])))
            del self._buffer[: HEADER_SIZE + length]
        return packets


def _check_length(length: int, max_packet: int) -> None:
    if length == 0:
        raise FramingError("LEN 0: an XCP packet has at least its PID")
    if length > max_packet:
        raise FramingError(f"LEN {length} exceeds the largest packet taken ({max_packet} bytes)")
