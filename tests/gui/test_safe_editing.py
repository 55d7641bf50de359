"""Typing values into every editor of the window, key by key as a user does, against the demo ECU:
what is typed is what is written, a value beyond the limits is refused with the limit named and the
ECU keeps its value, Enter writes, Esc and leaving the field write nothing, verbal values by text
and drop-down, block operations on a map's range. One window for the module (opening one costs
a second or two)."""

from __future__ import annotations

import uuid

import numpy as np
import pytest
from gui_helpers import WAIT_MS, ecu_and_window_fixtures, focus, press
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QApplication

from workbench.gui.models.fixes import COLUMNS as FIX_COLUMNS


ecu, window = ecu_and_window_fixtures("gui-edit")


@pytest.fixture
def writes(window, monkeypatch):
    """Every write the window asks the session for, by name."""
    asked = []
    controller = window.controller
    call = controller.call

    def counting(method, *args, **kwargs):
        if method in ("write", "override", "release"):
            asked.append(args[0])
        return call(method, *args, **kwargs)

    monkeypatch.setattr(controller, "call", counting)
    return asked


def keys(text: str) -> None:
    """Type ``text`` as a keyboard does: every key to the widget that has the focus."""
    for char in text:
        press(char)


def editor_on(window, qtbot, name: str):
    editor = window.open_editor(name)
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    return editor


def scalar_typed(editor, text: str) -> None:
    field = editor.field.input
    focus(field)
    field.selectAll()
    keys(text)


def cell_typed(view, row: int, column: int, text: str) -> None:
    focus(view)
    view.setCurrentIndex(view.model().index(row, column))
    keys(text)  # the first key opens the cell's field, the others go into it


def fix_row(panel, stem: str) -> int:
    return next(row for row, fix in enumerate(panel.model.rows) if fix.pair.stem == stem)


def fixes_listed(window, qtbot):
    panel = window.fix_panel
    qtbot.waitUntil(lambda: len(panel.model.rows) > 10, timeout=WAIT_MS)
    return panel


def test_900_typed_into_every_editor_kind_is_refused_with_the_limit_and_the_ecu_keeps_its_value(window, qtbot, ecu):
    session = window.controller.session
    before = {name: session.read(name) for name in ("xsSWITCH_TANK_THR", "zvRailPConv", "xvPRV_DC_FF",
                                                     "cfFUELLEVELLOW_VALUE", "zfRAILPRESSURE_VALUE")}
    scalar = editor_on(window, qtbot, "xsSWITCH_TANK_THR")
    scalar_typed(scalar, "900")
    assert scalar.field.input.text() == "900"  # every keystroke taken: no range that drops the last one
    with qtbot.waitSignal(scalar.refused, timeout=WAIT_MS) as refused:
        press(Qt.Key_Return)
    assert refused.args[0] == "xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00 bar"
    assert "above the upper limit 800" in scalar.status.text()

    for name, cell, limit in (("zvRailPConv", "zsRailVoltFilt 1.000 V", "50.00 bar"),
                              ("xvPRV_DC_FF", "xaPRV_FF_TARGET 10.00 bar / xaPRV_FF_MANIFOLD 50.00 bar", "100.00 %")):
        table = editor_on(window, qtbot, name)
        cell_typed(table.field.table, 0, 1, "900")
        with qtbot.waitSignal(table.refused, timeout=WAIT_MS) as refused:
            press(Qt.Key_Enter)
        assert refused.args[0] == f"{name}: 900.00 at {cell} is above the upper limit {limit}"

    verbal = editor_on(window, qtbot, "cfFUELLEVELLOW_VALUE")
    scalar_typed(verbal, "900")
    with qtbot.waitSignal(verbal.refused, timeout=WAIT_MS) as refused:
        press(Qt.Key_Return)
    assert refused.args[0] == "cfFUELLEVELLOW_VALUE: 900 is above the upper limit 1"

    panel = fixes_listed(window, qtbot)
    for stem, refusal in (("zfRAILPRESSURE", "900.00 is above the upper limit 50.00 bar"),
                          ("cfFUELLEVELLOW", "900 is above the upper limit 1")):
        cell_typed(panel.table, fix_row(panel, stem), FIX_COLUMNS.index("override"), "900")
        with qtbot.waitSignal(panel.refused, timeout=WAIT_MS) as refused:
            press(Qt.Key_Return)
        assert refused.args[0] == f"{stem}_VALUE: {refusal}"
    after = {name: session.read(name) for name in before}
    assert all(np.array_equal(np.asarray(after[n]), np.asarray(before[n])) for n in before), (before, after)
    assert not window.errors


