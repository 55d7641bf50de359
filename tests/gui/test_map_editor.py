"""A map's and a curve's editor against the demo ECU as a user reads them: the table and the heat map beside it run
the Y axis the same way, the first Y breakpoint on top (CANape's and INCA's way), each cell of the heat map in the
colour of its cell in the table; the operating point (where the axes' input measurements are) framed in the table and
crossed on the heat map or the curve. One window for the module, and one on an A2L with inputs on a map's axes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from gui_helpers import WAIT_MS, ecu_and_window_fixtures, open_window
from PySide6.QtCore import QPointF, Qt

from workbench import demo
from workbench.a2l import load_a2l_string
from workbench.gui import theme
from workbench.gui.a2l_info import calibration_info
from workbench.gui.widgets.operating_point import axis_position
from workbench.gui.widgets.surface_view import SurfaceView

ecu, window = ecu_and_window_fixtures("gui-map")


def heat_map_point(field, x: float, y: float):
    """Where the heat map draws the point (``x``, ``y``) of its cells' indices, in the plot widget's pixels."""
    scene = field.plot.getViewBox().mapViewToScene(QPointF(x, y))
    return field.plot.mapFromScene(scene)


def test_a_maps_table_and_heat_map_both_show_the_first_y_breakpoint_on_top_and_the_same_colours(window, qtbot):
    editor = window.open_editor("xvPRV_DC_FF")
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    field, model = editor.field, editor.field.model
    field.views.setCurrentIndex(0)
    qtbot.waitUntil(lambda: field.plot.isVisible() and field.plot.height() > 50, timeout=WAIT_MS)
    nx, ny = model.value.shape
    assert ny > 2 and len(np.unique(model.value[1])) > 2  # the map changes along Y: a flipped one would differ

    rows = [field.table.visualRect(model.index(j, 1)).top() for j in range(ny)]
    assert rows == sorted(rows) and model.headerData(0, Qt.Vertical) == f"{model.y_points[0]:.2f}"
    tops = [heat_map_point(field, 1, j).y() for j in range(ny)]
    assert tops == sorted(tops), "the heat map's first Y breakpoint is not on top, as in the table"
    assert field.axis_titles.text().replace("\u00a0", " ").startswith("↓ Y:")

    qtbot.wait(50)  # painted
    image = field.plot.grab().toImage()
    ratio = image.devicePixelRatio()
    for i in range(nx):
        for j in range(ny):
            at = heat_map_point(field, i + 0.25, j + 0.25)  # off the centre, where a grid line runs
            shown = image.pixelColor(int(at.x() * ratio), int(at.y() * ratio))
            cell = model.index(j, i).data(Qt.BackgroundRole)
            difference = max(abs(shown.red() - cell.red()), abs(shown.green() - cell.green()),
                             abs(shown.blue() - cell.blue()))
            assert difference <= 12, f"cell x={i} y={j}: heat map {shown.name()}, table {cell.name()}"


def test_a_curves_operating_point_is_its_input_measurements_live_value_framed_in_the_table_and_crossed_on_the_plot(
        window, qtbot):
    """zvRailPConv's axis has INPUT_QUANTITY zsRailVoltFilt (the demo A2L's): while its editor is open the ECU
    measures it and the editor marks where it is between the breakpoints, as CANape does."""
    editor = window.open_editor("zvRailPConv")
    field, model = editor.field, editor.field.model
    assert "zsRailVoltFilt" in window.hub.xcp_shown()

    def where_the_input_is() -> float | None:
        """The input's last sample as a fractional index of the breakpoints, by hand (None: no sample yet)."""
        last = window.hub.buffer("zsRailVoltFilt").last()
        points = model.x_points
        if last is None or len(points) < 2:
            return None
        below = int(np.searchsorted(points, last[1], side="right")) - 1  # the breakpoint at or below it
        below = min(max(below, 0), len(points) - 2)
        return below + (last[1] - points[below]) / (points[below + 1] - points[below])

    # the point follows the input (it moves: the rail pressure settles after connecting), ten times a second
    qtbot.waitUntil(lambda: field.operating_point is not None and where_the_input_is() is not None
                    and abs(field.operating_point[0] - where_the_input_is()) < 0.02, timeout=WAIT_MS)
    at = field.operating_point[0]
    assert 0 < at < len(model.x_points) - 1  # zsRailVoltFilt about 2.5 V: inside the axis
    assert model.operating_cells == {(math.floor(at),), (math.ceil(at),)}
    x, y = field.marker.getData()
    index = np.arange(len(model.x_points))
    assert x[0] == pytest.approx(np.interp(at, index, model.x_points))  # the input's volts
    assert y[0] == pytest.approx(np.interp(x[0], model.x_points, model.value))  # on the curve
    window._close_editor(window.editor_tabs.indexOf(editor))
    assert "zsRailVoltFilt" not in window.hub.shown() and field.operating_point is None


