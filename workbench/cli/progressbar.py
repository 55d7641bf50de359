"""A rich progress bar on stderr that implements :class:`workbench.progress.Progress`.

Shown only when stderr is a terminal (and disappears when done), so pipes, CI logs
and ``--json`` output stay clean. Ctrl-C interrupts the job (the CLI ends with exit code 130,
atomic writes leave no half-written file), except under :func:`cancel_on_interrupt`: a job that
writes to the ECU step by step (a flash, a dataset) is cancelled at its next step by the first
Ctrl-C and says what it did; ``cancelled`` is also for front ends with a Cancel button.
"""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["ProgressBar", "cancel_on_interrupt"]


class ProgressBar:
    """``with ProgressBar("updating") as progress: job(progress=progress)``."""

    def __init__(self, description: str, enabled: bool | None = None):
        self.description = description
        self.enabled = sys.stderr.isatty() if enabled is None else enabled
        self.cancelled = False
        self._bar = None
        self._task = None

    def __enter__(self) -> "ProgressBar":
        if self.enabled:  # rich is imported only when a bar is shown: it costs a noticeable start-up time
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self._bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                 TimeElapsedColumn(), console=Console(stderr=True), transient=True)
            self._bar.start()
            self._task = self._bar.add_task(self.description, total=None)
        return self

    def __exit__(self, *exc) -> None:
        if self._bar is not None:
            self._bar.stop()

    def update(self, done: int, total: int, label: str = "") -> None:
        if self._bar is not None:
            self._bar.update(self._task, completed=done, total=total or None,
                             description=label or self.description)


@contextmanager
def cancel_on_interrupt(progress: ProgressBar, step: str) -> Iterator[None]:
    """The first Ctrl-C cancels the job at its next ``step`` (a clean state it can say); a second one interrupts."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def cancel(signum, frame):
        if progress.cancelled:
            raise KeyboardInterrupt
        progress.cancelled = True
        print(f"\nstopping at the next {step} (Ctrl-C again to interrupt at once)", file=sys.stderr)

    previous = signal.signal(signal.SIGINT, cancel)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
