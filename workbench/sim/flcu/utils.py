"""Utils (50 ms, ``Utils.c``): sensor and actuator diagnostics and the FLCU system enable."""

from __future__ import annotations

from workbench.sim.flcu.hardware import DOUT_LED, DOUT_OTV1, DOUT_OTV2, PWMOUT_PRV, DiagStatus, Hardware
from workbench.sim.flcu.rt import ZERO
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "Utils"]

_SENSOR_STATUSES = ("xsTank1PSDiagStatus", "xsTank2PSDiagStatus", "xsManifoldPSDiagStatus", "xsRailPSDiagStatus")
_ACTUATOR_STATUSES = ("xsOTV1DiagStatus", "xsOTV2DiagStatus", "xsPRVDiagStatus", "xsLEDDiagStatus")
MEASUREMENTS = (*_SENSOR_STATUSES, *_ACTUATOR_STATUSES, "xsSensorDiag", "xsActuatorDiag", "xsSystemAbilitation")


class Utils:
    def __init__(self, variables: Variables, hardware: Hardware):
        self._v = variables
        self._hw = hardware

    def initialize(self) -> None:
        for name in MEASUREMENTS:
            self._v.set_u8(name, 0)

    def step(self) -> None:
        v = self._v
        volt_min = v.f32("xsDIAG_VOLT_MIN")
        volt_max = v.f32("xsDIAG_VOLT_MAX")
        tolerance = v.f32("xsMANIFOLD_TOL")
        volts = v.f32_array("zsSensVolt", 4)
        sensor = [
            DiagStatus.OUT_OF_RANGE if (volt < volt_min or volt > volt_max) else DiagStatus.NO_ERROR for volt in volts
        ]
        manifold = v.f32("zsManifoldPressure")

        def deviates(tank: str) -> bool:
            diff = manifold - v.f32(tank)
            return (-diff if diff < ZERO else diff) > tolerance

        if sensor[2] == DiagStatus.NO_ERROR and (
            (v.u8("xsOTV1Cmd") != 0 and deviates("zsTank1Pressure"))
            or (v.u8("xsOTV2Cmd") != 0 and deviates("zsTank2Pressure"))
        ):
            sensor[2] = DiagStatus.IMPLAUSIBLE
        actuator = [  # uint8 in C
            int(self._hw.dout_error_info(DOUT_OTV1)) & 0xFF,
            int(self._hw.dout_error_info(DOUT_OTV2)) & 0xFF,
            int(self._hw.pwmout_error_info(PWMOUT_PRV)) & 0xFF,
            int(self._hw.dout_error_info(DOUT_LED)) & 0xFF,
        ]
        for name, status in zip(_SENSOR_STATUSES + _ACTUATOR_STATUSES, sensor + actuator):
            v.set_u8(name, int(status))
        sensor_ok = all(s == DiagStatus.NO_ERROR for s in sensor)
        actuator_ok = all(s == DiagStatus.NO_ERROR for s in actuator)
        v.set_u8("xsSensorDiag", sensor_ok)
        v.set_u8("xsActuatorDiag", actuator_ok)
        v.set_u8("xsSystemAbilitation", v.u8("csPCM_TO_FLCU_001_EnableFLCU") != 0 and sensor_ok and actuator_ok)
