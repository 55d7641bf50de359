"""FuelLevel (50 ms, ``FuelLevel.c``): low-fuel LED enable and fuel level [%]."""

from __future__ import annotations

from workbench.sim.flcu.rt import HUNDRED, TWO, ZERO
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "FuelLevel"]

MEASUREMENTS = ("xsLEDEn", "xsFuelLevel")


class FuelLevel:
    def __init__(self, variables: Variables):
        self._v = variables

    def initialize(self) -> None:
        self._v.set_u8("xsLEDEn", 0)
        self._v.set_f32("xsFuelLevel", 0.0)

    def step(self) -> None:
        v = self._v
        tank1 = v.f32("zsTank1Pressure")
        tank2 = v.f32("zsTank2Pressure")
        empty = v.f32("xsEMPTY_TANK_THR")
        v.set_u8("xsLEDEn", tank1 < empty and tank2 < empty)
        level = ((tank1 + tank2) / (TWO * v.f32("xsFULL_TANK_PRESS"))) * HUNDRED
        if level > HUNDRED:
            level = HUNDRED
        elif level < ZERO:
            level = ZERO
        v.set_f32("xsFuelLevel", level)
