"""Recording from the window: the Record action writes what the plots measure, and CAN2 decoded with the
project's DBC, to MDF4 while the plots keep receiving; stopping finalizes the file; a refused file is a
dialog and measuring goes on."""

from __future__ import annotations

import re

import numpy as np
import pytest
from gui_helpers import WAIT_MS, open_window

from workbench.gui.project import PlotSpec


@pytest.fixture
def window(qtbot, demo_ecu, project):
    window = open_window(qtbot, project)
    yield window
    window.close()


def test_recording_the_plotted_signals_while_they_are_drawn(window, qtbot, tmp_path):
    from asammdf import MDF

    plot = window.add_plot(PlotSpec("Test", []))
    plot.add_signals(["zsRailPressure", "xsDC"])
    acquisition = window.hub.acquisition
    qtbot.waitUntil(lambda: set(acquisition.state.signals) >= {"zsRailPressure", "xsDC"}, timeout=WAIT_MS)
    path = tmp_path / "run.mf4"
    window.raw_can_action.setChecked(True)
    with qtbot.waitSignal(acquisition.recording_started, timeout=WAIT_MS):
        window.start_recording(path)
    assert window.record_action.isChecked()
    buffer = window.hub.buffer("zsRailPressure")
    shown = len(buffer)
    qtbot.waitUntil(lambda: len(buffer) > shown + 100, timeout=WAIT_MS)  # the plots are fed by the recording
    qtbot.waitUntil(lambda: acquisition.state.recorded_s > 0.5, timeout=WAIT_MS)
    window.status.refresh()
    assert re.fullmatch(r"● REC run\.mf4 · \d+ s · \d+ KiB", window.status.recording.text()), (  # not "0.0 MiB"
        window.status.link.text(), window.last_recording, [box.text() for box in window.errors])  # ended why
    plot.add_signals(["zsSensVolt"])  # shown meanwhile: measured once the recording ends
    with qtbot.waitSignal(acquisition.recording_stopped, timeout=WAIT_MS):
        window.record_action.trigger()
    stats = window.last_recording
    assert not window.record_action.isChecked() and stats.samples > 100 and stats.lost == 0
    assert stats.can_frames > 0 and stats.raw_frames > stats.can_frames
    qtbot.waitUntil(lambda: "zsSensVolt" in acquisition.state.signals, timeout=WAIT_MS)
    window.status.refresh()
    assert window.status.recording.text() == ""

    with MDF(path) as mdf:
        pressure = mdf.get("zsRailPressure")
        assert pressure.unit == "bar" and len(pressure) > 100 and np.all(np.diff(pressure.timestamps) > 0)
        assert "zsSensVolt[0]" not in mdf.channels_db
        assert np.allclose(mdf.get("TargetRailPressure").samples, 25.0)  # CAN2 through the project's DBC
        recorded = mdf.get("zsRailPressure")

    with qtbot.waitSignal(window.measurement_opened, timeout=WAIT_MS) as opened:  # the file, for analysis
        window.open_measurement(path)
    offline = opened.args[0]
    assert offline.title == "run.mf4 (offline)" and "run.mf4:zsRailPressure" in offline.signals
    assert dict(window.hub.info("run.mf4:EnableFLCU").states)[1.0] == "Enabled"  # CAN2, verbal, by the file
    t, v = window.hub.buffer("run.mf4:zsRailPressure").window(-np.inf, np.inf)
    assert np.array_equal(t, recorded.timestamps) and np.allclose(v, recorded.samples)
    assert window.browser.variable("run.mf4:xsDC").kind == "MDF"


def test_a_file_that_cannot_be_written_is_an_error_and_measuring_goes_on(window, qtbot, tmp_path):
    plot = window.plots[0] if window.plots else window.add_plot(PlotSpec("Test", ["zsRailPressure"]))
    plot.add_signals(["zsRailPressure"])
    acquisition = window.hub.acquisition
    (tmp_path / "a file").write_text("not a folder")
    with qtbot.waitSignal(acquisition.recording_stopped, timeout=WAIT_MS) as stopped:
        window.start_recording(tmp_path / "a file" / "run.mf4")
    assert stopped.args == [None] and not window.record_action.isChecked()
    qtbot.waitUntil(lambda: bool(window.errors), timeout=WAIT_MS)
    assert "cannot create" in window.errors[0].text()
    buffer = window.hub.buffer("zsRailPressure")
    count = len(buffer)
    qtbot.waitUntil(lambda: len(buffer) > count + 20, timeout=WAIT_MS)
    assert acquisition.state.running and not acquisition.recording
