"""A CAN bus's time: how long a frame occupies the bus, and a shared bus clock to pace frames.

:func:`frame_bits` counts a classic data frame's bits exactly: SOF through the CRC with
the stuff bits the frame's content needs, then CRC delimiter, ACK, EOF and the 3-bit
intermission (an 8-byte standard frame: 111 bits without stuffing, at most 135).
:class:`BusClock` lets every frame of a simulated bus occupy it one after another, so
traffic never exceeds what a real bus of that bit rate carries.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from functools import lru_cache

import can

_CRC15_POLY = 0x4599
_TRAILER_BITS = 1 + 2 + 7 + 3  # CRC delimiter, ACK slot + delimiter, EOF, intermission


@lru_cache(maxsize=8192)
def _bits(arbitration_id: int, extended: bool, data: bytes) -> int:
    dlc = len(data)
    if extended:
        header = (
            "0" + format(arbitration_id >> 18, "011b") + "11"  # SOF, base id, SRR, IDE
            + format(arbitration_id & 0x3FFFF, "018b") + "000"  # id extension, RTR, r1, r0
        )
    else:
        header = "0" + format(arbitration_id, "011b") + "000"  # SOF, id, RTR, IDE, r0
    stream = header + format(dlc, "04b") + "".join(format(b, "08b") for b in data)
    stream += format(_crc15(stream), "015b")
    stuffed, run, last = 0, 0, ""
    for bit in stream:
        if bit == last:
            run += 1
        else:
            last, run = bit, 1
        if run == 5:  # a stuff bit of the other level follows and starts a new run
            stuffed += 1
            last, run = ("1" if bit == "0" else "0"), 1
    return len(stream) + stuffed + _TRAILER_BITS


def _crc15(bits: str) -> int:
    crc = 0
    for bit in bits:
        feedback = (crc >> 14) ^ (bit == "1")
        crc = (crc << 1) & 0x7FFF
        if feedback:
            crc ^= _CRC15_POLY
    return crc


def frame_bits(message: can.Message) -> int:
    """Bits the frame occupies on a classic CAN bus, stuff bits and intermission included."""
    return _bits(message.arbitration_id, message.is_extended_id, bytes(message.data))


class BusClock:
    """The shared bus of one bit rate: each frame starts when the previous one ended.

    :meth:`occupy` books a frame and returns when it will have ended (``clock`` seconds);
    :meth:`wait_until` sleeps only when the booking runs ahead of real time by more than
    ``slack_s``, so the average rate is exact although sleeps are coarse.
    """

    def __init__(
        self,
        bitrate: int,
        clock: Callable[[], float] = time.perf_counter,
        sleep: Callable[[float], None] = time.sleep,
        slack_s: float = 0.002,
    ):
        if bitrate <= 0:
            raise ValueError(f"bit rate must be positive, got {bitrate}")
        self.bitrate = bitrate
        self._clock = clock
        self._sleep = sleep
        self._slack_s = slack_s
        self._free_at = 0.0
        self._lock = threading.Lock()
        self.frames = 0
        self.bits = 0

    def frame_time(self, message: can.Message) -> float:
        return frame_bits(message) / self.bitrate

    def occupy(self, message: can.Message) -> float:
        """Book the bus for ``message``; returns the time its transmission ends."""
        bits = frame_bits(message)
        with self._lock:
            start = max(self._clock(), self._free_at)
            self._free_at = start + bits / self.bitrate
            self.frames += 1
            self.bits += bits
            return self._free_at

    def wait_until(self, end: float) -> None:
        ahead = end - self._clock()
        if ahead > self._slack_s:
            self._sleep(ahead)
