"""SW_REQ_ID_008 UTILS: the diagnosis of the four pressure sensors and the four actuators."""

from __future__ import annotations

import pytest

from workbench.testbench import needs_simulator, requirement

from .flcu import SENSOR_SPAN_V, STEP_50MS_S

# A sensor works properly while its voltage is inside its 0.5-4.5 V span (within the 0-5 V input): below
# it a short to ground or a broken wire, above it a short to the supply. 0.4 V outside each end must be
# diagnosed OUT_OF_RANGE, 0.1 V inside must not.
OUTSIDE = (SENSOR_SPAN_V[1] + 0.4, SENSOR_SPAN_V[0] - 0.3)
INSIDE = SENSOR_SPAN_V[1] - 0.1

SENSORS = [
    pytest.param("tank1", "xsTank1PSDiagStatus", marks=requirement("SW_REQ_ID_008.1"), id="tank1"),
    pytest.param("tank2", "xsTank2PSDiagStatus", marks=requirement("SW_REQ_ID_008.2"), id="tank2"),
    pytest.param("manifold", "xsManifoldPSDiagStatus", marks=requirement("SW_REQ_ID_008.3"), id="manifold"),
    pytest.param("rail", "xsRailPSDiagStatus", marks=requirement("SW_REQ_ID_008.4"), id="rail"),
]
ACTUATORS = [
    pytest.param("LED", "xsLEDDiagStatus", marks=requirement("SW_REQ_ID_008.5"), id="LED"),
    pytest.param("PRV", "xsPRVDiagStatus", marks=requirement("SW_REQ_ID_008.6"), id="PRV"),
    pytest.param("OTV1", "xsOTV1DiagStatus", marks=requirement("SW_REQ_ID_008.7"), id="OTV1"),
    pytest.param("OTV2", "xsOTV2DiagStatus", marks=requirement("SW_REQ_ID_008.8"), id="OTV2"),
]


@needs_simulator
@pytest.mark.parametrize(("sensor", "status"), SENSORS)
def test_a_sensor_outside_its_span_is_diagnosed(ecu, sensor, status):
    """Outside the span at either end: OUT_OF_RANGE and the sensor diagnosis failed, within one 50 ms step;
    back inside: NO_ERROR again."""
    ecu.watch(status, "xsSensorDiag")
    ecu.expect(status, "NO_ERROR", for_s=0.1)
    for volts in OUTSIDE:
        ecu.sim.sensor_voltage(sensor, volts)
        ecu.wait_until(status, "OUT_OF_RANGE", timeout=STEP_50MS_S)
        ecu.expect("xsSensorDiag", "OFF", for_s=0.1)
    ecu.sim.sensor_voltage(sensor, INSIDE)
    ecu.expect_edge(status, "NO_ERROR", within=STEP_50MS_S)


@needs_simulator
@pytest.mark.parametrize(("actuator", "status"), ACTUATORS)
def test_an_actuator_driver_fault_is_diagnosed(ecu, actuator, status):
    """Each fault the output driver reports (short to ground, short to battery, open load) is the actuator's
    status and fails the actuator diagnosis within one 50 ms step; repaired, NO_ERROR again."""
    ecu.watch(status, "xsActuatorDiag")
    for fault in ("SHORT_TO_GND", "SHORT_TO_BAT", "OPEN_LOAD"):
        ecu.sim.actuator_error(actuator, fault)
        ecu.expect_edge(status, fault, within=STEP_50MS_S)
        ecu.expect("xsActuatorDiag", "OFF", for_s=0.05)
    ecu.sim.actuator_error(actuator, None)
    ecu.expect_edge(status, "NO_ERROR", within=STEP_50MS_S)
