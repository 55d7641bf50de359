"""PRVCtrl (50 ms, ``PRVCtrl.c``): PID plus feed-forward map on the rail pressure -> PRV duty cycle.

The integrator runs only while the error is within ``xsPRV_I_BAND`` and is limited so that
feed-forward plus integral stays within the duty-cycle limits.

The delay states live in ``PRVCtrl_DW`` (``DW_PRVCtrl_T``) like the C code's, so a restart or
an XCP write sees the same state in both.
"""

from __future__ import annotations

import numpy as np

from workbench.sim.flcu.rt import HALF, ZERO, look2, saturate
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "PRVCtrl"]

TS = np.float32(0.05)
FF_TARGET_POINTS = 6
FF_MANIFOLD_POINTS = 5
# DW_PRVCtrl_T member offsets
_INTEGRATOR, _ERROR, _DERROR = 0, 4, 8
MEASUREMENTS = ("xsRailPressureErr", "xsPidP", "xsPidI", "xsPidD", "xsPidFF", "xsDC", "PRVCtrl_DW")


class PRVCtrl:
    def __init__(self, variables: Variables):
        self._v = variables

    def _reset(self) -> None:
        for name in MEASUREMENTS[1:6]:
            self._v.set_f32(name, ZERO)
        self._v.set_raw("PRVCtrl_DW", bytes(12))

    def initialize(self) -> None:
        self._v.set_f32("xsRailPressureErr", ZERO)
        self._reset()

    def step(self) -> None:
        v = self._v
        target = v.f32("csPCM_TO_FLCU_002_TargetRailPressure")
        error = target - v.f32("zsRailPressure")
        v.set_f32("xsRailPressureErr", error)
        if v.u8("xsSystemAbilitation") == 0:
            self._reset()
            return
        dc_min = v.f32("xsPRV_DC_MIN")
        dc_max = v.f32("xsPRV_DC_MAX")
        table = v.f32_array("xvPRV_DC_FF", FF_MANIFOLD_POINTS * FF_TARGET_POINTS).reshape(
            FF_MANIFOLD_POINTS, FF_TARGET_POINTS
        )
        feed_forward = look2(
            target,
            v.f32("zsManifoldPressure"),
            v.f32_array("xaPRV_FF_TARGET", FF_TARGET_POINTS),
            v.f32_array("xaPRV_FF_MANIFOLD", FF_MANIFOLD_POINTS),
            table,
        )
        proportional = v.f32("xsPRV_KP") * error
        integral = v.f32("PRVCtrl_DW", _INTEGRATOR)
        if (-error if error < ZERO else error) <= v.f32("xsPRV_I_BAND"):
            integral = integral + (v.f32("xsPRV_KI") * error) * TS
        integral = saturate(integral, dc_min - feed_forward, dc_max - feed_forward)
        d_error = error - v.f32("PRVCtrl_DW", _ERROR)
        derivative = v.f32("xsPRV_KD") * (((d_error + v.f32("PRVCtrl_DW", _DERROR)) * HALF) / TS)
        duty = saturate(((proportional + integral) + derivative) + feed_forward, dc_min, dc_max)
        for name, value in zip(MEASUREMENTS[1:6], (proportional, integral, derivative, feed_forward, duty)):
            v.set_f32(name, value)
        v.set_f32("PRVCtrl_DW", integral, _INTEGRATOR)
        v.set_f32("PRVCtrl_DW", error, _ERROR)
        v.set_f32("PRVCtrl_DW", d_error, _DERROR)
