"""The window on A2L files other tools wrote (tests/corpus/a2l), no ECU: a file without IF_DATA XCP (a parser's test
file, one a2ltool wrote from C sources) and one whose /include names a file sent without it (XCPlite's A2ML) open
for offline work, and the window says what it cannot do with them."""

from __future__ import annotations

from pathlib import Path

from gui_helpers import WAIT_MS

from workbench.gui.project import Project

CORPUS = Path(__file__).parents[1] / "corpus" / "a2l"


def window_on(qtbot, a2l: Path):
    """A window on ``a2l`` alone, shown; its files read (``loaded``) or refused (an error dialog)."""
    from workbench.gui.widgets.main_window import MainWindow

    window = MainWindow(Project(a2l=a2l))
    qtbot.addWidget(window)
    window.show()
    loaded = []
    window.loaded.connect(lambda: loaded.append(True))
    window.load()
    qtbot.waitUntil(lambda: bool(loaded or window.errors), timeout=WAIT_MS)
    return window, bool(loaded)


def test_an_a2l_without_if_data_xcp_opens_offline_and_connect_says_why_not(qtbot):
    window, loaded = window_on(qtbot, CORPUS / "domohuhn-a2l" / "example-ecu.a2l")
    assert loaded, [box.text() for box in window.errors]
    assert not window.errors
    names = {row.name for row in window.browser.model.rows}
    assert {"MeasureKMH", "DataMap", "DataCurve", "Bitfield16"} <= names
    assert window.status.link.text() == "○ offline: the A2L has no IF_DATA XCP"
    assert "example-ecu.a2l:17:3" in window.status.link.toolTip()
    assert window.open_editor("DataMap") is not None and not window.errors

    assert window.connect_ecu() is None  # nothing tried: no bus opened, no worker
    (box,) = window.errors
    assert box.text().startswith("cannot connect: ") and "example-ecu.a2l:17:3: the MODULE has no IF_DATA XCP" in box.text()
    assert "Tools > Merge A2L fragments" in box.text()
    assert window.connect_action.isEnabled()


def test_an_a2l_whose_include_is_missing_opens_without_it_and_says_which(qtbot):
    window, loaded = window_on(qtbot, CORPUS / "xcplite" / "c_demo.a2l")  # /include "XCP_104.aml", not in the corpus
    assert loaded
    (box,) = window.errors
    assert box.text().startswith(f'{CORPUS / "xcplite" / "c_demo.a2l"}:8:1: /include "XCP_104.aml" left out: no such file\n')
    assert "the rest of the A2L is open" in box.text()
    assert {"counter", "map_f32", "curve_f32"} & {row.name for row in window.browser.model.rows}
    assert window.workspace.config is not None  # its IF_DATA XCP is read without the A2ML
    assert "offline" not in window.status.link.text()


def test_an_a2l_made_of_instances_lists_their_objects_and_says_what_it_leaves_out(qtbot):
    """a2ltool's typedef tests hold INSTANCEs only: the browser looked empty ("0 of 0 objects"); pointers are left out."""
    from workbench.gui.widgets.main_window import MainWindow

    a2l = CORPUS / "a2ltool" / "update_typedef_test1.a2l"
    window = MainWindow(Project(a2l=a2l))
    qtbot.addWidget(window)
    window.show()
    with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
        window.load()
        assert window.browser.count.text() == "reading update_typedef_test1.a2l …"
    assert window.browser.count.text() == "44 of 44 objects · 9 INSTANCE parts left out"
    assert "INSTANCE TEST_structptr: reached through a pointer (ADDRESS_TYPE PLONG): not supported" in (
        window.browser.count.toolTip())
    assert "TEST_structarr[9].value" in {row.name for row in window.browser.model.all_rows}


def test_without_plots_the_plot_area_says_what_to_do_and_a_drop_there_opens_a_plot(qtbot):
    """An A2L opened on its own had a blank plot area: nothing said that signals are dropped there."""
    from PySide6.QtCore import QPointF, Qt
    from PySide6.QtGui import QDropEvent

    from workbench.gui.mime import signals_mime

    window, loaded = window_on(qtbot, CORPUS / "domohuhn-a2l" / "example-ecu.a2l")
    assert loaded and not window.plots
    hint = window.plot_hint
    assert hint.isVisible() and not window.plot_area.isVisible() and "Drop signals here" in hint.text()
    mime = signals_mime(["MeasureKMH", "DataMap"])  # kept: the event does not own it
    hint.dropEvent(QDropEvent(QPointF(10, 10), Qt.CopyAction, mime, Qt.LeftButton, Qt.NoModifier))
    (plot,) = window.plots
    assert plot.signals == ["MeasureKMH"]  # a calibration is not plotted
    assert window.plot_area.isVisible() and not hint.isVisible()
    plot.close_requested.emit()
    assert hint.isVisible() and not window.plots


def test_an_a2l_of_two_modules_is_refused_saying_what_to_open(qtbot):
    window, loaded = window_on(qtbot, CORPUS / "domohuhn-a2l" / "xcp-sim.a2l")
    assert not loaded
    (box,) = window.errors
    assert box.text().endswith("xcp-sim.a2l:4:1: expected exactly one MODULE, found 2 (DH.XCP.SIM, DH.XCP.LIGHT); the "
                               "workbench reads one ECU per A2L: open an A2L of one MODULE (its own file)")
    assert window.browser.count.text() == "0 of 0 objects"  # not 'reading …' still


def test_an_a2l_without_a_transport_layer_says_where_the_window_takes_the_ecus_address(qtbot, tmp_path):
    """XCPlite's A2Ls state no XCP_ON_CAN and no XCP_ON_UDP_IP: the window said 'use --host/--port', a command line's
    options."""
    import shutil

    from workbench import demo

    shutil.copy(CORPUS / "xcplite" / "hello_xcp.a2l", tmp_path)
    shutil.copy(demo.master_a2l().parent / "XCP.aml", tmp_path / "XCP_104.aml")
    window, loaded = window_on(qtbot, tmp_path / "hello_xcp.a2l")
    assert loaded and not window.errors
    window.connect_ecu()
    qtbot.waitUntil(lambda: bool(window.errors), timeout=WAIT_MS)
    assert window.errors[0].text().endswith("with the ECU's host and port (--host/--port; in the window: "
                                            "ECU > Connection…)")
