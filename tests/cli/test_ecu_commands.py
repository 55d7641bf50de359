"""The ECU commands end to end: workbench info, measure, cal get/set/list/fix/page against the simulated ECU
on a udp_multicast port of the test's own, output and exit codes as a user meets them."""

from __future__ import annotations

import io
import json
import re

import pytest
from cli_helpers import run

from workbench.cli import main
from workbench.sim import serve_demo


@pytest.fixture
def sim(free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}, pcm_target_bar=25.0) as simulator:
        yield simulator


@pytest.fixture
def bus(sim, free_udp_port):
    return ["--bus-kwargs", f"port={free_udp_port}"]



def test_info(bus, capsys):
    code, out, err = run(capsys, "info", *bus)
    assert code == 0 and err == ""
    assert "EPK           ECU '10300020250301', A2L '10300020250301': match" in out
    code, out, _ = run(capsys, "info", "--json", *bus)
    assert json.loads(out)["epk_match"] is True


def test_cal_get_shows_units_and_tables(bus, capsys):
    code, out, _ = run(capsys, "cal", "get", "xsSWITCH_TANK_THR", "zvTankPConv", "xsTankCtrlState", *bus)
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == "xsSWITCH_TANK_THR = 20.00 bar"
    assert lines[1] == "zvTankPConv: x [V], values [bar]"
    assert lines[2].split() == ["x", "0.500", "1.000", "1.500", "2.000", "2.500", "3.000", "3.500", "4.000", "4.500"]  # %6.3
    assert lines[3].split() == ["value", "0.00", "100.00", "200.00", "300.00", "400.00", "500.00", "600.00", "700.00",
                                "800.00"]
    assert lines[4] == "xsTankCtrlState = TANK1_ON" or lines[4].startswith("xsTankCtrlState = ")
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)
    data = json.loads(out)["xvPRV_DC_FF"]
    assert data["kind"] == "MAP" and len(data["value"]) == 6 and data["axes"][1]["name"] == "xaPRV_FF_MANIFOLD"


def test_a_map_is_shown_as_the_window_shows_it(bus, capsys):
    """X across, Y down (as the window and CANape), each axis named with its unit; JSON stays indexed [x][y]."""
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF", *bus)
    lines = out.splitlines()
    assert lines[0] == ("xvPRV_DC_FF: x = xaPRV_FF_TARGET [bar] across, y = xaPRV_FF_MANIFOLD [bar] down, "
                        "values [%]")
    assert lines[1].split() == ["y\\x", "0.00", "10.00", "20.00", "30.00", "40.00", "50.00"]  # the axes' %8.2
    assert [line.split()[0] for line in lines[2:]] == ["50.00", "100.00", "200.00", "400.00", "700.00"]
    assert lines[4].split() == ["200.00", "0.00", "70.00", "70.00", "70.00", "70.00", "70.00"]
    as_json = json.loads(run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)[1])["xvPRV_DC_FF"]
    table = [[float(cell) for cell in line.split()[1:]] for line in lines[2:]]
    assert [list(column) for column in zip(*table)] == as_json["value"]  # the grid is the [x][y] array turned


def test_cal_get_takes_the_globs_cal_list_takes(bus, capsys):
    code, out, _ = run(capsys, "cal", "get", "xsPRV_K*", "xsSWITCH_TANK_THR", *bus)
    assert code == 0 and [line.split()[0] for line in out.splitlines()] == ["xsPRV_KP", "xsPRV_KI", "xsPRV_KD",
                                                                            "xsSWITCH_TANK_THR"]
    listed = [line.split()[0] for line in run(capsys, "cal", "list", "xsPRV_K*", *bus)[1].splitlines()]
    assert listed == ["xsPRV_KP", "xsPRV_KI", "xsPRV_KD"]
    code, out, _ = run(capsys, "cal", "get", "zsRail[PV]*", "--json", *bus)
    assert code == 0 and set(json.loads(out)) == {"zsRailPressure", "zsRailPressureTmp", "zsRailVoltFilt"}
    code, out, err = run(capsys, "cal", "get", "xsNOTHING*", *bus)
    assert (code, out, err) == (2, "", "error: no object matches 'xsNOTHING*'\n")


def test_cal_set_reads_back_and_refuses_bad_values(bus, capsys):
    code, out, _ = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "12.5", *bus)
    assert (code, out) == (0, "xsSWITCH_TANK_THR = 12.50 bar (written, read back)\n")
    code, out, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "900", *bus)
    assert (code, out) == (2, "") and err == "error: xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00 bar\n"
    code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THRX", "5", *bus)
    assert code == 2 and "did you mean 'xsSWITCH_TANK_THR'" in err
    code, _, err = run(capsys, "cal", "set", "zsRailPressure", "5", *bus)
    assert code == 2 and "MEASUREMENT" in err


