"""The window's keys, pressed as a user presses them (to the widget that has the focus) against the demo
ECU: Ctrl+Z / Ctrl+Shift+Z / Ctrl+Y undo and redo a calibration editor's writes (Edit menu, enabled as the
editor's own buttons), function keys connect, disconnect, flash and record, Ctrl+Shift+W/R switch the
page, Ctrl+Shift+P opens a plot; offline, Ctrl+F reaches the variable browser, Down/Up move between its
search and results, Enter opens a row, Ctrl+Q closes the window. One connected window for the module."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import WAIT_MS, ecu_and_window_fixtures, focus, offline_window, press
from PySide6.QtCore import Qt
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QApplication, QFileDialog

CTRL, SHIFT = Qt.ControlModifier, Qt.ShiftModifier


ecu, window = ecu_and_window_fixtures("gui-keys")


def test_ctrl_z_in_a_maps_table_undoes_its_write_and_ctrl_shift_z_and_ctrl_y_redo_it(window, qtbot):
    session = window.controller.session
    before = np.asarray(session.read("xvPRV_DC_FF"), dtype=float)
    editor = window.open_editor("xvPRV_DC_FF")
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    assert not window.undo_action.isEnabled() and not window.redo_action.isEnabled()
    view = editor.field.table
    focus(view)
    view.setCurrentIndex(view.model().index(1, 1))
    for key in "42":
        press(key)  # the first key opens the cell's field
    press(Qt.Key_Return)
    qtbot.waitUntil(editor.undo_stack.canUndo, timeout=WAIT_MS)
    after = np.asarray(session.read("xvPRV_DC_FF"), dtype=float)
    assert not np.array_equal(after, before) and 42.0 in after
    assert window.undo_action.isEnabled() and editor.undo_button.isEnabled()
    assert not window.redo_action.isEnabled() and not editor.redo_button.isEnabled()
    assert window.undo_action.text() == "Undo xvPRV_DC_FF: 1 of 30 values"

    def holds(expected):
        qtbot.waitUntil(lambda: np.array_equal(np.asarray(session.read("xvPRV_DC_FF"), dtype=float), expected),
                        timeout=WAIT_MS)

    qtbot.waitUntil(lambda: QApplication.focusWidget() is view, timeout=WAIT_MS)
    press(Qt.Key_Z, CTRL)
    holds(before)
    qtbot.waitUntil(editor.redo_button.isEnabled, timeout=WAIT_MS)
    assert window.redo_action.isEnabled() and not window.undo_action.isEnabled()
    press(Qt.Key_Z, CTRL | SHIFT)
    holds(after)
    qtbot.waitUntil(editor.undo_stack.canUndo, timeout=WAIT_MS)
    press(Qt.Key_Z, CTRL)
    holds(before)
    qtbot.waitUntil(editor.undo_stack.canRedo, timeout=WAIT_MS)
    press(Qt.Key_Y, CTRL)
    holds(after)
    qtbot.waitUntil(editor.undo_stack.canUndo, timeout=WAIT_MS)

    other = window.open_editor("xsSWITCH_TANK_THR")  # the Edit menu follows the editor shown
    assert not window.undo_action.isEnabled()
    window.editor_tabs.setCurrentWidget(editor)
    assert window.undo_action.isEnabled()
    editor.undo_stack.undo()
    holds(before)
    assert not window.errors and other is not None


def test_ctrl_z_in_a_scalars_field_undoes_the_write_and_while_typing_the_typing(window, qtbot):
    session = window.controller.session
    editor = window.open_editor("xsSWITCH_TANK_THR")
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    shown = session.read("xsSWITCH_TANK_THR")
    field = editor.field.input
    focus(field)
    field.selectAll()
    for key in "31":
        press(key)
    press(Qt.Key_Return)
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(31.0), timeout=WAIT_MS)
    qtbot.waitUntil(editor.undo_stack.canUndo, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: field.text() == "31.00", timeout=WAIT_MS)  # read back
    press(Qt.Key_3)
    press(Qt.Key_Z, CTRL)  # typed: the field's own undo, nothing written
    assert field.text() == field.shown == "31.00" and session.read("xsSWITCH_TANK_THR") == pytest.approx(31.0)
    press(Qt.Key_Escape)
    press(Qt.Key_Z, CTRL)
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(shown), timeout=WAIT_MS)
    qtbot.waitUntil(lambda: field.text() == field.shown and float(field.text()) == pytest.approx(shown),
                    timeout=WAIT_MS)


def test_ctrl_shift_r_and_w_switch_to_the_reference_page_and_back(window, qtbot):
    session = window.controller.session
    working, reference = session.page_numbers()
    focus(window.browser.table)
    press(Qt.Key_R, CTRL | SHIFT)
    qtbot.waitUntil(lambda: session.page().ecu_page == reference, timeout=WAIT_MS)
    qtbot.waitUntil(window.reference_action.isChecked, timeout=WAIT_MS)
    press(Qt.Key_W, CTRL | SHIFT)
    qtbot.waitUntil(lambda: session.page().ecu_page == working, timeout=WAIT_MS)


def test_ctrl_shift_p_opens_a_plot_and_f12_records_what_it_measures_until_f12_again(window, qtbot, tmp_path,
                                                                                      monkeypatch):
    focus(window.browser.table)
    press(Qt.Key_P, CTRL | SHIFT)
    assert len(window.plots) == 1
    plot = window.plots[0]
    plot.add_signals(["zsRailPressure"])
    acquisition = window.hub.acquisition
    qtbot.waitUntil(lambda: "zsRailPressure" in acquisition.state.signals, timeout=WAIT_MS)
    path = tmp_path / "keys.mf4"  # typed "keys": the dialog's filter gives the suffix, as a native dialog adds it
    monkeypatch.setattr(QFileDialog, "getSaveFileName", lambda *args, **kwargs: (str(tmp_path / "keys"), ""))
    with qtbot.waitSignal(acquisition.recording_started, timeout=WAIT_MS):
        press(Qt.Key_F12)
    assert window.record_action.isChecked()
    qtbot.waitUntil(lambda: acquisition.state.recorded_s > 0.2, timeout=WAIT_MS)
    with qtbot.waitSignal(acquisition.recording_stopped, timeout=WAIT_MS):
        press(Qt.Key_F12)
    assert not window.record_action.isChecked() and window.last_recording.samples > 0 and path.exists()
    window._remove_plot(plot)


def test_ctrl_f9_opens_the_flash_dialog_which_flashes_nothing_by_itself(window, qtbot):
    focus(window.browser.table)
    press(Qt.Key_F9, CTRL)
    dialog = window.flash_dialog
    assert dialog is not None and dialog.isVisible() and dialog.task is None
    dialog.reject()
    assert window.controller.is_connected


def test_shift_f9_disconnects_and_f9_connects_again(window, qtbot):
    focus(window.browser.table)
    with qtbot.waitSignal(window.controller.released, timeout=WAIT_MS):  # F9 waits for the ECU to be let go of
        press(Qt.Key_F9, SHIFT)
    assert not window.disconnect_action.isEnabled()
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        press(Qt.Key_F9)
    assert window.controller.is_connected


def test_the_keys_are_in_the_menus_and_tooltips_and_none_is_twice_or_a_standard_key(window):
    menus = {action.text().replace("&", ""): action.menu() for action in window.menuBar().actions()}
    assert list(menus)[:3] == ["File", "Edit", "ECU"]
    assert [a.text().split()[0] for a in menus["Edit"].actions() if a.text()] == ["Undo", "Redo", "Find"]
    shortcuts = {}
    for action in window.findChildren(QAction):
        for key in action.shortcuts():
            text = key.toString()
            assert text not in shortcuts, f"{text}: {shortcuts.get(text)} and {action.text()}"
            shortcuts[text] = action.text()
        if action.shortcuts() and action.text() not in ("Open…", "Save", "Save as…"):
            assert action.toolTip().endswith(f"({action.shortcut().toString(QKeySequence.NativeText)})")
    assert {key: shortcuts.get(key) for key in ("F9", "Shift+F9", "Ctrl+F9", "F12", "Ctrl+Shift+W", "Ctrl+Shift+R",
                                                "Ctrl+Shift+P", "Ctrl+F", "Ctrl+Z", "Ctrl+Shift+Z", "Ctrl+Y",
                                                "Ctrl+Q")} == {
        "F9": "Connect", "Shift+F9": "Disconnect", "Ctrl+F9": "Flash…", "F12": "Record",
        "Ctrl+Shift+W": "Working page", "Ctrl+Shift+R": "Reference page", "Ctrl+Shift+P": "New plot",
        "Ctrl+F": "Find variable…", "Ctrl+Z": window.undo_action.text(), "Ctrl+Shift+Z": window.redo_action.text(),
        "Ctrl+Y": window.redo_action.text(), "Ctrl+Q": "Quit"}
    assert window.copy_action.shortcut().isEmpty()  # overwrites every change since start-up: no key for it
    # keys that mean here what Qt means by them (Ctrl+Q is Qt's Quit on X11, no key offscreen)
    standard_meaning = ("Open…", "Save", "Save as…", "Find variable…", "Quit", window.undo_action.text(),
                        window.redo_action.text())
    ours = {key for key, text in shortcuts.items() if text not in standard_meaning}
    for standard in QKeySequence.StandardKey:
        taken = ours & {key.toString() for key in QKeySequence.keyBindings(standard)}
        assert not taken, f"{taken} is Qt's {standard.name}"


def test_ctrl_f_down_up_and_enter_reach_and_open_a_variable_and_ctrl_q_closes_the_window(qtbot):
    window = offline_window(qtbot)
    browser = window.browser
    focus(window.editor_tabs)
    press(Qt.Key_F, CTRL)
    assert QApplication.focusWidget() is browser.search
    for key in "xvPRV_DC_F":
        press(key)
    assert browser.model.rowCount() >= 1
    press(Qt.Key_Down)
    assert QApplication.focusWidget() is browser.table and browser.table.currentIndex().row() == 0
    assert browser.table.selectionModel().isRowSelected(0)
    press(Qt.Key_Up)  # from the first row back to the search
    assert QApplication.focusWidget() is browser.search
    press(Qt.Key_Up)  # to the last row
    assert browser.table.currentIndex().row() == browser.model.rowCount() - 1
    name = browser.table.currentIndex().data()
    press(Qt.Key_Return)
    assert name in window.editors and window.editor_tabs.currentWidget() is window.editors[name]
    press(Qt.Key_Q, CTRL)
    qtbot.waitUntil(lambda: not window.isVisible(), timeout=WAIT_MS)
