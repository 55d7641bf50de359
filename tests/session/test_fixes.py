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
    assert wait_for(lambda: ecu.fix_state("cfENABLEFLCU").live == "ON")  # the PCM enables the FLCU
    # a sent signal computed under an abbreviated name: RailPSDiagnosticStatus from xsRailPSDiagStatus
    assert states["cfRAILPSDIAGNOSTICSTATUS"].pair.live == "xsRailPSDiagStatus"
    assert states["cfRAILPSDIAGNOSTICSTATUS"].live == "NO_ERROR"
    # FuelLevelLow is sent from xsLEDEn: no name tells, the A2L's COMPARISON_QUANTITY does
    assert states["cfFUELLEVELLOW"].pair.live == "xsLEDEn" and states["cfFUELLEVELLOW"].live in ("ON", "OFF")
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
