"""TankCtrl (50 ms, ``TankCtrl.c``): the Stateflow chart that opens one tank valve at a time.

OFF -> TANK1_ON when enabled and not low on fuel (TANK2_ON if tank 2 is fuller); switch tank
when the other one is fuller by more than ``xsSWITCH_TANK_THR``; back to OFF when disabled or
low on fuel. An invalid state (written by a calibration tool) falls back to OFF.
"""

from __future__ import annotations

from workbench.sim.flcu.hardware import TankCtrlState
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "TankCtrl"]

MEASUREMENTS = ("xsTankCtrlState", "xsValve1State", "xsValve2State", "xsTankPressDiff")


class TankCtrl:
    def __init__(self, variables: Variables):
        self._v = variables

    def initialize(self) -> None:
        for name in MEASUREMENTS[:3]:
            self._v.set_u8(name, 0)
        self._v.set_f32("xsTankPressDiff", 0.0)

    def step(self) -> None:
        v = self._v
        tank1 = v.f32("zsTank1Pressure")
        tank2 = v.f32("zsTank2Pressure")
        threshold = v.f32("xsSWITCH_TANK_THR")
        may_run = v.u8("xsSystemAbilitation") != 0 and v.u8("xsLEDEn") == 0
        v.set_f32("xsTankPressDiff", tank1 - tank2)
        state = v.u8("xsTankCtrlState")
        if state == TankCtrlState.OFF:
            if may_run:
                state = TankCtrlState.TANK2_ON if tank2 > tank1 else TankCtrlState.TANK1_ON
        elif state == TankCtrlState.TANK1_ON:
            if not may_run:
                state = TankCtrlState.OFF
            elif tank2 - tank1 > threshold:
                state = TankCtrlState.TANK2_ON
        elif state == TankCtrlState.TANK2_ON:
            if not may_run:
                state = TankCtrlState.OFF
            elif tank1 - tank2 > threshold:
                state = TankCtrlState.TANK1_ON
        else:
            state = TankCtrlState.OFF
        v.set_u8("xsTankCtrlState", state)
        v.set_u8("xsValve1State", state == TankCtrlState.TANK1_ON)
        v.set_u8("xsValve2State", state == TankCtrlState.TANK2_ON)