def test_cal_set_takes_what_cal_get_shows(bus, capsys, tmp_path):
    """One orientation: the tables cal get prints, each row split at its spaces into a CSV row, are what
    cal set --from takes (a map X across and Y down, a curve one row; axis points optional and written
    too); a grid that fits only turned is refused naming the rows x columns and writes nothing; what
    cal get --json printed is taken unchanged."""
    lines = run(capsys, "cal", "get", "xvPRV_DC_FF", "zvTankPConv", *bus)[1].splitlines()
    before = json.loads(run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)[1])["xvPRV_DC_FF"]["value"]
    table = [line.split() for line in lines[1:7]]
    table[3][2] = "55"  # y = 200 (the third Y point), x = 10 (the second X point)
    (tmp_path / "map.csv").write_text("\n".join(",".join(row) for row in table) + "\n")
    code, out, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(tmp_path / "map.csv"), *bus)
    assert (code, err) == (0, "") and out.splitlines()[4].split()[:3] == ["200.00", "0.00", "55.00"]
    after = json.loads(run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)[1])["xvPRV_DC_FF"]["value"]
    before[1][2] = 55.0
    assert after == before

    printed = "\n".join(lines[:7]).replace(" 70.00 ", " 71.00 ", 1)  # as printed (`cal get NAME > map.csv`)
    (tmp_path / "printed.csv").write_text(printed + "\n")
    code, out, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(tmp_path / "printed.csv"), *bus)
    assert (code, err) == (0, "") and out.splitlines()[4].split()[:4] == ["200.00", "0.00", "71.00", "70.00"]

    grid = [[float(10 * y + x) for x in range(6)] for y in range(5)]  # the values alone, 5 Y rows x 6 X columns
    (tmp_path / "values.csv").write_text("\n".join(",".join(map(str, row)) for row in grid))
    assert run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(tmp_path / "values.csv"), *bus)[0] == 0
    as_json = json.loads(run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)[1])["xvPRV_DC_FF"]
    assert as_json["value"] == [list(column) for column in zip(*grid)]  # indexed [x][y]
    turned = tmp_path / "turned.csv"
    turned.write_text("\n".join(",".join(str(row[y] + 1) for row in grid) for y in range(6)))
    code, out, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(turned), *bus)
    assert (code, out) == (2, "") and err == (f"error: {turned}: 6 rows x 5 columns of values (the file holds it "
                                              "turned); xvPRV_DC_FF takes 5 rows x 6 columns, X across, Y down, as "
                                              "`workbench cal get` prints it\n")
    as_json["value"][0][0] = 3.0
    (tmp_path / "map.json").write_text(json.dumps({"xvPRV_DC_FF": as_json}))
    assert run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(tmp_path / "map.json"), *bus)[0] == 0
    assert json.loads(run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)[1])["xvPRV_DC_FF"] == as_json

    curve = [line.split() for line in lines[8:10]]
    curve[0][1], curve[1][-1] = "0.25", "750"  # an axis point and a value
    (tmp_path / "curve.csv").write_text("\n".join(",".join(row) for row in curve))
    assert run(capsys, "cal", "set", "zvTankPConv", "--from", str(tmp_path / "curve.csv"), *bus)[0] == 0
    written = json.loads(run(capsys, "cal", "get", "zvTankPConv", "--json", *bus)[1])["zvTankPConv"]
    assert written["axes"][0]["points"][:2] == [0.25, 1.0] and written["value"][-1] == 750.0
    (tmp_path / "column.csv").write_text("\n".join(curve[1][1:]))
    code, _, err = run(capsys, "cal", "set", "zvTankPConv", "--from", str(tmp_path / "column.csv"), *bus)
    assert code == 2 and "9 rows x 1 column of values (the file holds it turned); zvTankPConv takes 1 row x 9" in err
    code, _, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "[1, 2", *bus)
    assert code == 2 and "not a list" in err


def test_cal_list_and_page(bus, capsys):
    code, out, _ = run(capsys, "cal", "list", "xsPRV_K*", *bus)
    assert code == 0 and [line.split()[0] for line in out.splitlines()] == ["xsPRV_KP", "xsPRV_KI", "xsPRV_KD"]
    code, out, _ = run(capsys, "cal", "list", "xvPRV_DC_FF", *bus)  # a row per Y point, as cal get's table
    assert out.split("[[")[1].startswith("0.00 100.00 100.00 100.00 100.00 100.00]; [0.00 100.00")
    run(capsys, "cal", "set", "xsPRV_KP", "6", *bus)
    code, out, _ = run(capsys, "cal", "page", "copy", *bus)
    assert code == 0 and "copied the reference page" in out
    code, out, _ = run(capsys, "cal", "get", "xsPRV_KP", *bus)
    assert out.startswith("xsPRV_KP = 5")


