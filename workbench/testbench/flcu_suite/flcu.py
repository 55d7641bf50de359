"""What the FLCU suite knows of the demo system: message periods, task periods, the bounds they give, and
the steps every test starts with.

Every bound is derived here, or next to its test, from the requirement's text, the DBC and the demo's
physics (thesis chapter 7, docs/demo-ecu.md); none is read from the ECU's calibration, so a wrong
calibration in the ECU's flash fails the tests it breaks.
"""

from __future__ import annotations

__all__ = [
    "CAN_PERIOD_S",
    "EMPTY_TANK_BAR",
    "FULL_TANK_BAR",
    "HOST_SLACK_S",
    "RAIL_SENSOR_BAR",
    "RX_LATENCY_S",
    "RX_TIMEOUT_S",
    "SENSOR_SPAN_V",
    "STEP_50MS_S",
    "SWITCH_TANK_BAR",
    "TANK_SENSOR_BAR",
    "TARGET_MAX_BAR",
    "TX_LATENCY_S",
    "MANIFOLD_TOLERANCE_BAR",
    "pressure_of",
    "set_tanks",
    "start_pcm",
    "start_running",
]

# --- time ------------------------------------------------------------------------------------------
CAN_PERIOD_S = 0.100  # every CAN2 message of the FLCU: GenMsgCycleTime 100 ms (DBC), "every 100 ms" (SW_REQ_ID_001/004)
RX_TIMEOUT_S = 0.300  # GenMsgTimeoutTime 300 ms (DBC)
TASK_50MS_S = 0.050  # TANK_CTRL, PRV_CTRL, FUEL_LEVEL, UTILS, ACTUATOR_COMMANDS "every 50 ms"
TASK_100MS_S = 0.100  # CANRX, CANTX "every 100 ms"
# The bench, the bus and (for the simulator) the ECU share a host that others load: its scheduling may
# hold a frame or a task this long. It widens the deadlines below, which still fail an ECU that reacts a
# cycle late, wrongly or not at all; no requirement asks for less.
HOST_SLACK_S = 0.100
# A value the PCM sends reaches the ECU's signal with the next frame (at most one period) and the next
# CANRX step (at most one period).
RX_LATENCY_S = CAN_PERIOD_S + TASK_100MS_S + HOST_SLACK_S
# A calibration, a fix or a fault acts at the next step of a 50 ms module.
STEP_50MS_S = TASK_50MS_S + HOST_SLACK_S
# A value the ECU computes every 50 ms travels with the next CANTX step.
TX_LATENCY_S = TASK_50MS_S + TASK_100MS_S + HOST_SLACK_S

# --- the fuel system -----------------------------------------------------------------------------------
FULL_TANK_BAR = 700.0  # the demo's CNG tanks are full at 700 bar (thesis 7.4.5; docs/demo-ecu.md FuelLevel)
EMPTY_TANK_BAR = 5.0  # low fuel level: both tanks below 5 bar (thesis 7.1.2)
SWITCH_TANK_BAR = 20.0  # SW_REQ_ID_002.2: "a delta calibration set to 20 bar initially"
SENSOR_SPAN_V = (0.5, 4.5)  # the pressure sensors' output span inside their 0-5 V input (thesis 7.4.2)
TANK_SENSOR_BAR = 800.0  # tank and manifold sensors: linear 0.5-4.5 V over 0-800 bar
RAIL_SENSOR_BAR = 50.0  # rail sensor: linear 0.5-4.5 V over 0-50 bar
TARGET_MAX_BAR = 50.0  # TargetRailPressure's DBC range is 0..50 bar
# The manifold is plausible within 30 bar of the open tank (thesis 7.1.5): tank pressures set for a test
# keep the manifold within this of both tanks, so that no diagnosis disables the system by the way.
MANIFOLD_TOLERANCE_BAR = 30.0


def pressure_of(volts: float, range_bar: float) -> float:
    """The pressure a sensor's voltage stands for (its transfer function, which the ECU's LUT must invert)."""
    low, high = SENSOR_SPAN_V
    return (min(max(volts, low), high) - low) / (high - low) * range_bar


def set_tanks(ecu, tank1_bar: float, tank2_bar: float, manifold_bar: float | None = None) -> None:
    """Fix the three tank-side pressures as the sensors would read them (their fix calibrations), the
    manifold between the tanks unless given: the test decides the tank pressures, whatever the real tanks
    of the ECU hold after the tests before (an ECU that runs for a while drains its tanks)."""
    manifold = (tank1_bar + tank2_bar) / 2 if manifold_bar is None else manifold_bar
    ecu.override("zfMANIFOLDPRESSURE", manifold)
    ecu.override("zfTANK1PRESSURE", tank1_bar)
    ecu.override("zfTANK2PRESSURE", tank2_bar)


def start_pcm(ecu, *, enable: int = 1, target_bar: float = 25.0) -> None:
    """The bench plays the PCM: EnableFLCU and TargetRailPressure every 100 ms."""
    ecu.send("PCM_TO_FLCU_001", period=CAN_PERIOD_S, EnableFLCU=enable)
    ecu.send("PCM_TO_FLCU_002", period=CAN_PERIOD_S, TargetRailPressure=target_bar)


def start_running(ecu, *, target_bar: float = 25.0) -> float:
    """The PCM enables the FLCU; wait until the system runs (enabled, every diagnosis good). Returns when it
    did (bench s). Fix the tank pressures (``set_tanks``) before: set while it runs, the manifold's fix meets
    the tanks of an ECU that ran for a while (drained) and diagnoses them implausible."""
    ecu.watch("xsSystemAbilitation")
    start_pcm(ecu, target_bar=target_bar)
    return ecu.wait_until("xsSystemAbilitation", "ON", timeout=RX_LATENCY_S + STEP_50MS_S)
