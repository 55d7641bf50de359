"""Plain library functions run off the GUI thread, with progress and cancel.

A :class:`Task` calls one function in Qt's thread pool and reports back through signals, which
Qt delivers in the GUI thread: the window never waits for the ECU, and nothing polls
(no ``processEvents``, no ``sleep``). A task made with ``progress=True`` hands the function a
:class:`QtProgress` as its ``progress`` keyword: the library reports to it through the toolkit-free
:class:`workbench.progress.Progress` protocol, and :meth:`Task.cancel` makes the library raise
:class:`~workbench.errors.Cancelled` at its next check point.
"""

from __future__ import annotations

import gc
import threading
import weakref
from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QObject, QRunnable, QThreadPool, QTimer, Signal, Slot

from workbench.logs import logger

log = logger(__name__)

__all__ = ["QtProgress", "Task", "collect_garbage_on_the_gui_thread", "new_task", "run_task"]


class QtProgress(QObject):
    """A :class:`workbench.progress.Progress` whose reports become a Qt signal (any thread may report)."""

    changed = Signal(int, int, str)  # done, total, label

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self._cancel = threading.Event()

    def update(self, done: int, total: int, label: str = "") -> None:
        self.changed.emit(int(done), int(total), label)

    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    def cancel(self) -> None:
        self._cancel.set()


class Task(QObject):
    """One call of ``function(*args, **kwargs)`` in the thread pool.

    Exactly one of ``succeeded(result)`` and ``failed(exception)`` is emitted, then ``finished``.
    """

    succeeded = Signal(object)
    failed = Signal(object)
    finished = Signal()

    _running: set[Task] = set()  # keeps a task (and its signals) alive until its pool thread let go of it
    _releases: _Releases | None = None

    def __init__(self, function: Callable[..., Any], *args, progress: bool = False, **kwargs):
        super().__init__()
        self.function, self.args, self.kwargs = function, args, kwargs
        self.progress = QtProgress() if progress else None
        if self.progress is not None:
            self.kwargs["progress"] = self.progress

    def start(self, pool: QThreadPool | None = None) -> Task:
        """Run it in ``pool`` (Qt's global one); called in the GUI thread."""
        if Task._releases is None:
            Task._releases = _Releases()
        Task._running.add(self)
        (pool or QThreadPool.globalInstance()).start(_Runnable(self, Task._releases))
        return self

    def cancel(self) -> None:
        if self.progress is not None:
            self.progress.cancel()

    def run(self) -> None:
        """The body, in a pool thread."""
        try:
            result = self.function(*self.args, **self.kwargs)
        except Exception as exc:  # noqa: BLE001 - every error goes to the GUI as a dialog, none kills the pool
            log.debug("task %s failed", getattr(self.function, "__name__", self.function), exc_info=True)
            self.failed.emit(exc)
        else:
            self.succeeded.emit(result)
        finally:
            self.finished.emit()


class _Releases(QObject):
    """Takes a task out of :attr:`Task._running` in the GUI thread once its pool thread holds it no more, so that the
    last reference to it goes in the GUI thread: freed in a pool thread (which ``finished`` taking it out let happen
    when that thread was switched out after emitting it), the task, its progress and whatever its callbacks refer to
    (an editor, a closed project's A2L model) were Qt objects destroyed outside their thread, the hang
    :func:`collect_garbage_on_the_gui_thread` tells of."""

    released = Signal(object)  # a weak reference to the task

    def __init__(self):
        super().__init__()
        self.released.connect(self._forget)

    @Slot(object)
    def _forget(self, task: weakref.ref[Task]) -> None:
        Task._running.discard(task())


class _Runnable(QRunnable):
    def __init__(self, task: Task, releases: _Releases):
        super().__init__()
        self.task, self.releases = task, releases

    def run(self) -> None:
        task, self.task = self.task, None  # the pool may keep this wrapper past the run: not the task with it
        released = weakref.ref(task)
        try:
            task.run()
        finally:
            del task  # posted after the task's own signals, the release comes to the GUI thread after them
            self.releases.released.emit(released)


def new_task(function: Callable[..., Any], *args, on_done: Callable[[Any], None] | None = None,
             on_error: Callable[[BaseException], None] | None = None, progress: bool = False, **kwargs) -> Task:
    """A task to start that runs ``function(*args, **kwargs)`` in the pool; ``on_done(result)``/``on_error(exc)``
    run in the GUI thread."""
    task = Task(function, *args, progress=progress, **kwargs)
    if on_done is not None:
        task.succeeded.connect(on_done)
    if on_error is not None:
        task.failed.connect(on_error)
    return task


def run_task(function: Callable[..., Any], *args, on_done: Callable[[Any], None] | None = None,
             on_error: Callable[[BaseException], None] | None = None, progress: bool = False, **kwargs) -> Task:
    """:func:`new_task`, started."""
    return new_task(function, *args, on_done=on_done, on_error=on_error, progress=progress, **kwargs).start()


def collect_garbage_on_the_gui_thread(parent: QObject) -> QTimer:
    """Python's cycle collector runs in whichever thread allocates when its threshold is reached. On a worker (a
    DAQ thread writing an MDF4 file, say) it destroyed Qt objects of the window's cycles there: Qt's destructor
    waited for the GIL while the GUI thread, holding it, waited for Qt's lock to delete another, and both hung (a
    CI run). The automatic collector is switched off and a timer on the GUI thread collects what is due instead;
    the timer's owner (``parent``) going away, or :meth:`QTimer.stop`, leaves it switched off: call
    ``gc.enable()`` after stopping it."""
    gc.disable()
    timer = QTimer(parent)
    timer.timeout.connect(_collect_due)
    timer.start(100)
    return timer


def _collect_due() -> None:
    """The generation the automatic collector would collect now, if any (its thresholds)."""
    counts, thresholds = gc.get_count(), gc.get_threshold()
    if counts[0] > thresholds[0]:
        gc.collect(2 if counts[2] > thresholds[2] else 1 if counts[1] > thresholds[1] else 0)
