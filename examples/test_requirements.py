"""Requirement tests to copy: a timing requirement stimulated on CAN2, a fault reaction, a parametrized bound.

Run: workbench test examples/test_requirements.py --report out/   (a simulated ECU per test)
     workbench test examples/test_requirements.py --interface udp_multicast --bus-kwargs port=43200
     (the latter against `workbench sim --interface udp_multicast --bus-kwargs port=43200` in another terminal)
out/junit.xml for the CI server, out/report.html to read (docs/requirement-tests.md).
"""

import pytest

from workbench.testbench import needs_simulator, other_than, requirement

PERIOD_S = 0.100  # the PCM's messages: GenMsgCycleTime 100 ms (DBC)
SLACK_S = 0.100  # a loaded host may hold a frame or a task this long


def start_pcm(ecu, enable=1, target_bar=25.0):
    """The bench plays the PCM on CAN2: both messages every 100 ms; wait until the FLCU runs."""
    ecu.watch("xsSystemAbilitation")
    ecu.send("PCM_TO_FLCU_001", period=PERIOD_S, EnableFLCU=enable)
    ecu.send("PCM_TO_FLCU_002", period=PERIOD_S, TargetRailPressure=target_bar)
    return ecu.wait_until("xsSystemAbilitation", "ON", timeout=1.0)


@requirement("SW_REQ_ID_002.1")
def test_valves_close_when_the_pcm_disables_the_system(ecu):
    """EnableFLCU = 0 closes both tank valves: TankCtrl (50 ms) sees it at the next CANRX step (100 ms)."""
    ecu.watch("xsTankCtrlState", "xsValve1State", "xsValve2State")  # before the stimulus: an edge needs a before
    start_pcm(ecu)
    ecu.wait_until("xsTankCtrlState", other_than("OFF"), timeout=1.0)
    ecu.send("PCM_TO_FLCU_001", EnableFLCU=0)  # from the message's next frame on; a deadline counts from that frame
    ecu.expect_edge("xsTankCtrlState", "OFF", within=0.100 + 0.050 + SLACK_S)
    ecu.expect("xsValve1State", "OFF", for_s=0.3)
    ecu.expect("xsValve2State", "OFF", for_s=0.3)


@requirement("SW_REQ_ID_008.4", "SW_REQ_ID_007.3")
@needs_simulator  # the sensor's voltage is the simulator's: skipped (with the reason) on a real ECU
def test_a_rail_sensor_out_of_range_stops_the_prv(ecu):
    """4.95 V is beyond the rail sensor's 0.5-4.5 V span: diagnosed, the PRV commanded 0 %, the PCM told."""
    ecu.watch("xsRailPSDiagStatus", "xsPRVDutyCmd")
    start_pcm(ecu)
    ecu.sim.sensor_voltage("rail", 4.95)
    ecu.expect_edge("xsRailPSDiagStatus", "OUT_OF_RANGE", within=0.050 + SLACK_S)
    ecu.expect("xsPRVDutyCmd", 0.0, for_s=0.3)
    ecu.expect("FLCU_TO_PCM_003.RailPSDiagnosticStatus", "OUT_OF_RANGE", for_s=0.3)  # on CAN2, by the DBC's text


@requirement("SW_REQ_ID_001.2")
@pytest.mark.parametrize("target_bar", [12.5, 40.0])
def test_the_target_rail_pressure_is_read(ecu, target_bar):
    """TargetRailPressure (0x220, 0.01 bar per bit) is read as sent."""
    ecu.watch("csPCM_TO_FLCU_002_TargetRailPressure")
    start_pcm(ecu, target_bar=target_bar)
    ecu.expect("csPCM_TO_FLCU_002_TargetRailPressure", (target_bar - 0.01, target_bar + 0.01), for_s=0.3)
