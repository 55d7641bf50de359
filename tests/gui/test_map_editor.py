"""A map's editor against the demo ECU as a user reads it: the table and the heat map beside it run the Y axis
the same way, the first Y breakpoint on top (CANape's and INCA's way), and each cell of the heat map has the colour
of its cell in the table. One window for the module."""

from __future__ import annotations

import numpy as np
from gui_helpers import WAIT_MS, ecu_and_window_fixtures
from PySide6.QtCore import QPointF, Qt

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
