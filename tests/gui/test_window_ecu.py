"""The window against the simulated ECU on a virtual bus: connect, live plots, calibration editors,
fix overrides, pages: what a user does, checked through the session."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import WAIT_MS, open_window
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QMessageBox

from workbench.calib.fixes import find_fix_pairs
from workbench.gui.models.fixes import COLUMNS as FIX_COLUMNS
from workbench.gui.models.fixes import FixModel
from workbench.gui.project import PlotSpec
from workbench.session.fixes import FixState


@pytest.fixture
def window(qtbot, demo_ecu, project):
    window = open_window(qtbot, project)
    yield window
    window.close()
    assert not window.errors or pytest.fail(f"error dialogs: {[box.text() for box in window.errors]}")


def test_connecting_shows_who_the_ecu_is_and_that_its_epk_matches(window):
    session = window.controller.session
    assert session is not None and session.epk.matches
    assert window.status.epk.text() == "EPK ✓" and session.epk.ecu in window.status.epk.toolTip()
    assert "FLCU" in window.status.ecu.text() and window.status.link.text().startswith("●")
    assert window.flash_action.isEnabled() and not window.connect_action.isEnabled()
    assert window.browser.model.rowCount() > 100
    # a message (the cache sync's after a connect, one here) stands beside the indicators, not over them
    window.statusBar().showMessage("the data in the ECU equals \"FLCU.s19\" (58 objects)", 15000)
    indicators = (window.status.link, window.status.ecu, window.status.epk, window.status.page)
    assert all(label.isVisible() for label in indicators) and window.status.message.isVisible()
    assert window.statusBar().currentMessage() == "the data in the ECU equals \"FLCU.s19\" (58 objects)"
    window.statusBar().clearMessage()
    assert window.statusBar().currentMessage() == ""


def test_rail_pressure_dropped_on_a_new_plot_arrives_by_daq(window, qtbot):
    plot = window.add_plot(PlotSpec("Test", []))
    plot.add_signals(["zsRailPressure"])
    qtbot.waitUntil(lambda: plot.samples_shown() > 20, timeout=WAIT_MS)
    assert "zsRailPressure" in window.hub.acquisition.state.signals
    t, bar = window.hub.buffer("zsRailPressure").window(-np.inf, np.inf)
    assert np.all(np.diff(t) > 0) and 0.0 <= bar.min() and bar.max() < 60.0
    # the 4 ms task's event, by the ECU's clock: most samples 4 ms apart to a few microseconds (host arrival times
    # jitter by tens of them and come in bursts on a loaded machine); the others where the ECU's clock is mapped to
    # the host's anew (a sample that travelled faster, xcp.daq.clock), in order all the same
    spacing = np.diff(t)
    assert np.mean(np.abs(spacing - 0.004) < 5e-6) > 0.5, np.round(spacing[:50] * 1e3, 4)
    state = window.hub.acquisition.state
    assert state.lost == 0 and state.overloads == 0
    window.statusBar().clearMessage()
    window.status.refresh()
    labels = (window.status.daq, window.status.bus, window.status.epk, window.status.page)
    # not cut, once the status bar has laid them out again (the DAQ counts change while it does)
    qtbot.waitUntil(lambda: all(label.text() and label.width() >= label.sizeHint().width() for label in labels),
                    timeout=WAIT_MS)


def test_can2_signals_decoded_from_the_dbc_arrive_beside_xcp(window, qtbot):
    plot = window.plots[0]
    plot.add_signals(["FLCU_TO_PCM_002.RailPressure"])
    buffer = window.hub.buffer("FLCU_TO_PCM_002.RailPressure")
    qtbot.waitUntil(lambda: len(buffer) >= 3, timeout=WAIT_MS)
    assert window.hub.info("FLCU_TO_PCM_002.RailPressure").source == "CAN2"
    window.trace.refresh()
    assert any(entry.message == "FLCU_TO_PCM_002" for entry in window.trace.model.rows)
    assert window.hub.can_monitor.bus_load() > 0


def _fix_row(panel, signal: str) -> int:
    return next(row for row, fix in enumerate(panel.model.rows) if fix.pair.signal == signal)


def test_a_fix_override_replaces_the_rail_pressure_until_released(window, qtbot):
    session = window.controller.session
    panel = window.fix_panel
    qtbot.waitUntil(lambda: any(f.pair.stem == "zfRAILPRESSURE" for f in panel.model.rows), timeout=WAIT_MS)
    model = panel.model
    row = _fix_row(panel, "zsRailPressure")
    assert model.setData(model.index(row, FIX_COLUMNS.index("override")), "12.5")
    qtbot.waitUntil(lambda: session.read("zfRAILPRESSURE_VALUE") == pytest.approx(12.5), timeout=WAIT_MS)
    assert model.setData(model.index(row, FIX_COLUMNS.index("on")), Qt.Checked.value, Qt.CheckStateRole)
    qtbot.waitUntil(lambda: session.fix_state("zfRAILPRESSURE").active, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: panel.model.rows[_fix_row(panel, "zsRailPressure")].live == pytest.approx(12.5),
                    timeout=WAIT_MS)
    low = model.index(next(r for r, f in enumerate(model.rows) if f.pair.stem == "cfFUELLEVELLOW"),
                      FIX_COLUMNS.index("live"))
    # xsLEDEn (the A2L's COMPARISON_QUANTITY) reads OFF: the override's table calls that Normal, as cal fix does
    qtbot.waitUntil(lambda: model.data(low) == "Normal", timeout=WAIT_MS)
    assert "live: xsLEDEn = OFF, which cfFUELLEVELLOW_VALUE calls Normal" in model.data(low, Qt.ToolTipRole)
    # in the _VALUE's unit, as cal fix --list prints it (the panel showed "12.50": bar, % or V?)
    assert model.data(model.index(_fix_row(panel, "zsRailPressure"), FIX_COLUMNS.index("override"))) == "12.50 bar"
    assert model.data(model.index(_fix_row(panel, "zsRailPressure"), FIX_COLUMNS.index("live"))).endswith(" bar")
    index = model.index(_fix_row(panel, "zsRailPressure"), FIX_COLUMNS.index("on"))
    assert model.data(index, Qt.CheckStateRole) == Qt.Checked
    assert model.setData(index, Qt.Unchecked.value, Qt.CheckStateRole)
    qtbot.waitUntil(lambda: not session.fix_state("zfRAILPRESSURE").active, timeout=WAIT_MS)


def test_a_fix_without_a_live_measurement_shows_its_value_as_sent_on_can2(qapp):
    """A third-party A2L that neither links nor names FuelLevelLow's source: the CAN2 monitor's value."""
    pairs = find_fix_pairs(["cfFUELLEVELLOW_EN", "cfFUELLEVELLOW_VALUE"], ["xsLEDEn"])
    model = FixModel(bus_value=lambda fix: "Low" if fix.pair.stem == "cfFUELLEVELLOW" else None)
    model.set_fixes([FixState(pairs[0], None, "Normal", False)])
    live = model.index(0, FIX_COLUMNS.index("live"))
    assert model.data(live) == "Low" and "live: as sent on CAN2" in model.data(live, Qt.ToolTipRole)
    unknown = FixModel()
    unknown.set_fixes([FixState(pairs[0], None, "Normal", False)])
    assert unknown.data(unknown.index(0, FIX_COLUMNS.index("live"))) == "—"


def test_the_page_buttons_switch_the_ecu_to_the_reference_page_and_back(window, qtbot):
    session = window.controller.session
    working, reference = session.page_numbers()
    window.reference_action.trigger()
    qtbot.waitUntil(lambda: session.page().ecu_page == reference, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: "reference" in window.status.page.text(), timeout=WAIT_MS)
    window.working_action.trigger()
    qtbot.waitUntil(lambda: session.page().ecu_page == working, timeout=WAIT_MS)



def test_copying_the_reference_page_says_what_it_overwrites_and_copies_only_on_yes(window, qtbot):
    """As `cal page copy` asks in a terminal: No (the default) sends nothing, Yes undoes the change."""
    session = window.controller.session
    session.write("xsPRV_KP", 6.0)  # the reference page holds 5
    editor = window.open_editor("xsPRV_KP")
    qtbot.waitUntil(lambda: editor.value is not None and not editor.modified_badge.isHidden(), timeout=WAIT_MS)
    window.copy_action.trigger()
    qtbot.waitUntil(lambda: window.copy_confirm is not None and window.copy_confirm.isVisible(), timeout=WAIT_MS)
    box = window.copy_confirm
    assert box.text() == "Copy the reference page onto the working page, losing every change since start-up?"
    assert box.informativeText() == ("Overwrites the working page 0 of segment 0 (CALRAM, 0x40000000-0x4001FFFF, "
                                     "131072 bytes, 58 calibrations) with the reference page 1.")
    assert box.defaultButton() is box.button(QMessageBox.No)
    box.button(QMessageBox.No).click()
    qtbot.waitUntil(lambda: window.statusBar().currentMessage() == "not confirmed: nothing copied", timeout=WAIT_MS)
    assert session.read("xsPRV_KP") == pytest.approx(6.0)  # nothing was sent

    window.copy_action.trigger()
    qtbot.waitUntil(lambda: window.copy_confirm is not box and window.copy_confirm.isVisible(), timeout=WAIT_MS)
    window.copy_confirm.button(QMessageBox.Yes).click()
    qtbot.waitUntil(lambda: window.statusBar().currentMessage() == "copied the reference page onto the working page",
                    timeout=WAIT_MS)
    assert session.read("xsPRV_KP") == pytest.approx(5.0)
    qtbot.waitUntil(lambda: editor.value.value == pytest.approx(5.0) and editor.modified_badge.isHidden(),
                    timeout=WAIT_MS)  # the editor read again


def test_a_plain_0_1_flag_without_state_texts_steps_in_a_lane_as_a_verbal_signal_does(window, qtbot):
    """CANRX_PCM_TO_FLCU_001_Pdu.NewDataReceived (UBYTE, CM_Identity, limits 0 .. 1, no texts) in a lane labelled
    0 and 1 below the curves, beside xsValve1State's ON/OFF; it was drawn on a unit's scale of its own."""
    flag = "CANRX_PCM_TO_FLCU_001_Pdu.NewDataReceived"
    plot = window.add_plot(PlotSpec("Flags", []))
    plot.add_signals(["zsRailPressure", flag, "xsValve1State"])
    curve = plot._curves[flag]
    qtbot.waitUntil(lambda: curve.yData is not None and len(curve.yData) > 20, timeout=WAIT_MS)
    assert plot.lanes.names == [flag, "xsValve1State"] and plot.drawn_axes() == ["bar"]
    assert curve.getViewBox() is plot.lanes.view
    level = plot.lanes.level
    assert {(level(flag, 0.0), "0"), (level(flag, 1.0), "1")} <= set(plot.lanes.axis._tickLevels[0])
    _, values = window.hub.buffer(flag).window(-np.inf, np.inf)
    assert set(np.unique(values)) <= {0.0, 1.0}
    drawn = set(np.unique(curve.yData[np.isfinite(curve.yData)]))
    assert drawn and drawn <= {level(flag, 0.0), level(flag, 1.0)}


def test_a_page_switch_the_ecu_refuses_leaves_the_buttons_and_status_on_the_page_it_uses(window, qtbot, monkeypatch):
    from workbench.errors import XcpCommandError

    def refuse(*_):
        raise XcpCommandError("SET_CAL_PAGE", 0x25)

    monkeypatch.setattr(window.controller.session.master, "set_cal_page", refuse)
    errors = len(window.errors)
    window.reference_action.trigger()  # checked at once by the click, as a QActionGroup does
    qtbot.waitUntil(lambda: len(window.errors) > errors, timeout=WAIT_MS)
    assert window.errors[-1].text() == ("switching the ECU to the reference page (it stays on the working page): "
                                        "XCP SET_CAL_PAGE failed: ERR_ACCESS_LOCKED (0x25)")
    assert window.working_action.isChecked() and not window.reference_action.isChecked()
    assert "working" in window.status.page.text() and window.controller.page == "working"
    window.errors.pop().close()  # the one dialog expected


def test_a_window_without_plots_is_live_once_connected_and_its_placeholder_tab_has_no_close_button(qtbot, demo_ecu,
                                                                                                   project):
    """`workbench gui --a2l MINE.a2l --screenshot` (no plots) waited 30 s for samples nothing measured, then failed."""
    from PySide6.QtWidgets import QTabBar

    from workbench.gui.widgets.main_window import MainWindow

    project.plots, project.editors = [], []
    window = MainWindow(project)
    qtbot.addWidget(window)
    window.show()
    with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
        window.load()
    bar = window.editor_tabs.tabBar()
    assert window.editor_tabs.widget(0) is window.editor_placeholder
    assert bar.tabButton(0, QTabBar.RightSide) is None and bar.tabButton(0, QTabBar.LeftSide) is None
    with qtbot.waitSignal(window.live, timeout=WAIT_MS):
        window.connect_ecu()
    window.close()
