"""SW_REQ_ID_004 CANTX: the FLCU's three messages on their ids, every 100 ms, carrying what the ECU holds."""

from __future__ import annotations

from workbench.testbench import equals, needs_simulator, requirement

from .flcu import CAN_PERIOD_S, FULL_TANK_BAR, STEP_50MS_S, TX_LATENCY_S, start_running

# The period: 100 ms within +-5 ms (a task 10 % slower or faster fails), judged as the median slope over
# the frames of the window, which a frame the host's scheduling delayed does not move; a missing or a
# doubled frame fails on its own (expect_period). 0.8 s holds eight periods.
PERIOD_TOLERANCE_S = 0.005
PERIOD_WINDOW_S = 0.8


@requirement("SW_REQ_ID_004.1")
def test_rail_pressure_is_sent_on_0x123(ecu):
    """FLCU_TO_PCM_002 (0x123) every 100 ms carries the rail pressure the ECU holds: fixed to 33.33 bar,
    33.33 bar travels (0.01 bar per bit)."""
    assert ecu.can2.message("FLCU_TO_PCM_002").frame_id == 0x123, "the DBC puts FLCU_TO_PCM_002 elsewhere"
    ecu.watch("zsRailPressure")
    ecu.expect_period("FLCU_TO_PCM_002", CAN_PERIOD_S, PERIOD_TOLERANCE_S, for_s=PERIOD_WINDOW_S)
    ecu.override("zfRAILPRESSURE", 33.33)
    ecu.expect_edge("FLCU_TO_PCM_002.RailPressure", equals(33.33, 0.006), within=TX_LATENCY_S)
    ecu.expect("FLCU_TO_PCM_002.RailPressure", equals(33.33, 0.006), for_s=0.3)


@requirement("SW_REQ_ID_004.2")
def test_fuel_level_and_low_fuel_are_sent_on_0x167(ecu):
    """FLCU_TO_PCM_001 (0x167) every 100 ms carries the fuel level (half-full tanks: 50 %) and the low-fuel
    flag (both tanks below 5 bar: Low)."""
    assert ecu.can2.message("FLCU_TO_PCM_001").frame_id == 0x167, "the DBC puts FLCU_TO_PCM_001 elsewhere"
    ecu.watch("xsFuelLevel", "xsLEDEn")
    ecu.expect_period("FLCU_TO_PCM_001", CAN_PERIOD_S, PERIOD_TOLERANCE_S, for_s=PERIOD_WINDOW_S)
    half = FULL_TANK_BAR / 2
    ecu.override("zfTANK1PRESSURE", half)
    ecu.override("zfTANK2PRESSURE", half)
    ecu.expect_edge("FLCU_TO_PCM_001.FuelLevel", equals(50.0, 0.05), within=TX_LATENCY_S)
    ecu.expect("FLCU_TO_PCM_001.FuelLevelLow", "Normal", for_s=0.2)
    ecu.override("zfTANK1PRESSURE", 3.0)
    ecu.override("zfTANK2PRESSURE", 4.0)
    ecu.expect_edge("FLCU_TO_PCM_001.FuelLevelLow", "Low", within=TX_LATENCY_S)
    ecu.expect("FLCU_TO_PCM_001.FuelLevel", equals(7.0 / (2 * FULL_TANK_BAR) * 100, 0.05), for_s=0.2)


DIAGNOSTIC_SIGNALS = ("Tank1PSDiagStatus", "Tank2PSDiagStatus", "ManifoldPSDiagStatus", "RailPSDiagnosticStatus",
                      "OTV1DiagStatus", "OTV2DiagStatus", "PRVDiagStatus", "LedDiagStatus")


@requirement("SW_REQ_ID_004.3")
def test_diagnostic_statuses_are_sent_on_0x145(ecu):
    """FLCU_TO_PCM_003 (0x145) every 100 ms carries the eight diagnostic statuses: all NO_ERROR while the
    running system diagnoses nothing."""
    assert ecu.can2.message("FLCU_TO_PCM_003").frame_id == 0x145, "the DBC puts FLCU_TO_PCM_003 elsewhere"
    ecu.watch("xsSensorDiag", "xsActuatorDiag")
    start_running(ecu)
    ecu.expect_period("FLCU_TO_PCM_003", CAN_PERIOD_S, PERIOD_TOLERANCE_S, for_s=PERIOD_WINDOW_S)
    since = ecu.now() - PERIOD_WINDOW_S
    for signal in DIAGNOSTIC_SIGNALS:
        ecu.expect(f"FLCU_TO_PCM_003.{signal}", "NO_ERROR", for_s=PERIOD_WINDOW_S, since=since)


@requirement("SW_REQ_ID_004.3")
@needs_simulator
def test_a_diagnosed_fault_is_sent_on_0x145(ecu):
    """A sensor out of range and a valve's open load reach FLCU_TO_PCM_003 with the next frames."""
    ecu.watch("xsRailPSDiagStatus", "xsOTV1DiagStatus")
    ecu.expect("FLCU_TO_PCM_003.RailPSDiagnosticStatus", "NO_ERROR", for_s=0.15)
    ecu.sim.sensor_voltage("rail", 4.9)
    ecu.expect_edge("FLCU_TO_PCM_003.RailPSDiagnosticStatus", "OUT_OF_RANGE", within=TX_LATENCY_S)
    ecu.sim.actuator_error("OTV1", "OPEN_LOAD")
    ecu.expect_edge("FLCU_TO_PCM_003.OTV1DiagStatus", "OPEN_LOAD", within=TX_LATENCY_S)
    ecu.expect("FLCU_TO_PCM_003.RailPSDiagnosticStatus", "OUT_OF_RANGE", for_s=STEP_50MS_S)
