"""Calibration pages of an A2L that describes no XCP SEGMENT: the ECU's own (GET_PAG_PROCESSOR_INFO, GET_SEGMENT_INFO)
are switched and read through, segment by segment where it has no 'all segments' mode."""

from __future__ import annotations

import re

import pytest
from session_helpers import FAST, WRITE, refused_on_the_reference_page
from xcp_commands import CommandLog

from workbench import PageError, Session
from workbench.errors import XcpCommandError
from workbench.a2l import load_a2l_string, read_xcp_config
from workbench.sim import serve_demo
from workbench.sim.profiles import SlaveProfile
from workbench.xcp_protocol import Cmd, Err


def _without_segments(sim):
    """The profile's A2L with its XCP SEGMENT blocks taken out: the pages are the ECU's to tell."""
    text = sim.a2l.data.decode(sim.a2l.encoding)
    silent = load_a2l_string(re.sub(r"/begin IF_DATA XCP\s+/begin SEGMENT.*?/end SEGMENT\s+/end IF_DATA", "",
                                    text, flags=re.S), sim.a2l.path)
    assert read_xcp_config(silent).segments == ()
    return silent


def test_pages_the_ecu_says_it_has_when_the_a2l_is_silent(channel):
    with serve_demo({"interface": "virtual", "channel": channel}, profile="segments-one-by-one") as sim:
        with Session.open(_without_segments(sim), interface="virtual", channel=channel, timeouts=FAST) as ecu:
            assert [(s.number, s.address, s.size) for s in ecu.calibration_segments()] == [
                (0, 0x40000000, 0x10), (1, 0x40000010, 0x1FFF0)]
            ecu.write("xsSWITCH_TANK_THR", 24.0)
            assert ecu.read("xsSWITCH_TANK_THR", page="reference") == 20.0
            ecu.set_page("reference")
            assert sim.ecu.pages.ecu_pages == sim.ecu.pages.xcp_pages == [1, 1]
            assert [state.name(state.xcp_page) for state in ecu.info().pages] == ["reference", "reference"]
            ecu.set_page("working")
            assert ecu.read("xsSWITCH_TANK_THR") == 24.0


def test_a_write_on_the_reference_page_the_ecu_describes_is_refused_before_sending(channel):
    """The write's page check knows the segments the page switching knows: here the ECU's."""
    with serve_demo({"interface": "virtual", "channel": channel}, profile="segments-one-by-one") as sim:
        with Session.open(_without_segments(sim), interface="virtual", channel=channel, timeouts=FAST) as ecu, \
                CommandLog(channel) as log:
            refused_on_the_reference_page(ecu, log, 1)


def test_an_ecu_without_page_commands_is_asked_once_a_session(sim, channel):
    """Neither the A2L nor the ECU (ERR_CMD_UNKNOWN) has segments: no page to check, and each write after the
    first is SET_MTA, DOWNLOAD and the read-back."""
    with Session.open(_without_segments(sim), interface="virtual", channel=channel, timeouts=FAST) as ecu, \
            CommandLog(channel) as log:
        sim.ecu.faults.reject_command(1, Err.CMD_UNKNOWN, Cmd.GET_PAG_PROCESSOR_INFO)
        ecu.write("xsSWITCH_TANK_THR", 24.0)
        assert "GET_PAG_PROCESSOR_INFO" in log.take()
        assert ecu.write("xsSWITCH_TANK_THR", 23.0).value == 23.0
        assert log.take() == WRITE


@pytest.mark.parametrize("profile", ["segments", "segments-one-by-one"])
def test_a_reference_page_an_earlier_session_switched_to_is_found_before_anything_is_written(channel, profile):
    """A new session (a second `workbench cal` process) cannot know the page: it asks the ECU's segments and the
    page XCP is on (after unlocking CAL/PAG), and refuses before SET_MTA or DOWNLOAD, in either page mode."""
    with serve_demo({"interface": "virtual", "channel": channel}, profile=profile) as sim:
        a2l = _without_segments(sim)
        with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as earlier:
            earlier.set_page("reference")
        with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu, CommandLog(channel) as log:
            with pytest.raises(PageError, match="reference page of segment 1 is active"):
                ecu.write("xsSWITCH_TANK_THR", 21.0)
            asked = log.take()
            assert asked[:3] == ["GET_SEED", "UNLOCK", "GET_PAG_PROCESSOR_INFO"] and asked[-1] == "GET_CAL_PAGE"
            assert set(asked[3:-1]) == {"GET_SEGMENT_INFO"}
            with pytest.raises(PageError, match="xvPRV_DC_FF is not written: the reference page of segment 1"):
                ecu.write_cells("xvPRV_DC_FF", {(0, 0): 1.0})
            assert log.take() == []
        assert sim.ecu.pages.xcp_pages == [1, 1]


def test_a_slave_without_get_cal_page_is_read_by_page_and_put_back_on_its_working_page(channel):
    """GET_CAL_PAGE is optional: reading by page switches XCP to the reference page and back to the working page (the
    one it was set to, else the A2L's working page); it failed 'GET_CAL_PAGE failed: ERR_CMD_UNKNOWN'. The pages are
    told as this master set them, and until then the error says how to make them known."""
    quiet = SlaveProfile("no-get-cal-page", "", "", xcp={"without": frozenset({Cmd.GET_CAL_PAGE})})
    with serve_demo({"interface": "virtual", "channel": channel}, profile=quiet) as sim:
        with Session.open(sim.a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
            with pytest.raises(XcpCommandError, match=r"the ECU does not tell the pages of segment 0 \(no "
                                                      r"GET_CAL_PAGE\): switching them \(cal page working, or "
                                                      r"reference\) puts them on a known page"):
                ecu.page(0)
            ecu.write("xsSWITCH_TANK_THR", 24.0)
            try:
                assert ecu.read("xsSWITCH_TANK_THR", page="reference") == 20.0
                assert sim.ecu.pages.xcp_pages == [0]
                assert ecu.read("xsSWITCH_TANK_THR") == 24.0
                ecu.set_page("reference")
                assert (ecu.page(0).ecu_page, ecu.page(0).xcp_page) == (1, 1)  # as this master set them
                assert ecu.read("xsSWITCH_TANK_THR", page="working") == 24.0
                assert sim.ecu.pages.xcp_pages == [1]  # back where this master had set it
            finally:
                ecu.set_page("working")
                ecu.write("xsSWITCH_TANK_THR", 20.0)


def test_a_slave_without_copy_cal_page_gets_the_copy_by_upload_and_download(channel):
    """COPY_CAL_PAGE is optional: the segment is read on both pages and what differs written on the working page
    (it failed 'COPY_CAL_PAGE failed: ERR_CMD_UNKNOWN')."""
    quiet = SlaveProfile("no-copy-cal-page", "", "", xcp={"without": frozenset({Cmd.COPY_CAL_PAGE})})
    with serve_demo({"interface": "virtual", "channel": channel}, profile=quiet) as sim:
        with Session.open(sim.a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
            ecu.write("xsSWITCH_TANK_THR", 24.0)
            ecu.write("cfTARGETRAILPRESSURE_VALUE", 31.5)
            ecu.copy_reference_to_working()
            assert ecu.read("xsSWITCH_TANK_THR") == 20.0
            assert ecu.read("cfTARGETRAILPRESSURE_VALUE") == ecu.read("cfTARGETRAILPRESSURE_VALUE", page="reference")
            assert sim.ecu.pages.xcp_pages == [0]
        with sim.lock:
            assert sim.ecu.read(0x40000000, 0x20000) == sim.ecu.read(0xFC0000, 0x20000)
