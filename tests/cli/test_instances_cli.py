"""Objects an A2L defines through typedefs (INSTANCEs), used by name end to end against the simulated ECU: a variant
of the demo A2L describes a few of its calibrations and measurements again as INSTANCEs of TYPEDEF_STRUCTUREs at the
same addresses; their names read and write the same bytes as the plain objects."""

from __future__ import annotations

import json
import re

import pytest

from workbench import demo
from workbench.cli import main
from workbench.sim import serve_demo

# xsEMPTY_TANK_THR 0x400000D8, xsSWITCH_TANK_THR 0x400000E0, xsPRV_KP 0x400000E4 (FLOAT32, Scalar_FLOAT32_IEEE);
# zvTankPConv 0x4000001C (CURVE of 9); zsSensVolt[4] 0x4002001C and zsRailPressure 0x4002004C (FLOAT32)
TYPEDEFS = '''
/begin TYPEDEF_CHARACTERISTIC T_THR "tank threshold" VALUE Scalar_FLOAT32_IEEE 0 CM_bar 0 800 /end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_CHARACTERISTIC T_KP "gain" VALUE Scalar_FLOAT32_IEEE 0 CM_PRV_KP 0 100 /end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_CHARACTERISTIC T_CONV "volts -> bar" CURVE Lookup1D_Struct_FLOAT32_IEEE 0 CM_bar 0 800
  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM_V 9 0 5 /end AXIS_DESCR
/end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_MEASUREMENT T_VOLT "volts" FLOAT32_IEEE CM_V 0 0 0 5 /end TYPEDEF_MEASUREMENT
/begin TYPEDEF_MEASUREMENT T_BAR "bar" FLOAT32_IEEE CM_bar 0 0 0 50 /end TYPEDEF_MEASUREMENT
/begin TYPEDEF_STRUCTURE Tank_T "" 0x10
  /begin STRUCTURE_COMPONENT empty T_THR 0x0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT switch T_THR 0x8 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT kp T_KP 0xC /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE Conv_T "" 0x48
  /begin STRUCTURE_COMPONENT tank T_CONV 0x0 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE Sens_T "" 0x34
  /begin STRUCTURE_COMPONENT volt T_VOLT 0x0 MATRIX_DIM 4 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT rail T_BAR 0x30 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin INSTANCE tank "" Tank_T 0x400000D8 /end INSTANCE
/begin INSTANCE conv "" Conv_T 0x4000001C /end INSTANCE
/begin INSTANCE sens "" Sens_T 0x4002001C
  /begin IF_DATA XCP /begin DAQ_EVENT VARIABLE /begin DEFAULT_EVENT_LIST EVENT 0x0000 /end DEFAULT_EVENT_LIST
  /end DAQ_EVENT /end IF_DATA
/end INSTANCE
'''


@pytest.fixture
def a2l(tmp_path):
    """The demo A2L with the typedefs and INSTANCEs added to its MODULE (its includes beside it)."""
    text = demo.a2l().read_text(encoding="latin-1")
    cut = text.rindex("/end MODULE")
    path = tmp_path / "FLCU_instances.a2l"
    path.write_text(text[:cut] + TYPEDEFS + text[cut:], encoding="latin-1")
    return str(path)


@pytest.fixture
def bus(free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
        yield ["--bus-kwargs", f"port={free_udp_port}"]


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


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


def test_an_instances_measurements_are_sampled_with_the_plain_ones(capsys, a2l, bus):
    code, out, err = run(capsys, "measure", "sens.rail", "zsRailPressure", "sens.volt[2]", "zsSensVolt[2]",
                         "--duration", "0.1", "--a2l", a2l, *bus)
    assert code == 0, err
    lines = out.splitlines()
    assert lines
    for line in lines:  # one DAQ sample: the same bytes, the same text
        fields = dict(re.findall(r"(\S+)=(\S+)", line))
        assert fields["sens.rail"] == fields["zsRailPressure"] and fields["sens.volt[2]"] == fields["zsSensVolt[2]"]
