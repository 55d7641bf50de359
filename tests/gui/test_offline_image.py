"""Offline calibration in the window: before any ECU is connected the editors edit the project's s19 in memory
(checked as online), the window says it is modified, File > Save image writes it (only changed records); a
connection afterwards compares the ECU with the image as edited and offers to download the changes."""

from __future__ import annotations

import shutil
from dataclasses import replace

import numpy as np
import pytest
from gui_helpers import WAIT_MS, offline_window

from workbench import ImageCalibration, demo
from workbench.gui.project import demo_project
from workbench.gui.widgets.sync_dialog import SyncChoice


def _editor(window, qtbot, name: str):
    editor = window.open_editor(name)
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    return editor


def _copy_project(tmp_path, project=None):
    project = project or demo_project()
    project.s19 = tmp_path / "app.s19"
    shutil.copy(demo.s19(), project.s19)
    return project


def test_edits_go_into_the_image_and_save_image_writes_them(qtbot, tmp_path):
    window = offline_window(qtbot, _copy_project(tmp_path))
    scalar = _editor(window, qtbot, "xsSWITCH_TANK_THR")
    assert scalar.field.input.isEnabled() and scalar.status.text() == (
        "offline: the values of app.s19; an edit changes the image (File ▸ Save image)")
    assert "modified" not in window.windowTitle() and window.save_image_action.isEnabled()
    scalar.edit(22.5)
    qtbot.waitUntil(lambda: scalar.value.value == 22.5, timeout=WAIT_MS)
    assert window.windowTitle().endswith("— app.s19 modified — workbench") and scalar.modified_badge.isVisible()
    scalar.edit(9999.0)  # refused as online, in the editor's status line
    qtbot.waitUntil(lambda: scalar.status.text().startswith("not written:"), timeout=WAIT_MS)
    assert "800.00" in scalar.status.text() and scalar.value.value == 22.5
    scalar.undo_stack.undo()
    qtbot.waitUntil(lambda: scalar.value.value == 20.0, timeout=WAIT_MS)
    assert "modified" not in window.windowTitle()
    scalar.undo_stack.redo()
    qtbot.waitUntil(lambda: scalar.value.value == 22.5, timeout=WAIT_MS)
    table = _editor(window, qtbot, "xvPRV_DC_FF")
    cells = table.value.value.copy()
    cells[0][0] = 1.0
    table.edit(cells)
    qtbot.waitUntil(lambda: window.workspace.file_values.changed() == ["xsSWITCH_TANK_THR", "xvPRV_DC_FF"],
                    timeout=WAIT_MS)
    with qtbot.waitSignal(window.offline_image.saved, timeout=WAIT_MS):
        window.save_image_action.trigger()  # in place: the project's own copy
    saved = ImageCalibration.open(tmp_path / "app.s19")
    assert saved.read("xsSWITCH_TANK_THR") == 22.5 and saved.read("xvPRV_DC_FF")[0][0] == 1.0
    assert "modified" not in window.windowTitle() and not scalar.modified_badge.isVisible()
    assert not window.errors


def test_after_connecting_the_offline_changes_are_offered_for_download(qtbot, demo_ecu, project, tmp_path,
                                                                       monkeypatch):
    from PySide6.QtWidgets import QMessageBox

    asked = []
    answers = iter([QMessageBox.Cancel, QMessageBox.Discard])
    monkeypatch.setattr(QMessageBox, "question", lambda _parent, _title, text, *_: asked.append(text) or next(answers))
    window = offline_window(qtbot, _copy_project(tmp_path, project))
    scalar = _editor(window, qtbot, "xsSWITCH_TANK_THR")
    scalar.edit(23.5)
    qtbot.waitUntil(lambda: window.offline_image.modified, timeout=WAIT_MS)
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    qtbot.waitUntil(lambda: window.sync_dialog is not None and window.sync_dialog.isVisible(), timeout=WAIT_MS)
    dialog = window.sync_dialog
    rows = {dialog.table.item(r, 0).text(): (dialog.table.item(r, 1).text(), dialog.table.item(r, 2).text())
            for r in range(dialog.table.rowCount())}
    assert rows == {"xsSWITCH_TANK_THR": ("20.00 bar", "23.50 bar")}  # the ECU's, the image's (not saved)
    dialog.download.click()
    assert dialog.choice is SyncChoice.DOWNLOAD
    dialog.accept()
    session = window.controller.session
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(23.5), timeout=WAIT_MS)
    qtbot.waitUntil(lambda: scalar.value_source == "" and scalar.value.value == pytest.approx(23.5), timeout=WAIT_MS)
    assert (tmp_path / "app.s19").read_bytes() == demo.s19().read_bytes()  # nothing saved without asking
    window.close()  # unsaved offline edits: asked first; Cancel keeps the window open
    assert window.isVisible() and asked == [("app.s19 holds calibrations edited offline that are not saved: "
                                             "xsSWITCH_TANK_THR.\nSave the image?")]
    window.close()  # Discard closes it
    assert not window.isVisible() and len(asked) == 2 and not window.errors


