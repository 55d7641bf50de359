"""DAQ samples in the tests, read until what a test needs came, never for a window of time: a loaded machine
delivers the same samples, later (CI: 0.3 s of a 4 ms event held one sample). Works on what has ``read(timeout)``
returning batches with a ``time`` column: :class:`~workbench.xcp.daq.DaqStream`, a session's DAQ measurement."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

__all__ = ["WAIT_S", "collect_until", "samples"]

WAIT_S = 20.0  # what a loaded machine may take to deliver what the ECU sends in a second; a failing test waits it


def samples(batches: Iterable) -> int:
    """How many samples ``batches`` hold."""
    return sum(len(batch.time) for batch in batches)


def collect_until(live, enough: Callable[[list], bool]) -> list:
    """The batches read from ``live`` until ``enough(batches)`` (or :data:`WAIT_S` passed: the test's own
    assertion then says what did not come)."""
    batches, deadline = [], time.monotonic() + WAIT_S
    while not enough(batches) and time.monotonic() < deadline:
        batches += live.read(0.05)
    return batches
