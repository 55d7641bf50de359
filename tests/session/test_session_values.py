"""Reading and writing by name against the simulated ECU: physical values, limits, pages, EPK, partial writes."""

from __future__ import annotations

import numpy as np
import pytest
from session_helpers import FAST, edited_a2l

from workbench import EpkMismatchError, Session
from workbench.calib.values import Axis, CalValue
from workbench.errors import InputError, LimitsError, PartialWriteError, UnknownSymbolError, XcpCommandError
from workbench.xcp_protocol import Cmd, Err


def test_measurements_and_calibrations_read_in_physical_units(ecu):
    assert ecu.read("xsSWITCH_TANK_THR") == 20.0
    assert ecu.read("xsEMPTY_TANK_THR") == 5.0
    assert ecu.read("xsTankCtrlState") in ("OFF", "TANK1_ON", "TANK2_ON")  # an enum reads as its text
    volts = ecu.read("zsSensVolt")
    assert volts.shape == (4,) and np.all((volts >= 0) & (volts <= 5))
    assert ecu.read("xaPRV_FF_TARGET").tolist() == [0, 10, 20, 30, 40, 50]


def test_a_curve_and_a_map_come_with_their_axes(ecu):
    curve = ecu.read_value("zvTankPConv")
    assert curve.kind == "CURVE" and curve.unit == "bar"
    assert curve.axes[0].values[0] == 0.5 and curve.axes[0].values[-1] == 4.5
    assert curve.value[0] == 0 and curve.value[-1] == 800
    ff = ecu.read_value("xvPRV_DC_FF")
    assert ff.shape == (6, 5)  # [target, manifold]
    assert [axis.name for axis in ff.axes] == ["xaPRV_FF_TARGET", "xaPRV_FF_MANIFOLD"]
    assert ff.value[0, 0] == 0  # no duty at target 0


def test_a_batch_read_merges_neighbours(ecu, sim):
    names = ["xsSWITCH_TANK_THR", "xsEMPTY_TANK_THR", "xsFULL_TANK_PRESS", "xsPRV_KP", "xsPRV_KI", "xsPRV_KD"]
    frames_before = sim.ecu.faults._frames["rx"]
    values = ecu.read_many(names)
    batch_frames = sim.ecu.faults._frames["rx"] - frames_before
    assert values == {name: ecu.read(name) for name in names}
    assert batch_frames < len(names)


def test_a_write_is_read_back_and_lands_in_the_working_page(ecu):
    written = ecu.write("xsSWITCH_TANK_THR", 25.5)
    assert written.value == 25.5 and ecu.read("xsSWITCH_TANK_THR") == 25.5
    assert ecu.read("xsSWITCH_TANK_THR", page="reference") == 20.0  # CAL ROM keeps the flashed value
    ecu.copy_reference_to_working()
    assert ecu.read("xsSWITCH_TANK_THR") == 20.0


def test_an_enum_is_written_by_its_text(ecu):
    ecu.write("cfENABLEFLCU_VALUE", "Enabled")
    assert ecu.read("cfENABLEFLCU_VALUE") == "Enabled"
    with pytest.raises(InputError, match="Disabled.*Enabled|Enabled.*Disabled"):
        ecu.write("cfENABLEFLCU_VALUE", "Maybe")


def test_a_map_is_written_as_an_array_indexed_x_y(ecu, sim):
    ff = ecu.read_value("xvPRV_DC_FF")
    new = ff.value.copy()
    new[2, 3] = 42.0
    ecu.write("xvPRV_DC_FF", new)
    assert ecu.read("xvPRV_DC_FF")[2, 3] == 42.0
    # memory order: target (x) fastest, a float32 [manifold][target] array in C
    address = ecu.model.characteristic("xvPRV_DC_FF").address
    assert np.frombuffer(sim.ecu.read(address + 4 * (3 * 6 + 2), 4), "<f4")[0] == 42.0


def test_new_axis_points_go_into_the_curve(ecu):
    curve = ecu.read_value("zvRailPConv")
    points = curve.axes[0].values.copy()
    points[-1] = 4.6
    ecu.write("zvRailPConv", CalValue(curve.name, "CURVE", curve.value, (Axis(points, "STD_AXIS"),)))
    assert ecu.read_value("zvRailPConv").axes[0].values[-1] == pytest.approx(4.6)


def test_a_value_beyond_the_limits_is_refused_before_anything_is_sent(ecu, sim):
    frames_before = sim.ecu.faults._frames["rx"]
    with pytest.raises(LimitsError, match="xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00 bar"):
        ecu.write("xsSWITCH_TANK_THR", 900.0)
    assert sim.ecu.faults.frames_seen("rx") == frames_before  # nothing at all (tests/session/test_write_commands.py)
    assert ecu.read("xsSWITCH_TANK_THR") == 20.0


