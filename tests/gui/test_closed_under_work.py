"""Work the window started on the ECU (the cache check after connecting, a comparison of parameter sets) when the
user closes the session under it (Disconnect, the window closed, another project): nothing to say, the user closed
it; it said "the XCP link is closed" in an error dialog (as the DAQ acquisition did: test_acquisition_close.py)."""

from __future__ import annotations

import threading

from gui_helpers import WAIT_MS, open_window

from workbench.gui.worker import Task


def _held_until_closed(function, starting: threading.Event, closed: threading.Event):
    """``function`` that waits, once it is called, until the test closed the session."""
    def held(*args, **kwargs):
        starting.set()
        closed.wait(WAIT_MS / 1000)
        return function(*args, **kwargs)

    return held


def _close_under_it(qtbot, window, starting: threading.Event, closed: threading.Event) -> None:
    qtbot.waitUntil(starting.is_set, timeout=WAIT_MS)
    with qtbot.waitSignal(window.controller.disconnected, timeout=WAIT_MS):
        window.disconnect_action.trigger()
    closed.set()
    qtbot.waitUntil(lambda: not Task._running, timeout=WAIT_MS)  # its failure (or result) reached the window


def test_the_cache_check_of_a_session_closed_under_it_says_nothing(qtbot, demo_ecu, project, monkeypatch):
    import workbench.sync

    starting, closed = threading.Event(), threading.Event()
    monkeypatch.setattr(workbench.sync, "sync_compare",
                        _held_until_closed(workbench.sync.sync_compare, starting, closed))
    window = open_window(qtbot, project)  # connected: the ECU is compared with the project's s19
    _close_under_it(qtbot, window, starting, closed)
    assert [dialog.text() for dialog in window.errors] == [] and window.sync_dialog is None


def test_a_comparison_of_the_pages_of_a_session_closed_under_it_says_nothing(qtbot, demo_ecu, project, monkeypatch):
    import workbench.sync

    project.s19 = None  # no cache check after connecting
    window = open_window(qtbot, project)
    starting, closed = threading.Event(), threading.Event()
    monkeypatch.setattr(workbench.sync, "read_dataset",
                        _held_until_closed(workbench.sync.read_dataset, starting, closed))
    window.compare_pages_action.trigger()
    _close_under_it(qtbot, window, starting, closed)
    assert [dialog.text() for dialog in window.errors] == []