class _Terminal(io.StringIO):
    """stdin as a terminal where the user types ``text``."""

    def isatty(self) -> bool:
        return True


def test_cal_page_copy_says_what_it_overwrites_and_asks_in_a_terminal(bus, capsys, monkeypatch):
    overwritten = ("the working page 0 of segment 0 (CALRAM, 0x40000000-0x4001FFFF, 131072 bytes, 58 calibrations) "
                   "with the reference page 1")
    run(capsys, "cal", "set", "xsPRV_KP", "6", *bus)
    code, out, err = run(capsys, "cal", "page", "copy", "--dry-run", *bus)
    assert (code, err) == (0, "") and out.splitlines()[:2] == [f"copy would overwrite {overwritten}",
                                                              "dry run: nothing was copied"]
    monkeypatch.setattr("sys.stdin", _Terminal("n\n"))
    code, out, err = run(capsys, "cal", "page", "copy", *bus)
    assert (code, out) == (1, f"copy overwrites {overwritten}\n")
    assert err == ("copy the reference page onto the working page, losing every change since start-up? [y/N] "
                   "not confirmed: nothing copied\n")
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 6.0000 %/bar\n"  # nothing was copied
    monkeypatch.setattr("sys.stdin", _Terminal("y\n"))
    code, out, err = run(capsys, "cal", "page", "copy", *bus)
    assert code == 0 and "[y/N]" in err and "copied the reference page onto the working page" in out
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 5.0000 %/bar\n"
    monkeypatch.setattr("sys.stdin", _Terminal(""))  # --yes: not asked
    assert run(capsys, "cal", "page", "copy", "--yes", *bus)[::2] == (0, "")
    code, out, err = run(capsys, "cal", "page", "working", "--yes", *bus)
    assert (code, out, err) == (2, "", "error: --yes and --dry-run are for 'cal page copy'\n")


def test_cal_fix_override_release_list(bus, capsys):
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "12.5", *bus)
    assert code == 0 and out.startswith("zfRAILPRESSURE  ON   override 12.50 bar")  # the _VALUE's format
    code, out, _ = run(capsys, "cal", "fix", "--list", "--json", *bus)
    states = {item["fix"]: item for item in json.loads(out)}
    assert states["zfRAILPRESSURE"]["active"] is True and len(states) == 17
    low = states["cfFUELLEVELLOW"]  # xsLEDEn (the A2L's COMPARISON_QUANTITY) as the override's table reads it
    assert (low["live_from"], low["measured"], low["live"]) in (("xsLEDEn", "ON", "Low"), ("xsLEDEn", "OFF", "Normal"))
    code, out, _ = run(capsys, "cal", "fix", "--list", *bus)
    assert code == 0 and "live -" not in out  # every fix of the demo has a live value
    assert re.search(r"cfFUELLEVELLOW\s+off\s+override Normal\s+live (Low|Normal)\s+\(CAN signal: FUELLEVELLOW; "
                     r"xsLEDEn = (ON|OFF)\)", out)
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "--release", *bus)
    assert code == 0 and "off" in out
    code, _, err = run(capsys, "cal", "fix", "zfRAILPRESSURE", *bus)
    assert code == 2 and "either VALUE" in err


def test_cal_fix_list_reads_a_can2_signal_a_third_party_a2l_has_no_measurement_for(bus, capsys, tmp_path):
    """Without COMPARISON_QUANTITY nothing in the A2L shows FuelLevelLow: with --can2 DBC its value comes from the
    bus as sent; without, the row shows '-' and a note on stderr says why."""
    from pathlib import Path

    from workbench import demo

    a2l = tmp_path / "third_party.a2l"
    a2l.write_text(re.sub(r"\n\s*COMPARISON_QUANTITY \w+", "", Path(demo.a2l()).read_text(encoding="utf-8")),
                   encoding="utf-8")
    code, out, err = run(capsys, "cal", "fix", "--list", "--a2l", str(a2l), *bus)
    assert code == 0 and re.search(r"cfFUELLEVELLOW\s+off\s+override \S+\s+live -", out)
    assert err == ("note: cfFUELLEVELLOW: no live value: no measurement of the A2L shows FUELLEVELLOW (no "
                   "COMPARISON_QUANTITY links one, none has its name); name the CAN2 DBC to read it as sent (--can2 "
                   "DBC, fixes(can2=...))\n")
    code, out, err = run(capsys, "cal", "fix", "--list", "--a2l", str(a2l), "--can2", str(demo.dbc_can2()), *bus)
    assert (code, err) == (0, "")
    assert re.search(r"cfFUELLEVELLOW\s+off\s+override \S+\s+live (Normal|Low)\s+\(CAN signal: FUELLEVELLOW, "
                     r"CAN2 FLCU_TO_PCM_001\.FuelLevelLow\)", out), out


