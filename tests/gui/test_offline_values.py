"""Before any ECU is connected, the calibration editors show what the project's s19 holds (as CANape shows an offline
dataset), saying whose values they are; connected, the ECU's values replace them."""

from __future__ import annotations

import numpy as np
from demo_calibrations import FEED_FORWARD, MANIFOLD, TARGET
from gui_helpers import WAIT_MS, offline_window

from workbench.gui.project import demo_project


def test_offline_editors_show_the_s19s_values_read_only_and_say_whose(qtbot):
    window = offline_window(qtbot)
    table = window.open_editor("xvPRV_DC_FF")
    scalar = window.open_editor("xsSWITCH_TANK_THR")
    qtbot.waitUntil(lambda: table.value is not None and scalar.value is not None, timeout=WAIT_MS)
    np.testing.assert_array_equal(table.value.value, FEED_FORWARD)
    np.testing.assert_array_equal(table.field.model.x_points, TARGET)
    np.testing.assert_array_equal(table.field.model.y_points, MANIFOLD)
    assert scalar.value.value == 20.0 and scalar.field.input.text().strip() == "20.00"
    for editor in (table, scalar):  # editable offline: an edit changes the image (tests/gui/test_offline_image.py)
        assert editor.status.text() == "offline: the values of FLCU.s19; an edit changes the image (File ▸ Save image)"
        assert editor.value_source == "FLCU.s19"
    assert scalar.field.input.isEnabled() and not window.errors


def test_without_a_flash_file_the_offline_editors_stay_empty(qtbot):
    project = demo_project()
    project.s19 = None
    window = offline_window(qtbot, project)
    editor = window.open_editor("xsSWITCH_TANK_THR")
    qtbot.wait(50)
    assert editor.value is None and editor.status.text() == (
        "read-only: not connected; no values before connecting (the project names no s19/hex to show them from)")


def test_connected_the_ecus_value_replaces_the_files(qtbot, demo_ecu, project, channel):
    from workbench import Session

    with Session.open(project.a2l, interface="virtual", channel=channel) as ecu:  # the ECU apart from the s19
        ecu.write("xsSWITCH_TANK_THR", 23.0)
    window = offline_window(qtbot, project)
    editor = window.open_editor("xsSWITCH_TANK_THR")
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    assert editor.value.value == 20.0
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    qtbot.waitUntil(lambda: editor.value is not None and editor.value_source == "", timeout=WAIT_MS)
    assert editor.value.value == 23.0 and editor.field.input.isEnabled()
    assert "FLCU.s19" not in editor.status.text()
    window.close()


def brightest(toolbar, action) -> int:
    """The lightness of the brightest pixel of ``action``'s button as ``toolbar`` draws it (its text: dark theme)."""
    image = toolbar.grab(toolbar.widgetForAction(action).geometry()).toImage()
    return max(image.pixelColor(x, y).lightness() for x in range(image.width()) for y in range(image.height()))


def test_what_cannot_be_used_now_looks_so(qtbot):
    """Disabled toolbar buttons were drawn as the enabled ones (the theme gave every state its text colour):
    offline, Disconnect, Flash and Record looked as usable as Connect."""
    from PySide6.QtWidgets import QToolBar

    from workbench.gui import theme

    toolbar = QToolBar()
    qtbot.addWidget(toolbar)
    toolbar.setStyleSheet(theme.STYLE_SHEET)
    usable, unusable = toolbar.addAction("Connect"), toolbar.addAction("Disconnect")
    unusable.setEnabled(False)
    toolbar.show()
    qtbot.waitExposed(toolbar)
    assert brightest(toolbar, unusable) < brightest(toolbar, usable) - 60
