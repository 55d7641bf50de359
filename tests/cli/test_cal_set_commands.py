"""`workbench cal set` on the bus, in-process through main() on a virtual CAN bus, command by command: refused
before connecting (nothing sent), one DOWNLOAD and one read-back once connected, the page and a read-only
session refused before the write is sent."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest
from cli_helpers import run
from xcp_commands import CommandLog

from workbench import demo
from workbench.sim import serve_demo

_channels = itertools.count()
CONNECTED = ["CONNECT", "GET_COMM_MODE_INFO", "GET_STATUS", "GET_ID", "UPLOAD",  # UPLOAD: the EPK GET_ID names
             *["SET_MTA", "UPLOAD"] * 2]  # the EPK of each part: CALIB's, the application header's
WRITE = ["GET_SEED", "UNLOCK", "GET_CAL_PAGE", "SET_MTA", "DOWNLOAD", "SHORT_UPLOAD", "DISCONNECT"]


@pytest.fixture
def bus():
    channel = f"cal-set-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0) as sim, \
            CommandLog(channel) as log:
        yield ["--interface", "virtual", "--channel", channel], log, sim



@pytest.mark.parametrize("argv, message", [
    (["xsSWITCH_TANK_THR", "900"], "xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00 bar"),
    (["xsSWITCH_TANK_THR", "abc"], "xsSWITCH_TANK_THR: 'abc' is not a number (a value from 0.00 to 800.00 bar)"),
    (["cfENABLEFLCU_VALUE", "Foo"], "cfENABLEFLCU_VALUE: 'Foo' is not one of its values (Disabled, Enabled)"),
    (["xvPRV_DC_FF", "1,2,3"], "xvPRV_DC_FF has shape (6, 5), the value (3,)"),
    (["xvPRV_DC_FF[2,3]", "200"], "xvPRV_DC_FF[2, 3]: 200.00 is above the upper limit 100.00 %"),
    (["xvPRV_DC_FF[6][0]", "1"], "xvPRV_DC_FF has 6 x 5 values: x index 6 is beyond (0-5)"),
    (["xaPRV_FF_TARGET", "0,10,5,30,40,50"], "xaPRV_FF_TARGET: points 1 and 2 (10, 5) break MON_INCREASE"),
    (["zsRailPressure", "1"], "zsRailPressure is a MEASUREMENT: measurements are read, calibrations written"),
])
def test_a_refused_value_sends_nothing_not_even_connect(bus, capsys, argv, message):
    options, log, _ = bus
    code, out, err = run(capsys, "cal", "set", *argv, *options)
    assert (code, out, err) == (2, "", f"error: {message}\n")
    assert log.take() == []


@pytest.mark.parametrize("command, message", [
    (["cal", "get", "xsSWITCH_TANK_THR", "xsNOSUCH"], "unknown symbol 'xsNOSUCH'"),
    (["cal", "get", "xsNOSUCH_*"], "no object matches 'xsNOSUCH_*'"),
    (["cal", "list", "xsNOSUCH_*"], "no calibration matches 'xsNOSUCH_*'"),
    (["measure", "zsRailPressure", "zsNOSUCH", "--duration", "0.1"], "unknown symbol 'zsNOSUCH'"),
    (["measure", "zsNOSUCH", "--record", "x.mf4", "--duration", "0.1"], "unknown symbol 'zsNOSUCH'"),
    (["measure", "zsRailPressure", "--event", "Task7ms", "--duration", "0.1"], "no DAQ event 'Task7ms' (the A2L has"),
    (["measure", "zsRailPressure", "--daq", "--event", "7", "--duration", "0.1"],
     "no DAQ event '7' (the A2L has 0 Task4ms, 1 Task50ms, 2 Task100ms)"),  # not the ECU's ERR_OUT_OF_RANGE
])
def test_a_name_neither_a2l_nor_dbc_has_sends_nothing(bus, capsys, tmp_path, monkeypatch, command, message):
    """With no ECU a typo would otherwise be 'no ECU answers' after T1."""
    options, log, _ = bus
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, *command, *options)
    assert (code, out) == (2, "") and err.startswith(f"error: {message}") and err.count("\n") == 1
    assert log.take() == []


def test_a_value_is_one_download_and_one_read_back(bus, capsys):
    options, log, sim = bus
    code, out, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "20.1", *options)
    assert (code, err) == (0, "")
    assert log.take() == CONNECTED + WRITE
    assert out == "xsSWITCH_TANK_THR = 20.10 bar (written, read back)\n"  # the A2L's %.2, as cal get shows it


def test_an_enum_text_may_differ_in_case_and_reads_back_as_the_a2l_writes_it(bus, capsys):
    options, log, sim = bus
    code, out, err = run(capsys, "cal", "set", "cfENABLEFLCU_VALUE", "enabled", *options)
    assert (code, out, err) == (0, "cfENABLEFLCU_VALUE = Enabled (written, read back)\n", "")
    code, out, err = run(capsys, "cal", "set", "cfENABLEFLCU_VALUE", "DISABLED", *options)
    assert (code, out, err) == (0, "cfENABLEFLCU_VALUE = Disabled (written, read back)\n", "")


def test_a_value_may_carry_its_unit_as_cal_get_prints_it(bus, capsys):
    options, log, sim = bus
    assert run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "25.5 bar", *options) == \
        (0, "xsSWITCH_TANK_THR = 25.50 bar (written, read back)\n", "")
    assert run(capsys, "cal", "set", "xvPRV_DC_FF[1,2]", "60 %", *options)[1] == \
        "xvPRV_DC_FF[1, 2] = 60.00 % (written, read back)\n"
    assert run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "25.6bar", *options)[1] == \
        "xsSWITCH_TANK_THR = 25.60 bar (written, read back)\n"  # typed without the space
    log.take()
    assert run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "25.5 mbar", *options) == \
        (2, "", "error: xsSWITCH_TANK_THR: '25.5 mbar' is in mbar, xsSWITCH_TANK_THR in bar (no unit conversion: "
                "give a value from 0.00 to 800.00 bar)\n")  # another unit is named as such, not "not a number"
    assert run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "0x10", *options)[2] == \
        "error: xsSWITCH_TANK_THR: '0x10' is not a number (a value from 0.00 to 800.00 bar)\n"  # not 'is in x10'
    assert log.take() == []
    code, out, err = run(capsys, "cal", "fix", "zfRAILPRESSURE", "30 bar", *options)  # a fix's _VALUE alike
    assert (code, err) == (0, "") and out.startswith("zfRAILPRESSURE  ON   override 30.00 bar")


def test_a_map_cell_is_its_own_bytes_only(bus, capsys):
    options, log, sim = bus
    code, out, err = run(capsys, "cal", "set", "xvPRV_DC_FF[2,3]", "42", *options)
    assert (code, out, err) == (0, "xvPRV_DC_FF[2, 3] = 42.00 % (written, read back)\n", "")
    assert log.take() == CONNECTED + WRITE
    download = next(frame for frame in log.frames if frame.data[0] == 0xF0)
    assert download.data[1] == 4  # one float32
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *options)
    assert json.loads(out)["xvPRV_DC_FF"]["value"][2][3] == 42.0
    code, out, _ = run(capsys, "cal", "set", "xvPRV_DC_FF[0, 4]", "5", "--json", *options)
    assert (code, json.loads(out)) == (0, {"xvPRV_DC_FF[0, 4]": 5.0})


def test_one_axis_point_is_written_alone_its_order_checked_against_the_ecus_points(bus, capsys):
    """A shared axis edited point by point, as in CANape's map editor: NAME[i] of an AXIS_PTS."""
    options, log, sim = bus
    code, out, err = run(capsys, "cal", "set", "xaPRV_FF_TARGET[2]", "21", *options)
    assert (code, out, err) == (0, "xaPRV_FF_TARGET[2] = 21.00 bar (written, read back)\n", "")
    assert log.take().count("DOWNLOAD") == 1
    download = next(frame for frame in log.frames if frame.data[0] == 0xF0)
    assert download.data[1] == 4  # the one float32 point, not the axis
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *options)
    assert json.loads(out)["xvPRV_DC_FF"]["axes"][0]["points"] == [0.0, 10.0, 21.0, 30.0, 40.0, 50.0]
    log.take()
    code, out, err = run(capsys, "cal", "set", "xaPRV_FF_TARGET[2]", "35", *options)
    assert (code, out, err) == (2, "", "error: xaPRV_FF_TARGET: points 2 and 3 (35, 30) break MON_INCREASE\n")
    assert "DOWNLOAD" not in log.take()


