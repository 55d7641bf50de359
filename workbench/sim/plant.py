"""The simulated fuel system of the FLCU: two CNG tanks, the tank manifold, the PRV and the rail.

It is the analog/digital/PWM half of the BSW API the application calls
(:class:`workbench.sim.flcu.Hardware`): sensor voltages in, valve/LED/PRV outputs out. The ECU
core advances it with :meth:`FuelSystemPlant.step`.

Physics, kept simple and stated in the thesis's terms (chapter 7.4.5, figure 93):

* The PRV passes a mass flow ``prv_full_flow · duty/100 · supply/reference_supply`` [kg/h]; the
  supply is the manifold pressure while the flow is choked (rail below half the manifold
  pressure) and ``2 · (manifold − rail)`` above that, 0 when the rail is not below the manifold.
* The rail pressure changes by ``rail_gain · (PRV flow − engine flow)`` [bar/s], saturated to
  [0, 50] bar. With the defaults, an open PRV on a 700 bar supply and no engine flow raises the
  rail by 5 bar per 50 ms step, as in the thesis's delta-pressure table.
* The open tank feeds the PRV flow (``tank_bar_per_kg``); the manifold follows the open tank's
  pressure with a time constant, and with both valves closed the PRV flow drains it.
* Sensors are linear 0.5–4.5 V over 0–800 bar (tanks, manifold) and 0–50 bar (rail), the
  inverse of the ECU's initial LUTs, with a first-order response (the EWMA of the harness).

Faults for tests: :meth:`override_voltage`, :meth:`set_output_error`, :meth:`set_pressures`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from workbench.sim.flcu.hardware import (
    ANIN_MANIFOLD,
    ANIN_RAIL,
    ANIN_TANK1,
    ANIN_TANK2,
    DOUT_OTV1,
    DOUT_OTV2,
    PWMOUT_PRV,
    DiagStatus,
)

__all__ = ["FuelSystemPlant", "PlantParameters"]

SENSOR_VOLT_MIN = 0.5
SENSOR_VOLT_MAX = 4.5
SECONDS_PER_HOUR = 3600.0


@dataclass
class PlantParameters:
    """Sizes of the simulated fuel system (units in the names)."""

    tank1_start_bar: float = 700.0
    tank2_start_bar: float = 700.0
    engine_flow_kg_h: float = 20.0  # Q_inj: what the engine draws from the rail
    prv_full_flow_kg_h: float = 100.0  # PRV flow at 100 % duty, choked, with the reference supply
    reference_supply_bar: float = 700.0
    rail_gain_bar_per_s_per_kg_h: float = 1.0  # rail volume: pressure rise per kg/h of net inflow
    rail_max_bar: float = 50.0
    manifold_drain_bar_per_s_per_kg_h: float = 2.0  # manifold volume, valves closed
    manifold_time_constant_s: float = 0.02  # the manifold follows the open tank
    tank_bar_per_kg: float = 35.0  # a ~20 kg CNG tank at 700 bar
    tank_sensor_range_bar: float = 800.0
    rail_sensor_range_bar: float = 50.0
    sensor_time_constant_s: float = 0.005


def _pressure_to_volt(pressure_bar: float, range_bar: float) -> float:
    return SENSOR_VOLT_MIN + (SENSOR_VOLT_MAX - SENSOR_VOLT_MIN) * pressure_bar / range_bar


def _lag(value: float, target: float, dt: float, time_constant: float) -> float:
    """Exact first-order step: stable for any ``dt``."""
    if time_constant <= 0.0:
        return target
    return target + (value - target) * math.exp(-dt / time_constant)


class FuelSystemPlant:
    """Tanks, manifold, PRV and rail; implements the analog/digital/PWM services of the BSW API.

    Pressures are in bar, flows in kg/h, time in seconds. Unknown channels read 0 V and
    report NO_ERROR; outputs on unknown channels are recorded and otherwise ignored.
    """

    def __init__(self, parameters: PlantParameters | None = None):
        self.parameters = p = parameters or PlantParameters()
        self.tank1_bar = p.tank1_start_bar
        self.tank2_bar = p.tank2_start_bar
        # the pipe to the PRV holds the gas it was left with: the fuller tank's pressure
        self.manifold_bar = max(p.tank1_start_bar, p.tank2_start_bar)
        self.rail_bar = 0.0
        self.engine_flow_kg_h = p.engine_flow_kg_h
        self.time_s = 0.0
        self.digital_outputs: dict[str, int] = {}
        self.pwm_outputs: dict[str, tuple[int, float]] = {}  # channel -> (period µs, duty %)
        self._output_errors: dict[str, int] = {}
        self._voltage_overrides: dict[str, float] = {}
        self._volts = {channel: _pressure_to_volt(value, rng) for channel, value, rng in self._sensor_inputs()}

    # ------------------------------------------------------------------ BSW services

    def anin_get_adc(self, channel: str) -> float:
        """Sensor voltage [V] (an override wins)."""
        if channel in self._voltage_overrides:
            return self._voltage_overrides[channel]
        return self._volts.get(channel, 0.0)

    def dout_set(self, channel: str, value: int) -> None:
        self.digital_outputs[channel] = 1 if value else 0

    def dout_error_info(self, channel: str) -> int:
        return self._output_errors.get(channel, DiagStatus.NO_ERROR)

    def pwmout_set(self, channel: str, period_us: int, duty_percent: float) -> None:
        self.pwm_outputs[channel] = (int(period_us), float(duty_percent))

    def pwmout_error_info(self, channel: str) -> int:
        return self._output_errors.get(channel, DiagStatus.NO_ERROR)

    # ------------------------------------------------------------------ faults and set-up

    def override_voltage(self, channel: str, volts: float | None) -> None:
        """Force a sensor voltage (e.g. 4.9 V: out of range); ``None`` removes the override."""
        if volts is None:
            self._voltage_overrides.pop(channel, None)
        else:
            self._voltage_overrides[channel] = float(volts)

    def set_output_error(self, channel: str, status: DiagStatus | int) -> None:
        """The driver of an output reports ``status``; a faulty valve or PRV does not actuate."""
        if status == DiagStatus.NO_ERROR:
            self._output_errors.pop(channel, None)
        else:
            self._output_errors[channel] = int(status)

    def set_pressures(
        self,
        tank1_bar: float | None = None,
        tank2_bar: float | None = None,
        manifold_bar: float | None = None,
        rail_bar: float | None = None,
    ) -> None:
        """Put the fuel system into a state (the sensors follow with their response time)."""
        if tank1_bar is not None:
            self.tank1_bar = float(tank1_bar)
        if tank2_bar is not None:
            self.tank2_bar = float(tank2_bar)
        if manifold_bar is not None:
            self.manifold_bar = float(manifold_bar)
        if rail_bar is not None:
            self.rail_bar = float(rail_bar)

    # ------------------------------------------------------------------ state

    def valve_open(self, channel: str) -> bool:
        """A valve is open while commanded and its driver reports no error."""
        return bool(self.digital_outputs.get(channel)) and channel not in self._output_errors

    @property
    def prv_duty_percent(self) -> float:
        """The duty cycle acting on the PRV (0 while its driver reports an error)."""
        if PWMOUT_PRV in self._output_errors:
            return 0.0
        return self.pwm_outputs.get(PWMOUT_PRV, (0, 0.0))[1]

    def prv_flow_kg_h(self) -> float:
        """Mass flow through the PRV at the present pressures and duty."""
        p = self.parameters
        if self.rail_bar >= self.manifold_bar:
            return 0.0
        supply = min(self.manifold_bar, 2.0 * (self.manifold_bar - self.rail_bar))
        return p.prv_full_flow_kg_h * self.prv_duty_percent / 100.0 * supply / p.reference_supply_bar

    def _sensor_inputs(self) -> tuple[tuple[str, float, float], ...]:
        p = self.parameters
        return (
            (ANIN_TANK1, self.tank1_bar, p.tank_sensor_range_bar),
            (ANIN_TANK2, self.tank2_bar, p.tank_sensor_range_bar),
            (ANIN_MANIFOLD, self.manifold_bar, p.tank_sensor_range_bar),
            (ANIN_RAIL, self.rail_bar, p.rail_sensor_range_bar),
        )

    def step(self, dt: float) -> None:
        """Advance the fuel system by ``dt`` seconds."""
        p = self.parameters
        flow = self.prv_flow_kg_h()
        engine_flow = self.engine_flow_kg_h if self.rail_bar > 0.0 else 0.0
        rail = self.rail_bar + p.rail_gain_bar_per_s_per_kg_h * (flow - engine_flow) * dt
        self.rail_bar = min(max(rail, 0.0), p.rail_max_bar)

        open_tanks = [name for name, channel in (("tank1_bar", DOUT_OTV1), ("tank2_bar", DOUT_OTV2))
                      if self.valve_open(channel)]
        if open_tanks:
            drop = flow / SECONDS_PER_HOUR * dt * p.tank_bar_per_kg / len(open_tanks)
            for name in open_tanks:
                setattr(self, name, max(getattr(self, name) - drop, 0.0))
            supply = sum(getattr(self, name) for name in open_tanks) / len(open_tanks)
            self.manifold_bar = _lag(self.manifold_bar, supply, dt, p.manifold_time_constant_s)
        else:
            self.manifold_bar = max(self.manifold_bar - p.manifold_drain_bar_per_s_per_kg_h * flow * dt, 0.0)

        for channel, pressure, range_bar in self._sensor_inputs():
            target = _pressure_to_volt(pressure, range_bar)
            self._volts[channel] = _lag(self._volts[channel], target, dt, p.sensor_time_constant_s)
        self.time_s += dt
