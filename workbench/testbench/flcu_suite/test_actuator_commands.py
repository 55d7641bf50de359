"""SW_REQ_ID_007 ACTUATOR_COMMANDS: valves and PRV commanded as the control computed, closed/0 % on a diagnostic error."""

from __future__ import annotations

import pytest

from workbench.testbench import at_least, needs_simulator, requirement

from .flcu import STEP_50MS_S, SWITCH_TANK_BAR, set_tanks, start_running

HELD_S = 0.3


VALVES = [  # valve, its command, TankCtrl's state of it, the tank pressures that make TankCtrl draw it, a fault
    pytest.param("OTV1", "xsOTV1Cmd", "xsValve1State", (700.0, 700.0 - SWITCH_TANK_BAR - 2.0), "OPEN_LOAD",
                 marks=requirement("SW_REQ_ID_007.1"), id="OTV1"),
    pytest.param("OTV2", "xsOTV2Cmd", "xsValve2State", (700.0 - SWITCH_TANK_BAR - 2.0, 700.0), "SHORT_TO_GND",
                 marks=requirement("SW_REQ_ID_007.2"), id="OTV2"),
]


@needs_simulator
@pytest.mark.parametrize(("valve", "command", "state", "tanks", "fault"), VALVES)
def test_a_tank_valve_follows_its_state_and_closes_on_its_diagnostic_error(ecu, valve, command, state, tanks, fault):
    """The valve is commanded open while TankCtrl draws its tank (the fuller one beyond the delta) and its
    driver reports no error; a driver error closes it within one 50 ms step, and it stays closed."""
    ecu.watch(command, state)
    set_tanks(ecu, *tanks)
    start_running(ecu)
    ecu.wait_until(command, "ON", timeout=2 * STEP_50MS_S)
    ecu.expect_follows(command, state, 0, for_s=0.2)
    ecu.sim.actuator_error(valve, fault)
    ecu.expect_edge(command, "OFF", within=STEP_50MS_S)
    ecu.expect(command, "OFF", for_s=HELD_S)


@requirement("SW_REQ_ID_007.3")
@needs_simulator
def test_prv_duty_follows_the_control_and_is_zero_on_its_diagnostic_error(ecu):
    """The PRV is commanded the duty cycle PRVCtrl computes (sample by sample) while its driver reports no
    error; an open load sets it to 0 % within one 50 ms step, and it stays there."""
    ecu.watch("xsPRVDutyCmd", "xsDC")
    start_running(ecu)
    ecu.wait_until("xsPRVDutyCmd", at_least(5.0), timeout=2 * STEP_50MS_S)  # the rail rising: the PRV well open
    ecu.expect_follows("xsPRVDutyCmd", "xsDC", 0.005, for_s=0.3)  # 0.005 %: the PWM driver's 0.01 % steps
    ecu.sim.actuator_error("PRV", "OPEN_LOAD")
    ecu.expect_edge("xsPRVDutyCmd", 0.0, within=STEP_50MS_S)
    ecu.expect("xsPRVDutyCmd", 0.0, for_s=HELD_S)
