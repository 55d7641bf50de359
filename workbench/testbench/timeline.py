"""The samples a test has seen so far, per signal, on the test's own clock (seconds since the bench started).

DAQ samples come from the recorder's thread (their ECU time mapped to the host's clock), CAN2 signal
values from the bus listener's thread (the frames' receive times); the test's thread reads them and
waits for more. Each signal keeps the time its sampling (re)started, so an edge can be checked only
where the signal was watched before the stimulus.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import numpy as np

__all__ = ["Timeline"]


class _Series:
    def __init__(self) -> None:
        self.times: list[np.ndarray] = []
        self.values: list[np.ndarray] = []
        self.cache: tuple[np.ndarray, np.ndarray] | None = None
        self.segment_start: float | None = None  # first sample since sampling (re)started
        self.pending_segment = False

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        if self.cache is None:
            if not self.times:
                self.cache = np.empty(0), np.empty(0)
            else:
                self.cache = np.concatenate(self.times), np.concatenate(self.values)
                self.times, self.values = [self.cache[0]], [self.cache[1]]
        return self.cache


class Timeline:
    """Thread-safe store of (time, value) samples by signal name; ``epoch`` is the bench's time 0 (s since the epoch)."""

    def __init__(self, epoch: float | None = None):
        self.epoch = time.time() if epoch is None else epoch
        self._series: dict[str, _Series] = {}
        self._changed = threading.Condition()

    def now(self) -> float:
        """Seconds since the bench started."""
        return time.time() - self.epoch

    def add(self, name: str, epoch_times: np.ndarray, values: np.ndarray) -> None:
        """Append samples stamped in seconds since the epoch."""
        if not len(epoch_times):
            return
        times = np.asarray(epoch_times, dtype=np.float64) - self.epoch
        with self._changed:
            series = self._series.setdefault(name, _Series())
            if series.pending_segment or series.segment_start is None:
                series.segment_start = float(times[0])
                series.pending_segment = False
            series.times.append(times)
            series.values.append(np.asarray(values))
            series.cache = None
            self._changed.notify_all()

    def restart(self, names) -> None:
        """Sampling of ``names`` starts over (a new recording): their next sample opens a new segment."""
        with self._changed:
            for name in names:
                self._series.setdefault(name, _Series()).pending_segment = True

    def samples(self, name: str, start: float = -np.inf, end: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
        """Times and values of ``name`` with ``start <= t <= end``."""
        with self._changed:
            series = self._series.get(name)
            times, values = series.arrays() if series is not None else (np.empty(0), np.empty(0))
        keep = (times >= start) & (times <= end)
        return times[keep], values[keep]

    def last_before(self, name: str, moment: float) -> tuple[float, object] | None:
        """The last sample at or before ``moment``, within the current sampling segment (None: none there)."""
        with self._changed:
            series = self._series.get(name)
            if series is None or series.segment_start is None or series.segment_start > moment:
                return None
            times, values = series.arrays()
        index = int(np.searchsorted(times, moment, side="right")) - 1
        return (float(times[index]), values[index]) if index >= 0 else None

    def sampled_from(self, name: str) -> float | None:
        """The time of the first sample of ``name`` since its sampling (re)started (None: none yet)."""
        with self._changed:
            series = self._series.get(name)
            return None if series is None or series.pending_segment else series.segment_start

    def horizon(self, name: str) -> float | None:
        """The time of the latest sample of ``name`` (None: none yet)."""
        with self._changed:
            series = self._series.get(name)
            if series is None:
                return None
            times, _ = series.arrays()
        return float(times[-1]) if len(times) else None

    def wait_past(self, name: str, moment: float, give_up_at: float, ended: Callable[[], bool] | None = None) -> bool:
        """Block until a sample of ``name`` later than ``moment`` arrived (True) or the bench's clock
        passed ``give_up_at`` or ``ended()`` says no more samples will come (False)."""
        with self._changed:
            while True:
                horizon = self.horizon(name)
                if horizon is not None and horizon > moment:
                    return True
                left = give_up_at - self.now()
                if left <= 0 or (ended is not None and ended()):
                    return False
                self._changed.wait(min(left, 0.05))

    def wait_started(self, names, give_up_at: float) -> list[str]:
        """Block until every one of ``names`` has a sample in its current segment, or the bench's clock
        passed ``give_up_at``; returns the names still without one."""
        with self._changed:
            while True:
                missing = [name for name in names if (series := self._series.get(name)) is None
                           or series.pending_segment or series.segment_start is None]
                left = give_up_at - self.now()
                if not missing or left <= 0:
                    return missing
                self._changed.wait(min(left, 0.05))

    def names(self) -> list[str]:
        with self._changed:
            return list(self._series)
