"""The GUI's one door to the ECU: a :class:`~workbench.session.Session` driven from worker threads.

Widgets never call the session themselves; they ask the :class:`EcuController`, which runs the
session's method in the thread pool (:mod:`workbench.gui.worker`) and answers through callbacks in
the GUI thread. So the protocol stays in the library, a slow ECU never freezes the window, and
this file lists every session method the GUI uses:

``Session.open``, ``.info()``, ``.epk``, ``.read_only``, ``.page()``, ``.set_page()``,
``.copy_reference_to_working()``, ``.read()``, ``.read_value()``, ``.read_many()``, ``.write()``,
``.measure()`` (in :mod:`workbench.gui.acquisition`), ``.fixes()``, ``.override()``, ``.release()``,
``.close()``; the dataset functions of :mod:`workbench.sync` take the session in the window's workers.

A :class:`~workbench.errors.ConnectionLostError` from any call (or from the DAQ thread, through
:meth:`EcuController.connection_lost`) ends the session: ``lost`` says what and when, and the
controller tries to open the session again every few seconds until the ECU answers (``connected``
follows) or :meth:`EcuController.stop_reconnecting` is called.

Closing a session never waits in the GUI thread: :meth:`EcuController.close` (and a lost connection) says
``disconnected`` at once, stops what the window runs on the session (``before_close``: the DAQ thread, the CAN
monitor) and closes the session in a worker (its DAQ stopped, DISCONNECT, the bus and its receive thread freed:
100-400 ms, seconds for an ECU that stopped answering); ``released`` follows. Opening a session again waits in its
worker for that release, so the ECU is never asked to CONNECT while the DISCONNECT of the session before is under way.

A change of the ECU's values (:meth:`EcuController.change`: a write, an override) is never lost silently:
without a session it is refused at once (:class:`NotWrittenError` "not connected"), and one under way when
the connection is lost or closed ends with a :class:`NotWrittenError` too, through the same ``on_error``.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

from PySide6.QtCore import QEventLoop, QObject, QTimer, Signal

from workbench.errors import ConnectionLostError, InputError, PageError, WorkbenchError
from workbench.gui.project import Connection
from workbench.gui.widgets.status_bar import clock
from workbench.gui.worker import Task, new_task, run_task
from workbench.logs import logger

log = logger(__name__)

__all__ = ["IN_BOOT", "READ_ONLY_PAGE", "Connected", "EcuController", "NotWrittenError", "refusal"]

IN_BOOT = ("the ECU is in its boot loader: no application runs, so there are no calibrations to read or write; "
           "flash its software first (Flash, on the toolbar and in the ECU menu)")
READ_ONLY_PAGE = ("the reference page is active and XCP may not write it; switch to the working page first "
                  "(Working page, on the toolbar and in the ECU menu)")


def refusal(exc: BaseException) -> str | None:
    """Why a change was not made, as the editor it was typed in says it; None: the ECU failed (a dialog)."""
    if isinstance(exc, PageError):  # the library's advice is a command line; the window has a button
        return READ_ONLY_PAGE
    if isinstance(exc, InputError):  # refused before anything was sent, or not sent at all
        return str(exc)
    return None


class NotWrittenError(InputError):
    """A change the window did not make: no session (``lost``: the connection was lost, under the
    change or before it). An input error: the editors say it where the value was typed, not in a dialog."""

    def __init__(self, message: str, lost: bool = False):
        super().__init__(message)
        self.lost = lost


@dataclass(frozen=True)
class Connected:
    """What the window needs right after connecting (read in the worker, not the GUI thread)."""

    session: Any  # workbench.session.Session
    info: Any  # workbench.session.info.EcuInfo


# How long a close in a worker waits for the window's DAQ thread, and an open for the close before it: closing
# stops DAQ and sends DISCONNECT, each bounded by the ECU's timeouts (seconds for one that stopped answering)
_RELEASE_WAIT_S = 30.0


def _open(a2l, connection: Connection, accept_epk_mismatch: bool, released: threading.Event | None = None
          ) -> Connected:
    from workbench.session import Session

    if released is not None:  # the session before lets go of the ECU and the bus first
        released.wait(_RELEASE_WAIT_S)
    session = Session.open(a2l, accept_epk_mismatch=accept_epk_mismatch, **connection.session_options())
    try:
        info = session.info()
    except BaseException:
        session.close()
        raise
    return Connected(session, info)


def _close(session, before: threading.Event | None) -> None:
    """Close ``session`` once ``before`` is set (the window's DAQ thread ended), in a worker."""
    if before is not None:
        before.wait(_RELEASE_WAIT_S)
    session.close()


class EcuController(QObject):
    """Connects, disconnects and calls the session off the GUI thread.

    ``before_close()`` runs in the GUI thread whenever a session closes (Disconnect, a lost connection, the window
    closing), before the session does: what uses the session stops there; the close waits in its worker for the
    ``threading.Event`` it returns (None: for nothing).
    """

    connected = Signal(object)  # Connected
    disconnected = Signal()
    failed = Signal(object)  # an exception of a call nobody else handles
    written = Signal(str)  # a calibration was written (its name): editors and the fix panel refresh
    page_changed = Signal(str)  # "working" / "reference"
    lost = Signal(object)  # the ConnectionLostError that ended the session (after ``disconnected``)
    reconnecting = Signal(int)  # an attempt to open the session again starts (its number)
    released = Signal()  # the sessions closed have let go of the ECU and the bus (after ``disconnected``)

    RECONNECT_MS = 2000

    def __init__(self, parent: QObject | None = None,
                 before_close: Callable[[], threading.Event | None] | None = None):
        super().__init__(parent)
        self.before_close = before_close
        self._closing: set[Task] = set()  # the closes under way in workers
        self._released = threading.Event()  # set while no close is under way (what an open waits for)
        self._released.set()
        self.session = None
        self.info = None
        self.lost_error: ConnectionLostError | None = None  # while the connection is lost
        self.page = "working"  # the page the ECU and XCP use (as the status bar shows it)
        self._target = None  # (a2l, connection, accept_epk_mismatch) of the last open
        self._attempt = 0
        self._generation = 0  # counts opens and closes: a reconnect attempt of an earlier one is not taken
        self._retry = QTimer(self)
        self._retry.setSingleShot(True)
        self._retry.timeout.connect(self.reconnect)

    @property
    def is_connected(self) -> bool:
        return self.session is not None

    def open(self, a2l, connection: Connection, accept_epk_mismatch: bool = False,
             on_failed: Callable[[], None] | None = None) -> Task:
        """Connect to the ECU of ``a2l`` (a path or a loaded A2lDocument) as ``connection`` says;
        ``connected`` or ``failed`` follows. ``on_failed()`` runs after any failure of this attempt, said or not
        (connected before the attempt starts: one that fails at once would otherwise be missed)."""
        self.close()
        self._target = (a2l, connection, accept_epk_mismatch)
        refused = self._refusal(self.failed.emit)

        def failed(exc: BaseException) -> None:
            if isinstance(exc, ConnectionLostError):  # no session to lose: a failure to say (it went unsaid)
                exc = WorkbenchError(f"not connected: {exc}")
            refused(exc)
            if on_failed is not None:
                on_failed()

        return run_task(_open, a2l, connection, accept_epk_mismatch, self._released, on_done=self._taker(),
                        on_error=failed)

    def _taker(self) -> Callable[[Connected], None]:
        """What takes the session being opened now: it is closed instead when the controller was closed (or opened
        anew) meanwhile (another project opened while connecting: the session holds the A2L before)."""
        generation = self._generation

        def take(result: Connected) -> None:
            if generation != self._generation:
                self._release(result.session, None)
                return
            self._opened(result)

        return take

    def _refusal(self, say: Callable[[BaseException], None]) -> Callable[[BaseException], None]:
        """What says why the session being opened now failed: nothing once the controller was closed (or opened
        anew) meanwhile (another project opened while connecting: the failure concerns the project before)."""
        generation = self._generation

        def refused(exc: BaseException) -> None:
            if generation != self._generation:
                log.debug("a connection attempt of an earlier project failed: %s", exc)
                return
            say(exc)

        return refused

    def _opened(self, result: Connected) -> None:
        self.stop_reconnecting()
        self.session, self.info = result.session, result.info
        self.page = "working"
        self.connected.emit(result)

    def close(self) -> None:
        """Disconnect: ``disconnected`` at once when there was a session, ``released`` once it has closed in a
        worker (DAQ stopped, DISCONNECT, the bus freed)."""
        self._generation += 1
        self.stop_reconnecting()
        session, self.session = self.session, None
        self.info = None  # who the ECU was: the window's title says offline (a lost connection keeps it)
        if session is not None:
            self._release(session, self.before_close() if self.before_close is not None else None)
            self.disconnected.emit()

    @property
    def closing(self) -> bool:
        """Whether a session is still closing in a worker (``released`` follows)."""
        return bool(self._closing)

    def _release(self, session, before: threading.Event | None) -> None:
        """Close ``session`` in a worker, after ``before``; ``released`` once no close is under way any more."""
        self._released.clear()
        task = new_task(_close, session, before, on_error=lambda error: log.debug("closing the session: %s", error))
        self._closing.add(task)
        task.finished.connect(lambda: self._closed(task))  # before it starts: a quick close ends before a later connect
        task.start()

    def _closed(self, task: Task) -> None:
        self._closing.discard(task)
        if not self._closing:
            self._released.set()
            self.released.emit()

    def wait_released(self) -> None:
        """Wait until the sessions closing have closed, the window painting meanwhile (a nested event loop: for the
        window's last moment, when the ECU must be let go of before the process ends)."""
        if not self._closing:
            return
        loop = QEventLoop()
        self.released.connect(loop.quit)
        QTimer.singleShot(int(2 * _RELEASE_WAIT_S * 1000), loop.quit)  # a close that never ends keeps no window
        try:
            loop.exec()
        finally:
            self.released.disconnect(loop.quit)

    @property
    def in_boot(self) -> bool:
        """Whether the ECU connected answers in its boot loader (as read at CONNECT, or after a flash)."""
        return self.session is not None and self.info is not None and bool(self.info.boot)

    @property
    def offline_reason(self) -> str:
        """Why nothing can be written now ("" when connected)."""
        if self.session is not None:
            return ""
        if self.lost_error is not None:
            return f"the connection to the ECU was lost at {clock(self.lost_error.when)} (reconnecting)"
        return "not connected"

    def call(self, method: str | Callable[..., Any], *args, on_done: Callable[[Any], None] | None = None,
             on_error: Callable[[BaseException], None] | None = None,
             on_lost: Callable[[BaseException], None] | None = None, **kwargs) -> Task | None:
        """:meth:`task`, started (None: no session)."""
        task = self.task(method, *args, on_done=on_done, on_error=on_error, on_lost=on_lost, **kwargs)
        return task.start() if task is not None else None

    def task(self, method: str | Callable[..., Any], *args, on_done: Callable[[Any], None] | None = None,
             on_error: Callable[[BaseException], None] | None = None,
             on_lost: Callable[[BaseException], None] | None = None, progress: bool = False,
             **kwargs) -> Task | None:
        """A task (to start) that runs ``session.<method>(*args, **kwargs)``, or ``method(session, *args, **kwargs)``
        (a library function of the session, such as :func:`workbench.sync.sync_compare`), in the pool; None without
        a session. Errors go to ``on_error`` or ``failed``; a lost connection to :meth:`connection_lost` instead;
        any error of a session closed meanwhile only to ``on_lost``: the user closed it (Disconnect, the window),
        what that made fail is no error to show."""
        session = self.session
        if session is None:
            return None
        failed = on_error or self.failed.emit
        function = getattr(session, method) if isinstance(method, str) else partial(method, session)
        what = method if isinstance(method, str) else method.__name__

        def error(exc: BaseException) -> None:
            if self.session is not session:  # closed (or lost) under the call: its failure is no news
                log.debug("%s on a session closed meanwhile: %s", what, exc)
                if on_lost is not None:
                    on_lost(exc)
            elif isinstance(exc, ConnectionLostError):
                self.connection_lost(exc)
                if on_lost is not None:
                    on_lost(exc)
            else:
                failed(exc)

        return new_task(function, *args, on_done=on_done, on_error=error, progress=progress, **kwargs)

    # --- a lost connection --------------------------------------------------------------------------

    def connection_lost(self, exc: ConnectionLostError) -> None:
        """The ECU stopped answering: the session is closed (in a worker: its stop commands would wait for
        their timeouts), ``disconnected`` and ``lost`` follow, and reconnecting starts."""
        session, self.session = self.session, None
        if session is None:
            return
        self.lost_error = exc
        self._release(session, self.before_close() if self.before_close is not None else None)
        self.disconnected.emit()
        self.lost.emit(exc)
        self._attempt = 0
        self._retry.start(self.RECONNECT_MS)

    def reconnect(self) -> None:
        """One attempt to open the session again (now); the next follows after ``RECONNECT_MS`` if it fails."""
        if self._target is None or self.session is not None:
            return
        self._retry.stop()
        self._attempt += 1
        self.reconnecting.emit(self._attempt)

        def failed(error: BaseException) -> None:
            log.debug("reconnect attempt %d: %s", self._attempt, error)
            if self.lost_error is not None:
                self._retry.start(self.RECONNECT_MS)

        run_task(_open, *self._target, self._released, on_done=self._taker(), on_error=failed)

    def stop_reconnecting(self) -> None:
        """No further attempts (one under way still connects if the ECU answers)."""
        self._retry.stop()
        self.lost_error = None
        self._attempt = 0

    def change(self, method: str, name: str, *args, on_done: Callable[[Any], None] | None = None,
               on_error: Callable[[BaseException], None], changes: tuple[str, ...] = (), **kwargs) -> Task | None:
        """``session.<method>(name, ...)`` that changes the ECU's values; ``written`` follows for ``name`` (or each
        of ``changes``). Without a session ``on_error`` gets a :class:`NotWrittenError` at once; lost under the
        call, one saying so."""
        if self.session is None:
            on_error(NotWrittenError(self.offline_reason, lost=self.lost_error is not None))
            return None

        def done(result) -> None:
            for written in changes or (name,):
                self.written.emit(written)
            if on_done is not None:
                on_done(result)

        def lost(exc: BaseException) -> None:
            when = getattr(self.lost_error or exc, "when", None)
            at = f" at {clock(when)}" if when else ""
            on_error(NotWrittenError(f"the connection was lost{at} while {name} was being written" if self.lost_error
                                     else f"disconnected while {name} was being written", lost=True))

        return self.call(method, name, *args, on_done=done, on_error=on_error, on_lost=lost, **kwargs)

    def write(self, name: str, value, *, allow_extended_limits: bool = False,
              on_done: Callable[[Any], None] | None = None,
              on_error: Callable[[BaseException], None]) -> Task | None:
        """Write a calibration as the session checks it (limits, EXTENDED_LIMITS only when allowed; read
        back): :meth:`change`."""
        return self.change("write", name, value, allow_extended_limits=allow_extended_limits, on_done=on_done,
                           on_error=on_error)

    def set_page(self, page: str, on_error: Callable[[BaseException], None] | None = None) -> Task | None:
        """Switch the ECU to ``page``: ``page_changed`` follows, or ``on_error`` (``failed``) with the page unchanged."""
        def done(_) -> None:
            self.page = page
            self.page_changed.emit(page)

        return self.call("set_page", page, on_done=done, on_error=on_error)