def test_esc_and_leaving_a_field_write_nothing_and_show_the_ecus_value_again(window, qtbot, writes):
    scalar = editor_on(window, qtbot, "xsSWITCH_TANK_THR")
    shown = scalar.field.input.text()
    scalar_typed(scalar, "30")
    press(Qt.Key_Escape)
    assert scalar.field.input.text() == shown
    scalar_typed(scalar, "31")
    window.browser.search.setFocus()  # a click elsewhere
    assert scalar.field.input.text() == shown

    table = editor_on(window, qtbot, "xvPRV_DC_FF")
    view = table.field.table
    cell_typed(view, 1, 1, "42")
    press(Qt.Key_Escape)
    cell_typed(view, 1, 2, "43")
    press(Qt.Key_Tab)
    cell_typed(view, 1, 3, "44")
    window.browser.search.setFocus()
    panel = fixes_listed(window, qtbot)
    cell_typed(panel.table, fix_row(panel, "zfRAILPRESSURE"), FIX_COLUMNS.index("override"), "12")
    press(Qt.Key_Escape)
    cell_typed(panel.table, fix_row(panel, "zfRAILPRESSURE"), FIX_COLUMNS.index("override"), "13")
    window.browser.search.setFocus()
    QApplication.processEvents()
    assert writes == []
    assert view.state() != view.State.EditingState and panel.table.state() != view.State.EditingState


def test_enter_writes_what_was_typed_and_verbal_values_take_their_text(window, qtbot):
    session = window.controller.session
    scalar = editor_on(window, qtbot, "xsSWITCH_TANK_THR")
    scalar_typed(scalar, "26,5")
    press(Qt.Key_Return)
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(26.5), timeout=WAIT_MS)
    qtbot.waitUntil(lambda: scalar.modified_badge.isVisible(), timeout=WAIT_MS)
    scalar.undo_stack.undo()
    qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0), timeout=WAIT_MS)

    verbal = editor_on(window, qtbot, "cfFUELLEVELLOW_VALUE")
    scalar_typed(verbal, "low")
    press(Qt.Key_Return)
    qtbot.waitUntil(lambda: session.read("cfFUELLEVELLOW_VALUE") == "Low", timeout=WAIT_MS)
    qtbot.waitUntil(lambda: verbal.field.input.text() == "Low", timeout=WAIT_MS)
    field = verbal.field.input
    focus(field)
    field.open_choices()  # the drop-down
    assert [a.text() for a in field.choices.actions()] == ["Normal", "Low"]
    field.choices.actions()[0].trigger()
    qtbot.waitUntil(lambda: session.read("cfFUELLEVELLOW_VALUE") == "Normal", timeout=WAIT_MS)

    panel = fixes_listed(window, qtbot)
    qtbot.waitUntil(lambda: panel.model.rows[fix_row(panel, "cfFUELLEVELLOW")].override == "Normal", timeout=WAIT_MS)
    cell_typed(panel.table, fix_row(panel, "cfFUELLEVELLOW"), FIX_COLUMNS.index("override"), "Low")
    press(Qt.Key_Return)
    qtbot.waitUntil(lambda: session.read("cfFUELLEVELLOW_VALUE") == "Low", timeout=WAIT_MS)
    session.write("cfFUELLEVELLOW_VALUE", "Normal")
    assert not window.errors


def test_a_maps_range_is_interpolated_between_its_corners_and_a_product_beyond_the_limits_is_refused(window, qtbot):
    session = window.controller.session
    editor = editor_on(window, qtbot, "xvPRV_DC_FF")
    field, model = editor.field, editor.field.model
    original = session.read("xvPRV_DC_FF")
    selection = field.table.selectionModel()
    from PySide6.QtCore import QItemSelection, QItemSelectionModel

    selection.select(QItemSelection(model.index(1, 1), model.index(3, 4)), QItemSelectionModel.ClearAndSelect)
    assert field.selected_cells()[0] == (1, 1) and field.selected_cells()[-1] == (4, 3)
    field.apply_block("interpolate")
    x, y = model.x_points, model.y_points
    qtbot.waitUntil(lambda: not np.array_equal(session.read("xvPRV_DC_FF"), original), timeout=WAIT_MS)
    written = session.read("xvPRV_DC_FF")
    corners = [(1, 1), (4, 1), (1, 3), (4, 3)]
    assert all(written[c] == pytest.approx(original[c], abs=0.01) for c in corners)
    wx = (x[2] - x[1]) / (x[4] - x[1])
    wy = (y[2] - y[1]) / (y[3] - y[1])
    expected = ((1 - wx) * (1 - wy) * original[1, 1] + wx * (1 - wy) * original[4, 1]
                + (1 - wx) * wy * original[1, 3] + wx * wy * original[4, 3])
    assert written[2, 2] == pytest.approx(expected, abs=0.01)
    assert np.array_equal(written[0], original[0])  # outside the range: untouched

    field.operand.setText("1000")
    with qtbot.waitSignal(editor.refused, timeout=WAIT_MS) as refused:
        field.apply_block("multiply")
    assert "is above the upper limit 100" in refused.args[0]
    assert np.array_equal(session.read("xvPRV_DC_FF"), written)
    session.write("xvPRV_DC_FF", original)


