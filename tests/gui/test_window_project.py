"""The window and its project file: what is open is saved, and a saved project opens the same way."""

from __future__ import annotations

import struct

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


def _project_b(tmp_path, connection):
    """Another project on the same (simulated) ECU: its A2L the demo's with xsSWITCH_TANK_THR limited to 50 bar
    (800 in the demo's), one editor and one plot of its own."""
    from workbench import demo
    from workbench.gui.project import demo_project, save_project

    text = demo.a2l().read_text(encoding="utf-8")
    start = text.index("/* Name                   */ xsSWITCH_TANK_THR")
    limit = text.index("/* Upper Limit            */ 800", start)
    a2l = tmp_path / "b" / "FLCU_B.a2l"
    a2l.parent.mkdir()
    a2l.write_text(text[:limit] + "/* Upper Limit            */ 50" + text[limit + 33:], encoding="utf-8")
    project = demo_project()
    project.a2l, project.connection = a2l, connection
    project.editors, project.plots, project.tables = ["xsSWITCH_TANK_THR"], [PlotSpec("B", ["xsPidP"])], []
    save_project(project, tmp_path / "b" / "b.toml")
    return tmp_path / "b" / "b.toml"


def test_opening_another_project_leaves_nothing_bound_to_the_a2l_before(qtbot, tmp_path, demo_ecu, project):
    """Its editors, plots, fixes and comparison go with the project before; the new one's open on its own A2L and
    write into the ECU through it once connected."""
    from shiboken6 import isValid

    from gui_helpers import WAIT_MS, open_window
    from workbench.gui.a2l_info import calibration_info

    window = open_window(qtbot, project)
    try:
        old_editors, old_plots = list(window.editors.values()), list(window.plots)
        assert window.editors["xsSWITCH_TANK_THR"].info.limits == (0, 800)
        with qtbot.waitSignal(window.parameter_sets.compared, timeout=WAIT_MS):
            window.parameter_sets.compare_pages()
        qtbot.waitUntil(lambda: window.fix_panel.model.rowCount() > 0, timeout=WAIT_MS)
        with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
            window.open_project_file(_project_b(tmp_path, project.connection))
        assert window.controller.session is None and window.windowTitle().startswith("b — offline")
        editor = window.editors["xsSWITCH_TANK_THR"]
        assert list(window.editors) == ["xsSWITCH_TANK_THR"] and editor not in old_editors
        assert editor.info == calibration_info(window.workspace.model, "xsSWITCH_TANK_THR")
        assert editor.info.limits == (0, 50)
        assert [p.title for p in window.plots] == ["B"] and not set(window.plots) & set(old_plots)
        assert window.numeric.signals == [] and window.fix_panel.model.rowCount() == 0
        assert window.compare.diff is None and window.compare.model.rowCount() == 0
        assert window.parameter_sets.last is None and not window.compare.refresh_button.isEnabled()
        qtbot.waitUntil(lambda: not any(isValid(w) for w in (*old_editors, *old_plots)), timeout=WAIT_MS)

        with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
            window.connect_ecu()
        assert window.controller.session.doc is window.workspace.doc
        qtbot.waitUntil(lambda: window.fix_panel.model.rowCount() > 0, timeout=WAIT_MS)  # the new session's fixes
        with qtbot.waitSignal(editor.refused, timeout=WAIT_MS):
            editor.write(100.0)  # within the A2L before, beyond this one's
        with qtbot.waitSignal(window.controller.written, timeout=WAIT_MS):
            editor.write(30.0)
        assert struct.unpack("<f", demo_ecu.ecu.read(0x400000E0, 4)) == (30.0,)  # the ECU's RAM, at the A2L's address
    finally:
        window.close()


def test_a_connection_under_way_when_another_project_opens_is_not_taken(qtbot, tmp_path, demo_ecu, project):
    window = offline_window(qtbot, project)
    try:
        over = []
        window.connect_ecu().finished.connect(lambda: over.append(True))  # after its result was taken or not
        with qtbot.waitSignal(window.loaded, timeout=15_000):
            window.open_project_file(_project_b(tmp_path, project.connection))
        qtbot.waitUntil(lambda: bool(over), timeout=15_000)
        assert window.controller.session is None  # it held the A2L before: closed, not connected
        qtbot.waitUntil(window.connect_action.isEnabled, timeout=15_000)  # and Connect offered for the new one
        assert window.status.link.text() == "○ not connected"
    finally:
        window.close()


def test_a_connection_that_fails_after_another_project_opened_says_nothing(qtbot, tmp_path, project):
    """Its failure concerns the project before: no dialog about it over the new one (a failure of the project
    open now still is one)."""
    from dataclasses import replace

    from workbench.gui.worker import Task

    window = offline_window(qtbot, replace(project, connection=replace(project.connection, interface="nosuch")))
    try:
        first = window.connect_ecu()  # it may fail before a waitSignal on its finished would be connected
        qtbot.waitUntil(lambda: first not in Task._running and bool(window.errors), timeout=15_000)
        assert [box.text() for box in window.errors][-1].startswith("unknown python-can interface 'nosuch'")
        assert window.status.link.text() == "○ not connected" and window.connect_action.isEnabled()
        shown = len(window.errors)

        attempt = window.connect_ecu()  # fails in the pool, said after the switch (or before: it may fail at once)
        with qtbot.waitSignal(window.loaded, timeout=15_000):
            window.open_project_file(_project_b(tmp_path, project.connection))
        qtbot.waitUntil(lambda: attempt not in Task._running, timeout=15_000)  # over (its finished may be past)
        assert len(window.errors) == shown and window.controller.session is None
        assert window.status.link.text() == "○ not connected" and window.connect_action.isEnabled()
    finally:
        window.close()


def test_the_project_before_is_freed_when_another_opens(qtbot, tmp_path):
    """Its A2L model (tens of MB for a real ECU's) goes: every task the window had run kept what its callbacks referred
    to (an editor reading the s19, and through it the model), and the compare view kept the model for its decimals."""
    import gc
    import weakref

    from gui_helpers import WAIT_MS
    from PySide6.QtCore import QCoreApplication, QEvent, QThreadPool

    from workbench.gui.project import demo_project

    window = offline_window(qtbot)  # the demo's editors read their values from its s19, each in a task
    try:
        qtbot.waitUntil(lambda: window.editors["xsSWITCH_TANK_THR"].value is not None, timeout=WAIT_MS)
        model = weakref.ref(window.workspace.model)
        with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
            window.open_project_file(_project_b(tmp_path, demo_project().connection))
        QThreadPool.globalInstance().waitForDone(WAIT_MS)
        qtbot.wait(50)  # the tasks' ends delivered
        QCoreApplication.sendPostedEvents(None, QEvent.DeferredDelete)  # the closed editors
        gc.collect()
        assert model() is None
    finally:
        window.close()
