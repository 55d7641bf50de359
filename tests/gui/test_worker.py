"""The window's tasks (plain functions run off the GUI thread): a finished one keeps nothing of what its callbacks
refer to (an editor, the A2L model of a project closed since)."""

from __future__ import annotations

import gc
import threading
import time
import weakref

from gui_helpers import WAIT_MS
from PySide6.QtCore import QThreadPool

from workbench.gui.worker import Task, run_task


class _Payload:
    """What a task's callbacks refer to."""


def _job(fails: bool) -> int:
    if fails:
        raise ValueError("refused")
    return 1


def test_a_finished_task_keeps_nothing_its_callbacks_refer_to(qtbot):
    payloads, results = [], []
    for fails in (False, True):
        payload = _Payload()
        payloads.append(weakref.ref(payload))
        run_task(_job, fails, on_done=lambda result, p=payload: results.append(result),
                 on_error=lambda exc, p=payload: results.append(str(exc)))
        del payload
    qtbot.waitUntil(lambda: len(results) == 2 and not Task._running, timeout=WAIT_MS)
    QThreadPool.globalInstance().waitForDone(WAIT_MS)
    gc.collect()
    assert sorted(map(str, results)) == ["1", "refused"] and [ref() for ref in payloads] == [None, None]


def test_a_task_and_what_its_callbacks_refer_to_are_freed_in_the_gui_thread(qtbot, monkeypatch):
    """The pool thread may still hold a task when the GUI thread has delivered its end (it was switched out after the
    task's ``finished``): the last reference must still go in the GUI thread, not free a Qt object (and an editor its
    callbacks refer to) in the pool thread."""
    run = Task.run

    def run_then_switched_out(task):
        run(task)
        time.sleep(0.01)  # the GUI thread runs meanwhile: it has taken the task's end

    monkeypatch.setattr(Task, "run", run_then_switched_out)
    freed_in, results = [], []
    for _ in range(6):
        payload = _Payload()
        task = run_task(_job, False, on_done=lambda result, p=payload: results.append(result))
        for referent in (task, payload):
            weakref.finalize(referent, lambda: freed_in.append(threading.current_thread() is threading.main_thread()))
        del task, payload, referent
    qtbot.waitUntil(lambda: len(results) == 6 and not Task._running, timeout=WAIT_MS)
    QThreadPool.globalInstance().waitForDone(WAIT_MS)
    gc.collect()
    assert len(freed_in) == 12 and all(freed_in)


def test_a_finished_slot_runs_though_nobody_holds_the_task(qtbot):
    """The caller's own ``finished`` slots (a dialog's reset, the job buttons) run after the task's end though only
    the pool held it: freed at its first ``finished`` slot, the task took the later ones with it (none ran)."""
    ends = []
    for _ in range(10):
        task = Task(_job, False)
        task.finished.connect(lambda: ends.append("finished"))
        task.start()
        del task
    qtbot.waitUntil(lambda: len(ends) == 10 and not Task._running, timeout=WAIT_MS)
