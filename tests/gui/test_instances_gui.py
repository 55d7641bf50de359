"""The window lists the objects an A2L's INSTANCEs stand for and opens their editors: the demo A2L with a few of its
objects described again as INSTANCEs (same addresses) shows the same values under both names."""

from __future__ import annotations

import pytest
from demo_instances import write_demo_instances_a2l
from gui_helpers import WAIT_MS, demo_ecu_on_a_channel_of_its_own, open_window

from workbench.gui.project import Connection, demo_project


@pytest.fixture(scope="module")
def ecu():
    yield from demo_ecu_on_a_channel_of_its_own("gui-instances")


@pytest.fixture
def window(qtbot, ecu, tmp_path):
    project = demo_project()
    project.a2l = write_demo_instances_a2l(tmp_path)
    project.connection = Connection(interface="virtual", channel=ecu[0])
    project.plots = []
    window = open_window(qtbot, project)
    yield window
    window.close()


def editor_on(window, qtbot, name: str):
    editor = window.open_editor(name)
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    return editor


def test_the_browser_lists_an_instances_objects_and_their_editors_show_the_plain_objects_values(window, qtbot):
    names = {row.name for row in window.browser.model.all_rows}
    assert {"tank.empty", "tank.switch", "tank.kp", "conv.tank", "sens.rail", "sens.volt", "convs[0]", "convs[1]",
            "pconv.curves[1]"} <= names  # an array of curves: one curve per element
    assert "INSTANCE" not in window.browser.count.text()  # nothing left out
    typed, plain = editor_on(window, qtbot, "tank.switch"), editor_on(window, qtbot, "xsSWITCH_TANK_THR")
    assert (typed.value.value, typed.value.unit) == (plain.value.value, plain.value.unit) == (20.0, "bar")
    curve, plain_curve = editor_on(window, qtbot, "conv.tank"), editor_on(window, qtbot, "zvTankPConv")
    assert curve.value.kind == "CURVE" and len(curve.value.value) == 9
    assert list(curve.value.value) == list(plain_curve.value.value)
    assert curve.value.axes == plain_curve.value.axes  # the points, their unit
    second = editor_on(window, qtbot, "convs[1]")
    assert list(second.value.value) == list(editor_on(window, qtbot, "zvRailPConv").value.value)