def test_the_operating_point_is_held_at_an_axis_end_and_a_falling_axis_counts_from_its_first_breakpoint():
    points = [0.5, 1.0, 2.0, 4.0]
    assert [axis_position(points, v) for v in (-3.0, 0.5, 0.75, 3.0, 4.0, 9.0)] == [0.0, 0.0, 0.5, 2.5, 3.0, 3.0]
    assert axis_position(points[::-1], 3.0) == 0.5 and axis_position(points[::-1], 0.75) == 2.5
    assert axis_position(points, float("nan")) is None and axis_position([], 1.0) is None


def with_map_inputs(text: str) -> str:
    """The demo A2L with inputs on xvPRV_DC_FF's axes: X in its AXIS_DESCR (the target pressure from CAN2), Y in its
    COM_AXIS' AXIS_PTS (the manifold pressure)."""
    at = text.index("/* Name                   */ xvPRV_DC_FF")
    end = text.index("/end CHARACTERISTIC", at)
    block = text[at:end].replace("/* Reference to Input           */ NO_INPUT_QUANTITY",
                                 "/* Reference to Input           */ csPCM_TO_FLCU_002_TargetRailPressure", 1)
    text = text[:at] + block + text[end:]
    at = text.index("/* Name                   */ xaPRV_FF_MANIFOLD")
    end = text.index("/end AXIS_PTS", at)
    block = text[at:end].replace("/* Input Quantity         */ NO_INPUT_QUANTITY",
                                 "/* Input Quantity         */ zsManifoldPressure", 1)
    return text[:at] + block + text[end:]


