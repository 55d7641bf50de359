"""The window's DAQ acquisition when its session closes under it (the window closed, Disconnect, another project)
while DAQ starts: nothing to say, the user closed it (CI: "the XCP link is closed" as an error dialog)."""

from __future__ import annotations

import threading

from workbench import Session, demo
from workbench.gui.acquisition import DaqAcquisition


def test_a_session_closed_while_daq_starts_is_no_failure(qtbot, demo_ecu, channel):
    session = Session.open(demo.a2l(), interface="virtual", channel=channel)
    starting, closed = threading.Event(), threading.Event()
    measure = session.measure

    def measure_that_starts_after_the_close(names):
        measurement = measure(names)
        start = measurement.start

        def start_after_the_close():
            starting.set()
            closed.wait(10)
            return start()

        measurement.start = start_after_the_close
        return measurement

    session.measure = measure_that_starts_after_the_close
    acquisition = DaqAcquisition(session, lambda name, times, values: None, 0.0)
    failures = []
    acquisition.failed.connect(failures.append)
    acquisition.measure(("zsRailPressure",))
    assert starting.wait(10)
    session.close()
    closed.set()
    qtbot.wait(300)
    acquisition.stop()
    qtbot.wait(50)
    assert failures == []
