"""ActuatorCommands (50 ms, ``ActuatorCommands.c``): valve, LED and PRV outputs, gated by diagnostics."""

from __future__ import annotations

import numpy as np

from workbench.sim.flcu.rt import HALF, HUNDRED, ZERO
from workbench.sim.flcu.hardware import DOUT_LED, DOUT_OTV1, DOUT_OTV2, PWMOUT_PRV, DiagStatus, Hardware
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "ActuatorCommands", "duty_steps"]

MEASUREMENTS = ("xsOTV1Cmd", "xsOTV2Cmd", "xsLEDCmd", "xsPRVDutyCmd")
DUTY_STEPS_PER_PERCENT = 100


def duty_steps(duty_percent: np.float32) -> int:
    """The PWM driver's 0.01 % steps: round(duty * 100), saturated to [0, 10000]; NaN gives 0."""
    if not duty_percent > ZERO:
        return 0
    if duty_percent >= HUNDRED:
        return 100 * DUTY_STEPS_PER_PERCENT
    return int(duty_percent * HUNDRED + HALF)


class ActuatorCommands:
    def __init__(self, variables: Variables, hardware: Hardware):
        self._v = variables
        self._hw = hardware

    def initialize(self) -> None:
        for name in MEASUREMENTS[:3]:
            self._v.set_u8(name, 0)
        self._v.set_f32("xsPRVDutyCmd", ZERO)

    def step(self) -> None:
        v = self._v
        otv1 = v.u8("xsValve1State") if v.u8("xsOTV1DiagStatus") == DiagStatus.NO_ERROR else 0
        otv2 = v.u8("xsValve2State") if v.u8("xsOTV2DiagStatus") == DiagStatus.NO_ERROR else 0
        led = v.u8("xsLEDEn")
        duty = v.f32("xsDC") if v.u8("xsPRVDiagStatus") == DiagStatus.NO_ERROR else ZERO
        for name, value in zip(MEASUREMENTS[:3], (otv1, otv2, led)):
            v.set_u8(name, value)
        v.set_f32("xsPRVDutyCmd", duty)
        self._hw.dout_set(DOUT_OTV1, otv1)
        self._hw.dout_set(DOUT_OTV2, otv2)
        self._hw.dout_set(DOUT_LED, led)
        self._hw.pwmout_set(PWMOUT_PRV, v.u16("xsPRV_PWM_PERIOD"), duty_steps(duty) / DUTY_STEPS_PER_PERCENT)
