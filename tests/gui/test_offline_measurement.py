"""A measurement file someone else wrote (asammdf's own writer) opened in the window with no ECU: its
channels in a plot of their own with the whole file in view, two cursors with the values and the time
between them, verbal channels by their texts, the channels in the variable browser."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import offline_window

from workbench.gui.project import demo_project
from workbench.gui.widgets.main_window import MainWindow


@pytest.fixture
def measurement_file(tmp_path):
    from asammdf import MDF, Signal

    t = np.arange(0, 10, 0.01)
    gear_table = {"raw_count": 3, "val_0": 0, "text_0": b"N", "val_1": 1, "text_1": b"FIRST", "val_2": 2,
                  "text_2": b"SECOND", "default": b""}
    mdf = MDF(version="4.10")
    mdf.append([Signal(20 + t, t, name="speed", unit="km/h", comment="vehicle speed"),
                Signal((t > 4).astype(np.uint8) + (t > 7), t, name="gear", conversion=gear_table)])
    mdf.append([Signal(np.sin(t[::10]), t[::10], name="speed", unit="")])  # a second group with a known name
    path = tmp_path / "drive.mf4"
    mdf.save(path)
    mdf.close()
    return path


def test_a_file_written_by_another_tool_is_analysed_with_two_cursors_without_an_ecu(qtbot, measurement_file):
    window = offline_window(qtbot)
    with qtbot.waitSignal(window.measurement_opened, timeout=15_000) as opened:
        window.open_measurement(measurement_file)
    plot = opened.args[0]
    assert window.controller.session is None and not window.errors
    names = plot.signals
    assert names == ["drive.mf4:group 0.speed", "drive.mf4:gear", "drive.mf4:group 1.speed"]  # one name, two groups
    (x0, x1), _ = plot.plot.vb.viewRange()
    assert x0 <= 0.0 and x1 >= 9.99 and not plot.following  # the whole file in view
    plot.cursor.setPos(2.0)
    plot.cursor2_button.setChecked(True)
    plot.cursor2.setPos(8.0)
    assert plot.value_at_cursors("drive.mf4:group 0.speed") == ("22.00", "28.00")  # no precision: by range
    assert plot.value_at_cursors("drive.mf4:gear") == ("N", "SECOND")  # by the file's value table
    assert "Δt = 6.000 s" in plot.cursor_label.textItem.toPlainText()
    assert window.browser.variable("drive.mf4:gear").plottable
    window.close()


def test_offline_a_parameter_set_is_compared_with_the_projects_s19(qtbot, tmp_path):
    from workbench.calib.dataset import save_dataset
    from workbench.calib.values import CalValue
    from workbench.image import load_image
    from workbench.sync import image_dataset

    window = offline_window(qtbot)
    dataset = image_dataset(window.workspace.model, load_image(window.project.s19))
    dataset["xsSWITCH_TANK_THR"] = CalValue("xsSWITCH_TANK_THR", "VALUE", 30.0, unit="bar")
    save_dataset(dataset, tmp_path / "tuned.cdfx")
    with qtbot.waitSignal(window.parameter_sets.compared, timeout=15_000):
        window.parameter_sets.open(tmp_path / "tuned.cdfx")
    assert window.compare.rows_shown() == ["xsSWITCH_TANK_THR"]
    assert window.compare.apply_button.isVisible()  # into the image (tests/gui/test_offline_image.py)
    assert window.compare.sides.text().startswith("A: ") and window.compare.sides.text().endswith("tuned.cdfx")


def test_a_file_that_is_no_measurement_is_one_error(qtbot, tmp_path):
    window = MainWindow(demo_project())
    qtbot.addWidget(window)
    (tmp_path / "notes.mf4").write_text("not MDF")
    window.open_measurement(tmp_path / "notes.mf4")
    qtbot.waitUntil(lambda: bool(window.errors), timeout=15_000)
    assert window.errors[0].text().startswith(f"{tmp_path / 'notes.mf4'}: not a measurement file asammdf reads")


def test_a_channel_shows_its_precision_else_as_many_decimals_as_its_range_needs(tmp_path):
    from workbench.gui.formatting import range_decimals
    from workbench.gui.offline import read_measurement_file
    from workbench.record.mdf_stream import ChannelSpec, GroupSpec, MdfStreamWriter

    t = np.arange(0, 2, 0.01)
    pressure = 22.0 + np.sin(t) * 1.2345678  # as our recorder writes a MEASUREMENT with FORMAT "%8.2"
    channels = (ChannelSpec("zsRailPressure", np.dtype("<f8"), "bar", decimals=2),
                ChannelSpec("duty", np.dtype("<f8"), "%"), ChannelSpec("count", np.dtype("<u2")))
    path = tmp_path / "ours.mf4"
    writer = MdfStreamWriter(path, [GroupSpec("Task10ms", channels)])
    writer.append(0, t, [pressure, 6.86631 * (1 + t), np.arange(len(t), dtype=np.uint16)])
    writer.close()
    found = {channel.name: channel for channel in read_measurement_file(path)}
    assert found["zsRailPressure"].decimals == 2  # the A2L's FORMAT travelled with the file
    assert found["duty"].decimals == 2 and found["count"].decimals == 0  # by range: 6.87 ... 20.4 %, whole numbers
    assert range_decimals(np.array([698.0, 699.5, 700.0])) == 2  # a small swing about a large value shows
    assert range_decimals(np.array([0.0012, 0.0031])) == 6 and range_decimals(np.array([1e-9, 3e-9])) is None
    assert range_decimals(np.array([1500.5, 6500.25])) == 0 and range_decimals(np.array([np.nan])) == 0


def test_a_can2_signal_shows_one_raw_steps_decimals_live_as_its_recording_does(demo_workspace):
    infos = {info.name: info for info in demo_workspace.can2_infos()}
    target = infos["PCM_TO_FLCU_002.TargetRailPressure"]  # factor 0.01 in the DBC
    assert target.decimals == 2 and target.format(25.0) == "25.00" and target.format(24.96) == "24.96"
    assert infos["PCM_TO_FLCU_001.EnableFLCU"].format(1.0) == "Enabled"  # a value table: its texts
