"""Simulated time and periodic tasks.

Time is an integer number of microseconds, so 4/50/100 ms periods never drift. Whoever
owns the scheduler decides how time moves: a real-time clock thread (users), a faster
clock, or explicit :meth:`Scheduler.run_until` calls (tests, benchmarks).
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = ["US_PER_S", "PeriodicTask", "Scheduler", "seconds_to_us"]

US_PER_S = 1_000_000


def seconds_to_us(seconds: float) -> int:
    return round(seconds * US_PER_S)


@dataclass(order=True)
class PeriodicTask:
    next_due_us: int
    order: int  # among tasks due at the same instant, lower runs first
    sequence: int
    period_us: int = field(compare=False)
    run: Callable[[], None] = field(compare=False)
    name: str = field(compare=False)
    cancelled: bool = field(default=False, compare=False)


class Scheduler:
    def __init__(self) -> None:
        self.now_us = 0
        self._queue: list[PeriodicTask] = []
        self._sequence = itertools.count()

    @property
    def now_s(self) -> float:
        return self.now_us / US_PER_S

    def add(self, period_s: float, run: Callable[[], None], name: str, order: int = 0, first_due_s: float | None = None) -> PeriodicTask:
        """Run ``run`` every ``period_s`` seconds, first at ``first_due_s`` (default: one period from now)."""
        period_us = seconds_to_us(period_s)
        if period_us <= 0:
            raise ValueError(f"task {name}: period must be positive, got {period_s} s")
        first = self.now_us + period_us if first_due_s is None else seconds_to_us(first_due_s)
        task = PeriodicTask(first, order, next(self._sequence), period_us, run, name)
        heapq.heappush(self._queue, task)
        return task

    def cancel(self, task: PeriodicTask) -> None:
        task.cancelled = True

    def next_due_us(self) -> int | None:
        while self._queue and self._queue[0].cancelled:
            heapq.heappop(self._queue)
        return self._queue[0].next_due_us if self._queue else None

    def run_until(self, time_us: int) -> None:
        """Run every task due up to and including ``time_us``, in time order, then set the time."""
        while True:
            due = self.next_due_us()
            if due is None or due > time_us:
                break
            task = heapq.heappop(self._queue)
            self.now_us = task.next_due_us
            task.next_due_us += task.period_us
            heapq.heappush(self._queue, task)
            task.run()
        self.now_us = max(self.now_us, time_us)

    def advance(self, seconds: float) -> None:
        self.run_until(self.now_us + seconds_to_us(seconds))