@pytest.mark.parametrize("argv, message", [
    (["xaPRV_FF_TARGET[2]", "60"], "xaPRV_FF_TARGET[2]: 60.00 is above the upper limit 50.00 bar"),
    (["xaPRV_FF_TARGET[6]", "60"], "xaPRV_FF_TARGET has 6 points at most: index 6 is beyond (0-5)"),
    (["xaPRV_FF_TARGET[1,1]", "5"], "xaPRV_FF_TARGET has 6 points at most: give one index, not 2"),
])
def test_an_axis_point_beyond_its_limits_or_index_sends_nothing(bus, capsys, argv, message):
    options, log, _ = bus
    assert run(capsys, "cal", "set", *argv, *options) == (2, "", f"error: {message}\n")
    assert log.take() == []


def test_the_reference_page_is_refused_before_the_write_saying_how_to_switch(bus, capsys):
    options, log, sim = bus
    assert run(capsys, "cal", "page", "reference", *options)[0] == 0
    log.take()
    code, out, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "21", *options)
    assert (code, out) == (1, "")
    assert err == ("error: xsSWITCH_TANK_THR is not written: the reference page of segment 0 is active and XCP may "
                   "not write it; switch to the working page first: `workbench cal page working` "
                   "(Session.set_page('working'))\n")
    assert "DOWNLOAD" not in log.take()
    assert run(capsys, "cal", "page", "working", *options)[0] == 0
    assert run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "21", *options)[:2] == (
        0, "xsSWITCH_TANK_THR = 21.00 bar (written, read back)\n")


