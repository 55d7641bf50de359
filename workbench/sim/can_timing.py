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

__all__ = ["BusClock", "frame_bits"]

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


DEFAULT_LEAD_S = 0.010  # twice CPython's GIL switch interval (5 ms): how late a ready thread may run


class BusClock:
    """The shared bus of one bit rate: each frame starts when the previous one ended.

    :meth:`occupy` books a frame and returns when it will have ended (``clock`` seconds).
    Senders may run up to ``lead_s`` ahead of the booked bus: :meth:`wait_until` sleeps only
    when a booking ends further ahead, and then until it is ``lead_s / 2`` ahead. Sleeping to
    each frame's exact end would leave the modelled bus idle whenever a thread wakes late (a
    sleep overshoots; a thread that wants the GIL waits up to its 5 ms switch interval), and
    that idle time is lost for good. With the lead the rate over any stretch longer than
    ``lead_s`` is exactly the bus's, and no frame goes out more than ``lead_s`` early.
    """

    def __init__(
        self,
        bitrate: int,
        clock: Callable[[], float] = time.perf_counter,
        sleep: Callable[[float], None] = time.sleep,
        lead_s: float = DEFAULT_LEAD_S,
    ):
        if bitrate <= 0:
            raise ValueError(f"bit rate must be positive, got {bitrate}")
        self.bitrate = bitrate
        self.lead_s = lead_s
        self._clock = clock
        self._sleep = sleep
        self._free_at = 0.0
        self._lock = threading.Lock()
        self.frames = 0
        self.bits = 0

    def occupy(self, message: can.Message) -> float:
        """Book the bus for ``message``; returns the time its transmission ends."""
        bits = frame_bits(message)
        with self._lock:
            start = max(self._clock(), self._free_at)
            self._free_at = start + bits / self.bitrate
            self.frames += 1
            self.bits += bits
            return self._free_at

    def is_due(self, end: float) -> bool:
        """True when a frame whose booking ends at ``end`` may go on the bus now (within the lead)."""
        return end - self._clock() <= self.lead_s

    def wait_until(self, end: float) -> None:
        """Return when a frame booked to end at ``end`` may go on the bus; sleeps only beyond the lead."""
        ahead = end - self._clock()
        if ahead > self.lead_s:
            self._sleep(ahead - self.lead_s / 2)
