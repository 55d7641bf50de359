"""The calibration editors, the fix panel and the compare view when nothing can be written: disconnected (the
Disconnect button), the connection lost under a write, the reference page active. Never a write lost silently:
the editors are read-only and greyed with the reason in their tooltips, a write tried is refused at once, a write
cut off says "not written" and the field shows what the ECU holds; the fix panel keeps the A2L's format and greys
what is not current; a comparison with the ECU is outdated once the ECU connects again."""

from __future__ import annotations

import re

import numpy as np
import pytest
from gui_helpers import WAIT_MS, ecu_and_window_fixtures, open_window
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor

from workbench.gui import theme
from workbench.gui.ecu import READ_ONLY_PAGE
from workbench.gui.models.fixes import COLUMNS as FIX_COLUMNS


ecu, window = ecu_and_window_fixtures("gui-offline")


def editor_on(window, qtbot, name: str):
    editor = window.open_editor(name)
    qtbot.waitUntil(lambda: editor.value is not None and editor.field.isEnabled(), timeout=WAIT_MS)
    return editor


def fix_texts(panel, column: str) -> list[str]:
    return [panel.model.index(row, FIX_COLUMNS.index(column)).data() for row in range(panel.model.rowCount())]


def decimals(texts) -> list[int | None]:
    return [len(t.split(".")[1]) if re.fullmatch(r"-?\d+\.\d+", t) else None for t in texts]


def reconnect(window, qtbot) -> None:
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()


def test_disconnected_editors_and_fix_panel_are_read_only_and_a_write_is_refused_at_once(window, qtbot):
    scalar = editor_on(window, qtbot, "xsSWITCH_TANK_THR")
    table = editor_on(window, qtbot, "xvPRV_DC_FF")
    panel = window.fix_panel
    qtbot.waitUntil(lambda: len(panel.model.rows) > 10 and not panel.model.stale, timeout=WAIT_MS)
    live, override = fix_texts(panel, "live"), fix_texts(panel, "override")
    assert "0.00 %" in override and "30.00 bar" not in override

    window.disconnect_action.trigger()
    field = scalar.field.input
    assert not field.isEnabled() and field.toolTip() == "read-only: not connected"
    assert scalar.status.text() == "read-only: not connected"
    cell = table.field.model.index(1, 1)
    assert not cell.flags() & Qt.ItemIsEditable and "read-only: not connected" in cell.data(Qt.ToolTipRole)
    assert cell.data(Qt.ForegroundRole) == QColor(theme.MUTED)
    assert not any(button.isEnabled() for button in table.field.block_buttons.values())
    with qtbot.waitSignal(scalar.refused, timeout=WAIT_MS) as refused:
        scalar.edit(26.0)  # as Enter, or an undo, would ask
    assert refused.args[0] == "not connected" and scalar.status.text() == "not written: not connected"
    with qtbot.waitSignal(table.refused, timeout=WAIT_MS) as refused:
        table.edit(np.zeros_like(table.value.value))
    assert refused.args[0] == "not connected"

    assert fix_texts(panel, "override") == override  # the A2L's format, not "0" and "30"
    assert decimals(fix_texts(panel, "live")) == decimals(live)
    row = next(r for r, fix in enumerate(panel.model.rows) if fix.pair.stem == "zfRAILPRESSURE")
    value = panel.model.index(row, FIX_COLUMNS.index("override"))
    assert value.data(Qt.ForegroundRole) == QColor(theme.MUTED) and "not current" in value.data(Qt.ToolTipRole)
    assert not value.flags() & Qt.ItemIsEditable
    assert not panel.model.index(row, FIX_COLUMNS.index("on")).flags() & Qt.ItemIsUserCheckable
    with qtbot.waitSignal(panel.refused, timeout=WAIT_MS) as refused:
        panel.model.setData(value, 30.0)
    assert refused.args[0] == "not connected" and panel.message.text() == "not written: not connected"

    reconnect(window, qtbot)
    qtbot.waitUntil(lambda: field.isEnabled() and not panel.model.stale, timeout=WAIT_MS)
    assert scalar.status.text() == "" and value.flags() & Qt.ItemIsEditable
    assert fix_texts(panel, "override") == override
    assert not window.errors


def test_the_reference_page_makes_the_editors_read_only_and_a_refusal_there_is_gone_on_the_working_page(window,
                                                                                                        qtbot):
    scalar = editor_on(window, qtbot, "xsSWITCH_TANK_THR")
    with qtbot.waitSignal(window.controller.page_changed, timeout=WAIT_MS):
        window.reference_action.trigger()
    assert not scalar.field.input.isEnabled() and scalar.field.input.toolTip() == f"read-only: {READ_ONLY_PAGE}"
    assert "Working page" in READ_ONLY_PAGE and "workbench cal" not in READ_ONLY_PAGE
    with qtbot.waitSignal(scalar.refused, timeout=WAIT_MS) as refused:
        scalar.edit(26.0)  # an undo on the reference page: the session refuses it
    assert refused.args[0] == READ_ONLY_PAGE and scalar.status.text() == f"not written: {READ_ONLY_PAGE}"
    panel = window.fix_panel
    assert not panel.model.index(0, FIX_COLUMNS.index("override")).flags() & Qt.ItemIsEditable
    with qtbot.waitSignal(window.controller.page_changed, timeout=WAIT_MS):
        window.working_action.trigger()
    qtbot.waitUntil(lambda: scalar.field.input.isEnabled(), timeout=WAIT_MS)
    assert scalar.status.text() == ""  # the refusal was the reference page's
    assert panel.model.index(0, FIX_COLUMNS.index("override")).flags() & Qt.ItemIsEditable
    assert window.controller.session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0)
    assert not window.errors  # refused in the editor, no dialog


