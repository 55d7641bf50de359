"""The simulated fuel system on its own: sensors, PRV, rail, tanks, manifold, faults."""

from __future__ import annotations

import pytest

from workbench.sim.flcu import (
    ANIN_MANIFOLD,
    ANIN_RAIL,
    ANIN_TANK1,
    ANIN_TANK2,
    DOUT_OTV1,
    DOUT_OTV2,
    PWMOUT_PRV,
    DiagStatus,
)
from workbench.sim.plant import FuelSystemPlant, PlantParameters


def run(plant: FuelSystemPlant, seconds: float, dt: float = 0.001) -> None:
    for _ in range(round(seconds / dt)):
        plant.step(dt)


def test_sensor_voltages_are_the_inverse_of_the_ecu_luts():
    plant = FuelSystemPlant(PlantParameters(tank1_start_bar=700.0, tank2_start_bar=400.0))
    assert plant.anin_get_adc(ANIN_TANK1) == pytest.approx(0.5 + 4.0 * 700 / 800)
    assert plant.anin_get_adc(ANIN_TANK2) == pytest.approx(2.5)
    assert plant.anin_get_adc(ANIN_MANIFOLD) == pytest.approx(0.5 + 4.0 * 700 / 800)  # trapped gas
    assert plant.anin_get_adc(ANIN_RAIL) == pytest.approx(0.5)
    assert plant.anin_get_adc("ANIN_CH_ID_017") == 0.0


def test_open_prv_raises_the_rail_5_bar_per_50_ms_without_flow():
    """Thesis figure 93: empty flow, valve fully open: +5 bar per 50 ms step."""
    plant = FuelSystemPlant(PlantParameters(engine_flow_kg_h=0.0))
    plant.pwmout_set(PWMOUT_PRV, 1000, 100.0)
    run(plant, 0.05)
    assert plant.rail_bar == pytest.approx(5.0, rel=0.01)
    run(plant, 1.0)
    assert plant.rail_bar == 50.0  # saturated at the rail's range


def test_engine_flow_drains_the_rail_and_the_open_tank_feeds_the_prv():
    plant = FuelSystemPlant(PlantParameters(engine_flow_kg_h=20.0, tank_bar_per_kg=3600.0))
    plant.set_pressures(rail_bar=25.0)
    run(plant, 1.0)
    assert plant.rail_bar == pytest.approx(5.0, abs=0.05)  # 20 bar/s at 20 kg/h, PRV closed

    plant.dout_set(DOUT_OTV1, 1)
    plant.pwmout_set(PWMOUT_PRV, 1000, 20.0)  # 20 kg/h through the PRV at 700 bar
    plant.set_pressures(rail_bar=25.0)
    run(plant, 1.0)
    assert plant.rail_bar == pytest.approx(25.0, abs=0.3)  # in balance with the engine flow
    assert plant.tank1_bar < 700.0 - 15.0 and plant.tank2_bar == 700.0  # 20 kg/h for 1 s at 3600 bar/kg
    assert plant.manifold_bar == pytest.approx(plant.tank1_bar, abs=1.0)


def test_supply_limits_the_prv_flow():
    plant = FuelSystemPlant(PlantParameters(tank1_start_bar=30.0, tank2_start_bar=30.0))
    plant.pwmout_set(PWMOUT_PRV, 1000, 100.0)
    plant.set_pressures(rail_bar=20.0)
    assert plant.prv_flow_kg_h() == pytest.approx(100.0 * 2 * (30 - 20) / 700)
    plant.set_pressures(rail_bar=30.0)
    assert plant.prv_flow_kg_h() == 0.0


def test_manifold_drains_while_both_valves_are_closed():
    plant = FuelSystemPlant()
    plant.pwmout_set(PWMOUT_PRV, 1000, 50.0)
    run(plant, 0.5)
    assert plant.manifold_bar < 700.0 - 30.0
    assert plant.tank1_bar == plant.tank2_bar == 700.0


def test_faults_override_voltages_and_block_actuators():
    plant = FuelSystemPlant()
    plant.override_voltage(ANIN_RAIL, 4.9)
    assert plant.anin_get_adc(ANIN_RAIL) == 4.9
    plant.override_voltage(ANIN_RAIL, None)
    assert plant.anin_get_adc(ANIN_RAIL) == pytest.approx(0.5)

    plant.dout_set(DOUT_OTV2, 1)
    plant.set_output_error(DOUT_OTV2, DiagStatus.OPEN_LOAD)
    assert plant.dout_error_info(DOUT_OTV2) == DiagStatus.OPEN_LOAD and not plant.valve_open(DOUT_OTV2)
    plant.set_output_error(DOUT_OTV2, DiagStatus.NO_ERROR)
    assert plant.valve_open(DOUT_OTV2)

    plant.pwmout_set(PWMOUT_PRV, 1000, 60.0)
    plant.set_output_error(PWMOUT_PRV, DiagStatus.SHORT_TO_BAT)
    assert plant.pwmout_error_info(PWMOUT_PRV) == DiagStatus.SHORT_TO_BAT and plant.prv_duty_percent == 0.0


def test_sensors_follow_with_their_response_time():
    plant = FuelSystemPlant()
    plant.set_pressures(tank2_bar=300.0)
    plant.step(0.001)
    assert plant.anin_get_adc(ANIN_TANK2) > 2.0  # not there yet (300 bar is 2.0 V)
    run(plant, 0.05)
    assert plant.anin_get_adc(ANIN_TANK2) == pytest.approx(2.0, abs=1e-3)
