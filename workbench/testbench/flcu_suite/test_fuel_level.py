"""SW_REQ_ID_006 FUEL_LEVEL: the fuel level from both tanks' pressures, and the low-fuel flag."""

from __future__ import annotations

from workbench.testbench import equals, requirement

from .flcu import EMPTY_TANK_BAR, FULL_TANK_BAR, STEP_50MS_S

# Tank pressures (bar) and the fuel level they mean: the mean of both over the full tank's 700 bar,
# 0..100 %; tanks above 700 bar (overfilled, a warm tank) are 100 %.
POINTS = ((350.0, 560.0), (700.0, 0.0), (50.0, 20.0), (800.0, 760.0))
LEVEL_TOLERANCE = 0.05  # % (float32 arithmetic on 700 bar is good to 1e-4 %)


def level_of(tank1: float, tank2: float) -> float:
    return min(max((tank1 + tank2) / (2 * FULL_TANK_BAR) * 100.0, 0.0), 100.0)


@requirement("SW_REQ_ID_006.1")
def test_fuel_level_from_both_tank_pressures(ecu):
    """The fuel level follows both tanks' pressures (set by their fix calibrations) within one 50 ms step."""
    ecu.watch("xsFuelLevel")
    for tank1, tank2 in POINTS:
        ecu.override("zfTANK1PRESSURE", tank1)
        ecu.override("zfTANK2PRESSURE", tank2)
        expected = level_of(tank1, tank2)
        ecu.wait_until("xsFuelLevel", equals(expected, LEVEL_TOLERANCE), timeout=STEP_50MS_S)
        ecu.expect("xsFuelLevel", equals(expected, LEVEL_TOLERANCE), for_s=0.1)


@requirement("SW_REQ_ID_006.2")
def test_low_fuel_when_both_tanks_fall_below_5_bar(ecu):
    """Low fuel (the LED) when both tanks are below 5 bar, half a bar either side; not when one is above."""
    ecu.watch("xsLEDEn", "xsLEDCmd")
    ecu.override("zfTANK1PRESSURE", EMPTY_TANK_BAR - 0.5)
    ecu.override("zfTANK2PRESSURE", EMPTY_TANK_BAR - 0.5)
    ecu.expect_edge("xsLEDEn", "ON", within=STEP_50MS_S)
    ecu.expect("xsLEDCmd", "ON", for_s=0.2)
    ecu.override("zfTANK2PRESSURE", EMPTY_TANK_BAR + 0.5)
    ecu.expect_edge("xsLEDEn", "OFF", within=STEP_50MS_S)
    ecu.override("zfTANK1PRESSURE", EMPTY_TANK_BAR + 0.5)
    ecu.override("zfTANK2PRESSURE", EMPTY_TANK_BAR - 0.5)
    ecu.expect("xsLEDEn", "OFF", for_s=0.2)