def test_a_read_only_session_refuses_page_switches(bus, capsys, tmp_path):
    options, log, sim = bus
    text = Path(demo.a2l()).read_text(encoding="utf-8")
    a2l = tmp_path / "other.a2l"
    a2l.write_text(text.replace('EPK "10300020250301"', 'EPK "99999920991231"'), encoding="utf-8")
    for argv in (["page", "reference"], ["page", "copy"], ["page", "copy", "--dry-run"],
                 ["set", "xsSWITCH_TANK_THR", "21"]):
        code, out, err = run(capsys, "cal", *argv, "--a2l", str(a2l), *options)
        assert (code, out) == (1, "") and "the session is read-only (no writes, no page switches)" in err
        assert log.take() == CONNECTED + ["DISCONNECT"]
    assert sim.ecu.pages.xcp_pages == sim.ecu.pages.ecu_pages == [0]
    code, out, _ = run(capsys, "cal", "page", "--a2l", str(a2l), *options)
    assert code == 0 and "segment 0: ECU on the working page, XCP on the working page" in out


def test_a_fix_override_beyond_its_limits_sends_nothing(bus, capsys):
    options, log, _ = bus
    code, out, err = run(capsys, "cal", "fix", "zfRAILPRESSURE", "900", *options)
    assert (code, out) == (2, "") and err.startswith("error: zfRAILPRESSURE_VALUE: 900.00 is above the upper limit 50.00 bar")
    assert log.take() == []


def test_without_get_id_the_epk_at_addr_epk_is_read_once(capsys):
    """A slave without GET_ID: the EPK read at ADDR_EPK is also CALIB's part; only the application header's is read
    beside it."""
    channel = f"cal-set-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}, profile="no-get-id"), CommandLog(channel) as log:
        code, _, err = run(capsys, "cal", "get", "xsSWITCH_TANK_THR", "--interface", "virtual", "--channel", channel)
        assert (code, err) == (0, "")
        assert log.take() == ["CONNECT", "GET_COMM_MODE_INFO", "GET_STATUS", "GET_ID", *["SET_MTA", "UPLOAD"] * 2,
                              "SHORT_UPLOAD", "DISCONNECT"]
