"""Parameter sets in the window against the demo ECU: the working page compared with the reference page,
the ECU's values saved as a DCM, a changed parameter set compared with the ECU and applied with the
checks of ``cal load`` (a dry run first; a refused object and nothing is written), two files compared."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from gui_helpers import WAIT_MS, demo_ecu_on_a_channel_of_its_own, ecu_and_window_fixtures, open_window, text_rect
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QMessageBox
from session_helpers import extended_limits_a2l

from workbench.calib.dataset import Dataset, load_dataset, save_dataset
from workbench.calib.values import CalValue
from workbench.gui.project import Connection, demo_project


ecu, window = ecu_and_window_fixtures("gui-sets")


def test_the_working_page_is_compared_with_the_reference_page(window, qtbot):
    session = window.controller.session
    session.write("xsSWITCH_TANK_THR", 27.5)
    view = window.compare
    with qtbot.waitSignal(window.parameter_sets.compared, timeout=WAIT_MS):
        window.compare_pages_action.trigger()
    assert view.rows_shown() == ["xsSWITCH_TANK_THR"]  # only what differs
    assert view.sides.text() == "A: reference page (CAL ROM)   ·   B: working page (CAL RAM)"
    row = [view.proxy.index(0, column).data() for column in range(5)]
    # CM_bar's %8.2; B - A signed and in its unit, as the details and cal diff show it
    assert row == ["xsSWITCH_TANK_THR", "differs", "20.00 bar", "27.50 bar", "Δ +7.50 bar"]
    view.table.selectRow(0)
    assert [view.elements.index(0, c).data() for c in range(4)] == ["value", "20.00", "27.50", "+7.50"]
    b, difference = (view.proxy.index(0, column) for column in (3, 4))  # B's value and the difference apart
    gap = text_rect(view.table, difference).left() - text_rect(view.table, b).right()
    assert gap >= 12, gap
    view.show_equal.setChecked(True)
    assert len(view.rows_shown()) > 50
    view.show_equal.setChecked(False)
    session.write("xsSWITCH_TANK_THR", 20.0)
    window.controller.written.emit("xsSWITCH_TANK_THR")  # as an editor of the window says it
    assert view.summary.text() == "1 of 58 objects differ · outdated: xsSWITCH_TANK_THR written since"
    with qtbot.waitSignal(window.parameter_sets.compared, timeout=WAIT_MS):
        view.refresh_button.click()
    assert view.rows_shown() == [] and "outdated" not in view.summary.text()


def test_the_compare_views_filter_keeps_its_placeholder_at_the_least_width_beside_the_apply_button(qtbot):
    from workbench.gui.widgets.compare_view import CompareView

    view = CompareView()
    qtbot.addWidget(view)
    view.apply_button.setVisible(True)  # a parameter set compared with the ECU
    view.summary.setText("1 of 58 objects differ")
    view.show()
    view.resize(view.minimumSizeHint().width(), 300)
    qtbot.waitUntil(lambda: view.width() == view.minimumSizeHint().width(), timeout=WAIT_MS)
    search = view.search
    assert search.width() >= search.fontMetrics().horizontalAdvance(search.placeholderText()) + 24  # padding


def test_a_parameter_set_saved_changed_and_applied_with_the_checks_of_cal_load(window, qtbot, tmp_path):
    session = window.controller.session
    sets = window.parameter_sets
    with qtbot.waitSignal(sets.message, timeout=WAIT_MS) as saved:
        sets.save(tmp_path / "base.dcm")
    assert saved.args[0].endswith(f"saved to {tmp_path / 'base.dcm'}")
    dataset = load_dataset(tmp_path / "base.dcm")
    assert dataset["xsSWITCH_TANK_THR"].value == pytest.approx(20.0)
    tuned = dataset["xvPRV_DC_FF"]
    values = np.array(tuned.value, dtype=float)
    values[1, 2] += 5.0
    dataset["xvPRV_DC_FF"] = CalValue(tuned.name, tuned.kind, values, tuned.axes, tuned.unit)
    save_dataset(dataset, tmp_path / "tuned.dcm")

    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        sets.open(tmp_path / "tuned.dcm")
    view = window.compare
    assert view.rows_shown() == ["xvPRV_DC_FF"] and view.apply_button.isVisible()
    assert view.sides.text() == f"A: ECU working page (CAL RAM)   ·   B: {tmp_path / 'tuned.dcm'}"  # which page
    assert view.elements.rowCount() == 1 and view.elements.index(0, 0).data().startswith("value[1, 2] at (")
    a, b, delta = (view.elements.index(0, column).data() for column in (1, 2, 3))
    assert delta == "+5.00" and float(b) - float(a) == pytest.approx(5.0)  # CM_Percent's %6.2, as the editor
    assert a == f"{float(a):.2f}" and view.elements.index(0, 0).data().endswith(".00)")  # axis points: %x.2 too
    before = session.read("xvPRV_DC_FF")
    view.apply_button.click()  # a dry run, then the question
    qtbot.waitUntil(lambda: sets.confirm is not None and sets.confirm.isVisible(), timeout=WAIT_MS)
    assert sets.confirm.text() == "Write 1 changed object(s) of tuned.dcm into the ECU?"
    assert np.array_equal(session.read("xvPRV_DC_FF"), before)  # nothing written before the answer
    with qtbot.waitSignal(sets.applied, timeout=WAIT_MS) as applied:
        sets.confirm.button(QMessageBox.Ok).click()
    assert applied.args[0].named("applied") == ["xvPRV_DC_FF"]
    assert session.read("xvPRV_DC_FF")[1, 2] == pytest.approx(values[1, 2], abs=0.01)
    qtbot.waitUntil(lambda: view.rows_shown() == [], timeout=WAIT_MS)  # compared again: the ECU holds the file

    dataset["xsSWITCH_TANK_THR"] = CalValue("xsSWITCH_TANK_THR", "VALUE", 900.0, unit="bar")
    save_dataset(dataset, tmp_path / "bad.dcm")
    _asked_to_apply(sets, view, qtbot, tmp_path / "bad.dcm")
    assert sets.confirm.text() == "1 object(s) of bad.dcm are refused; nothing is written."
    assert "xsSWITCH_TANK_THR" in sets.confirm.detailedText() and "upper limit 800" in sets.confirm.detailedText()
    assert sets.confirm.button(QMessageBox.Ok) is None
    assert sets.confirm.checkBox() is None  # no EXTENDED_LIMITS in the demo A2L: no such choice offered
    sets.confirm.close()
    assert session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0)
    session.write("xvPRV_DC_FF", before)

    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        sets.compare_files(tmp_path / "base.dcm", tmp_path / "bad.dcm")
    assert view.rows_shown() == ["xvPRV_DC_FF", "xsSWITCH_TANK_THR"] and not view.apply_button.isVisible()

    moved = Dataset()  # the map alone, its shared axis's point moved: said before Ok, not only under Details
    points = tuned.axes[0].values.copy()
    points[1] += 2.0
    moved.add(CalValue(tuned.name, tuned.kind, tuned.value, (replace(tuned.axes[0], values=points), tuned.axes[1]),
                       tuned.unit))
    save_dataset(moved, tmp_path / "moved.dcm")
    _asked_to_apply(sets, view, qtbot, tmp_path / "moved.dcm")
    assert "\nwarning: xvPRV_DC_FF: its X axis is the AXIS_PTS xaPRV_FF_TARGET" in sets.confirm.informativeText()
    sets.confirm.close()
    assert not window.errors


def _asked_to_apply(sets, view, qtbot, path) -> None:
    """``path`` opened and compared, Apply pressed: its dry run's question shown."""
    sets.confirm = None
    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        sets.open(path)
    view.apply_button.click()
    qtbot.waitUntil(lambda: sets.confirm is not None and sets.confirm.isVisible(), timeout=WAIT_MS)


