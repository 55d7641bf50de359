"""SW_REQ_ID_007 ACTUATOR_COMMANDS: valves and PRV commanded as the control computed, closed/0 % on a diagnostic error."""

from __future__ import annotations

from workbench.testbench import at_least, needs_simulator, requirement

from .flcu import STEP_50MS_S, SWITCH_TANK_BAR, set_tanks, start_running

HELD_S = 0.3


@requirement("SW_REQ_ID_007.1")
@needs_simulator
def test_tank1_valve_follows_its_state_and_closes_on_its_diagnostic_error(ecu):
    """OTV1 is commanded open while TankCtrl draws tank 1 and its driver reports no error; an open load
    closes it within one 50 ms step."""
    ecu.watch("xsOTV1Cmd", "xsValve1State")
    start_running(ecu)
    set_tanks(ecu, 700.0, 700.0 - SWITCH_TANK_BAR - 2.0)  # tank 1 the fuller beyond the delta: TankCtrl draws it
    ecu.wait_until("xsOTV1Cmd", "ON", timeout=2 * STEP_50MS_S)
    ecu.expect_follows("xsOTV1Cmd", "xsValve1State", 0, for_s=0.2)
    ecu.sim.actuator_error("OTV1", "OPEN_LOAD")
    ecu.expect_edge("xsOTV1Cmd", "OFF", within=STEP_50MS_S)
    ecu.expect("xsOTV1Cmd", "OFF", for_s=HELD_S)


@requirement("SW_REQ_ID_007.2")
@needs_simulator
def test_tank2_valve_follows_its_state_and_closes_on_its_diagnostic_error(ecu):
    """OTV2 is commanded open while TankCtrl draws tank 2 (the fuller beyond the delta) and its driver
    reports no error; a short to ground closes it within one 50 ms step."""
    ecu.watch("xsOTV2Cmd", "xsValve2State")
    start_running(ecu)
    set_tanks(ecu, 700.0 - SWITCH_TANK_BAR - 2.0, 700.0)
    ecu.wait_until("xsOTV2Cmd", "ON", timeout=2 * STEP_50MS_S)
    ecu.expect_follows("xsOTV2Cmd", "xsValve2State", 0, for_s=0.2)
    ecu.sim.actuator_error("OTV2", "SHORT_TO_GND")
    ecu.expect_edge("xsOTV2Cmd", "OFF", within=STEP_50MS_S)
    ecu.expect("xsOTV2Cmd", "OFF", for_s=HELD_S)


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