def test_cal_fix_takes_a_can_signal_by_the_name_the_window_shows(bus, capsys):
    code, out, _ = run(capsys, "cal", "fix", "FLCU_TO_PCM_002.RailPressure", "30", "--json", *bus)
    state = json.loads(out)[0]
    assert code == 0 and (state["fix"], state["active"], state["override"]) == ("cfRAILPRESSURE", True, 30.0)
    assert run(capsys, "cal", "fix", "FLCU_TO_PCM_002.RailPressure", "--release", *bus)[0] == 0


def test_cal_fix_shows_the_live_value_after_the_switch(bus, capsys):
    """The live value printed is the ECU's once it has used the switch: the override, then its own again."""
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "12.5", "--json", *bus)
    assert code == 0 and json.loads(out)[0]["live"] == 12.5
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "--release", "--json", *bus)
    state = json.loads(out)[0]
    assert code == 0 and state["active"] is False and state["override"] == 12.5
    assert state["live"] != 12.5  # the sensor's own pressure (the PCM asks for 25 bar)
    code, _, err = run(capsys, "cal", "fix", "RailPressure", "3", *bus)
    assert code == 2 and "2 fix calibrations" in err


def test_measure_polls_and_samples(bus, capsys):
    code, out, _ = run(capsys, "measure", "zsRailPressure", "xsDC", "--duration", "0.3", "--json", *bus)
    lines = [json.loads(line) for line in out.splitlines()]
    assert code == 0 and len(lines) >= 2 and lines[0]["event"] == "poll"
    assert set(lines[0]["values"]) == {"zsRailPressure", "xsDC"}
    code, out, err = run(capsys, "measure", "zsRailPressure", "--daq", "--duration", "0.5", "--json", *bus)
    times = [json.loads(line)["time"] for line in out.splitlines()]
    assert code == 0 and len(times) > 50 and times == sorted(times)
    assert "0 lost" in err


def test_measure_takes_can2_signals_by_the_names_the_window_plots(bus, capsys):
    """A CAN2 signal of the DBC by its bare name or as Message.Signal (the window's name), beside A2L names."""
    code, out, _ = run(capsys, "measure", "RailPressure", "zsRailPressure", "FLCU_TO_PCM_001.FuelLevelLow",
                       "--duration", "0.6", "--json", *bus)
    rows = [json.loads(line)["values"] for line in out.splitlines()]
    assert code == 0 and list(rows[0]) == ["FLCU_TO_PCM_002.RailPressure", "zsRailPressure",
                                           "FLCU_TO_PCM_001.FuelLevelLow"]
    received = [row for row in rows if row["FLCU_TO_PCM_002.RailPressure"] is not None]
    sensed = [row["zsRailPressure"] for row in rows]  # the pressure may still be rising: the frame comes every 100 ms
    assert received and min(sensed) - 1 <= received[-1]["FLCU_TO_PCM_002.RailPressure"] <= max(sensed) + 1
    assert received[-1]["FLCU_TO_PCM_001.FuelLevelLow"] in ("Normal", "Low")  # the DBC's value table
    code, out, err = run(capsys, "measure", "zsRailPressure", "RailPressure", "--daq", "--duration", "0.6", "--json",
                         *bus)
    events = [json.loads(line)["event"] for line in out.splitlines()]
    assert code == 0 and "CAN2" in events and "Task4ms" in events, err
    code, out, _ = run(capsys, "measure", "RailPressure", "FuelLevelLow", "--duration", "0.6", *bus)
    shown = [line for line in out.splitlines() if "RailPressure=-" not in line]
    assert code == 0 and shown  # one raw step of the DBC's factor 0.01: 2 decimals, as an A2L FORMAT gives
    assert re.search(r"RailPressure=\d+\.\d\d bar FLCU_TO_PCM_001.FuelLevelLow=(Normal|Low)$", shown[-1]), shown[-1]
    code, out, err = run(capsys, "measure", "Railpressure", *bus)
    assert (code, out) == (2, "") and "'RailPressure'" in err and "'zsRailPressure'" in err
    # a --can2 that names no file is said, though no NAME is one of its signals
    code, out, err = run(capsys, "measure", "zsRailPressure", "--can2", "missing.dbc", *bus)
    assert (code, out, err) == (2, "", "error: missing.dbc: no such file\n")


