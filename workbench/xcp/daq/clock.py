"""DAQ time: the slave's wrapping timestamp counter unwrapped into seconds, and mapped to host time.

Host arrival times come in bursts (a CAN controller's queue, the OS scheduler), so a sample's
time is the slave's timestamp when it sends one. The counter wraps (1, 2 or 4 bytes); host arrival
times tell how many times it wrapped between two samples: a sample cannot have travelled faster than
the fastest one so far, so it takes the most wraps that keep its travel time at or above that (less a
margin of an eighth of a wrap). A 16-bit counter of 10 µs ticks that wraps every 0.65 s is unwrapped
for a list sampled once a second, and a 1-byte millisecond counter (a wrap every 256 ms) through a
stall of the host of up to 220 ms (a count of wraps rounded from arrival gaps erred past 128 ms).
Arrival says little on a loaded host, though: a stalled receiver, or a slave that falls behind and
sends what it owes late, delivers samples long after they were taken (a simulated ECU at load 8 ran
up to 0.7 s behind), and a 1-byte counter took every delay past 220 ms for a wrap, each one lowering
the fastest travel by up to 32 ms: 25 s of phantom wraps in 3 minutes, their samples counted lost.
So a list's own cycle comes first: a step of one cycle (within a sixteenth of it) is the next sample,
whenever it arrived; only a step that is no cycle (samples were lost, or the cycle is not known) is
unwrapped by arrival. That misreads a loss only when it is a whole number of wraps to within a
sixteenth of a cycle (64 samples of a 4 ms list on a millisecond byte counter). Within a read, a
burst is judged by its fastest sample (each sample by the fastest travel from it to the end of its
batch: the samples after it count on from it). The fastest travel may rise by ``max_drift`` as the
slave's time runs on: a slave clock slower than the host's makes every travel longer, 224 ms after
37 minutes at 100 ppm, which would have been a phantom wrap.

Host time = slave time + offset, where the offset is the smallest (arrival − slave time) seen:
the sample that travelled fastest. It may rise slowly (``max_drift``) so that a slave clock
running slower than the host's does not fall behind. When a sample travels faster than all before
(the first ones sat in a queue of a loaded host), the offset falls to it not at once but at most half
as fast as the slave's time runs on, so that a list's host times never go back (the batch before was
mapped with the larger offset): a correction of 4 ms is spread over the next 8 ms of samples.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DaqClock"]

MAX_DRIFT = 200e-6  # s/s: crystal tolerances of ECU and host together


class DaqClock:
    """One per measurement: all lists share the slave's counter and the origin (the first sample's time)."""

    def __init__(self, timestamp_size: int, resolution_s: float, *, max_drift: float = MAX_DRIFT):
        self.modulus = 1 << (8 * timestamp_size) if timestamp_size else 0
        self.resolution_s = resolution_s
        self.max_drift = max_drift
        self._last: dict[int, tuple[int, int, float]] = {}  # list -> (last raw count, unwrapped, fastest travel s)
        self._origin_count: int | None = None
        self._origin_host_ns: int | None = None
        self._offset_s: float | None = None
        self._offset_at_s = 0.0
        self._mapped: dict[int, tuple[float, float]] = {}  # list -> (its last sample's s, the offset it had)

    def times(self, daq_list: int, counts: np.ndarray | None, host_ns: np.ndarray, period_s: float | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
        """(seconds since the measurement's first sample, host time in seconds since the epoch) per sample.

        ``counts``: the slave's raw timestamps (None: the slave sends none; host arrival is used).
        ``period_s``: the list's cycle (its event's, prescaler included; None: not cyclic or not known).
        """
        host_ns = np.asarray(host_ns, dtype=np.int64)
        if self._origin_host_ns is None and len(host_ns):
            self._origin_host_ns = int(host_ns[0])
        if counts is None or not self.modulus:
            seconds = (host_ns - self._origin_host_ns) * 1e-9
            return seconds, host_ns * 1e-9
        unwrapped = self._unwrap(daq_list, np.asarray(counts, dtype=np.int64), host_ns,
                                 period_s / self.resolution_s if period_s else None)
        if self._origin_count is None and len(unwrapped):
            self._origin_count = int(unwrapped[0])
        seconds = (unwrapped - self._origin_count) * self.resolution_s
        return seconds, self._host(daq_list, seconds, host_ns)

    def _unwrap(self, daq_list: int, counts: np.ndarray, host_ns: np.ndarray, period: float | None) -> np.ndarray:
        if not len(counts):
            return counts
        host_s = host_ns * 1e-9
        last = self._last.get(daq_list)
        if last is None:
            previous_raw, previous, fastest = int(counts[0]), int(counts[0]), float(host_s[0] - counts[0] * self.resolution_s)
        else:
            previous_raw, previous, fastest = last
        steps = np.mod(np.diff(np.concatenate(([previous_raw], counts))), self.modulus)
        regular = np.zeros(len(steps), dtype=bool)
        if period:  # a step of one cycle (within a sixteenth) is the next sample, however late it came
            wraps = np.maximum(np.rint((period - steps) / self.modulus), 0).astype(np.int64)
            regular = np.abs(steps + wraps * self.modulus - period) <= max(1.0, period / 16)
            steps = steps + np.where(regular, wraps, 0) * self.modulus
        unwrapped = previous + np.cumsum(steps)  # no wrap beyond what each step and the cycle show
        wrap_s = self.modulus * self.resolution_s
        travel = host_s - unwrapped * self.resolution_s  # minus what the missing wraps would add to the slave time
        settled = np.minimum.accumulate(travel[::-1])[::-1]  # a burst is judged by its fastest sample (see above)
        missing = np.where(regular, 0, np.floor((settled - fastest + wrap_s / 8) / wrap_s).astype(np.int64))
        unwrapped = unwrapped + np.maximum.accumulate(np.maximum(missing, 0)) * self.modulus
        drifted = fastest + self.max_drift * max(int(unwrapped[-1]) - previous, 0) * self.resolution_s
        fastest = min(drifted, float(np.min(host_s - unwrapped * self.resolution_s)))
        self._last[daq_list] = (int(counts[-1]), int(unwrapped[-1]), fastest)
        return unwrapped

    def _host(self, daq_list: int, seconds: np.ndarray, host_ns: np.ndarray) -> np.ndarray:
        if not len(seconds):
            return seconds + self._origin_host_ns * 1e-9
        host_s = (host_ns - self._origin_host_ns) * 1e-9
        batch_offset = float(np.min(host_s - seconds))
        if self._offset_s is None:
            self._offset_s = batch_offset
        else:
            allowed = self._offset_s + self.max_drift * max(float(seconds[-1]) - self._offset_at_s, 0.0)
            self._offset_s = min(allowed, batch_offset)
        self._offset_at_s = float(seconds[-1])
        offset = np.full(len(seconds), self._offset_s)
        mapped = self._mapped.get(daq_list)
        if mapped is not None:  # falling no faster than half the slave's time since this list's last sample
            last_s, last_offset = mapped
            offset = np.maximum(offset, last_offset - (seconds - last_s) / 2)
        self._mapped[daq_list] = (float(seconds[-1]), float(offset[-1]))
        return self._origin_host_ns * 1e-9 + seconds + offset
