"""A lost ECU in the window: "connection lost" with what and when, the measurement paused (a gap in the
plots), reconnecting by itself when the ECU answers again, measuring again after it."""

from __future__ import annotations

import pytest
from gui_helpers import WAIT_MS, open_window

from workbench.errors import ConnectionLostError


def test_a_lost_ecu_is_said_and_the_window_reconnects_when_it_answers_again(qtbot, project, channel, monkeypatch):
    from workbench.session.measure import DaqMeasurement
    from workbench.sim import serve_demo

    settings = {"interface": "virtual", "channel": channel}
    read = DaqMeasurement.read
    lost = []

    def read_until_lost(self, *args, **kwargs):  # the DAQ stream as the session reports a lost ECU
        if lost:
            raise lost[0]
        return read(self, *args, **kwargs)

    monkeypatch.setattr(DaqMeasurement, "read", read_until_lost)
    with serve_demo(settings, pcm_target_bar=25.0):
        window = open_window(qtbot, project)
        window.controller.RECONNECT_MS = 200
        plot = window.plots[0]
        qtbot.waitUntil(lambda: plot.samples_shown() > 0, timeout=WAIT_MS)
        with qtbot.waitSignal(window.controller.lost, timeout=WAIT_MS):
            lost.append(ConnectionLostError(window.controller.session.link.settings.describe(), "no DTO for 300 ms"))
    monkeypatch.setattr(DaqMeasurement, "read", read)
    assert window.controller.session is None and not window.errors  # said in the window, not a dialog
    banner = window.lost_banner.label.text()
    assert "Connection lost at " in banner and "no DTO for 300 ms" in banner and window.lost_banner.isVisible()
    assert window.status.link.text().startswith("✕ connection lost at ") and "no DTO" in window.status.link.text()
    assert window.status.daq.text().startswith("DAQ paused: ")
    qtbot.waitUntil(lambda: "attempt 2" in window.lost_banner.label.text(), timeout=WAIT_MS)  # no ECU: tries again

    with serve_demo(settings, pcm_target_bar=25.0):
        with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
            pass  # the next attempt finds the ECU
        qtbot.waitUntil(lambda: window.hub.acquisition is not None and window.hub.acquisition.state.running,
                        timeout=WAIT_MS)
        assert not window.lost_banner.isVisible() and window.status.link.text().startswith("●")
        buffer = window.hub.buffer(plot.signals[0])
        qtbot.waitUntil(lambda: buffer.gaps and buffer.last()[0] > buffer.gaps[-1], timeout=WAIT_MS)
        window.close()
    assert not window.errors or pytest.fail(f"error dialogs: {[box.text() for box in window.errors]}")
