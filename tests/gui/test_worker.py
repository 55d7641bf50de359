"""The window's tasks (plain functions run off the GUI thread): a finished one keeps nothing of what its callbacks
refer to (an editor, the A2L model of a project closed since)."""

from __future__ import annotations

import gc
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
