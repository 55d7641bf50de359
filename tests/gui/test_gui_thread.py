"""The GUI thread never waits for the ECU or a thread: Disconnect, closing the window, connecting and starting a flash
stop the DAQ thread, take the CAN monitor off the bus (python-can's Notifier joins its thread) and close the session
in workers (they stalled the window 100-400 ms, a flash start once 5.2 s). Checked by where those calls run, not by
how long they take."""

from __future__ import annotations

import threading
from contextlib import contextmanager

import pytest
from gui_helpers import WAIT_MS, open_window
from PySide6.QtCore import QTimer

from workbench.session import Session

FLASH_MS = 120_000


@contextmanager
def waits_on_the_gui_thread(monkeypatch):
    """The names of the calls that wait (a thread's join, a session's close, a CAN listener's start) made on the GUI
    thread meanwhile."""
    seen: list[str] = []

    def watched(owner, name: str) -> None:
        original = getattr(owner, name)

        def call(*args, **kwargs):
            if threading.current_thread() is threading.main_thread():
                seen.append(f"{owner.__name__}.{name}")
            return original(*args, **kwargs)

        patch.setattr(owner, name, call)

    with monkeypatch.context() as patch:
        for owner, name in ((threading.Thread, "join"), (Session, "close"), (Session, "listen_can")):
            watched(owner, name)
        yield seen


@pytest.fixture
def window(qtbot, demo_ecu, project):
    window = open_window(qtbot, project)  # the demo's plots: DAQ runs, and the CAN monitor on the XCP bus
    qtbot.waitUntil(lambda: window.hub.can_monitor is not None and window.plots[0].samples_shown() > 0,
                    timeout=WAIT_MS)
    yield window
    window.close()


def test_disconnect_closes_in_a_worker_and_connect_waits_for_the_ecu_to_be_let_go_of(window, qtbot, monkeypatch):
    session = window.controller.session
    with waits_on_the_gui_thread(monkeypatch) as waits:
        window.disconnect_action.trigger()
        assert waits == []
        # disconnected at once, Connect only once the session has let go of the ECU
        assert window.controller.session is None and not window.disconnect_action.isEnabled()
        assert not window.connect_action.isEnabled() and window.status.link.text() == "○ disconnecting …"
        with qtbot.waitSignal(window.controller.released, timeout=WAIT_MS):
            window.disconnect_action.trigger()  # nothing to close twice
    assert waits == [] and session.closed
    assert window.connect_action.isEnabled() and window.status.link.text() == "○ not connected"


def test_connecting_starts_listening_to_can2_in_a_worker(window, qtbot, monkeypatch):
    window.controller.close()
    qtbot.waitUntil(window.connect_action.isEnabled, timeout=WAIT_MS)
    with waits_on_the_gui_thread(monkeypatch) as waits:
        with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
            window.connect_action.trigger()
        qtbot.waitUntil(lambda: window.hub.can_monitor is not None, timeout=WAIT_MS)  # CAN2 listened to again
    assert waits == []


def test_closing_the_window_lets_go_of_the_ecu_while_it_paints(window, qtbot, monkeypatch):
    session = window.controller.session
    ticks = []
    heartbeat = QTimer(window)
    heartbeat.timeout.connect(lambda: ticks.append(1))
    heartbeat.start(0)
    with waits_on_the_gui_thread(monkeypatch) as waits:
        window.close()
    heartbeat.stop()
    assert waits == [] and ticks  # the event loop ran while the ECU was let go of
    assert session.closed and not window.isVisible() and not window.controller.closing


def test_a_flash_starts_without_waiting_for_daq_to_stop_on_the_gui_thread(window, qtbot, monkeypatch):
    dialog = window.open_flash_dialog()
    qtbot.waitUntil(lambda: dialog.plan is not None, timeout=WAIT_MS)
    with waits_on_the_gui_thread(monkeypatch) as waits:
        with qtbot.waitSignal(dialog.flashed, timeout=FLASH_MS):
            dialog.start()  # the flash waits in its worker for DAQ to stop (it refuses an ECU whose DAQ runs)
    assert waits == []
    qtbot.waitUntil(lambda: window.hub.acquisition is not None and window.hub.acquisition.state.running,
                    timeout=WAIT_MS)
    dialog.close_button.click()
