"""Fix calibrations through the session: every pair listed, override and release, ambiguity refused."""

from __future__ import annotations

import time

import pytest

from workbench.errors import InputError


def wait_for(condition, seconds: float = 2.0) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.02)
    return False


def test_every_fixable_signal_is_listed_with_its_values(ecu):
    states = {state.pair.stem: state for state in ecu.fixes()}
    assert len(states) == 17
    rail = states["zfRAILPRESSURE"]
    assert rail.signal == "zsRailPressure" and rail.active is False and rail.override == 0.0
    # the PCM enables the FLCU: live in the override's terms (its verbal table), the measurement's own beside
    assert wait_for(lambda: ecu.fix_state("cfENABLEFLCU").live == "Enabled")
    assert ecu.fix_state("cfENABLEFLCU").measured == "ON"
    # a sent signal computed under an abbreviated name: RailPSDiagnosticStatus from xsRailPSDiagStatus
    assert states["cfRAILPSDIAGNOSTICSTATUS"].pair.live == "xsRailPSDiagStatus"
    assert states["cfRAILPSDIAGNOSTICSTATUS"].live == "NO_ERROR"
    # FuelLevelLow is sent from xsLEDEn: no name tells, the A2L's COMPARISON_QUANTITY does
    low = states["cfFUELLEVELLOW"]
    assert low.pair.live == "xsLEDEn" and (low.measured, low.live) in (("ON", "Low"), ("OFF", "Normal"))
    assert all(state.pair.live is not None for state in states.values())


def test_an_override_writes_value_then_enable_and_a_release_gives_the_signal_back(ecu):
    state = ecu.override("cfTARGETRAILPRESSURE", 30.0)
    assert state.active and state.override == pytest.approx(30.0)
    assert wait_for(lambda: ecu.read("csPCM_TO_FLCU_002_TargetRailPressure") == pytest.approx(30.0))
    state = ecu.release("TargetRailPressure")
    assert not state.active
    assert wait_for(lambda: ecu.read("csPCM_TO_FLCU_002_TargetRailPressure") == pytest.approx(25.0))


def test_a_name_two_fixes_share_is_refused(ecu):
    with pytest.raises(InputError, match="'RailPressure' has 2 fix calibrations: cfRAILPRESSURE .*zfRAILPRESSURE"):
        ecu.override("RailPressure", 10.0)


def test_a_can_signal_no_measurement_shows_is_read_from_can2_by_the_dbc_or_says_why_not(sim, channel, tmp_path):
    """A third-party A2L: the fix pairs without COMPARISON_QUANTITY, and FuelLevelLow (sent from xsLEDEn) has no
    measurement of its name. The DBC finds it by the fix's name, as the window does; without one, or when its
    message does not come, the state says why there is no live value."""
    import re
    from pathlib import Path

    from session_helpers import FAST

    from workbench import Session, demo
    from workbench.bus_defaults import BusSpec

    a2l = tmp_path / "third_party.a2l"
    a2l.write_text(re.sub(r"\n\s*COMPARISON_QUANTITY \w+", "", Path(demo.a2l()).read_text(encoding="utf-8")),
                   encoding="utf-8")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        state = {state.pair.stem: state for state in ecu.fixes()}["cfFUELLEVELLOW"]
        assert (state.live, state.live_from) == (None, None)
        assert state.no_live == ("no measurement of the A2L shows FUELLEVELLOW (no COMPARISON_QUANTITY links one, "
                                 "none has its name); name the CAN2 DBC to read it as sent (--can2 DBC, "
                                 "fixes(can2=...))")
        states = {state.pair.stem: state for state in ecu.fixes(demo.dbc_can2())}
        state = states["cfFUELLEVELLOW"]
        assert state.live in ("Normal", "Low") and state.live_from == "CAN2 FLCU_TO_PCM_001.FuelLevelLow"
        assert state.no_live is None
        assert states["zfRAILPRESSURE"].live_from == "zsRailPressure"  # the A2L's measurements stay first
        silent = BusSpec("virtual", f"{channel}-nothing")
        state = {state.pair.stem: state for state in ecu.fixes(demo.dbc_can2(), can2_bus=silent)}["cfFUELLEVELLOW"]
        assert state.live is None and state.no_live.endswith(
            f"; CAN2 FLCU_TO_PCM_001.FuelLevelLow: FLCU_TO_PCM_001 did not come on CAN2 (virtual {channel}-nothing) "
            "within 200 ms")
