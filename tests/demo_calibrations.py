"""Every calibration of the demo ECU with its initial value, physical, as docs/demo-ecu.md and the C
sources (assets/ecu/*.c) state them and the A2L converts them (units, verbal tables).

Written by hand from those sources, not read from the A2L, so it can check what is read from
files (and, once the A2L model reads the s19's CAL ROM, that too). real32_T values are the
float32 the ECU holds, widened to float64 (0.2F is 0.20000000298023224).
"""

from __future__ import annotations

import numpy as np

from workbench.calib.dataset import Dataset, FunctionInfo, ObjectInfo
from workbench.calib.values import Axis, CalValue


def f32(*values: float):
    """The float32 values the ECU holds, as Python floats (one) or a float64 array (several)."""
    array = np.array(values, dtype=np.float32).astype(np.float64)
    return float(array[0]) if len(values) == 1 else array


VOLTS = f32(0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5)
TARGET = f32(0, 10, 20, 30, 40, 50)
MANIFOLD = f32(50, 100, 200, 400, 700)
# xvPRV_DC_FF[m][t] in C: one row per manifold point (y), the target (x) varies fastest
FEED_FORWARD = f32(*[0, 100, 100, 100, 100, 100, 0, 100, 100, 100, 100, 100, 0, 70, 70, 70, 70, 70,
                     0, 35, 35, 35, 35, 35, 0, 20, 20, 20, 20, 20]).reshape(5, 6).T.copy()

_CAN_SIGNALS = ("ENABLEFLCU", "TARGETRAILPRESSURE", "FUELLEVELLOW", "FUELLEVEL", "RAILPRESSURE", "TANK1PSDIAGSTATUS",
                "TANK2PSDIAGSTATUS", "MANIFOLDPSDIAGSTATUS", "RAILPSDIAGNOSTICSTATUS", "OTV1DIAGSTATUS",
                "OTV2DIAGSTATUS", "PRVDIAGSTATUS", "LEDDIAGSTATUS")
_CAN_FIX_VALUES = {"ENABLEFLCU": ("Disabled", ""), "TARGETRAILPRESSURE": (0.0, "bar"), "FUELLEVELLOW": ("Normal", ""),
                   "FUELLEVEL": (0.0, "%"), "RAILPRESSURE": (0.0, "bar")}
_SCALARS = {  # name: (value, unit, function)
    "zsEWMA_ALPHA": (f32(0.2), "", "PressSens"), "zsSENS_VOLT_MIN": (f32(0.5), "V", "PressSens"),
    "zsSENS_VOLT_MAX": (f32(4.5), "V", "PressSens"),
    "xsDIAG_VOLT_MIN": (f32(0.5), "V", "Utils"), "xsDIAG_VOLT_MAX": (f32(4.5), "V", "Utils"),
    "xsMANIFOLD_TOL": (f32(30), "bar", "Utils"),
    "xsEMPTY_TANK_THR": (f32(5), "bar", "FuelLevel"), "xsFULL_TANK_PRESS": (f32(700), "bar", "FuelLevel"),
    "xsSWITCH_TANK_THR": (f32(20), "bar", "TankCtrl"),
    "xsPRV_KP": (f32(5), "%/bar", "PRVCtrl"), "xsPRV_KI": (f32(2), "%/(bar*s)", "PRVCtrl"),
    "xsPRV_KD": (f32(0.02), "%*s/bar", "PRVCtrl"), "xsPRV_I_BAND": (f32(5), "bar", "PRVCtrl"),
    "xsPRV_DC_MIN": (f32(0), "%", "PRVCtrl"), "xsPRV_DC_MAX": (f32(100), "%", "PRVCtrl"),
    "xsPRV_PWM_PERIOD": (1000, "µs", "ActuatorCommands"),
}


def demo_dataset() -> Dataset:
    """The demo ECU's calibrations (and the axis objects of its map) in the order of the A2L's functions."""
    dataset = Dataset(functions={m: FunctionInfo(version="1.0.0") for m in (
        "PressSens", "Utils", "FuelLevel", "TankCtrl", "PRVCtrl", "ActuatorCommands", "CANRX", "CANTX")})

    def add(value: CalValue, function: str) -> None:
        dataset.add(value, ObjectInfo(functions=(function,)))

    for name in ("zsEWMA_ALPHA", "zsSENS_VOLT_MIN", "zsSENS_VOLT_MAX"):
        value, unit, function = _SCALARS[name]
        add(CalValue(name, "VALUE", value, unit=unit), function)
    for name, top in (("zvTankPConv", 800), ("zvRailPConv", 50)):
        points = f32(*np.linspace(0, top, 9))
        add(CalValue(name, "CURVE", points, axes=(Axis(VOLTS.copy(), unit="V"),), unit="bar"), "PressSens")
    for sensor in ("TANK1", "TANK2", "MANIFOLD", "RAIL"):
        add(CalValue(f"zf{sensor}PRESSURE_EN", "VALUE", "OFF"), "PressSens")
        add(CalValue(f"zf{sensor}PRESSURE_VALUE", "VALUE", 0.0, unit="bar"), "PressSens")
    for name, (value, unit, function) in _SCALARS.items():
        if not name.startswith("zs"):
            add(CalValue(name, "VALUE", value, unit=unit), function)
    add(CalValue("xaPRV_FF_TARGET", "AXIS_PTS", TARGET.copy(), unit="bar"), "PRVCtrl")
    add(CalValue("xaPRV_FF_MANIFOLD", "AXIS_PTS", MANIFOLD.copy(), unit="bar"), "PRVCtrl")
    axes = (Axis(TARGET.copy(), "COM_AXIS", "xaPRV_FF_TARGET", "bar"),
            Axis(MANIFOLD.copy(), "COM_AXIS", "xaPRV_FF_MANIFOLD", "bar"))
    add(CalValue("xvPRV_DC_FF", "MAP", FEED_FORWARD.copy(), axes=axes, unit="%"), "PRVCtrl")
    for signal in _CAN_SIGNALS:
        value, unit = _CAN_FIX_VALUES.get(signal, ("NO_ERROR", ""))
        function = "CANRX" if signal in ("ENABLEFLCU", "TARGETRAILPRESSURE") else "CANTX"
        add(CalValue(f"cf{signal}_EN", "VALUE", "OFF"), function)
        add(CalValue(f"cf{signal}_VALUE", "VALUE", value, unit=unit), function)
    for message in ("FLCU_TO_PCM_001", "FLCU_TO_PCM_002", "FLCU_TO_PCM_003"):
        add(CalValue(f"cs{message}_En", "VALUE", "ON"), "CANTX")
    return dataset
