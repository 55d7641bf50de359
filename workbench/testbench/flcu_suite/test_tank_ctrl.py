"""SW_REQ_ID_002 TANK_CTRL: one tank valve open at a time, the fuller tank drawn, none without need."""

from __future__ import annotations

from workbench.testbench import other_than, requirement

from .flcu import EMPTY_TANK_BAR, RX_LATENCY_S, STEP_50MS_S, SWITCH_TANK_BAR, TASK_50MS_S, set_tanks, start_running

STATE, VALVE1, VALVE2 = "xsTankCtrlState", "xsValve1State", "xsValve2State"
HELD_S = 0.4  # long enough for several 50 ms steps to have decided otherwise


@requirement("SW_REQ_ID_002.1")
def test_valves_close_when_the_system_is_disabled(ecu):
    """EnableFLCU = 0 from the PCM: both valves close once CANRX has read it and TankCtrl has run, and stay closed."""
    ecu.watch(STATE, VALVE1, VALVE2, "xsOTV1Cmd", "xsOTV2Cmd")
    start_running(ecu)
    ecu.wait_until(STATE, other_than("OFF"), timeout=2 * STEP_50MS_S)  # a valve open, whichever
    ecu.send("PCM_TO_FLCU_001", EnableFLCU=0)
    ecu.expect_edge(STATE, "OFF", within=RX_LATENCY_S + TASK_50MS_S)
    closed = ecu.now()
    for name in (VALVE1, VALVE2, "xsOTV1Cmd", "xsOTV2Cmd"):
        ecu.expect(name, "OFF", for_s=HELD_S, since=closed)


@requirement("SW_REQ_ID_002.2")
def test_the_tank_difference_stays_below_the_delta_calibration(ecu):
    """The open tank is left for the other one when the other is fuller by more than the delta (20 bar at
    first, SW_REQ_ID_002.2), not before; the calibration decides: at 10 bar a 12 bar difference switches."""
    ecu.watch(STATE, "xsSystemAbilitation")
    set_tanks(ecu, 700.0, 700.0 - SWITCH_TANK_BAR - 2.0, manifold_bar=701.5)  # tank 1 fuller beyond the delta
    began = start_running(ecu)
    ecu.wait_until(STATE, "TANK1_ON", timeout=2 * STEP_50MS_S)
    ecu.override("zfTANK2PRESSURE", 700.0 + SWITCH_TANK_BAR - 5.0)  # 5 bar below the delta: stay
    ecu.expect(STATE, "TANK1_ON", for_s=HELD_S)
    ecu.override("zfTANK2PRESSURE", 700.0 + SWITCH_TANK_BAR + 5.0)  # 5 bar beyond it: switch
    ecu.expect_edge(STATE, "TANK2_ON", within=STEP_50MS_S)
    ecu.write("xsSWITCH_TANK_THR", 10.0)
    ecu.override("zfTANK2PRESSURE", 700.0 - 12.0)  # tank 1 fuller by 12 bar: beyond 10, below 20
    ecu.expect_edge(STATE, "TANK1_ON", within=STEP_50MS_S)
    # every pressure set lies within the manifold's tolerance of 701.5 bar: no diagnosis took part
    ecu.expect("xsSystemAbilitation", "ON", for_s=ecu.now() - began, since=began)


@requirement("SW_REQ_ID_002.3")
def test_both_valves_close_on_a_low_fuel_level(ecu):
    """Both tanks below 5 bar: both valves close, and stay closed with the system enabled (closed for the
    fuel level, not by a diagnosis); one tank above 5 bar again and its valve opens."""
    ecu.watch(STATE, VALVE1, VALVE2, "xsSystemAbilitation")
    start_running(ecu)
    ecu.wait_until(STATE, other_than("OFF"), timeout=2 * STEP_50MS_S)
    emptied = ecu.now()
    set_tanks(ecu, EMPTY_TANK_BAR - 2.0, EMPTY_TANK_BAR - 1.0)
    ecu.expect_edge(STATE, "OFF", within=STEP_50MS_S + (ecu.now() - emptied), after=emptied)
    closed = ecu.now()
    for name in (VALVE1, VALVE2):
        ecu.expect(name, "OFF", for_s=HELD_S, since=closed)
    ecu.expect("xsSystemAbilitation", "ON", for_s=HELD_S, since=closed)
    ecu.override("zfTANK2PRESSURE", EMPTY_TANK_BAR + 3.0)
    ecu.expect_edge(VALVE2, "ON", within=STEP_50MS_S)