def test_a_map_has_a_3d_view_that_renders_offscreen(window, qtbot):
    editor = editor_on(window, qtbot, "xvPRV_DC_FF")
    surface = editor.field.surface
    editor.field.views.setCurrentWidget(surface)
    surface.resize(320, 220)
    image = surface.grab().toImage()
    colours = {image.pixel(x, y) for x in range(0, image.width(), 8) for y in range(0, image.height(), 8)}
    assert len(colours) > 8  # shaded quads, not an empty background


def test_extended_limits_are_written_only_when_the_user_chose_them(qtbot, tmp_path):
    from workbench import demo
    from workbench.a2l import load_a2l
    from workbench.gui.a2l_info import calibration_info
    from workbench.gui.ecu import EcuController
    from workbench.gui.project import Connection
    from workbench.gui.widgets.calibration_editor import CalibrationEditor
    from workbench.sim import serve_demo

    channel = f"gui-extended-{uuid.uuid4().hex[:10]}"
    text = demo.a2l().read_text(encoding="utf-8")
    block = "/* Conversion Method      */ CM_bar\n      /* Lower Limit            */ 0\n      /* Upper Limit            */ 800\n"
    at = text.index(block, text.index("/* Name                   */ xsSWITCH_TANK_THR"))
    text = text[:at + len(block)] + "      EXTENDED_LIMITS 0 1000\n" + text[at + len(block):]
    (tmp_path / "extended.a2l").write_text(text, encoding="utf-8")
    doc = load_a2l(tmp_path / "extended.a2l")
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0):  # an ECU of its own
        controller = EcuController()
        with qtbot.waitSignal(controller.connected, timeout=WAIT_MS):
            controller.open(doc, Connection(interface="virtual", channel=channel))
        editor = CalibrationEditor(controller, calibration_info(doc.model(), "xsSWITCH_TANK_THR"))
        qtbot.addWidget(editor)
        editor.show()
        editor.reload()
        qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
        assert editor.field.extended.text() == "extended 0 … 1000 bar" and not editor.field.extended.isChecked()
        scalar_typed(editor, "900")
        with qtbot.waitSignal(editor.refused, timeout=WAIT_MS) as refused:
            press(Qt.Key_Return)
        assert refused.args[0].endswith("900.00 is above the upper limit 800.00 bar")
        editor.field.extended.setChecked(True)  # the explicit choice
        scalar_typed(editor, "900")
        press(Qt.Key_Return)
        session = controller.session
        qtbot.waitUntil(lambda: session.read("xsSWITCH_TANK_THR") == pytest.approx(900.0), timeout=WAIT_MS)
        controller.close()


def test_breakpoints_read_with_their_axis_decimals_in_every_view_of_a_map_and_a_curve(window, qtbot):
    """xvPRV_DC_FF's axes (CM_bar, %8.2) and zvRailPConv's (%6.3): headers, heat map ticks, the 3D view's labels
    show the A2L's decimals, as the values do (the breakpoints read "10" and "200" before)."""
    editor = editor_on(window, qtbot, "xvPRV_DC_FF")
    field, model = editor.field, editor.field.model
    x, y = model.x_points, model.y_points
    assert [model.headerData(i, Qt.Horizontal) for i in range(len(x))] == [f"{p:.2f}" for p in x]
    assert [model.headerData(i, Qt.Vertical) for i in range(len(y))] == [f"{p:.2f}" for p in y]
    ticks = field.plot.getAxis("bottom")._tickLevels  # the ends always, the others where there is room
    assert sorted(tick for level in ticks for tick in level) == [(i, f"{p:.2f}") for i, p in enumerate(x)]
    assert ticks[0] == [(0, f"{x[0]:.2f}"), (len(x) - 1, f"{x[-1]:.2f}")]
    assert field.surface.point_text(1, y[-1]) == f"{y[-1]:.2f}" and field.surface.value_text(20) == "20.00"
    curve = editor_on(window, qtbot, "zvRailPConv")
    points = curve.field.model.x_points
    assert curve.field.model.headerData(0, Qt.Horizontal) == f"{points[0]:.3f}"