def test_a_wrong_shape_is_refused(ecu):
    with pytest.raises(LimitsError, match="shape"):
        ecu.write("xvPRV_DC_FF", np.zeros((5, 6)))


def test_measurements_are_not_written(ecu):
    with pytest.raises(InputError, match="zsRailPressure is a MEASUREMENT"):
        ecu.write("zsRailPressure", 3.0)


def test_an_unknown_name_suggests_the_closest(ecu):
    with pytest.raises(UnknownSymbolError, match="did you mean 'xsSWITCH_TANK_THR'"):
        ecu.read("xsSWITCH_TANK_TRH")


def test_a_read_only_calibration_is_refused(tmp_path, sim, channel):
    a2l = edited_a2l(tmp_path, "/* Name                   */ xsEMPTY_TANK_THR",
                     "/* Name                   */ xsEMPTY_TANK_THR")
    text = a2l.read_text(encoding="utf-8")
    start = text.index("/* Name                   */ xsEMPTY_TANK_THR")
    end = text.index("/end CHARACTERISTIC", start)
    a2l.write_text(text[:end] + "READ_ONLY\n    " + text[end:], encoding="utf-8")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        with pytest.raises(LimitsError, match="xsEMPTY_TANK_THR cannot be written \\(READ_ONLY\\)"):
            ecu.write("xsEMPTY_TANK_THR", 4.0)


def test_a_calibration_outside_writable_memory_is_refused(tmp_path, sim, channel):
    a2l = edited_a2l(tmp_path, "DATA RAM INTERN 0x40000000 0x20000", "DATA RAM INTERN 0x40000000 0x10")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        with pytest.raises(InputError, match="outside the A2L's writable memory"):
            ecu.write("xsSWITCH_TANK_THR", 21.0)


def test_a_calibration_in_an_address_space_no_memory_segment_describes_is_written(tmp_path, sim, channel):
    """XCPlite's A2L has parameters on a stack frame, behind a pointer and in application memory (address extensions
    2, 3, 128) that no MEMORY_SEGMENT describes (they describe extension 0): `cal set` refused them as 'outside the
    A2L's writable memory' before asking the ECU. The demo ECU has no extension 3: it refuses the address."""
    a2l = edited_a2l(tmp_path, "DATA RAM INTERN 0x40000000 0x20000", "DATA RAM INTERN 0x40000000 0x10")
    text = a2l.read_text(encoding="utf-8")
    start = text.index("/* Name                   */ xsSWITCH_TANK_THR")
    end = text.index("/end CHARACTERISTIC", start)
    a2l.write_text(text[:end] + "ECU_ADDRESS_EXTENSION 3\n    " + text[end:], encoding="utf-8")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        with pytest.raises(XcpCommandError, match="ERR_OUT_OF_RANGE"):  # the ECU's answer, not the A2L's check
            ecu.write("xsSWITCH_TANK_THR", 21.0)
        with pytest.raises(InputError, match="outside the A2L's writable memory"):  # extension 0 is described
            ecu.write("xsEMPTY_TANK_THR", 4.0)


def test_an_epk_mismatch_makes_the_session_read_only(tmp_path, sim, channel):
    a2l = edited_a2l(tmp_path, 'EPK "10300020250301"', 'EPK "99999920991231"')
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        assert ecu.epk.matches is False and ecu.read_only
        assert ecu.read("xsSWITCH_TANK_THR") == 20.0  # reading is fine
        with pytest.raises(EpkMismatchError, match="'99999920991231'.*'10300020250301'.*read-only"):
            ecu.write("xsSWITCH_TANK_THR", 21.0)
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST, accept_epk_mismatch=True) as ecu:
        assert ecu.write("xsSWITCH_TANK_THR", 21.0).value == 21.0


def test_a_write_failing_halfway_names_what_was_written(ecu, sim):
    curve = ecu.read_value("zvRailPConv")
    points = curve.axes[0].values + 0.01
    sim.ecu.faults.reject_command(2, Err.WRITE_PROTECTED, command=Cmd.DOWNLOAD)  # the second field's DOWNLOAD
    with pytest.raises(PartialWriteError, match="zvRailPConv is half written: .* reached the ECU"):
        ecu.write("zvRailPConv", CalValue(curve.name, "CURVE", curve.value * 0.9, (Axis(points, "STD_AXIS"),)))
