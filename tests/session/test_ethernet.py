"""The same session code over XCP on UDP and TCP."""

from __future__ import annotations

import time


def test_read_write_and_daq_over_ethernet(ethernet_ecu):
    ecu = ethernet_ecu
    assert ecu.info().max_dto == 1024
    assert ecu.write("xsSWITCH_TANK_THR", 22.5).value == 22.5
    assert ecu.read_value("xvPRV_DC_FF").shape == (6, 5)
    with ecu.measure(["zsRailPressure", "zsSensVolt", "xsDC"]) as live:
        deadline, samples = time.monotonic() + 0.5, 0
        while time.monotonic() < deadline:
            samples += sum(len(batch) for batch in live.read(0.05))
    assert samples > 50 and live.stats.lost == 0
