"""The ECU commands end to end: workbench info, measure, cal get/set/list/fix/page against the simulated ECU
on a udp_multicast port of the test's own, output and exit codes as a user meets them."""

from __future__ import annotations

import json

import pytest

from workbench.cli import main
from workbench.sim import serve_demo


@pytest.fixture
def bus(free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}, pcm_target_bar=25.0):
        yield ["--bus-kwargs", f"port={free_udp_port}"]


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


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
    assert lines[1] == "zvTankPConv:"
    assert lines[2].split() == ["x", "0.5", "1", "1.5", "2", "2.5", "3", "3.5", "4", "4.5"]
    assert lines[3].split() == ["value", "0.00", "100.00", "200.00", "300.00", "400.00", "500.00", "600.00", "700.00",
                                "800.00", "bar"]
    assert lines[4] == "xsTankCtrlState = TANK1_ON" or lines[4].startswith("xsTankCtrlState = ")
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)
    data = json.loads(out)["xvPRV_DC_FF"]
    assert data["kind"] == "MAP" and len(data["value"]) == 6 and data["axes"][1]["name"] == "xaPRV_FF_MANIFOLD"


def test_cal_set_reads_back_and_refuses_bad_values(bus, capsys):
    code, out, _ = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "12.5", *bus)
    assert (code, out) == (0, "xsSWITCH_TANK_THR = 12.5 bar (written, read back)\n")
    code, out, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "900", *bus)
    assert (code, out) == (2, "") and err == "error: xsSWITCH_TANK_THR: 900 is above the upper limit 800 bar\n"
    code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THRX", "5", *bus)
    assert code == 2 and "did you mean 'xsSWITCH_TANK_THR'" in err
    code, _, err = run(capsys, "cal", "set", "zsRailPressure", "5", *bus)
    assert code == 2 and "MEASUREMENT" in err


def test_cal_set_a_map_from_a_file(bus, capsys, tmp_path):
    import numpy as np

    rows = [[float(x * 10 + y) for y in range(5)] for x in range(6)]
    (tmp_path / "ff.csv").write_text("\n".join(",".join(map(str, row)) for row in rows))
    code, out, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "--from", str(tmp_path / "ff.csv"), *bus)
    assert code == 0, err
    code, out, _ = run(capsys, "cal", "get", "xvPRV_DC_FF", "--json", *bus)
    assert np.array_equal(json.loads(out)["xvPRV_DC_FF"]["value"], rows)
    code, _, err = run(capsys, "cal", "set", "xvPRV_DC_FF", "[1, 2", *bus)
    assert code == 2 and "not a list" in err


def test_cal_list_and_page(bus, capsys):
    code, out, _ = run(capsys, "cal", "list", "xsPRV_K*", *bus)
    assert code == 0 and [line.split()[0] for line in out.splitlines()] == ["xsPRV_KP", "xsPRV_KI", "xsPRV_KD"]
    run(capsys, "cal", "set", "xsPRV_KP", "6", *bus)
    code, out, _ = run(capsys, "cal", "page", "copy", *bus)
    assert code == 0 and "copied the reference page" in out
    code, out, _ = run(capsys, "cal", "get", "xsPRV_KP", *bus)
    assert out.startswith("xsPRV_KP = 5")


def test_cal_fix_override_release_list(bus, capsys):
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "12.5", *bus)
    assert code == 0 and out.startswith("zfRAILPRESSURE  ON   override 12.5")
    code, out, _ = run(capsys, "cal", "fix", "--list", "--json", *bus)
    states = {item["fix"]: item for item in json.loads(out)}
    assert states["zfRAILPRESSURE"]["active"] is True and len(states) == 17
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "--release", *bus)
    assert code == 0 and "off" in out
    code, _, err = run(capsys, "cal", "fix", "RailPressure", "3", *bus)
    assert code == 2 and "2 fix calibrations" in err
    code, _, err = run(capsys, "cal", "fix", "zfRAILPRESSURE", *bus)
    assert code == 2 and "either VALUE" in err


def test_measure_polls_and_samples(bus, capsys):
    code, out, _ = run(capsys, "measure", "zsRailPressure", "xsDC", "--duration", "0.3", "--json", *bus)
    lines = [json.loads(line) for line in out.splitlines()]
    assert code == 0 and len(lines) >= 2 and lines[0]["event"] == "poll"
    assert set(lines[0]["values"]) == {"zsRailPressure", "xsDC"}
    code, out, err = run(capsys, "measure", "zsRailPressure", "--daq", "--duration", "0.5", "--json", *bus)
    times = [json.loads(line)["time"] for line in out.splitlines()]
    assert code == 0 and len(times) > 50 and times == sorted(times)
    assert "0 lost" in err


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