def test_a_parameter_set_applies_to_the_image_offline(qtbot, tmp_path):
    from PySide6.QtWidgets import QMessageBox

    from workbench.calib.dataset import save_dataset

    window = offline_window(qtbot, _copy_project(tmp_path))
    scalar = _editor(window, qtbot, "xsSWITCH_TANK_THR")
    dataset = ImageCalibration.open(demo.s19()).dataset(["xsSWITCH_TANK_THR", "xsPRV_KP"])
    dataset["xsSWITCH_TANK_THR"] = replace(dataset["xsSWITCH_TANK_THR"], value=31.0)
    save_dataset(dataset, tmp_path / "tuned.dcm")
    sets = window.parameter_sets
    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        sets.open(tmp_path / "tuned.dcm")
    assert window.compare.rows_shown() == ["xsSWITCH_TANK_THR"] and window.compare.apply_button.isVisible()
    sets.ask_apply()
    qtbot.waitUntil(lambda: sets.confirm is not None and sets.confirm.isVisible(), timeout=WAIT_MS)
    assert sets.confirm.text() == "Write 1 changed object(s) of tuned.dcm into app.s19?"
    with qtbot.waitSignal(sets.applied, timeout=WAIT_MS):
        sets.confirm.button(QMessageBox.Ok).click()
    qtbot.waitUntil(lambda: scalar.value.value == 31.0, timeout=WAIT_MS)
    assert window.windowTitle().endswith("— app.s19 modified — workbench")
    assert (tmp_path / "app.s19").read_bytes() == demo.s19().read_bytes()
    window.workspace.file_values.image().write("xsSWITCH_TANK_THR", 20.0)  # back: the window closes unasked


def test_open_image_takes_another_s19_for_the_editors(qtbot, tmp_path):
    project = demo_project()
    project.s19 = None
    window = offline_window(qtbot, project)
    scalar = window.open_editor("xsSWITCH_TANK_THR")
    assert scalar.value is None and not window.save_image_action.isEnabled() and window.open_image_action.isEnabled()
    tuned = ImageCalibration.open(demo.s19())
    tuned.write("xsSWITCH_TANK_THR", 27.0)
    tuned.save(tmp_path / "tuned.hex")
    window.offline_image.open(tmp_path / "tuned.hex")
    qtbot.waitUntil(lambda: scalar.value is not None, timeout=WAIT_MS)
    assert scalar.value.value == 27.0 and scalar.value_source == "tuned.hex" and scalar.field.input.isEnabled()
    assert window.project.s19 == tmp_path / "tuned.hex" and window.save_image_action.isEnabled()


def test_the_fix_panel_edits_the_image_offline(qtbot, tmp_path):
    from PySide6.QtCore import Qt

    from workbench.gui.models.fixes import COLUMNS

    window = offline_window(qtbot, _copy_project(tmp_path))
    panel = window.fix_panel
    qtbot.waitUntil(lambda: len(panel.model.rows) > 10 and not panel.model.stale, timeout=WAIT_MS)
    assert panel.model.read_only == "" and panel.offline_mode()
    row = [fix.pair.stem for fix in panel.model.rows].index("zfRAILPRESSURE")
    model = panel.model
    model.setData(model.index(row, COLUMNS.index("override")), "30", Qt.EditRole)  # off: only _VALUE
    qtbot.waitUntil(lambda: model.rows[row].override == 30.0, timeout=WAIT_MS)
    model.setData(model.index(row, COLUMNS.index("on")), Qt.Checked.value, Qt.CheckStateRole)
    qtbot.waitUntil(lambda: model.rows[row].active, timeout=WAIT_MS)
    assert window.workspace.file_values.changed() == ["zfRAILPRESSURE_VALUE", "zfRAILPRESSURE_EN"]
    assert window.windowTitle().endswith("— app.s19 modified — workbench")
    model.setData(model.index(row, COLUMNS.index("on")), Qt.Unchecked.value, Qt.CheckStateRole)  # release
    qtbot.waitUntil(lambda: not model.rows[row].active, timeout=WAIT_MS)
    window.workspace.file_values.image().write("zfRAILPRESSURE_VALUE", 0.0)  # back: the window closes unasked
    assert not window.errors


def test_an_axis_edited_offline_shows_in_the_map_that_shares_it(qtbot, tmp_path):
    """xvPRV_DC_FF's X axis is the AXIS_PTS xaPRV_FF_TARGET (COM_AXIS): a write of either refreshes the other's editor
    (the map showed its old breakpoints until reopened)."""
    window = offline_window(qtbot, _copy_project(tmp_path))
    table = _editor(window, qtbot, "xvPRV_DC_FF")
    axis = _editor(window, qtbot, "xaPRV_FF_TARGET")
    points = np.array(axis.value.value, dtype=np.float64)
    points[-1] -= 1.0  # the last breakpoint, still ascending
    axis.edit(points)
    qtbot.waitUntil(lambda: table.value.axes[0].values[-1] == points[-1], timeout=WAIT_MS)
    axis.undo_stack.undo()  # the map follows the undo too
    qtbot.waitUntil(lambda: table.value.axes[0].values[-1] == points[-1] + 1.0, timeout=WAIT_MS)
    assert not window.errors


def test_an_image_that_cannot_be_read_is_refused_and_the_project_keeps_its_image(qtbot, tmp_path):
    window = offline_window(qtbot, _copy_project(tmp_path))
    scalar = _editor(window, qtbot, "xsSWITCH_TANK_THR")
    bad = tmp_path / "bad.s19"
    bad.write_text("S1 this is no S-record\n")
    window.offline_image.open(bad)
    qtbot.waitUntil(lambda: len(window.errors) == 1, timeout=WAIT_MS)
    assert window.errors[0].text() == f"{bad}:1:3: ' ' where a hex digit belongs"  # where the record breaks
    assert window.errors[0].informativeText() == "bad.s19 not opened: the editors keep the values of app.s19"
    assert window.project.s19 == tmp_path / "app.s19" and window.workspace.file_values.path == tmp_path / "app.s19"
    assert scalar.value_source == "app.s19" and scalar.field.input.isEnabled()
