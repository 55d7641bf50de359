"""The window and its project file: what is open is saved, and a saved project opens the same way."""

from __future__ import annotations

from gui_helpers import offline_window
from PySide6.QtCore import QPointF, Qt
from PySide6.QtGui import QDropEvent
from PySide6.QtWidgets import QToolButton

from workbench.gui.mime import signals_mime
from workbench.gui.project import PlotSpec, load_project
from workbench.gui.widgets.main_window import MainWindow


def test_the_open_windows_and_signals_are_saved_and_restored(qtbot, tmp_path):
    window = offline_window(qtbot)
    window.fix_panel.table.horizontalHeader().resizeSection(0, 123)  # as a user drags the column's edge
    window.add_plot(PlotSpec("Mine", ["xsPidP"], 30.0)).add_signals(["FLCU_TO_PCM_002.RailPressure"])
    window.numeric.add_signals(["xsTankPressDiff"])
    mime = signals_mime(["xsEMPTY_TANK_THR", "zsRailPressure"])  # kept: the event does not own it
    drop = QDropEvent(QPointF(5, 5), Qt.CopyAction, mime, Qt.LeftButton, Qt.NoModifier)
    window.editor_tabs.dropEvent(drop)  # a calibration dropped on the editors opens one; a signal does not
    assert list(window.editors) == ["xsSWITCH_TANK_THR", "xvPRV_DC_FF", "xsEMPTY_TANK_THR"]
    window.save_to(tmp_path / "bench.toml")
    window.close()

    project = load_project(tmp_path / "bench.toml")
    assert project.plots[-1] == PlotSpec("Mine", ["xsPidP", "FLCU_TO_PCM_002.RailPressure"], 30.0)
    assert project.tables[0][-1] == "xsTankPressDiff" and project.editors[-1] == "xsEMPTY_TANK_THR"
    assert project.columns["fixes"][0] == 123 and len(project.columns["fixes"]) == 5
    assert "plot 3" not in project.columns  # widths nobody gave keep following the window
    again = MainWindow(project)
    qtbot.addWidget(again)
    again.show()
    with qtbot.waitSignal(again.loaded, timeout=15_000):
        again.load()
    again.resize(again.width() - 50, again.height())  # a smaller window keeps the user's widths
    qtbot.waitUntil(lambda: again.fix_panel.table.columnWidth(0) == 123, timeout=5_000)
    assert [p.signals for p in again.plots] == [p.signals for p in project.plots]
    assert list(again.editors) == project.editors and again.numeric.signals == project.tables[0]
    assert again.windowTitle().startswith("bench — offline")
    again.close()


def test_the_window_fits_the_screen_and_stays_within_it_after_edits_and_new_windows(qtbot):
    window = offline_window(qtbot)
    screen = window.screen().availableGeometry()
    assert window.width() <= screen.width() and window.height() <= screen.height()
    assert window.minimumSizeHint().width() <= screen.width()
    editor = window.editors["xsSWITCH_TANK_THR"]
    undo = next(b for b in editor.findChildren(QToolButton) if b.text() == "Undo")
    undo_at, title_at = undo.geometry(), editor.title.geometry()
    editor.modified_badge.show()  # the "modified" badge appears: nothing beside it moves
    qtbot.wait(20)
    assert (undo.geometry(), editor.title.geometry()) == (undo_at, title_at)
    for name in ("xsEMPTY_TANK_THR", "zvRailPConv", "cfRAILPSDIAGNOSTICSTATUS_VALUE"):
        window.open_editor(name)
    window.add_plot(PlotSpec("More", ["xsPidP", "FLCU_TO_PCM_001.FuelLevelLow", "csPCM_TO_FLCU_002_TargetRailPressure"]))
    window.status.link.setText("● XCP on CAN (virtual a-very-long-channel-name-that-a-user-gave-it, ids 0x7F0/0x7F1)")
    qtbot.wait(50)
    assert window.width() <= screen.width() and window.frameGeometry().right() <= screen.right() + 1
    assert window.status.link.toolTip().startswith("● XCP on CAN (virtual a-very-long")
