"""An ECU in its boot loader (the application-valid key cleared): no calibration or measurement lives there, so
reading one by name, writing, switching pages and DAQ are refused with what to do, before anything is sent;
raw memory stays readable (flashing needs it)."""

from __future__ import annotations

import pytest
from session_helpers import FAST
from xcp_commands import CommandLog

from workbench import Session, WorkbenchError
from workbench.cli import main
from workbench.sim import serve_demo

IN_BOOT = "the ECU is in its boot loader"


@pytest.fixture
def in_boot(channel):
    with serve_demo({"interface": "virtual", "channel": channel}, valid_key=False), \
            Session.open(interface="virtual", channel=channel, timeouts=FAST) as session, CommandLog(channel) as log:
        assert session.in_boot
        yield session, log


@pytest.mark.parametrize("call", [
    lambda ecu: ecu.read("xsSWITCH_TANK_THR"),       # the simulator answers zeros: 0.00 bar
    lambda ecu: ecu.read("zsRailPressure"),
    lambda ecu: ecu.read_value("xvPRV_DC_FF"),
    lambda ecu: ecu.read_many(["xsPRV_KP", "zsRailPressure"]),
    lambda ecu: ecu.write("xsSWITCH_TANK_THR", 22.0),  # was: XCP DOWNLOAD failed: ERR_CMD_UNKNOWN
    lambda ecu: ecu.set_page("reference"),
    lambda ecu: ecu.measure(["zsRailPressure"]),      # was: GET_DAQ_PROCESSOR_INFO failed: ERR_CMD_UNKNOWN
    lambda ecu: ecu.pages(),                           # cal page; was: GET_CAL_PAGE failed: ERR_CMD_UNKNOWN
    lambda ecu: ecu.on_page("working").__enter__(),    # cal save, cal load (a dataset read and written on it)
], ids=["read", "read-measurement", "read_value", "read_many", "write", "set_page", "measure", "pages", "on_page"])
def test_what_needs_the_application_is_refused_before_sending(in_boot, call):
    ecu, log = in_boot
    with pytest.raises(WorkbenchError, match=f"{IN_BOOT}.*workbench flash FILE -r APPLICATIVE -r CALIB"):
        call(ecu)
    assert log.take() == []


def test_raw_memory_stays_readable(in_boot):
    ecu, log = in_boot
    assert len(ecu.read_memory(ecu.doc.addr_epk(), 4)) == 4
    assert log.take() != []


def test_cal_get_is_one_line_and_exit_1(channel, capsys):
    with serve_demo({"interface": "virtual", "channel": channel}, valid_key=False):
        code = main(["cal", "get", "xsSWITCH_TANK_THR", "--interface", "virtual", "--channel", channel])
    out, err = capsys.readouterr()
    assert (code, out) == (1, "") and err.startswith(f"error: {IN_BOOT}") and err.count("\n") == 1


def test_a_name_read_before_the_ecu_went_to_boot_is_refused_too(channel):
    """A polled read keeps how to read a name (one command); an ECU found in boot on connecting again (a
    cancelled flash, a reset into the boot loader) refuses it like a name never read."""
    with serve_demo({"interface": "virtual", "channel": channel}):
        session = Session.open(interface="virtual", channel=channel, timeouts=FAST)
        assert session.read("xsSWITCH_TANK_THR") == pytest.approx(20.0)
    with session, serve_demo({"interface": "virtual", "channel": channel}, valid_key=False), \
            CommandLog(channel) as log:
        session.connect()
        assert session.in_boot
        log.take()
        with pytest.raises(WorkbenchError, match=IN_BOOT):
            session.read("xsSWITCH_TANK_THR")
        assert log.take() == []
