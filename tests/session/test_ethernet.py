"""The same session code over XCP on UDP and TCP."""

from __future__ import annotations

import time

import pytest
from session_helpers import FAST

from workbench import Session
from workbench.errors import WorkbenchError
from workbench.sim import EthernetEndpoint, serve_demo


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


def test_the_a2l_the_ecu_holds_is_uploaded_by_get_id_4(free_udp_port):
    """XCPlite generates its A2L at run time and offers it by GET_ID 4 (CANape loads it so); the simulator offers the A2L
    it was served with. Byte for byte, 136 KB in slave block mode; a slave without GET_ID says it offers none."""
    for profile in ("demo", "no-get-id"):
        with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", free_udp_port, "UDP"), profile=profile) as simulator, \
                Session.open(simulator.a2l, host="127.0.0.1", port=free_udp_port, timeouts=FAST) as session:
            if profile == "demo":
                assert session.ecu_a2l() == bytes(simulator.a2l.data)
            else:
                with pytest.raises(WorkbenchError, match=r"the ECU offers no A2L to upload \(GET_ID 4: ERR_CMD_UNKNOWN"):
                    session.ecu_a2l()
