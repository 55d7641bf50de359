"""Sample buffers between the acquisition threads and the plots: bounded, thread-safe, contiguous.

A :class:`RingBuffer` keeps the last ``capacity`` (time, value) pairs of one signal in arrays twice
that long; appending past the end moves the newest half to the front (amortised O(1)), so the
samples are always one contiguous slice and a plot reads a time window with two ``searchsorted``
and one copy, never a concatenation of chunks.

A pause in the measurement (stopped for a flash, restarted with other signals, a lost connection)
is marked with :meth:`RingBuffer.mark_gap`; :meth:`RingBuffer.window` then puts a NaN between the
samples either side of it, so a plot breaks its line there instead of drawing what was never measured.
"""

from __future__ import annotations

import threading

import numpy as np

__all__ = ["RingBuffer"]


class RingBuffer:
    """The newest ``capacity`` samples of one signal (time in seconds, value as float64)."""

    def __init__(self, capacity: int = 200_000):
        if capacity < 1:
            raise ValueError("capacity must be positive")
        self.capacity = capacity
        self._time = np.empty(2 * capacity)
        self._value = np.empty(2 * capacity)
        self._start = self._end = 0
        self._lock = threading.Lock()
        self._gaps: list[float] = []  # times of the last sample before each pause, ascending
        self.total = 0  # samples ever appended

    def __len__(self) -> int:
        return self._end - self._start

    def append(self, time: np.ndarray, value: np.ndarray) -> None:
        """Append samples (``time`` ascending, seconds); the oldest fall out past ``capacity``."""
        time = np.asarray(time, dtype=np.float64).ravel()
        value = np.asarray(value, dtype=np.float64).ravel()
        if len(time) != len(value):
            raise ValueError(f"{len(time)} times for {len(value)} values")
        if len(time) > self.capacity:
            time, value = time[-self.capacity:], value[-self.capacity:]
        n = len(time)
        with self._lock:
            if self._end + n > len(self._time):
                keep = min(self._end - self._start, self.capacity - n)
                self._time[:keep] = self._time[self._end - keep:self._end]
                self._value[:keep] = self._value[self._end - keep:self._end]
                self._start, self._end = 0, keep
            self._time[self._end:self._end + n] = time
            self._value[self._end:self._end + n] = value
            self._end += n
            self._start = max(self._start, self._end - self.capacity)
            self.total += n
            oldest = self._time[self._start]
            while self._gaps and self._gaps[0] < oldest:
                self._gaps.pop(0)

    def mark_gap(self) -> None:
        """The measurement pauses after the newest sample: no line joins it to the next one."""
        with self._lock:
            if self._end > self._start:
                last = float(self._time[self._end - 1])
                if not self._gaps or self._gaps[-1] != last:
                    self._gaps.append(last)

    @property
    def gaps(self) -> list[float]:
        with self._lock:
            return list(self._gaps)

    def window(self, t0: float, t1: float, margin: int = 1, gaps: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Copies of the samples with ``t0 <= time <= t1``, plus ``margin`` samples on either side
        (so a line runs to the plot's edges); with ``gaps``, a NaN after the last sample before each pause."""
        with self._lock:
            times = self._time[self._start:self._end]
            lo = max(int(np.searchsorted(times, t0, "left")) - margin, 0)
            hi = min(int(np.searchsorted(times, t1, "right")) + margin, len(times))
            t, v = times[lo:hi].copy(), self._value[self._start + lo:self._start + hi].copy()
            breaks = [g for g in self._gaps if len(t) and t[0] <= g < t[-1]] if gaps else []
        if breaks:
            at = np.searchsorted(t, breaks, "right")
            t, v = np.insert(t, at, breaks), np.insert(v, at, np.nan)
        return t, v

    def last(self) -> tuple[float, float] | None:
        """The newest (time, value), or None when empty."""
        with self._lock:
            if self._end == self._start:
                return None
            return float(self._time[self._end - 1]), float(self._value[self._end - 1])

    def at(self, t: float) -> float | None:
        """The value of the newest sample at or before ``t`` (a sample-and-hold reading), or None (also
        during a pause: after its last sample, before the next)."""
        with self._lock:
            times = self._time[self._start:self._end]
            i = int(np.searchsorted(times, t, "right")) - 1
            if i < 0 or (times[i] < t and float(times[i]) in self._gaps):
                return None
            return float(self._value[self._start + i])

    def span(self) -> tuple[float, float] | None:
        """(oldest, newest) time, or None when empty."""
        with self._lock:
            if self._end == self._start:
                return None
            return float(self._time[self._start]), float(self._time[self._end - 1])

    def clear(self) -> None:
        with self._lock:
            self._start = self._end = 0
            self._gaps.clear()
