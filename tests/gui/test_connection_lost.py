"""A lost ECU in the window: the simulated ECU stops while the plots measure by DAQ; the window says
"connection lost" with what and when (no dialog), pauses the measurement (a gap in the plots), tries to
reconnect, and reconnects and measures again when the ECU answers again."""

from __future__ import annotations

import time

import pytest
from gui_helpers import WAIT_MS, open_window


def test_a_lost_ecu_is_said_and_the_window_reconnects_when_it_answers_again(qtbot, project, channel):
    from workbench.sim import serve_demo

    settings = {"interface": "virtual", "channel": channel}
    with serve_demo(settings, pcm_target_bar=25.0):
        window = open_window(qtbot, project)
        window.controller.RECONNECT_MS = 200
        plot = window.plots[0]
        qtbot.waitUntil(lambda: plot.samples_shown() > 0, timeout=WAIT_MS)
    stopped = time.time()  # the ECU is gone (its power cut): the DAQ stream notices the silence
    with qtbot.waitSignal(window.controller.lost, timeout=WAIT_MS) as lost:
        pass
    assert lost.args[0].when >= stopped and window.controller.session is None
    assert not window.errors  # said in the window, not in a dialog
    banner = window.lost_banner.label.text()
    assert "Connection lost at " in banner and "nothing from the ECU" in banner and window.lost_banner.isVisible()
    assert window.status.link.text().startswith("✕ connection lost at ")
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
