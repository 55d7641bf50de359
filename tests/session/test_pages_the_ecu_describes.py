"""Calibration pages of an A2L that describes no XCP SEGMENT: the ECU's own (GET_PAG_PROCESSOR_INFO, GET_SEGMENT_INFO)
are switched and read through, segment by segment where it has no 'all segments' mode."""

from __future__ import annotations

import re

from session_helpers import FAST

from workbench import Session
from workbench.a2l import load_a2l_string, read_xcp_config
from workbench.sim import serve_demo


def test_pages_the_ecu_says_it_has_when_the_a2l_is_silent(channel):
    with serve_demo({"interface": "virtual", "channel": channel}, profile="segments-one-by-one") as sim:
        text = sim.a2l.data.decode(sim.a2l.encoding)
        silent = load_a2l_string(re.sub(r"/begin IF_DATA XCP\s+/begin SEGMENT.*?/end SEGMENT\s+/end IF_DATA", "",
                                        text, flags=re.S), sim.a2l.path)
        assert read_xcp_config(silent).segments == ()
        with Session.open(silent, interface="virtual", channel=channel, timeouts=FAST) as ecu:
            assert [(s.number, s.address, s.size) for s in ecu.calibration_segments()] == [
                (0, 0x40000000, 0x10), (1, 0x40000010, 0x1FFF0)]
            ecu.write("xsSWITCH_TANK_THR", 24.0)
            assert ecu.read("xsSWITCH_TANK_THR", page="reference") == 20.0
            ecu.set_page("reference")
            assert sim.ecu.pages.ecu_pages == sim.ecu.pages.xcp_pages == [1, 1]
            assert [state.name(state.xcp_page) for state in ecu.info().pages] == ["reference", "reference"]
            ecu.set_page("working")
            assert ecu.read("xsSWITCH_TANK_THR") == 24.0