def test_options_that_do_nothing_there_are_refused_before_connecting(free_udp_port, capsys):
    bus = ["--bus-kwargs", f"port={free_udp_port}"]  # no ECU there: a refusal must come before connecting
    for argv, message in ((["--daq", "--rate", "5"], "--rate HZ: only when polling"),
                          (["--record", "x.mf4", "--rate", "5"], "--rate HZ: only when polling"),
                          (["--raw-can"], "--raw-can: only with --record OUT.mf4")):
        code, out, err = run(capsys, "measure", "zsRailPressure", *argv, *bus)
        assert (code, out) == (2, "") and err.startswith(f"error: {message}"), argv


def test_a_wrong_can2_dbc_is_bad_input_before_connecting(free_udp_port, capsys, tmp_path):
    bus = ["--bus-kwargs", f"port={free_udp_port}"]  # no ECU there: connecting would be exit 1
    (tmp_path / "bad.dbc").write_text("BO_ 12 Broken: 8 Vector__XXX\n SG_ x : 0|8@1+ (1,0) [0|1] \"\" Vector__XXX\nBO_ oops\n")
    for command in (["cal", "fix", "--list"], ["measure", "zsRailPressure"], ["measure", "zsRailPressure", "--record",
                    str(tmp_path / "m.mf4")], ["record", str(tmp_path / "r.mf4"), "zsRailPressure"]):
        code, out, err = run(capsys, *command, "--can2", "missing.dbc", *bus)
        assert (code, out, err) == (2, "", "error: missing.dbc: no such file\n"), command
        code, out, err = run(capsys, *command, "--can2", str(tmp_path / "bad.dbc"), *bus)
        assert (code, out) == (2, "") and err.startswith(f"error: {tmp_path / 'bad.dbc'}:") and err.count("\n") == 1, err
    assert not list(tmp_path.glob("*.mf4"))


def test_no_ecu_is_one_line_and_exit_1(free_udp_port, capsys):
    code, out, err = run(capsys, "cal", "get", "xsSWITCH_TANK_THR", "--bus-kwargs", f"port={free_udp_port}")
    assert code == 1 and out == "" and err.count("\n") == 1 and "no ECU answers" in err


def test_a_bad_a2l_is_exit_2(tmp_path, capsys):
    (tmp_path / "broken.a2l").write_text("/begin PROJECT x \"\" /begin MODULE m \"\"")
    code, _, err = run(capsys, "info", "--a2l", str(tmp_path / "broken.a2l"))
    assert code == 2 and err.startswith(f"error: {tmp_path / 'broken.a2l'}:")


def test_raw_values(bus, capsys):
    code, out, _ = run(capsys, "cal", "get", "xsTankCtrlState", "cfENABLEFLCU_VALUE", "xsSWITCH_TANK_THR", "--raw", *bus)
    lines = out.splitlines()
    assert code == 0 and lines[0] in ("xsTankCtrlState = 1", "xsTankCtrlState = 2", "xsTankCtrlState = 0")
    assert lines[1:] == ["cfENABLEFLCU_VALUE = 0", "xsSWITCH_TANK_THR = 20"]
    code, out, _ = run(capsys, "measure", "xsTankCtrlState", "--duration", "0.15", "--json", "--raw", *bus)
    assert isinstance(json.loads(out.splitlines()[0])["values"]["xsTankCtrlState"], int)


def test_an_erased_epk_reads_as_erased(sim, bus, capsys):
    area = sim.ecu.memory.area_at(sim.ecu.params.epk_address, sim.ecu.params.epk_length)
    start = sim.ecu.params.epk_address - area.start
    area.data[start:start + sim.ecu.params.epk_length] = b"\xff" * sim.ecu.params.epk_length  # as after an erase
    code, out, _ = run(capsys, "info", *bus)
    assert "EPK           ECU erased (14 bytes FF), A2L '10300020250301': MISMATCH (read-only)" in out
    code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "12", *bus)
    assert code == 1 and "ECU has erased (14 bytes FF)" in err and "\xff" not in err