@pytest.fixture
def extended_ecu():
    yield from demo_ecu_on_a_channel_of_its_own("gui-sets-extended")


def test_values_within_their_extended_limits_are_applied_only_when_the_user_chooses_them(extended_ecu, qtbot,
                                                                                         tmp_path):
    """As `cal load --extended-limits`: an A2L whose xsSWITCH_TANK_THR has EXTENDED_LIMITS 0 1000, a set with 900."""
    project = demo_project()
    project.a2l = extended_limits_a2l(tmp_path)
    project.connection = Connection(interface="virtual", channel=extended_ecu[0])
    project.plots, project.tables, project.editors = [], [], []
    window = open_window(qtbot, project)
    session, sets = window.controller.session, window.parameter_sets
    save_dataset(Dataset({"xsSWITCH_TANK_THR": CalValue("xsSWITCH_TANK_THR", "VALUE", 900.0, unit="bar"),
                          "xsPRV_KP": CalValue("xsPRV_KP", "VALUE", 6.0)}), tmp_path / "wide.dcm")
    with qtbot.waitSignal(sets.compared, timeout=WAIT_MS):
        sets.open(tmp_path / "wide.dcm")
    window.compare.apply_button.click()
    qtbot.waitUntil(lambda: sets.confirm is not None and sets.confirm.isVisible(), timeout=WAIT_MS)
    refused = sets.confirm
    assert refused.text() == "1 object(s) of wide.dcm are refused; nothing is written."
    choice = refused.checkBox()
    assert choice.text() == "allow values up to the EXTENDED_LIMITS (1: xsSWITCH_TANK_THR)" and not choice.isChecked()
    choice.setChecked(True)  # the explicit choice: checked again with the EXTENDED_LIMITS
    qtbot.waitUntil(lambda: sets.confirm is not refused and sets.confirm.isVisible(), timeout=WAIT_MS)
    assert sets.confirm.text() == "Write 2 changed object(s) of wide.dcm into the ECU?"
    assert sets.confirm.checkBox().isChecked() and session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0)
    with qtbot.waitSignal(sets.applied, timeout=WAIT_MS) as applied:
        sets.confirm.button(QMessageBox.Ok).click()
    assert applied.args[0].named("applied") == ["xsSWITCH_TANK_THR", "xsPRV_KP"]
    assert session.read("xsSWITCH_TANK_THR") == pytest.approx(900.0)
    assert not window.errors
    window.close()


