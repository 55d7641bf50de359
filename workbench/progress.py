"""Progress reporting and cancellation for long jobs, free of any UI toolkit.

Long library functions take ``progress: Progress | None``; the CLI passes a rich
progress bar, the GUI a Qt-backed object, tests a recorder. Cancelling means the
job raises :class:`~workbench.errors.Cancelled` at its next check point.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from workbench.errors import Cancelled

__all__ = ["NullProgress", "Progress", "report"]


@runtime_checkable
class Progress(Protocol):
    def update(self, done: int, total: int, label: str = "") -> None:
        """Report ``done`` of ``total`` units (bytes, objects...) of work."""

    @property
    def cancelled(self) -> bool:
        """True once the user asked to stop."""


class NullProgress:
    """Progress that reports nowhere and is never cancelled."""

    cancelled = False

    def update(self, done: int, total: int, label: str = "") -> None:
        pass


NULL_PROGRESS = NullProgress()


def report(progress: Progress | None, done: int, total: int, label: str = "") -> None:
    """Report to ``progress`` (if any), then raise :class:`Cancelled` if it was cancelled."""
    if progress is None:
        return
    progress.update(done, total, label)
    if progress.cancelled:
        raise Cancelled(f"cancelled{': ' + label if label else ''} at {done}/{total}")