def test_reading_by_name_with_another_software_s_a2l_warns_once(sim, bus, capsys, tmp_path):
    """An A2L of other software reads values at addresses that may hold other things: measure and cal get say
    so on stderr (they said nothing: CANape asks), a write refuses in its one error line, info shows it."""
    from workbench import demo

    other = tmp_path / "other.a2l"
    other.write_bytes(demo.a2l().read_bytes().replace(b"10300020250301", b"10300020250999"))
    a2l = ["--a2l", str(other)]
    for command in (["cal", "get", "xsSWITCH_TANK_THR"], ["measure", "xsDC", "--duration", "0.1"],
                    ["cal", "fix", "--list"]):
        code, out, err = run(capsys, *command, *a2l, *bus)
        assert code == 0 and out, command
        assert err.splitlines()[0] == ("warning: EPK MISMATCH: A2L '10300020250999', ECU '10300020250301' (GET_ID): "
                                       "the values are read at this A2L's addresses, which may not hold them in the "
                                       "ECU's software"), command
    code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "12", *a2l, *bus)
    assert code == 1 and len(err.splitlines()) == 1 and err.startswith("error: EPK mismatch")
    code, out, err = run(capsys, "info", *a2l, *bus)
    assert code == 0 and err == "" and "MISMATCH (read-only)" in out


def test_names_may_follow_the_bus_kwargs(bus, capsys):
    """python-can's --bus-kwargs takes every word after it: `measure --bus-kwargs port=N zsRailPressure` was
    'Unable to parse bus keyword argument' (user trial 6); a word without '=' is the command's own."""
    code, out, _ = run(capsys, "cal", "set", *bus, "xsSWITCH_TANK_THR", "21.5")
    assert code == 0 and out == "xsSWITCH_TANK_THR = 21.50 bar (written, read back)\n"
    code, _, err = run(capsys, "cal", "set", *bus, "xsSWITCH_TANK_THR", "-5")  # a negative number is a value too
    assert code == 2 and err == "error: xsSWITCH_TANK_THR: -5.00 is below the lower limit 0.00 bar\n"
    code, out, _ = run(capsys, "measure", *bus, "xsSWITCH_TANK_THR", "xsDC", "--duration", "0.1", "--json")
    assert code == 0 and set(json.loads(out.splitlines()[0])["values"]) == {"xsSWITCH_TANK_THR", "xsDC"}
    code, out, _ = run(capsys, "cal", "get", "--bus-kwargs", bus[1], "bitrate=500000", "xsSWITCH_TANK_THR")
    assert code == 0 and out == "xsSWITCH_TANK_THR = 21.50 bar\n"


def test_epk_text():
    from workbench.errors import epk_text

    assert epk_text("10300020250301\0\0") == "'10300020250301'"
    assert epk_text("\xff" * 4) == "erased (4 bytes FF)" and epk_text("\0" * 2) == "empty (2 bytes 00)"
    assert epk_text("10\xff\x01") == "bytes 31 30 FF 01"


