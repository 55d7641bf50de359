"""The window and its project file: what is open is saved, and a saved project opens the same way."""

from __future__ import annotations

from PySide6.QtCore import QPointF, Qt
from PySide6.QtGui import QDropEvent

from workbench.gui.mime import signals_mime
from workbench.gui.project import PlotSpec, demo_project, load_project
from workbench.gui.widgets.main_window import MainWindow


def test_the_open_windows_and_signals_are_saved_and_restored(qtbot, tmp_path):
    window = MainWindow(demo_project())
    qtbot.addWidget(window)
    with qtbot.waitSignal(window.loaded, timeout=15_000):
        window.load()
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
    again = MainWindow(project)
    qtbot.addWidget(again)
    with qtbot.waitSignal(again.loaded, timeout=15_000):
        again.load()
    assert [p.signals for p in again.plots] == [p.signals for p in project.plots]
    assert list(again.editors) == project.editors and again.numeric.signals == project.tables[0]
    assert again.windowTitle().startswith("bench — offline")
    again.close()
