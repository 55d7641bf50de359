"""PressSens (4 ms, ``PressSens.c``): volts -> EWMA -> saturation -> LUT -> bar -> fix switch."""

from __future__ import annotations

import numpy as np

from workbench.sim.flcu.hardware import ANIN_MANIFOLD, ANIN_RAIL, ANIN_TANK1, ANIN_TANK2, Hardware
from workbench.sim.flcu.rt import look1
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "PressSens"]

LUT_POINTS = 9
# in zsSensVolt order: channel, filter state, LUT, fix calibration prefix, output
_SENSORS = (
    (ANIN_TANK1, "zsTank1VoltFilt", "zvTankPConv", "zfTANK1PRESSURE", "zsTank1Pressure"),
    (ANIN_TANK2, "zsTank2VoltFilt", "zvTankPConv", "zfTANK2PRESSURE", "zsTank2Pressure"),
    (ANIN_MANIFOLD, "zsManifoldVoltFilt", "zvTankPConv", "zfMANIFOLDPRESSURE", "zsManifoldPressure"),
    (ANIN_RAIL, "zsRailVoltFilt", "zvRailPConv", "zfRAILPRESSURE", "zsRailPressure"),
)
_FLOAT_OUTPUTS = (*(s[1] for s in _SENSORS), "zsRailPressureTmp", *(s[4] for s in _SENSORS))
MEASUREMENTS = ("zsSensVolt", *_FLOAT_OUTPUTS)


class PressSens:
    def __init__(self, variables: Variables, hardware: Hardware):
        self._v = variables
        self._hw = hardware

    def initialize(self) -> None:
        self._v.set_raw("zsSensVolt", bytes(4 * len(_SENSORS)))
        for name in _FLOAT_OUTPUTS:
            self._v.set_f32(name, 0.0)

    def _lut(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        values = self._v.f32_array(name, 2 * LUT_POINTS)
        return values[:LUT_POINTS], values[LUT_POINTS:]

    def step(self) -> None:
        v = self._v
        alpha = v.f32("zsEWMA_ALPHA")
        volt_min = v.f32("zsSENS_VOLT_MIN")
        volt_max = v.f32("zsSENS_VOLT_MAX")
        volts = [np.float32(self._hw.anin_get_adc(channel)) for channel, *_ in _SENSORS]
        v.set_raw("zsSensVolt", np.array(volts, dtype="<f4").tobytes())
        luts = {name: self._lut(name) for name in ("zvTankPConv", "zvRailPConv")}
        for volt, (_, filt_name, lut_name, fix, output) in zip(volts, _SENSORS):
            filt = v.f32(filt_name)
            filt = filt + alpha * (volt - filt)
            v.set_f32(filt_name, filt)
            saturated = volt_max if filt > volt_max else (volt_min if filt < volt_min else filt)
            pressure = look1(saturated, *luts[lut_name])
            if output == "zsRailPressure":
                v.set_f32("zsRailPressureTmp", pressure)
            if v.u8(f"{fix}_EN") == 1:
                pressure = v.f32(f"{fix}_VALUE")
            v.set_f32(output, pressure)
