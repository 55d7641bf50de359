"""Cache synchronisation after connecting (thesis figure 39): the ECU's calibrations against the
project's s19, the differing objects listed, download or upload."""

from __future__ import annotations

import pytest
from gui_helpers import WAIT_MS, open_window

from workbench.gui.widgets.sync_dialog import SyncChoice


def test_an_unchanged_ecu_is_confirmed_without_a_question_and_a_changed_one_is_synchronised(qtbot, demo_ecu, project):
    window = open_window(qtbot, project)
    qtbot.waitUntil(lambda: window.sync_report is not None, timeout=WAIT_MS)
    assert window.sync_report.equal and window.sync_dialog is None
    session = window.controller.session
    session.write("xsSWITCH_TANK_THR", 31.0)
    with qtbot.waitSignal(window.controller.disconnected, timeout=WAIT_MS):
        window.controller.close()
    window.sync_report = None
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    qtbot.waitUntil(lambda: window.sync_dialog is not None and window.sync_dialog.isVisible(), timeout=WAIT_MS)
    dialog = window.sync_dialog
    rows = {dialog.table.item(r, 0).text(): (dialog.table.item(r, 1).text(), dialog.table.item(r, 2).text())
            for r in range(dialog.table.rowCount())}
    assert rows == {"xsSWITCH_TANK_THR": ("31 bar", "20 bar")}
    assert dialog.choice is SyncChoice.DOWNLOAD
    dialog.accept()
    session = window.controller.session
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0), timeout=WAIT_MS)
    window.close()
    assert not window.errors
