"""Objects an A2L defines through typedefs (INSTANCEs), used by name end to end against the simulated ECU: a variant
of the demo A2L describes a few of its calibrations and measurements again as INSTANCEs of TYPEDEF_STRUCTUREs at the
same addresses; their names read and write the same bytes as the plain objects."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from cli_helpers import run
from demo_instances import write_demo_instances_a2l

from workbench.sim import serve_demo


@pytest.fixture
def a2l(tmp_path):
    return str(write_demo_instances_a2l(tmp_path))


@pytest.fixture
def bus(free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
        yield ["--bus-kwargs", f"port={free_udp_port}"]



def _values(capsys, a2l, bus, *names) -> dict:
    code, out, err = run(capsys, "cal", "get", *names, "--json", "--a2l", a2l, *bus)
    assert code == 0, err
    return {name: entry["value"] for name, entry in json.loads(out).items()}


def test_an_instances_names_read_and_write_the_plain_objects_bytes(capsys, a2l, bus):
    pairs = {"tank.empty": "xsEMPTY_TANK_THR", "tank.switch": "xsSWITCH_TANK_THR", "tank.kp": "xsPRV_KP",
             "conv.tank": "zvTankPConv"}
    values = _values(capsys, a2l, bus, *pairs, *pairs.values())
    assert all(values[typed] == values[plain] for typed, plain in pairs.items())
    code, out, err = run(capsys, "cal", "set", "tank.switch", "30", "--a2l", a2l, *bus)
    assert (code, out) == (0, "tank.switch = 30.00 bar (written, read back)\n"), err
    assert _values(capsys, a2l, bus, "xsSWITCH_TANK_THR") == {"xsSWITCH_TANK_THR": 30.0}
    code, out, err = run(capsys, "cal", "set", "conv.tank[2]", "222", "--a2l", a2l, *bus)
    assert code == 0, err
    assert _values(capsys, a2l, bus, "zvTankPConv")["zvTankPConv"][2] == 222.0
    code, out, _ = run(capsys, "cal", "list", "tank.*", "--a2l", a2l, *bus)
    assert code == 0 and [line.split()[0] for line in out.splitlines()] == ["tank.empty", "tank.switch", "tank.kp"]


def test_the_elements_of_an_array_of_curves_are_the_curves_one_after_the_other(capsys, a2l, bus, tmp_path):
    # INSTANCE convs: T_CONV MATRIX_DIM 2; pconv: a structure whose component is T_CONV MATRIX_DIM 2
    pairs = {"convs[0]": "zvTankPConv", "convs[1]": "zvRailPConv", "pconv.curves[1]": "zvRailPConv"}
    values = _values(capsys, a2l, bus, *pairs, *pairs.values())
    assert values["zvTankPConv"] != values["zvRailPConv"]
    assert all(values[typed] == values[plain] for typed, plain in pairs.items())
    code, _, err = run(capsys, "cal", "set", "convs[1][3]", "333", "--a2l", a2l, *bus)
    assert code == 0, err
    assert _values(capsys, a2l, bus, "zvRailPConv")["zvRailPConv"][3] == 333.0
    dataset = tmp_path / "convs.dcm"
    code, _, err = run(capsys, "cal", "save", str(dataset), "pconv.*", "--a2l", a2l, *bus)
    assert code == 0, err
    text = dataset.read_text(encoding="latin-1")
    assert "pconv.curves[0]" in text and "pconv.curves[1]" in text and "333" in text


def test_an_instances_measurements_are_sampled_with_the_plain_ones(capsys, a2l, bus):
    code, out, err = run(capsys, "measure", "sens.rail", "zsRailPressure", "sens.volt[2]", "zsSensVolt[2]",
                         "--daq", "--duration", "0.2", "--a2l", a2l, *bus)
    assert code == 0, err
    lines = out.splitlines()
    assert lines
    for line in lines:  # one DAQ sample: the same bytes, the same text
        fields = dict(re.findall(r"(\S+)=(\S+)", line))
        assert fields["sens.rail"] == fields["zsRailPressure"] and fields["sens.volt[2]"] == fields["zsSensVolt[2]"]


@pytest.mark.parametrize("suffix", ["dcm", "cdfx"])
def test_a_dataset_of_an_instances_names_saves_and_loads(capsys, a2l, bus, tmp_path, suffix):
    path = str(tmp_path / f"tank.{suffix}")
    code, _, err = run(capsys, "cal", "save", path, "tank.*", "conv.tank", "--a2l", a2l, *bus)
    assert code == 0, err
    text = (tmp_path / f"tank.{suffix}").read_text(encoding="utf-8", errors="replace")
    assert "tank.switch" in text and "conv.tank" in text
    assert run(capsys, "cal", "set", "tank.switch", "31", "--a2l", a2l, *bus)[0] == 0
    code, _, err = run(capsys, "cal", "load", path, "--a2l", a2l, *bus)
    assert code == 0, err
    assert _values(capsys, a2l, bus, "xsSWITCH_TANK_THR") == {"xsSWITCH_TANK_THR": 20.0}  # the saved value again


def test_check_places_an_instances_objects(capsys, a2l, tmp_path):
    """`a2l check` puts the objects of an INSTANCE into the overlap, segment and CAL RAM checks: the INSTANCE moved
    from CAL RAM into the CALIB flash is an error per calibration at its address; where it was, its objects repeat
    the plain calibrations' bytes (warnings: this variant describes them twice on purpose)."""
    code, out, _ = run(capsys, "a2l", "check", a2l)
    assert code == 1 and "error" not in out
    assert ": warning: CHARACTERISTIC tank.kp of INSTANCE tank occupies the same 4 byte(s) at 0x400000E4 as " \
           "CHARACTERISTIC xsPRV_KP" in out
    moved = tmp_path / "moved.a2l"
    text = Path(a2l).read_text(encoding="latin-1").replace("Tank_T 0x400000D8", "Tank_T 0xFC00D8")
    moved.write_text(text, encoding="latin-1")
    line = next(n for n, row in enumerate(text.splitlines(), 1) if "Tank_T 0xFC00D8" in row)
    code, out, err = run(capsys, "a2l", "check", moved)
    errors = [row for row in out.splitlines() if ": error: " in row]
    assert code == 1 and len(errors) == 3 and err.count("\n") == 1
    assert errors[0].startswith(f"{moved}:{line}:") and errors[0].endswith(
        "error: CHARACTERISTIC tank.empty of INSTANCE tank at 0xFC00D8 is in CALIB (DATA FLASH), not in a DATA RAM "
        "segment (CALRAM)")