def test_a_curves_breakpoints_and_values_are_never_cut_on_a_laptops_screen(window, qtbot):
    """zvRailPConv's nine points with three decimals in the 1366 px window: each column as wide as its widest
    text (0.500, 12.50 were '.50' and '12...'), the table scrolls sideways instead."""
    from PySide6.QtGui import QFontMetrics

    editor = editor_on(window, qtbot, "zvRailPConv")
    table, model = editor.field.table, editor.field.model
    qtbot.waitUntil(lambda: table.isVisible() and table.viewport().width() > 0, timeout=WAIT_MS)
    header = table.horizontalHeader()
    needed = QFontMetrics(header.font())
    for column in range(model.columnCount()):
        text = model.headerData(column, Qt.Horizontal)
        assert header.sectionSize(column) >= needed.horizontalAdvance(text) + 12, text
        cell = model.index(0, column).data()
        assert header.sectionSize(column) >= QFontMetrics(table.font()).horizontalAdvance(cell) + 6, cell
    assert header.length() > table.viewport().width()  # it did not fit: it scrolls


def test_a_selected_range_stays_selected_after_a_block_operation_for_the_next_one(window, qtbot):
    from PySide6.QtCore import QItemSelection, QItemSelectionModel

    session = window.controller.session
    editor = editor_on(window, qtbot, "xvPRV_DC_FF")
    field, model = editor.field, editor.field.model
    original = session.read("xvPRV_DC_FF")
    window.controller.written.emit("xvPRV_DC_FF")  # another test wrote it by the session: shown again
    qtbot.waitUntil(lambda: np.array_equal(model.value, original), timeout=WAIT_MS)
    field.table.selectionModel().select(QItemSelection(model.index(2, 1), model.index(3, 2)),
                                        QItemSelectionModel.ClearAndSelect)
    chosen = field.selected_cells()
    field.operand.setText("1")
    field.apply_block("add")
    qtbot.waitUntil(lambda: model.value[1, 2] == pytest.approx(original[1, 2] + 1), timeout=WAIT_MS)
    assert field.selected_cells() == chosen  # the written value read back, the range still selected
    field.apply_block("add")
    qtbot.waitUntil(lambda: model.value[1, 2] == pytest.approx(original[1, 2] + 2), timeout=WAIT_MS)
    written = session.read("xvPRV_DC_FF")
    assert written[2, 3] == pytest.approx(original[2, 3] + 2) and written[0, 0] == original[0, 0]
    session.write("xvPRV_DC_FF", original)


def test_a_refusal_below_the_map_leaves_every_row_of_its_table_in_view(window, qtbot):
    """At 1366 x 768 a refusal takes two lines under xvPRV_DC_FF: the table keeps its five rows whole and
    nothing is laid over another (the heat map's tabs covered its last row)."""
    from PySide6.QtCore import QItemSelection, QItemSelectionModel

    editor = editor_on(window, qtbot, "xvPRV_DC_FF")
    field, model = editor.field, editor.field.model
    window.resize(1366, 768)  # whatever screen this process has (Xvfb's, offscreen's 800 x 800): a laptop's
    window.resizeDocks([window.editor_dock], [426], Qt.Horizontal)  # as wide as beside the demo's plots
    window.resizeDocks([window.editor_dock, window.fix_dock], [int(768 * 0.36), int(768 * 0.5)], Qt.Vertical)
    field.table.selectionModel().select(QItemSelection(model.index(0, 1), model.index(4, 5)),
                                        QItemSelectionModel.ClearAndSelect)
    field.operand.setText("1000")
    with qtbot.waitSignal(editor.refused, timeout=WAIT_MS):
        field.apply_block("multiply")
    qtbot.wait(100)  # laid out again
    assert editor.status.height() > editor.status.fontMetrics().height() * 1.5  # two lines at this width
    assert " bar / " in editor.status.text() and "[" not in editor.status.text()  # the cell by its breakpoints
    assert "at xaPRV_FF_TARGET " in editor.status.toolTip()  # their names shortened to fit; whole in the tooltip
    table = field.table
    rows = model.rowCount() * table.verticalHeader().defaultSectionSize()
    assert table.viewport().height() >= rows, (table.viewport().height(), rows)
    views = field.views.mapTo(editor, field.views.rect().topLeft()).y()
    assert table.mapTo(editor, table.rect().bottomLeft()).y() < views
    assert field.views.height() >= field.views.minimumSizeHint().height()
    assert field.plot.height() >= field.plot.minimumHeight()  # the heat map with room for its X labels
    assert editor.status.mapTo(editor, editor.status.rect().bottomLeft()).y() <= editor.height()