def test_a_maps_operating_point_frames_the_four_cells_around_it_and_crosses_the_heat_map_there(
        qtbot, demo_ecu, project, tmp_path):
    """The PCM asks for 25 bar, the manifold holds about 700 bar: between the target's breakpoints 20 and 30 and the
    manifold's 400 and 700, in table and heat map; none while disconnected."""
    project.a2l = tmp_path / "inputs.a2l"
    project.a2l.write_text(with_map_inputs(demo.a2l().read_text(encoding="utf-8")), encoding="utf-8")
    project.plots, project.editors = [], []
    window = open_window(qtbot, project)
    editor = window.open_editor("xvPRV_DC_FF")
    field, model = editor.field, editor.field.model

    def manifold_shown() -> bool:  # the point follows the manifold's pressure (it falls slowly), 25 bar stay
        last = window.hub.buffer("zsManifoldPressure").last()
        return (field.operating_point is not None and last is not None and field.operating_point[0] == 2.5
                and abs(field.operating_point[1] - (3 + (last[1] - 400.0) / 300.0)) < 0.005)

    qtbot.waitUntil(manifold_shown, timeout=WAIT_MS)
    window.resize(1366, 768)  # whatever screen this process has (Xvfb's, offscreen's 800 x 800): a laptop's
    window.resizeDocks([window.editor_dock], [426], Qt.Horizontal)  # as wide as beside the demo's plots
    window.resizeDocks([window.editor_dock, window.fix_dock], [int(768 * 0.36), int(768 * 0.5)], Qt.Vertical)
    rows = model.rowCount() * field.table.verticalHeader().defaultSectionSize()
    qtbot.waitUntil(lambda: field.table.viewport().height() >= rows, timeout=WAIT_MS)  # laid out again
    assert list(model.y_points[3:5]) == [400.0, 700.0] and 3.0 < field.operating_point[1] <= 4.0
    cells = {(2, 3), (3, 3), (2, 4), (3, 4)} if field.operating_point[1] < 4.0 else {(2, 4), (3, 4)}
    assert model.operating_cells == cells
    assert list(zip(*field.marker.getData())) == [pytest.approx(field.operating_point)]

    qtbot.wait(50)  # painted: the cells' frames and the heat map's cross, in white
    table = field.table.viewport().grab().toImage()  # visualRect() is in the viewport's pixels
    for x, y in cells:
        rect = field.table.visualRect(model.table_index((x, y)))
        assert field.table.viewport().rect().contains(rect), (x, y)  # the whole cell in sight
        frame = table.pixelColor(rect.left() + 1, rect.center().y())  # the frame's left edge, inside the cell
        assert frame.name() == theme.OPERATING_POINT, (x, y, frame.name())
    unmarked = field.table.visualRect(model.table_index((0, 0)))
    assert table.pixelColor(unmarked.left() + 1, unmarked.center().y()).name() != theme.OPERATING_POINT
    heat_map = field.plot.grab().toImage()
    at = heat_map_point(field, *field.operating_point)
    crossed = [heat_map.pixelColor(at.x() + dx, at.y() + dy).name() for dx in range(-7, 8) for dy in (-1, 0, 1)]
    assert theme.OPERATING_POINT in crossed

    field.views.setCurrentWidget(field.surface)  # the 3D view: the cross on the surface
    qtbot.waitUntil(lambda: field.surface.isVisible(), timeout=WAIT_MS)
    surface = field.surface.grab().toImage()
    at = field.surface.operating_point_on_screen()
    assert field.surface.rect().contains(at.toPoint())
    crossed = [surface.pixelColor(int(at.x()) + dx, int(at.y()) + dy).name() for dx in range(-8, 9) for dy in (-1, 0)]
    assert theme.OPERATING_POINT in crossed

    with qtbot.waitSignal(window.controller.disconnected, timeout=WAIT_MS):
        window.disconnect_action.trigger()
    qtbot.waitUntil(lambda: field.operating_point is None, timeout=WAIT_MS)
    assert not model.operating_cells and len(field.marker.getData()[0]) == 0
    assert field.surface.operating_point_on_screen() is None
    window.close()


def test_an_axis_input_is_its_input_quantity_or_its_com_axis_ones_when_that_names_a_measurement():
    text = with_map_inputs(demo.a2l().read_text(encoding="utf-8"))
    model = load_a2l_string(text, "inputs.a2l").model()
    assert calibration_info(model, "xvPRV_DC_FF").axis_inputs == ("csPCM_TO_FLCU_002_TargetRailPressure",
                                                                  "zsManifoldPressure")
    assert calibration_info(model, "zvRailPConv").axis_inputs == ("zsRailVoltFilt",)  # the demo's own
    assert calibration_info(model, "zvTankPConv").axis_inputs == (None,)  # NO_INPUT_QUANTITY
    calibration = text.replace("/* Input Quantity         */ zsManifoldPressure",
                               "/* Input Quantity         */ xsSWITCH_TANK_THR", 1)
    info = calibration_info(load_a2l_string(calibration, "calibration.a2l").model(), "xvPRV_DC_FF")
    assert info.axis_inputs == ("csPCM_TO_FLCU_002_TargetRailPressure", None)  # a CHARACTERISTIC is no input


def test_the_3d_views_operating_point_lies_on_the_surface_between_the_grid_points_around_it(qtbot):
    view = SurfaceView("x", "y")
    qtbot.addWidget(view)
    view.resize(300, 200)
    view.set_surface(np.arange(12.0).reshape(4, 3) ** 2, [0, 1, 2, 3], [0, 10, 20])
    screen, _ = view._project(view._unit_cube())  # the grid's points as drawn
    view.set_operating_point((1.0, 2.0))
    assert view.operating_point_on_screen() == QPointF(*screen[1, 2])
    view.set_operating_point((1.5, 0.5))  # halfway in a quad: its corners' mean (the projection is linear)
    middle = screen[1:3, 0:2].reshape(-1, 2).mean(axis=0)
    shown = view.operating_point_on_screen()
    assert (shown.x(), shown.y()) == (pytest.approx(middle[0]), pytest.approx(middle[1]))
    view.set_operating_point(None)
    assert view.operating_point_on_screen() is None