def test_a_comparison_with_the_ecu_is_outdated_once_the_ecu_connects_again(window, qtbot, tmp_path):
    sets, view = window.parameter_sets, window.compare
    path = tmp_path / "base.dcm"
    with qtbot.waitSignal(sets.message, timeout=WAIT_MS):
        sets.save(path)
    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        sets.open(path)
    assert view.summary.text() == "0 of 58 objects differ"
    window.disconnect_action.trigger()
    with qtbot.waitSignal(sets.message, timeout=WAIT_MS) as said:
        view.apply_button.click()
    assert said.args[0] == "base.dcm not applied: not connected"
    reconnect(window, qtbot)
    assert view.summary.text() == "0 of 58 objects differ · outdated: ECU reconnected since"
    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        view.refresh_button.click()  # with the new session
    assert view.summary.text() == "0 of 58 objects differ"
    assert not window.errors


def test_a_write_cut_off_by_a_lost_connection_says_not_written_and_shows_what_the_ecu_holds(qtbot, project, channel):
    from workbench.sim import serve_demo
    from workbench.xcp_protocol import Cmd

    settings = {"interface": "virtual", "channel": channel}
    project.plots = []
    with serve_demo(settings, pcm_target_bar=25.0) as simulator:
        window = open_window(qtbot, project)
        window.controller.RECONNECT_MS = 200
        editor = editor_on(window, qtbot, "xsSWITCH_TANK_THR")
        simulator.ecu.faults.delay_answer(Cmd.DOWNLOAD, 0.5)  # under way when the ECU goes
        editor.edit(26.0)
        assert editor.status.text() == "writing …"
    qtbot.waitUntil(lambda: bool(editor.unwritten), timeout=WAIT_MS)
    assert re.fullmatch(r"26\.00 not written: the connection was lost at \d\d:\d\d:\d\d while xsSWITCH_TANK_THR was "
                        r"being written", editor.unwritten), editor.unwritten
    assert editor.status.text() == f"⚠ {editor.unwritten}; the field shows what the ECU holds"
    assert editor.modified_badge.isVisible() and editor.modified_badge.text() == "not written"
    assert not editor.field.input.isEnabled()

    with serve_demo(settings, pcm_target_bar=25.0):  # the ECU is back (restarted: 20 bar)
        qtbot.waitUntil(lambda: window.controller.is_connected and editor.field.input.isEnabled(), timeout=WAIT_MS)
        qtbot.waitUntil(lambda: editor.field.input.text() == "20.00", timeout=WAIT_MS)
        assert editor.modified_badge.text() == "not written"
        assert editor.status.text().startswith("⚠ 26.00 not written")
        editor.edit(21.0)  # written again: the mark is gone
        qtbot.waitUntil(lambda: editor.modified_badge.text() == "modified", timeout=WAIT_MS)
        assert window.controller.session.read("xsSWITCH_TANK_THR") == pytest.approx(21.0)
        window.close()
    assert not window.errors or pytest.fail(f"error dialogs: {[box.text() for box in window.errors]}")


def test_the_numeric_view_and_the_legends_grey_their_last_values_while_nothing_is_measured(window, qtbot):
    """Disconnected, the numeric view and a plot's legend showed the last values as live ones (white, no word of it)."""
    from workbench.gui.project import PlotSpec

    numeric = window.numeric
    numeric.add_signals(["zsRailPressure"])
    plot = window.add_plot(PlotSpec("Rail", ["zsRailPressure"]))
    value, legend = numeric.item(numeric.signals.index("zsRailPressure"), 1), plot.legend.item(0, 1)
    qtbot.waitUntil(lambda: value.text() != "—" and legend.text() != "—", timeout=WAIT_MS)
    for item in (value, legend):
        assert item.foreground().color() != QColor(theme.MUTED) and item.toolTip() == ""
    window.disconnect_action.trigger()
    numeric.refresh()
    plot._update_legend_values(None)
    for item in (value, legend):
        assert item.text() != "—" and item.foreground().color() == QColor(theme.MUTED)
        assert item.toolTip() == "not current: not connected (the last value measured)"
    reconnect(window, qtbot)
    for item in (value, legend):
        qtbot.waitUntil(lambda: item.foreground().color() != QColor(theme.MUTED), timeout=WAIT_MS)
    plot.close_requested.emit()
    assert not window.errors


def test_the_fixes_read_before_another_project_opened_are_not_shown_after(demo_ecu, project, qtbot, monkeypatch):
    """The ECU's answer to a refresh came after the panel was cleared for another project: its 17 rows came back
    (a flake of test_opening_another_project_leaves_nothing_bound_to_the_a2l_before on a loaded machine)."""
    window = open_window(qtbot, project)
    panel = window.fix_panel
    qtbot.waitUntil(lambda: panel.model.rowCount() > 0 and not panel._busy, timeout=WAIT_MS)
    fixes = list(panel.model.rows)
    answers = []
    monkeypatch.setattr(window.controller, "call", lambda _method, on_done=None, **_: answers.append(on_done) or True)
    panel.refresh()
    panel.clear()  # another project opens meanwhile
    answers[0](fixes)
    assert panel.model.rowCount() == 0
    window.close()
