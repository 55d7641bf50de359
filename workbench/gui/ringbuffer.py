"""Sample buffers between the acquisition threads and the plots: bounded, thread-safe, contiguous.

A :class:`RingBuffer` keeps the last ``capacity`` (time, value) pairs of one signal in arrays twice
that long; appending past the end moves the newest half to the front (amortised O(1)), so the
samples are always one contiguous slice and a plot reads a time window with two ``searchsorted``
and one copy, never a concatenation of chunks.
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

    def window(self, t0: float, t1: float, margin: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Copies of the samples with ``t0 <= time <= t1``, plus ``margin`` samples on either side
        (so a line runs to the plot's edges)."""
        with self._lock:
            times = self._time[self._start:self._end]
            lo = max(int(np.searchsorted(times, t0, "left")) - margin, 0)
            hi = min(int(np.searchsorted(times, t1, "right")) + margin, len(times))
            return times[lo:hi].copy(), self._value[self._start + lo:self._start + hi].copy()

    def last(self) -> tuple[float, float] | None:
        """The newest (time, value), or None when empty."""
        with self._lock:
            if self._end == self._start:
                return None
            return float(self._time[self._end - 1]), float(self._value[self._end - 1])

    def at(self, t: float) -> float | None:
        """The value of the newest sample at or before ``t`` (a sample-and-hold reading), or None."""
        with self._lock:
            times = self._time[self._start:self._end]
            i = int(np.searchsorted(times, t, "right")) - 1
            return None if i < 0 else float(self._value[self._start + i])

    def span(self) -> tuple[float, float] | None:
        """(oldest, newest) time, or None when empty."""
        with self._lock:
            if self._end == self._start:
                return None
            return float(self._time[self._start]), float(self._time[self._end - 1])

    def clear(self) -> None:
        with self._lock:
            self._start = self._end = 0