def test_convert_help_names_only_options_it_has(capsys):
    assert main(["cal", "convert", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "--a2l" not in text and "Exit 0: written" in text


def test_a_can2_bus_on_a_udp_port_of_its_own_is_named_by_can2_bus_kwargs(free_udp_port, another_free_udp_port, capsys):
    """``workbench sim`` puts CAN2 on a udp_multicast port of its own and ``measure`` finds it there, both by
    --can2-bus-kwargs (the XCP bus's port alone would hear no CAN2 frame: python-can binds a port for every group)."""
    from sim_process import start_sim_process

    xcp = ["--interface", "udp_multicast", "--bus-kwargs", f"port={free_udp_port}"]
    can2 = ["--can2-channel", "239.74.163.9", "--can2-bus-kwargs", f"port={another_free_udp_port}"]
    simulator, banner = start_sim_process(*xcp, *can2, "--pcm", "--no-control")
    try:
        code, out, err = run(capsys, "measure", "RailPressure", "zsRailPressure", "--duration", "1", "--json",
                             *xcp, *can2)
    finally:
        simulator.kill()
        simulator.communicate(timeout=10)
    rows = [json.loads(line)["values"] for line in out.splitlines()]
    assert code == 0, err
    assert [row for row in rows if row["FLCU_TO_PCM_002.RailPressure"] is not None], out


def test_an_a2l_never_updated_from_the_elf_is_named_as_the_cause(bus, capsys, tmp_path):
    """The merged fragments before `a2l update` hold address 0 everywhere: the ECU refuses to read there,
    and the message names the object, where, and the likely cause with the command that fixes it (it was
    the bare 'XCP SHORT_UPLOAD failed: ERR_OUT_OF_RANGE')."""
    from pathlib import Path

    a2l = Path(__file__).parents[2] / "a2l"
    merged = tmp_path / "merged.a2l"
    assert run(capsys, "a2l", "merge", str(a2l / "FLCU_master.a2l"), *map(str, sorted((a2l / "modules").glob("*.a2l"))),
               "-o", str(merged))[0] == 0
    code, out, err = run(capsys, "cal", "get", "xsPRV_KP", "--a2l", str(merged), *bus)
    assert (code, out) == (1, "")
    assert err == ("error: reading xsPRV_KP (0x0..0x3) (address 0: an A2L not yet updated from the build's ELF? "
                   "workbench a2l update IN.a2l ELF -o OUT.a2l): XCP SHORT_UPLOAD failed: ERR_OUT_OF_RANGE (0x22)\n")
    code, _, err = run(capsys, "measure", "zsRailPressure", "--daq", "--duration", "0.2", "--a2l", str(merged), *bus)
    assert code == 1 and "(address 0: an A2L not yet updated" in err and "WRITE_DAQ failed: ERR_OUT_OF_RANGE" in err


def test_a_decimal_comma_is_named_as_such(bus, capsys):
    """German-style input: '3,5' for a single value is a decimal comma (it was read as a list of two, refused
    as 'the value has shape (2,)'); a curve's '1,2,3' stays a list."""
    code, out, err = run(capsys, "cal", "set", "xsPRV_KP", "3,5", *bus)
    assert (code, out, err) == (2, "", "error: '3,5' is not a number: write a decimal point (3.5)\n")
    code, _, err = run(capsys, "cal", "set", "xvPRV_DC_FF[1,2]", "7,5", *bus)
    assert (code, err) == (2, "error: '7,5' is not a number: write a decimal point (7.5)\n")
    code, _, err = run(capsys, "cal", "fix", "zfRAILPRESSURE", "12,3", *bus)
    assert (code, err) == (2, "error: '12,3' is not a number: write a decimal point (12.3)\n")


def test_a_semicolon_csv_is_named_as_such(bus, capsys, tmp_path):
    """A spreadsheet saves CSV as 1,5;2,5 where the decimal mark is a comma: it was read as 5 rows x 1 column."""
    grid = tmp_path / "map.csv"
    grid.write_text("\n".join(";".join(f"{x},5" for x in range(6)) for _ in range(5)) + "\n")
    code, out, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(grid), *bus)
    assert (code, out) == (2, "") and err == (f"error: {grid}:1: values apart by ';' (a spreadsheet's CSV with decimal "
                                              "commas?): write them apart by ',' with decimal points, or as cal get "
                                              "prints them\n")


def test_cal_get_takes_a_cell_as_cal_set_does(bus, capsys):
    """NAME[x,y] reads one value of a map (indexed as cal set writes it), NAME[i] one of a curve."""
    assert run(capsys, "cal", "set", "xvPRV_DC_FF[2,3]", "42", *bus)[0] == 0
    code, out, err = run(capsys, "cal", "get", "xvPRV_DC_FF[2,3]", "zvRailPConv[3]", *bus)
    assert (code, err) == (0, "")
    assert out.splitlines()[0] == "xvPRV_DC_FF[2, 3] = 42.00 %"
    assert re.fullmatch(r"zvRailPConv\[3\] = \d+\.\d\d bar", out.splitlines()[1])
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF[2][3]", "--json", *bus)
    assert json.loads(out) == {"xvPRV_DC_FF[2, 3]": 42.0}
    code, _, err = run(capsys, "cal", "get", "xvPRV_DC_FF[9,3]", *bus)
    assert (code, err) == (2, "error: xvPRV_DC_FF has 6 x 5 values: x index 9 is beyond (0-5)\n")


def test_measure_takes_globs_and_records_can2_signals_by_name(bus, capsys, tmp_path):
    """measure 'zsRail*' as cal get takes globs (DAQ: its measurements only); --record takes the CAN2 names plain
    measure takes (it refused them as unknown A2L symbols); a calibration for DAQ says how to read it."""
    code, out, _ = run(capsys, "measure", "zsRail*", "--duration", "0.25", "--json", *bus)
    assert code == 0 and list(json.loads(out.splitlines()[-1])["values"]) == ["zsRailVoltFilt", "zsRailPressureTmp",
                                                                           "zsRailPressure"]
    assert run(capsys, "measure", "xs*THR", "--daq", "--duration", "0.2", *bus)[2] == \
        "error: no measurement matches 'xs*THR'\n"
    code, out, err = run(capsys, "measure", "FuelLevel", "zsRailPressure", "--record", str(tmp_path / "r.mf4"),
                         "--duration", "0.5", *bus)
    assert code == 0 and "CAN2 frames decoded" in out, err
    from asammdf import MDF

    with MDF(tmp_path / "r.mf4") as mdf:
        assert "FuelLevel" in mdf.channels_db and any(name.endswith("zsRailPressure") for name in mdf.channels_db)
    code, _, err = run(capsys, "measure", "xvPRV_DC_FF", "--daq", "--duration", "0.2", *bus)
    assert (code, err) == (2, "error: xvPRV_DC_FF is a CHARACTERISTIC (MAP): DAQ samples MEASUREMENTs and VALUE or "
                              "VAL_BLK calibrations; read it by polling (measure without --daq, or Session.read)\n")


def test_a_udp_multicast_port_given_as_port_is_named(capsys):
    """--port is XCP on Ethernet's; `--interface udp_multicast --port N` meant the bus's own port (user trial 6)."""
    code, _, err = run(capsys, "info", "--interface", "udp_multicast", "--port", "43210")
    assert code == 2 and err == ("error: port=43210 (--port) is XCP on Ethernet's, beside host= (--host); the port of a "
                                 "udp_multicast CAN bus goes in bus_kwargs={'port': 43210} (--bus-kwargs port=43210)\n")


def test_measure_takes_one_element_of_an_array(bus, capsys):
    """NAME[i] as CANape lists an array's elements: the array is read (polled or by DAQ), the element shown (it
    was 'no object matches': the brackets read as a glob; user trial 6)."""
    for daq in ([], ["--daq"]):
        code, out, _ = run(capsys, "measure", "zsSensVolt[3]", "zsSensVolt", "--duration", "0.1", "--json", *daq, *bus)
        lines = [json.loads(line)["values"] for line in out.splitlines()]
        assert code == 0 and lines and all(set(v) == {"zsSensVolt[3]", "zsSensVolt"} for v in lines), daq
        assert all(v["zsSensVolt[3]"] == v["zsSensVolt"][3] for v in lines)
    code, out, _ = run(capsys, "measure", "xvPRV_DC_FF[1,2]", "--duration", "0.05", *bus)
    assert code == 0 and re.fullmatch(r"\d+\.\d{4} xvPRV_DC_FF\[1, 2\]=70\.00 %", out.splitlines()[0])
    code, _, err = run(capsys, "measure", "zsSensVolt[4]", *bus)
    assert code == 2 and err == "error: zsSensVolt has 4 elements: index 4 is beyond (0-3)\n"


def test_info_saves_the_a2l_the_ecu_holds(capsys, tmp_path, free_udp_port):
    """`workbench info --host H --port P --save-a2l ecu.a2l`: XCPlite's own A2L (GET_ID 4), written atomically; the
    next commands take it with --a2l."""
    from workbench.sim import EthernetEndpoint

    with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", free_udp_port, "UDP")) as simulator:
        where = ["--host", "127.0.0.1", "--port", str(free_udp_port)]
        code, out, err = run(capsys, "info", *where, "--save-a2l", str(tmp_path / "ecu.a2l"))
        assert (code, err) == (0, "") and f"the ECU's own written to {tmp_path / 'ecu.a2l'}" in out
        assert (tmp_path / "ecu.a2l").read_bytes() == bytes(simulator.a2l.data)
        code, out, _ = run(capsys, "cal", "get", "xsSWITCH_TANK_THR", "--a2l", str(tmp_path / "ecu.a2l"), *where)
        assert (code, out) == (0, "xsSWITCH_TANK_THR = 20.00 bar\n")


def test_a_daq_list_can_id_the_ecu_refuses_is_one_line(bus, capsys):
    """--daq-can-id reaches SET_DAQ_ID, which the demo, whose lists all send on CAN_ID_SLAVE, does not implement."""
    code, out, err = run(capsys, "measure", "zsRailPressure", "--daq", "--duration", "0.2", "--daq-can-id", "0=0x7F6",
                         *bus)
    assert (code, out) == (1, "")
    assert err == ("error: moving DAQ list 0's DTOs to CAN id 0x7F6: XCP TRANSPORT_LAYER_CMD SET_DAQ_ID failed: "
                   "ERR_CMD_UNKNOWN (0x20)\n")
    assert run(capsys, "measure", "zsRailPressure", "--daq", "--daq-can-id", "0x7F6", *bus)[0] == 2


def test_a_bus_option_the_can2_bus_would_ignore_is_refused_in_one_line(bus, capsys):
    """Refused where the bus is opened (for a script as for the CLI): prot would leave CAN2 on the default port. The
    line names the bus, as the simulator's does: --bus-kwargs and --can2-bus-kwargs both give bus options."""
    code, out, err = run(capsys, "measure", "RailPressure", "--duration", "1", *bus, "--can2-bus-kwargs", "prot=1")
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert err.startswith("error: CAN2: bus option prot=1: python-can's udp_multicast bus has no option 'prot' and "
                          "would ignore it (did you mean port? ")
