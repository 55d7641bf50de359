"""Cache synchronisation after connecting (thesis figure 39): the ECU's calibrations against the
project's s19, the differing objects listed in the A2L's format, nothing written unless the user
chooses download or upload."""

from __future__ import annotations

import hashlib

import pytest
from gui_helpers import WAIT_MS, open_window
from PySide6.QtCore import Qt

from workbench.a2l.display_format import format_decimals
from workbench.cli.render import value_text
from workbench.gui.widgets.sync_dialog import SyncChoice


def _rows(dialog) -> dict[str, tuple[str, str]]:
    table = dialog.table
    return {table.item(r, 0).text(): (table.item(r, 1).text(), table.item(r, 2).text())
            for r in range(table.rowCount())}


def _next_dialog(qtbot, window, previous=None):
    qtbot.waitUntil(lambda: window.sync_dialog not in (None, previous) and window.sync_dialog.isVisible(),
                    timeout=WAIT_MS)
    return window.sync_dialog


def test_a_changed_ecu_is_kept_by_enter_and_escape_and_downloaded_only_when_chosen(qtbot, demo_ecu, project):
    s19 = hashlib.sha256(project.s19.read_bytes()).hexdigest()
    window = open_window(qtbot, project)
    qtbot.waitUntil(lambda: window.sync_report is not None, timeout=WAIT_MS)
    assert window.sync_report.equal and window.sync_dialog is None  # an unchanged ECU: no question
    session = window.controller.session
    session.write("xsSWITCH_TANK_THR", 25.7)  # the user's tuning, then a reconnect
    with qtbot.waitSignal(window.controller.disconnected, timeout=WAIT_MS):
        window.controller.close()
    window.sync_report = None
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    dialog = _next_dialog(qtbot, window)
    model = window.workspace.model
    obj = model.object("xsSWITCH_TANK_THR")
    as_cal_get = [value_text(v, model.unit_of(obj), format_decimals(model.format_of(obj))) for v in (25.7, 20.0)]
    assert _rows(dialog) == {"xsSWITCH_TANK_THR": ("25.70 bar", "20.00 bar")} and list(_rows(dialog)[
        "xsSWITCH_TANK_THR"]) == as_cal_get
    assert dialog.table.isVisible() and not dialog.expert.isVisible()  # one object: listed at once
    assert dialog.choice is SyncChoice.KEEP
    qtbot.keyClick(dialog, Qt.Key_Return)  # the default writes nothing
    assert not dialog.isVisible() and dialog.result() == dialog.DialogCode.Accepted
    assert "kept the ECU's values, nothing written" in window.statusBar().currentMessage()
    session = window.controller.session
    window.check_cache()
    dialog = _next_dialog(qtbot, window, dialog)
    qtbot.keyClick(dialog, Qt.Key_Escape)
    assert not dialog.isVisible()
    assert session.read("xsSWITCH_TANK_THR") == pytest.approx(25.7)
    assert hashlib.sha256(project.s19.read_bytes()).hexdigest() == s19 and window.project.s19 == project.s19
    window.check_cache()
    dialog = _next_dialog(qtbot, window, dialog)
    dialog.download.click()
    assert dialog.buttons.button(dialog.buttons.StandardButton.Ok).text() == "Download into the ECU"
    dialog.accept()
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0), timeout=WAIT_MS)
    window.close()
    assert not window.errors
