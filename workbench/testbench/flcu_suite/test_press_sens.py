"""SW_REQ_ID_005 PRESS_SENS: every 4 ms the four sensors' voltages converted (LUT) to bar, the rail saturated."""

from __future__ import annotations

import pytest

from workbench.testbench import equals, needs_simulator, requirement, within

from .flcu import RAIL_SENSOR_BAR, SENSOR_SPAN_V, TANK_SENSOR_BAR, pressure_of

# The filter (an EWMA over the 4 ms steps) settles a voltage step to 0.1 % within about 0.15 s; 0.3 s is
# the deadline. 0.2 % of the sensor's range is the band: the LUT between its points and the float32
# arithmetic stay far inside it, a LUT point off by 1 % of the range does not.
SETTLE_S = 0.3
BAND_OF_RANGE = 0.002
VOLTS = (1.0, 2.5, 4.0)  # a low, a middle and a high point of the span, between the LUT's points too

SENSORS = [
    pytest.param("tank1", "zsTank1Pressure", TANK_SENSOR_BAR, marks=requirement("SW_REQ_ID_005.1"), id="tank1"),
    pytest.param("tank2", "zsTank2Pressure", TANK_SENSOR_BAR, marks=requirement("SW_REQ_ID_005.2"), id="tank2"),
    pytest.param("manifold", "zsManifoldPressure", TANK_SENSOR_BAR, marks=requirement("SW_REQ_ID_005.3"),
                 id="manifold"),
    pytest.param("rail", "zsRailPressure", RAIL_SENSOR_BAR, marks=requirement("SW_REQ_ID_005.4"), id="rail"),
]


@needs_simulator
@pytest.mark.parametrize(("sensor", "pressure", "range_bar"), SENSORS)
def test_sensor_voltage_is_converted_to_pressure(ecu, sensor, pressure, range_bar):
    """The pressure is the sensor's voltage through the sensor's transfer function (linear over its
    0.5-4.5 V span), at three points of the span."""
    ecu.watch(pressure)
    band = BAND_OF_RANGE * range_bar
    for volts in VOLTS:
        expected = pressure_of(volts, range_bar)
        ecu.sim.sensor_voltage(sensor, volts)
        ecu.wait_until(pressure, within(expected - band, expected + band), timeout=SETTLE_S)
        ecu.expect(pressure, within(expected - band, expected + band), for_s=0.05)


@requirement("SW_REQ_ID_005.5")
@needs_simulator
def test_rail_pressure_saturates_beyond_the_sensor_span(ecu):
    """Beyond the rail sensor's span the pressure is the span's end: 50 bar above 4.5 V, 0 bar below 0.5 V."""
    ecu.watch("zsRailPressure")
    band = BAND_OF_RANGE * RAIL_SENSOR_BAR
    for volts, saturated in ((SENSOR_SPAN_V[1] + 0.4, RAIL_SENSOR_BAR), (SENSOR_SPAN_V[0] - 0.3, 0.0)):
        ecu.sim.sensor_voltage("rail", volts)
        ecu.wait_until("zsRailPressure", equals(saturated, band), timeout=SETTLE_S)
        ecu.expect("zsRailPressure", equals(saturated, band), for_s=0.2)