@pytest.mark.parametrize("name", ["inca_style.cdfx", "inca_style.dcm", "canape_style.cdfx"])
def test_a_set_of_the_flashed_values_equals_the_s19_offline_whatever_digits_its_tool_wrote(name, demo_workspace):
    """INCA writes a FLOAT32 0.2 as 0.2000000029802322, CANape's CDFX as 0.20000000298023224: the offline comparison
    (and `workbench cal diff FLCU.s19 FILE`) called xsPRV_KD and zsEWMA_ALPHA changed by 3e-9 where the ECU would
    hold the same float32."""
    from pathlib import Path

    from workbench import demo
    from workbench.gui.parameter_sets import compare_files

    path = Path(__file__).parents[1] / "corpus" / "datasets" / "tools" / name
    diff = compare_files(demo.s19(), path, demo_workspace.model)
    assert diff.equal, [o.name for o in diff.objects if o.status != "equal"]


def test_a_header_sorts_the_compare_view_by_the_texts_shown_each_made_once_a_row(qtbot, monkeypatch):
    """A QSortFilterProxyModel sorted by asking ``data`` twice a comparison: 1.4 s for the 7,000 calibrations of a
    big A2L compared with a parameter set. The model sorts its rows; the filter and the selection keep theirs."""
    from workbench.calib.dataset import diff_datasets
    from workbench.gui.models.compare import CompareModel
    from workbench.gui.widgets.compare_view import CompareView

    count = 300
    a = Dataset({f"k{i:03d}": CalValue(f"k{i:03d}", "VALUE", float(i % 7), unit="bar") for i in range(count)})
    b = Dataset({f"k{i:03d}": CalValue(f"k{i:03d}", "VALUE", float(i % 7 + (i % 3 == 0)), unit="bar")
                 for i in range(count)})
    view = CompareView()
    qtbot.addWidget(view)
    view.show_diff(diff_datasets(a, b))
    differing = [f"k{i:03d}" for i in range(count) if i % 3 == 0]
    assert view.rows_shown() == differing
    view.table.selectRow(view.rows_shown().index("k021"))
    calls = []
    original = CompareModel.data
    monkeypatch.setattr(CompareModel, "data", lambda self, index, role=Qt.DisplayRole: (
        calls.append(role), original(self, index, role))[1])
    view.table.sortByColumn(0, Qt.DescendingOrder)
    assert view.rows_shown() == differing[::-1] and len(calls) < count  # a proxy's sort: ~16 a row
    (selected,) = view.table.selectionModel().selectedRows()
    assert selected.data() == "k021"
    view.table.sortByColumn(2, Qt.AscendingOrder)  # by A's text: "0.0 bar" first, equal texts in the diff's order
    assert view.rows_shown() == sorted(differing, key=lambda name: f"{int(name[1:]) % 7}")
    view.show_equal.setChecked(True)  # the filter keeps the order sorted by
    assert view.rows_shown() == sorted((f"k{i:03d}" for i in range(count)), key=lambda name: f"{int(name[1:]) % 7}")
    view.table.sortByColumn(-1, Qt.AscendingOrder)
    assert view.rows_shown() == [f"k{i:03d}" for i in range(count)]
